//! The GNSS side of a real-time run: the row map, the simulated receiver's serial cable,
//! and the link thread. Prepared before anything starts (everything that can fail: the
//! map file, the pseudo-terminal), started with the other threads.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::thread::JoinHandle;
use std::time::Instant;

use mechweed_hw::geo::Geodetic;
use mechweed_hw::sim::PipeEnd;

use super::GnssStatus;
use super::place::RowPlace;
use super::thread::GnssThread;
use crate::camlink::simwire;
use crate::config::{Backend, CameraPort, GnssPort, MapSource, Settings};
use crate::gnss::rowmap::read_map;
use crate::rt::health::PanicFlag;
use crate::state::{Reader, Writer, shared};

/// Why the GNSS side could not be prepared (nothing has started then).
#[derive(Debug, thiserror::Error)]
pub enum GnssRunError {
    #[error(
        "[gnss] port = sim needs the simulated robot: set [gnss] port to the receiver's serial device (e.g. /dev/ttyACM0) or tcp://HOST:PORT"
    )]
    SimulatedReceiverOnRealRobot,
    #[error(
        "[gnss] map = sim is the simulated field's own map: on the real robot name a row map file ([gnss] map = config/rows.csv)"
    )]
    SimulatedMapOnRealRobot,
    #[error("the row map: {0}")]
    Map(String),
    #[error("cannot make a pseudo-terminal for the simulated GNSS receiver: {0}")]
    Wire(std::io::Error),
}

/// Everything ready: the map for the steer thread, the status for whoever reads it,
/// and the thread to start.
pub struct GnssRun {
    pub place: Option<RowPlace>,
    pub status: Reader<GnssStatus>,
    /// The link thread's port and its writing end of the status, until it starts.
    link: Option<(CameraPort, Writer<GnssStatus>)>,
    pub cable: Option<JoinHandle<()>>,
}

/// Prepare the GNSS side of a run. `receiver` is the simulated receiver's end of its
/// line and `planted` its field's map (simulated robot with [gnss] port = sim).
pub fn prepare(
    s: &Settings,
    receiver: Option<PipeEnd>,
    planted: Option<Vec<Geodetic>>,
    stop: &Arc<AtomicBool>,
) -> Result<GnssRun, GnssRunError> {
    let (writer, status) = shared(GnssStatus::default());
    let g = &s.gnss;
    let link = match &g.port {
        GnssPort::None => {
            return Ok(GnssRun {
                place: None,
                status,
                link: None,
                cable: None,
            });
        }
        GnssPort::Link(port) => port,
    };
    if *link == CameraPort::Sim && s.backend == Backend::Cards {
        return Err(GnssRunError::SimulatedReceiverOnRealRobot);
    }
    let place = match (&g.map, planted) {
        (MapSource::Sim, Some(points)) => {
            RowPlace::from_points(&points, g.antenna_ahead_m, g.antenna_left_m)
        }
        (MapSource::Sim, None) => return Err(GnssRunError::SimulatedMapOnRealRobot),
        (MapSource::File(path), _) => {
            let map = read_map(path).map_err(|e| GnssRunError::Map(e.to_string()))?;
            let label = path.display().to_string();
            RowPlace::new(
                &map,
                &label,
                (g.antenna_ahead_m, g.antenna_left_m),
                g.origin,
            )
        }
    }
    .map_err(GnssRunError::Map)?;
    let (port, cable) = match (link, receiver) {
        (CameraPort::Sim, Some(pipe)) => {
            let (path, cable) = simwire::start_named(pipe, stop.clone(), "gnss-cable")
                .map_err(GnssRunError::Wire)?;
            (
                CameraPort::Serial {
                    path,
                    baud: 115_200,
                },
                Some(cable),
            )
        }
        (port, _) => (port.clone(), None),
    };
    Ok(GnssRun {
        place: Some(place),
        status,
        link: Some((port, writer)),
        cable,
    })
}

impl GnssRun {
    /// Start the link thread (none without a receiver).
    pub fn start(
        &mut self,
        clock: Instant,
        panics: Arc<PanicFlag>,
        stop: Arc<AtomicBool>,
    ) -> Option<JoinHandle<()>> {
        let (port, writer) = self.link.take()?;
        let thread = GnssThread::new(port, clock, writer, panics, stop);
        let handle = std::thread::Builder::new()
            .name("gnss".into())
            .spawn(move || thread.run())
            .unwrap_or_else(|e| panic!("cannot start the GNSS link thread: {e}"));
        Some(handle)
    }
}
