//! What a launcher lets a plan run on its computer. The plan comes from the master's
//! identity alone (the access rules), but the launcher still decides: mechweed's own
//! programs always; any other executable only if the launcher's command line allows its
//! path (`--allow PATH`); no environment variable from a plan but the robot's own
//! (MECHWEED_*), so none changes how programs load (LD_*) or which are found (PATH).
//! On a secured cluster each mechweed program is given its role's identity from the
//! launcher's own keys folder.

use std::path::{Path, PathBuf};

use super::plan::Launch;
use crate::config::TlsFiles;

/// The launcher's own rules for what may run.
#[derive(Debug, Clone, Default)]
pub struct Admission {
    /// Executables besides mechweed that plans may name, as given on the command line.
    pub allowed: Vec<String>,
    /// The keys folder, on a secured cluster: each program gets its role's identity.
    pub keys: Option<PathBuf>,
}

/// Where `program` is: a path as it is, a bare name through PATH.
fn resolve(program: &str) -> Option<PathBuf> {
    if program.contains('/') {
        return std::fs::canonicalize(program).ok();
    }
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(program))
        .find(|p| p.is_file())
        .and_then(|p| std::fs::canonicalize(p).ok())
}

/// The identity a mechweed program runs as: its role's first identity.
fn role_of(command: &str) -> Option<&'static str> {
    match command {
        "run" => Some("robot"),
        "camsim" => Some("camera"),
        "watch" => Some("operator"),
        "record" => Some("recorder"),
        _ => None,
    }
}

impl Admission {
    /// `launch` as this launcher runs it, or why it does not.
    pub fn admit(&self, mut launch: Launch) -> Result<Launch, String> {
        if launch.program != "mechweed" {
            let wanted = resolve(&launch.program);
            let allowed = self
                .allowed
                .iter()
                .any(|a| *a == launch.program || (wanted.is_some() && resolve(a) == wanted));
            if !allowed {
                return Err(format!(
                    "{} is refused: {} is not a program this launcher allows (mechweed's own programs always; any other only with --allow PATH on the launcher's command line)",
                    launch.name, launch.program
                ));
            }
        }
        let (kept, dropped): (Vec<_>, Vec<_>) = launch
            .env
            .into_iter()
            .partition(|(name, _)| name.starts_with("MECHWEED_"));
        if let Some((name, _)) = dropped.first() {
            eprintln!(
                "launcher: {}: the plan's environment variable {name} is not taken (only MECHWEED_* come from a plan)",
                launch.name
            );
        }
        launch.env = kept;
        if let Some(dir) = &self.keys
            && launch.program == "mechweed"
            && let Some(role) = launch.args.first().and_then(|c| role_of(c))
        {
            identity_args(&mut launch.args, dir, role);
        }
        Ok(launch)
    }
}

/// Give a mechweed program its identity `name` in `dir`: `run` takes it as settings,
/// the tools as `--keys DIR --as NAME`.
fn identity_args(args: &mut Vec<String>, dir: &Path, name: &str) {
    if args.first().map(String::as_str) == Some("run") {
        let files = TlsFiles::in_folder(dir, name);
        for (key, file) in [
            ("tls_ca", &files.ca),
            ("tls_cert", &files.cert),
            ("tls_key", &files.key),
        ] {
            args.extend(["--set".to_string(), format!("bus.{key}={}", file.display())]);
        }
    } else {
        args.extend([
            "--keys".to_string(),
            dir.display().to_string(),
            "--as".to_string(),
            name.to_string(),
        ]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn launch(program: &str, args: &[&str]) -> Launch {
        Launch {
            name: "x".into(),
            program: program.into(),
            args: args.iter().map(|a| a.to_string()).collect(),
            env: vec![
                ("MECHWEED_ROBOT".into(), "mechweed".into()),
                ("LD_PRELOAD".into(), "/tmp/evil.so".into()),
                ("PATH".into(), "/tmp".into()),
            ],
            auto: true,
            restart: false,
            restart_delay_s: 0.0,
            after: Vec::new(),
            controller: false,
        }
    }

    #[test]
    fn only_mechweed_and_allowed_programs_run_without_loader_variables() {
        let none = Admission::default();
        let why = none.admit(launch("/bin/sh", &["-c", "id"])).unwrap_err();
        assert!(why.contains("--allow PATH"), "{why}");
        let sh = Admission {
            allowed: vec!["/bin/sh".into()],
            keys: None,
        };
        let taken = sh.admit(launch("/bin/sh", &[])).unwrap();
        assert_eq!(
            taken.env,
            [("MECHWEED_ROBOT".to_string(), "mechweed".to_string())]
        );
        assert!(none.admit(launch("mechweed", &["camsim"])).is_ok());
    }

    #[test]
    fn a_secured_launcher_gives_each_program_its_roles_identity() {
        let keys = Admission {
            allowed: Vec::new(),
            keys: Some(PathBuf::from("keys")),
        };
        let camsim = keys
            .admit(launch("mechweed", &["camsim", "--bus"]))
            .unwrap();
        assert_eq!(camsim.args[2..], ["--keys", "keys", "--as", "camera"]);
        let run = keys.admit(launch("mechweed", &["run"])).unwrap();
        assert!(
            run.args
                .contains(&"bus.tls_cert=keys/robot.pem".to_string())
        );
    }
}
