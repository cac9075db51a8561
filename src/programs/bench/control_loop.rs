//! `mechweed bench loop`: the real threads on the simulated robot, driving along the
//! row, for a set time at a set supervisor rate; prints each loop's wake-up lateness and
//! execution time, and the CPU time the whole process used (with `--gui`, also the
//! window's frames a second). Run cyclictest beside it to compare with what the machine
//! itself can do (docs/measurements.md).

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use serde::Serialize;

use crate::config::Backend;
use crate::config::Settings;
use crate::console::report::{loop_line, record_lines};
use crate::console::run;
use crate::gui::Tab;
use crate::programs::bench::halt::press_space;
use crate::programs::{load_settings, print_errors, write_json};
use crate::record::RecordOutcome;
use crate::rt::{LiuLayland, LoopSummary, liu_layland, process_cpu_s};
use crate::run::RunOptions;
use crate::state::modes::Mode;

#[derive(Debug, Serialize)]
pub(crate) struct LoopBench {
    pub rate_hz: f64,
    pub gui: bool,
    pub seconds: f64,
    pub supervisor: LoopSummary,
    pub steer: LoopSummary,
    pub liu_layland: LiuLayland,
    pub faults: Vec<String>,
    pub rt_warnings: Vec<String>,
    /// CPU time of the whole process from start to end of the run (start-up and
    /// shut-down included), s, and that per second of the run, CPUs.
    pub cpu_s: f64,
    pub cpus: f64,
    /// Frames the GUI drew, and per second of the run (None headless).
    pub gui_frames: Option<u64>,
    pub gui_fps: Option<f64>,
    /// With `--press-space`: the Space key (HALT) from the X server to the supervisor.
    pub halt_key: Option<HaltKey>,
    /// Its run record: a bench run is recorded like any run.
    pub record: RecordOutcome,
}

/// The Space key's way to the supervisor, ms (nearest-rank percentiles).
#[derive(Debug, Serialize)]
pub(crate) struct HaltKey {
    pub presses: usize,
    pub p50_ms: f64,
    pub p99_ms: f64,
    pub max_ms: f64,
}

impl HaltKey {
    fn of(mut ms: Vec<f64>) -> HaltKey {
        ms.sort_by(f64::total_cmp);
        let rank = |p: f64| super::nearest_rank(&ms, p);
        HaltKey {
            presses: ms.len(),
            p50_ms: rank(0.5),
            p99_ms: rank(0.99),
            max_ms: ms.last().copied().unwrap_or(f64::NAN),
        }
    }
}

/// With `gui`, the operator GUI is open on that tab for the whole run (on this, the
/// main thread), to measure what it costs the supervisor; None runs headless. With
/// `press_space_s` (and the GUI), the Space key is pressed that often (bench_halt.rs).
pub(crate) fn bench_loop(
    settings: &Settings,
    rate_hz: f64,
    seconds: f64,
    gui: Option<Tab>,
    press_space_s: Option<f64>,
) -> Result<LoopBench, String> {
    // bench loop has no --headless: without --gui it is headless.
    const ADVICE: &str = "drop --gui to measure without the GUI";
    if gui.is_some()
        && let Some(why) = crate::gui::display_missing()
    {
        return Err(format!("{why}: {ADVICE} (nothing started)"));
    }
    let mut settings = settings.clone();
    settings.supervisor.rate_hz = rate_hz;
    let options = RunOptions {
        settings,
        start_mode: Mode::Autonomous,
        duration_s: Some(seconds),
        // A status line every 5 s, as `run` prints, so that a long bench is not silent.
        status_every_s: 5.0,
        inject: None,
    };
    // Ctrl-C ends the bench as it ends a run: the supervisor writes the safe outputs.
    let stop = crate::console::ctrl_c();
    let cpu_before_s = process_cpu_s();
    let done = Arc::new(AtomicBool::new(false));
    let (pressed_tx, pressed) = crossbeam_channel::bounded(1);
    let beside = press_space_s.map(|every_s| {
        let done = done.clone();
        Box::new(move |supervisor, clock| {
            let _ = pressed_tx.send(press_space(supervisor, clock, every_s, done));
        }) as crate::gui::Beside
    });
    let (outcome, gui_frames) = match gui {
        Some(tab) => {
            let (outcome, frames) = crate::gui::run_gui(&options, None, tab, stop, ADVICE, beside)?;
            (outcome, Some(frames))
        }
        None => (run(&options, stop).map_err(|e| e.to_string())?, None),
    };
    done.store(true, Ordering::Relaxed);
    let halt_key = match press_space_s {
        None => None,
        Some(_) => match pressed.recv_timeout(Duration::from_secs(5)) {
            Ok(Ok(ms)) => Some(HaltKey::of(ms)),
            Ok(Err(why)) => return Err(format!("--press-space: {why}")),
            Err(_) => return Err("--press-space: the key presser did not end".to_string()),
        },
    };
    let cpu_s = process_cpu_s() - cpu_before_s;
    Ok(LoopBench {
        rate_hz,
        gui: gui.is_some(),
        seconds,
        supervisor: outcome.supervisor_loop,
        steer: outcome.steer_loop,
        liu_layland: liu_layland(&[outcome.supervisor_loop, outcome.steer_loop]),
        faults: outcome
            .faults
            .iter()
            .map(|f| format!("{:.2} s: {}", f.t_s, f.cause))
            .collect(),
        rt_warnings: outcome.rt_warnings,
        record: outcome.record,
        cpu_s,
        cpus: cpu_s / seconds,
        gui_frames,
        gui_fps: gui_frames.map(|f| f as f64 / seconds),
        halt_key,
    })
}

impl LoopBench {
    pub fn text(&self) -> String {
        let mut out = format!(
            "{} s at {} Hz, driving autonomously on the simulated robot{}\n",
            self.seconds,
            self.rate_hz,
            if self.gui {
                ", operator GUI open"
            } else {
                ", headless"
            }
        );
        out += &loop_line("supervisor", &self.supervisor);
        out += "\n";
        out += &loop_line("steer", &self.steer);
        out += "\n";
        out += &format!("Liu-Layland: {}\n", self.liu_layland.words());
        out += &format!(
            "CPU time of the whole process: {:.2} s, {:.3} CPUs",
            self.cpu_s, self.cpus
        );
        if let (Some(frames), Some(fps)) = (self.gui_frames, self.gui_fps) {
            out += &format!("; GUI: {frames} frames, {fps:.1} frames/s");
        }
        out += "\n";
        if let Some(k) = &self.halt_key {
            out += &format!(
                "Space key (HALT) from the X server to the supervisor's tick: {} presses, p50/p99/max {:.1}/{:.1}/{:.1} ms\n",
                k.presses, k.p50_ms, k.p99_ms, k.max_ms
            );
        }
        for fault in &self.faults {
            out += &format!("fault: {fault}\n");
        }
        for warning in &self.rt_warnings {
            out += &format!("real-time: {warning}\n");
        }
        out += &record_lines(&self.record);
        out
    }
}

#[derive(clap::Args)]
pub struct LoopArgs {
    /// Supervisor rate.
    #[arg(long, default_value_t = 100.0, value_name = "HZ")]
    pub rate: f64,
    #[arg(long, default_value_t = 10.0, value_name = "N")]
    pub seconds: f64,
    /// With the operator GUI open (needs a display).
    #[arg(long)]
    pub gui: bool,
    /// The GUI's tab while it is open [default: status]
    #[arg(long, value_enum, requires = "gui")]
    pub tab: Option<Tab>,
    /// Press the Space key (HALT) in the window about every S seconds through the X
    /// server, and measure the time to the supervisor's HALT (needs the X server's
    /// test extension, as Xvfb has).
    #[arg(long, value_name = "S", requires = "gui")]
    pub press_space: Option<f64>,
    /// Override one setting (SECTION.KEY=VALUE), e.g. --set bus.enabled=no; repeatable.
    #[arg(long, value_name = "SECTION.KEY=VALUE")]
    pub set: Vec<String>,
    /// Also write the figures as JSON to this file.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
}

/// `mechweed bench loop`: checks its options, refuses the real robot, prints the figures.
pub fn program(args: LoopArgs) -> ExitCode {
    let gui = args.gui.then(|| args.tab.unwrap_or_default());
    loop_program(
        args.rate,
        args.seconds,
        (gui, args.press_space),
        &args.set,
        args.json,
    )
}

fn loop_program(
    rate: f64,
    seconds: f64,
    (gui, press_space_s): (Option<Tab>, Option<f64>),
    set: &[String],
    json: Option<PathBuf>,
) -> ExitCode {
    let settings = match load_settings(None, set) {
        Ok(s) => s,
        Err(errors) => {
            print_errors(&errors);
            return ExitCode::FAILURE;
        }
    };
    if !(1.0..=10_000.0).contains(&rate) || !(0.001..=86_400.0).contains(&seconds) {
        eprintln!("--rate must be 1 to 10000 Hz and --seconds 0.001 to 86400");
        return ExitCode::FAILURE;
    }
    if press_space_s.is_some_and(|s| !(0.2..=60.0).contains(&s)) {
        eprintln!("--press-space must be 0.2 to 60 s");
        return ExitCode::FAILURE;
    }
    // It powers up and drives in autonomous with no one asked: never the real robot.
    if settings.backend != Backend::Sim {
        eprintln!(
            "bench loop drives the simulated robot and starts in autonomous without asking: it does not run on the real robot ([hw] backend = cards in {}); add --set hw.backend=sim",
            settings.source.label
        );
        return ExitCode::FAILURE;
    }
    match crate::programs::bench::control_loop::bench_loop(
        &settings,
        rate,
        seconds,
        gui,
        press_space_s,
    ) {
        Ok(figures) => {
            print!("{}", figures.text());
            write_json(json, &figures)
        }
        Err(why) => {
            eprintln!("{why}");
            ExitCode::FAILURE
        }
    }
}
