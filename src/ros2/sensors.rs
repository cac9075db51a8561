//! The sensors' messages from a status: the GNSS fix on /fix, and the row filter's row
//! on /row with the transform from base_link to the row's frame on /tf, so that rviz2
//! draws the row where the filter has it.

use serde_json::Value;

use super::msgs::{
    Covariance6, NavSatFix, NavSatStatus, Pose, PoseWithCovariance, PoseWithCovarianceStamped,
    Quaternion, TfMessage, Time, Transform, TransformStamped, Vector3,
};
use super::odom::header;

/// Up's variance when the robot does not know it, m²: so large that nothing trusts it.
pub const UNKNOWN_VARIANCE_M2: f64 = 1e6;

/// z, roll and pitch of a 6 × 6 covariance (rows 2, 3, 4): a robot on a plane does not
/// measure them, so their variance is one nothing trusts.
pub fn off_the_plane_unknown(cov: &mut Covariance6) {
    for k in [2, 3, 4] {
        cov[7 * k] = UNKNOWN_VARIANCE_M2;
    }
}
/// A heading's s.d. the robot did not say (a status from before it said one), rad.
const UNKNOWN_SD_RAD: f64 = 1e3;

/// The GGA quality as NavSatStatus says it: 1 GPS and 3 PPS a plain fix, 2 DGPS
/// satellite-augmented, 4 and 5 RTK ground-augmented; 0, and 6 dead reckoning, 7 manual,
/// 8 simulation, no fix of the sky.
pub(super) fn nav_sat_fix(
    quality: u64,
    lat: Option<f64>,
    lon: Option<f64>,
    sd_m: Option<f64>,
    stamp: Time,
    frame: &str,
) -> NavSatFix {
    let status = match quality {
        1 | 3 => 0,
        2 => 1,
        4 | 5 => 2,
        _ => -1,
    };
    // The robot carries the worse of the receiver's east and north s.d. (GST), not the
    // altitude: east and north from it, approximated; up is not known.
    let (covariance, kind) = match sd_m {
        Some(sd) => (
            [
                sd * sd,
                0.0,
                0.0,
                0.0,
                sd * sd,
                0.0,
                0.0,
                0.0,
                UNKNOWN_VARIANCE_M2,
            ],
            1,
        ),
        None => ([0.0; 9], 0),
    };
    NavSatFix {
        header: header(stamp, frame),
        status: NavSatStatus { status, service: 1 },
        latitude: lat.unwrap_or(f64::NAN),
        longitude: lon.unwrap_or(f64::NAN),
        altitude: f64::NAN,
        position_covariance: covariance,
        position_covariance_type: kind,
    }
}

/// The rear axle's place in the row's frame, from the row filter: the row offset `o`
/// (+ = row left of the robot) puts the robot at y = -o, and the row's heading
/// relative to the robot turns it by its negative.
pub(super) fn row(filter: &Value, stamp: Time, frame: &str) -> Option<PoseWithCovarianceStamped> {
    let offset_m = filter["offset_m"].as_f64()?;
    let heading_rad = filter["heading_rad"].as_f64()?;
    // The filter's own spread: across the row and of the heading; along it the robot
    // is at x = 0 by the frame's making; up, roll and pitch are not known.
    let sd_m = filter["offset_sd_m"].as_f64().unwrap_or(0.0);
    let heading_sd_rad = filter["heading_sd_rad"].as_f64().unwrap_or(UNKNOWN_SD_RAD);
    let mut covariance = [0.0; 36];
    covariance[7] = sd_m * sd_m;
    covariance[35] = heading_sd_rad * heading_sd_rad;
    off_the_plane_unknown(&mut covariance);
    Some(PoseWithCovarianceStamped {
        header: header(stamp, frame),
        pose: PoseWithCovariance {
            pose: Pose {
                position: Vector3 {
                    x: 0.0,
                    y: -offset_m,
                    z: 0.0,
                },
                orientation: Quaternion::yaw(-heading_rad),
            },
            covariance,
        },
    })
}

/// base_link -> row: the row's frame as the robot sees it, the inverse of /row's pose.
/// The row's point abreast of the rear axle is `offset_m` to its left, and the row runs
/// at `heading_rad` (+ = left) from the robot's x.
pub(super) fn row_transform(
    filter: &Value,
    stamp: Time,
    base: &str,
    frame: &str,
) -> Option<TfMessage> {
    let offset_m = filter["offset_m"].as_f64()?;
    let heading_rad = filter["heading_rad"].as_f64()?;
    let (s, c) = heading_rad.sin_cos();
    Some(TfMessage {
        transforms: vec![TransformStamped {
            header: header(stamp, base),
            child_frame_id: frame.to_string(),
            transform: Transform {
                translation: Vector3 {
                    x: -offset_m * s,
                    y: offset_m * c,
                    z: 0.0,
                },
                rotation: Quaternion::yaw(heading_rad),
            },
        }],
    })
}
