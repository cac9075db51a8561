//! One process a launcher runs: started in a process group of its own (a Ctrl-C at the
//! launcher's terminal reaches only the launcher, which then stops its processes in
//! order), its output passed on line by line under its name, its exit seen, and a
//! restart when the graph asks for one.

use std::io::{BufRead, BufReader, Read, Write};
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use super::ProcessReport;
use super::plan::Launch;

/// A process alive this long after its start counts as running.
const RUNNING_AFTER: Duration = Duration::from_secs(1);

pub struct Child {
    pub launch: Launch,
    exe: PathBuf,
    process: Option<std::process::Child>,
    /// As `ProcessReport::state` says it.
    pub state: &'static str,
    pub exit: Option<String>,
    pub restarts: u32,
    started: Instant,
    restart_at: Option<Instant>,
}

impl Child {
    /// `mechweed`: this program's path, for the mechweed commands.
    pub fn new(launch: Launch, mechweed: &Path) -> Child {
        let exe = if launch.program == "mechweed" {
            mechweed.to_path_buf()
        } else {
            PathBuf::from(&launch.program)
        };
        let state = match (launch.auto, launch.after.is_empty()) {
            (false, _) => "manual",
            (true, false) => "waiting",
            (true, true) => "starting",
        };
        Child {
            launch,
            exe,
            process: None,
            state,
            exit: None,
            restarts: 0,
            started: Instant::now(),
            restart_at: None,
        }
    }

    /// A process the launcher does not run (admit.rs said why).
    pub fn refused(launch: Launch, mechweed: &Path, why: String) -> Child {
        let mut child = Child::new(launch, mechweed);
        child.state = "refused";
        child.exit = Some(why);
        child
    }

    /// Start it; the error names the program.
    pub fn start(&mut self) -> Result<(), String> {
        let mut command = Command::new(&self.exe);
        command
            .args(&self.launch.args)
            .envs(self.launch.env.iter().cloned())
            // systemd's notify socket is the launcher's own: a controller it starts
            // must not speak for the launcher's service.
            .env_remove("NOTIFY_SOCKET")
            .env_remove("WATCHDOG_USEC")
            .env_remove("WATCHDOG_PID")
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .process_group(0);
        // A launcher that ends without stopping its processes (killed, or a panic)
        // leaves none running unwatched: each gets SIGTERM, on which mechweed's programs
        // stop as at Ctrl-C, the controller with its safe outputs.
        // SAFETY: the closure runs in the child between fork and exec and only calls
        // prctl, which is async-signal-safe.
        unsafe {
            command.pre_exec(|| {
                libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGTERM);
                Ok(())
            });
        }
        let mut process = command.spawn().map_err(|e| {
            format!(
                "cannot start {} ({}): {e}",
                self.launch.name,
                self.exe.display()
            )
        })?;
        let name = self.launch.name.clone();
        if let Some(out) = process.stdout.take() {
            relay(out, format!("[{name}] "), false);
        }
        if let Some(err) = process.stderr.take() {
            relay(err, format!("[{name}] "), true);
        }
        self.process = Some(process);
        self.started = Instant::now();
        self.state = "starting";
        Ok(())
    }

    pub fn pid(&self) -> Option<u32> {
        self.process.as_ref().map(std::process::Child::id)
    }

    /// See whether it exited, restart it when due, and note when it counts as running.
    /// True if its state changed.
    pub fn poll(&mut self) -> bool {
        let before = (self.state, self.restarts);
        if let Some(process) = &mut self.process
            && let Ok(Some(status)) = process.try_wait()
        {
            self.process = None;
            self.exit = Some(exit_words(status));
            self.state = "exited";
            if self.launch.restart {
                // Checked when the plan came (plan_check.rs); never a panic here.
                let delay = Duration::try_from_secs_f64(self.launch.restart_delay_s)
                    .unwrap_or(Duration::ZERO);
                self.restart_at = Some(Instant::now() + delay);
            }
        }
        if self.restart_at.is_some_and(|at| Instant::now() >= at) {
            self.restart_at = None;
            self.restarts += 1;
            if let Err(why) = self.start() {
                eprintln!("launcher: {why}");
                self.state = "exited";
            }
        }
        if self.state == "starting" && self.started.elapsed() >= RUNNING_AFTER {
            self.state = if self.restarts > 0 {
                "restarted"
            } else {
                "running"
            };
        }
        before != (self.state, self.restarts)
    }

    /// Stop it: SIGTERM to its process group (a mechweed program ends as at Ctrl-C, the
    /// controller with its safe outputs, and says the system asked), then SIGKILL if it
    /// has not ended within
    /// `patience`. No restart
    /// follows. Returns how it ended, in words.
    pub fn stop(&mut self, patience: Duration) -> String {
        self.restart_at = None;
        let Some(mut process) = self.process.take() else {
            self.state = if self.state == "manual" {
                "manual"
            } else {
                "stopped"
            };
            return self
                .exit
                .clone()
                .unwrap_or_else(|| "not running".to_string());
        };
        // Its whole process group (a shell's children too). The pid is ours and not
        // yet reaped, so the group cannot be another's.
        let group = -(process.id() as libc::pid_t);
        unsafe { libc::kill(group, libc::SIGTERM) };
        let end = Instant::now() + patience;
        let status = loop {
            match process.try_wait() {
                Ok(Some(status)) => break Some(status),
                Ok(None) if Instant::now() < end => std::thread::sleep(Duration::from_millis(20)),
                _ => break None,
            }
        };
        let words = match status {
            Some(status) => exit_words(status),
            None => {
                unsafe { libc::kill(group, libc::SIGKILL) };
                let _ = process.wait();
                format!(
                    "killed: it did not end within {:.0} s of SIGTERM",
                    patience.as_secs_f64()
                )
            }
        };
        self.state = "stopped";
        self.exit = Some(words.clone());
        words
    }

    pub fn report(&self, machine: &str) -> ProcessReport {
        ProcessReport {
            machine: machine.to_string(),
            process: self.launch.name.clone(),
            state: self.state.to_string(),
            exit: self.exit.clone(),
            restarts: self.restarts,
            pid: self.pid(),
            command: self.launch.command_line(),
        }
    }
}

/// "code 0", or "killed by SIGKILL".
fn exit_words(status: ExitStatus) -> String {
    match (status.code(), status.signal()) {
        (Some(code), _) => format!("code {code}"),
        (None, Some(signal)) => match signal {
            libc::SIGINT => "killed by SIGINT".to_string(),
            libc::SIGTERM => "killed by SIGTERM".to_string(),
            libc::SIGKILL => "killed by SIGKILL".to_string(),
            libc::SIGSEGV => "killed by SIGSEGV, a crash".to_string(),
            libc::SIGABRT => "killed by SIGABRT, an abort".to_string(),
            other => format!("killed by signal {other}"),
        },
        (None, None) => "ended".to_string(),
    }
}

/// Pass a child's output on, each line under `prefix`, from a thread of its own.
fn relay(stream: impl Read + Send + 'static, prefix: String, to_stderr: bool) {
    let name = prefix.clone();
    let spawned = std::thread::Builder::new()
        .name("relay".into())
        .spawn(move || {
            let mut reader = BufReader::new(stream);
            let mut bytes = Vec::new();
            // Bytes, not text: a line that is not UTF-8 is shown, not the end of the relay.
            while matches!(reader.read_until(b'\n', &mut bytes), Ok(n) if n > 0) {
                let line = String::from_utf8_lossy(&bytes);
                let line = line.trim_end_matches(['\n', '\r']);
                // Read on even where the terminal is gone: a full pipe would block the
                // child's own writes.
                let _ = if to_stderr {
                    writeln!(std::io::stderr().lock(), "{prefix}{line}")
                } else {
                    writeln!(std::io::stdout().lock(), "{prefix}{line}")
                };
                bytes.clear();
            }
        });
    if let Err(e) = spawned {
        eprintln!("launcher: cannot pass on the output of {name}: {e}");
    }
}
