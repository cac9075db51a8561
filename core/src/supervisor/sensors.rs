//! The sensors autonomous mode steers by, and whether each can be heard now. The
//! supervisor refuses Autonomous while one it needs is down (rules.rs), with the reason,
//! rather than accept it and fault a moment later with the robot already moving: which
//! sensors are needed follows [steer] source (camera, gnss, or both for fused).
//!
//! The camera link streams rows only while the robot drives, so standing it counts as
//! up while its port is open; streaming, also while row frames keep coming. The GNSS
//! receiver sends its epochs all the time, so it is up while they keep coming.

use crate::camlink::LinkStatus;
use crate::config::{CameraPort, Settings, SteerSource};
use crate::state::sensor_down::SensorDown;
use crate::steer::SteerCommand;

/// A camera computer that has answered no keep-alive for this long while the robot
/// stands is down, s: two PINGs (camlink::KEEPALIVE_S) and their answers' way back.
const CAMERA_UNHEARD_S: f64 = 2.5;

/// A receiver silent this long is down, s, however short [gnss] timeout_s (a fix's
/// age while steering): a 1 Hz receiver is between two epochs for up to a second, and
/// would otherwise be refused and taken by turns.
const GNSS_SILENT_S: f64 = 2.5;

/// The first sensor that autonomous mode needs by `s`'s [steer] source and cannot hear
/// at `now_s`, or None.
pub(crate) fn down(
    s: &Settings,
    link: &LinkStatus,
    steer: &SteerCommand,
    now_s: f64,
) -> Option<SensorDown> {
    let source = s.sources.source;
    if source != SteerSource::Gnss {
        let silent_s = now_s - link.last_row_s.max(link.streaming_since_s);
        if !link.connected {
            return Some(SensorDown::CameraClosed);
        }
        if link.streaming && silent_s > s.camera.link_timeout_s {
            return Some(SensorDown::CameraSilent { for_s: silent_s });
        }
        // Standing, the camera computer answers the link's keep-alive PINGs (rows from
        // the bus come from a program that is asked nothing).
        let unheard_s = now_s - link.heard_s;
        if !link.streaming && s.camera_port != CameraPort::Bus && unheard_s > CAMERA_UNHEARD_S {
            return Some(SensorDown::CameraUnheard { for_s: unheard_s });
        }
    }
    if source != SteerSource::Camera {
        let silent_s = steer.row.gnss_heard_s.map_or(f64::INFINITY, |t| now_s - t);
        if silent_s > s.gnss.timeout_s.max(GNSS_SILENT_S) {
            return Some(SensorDown::GnssSilent { for_s: silent_s });
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Settings;

    /// Fused steering: both sensors needed. The camera's port open, standing.
    fn fused() -> (Settings, LinkStatus, SteerCommand) {
        let mut s = Settings::shipped();
        s.sources.source = SteerSource::Fused;
        let link = LinkStatus {
            connected: true,
            heard_s: 9.9,
            ..LinkStatus::default()
        };
        (s, link, SteerCommand::default())
    }

    #[test]
    fn a_receiver_never_heard_or_silent_too_long_is_down_and_one_heard_is_not() {
        let (s, link, mut steer) = fused();
        let never = down(&s, &link, &steer, 10.0);
        assert_eq!(
            never,
            Some(SensorDown::GnssSilent {
                for_s: f64::INFINITY
            })
        );
        assert!(never.unwrap().to_string().contains("has sent nothing yet"));
        steer.row.gnss_heard_s = Some(10.0 - GNSS_SILENT_S - 0.1);
        assert!(matches!(
            down(&s, &link, &steer, 10.0),
            Some(SensorDown::GnssSilent { .. })
        ));
        // A 1 Hz receiver between two epochs is not down.
        steer.row.gnss_heard_s = Some(9.0);
        assert_eq!(down(&s, &link, &steer, 10.0), None);
        // The camera alone needs no receiver.
        let camera_alone = Settings::shipped();
        steer.row.gnss_heard_s = None;
        assert_eq!(down(&camera_alone, &link, &steer, 10.0), None);
    }

    #[test]
    fn a_camera_port_not_open_or_a_stream_without_frames_is_down() {
        let (s, mut link, mut steer) = fused();
        steer.row.gnss_heard_s = Some(9.9);
        link.connected = false;
        let closed = down(&s, &link, &steer, 10.0).unwrap();
        assert_eq!(closed, SensorDown::CameraClosed);
        assert!(
            closed.to_string().contains("check [camera] port"),
            "{closed}"
        );
        link.connected = true;
        // Streaming for a second with no frame: silent.
        link.streaming = true;
        link.streaming_since_s = 9.0;
        assert!(matches!(
            down(&s, &link, &steer, 10.0),
            Some(SensorDown::CameraSilent { .. })
        ));
        // Just started streaming: frames are on their way.
        link.streaming_since_s = 9.9;
        assert_eq!(down(&s, &link, &steer, 10.0), None);
        // Standing, a camera computer switched off answers no keep-alive.
        link.streaming = false;
        link.heard_s = 10.0 - CAMERA_UNHEARD_S - 0.1;
        let unheard = down(&s, &link, &steer, 10.0).unwrap();
        assert!(
            matches!(unheard, SensorDown::CameraUnheard { .. }),
            "{unheard:?}"
        );
        assert!(
            unheard.to_string().contains("answered nothing"),
            "{unheard}"
        );
        link.heard_s = 9.5;
        assert_eq!(down(&s, &link, &steer, 10.0), None);
    }
}
