//! `mechweed bench loop`: the real threads on the simulated robot, driving along the
//! row, for a set time at a set supervisor rate; prints each loop's wake-up lateness and
//! execution time. Run cyclictest beside it to compare with what the machine itself
//! can do (README).

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use serde::Serialize;

use crate::config::Settings;
use crate::console::run;
use crate::gui::Tab;
use crate::modes::Mode;
use crate::record::RecordOutcome;
use crate::report::{loop_line, record_lines};
use crate::rt::{LiuLayland, LoopSummary, liu_layland};
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
    /// Its run record: a bench run is recorded like any run.
    pub record: RecordOutcome,
}

/// With `gui`, the operator GUI is open on that tab for the whole run (on this, the
/// main thread), to measure what it costs the supervisor; None runs headless.
pub fn bench_loop(
    settings: &Settings,
    rate_hz: f64,
    seconds: f64,
    gui: Option<Tab>,
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
    let stop = Arc::new(AtomicBool::new(false));
    let outcome = match gui {
        Some(tab) => crate::gui::run_gui(&options, None, tab, stop, ADVICE)?,
        None => run(&options, stop).map_err(|e| e.to_string())?,
    };
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
