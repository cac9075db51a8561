//! The lockstep driver: the same tick functions as the real-time threads, run one
//! after the other on simulated time, as fast as the computer goes. Tests and
//! benchmarks use it; the product uses real threads (threads/supervisor.rs and
//! steer.rs, started by the program's src/run/).
//!
//! Every millisecond of simulated time: the plant advances, bytes from the simulated
//! camera computer go through the real decoder, the steer tick runs on a new estimate
//! or at its rate, command bytes go back; at the supervisor's rate the supervisor
//! reads the plant's inputs, ticks, and writes its outputs into the plant.
//!
//! The supervisor reaches the plant directly ([`Io::Direct`]), or through emulated I/O
//! cards and the real card drivers and wiring ([`Io::Cards`]): the whole path of the
//! real robot except the wires.

use mechweed_hw::emulated::CardRig;
use mechweed_hw::sim::{CrossTrackStats, Miswire, PipeEnd, SAMPLE_SPACING_M, SimRobot, byte_pipe};
use mechweed_hw::{Hw, HwError, Outputs};

use crate::camlink::LinkCore;
use crate::config::{CameraPort, GnssPort, Settings};
use crate::gnss::GnssCore;
use crate::gnss::place::RowPlace;
use crate::record::{Given, HwFailure, RecordTap};
use crate::rt::health::ThreadHealth;
use crate::state::modes::{Mode, Refusal, Request};
use crate::state::operator::OperatorScript;
use crate::steer::{SteerCommand, SteerCore};
use crate::supervisor::Supervisor;

/// Simulated time advances in steps of this, us (also the camera link's poll interval).
const STEP_US: u64 = 1000;

/// How the supervisor's inputs and outputs travel between it and the plant.
pub enum Io {
    /// The plant's signals are the supervisor's inputs and outputs.
    Direct,
    /// Plant -> emulated card registers -> drivers -> wiring -> supervisor, and back.
    Cards(Box<CardRig>),
}

impl Io {
    /// Emulated cards set up and wired as `settings` says ([hw], [io]).
    pub fn cards(settings: &Settings) -> Result<Io, HwError> {
        let rig = CardRig::new(&settings.cards, &settings.io)?;
        Ok(Io::Cards(Box::new(rig)))
    }
}

pub struct Lockstep {
    pub robot: SimRobot,
    pub io: Io,
    pipe: PipeEnd,
    pub supervisor: Supervisor,
    pub steer: SteerCore,
    pub link: LinkCore,
    pub steer_command: SteerCommand,
    /// The simulated GNSS receiver's line and its decoder, with [gnss] port = sim.
    gnss_pipe: Option<PipeEnd>,
    pub gnss: GnssCore,
    operator: OperatorScript,
    t_us: u64,
    supervisor_period_us: u64,
    steer_period_us: u64,
    next_steer_us: u64,
    buf: [u8; 512],
    pub steer_ticks: u64,
    /// Where each supervisor tick is recorded, if anywhere (see `record_into`).
    record: Option<RecordTap>,
    /// The row filter's error at the tool, if asked for (see `track_filter_error`).
    filter_error: Option<FilterErrorTrack>,
}

/// How far the row filter's estimate of the tool's offset is from the truth, sampled at
/// every steer tick (when the filter has just been brought to now) and weighted by
/// distance like the tool's cross-track error, over the same stretch of row. It splits
/// the tool's error into what the filter misjudged and what the steering did not correct.
struct FilterErrorTrack {
    tool_x_m: f64,
    from_m: f64,
    next_mark: u64,
    stats: CrossTrackStats,
}

impl FilterErrorTrack {
    fn sample(&mut self, steer: &SteerCore, robot: &SimRobot) {
        let truth = robot.truth();
        let marks = (truth.distance_m / SAMPLE_SPACING_M).floor() as u64;
        if marks < self.next_mark || truth.row_done {
            return;
        }
        let count = marks - self.next_mark + 1;
        self.next_mark = marks + 1;
        if truth.distance_m >= self.from_m {
            // The filter gives the row's offset from the tool (positive: the row lies to
            // the left), the truth the tool's offset from the row.
            let (row_at_tool_m, _) = steer.rows().filter().row_at(self.tool_x_m);
            self.stats
                .record(truth.tool_cross_track_m + row_at_tool_m, count);
        }
    }
}

impl Lockstep {
    /// A simulated robot at the row start with the controller beside it; the operator
    /// script pursues `start_mode` and the operator actions of [sim] events.
    pub fn new(settings: &Settings, start_mode: Mode) -> Lockstep {
        Lockstep::with_io(settings, start_mode, Io::Direct)
    }

    /// The same, with the supervisor reaching the plant through `io`.
    /// With [gnss] port = sim the robot carries its GNSS receiver, and GNSS steers by
    /// the simulated field's own map (whatever [gnss] map says: this is the field).
    pub fn with_io(settings: &Settings, start_mode: Mode, io: Io) -> Lockstep {
        let (camera_end, robot_end) = byte_pipe(4096);
        let with_receiver = settings.gnss.port == GnssPort::Link(CameraPort::Sim);
        let (receiver_end, gnss_pipe) = if with_receiver {
            let (receiver_end, program_end) = byte_pipe(8192);
            (Some(receiver_end), Some(program_end))
        } else {
            (None, None)
        };
        let mut robot = SimRobot::with_gnss(&settings.sim, camera_end, receiver_end);
        if let Io::Cards(_) = io {
            robot.dacs_on_cards();
        }
        let g = &settings.gnss;
        let place = with_receiver
            .then(|| {
                RowPlace::from_points(&robot.planted_map(), g.antenna_ahead_m, g.antenna_left_m)
                    .ok()
            })
            .flatten();
        // The camera's pipe is open from the start, as a port the link thread opened.
        let mut link = LinkCore::new(&settings.camera);
        link.connected();
        Lockstep {
            robot,
            io,
            pipe: robot_end,
            supervisor: Supervisor::new(settings),
            steer: SteerCore::with_map(settings, place),
            gnss_pipe,
            gnss: GnssCore::new(),
            link,
            steer_command: SteerCommand::default(),
            operator: OperatorScript::new(&settings.sim.events, start_mode),
            t_us: 0,
            supervisor_period_us: (1e6 / settings.supervisor.rate_hz).round() as u64,
            steer_period_us: (1e6 / settings.steer.rate_hz).round() as u64,
            next_steer_us: 0,
            buf: [0; 512],
            steer_ticks: 0,
            record: None,
            filter_error: None,
        }
    }

    pub fn now_s(&self) -> f64 {
        self.t_us as f64 * 1e-6
    }

    /// Record every supervisor tick from now on into `tap` (from `record::start`, best
    /// with `Delivery::WaitForRoom`: simulated time loses nothing by waiting).
    pub fn record_into(&mut self, tap: RecordTap) {
        self.record = Some(tap);
    }

    /// Stop recording: drops the tap, so that the recorder can finish its files.
    pub fn stop_recording(&mut self) {
        self.record = None;
    }

    /// From now on, compare the row filter's estimate of the offset of the tool
    /// (`tool_x_m` ahead of the rear axle) with the truth at every steer tick, once the
    /// robot has driven `from_m` (the benchmark's split of the tool's error).
    pub(crate) fn track_filter_error(&mut self, tool_x_m: f64, from_m: f64) {
        self.filter_error = Some(FilterErrorTrack {
            tool_x_m,
            from_m,
            next_mark: 0,
            stats: CrossTrackStats::new(),
        });
    }

    /// The row filter's error at the tool so far, if tracked.
    pub(crate) fn filter_error(&self) -> Option<&CrossTrackStats> {
        self.filter_error.as_ref().map(|t| &t.stats)
    }

    /// Send a request to the supervisor, as the GUI would.
    pub fn request(&mut self, request: Request) -> Result<(), Refusal> {
        let answer = self.handle(request);
        // As the real-time run passes them on its channel: the steer "thread" takes them.
        if let Some(settings) = self.supervisor.take_steer_settings() {
            self.steer.set_law_settings(&settings);
        }
        answer
    }

    fn steer_tick(&mut self) {
        let now = self.now_s();
        self.steer_command = self.steer.tick(
            now,
            self.supervisor.status(),
            self.link.status(),
            self.gnss.status(),
        );
        self.steer_ticks += 1;
        if let Some(track) = &mut self.filter_error {
            track.sample(&self.steer, &self.robot);
        }
    }

    /// Advance to the next supervisor tick, run it, and return the outputs it wrote.
    pub fn tick(&mut self) -> Outputs {
        self.advance();
        self.supervisor_step()
    }

    /// Everything up to the next supervisor tick: the plant, the camera link, the steer
    /// tick, and the operator's requests.
    pub fn advance(&mut self) {
        let step_us = STEP_US.min(self.supervisor_period_us);
        let next_supervisor_us =
            (self.t_us / self.supervisor_period_us + 1) * self.supervisor_period_us;
        while self.t_us < next_supervisor_us {
            self.t_us = (self.t_us + step_us).min(next_supervisor_us);
            let now = self.now_s();
            self.robot.advance_to(now);
            let n = self.pipe.try_read(&mut self.buf);
            let new_estimate = self.link.receive(&self.buf[..n], now);
            self.link.beat(now);
            if let Some(pipe) = &mut self.gnss_pipe {
                let n = pipe.try_read(&mut self.buf);
                self.gnss.receive(&self.buf[..n], now);
                self.gnss.beat(now);
            }
            if new_estimate || self.t_us >= self.next_steer_us {
                if self.t_us >= self.next_steer_us {
                    self.next_steer_us += self.steer_period_us;
                }
                self.steer_tick();
            }
            let ping = self.link.keepalive_due(now).then(|| self.link.ping(now));
            let command = self.link.command(self.steer_command.wants_rows, now);
            for byte in [ping, command].into_iter().flatten() {
                use std::io::Write;
                // The pipe drops what does not fit, as a UART would; a command is one byte.
                let _ = self.pipe.write(&[byte]);
            }
        }
        let now = self.now_s();
        if let Some(request) = self.operator.due(now, self.supervisor.status()) {
            // A refused request is what a person would see greyed out; the status shows why.
            let _ = self.handle(request);
        }
    }

    /// The supervisor handles a request before its next tick; the record keeps both.
    fn handle(&mut self, request: Request) -> Result<(), Refusal> {
        let answer = self.supervisor.handle(request);
        let (now_s, next_tick) = (self.now_s(), self.supervisor.status().tick + 1);
        if let Some(tap) = &mut self.record {
            tap.requested(now_s, next_tick, request, answer);
        }
        answer
    }

    /// The supervisor's tick as its thread runs it: read every input, tick, write every
    /// output.
    pub fn supervisor_step(&mut self) -> Outputs {
        let now = self.now_s();
        let (steer, link) = (&self.steer_command, self.link.status());
        // In lockstep every "thread" is a function call: none can stall or panic unseen.
        let health = ThreadHealth::default();
        let mut hw_failed = None;
        let outputs = match &mut self.io {
            Io::Direct => {
                let outputs = self
                    .supervisor
                    .tick(now, &self.robot.inputs(), steer, link, &health);
                self.robot.set_outputs(&outputs);
                outputs
            }
            Io::Cards(rig) => {
                // As the supervisor thread (threads/supervisor.rs) does with its Hw.
                rig.set_amplifier_switches_unipolar(self.robot.miswire() == Miswire::Dda06Unipolar);
                rig.set_wires(&self.robot.inputs());
                let mut outputs = match rig.hw.read() {
                    Ok(inputs) => self.supervisor.tick(now, &inputs, steer, link, &health),
                    Err(e) => {
                        hw_failed = Some(HwFailure {
                            during: "read",
                            card: e.card(),
                        });
                        self.supervisor.hardware_failed(now, e.card())
                    }
                };
                if let Err(e) = rig.hw.write(&outputs) {
                    hw_failed = Some(HwFailure {
                        during: "write",
                        card: e.card(),
                    });
                    outputs = self.supervisor.hardware_failed(now, e.card());
                }
                self.robot.set_outputs(&rig.plant_outputs());
                outputs
            }
        };
        if let Some(tap) = &mut self.record {
            let truth = self.robot.truth();
            tap.offer(
                self.supervisor.status(),
                &self.steer_command,
                self.link.status(),
                Some(&truth),
                &Given { health, hw_failed },
            );
        }
        outputs
    }

    /// Run supervisor ticks for `seconds` of simulated time.
    pub fn run_for(&mut self, seconds: f64) {
        let end_us = self.t_us + (seconds * 1e6).round() as u64;
        while self.t_us < end_us {
            self.tick();
        }
    }
}
