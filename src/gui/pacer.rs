//! The GUI's pacer thread: 30 times a second it reads a `View` of the controller, takes
//! the plots' sample, decides with `Pace` whether the window needs a frame, asks egui
//! for one if so, and beats for the GUI while every frame asked for has been drawn.
//! Looking costs microseconds; a frame under software rendering costs tens of
//! milliseconds, so the GUI thread sleeps until it has something to show.
//!
//! It runs at the GUI's normal priority, below every real-time thread. If it panics or
//! hangs, the GUI's beat stops and the supervisor faults: safe outputs (and Ctrl-C
//! closes the window at the next operator input instead of at once).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use eframe::egui;
use parking_lot::Mutex;

use super::app::Tab;
use super::pace::{LOOK_S, Pace};
use super::plot_data::PlotSamples;
use super::remote::RemoteView;
use super::view::{View, ViewSource};
use crate::run::Handles;
use crate::state::modes::Request;
use crate::state::request_channel::Answer;

/// Where the window's view comes from.
pub enum Source {
    /// The controller in this process (replaced when the operator resets the simulated
    /// robot).
    Local(Handles),
    /// A robot watched over the bus (`mechweed watch`); boxed, as it keeps a whole
    /// `View` between looks.
    Remote(Box<RemoteView>),
}

impl Source {
    /// The simulated robot's controls, for its panel: only where the controller is.
    pub fn sim(&self) -> Option<mechweed_hw::sim::SimControl> {
        match self {
            Source::Local(handles) => handles.sim.clone(),
            Source::Remote(_) => None,
        }
    }

    /// The GUI's heartbeat, which the supervisor in this process watches.
    fn beat(&self, now_s: f64) {
        if let Source::Local(handles) = self {
            handles.gui_beat.publish(&now_s);
        }
    }
}

impl ViewSource for Source {
    fn view(&mut self) -> View {
        match self {
            Source::Local(handles) => handles.view(),
            Source::Remote(remote) => remote.view(),
        }
    }

    fn send(
        &self,
        request: Request,
        reply: &crossbeam_channel::Sender<Answer>,
    ) -> Result<(), String> {
        match self {
            Source::Local(handles) => handles.send(request, reply),
            Source::Remote(remote) => remote.send(request, reply),
        }
    }

    fn ping_link(&self) {
        match self {
            Source::Local(handles) => handles.ping_link(),
            Source::Remote(remote) => remote.ping_link(),
        }
    }

    fn answers_in_words(&self) -> Vec<(Request, Result<(), String>)> {
        match self {
            Source::Local(handles) => handles.answers_in_words(),
            Source::Remote(remote) => remote.answers_in_words(),
        }
    }
}

/// What the GUI thread and its pacer share, behind one lock that neither holds while
/// drawing.
pub struct Shared {
    /// Where the view comes from and the requests go.
    pub source: Source,
    /// The tab shown.
    pub tab: Tab,
    /// Passes the GUI thread has run: frames, and the passes without drawing that
    /// eframe runs while the window is minimised.
    pub passes: u64,
    /// Frames drawn (passes that showed the window), for `bench loop --gui`.
    pub frames: u64,
    pub samples: PlotSamples,
}

pub(crate) type SharedGui = Arc<Mutex<Shared>>;

pub fn shared(source: Source, tab: Tab) -> SharedGui {
    Arc::new(Mutex::new(Shared {
        source,
        tab,
        passes: 0,
        frames: 0,
        samples: PlotSamples::default(),
    }))
}

/// Start the pacer for the window of `ctx`. `close` (Ctrl-C) also wakes the GUI thread
/// so that it closes the window; `quit` ends the pacer.
pub fn spawn(
    ctx: egui::Context,
    shared: SharedGui,
    close: Arc<AtomicBool>,
    quit: Arc<AtomicBool>,
) -> std::io::Result<JoinHandle<()>> {
    std::thread::Builder::new()
        .name("gui-pacer".into())
        .spawn(move || {
            let start = Instant::now();
            let mut pace = Pace::default();
            let period = Duration::from_secs_f64(LOOK_S);
            let mut next = Instant::now();
            while !quit.load(Ordering::Relaxed) {
                look_once(&ctx, &shared, &mut pace, start.elapsed().as_secs_f64());
                if close.load(Ordering::Relaxed) {
                    ask_for_one_frame(&ctx);
                }
                next += period;
                let now = Instant::now();
                if next > now {
                    std::thread::sleep(next - now);
                } else {
                    next = now; // behind (a busy machine): no burst of catching up
                }
            }
        })
}

/// One look: sample, decide, ask for a frame, beat. Public for tests, which drive the
/// harness's passes themselves.
pub fn look_once(ctx: &egui::Context, shared: &SharedGui, pace: &mut Pace, t_s: f64) {
    let look = {
        let mut s = shared.lock();
        let view = s.source.view();
        // A watched robot's plots take what arrived: nothing before its first status,
        // and no flat line drawn on from old values while it is silent.
        if !view.remote.as_ref().is_some_and(|link| link.stale()) {
            s.samples.record(&view);
        }
        let look = pace.look(&view, s.tab, s.passes, t_s);
        if look.beat {
            s.source.beat(view.now_s);
        }
        look
    };
    if look.draw {
        ask_for_one_frame(ctx);
    }
}

/// egui answers `request_repaint()` with two frames (to let things settle); a request
/// with a delay, however short, gets one: half the frames for the same picture.
fn ask_for_one_frame(ctx: &egui::Context) {
    ctx.request_repaint_after(Duration::from_millis(1));
}
