//! What a run's threads meet through, made in one place: each protected object's writer
//! goes to the one thread that writes it, its readers to the threads that read it
//! (docs/architecture.md lists who writes and who reads each), and each bounded channel
//! joins two threads.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use crossbeam_channel::{Sender, bounded};
use mechweed_hw::sim::TruthHandle;

use crate::bus::BusFigures;
use crate::bus::rows::RowCounts;
use crate::bus::thread::BusWires;
use crate::camlink::LinkStatus;
use crate::camlink::thread::LinkWires;
use crate::config::{Settings, SteerSettings};
use crate::gnss::GnssStatus;
use crate::record::{self, RecordTap, TickFlow};
use crate::rt::LoopSummary;
use crate::rt::health::PanicFlag;
use crate::state::modes::Gains;
use crate::state::request_channel::{self, SupervisorHandle};
use crate::state::status::Status;
use crate::state::{self, Reader, Writer, shared};
use crate::steer::SteerCommand;
use crate::threads::{SteerWires, SupervisorWires};

/// Ticks waiting for the bus thread: it publishes each as it comes, so a second's worth
/// is plenty; when full, ticks are dropped and counted.
const BUS_QUEUE_TICKS: usize = 64;

/// Every thread's wires, and what the operator interface keeps of them.
pub(super) struct Wired {
    pub steer: SteerWires,
    pub link: LinkWires,
    pub supervisor: SupervisorWires,
    /// None without a bus.
    pub bus: Option<BusWires>,
    pub requests: SupervisorHandle,
    pub status: Reader<Status>,
    pub steer_command: Reader<SteerCommand>,
    pub link_status: Reader<LinkStatus>,
    pub loops: [Reader<LoopSummary>; 2],
    pub ping: Sender<()>,
    pub gui_beat: Writer<f64>,
    pub steer_settings: Reader<SteerSettings>,
    pub bus_figures: Reader<BusFigures>,
    pub row_counts: Arc<RowCounts>,
}

/// Everything the threads of the run `s` share, with `bus` on or off. The GNSS link's
/// status, the record's tap, the panic flag and the stop come from the run's earlier
/// steps.
pub(super) fn wire(
    s: &Settings,
    truth: &TruthHandle,
    bus: bool,
    gnss: Reader<GnssStatus>,
    record: RecordTap,
    panics: &Arc<PanicFlag>,
    stop: &Arc<AtomicBool>,
) -> Wired {
    let (status_w, status_r) = shared(Status::default());
    let (steer_w, steer_r) = shared(SteerCommand::default());
    let (link_w, link_r) = shared(LinkStatus::default());
    let (gui_beat_w, gui_beat_r) = shared(f64::NAN);
    let (steer_settings_w, steer_settings_r) = shared(s.steer);
    let (tuning_w, tuning_r) = shared((Gains::from_settings(s), s.steer));
    let (estimate_tx, estimate_rx) = bounded(1);
    let (ping_tx, ping_rx) = bounded(1);
    let (new_steer_settings_tx, new_steer_settings_rx) = state::mailbox();
    let (supervisor_figures_w, supervisor_figures) = shared(LoopSummary::default());
    let (steer_figures_w, steer_figures) = shared(LoopSummary::default());
    let (handle, request_rx) = request_channel::channel(status_r.clone());
    let (bus_figures_w, bus_figures) = shared(BusFigures::default());
    let row_counts = Arc::new(RowCounts::default());
    let (bus_tap, bus_flow) = match bus {
        true => {
            let (tap, flow) = record::flow(s.bus.tick_every_n, BUS_QUEUE_TICKS, truth.clone());
            (tap, Some(flow))
        }
        false => (RecordTap::off(), None),
    };
    let mut wired = Wired {
        steer: SteerWires {
            new_estimate: estimate_rx,
            command: steer_w,
            status: status_r.clone(),
            link: link_r.clone(),
            gnss,
            figures: steer_figures_w,
            new_settings: new_steer_settings_rx,
            settings: steer_settings_w,
            panics: panics.clone(),
            stop: stop.clone(),
        },
        link: LinkWires {
            new_estimate: estimate_tx,
            ping_requests: ping_rx,
            status: link_w,
            robot: status_r.clone(),
            panics: panics.clone(),
            stop: stop.clone(),
        },
        supervisor: SupervisorWires {
            requests: request_rx,
            status: status_w,
            steer: steer_r.clone(),
            link: link_r.clone(),
            gui_beat: gui_beat_r,
            steer_settings: new_steer_settings_tx,
            tuning: tuning_w,
            figures: supervisor_figures_w,
            record,
            bus: bus_tap,
            panics: panics.clone(),
            stop: stop.clone(),
            load: None,
        },
        bus: None,
        requests: handle,
        status: status_r,
        steer_command: steer_r,
        link_status: link_r,
        loops: [supervisor_figures, steer_figures],
        ping: ping_tx,
        gui_beat: gui_beat_w,
        steer_settings: steer_settings_r,
        bus_figures,
        row_counts,
    };
    wired.bus = bus_flow.map(|flow| wired.bus_wires(flow, tuning_r, bus_figures_w, stop));
    wired
}

impl Wired {
    /// The bus thread's wires: the same readers as the operator interface's, the tick
    /// queue, and the figures it writes.
    fn bus_wires(
        &self,
        flow: TickFlow,
        tuning: Reader<(Gains, SteerSettings)>,
        figures: Writer<BusFigures>,
        stop: &Arc<AtomicBool>,
    ) -> BusWires {
        BusWires {
            status: self.status.clone(),
            link: self.link_status.clone(),
            steer: self.steer_command.clone(),
            loops: self.loops.clone(),
            flow,
            supervisor: self.requests.clone(),
            tuning,
            figures,
            rows: self.row_counts.clone(),
            rows_to_link: None,
            stop: stop.clone(),
        }
    }
}
