//! The headless operator console of `mechweed run`: follows the operator script,
//! prints scripted events, mode changes, faults and notices as they happen and a status line every few seconds, and
//! ends the run at its duration, on Ctrl-C, or when a thread has stopped. Beside it:
//! the run's closing report (report.rs) and how log lines look (log_style.rs).

pub mod log_style;
pub mod report;
pub mod systemd;

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};

use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
use signal_hook::iterator::Signals;
use std::time::Duration;

use crate::config::Backend;
use crate::rt::liu_layland;
use crate::run::{Handles, RunError, RunOptions, RunOutcome, start};
use crate::state::Reader;
use crate::state::cross_track::CrossTrackMeaning;
use crate::state::modes::Mode;
use crate::state::operator::OperatorScript;

/// Run the controller with the headless console until `duration_s` or until `stop` is
/// set; an error if the hardware or the camera port cannot be set up (nothing has
/// started then).
pub fn run(opts: &RunOptions, stop: Arc<AtomicBool>) -> Result<RunOutcome, RunError> {
    let (handles, running) = start(opts, stop.clone())?;
    if let Some(warning) = &handles.not_realtime {
        crate::say!("{warning}");
    }
    // Under systemd: READY, STATUS and its watchdog, fed while the supervisor's status
    // is as fresh as the supervisor's own heartbeat check asks of the other threads.
    let notifier = systemd::Notifier::from_env().map(|n| {
        let fresh_s = opts.settings.rt.heartbeat_timeout_s.max(0.5);
        let status = handles.supervisor.status.clone();
        n.start(status, handles.clock, fresh_s, stop.clone())
    });
    operate(opts, &handles, &stop, || running.any_thread_ended());
    let outcome = running.finish();
    if let Some(thread) = notifier {
        let _ = thread.join();
    }
    Ok(outcome)
}

const POLL: Duration = Duration::from_millis(10);

pub(crate) fn operate(
    opts: &RunOptions,
    handles: &Handles,
    stop: &Arc<AtomicBool>,
    any_thread_ended: impl Fn() -> bool,
) {
    let Handles {
        supervisor, clock, ..
    } = handles;
    let mut script = OperatorScript::new(&opts.settings.sim.events, opts.start_mode);
    // Every scripted event, the plant's and the operator's, is said as it becomes due,
    // so that a run's output tells what was done to the robot and when.
    // On the real robot nothing plays the plant's events.
    let simulated = opts.settings.backend == Backend::Sim;
    let cross_track = CrossTrackMeaning::of(&opts.settings);
    let mut events = (opts.settings.sim.events.iter())
        .filter(|e| simulated || e.action.is_operator())
        .peekable();
    let mut mode_seen = Mode::Halt;
    let mut last_refusal = String::new();
    let mut faults_seen = None;
    let mut notice_seen = None;
    let mut next_line_s = opts.status_every_s;
    let mut frames_at_last_line = 0;
    loop {
        std::thread::sleep(POLL);
        let now_s = clock.elapsed().as_secs_f64();
        if stop.load(Ordering::Relaxed) || opts.duration_s.is_some_and(|d| now_s >= d) {
            return;
        }
        if any_thread_ended() {
            eprintln!("a controller thread stopped unexpectedly; ending the run");
            return;
        }
        while let Some(event) = events.next_if(|e| e.t_s <= now_s) {
            crate::say!("{now_s:7.2} s  scripted event: {}", event.action);
        }
        let status = supervisor.status.snapshot();
        // The fault before the mode change it causes: the cause first, then its effect.
        if let Some(fault) = status.fault
            && faults_seen != Some(fault.tick_seen)
        {
            faults_seen = Some(fault.tick_seen);
            crate::say!("{}", log_style::fault_line(&fault));
        }
        if status.mode != mode_seen {
            crate::say!("{now_s:7.2} s  mode: {mode_seen} -> {}", status.mode);
            mode_seen = status.mode;
        }
        if let Some(request) = script.due(now_s, &status)
            && let Err(why) = supervisor.request(request)
            && why != last_refusal
        {
            eprintln!("{now_s:7.2} s  request {request:?} refused: {why}");
            last_refusal = why;
        }
        if status.notice != notice_seen {
            notice_seen = status.notice;
            if let Some(notice) = status.notice {
                crate::say!("{now_s:7.2} s  {}", notice);
            }
        }
        if opts.status_every_s > 0.0 && now_s >= next_line_s {
            let seen = StatusLine {
                now_s,
                status: &status,
                period_s: opts.status_every_s,
                cross_track,
            };
            seen.say(handles, &mut frames_at_last_line);
            next_line_s += opts.status_every_s;
        }
    }
}

/// What the status line every few seconds is made of.
struct StatusLine<'a> {
    now_s: f64,
    status: &'a crate::state::status::Status,
    /// Since the last line, s.
    period_s: f64,
    cross_track: CrossTrackMeaning,
}

impl StatusLine<'_> {
    /// Say the mode, speed, wheel, the tool off its row and the camera link; the row
    /// filter when it runs; the loops' worst figures; and that the robot is not
    /// real-time, when it is not. `frames_before` is the camera's frame count at the
    /// last line, moved on to now.
    fn say(&self, handles: &Handles, frames_before: &mut u64) {
        let (now_s, status) = (self.now_s, self.status);
        let l = handles.link.snapshot();
        let frames = l.counters.frames_ok;
        let rate = (frames - *frames_before) as f64 / self.period_s;
        *frames_before = frames;
        let t = handles.truth.truth();
        let c = &l.counters;
        let errors = c.crc_errors + c.bad_values + c.unknown_kinds;
        let link_state = match (l.problem, l.opening) {
            (Some(problem), _) => format!("DOWN: {problem}"),
            (None, Some(step)) => step.to_string(),
            (None, None) => format!(
                "{rate:4.1} frames/s, {errors} errors, {} gaps, {} duplicates",
                c.seq_gaps, c.duplicates
            ),
        };
        crate::say!(
            "{now_s:7.2} s  {:<10} speed {:5.2} m/s  wheel {:5.1} deg  tool off row {}  camera {link_state}",
            status.mode.name(),
            status.measured.speed_mps,
            status.measured.wheel_angle_rad.to_degrees(),
            self.cross_track.cm(t.tool_cross_track_m),
        );
        let steer = handles.steer.snapshot();
        let r = &steer.row;
        if let Some(f) = &r.filter {
            crate::say!(
                "           steering by {}; GNSS {}, {} satellites; row filter {:+.1} +- {:.1} cm, gate rejected {} camera rows, {} fixes",
                steer.sources.steering.words(),
                mechweed_hw::nmea::FixQuality::from_code(r.gnss_quality).words(),
                r.gnss_satellites,
                f.offset_m * 100.0,
                f.offset_sd_m * 100.0,
                f.camera_rejected,
                f.gnss_rejected
            );
        }
        let [supervisor_loop, steer_loop] = handles.loops.each_ref().map(Reader::snapshot);
        let check = liu_layland(&[supervisor_loop, steer_loop]);
        crate::say!(
            "           supervisor late p99 {} us, max {} us, exec max {} us, {} overruns; steer exec max {} us; Liu-Layland {}",
            supervisor_loop.late_us.p99,
            supervisor_loop.late_us.max,
            supervisor_loop.exec_us.max,
            supervisor_loop.overruns,
            steer_loop.exec_us.max,
            check.words(),
        );
        if let Some(warning) = &handles.not_realtime {
            crate::say!("           {warning}");
        }
    }
}

/// The signal that asked this program to stop (0: none yet).
static STOPPED_BY: AtomicI32 = AtomicI32::new(0);

/// A flag that Ctrl-C, SIGTERM (a service manager, `kill`, a shutdown) or SIGHUP (the
/// terminal closed) sets; `stop_request` says which it was. Each call gives a flag of
/// its own, all set by the same signals.
pub(crate) fn ctrl_c() -> Arc<AtomicBool> {
    let stop = Arc::new(AtomicBool::new(false));
    let flag = stop.clone();
    let signals = [SIGINT, SIGTERM, SIGHUP];
    let started = Signals::new(signals).and_then(|mut signals| {
        std::thread::Builder::new()
            .name("signals".into())
            .spawn(move || {
                for signal in signals.forever() {
                    let _ =
                        STOPPED_BY.compare_exchange(0, signal, Ordering::SeqCst, Ordering::SeqCst);
                    flag.store(true, Ordering::SeqCst);
                }
            })
    });
    if let Err(e) = started {
        eprintln!("cannot catch Ctrl-C and SIGTERM ({e}): stop with --duration");
    }
    stop
}

/// Who asked this program to stop, in words; None: no signal came.
pub(crate) fn stop_request() -> Option<&'static str> {
    match STOPPED_BY.load(Ordering::SeqCst) {
        SIGINT => Some("the operator (Ctrl-C)"),
        SIGTERM => {
            Some("a stop request from the system (SIGTERM: a service manager, kill or a shutdown)")
        }
        SIGHUP => Some("its terminal closing (SIGHUP)"),
        _ => None,
    }
}
