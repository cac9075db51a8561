//! `mechweed bench loop`: the real threads on the simulated robot, driving along the
//! row, for a set time at a set supervisor rate; prints each loop's wake-up lateness and
//! execution time, and the CPU time the whole process used (with `--gui`, also the
//! window's frames a second). Run cyclictest beside it to compare with what the machine
//! itself can do (docs/measurements.md).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use serde::Serialize;

use crate::bench_halt::press_space;
use crate::config::Settings;
use crate::console::run;
use crate::gui::Tab;
use crate::modes::Mode;
use crate::record::RecordOutcome;
use crate::report::{loop_line, record_lines};
use crate::rt::{LiuLayland, LoopSummary, liu_layland, process_cpu_s};
use crate::run::RunOptions;

#[derive(Debug, Serialize)]
pub struct LoopBench {
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
pub struct HaltKey {
    pub presses: usize,
    pub p50_ms: f64,
    pub p99_ms: f64,
    pub max_ms: f64,
}

impl HaltKey {
    fn of(mut ms: Vec<f64>) -> HaltKey {
        ms.sort_by(f64::total_cmp);
        let rank = |p: f64| {
            let k = ((p * ms.len() as f64).ceil() as usize).clamp(1, ms.len().max(1));
            ms.get(k - 1).copied().unwrap_or(f64::NAN)
        };
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
pub fn bench_loop(
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
        let ll = &self.liu_layland;
        out += &format!(
            "Liu-Layland: worst-case load {:.4} of bound {:.3}\n",
            ll.utilisation, ll.bound
        );
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
