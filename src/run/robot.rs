//! The first steps of a run: the robot (the simulated one, or the I/O cards) and where
//! its camera computer is. Each fails before any thread of the run has started.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::thread::JoinHandle;

use mechweed_hw::Hw;
use mechweed_hw::geo::Geodetic;
use mechweed_hw::sim::{PipeEnd, SimControl, SimHw, SimRobot, TruthHandle, byte_pipe};

use super::RunError;
use crate::camlink::simwire;
use crate::config::{Backend, CameraPort, GnssPort, Settings};

/// The robot a run drives, and the simulated devices' ends of their lines.
pub(super) struct Robot {
    pub hw: Box<dyn Hw>,
    /// The simulated robot's true state (none on the real robot).
    pub truth: TruthHandle,
    /// The simulated robot's controls, for the GUI's panel.
    pub sim: Option<SimControl>,
    /// The simulated camera computer's end of its serial line.
    pub camera_line: PipeEnd,
    /// The program's end of the simulated GNSS receiver's line ([gnss] port = sim).
    pub receiver: Option<PipeEnd>,
    /// The simulated field's planting record, for a row map of it.
    pub planted: Option<Vec<Geodetic>>,
}

/// Open the robot `[hw] backend` names: the simulated one with its camera computer
/// (and GNSS receiver when [gnss] port = sim), or the I/O cards.
pub(super) fn open_robot(s: &Settings) -> Result<Robot, RunError> {
    let (camera_end, camera_line) = byte_pipe(4096);
    match s.backend {
        Backend::Sim => {
            let (mut receiver, mut receiver_end) = (None, None);
            if s.gnss.port == GnssPort::Link(CameraPort::Sim) {
                let (robot_end, program_end) = byte_pipe(8192);
                receiver_end = Some(robot_end);
                receiver = Some(program_end);
            }
            let robot = SimRobot::with_gnss(&s.sim, camera_end, receiver_end);
            let planted = (s.gnss.port != GnssPort::None).then(|| robot.planted_map());
            let sim = SimHw::new(robot);
            let (truth, control) = (sim.truth_handle(), sim.control());
            Ok(Robot {
                hw: Box::new(sim),
                truth,
                sim: Some(control),
                camera_line,
                receiver,
                planted,
            })
        }
        // No simulated camera computer, no truth and no simulator panel on the real robot.
        Backend::Cards => Ok(Robot {
            hw: crate::threads::backend::open_hw(s).map_err(RunError::Cards)?,
            truth: TruthHandle::none(),
            sim: None,
            camera_line,
            receiver: None,
            planted: None,
        }),
    }
}

/// Where the camera link finds the camera computer: the simulated one speaks through a
/// pseudo-terminal (its cable thread is returned), unless robot.ini names a real port,
/// when it stays unplugged and the port's camera computer is used.
pub(super) fn camera_port(
    s: &Settings,
    camera_line: PipeEnd,
    stop: &Arc<AtomicBool>,
) -> Result<(CameraPort, Option<JoinHandle<()>>), RunError> {
    match (&s.camera_port, s.backend) {
        (CameraPort::Sim, Backend::Sim) => {
            let (path, cable) =
                simwire::start(camera_line, stop.clone()).map_err(RunError::SimulatedCameraWire)?;
            Ok((CameraPort::Serial { path, baud: 115200 }, Some(cable)))
        }
        (CameraPort::Sim, Backend::Cards) => Err(RunError::SimulatedCameraOnRealRobot),
        (port, _) => Ok((port.clone(), None)),
    }
}
