//! CDR, as ROS 2 puts a message on the wire and in a bag: the 4-byte encapsulation
//! header `00 01 00 00` (plain CDR, little-endian), then the fields in order, each
//! aligned to its own size counted from the byte after the header (cdr-encoding).

use byteorder::LittleEndian;
use serde::Serialize;
use serde::de::DeserializeOwned;

use super::msgs::{
    BatteryState, DiagnosticArray, Float64, JointState, Log, NavSatFix, Odometry,
    PoseWithCovarianceStamped, StringMsg, TfMessage,
};
use super::types::{self, MsgType};

/// CDR, little-endian, options 0.
pub const ENCAPSULATION: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

/// A message a topic carries: its struct and its ROS type.
pub trait RosMessage: Serialize {
    const TYPE: &'static MsgType;
}

macro_rules! ros_message {
    ($($rust:ty => $ros:expr),* $(,)?) => {
        $(impl RosMessage for $rust {
            const TYPE: &'static MsgType = &$ros;
        })*
    };
}

ros_message! {
    Float64 => types::FLOAT64,
    StringMsg => types::STRING,
    PoseWithCovarianceStamped => types::POSE_WITH_COVARIANCE_STAMPED,
    Odometry => types::ODOMETRY,
    TfMessage => types::TF_MESSAGE,
    NavSatFix => types::NAV_SAT_FIX,
    JointState => types::JOINT_STATE,
    DiagnosticArray => types::DIAGNOSTIC_ARRAY,
    Log => types::LOG,
    BatteryState => types::BATTERY_STATE,
}

/// The message's bytes on the wire: header and CDR.
pub fn encode<T: Serialize>(message: &T) -> Result<Vec<u8>, String> {
    let mut bytes = ENCAPSULATION.to_vec();
    cdr_encoding::to_writer::<T, LittleEndian, _>(&mut bytes, message)
        .map_err(|e| format!("cannot write CDR: {e}"))?;
    Ok(bytes)
}

/// A message from its bytes on the wire; an error names what is wrong.
pub fn decode<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, String> {
    let Some(body) = bytes.strip_prefix(&ENCAPSULATION) else {
        let start: Vec<String> = bytes.iter().take(4).map(|b| format!("{b:02x}")).collect();
        return Err(format!(
            "not little-endian CDR: the header is [{}], not [00 01 00 00]",
            start.join(" ")
        ));
    };
    let (message, used) = cdr_encoding::from_bytes::<T, LittleEndian>(body)
        .map_err(|e| format!("not this message's CDR: {e}"))?;
    // A sender pads the end to 4 bytes at most; more left over is another message.
    if body.len() - used > 3 {
        return Err(format!(
            "{} bytes left over after the message",
            body.len() - used
        ));
    }
    Ok(message)
}
