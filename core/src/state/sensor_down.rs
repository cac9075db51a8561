//! A sensor that autonomous mode needs and cannot hear now, in words: the supervisor
//! finds it (supervisor/sensors.rs) and refuses Autonomous with it.

use std::fmt;

/// A sensor autonomous mode needs, down, and why.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SensorDown {
    /// The camera link's port is not open (why is in the link's own status: the record
    /// keeps only that it is closed, and a replay must give the same words).
    CameraClosed,
    /// The camera link streams and no row frame has come for this long, s.
    CameraSilent { for_s: f64 },
    /// Standing, the camera computer has answered no keep-alive PING for this long
    /// (infinite: never), s.
    CameraUnheard { for_s: f64 },
    /// The GNSS receiver has sent no epoch for this long (infinite: none yet), s.
    GnssSilent { for_s: f64 },
}

impl fmt::Display for SensorDown {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SensorDown::CameraClosed => write!(
                f,
                "the camera link is down: its port is not open (the console and the Status tab's camera line say why); check [camera] port and the cable"
            ),
            SensorDown::CameraSilent { for_s } => write!(
                f,
                "the camera link is silent: no row frame for {for_s:.1} s (is the camera computer running?)"
            ),
            SensorDown::CameraUnheard { for_s } if for_s.is_infinite() => write!(
                f,
                "the camera computer has answered nothing yet: is it switched on, and is [camera] port its line?"
            ),
            SensorDown::CameraUnheard { for_s } => write!(
                f,
                "the camera computer has answered nothing for {for_s:.1} s: is it switched on, and its cable in?"
            ),
            SensorDown::GnssSilent { for_s } if for_s.is_infinite() => write!(
                f,
                "the GNSS receiver has sent nothing yet: check [gnss] port, the cable and the receiver's power"
            ),
            SensorDown::GnssSilent { for_s } => write!(
                f,
                "the GNSS receiver is silent: no epoch for {for_s:.1} s (check its cable and power)"
            ),
        }
    }
}
