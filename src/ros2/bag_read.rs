//! A ROS 2 bag of `mechweed record --ros2` read back: every message decoded by its
//! channel's schema, for `mechweed record summary` and the tests. An error names the
//! file and the message.

use std::collections::BTreeMap;
use std::path::Path;

use super::cdr::decode;
use super::msgs::{
    BatteryState, DiagnosticArray, Float64, JointState, Log, NavSatFix, Odometry,
    PoseWithCovarianceStamped, StringMsg, TfMessage,
};
use super::types;

/// One decoded message.
#[derive(Debug, Clone, PartialEq)]
pub enum RosMsg {
    Diagnostics(DiagnosticArray),
    Log(Log),
    Tf(TfMessage),
    Joints(JointState),
    Odom(Box<Odometry>),
    Fix(NavSatFix),
    Row(Box<PoseWithCovarianceStamped>),
    Float(Float64),
    Battery(BatteryState),
    /// The robot's URDF (robot_description).
    Text(StringMsg),
}

/// A message of the bag: its topic, log time (ns since 1970) and content.
#[derive(Debug, Clone, PartialEq)]
pub struct BagMessage {
    pub topic: String,
    pub log_time_ns: u64,
    pub msg: RosMsg,
}

/// Decode `bytes` as the type `schema` names.
pub fn decode_as(schema: &str, bytes: &[u8]) -> Result<RosMsg, String> {
    Ok(match schema {
        s if s == types::DIAGNOSTIC_ARRAY.name => RosMsg::Diagnostics(decode(bytes)?),
        s if s == types::LOG.name => RosMsg::Log(decode(bytes)?),
        s if s == types::TF_MESSAGE.name => RosMsg::Tf(decode(bytes)?),
        s if s == types::JOINT_STATE.name => RosMsg::Joints(decode(bytes)?),
        s if s == types::ODOMETRY.name => RosMsg::Odom(Box::new(decode(bytes)?)),
        s if s == types::NAV_SAT_FIX.name => RosMsg::Fix(decode(bytes)?),
        s if s == types::POSE_WITH_COVARIANCE_STAMPED.name => RosMsg::Row(Box::new(decode(bytes)?)),
        s if s == types::FLOAT64.name => RosMsg::Float(decode(bytes)?),
        s if s == types::BATTERY_STATE.name => RosMsg::Battery(decode(bytes)?),
        s if s == types::STRING.name => RosMsg::Text(decode(bytes)?),
        other => {
            return Err(format!(
                "a message of {other}, which mechweed does not write"
            ));
        }
    })
}

/// Every message of the bag at `path`, in file order.
pub fn read(path: &Path) -> Result<Vec<BagMessage>, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let bad = |why: String| format!("{}: {why}", path.display());
    let profile = profile(&bytes).unwrap_or_default();
    if profile != "ros2" {
        return Err(bad(format!(
            "not a ROS 2 bag (its MCAP profile is '{profile}', not 'ros2')"
        )));
    }
    let mut messages = Vec::new();
    let stream = mcap::MessageStream::new(&bytes).map_err(|e| bad(e.to_string()))?;
    for (i, message) in stream.enumerate() {
        let message = message.map_err(|e| bad(format!("message {}: {e}", i + 1)))?;
        let channel = &message.channel;
        let schema = channel
            .schema
            .as_ref()
            .ok_or_else(|| bad(format!("the channel {} has no schema", channel.topic)))?;
        if schema.encoding != "ros2msg" || channel.message_encoding != "cdr" {
            return Err(bad(format!(
                "the channel {} is {} in {}, not cdr in ros2msg",
                channel.topic, channel.message_encoding, schema.encoding
            )));
        }
        let msg = decode_as(&schema.name, &message.data)
            .map_err(|why| bad(format!("message {} on {}: {why}", i + 1, channel.topic)))?;
        messages.push(BagMessage {
            topic: channel.topic.clone(),
            log_time_ns: message.log_time,
            msg,
        });
    }
    Ok(messages)
}

/// `record summary` of a ROS 2 bag: its span, its topics and their messages, how far
/// /odom went, and the faults and notices on /rosout.
pub fn summary(path: &Path) -> Result<String, String> {
    let messages = read(path)?;
    let mut per_topic: BTreeMap<&str, usize> = BTreeMap::new();
    for m in &messages {
        *per_topic.entry(m.topic.as_str()).or_default() += 1;
    }
    let times = messages.iter().map(|m| m.log_time_ns);
    let span_s = match (times.clone().min(), times.max()) {
        (Some(a), Some(b)) => (b - a) as f64 / 1e9,
        _ => 0.0,
    };
    let mut text = format!(
        "ROS 2 bag {}: {} messages over {span_s:.1} s\n",
        path.display(),
        messages.len()
    );
    for (topic, n) in &per_topic {
        text += &format!("  {topic}: {n}\n");
    }
    let last_odom = messages.iter().rev().find_map(|m| match &m.msg {
        RosMsg::Odom(o) => Some(o.pose.pose.position),
        _ => None,
    });
    if let Some(p) = last_odom {
        text += &format!(
            "odometry: ended {:.2} m ahead and {:.2} m left of where it began\n",
            p.x, p.y
        );
    }
    let warnings: Vec<&str> = messages
        .iter()
        .filter_map(|m| match &m.msg {
            RosMsg::Log(log) if log.level >= 30 => Some(log.msg.as_str()),
            _ => None,
        })
        .collect();
    text += &format!("faults and notices on /rosout: {}\n", warnings.len());
    for w in warnings.iter().take(10) {
        text += &format!("  {w}\n");
    }
    Ok(text)
}

/// The profile in an MCAP file's header; None when it is not MCAP.
fn profile(bytes: &[u8]) -> Option<String> {
    // The header is the first record: the file's end need not be read for it.
    let start = mcap::read::Options::IgnoreEndMagic.into();
    match mcap::read::LinearReader::new_with_options(bytes, start)
        .ok()?
        .next()?
    {
        Ok(mcap::records::Record::Header(header)) => Some(header.profile),
        _ => None,
    }
}

/// Whether the file at `path` is an MCAP file of the `ros2` profile (its first 4 kB).
pub fn is_ros2_bag(path: &Path) -> bool {
    use std::io::Read;
    let mut start = Vec::new();
    let read = std::fs::File::open(path).and_then(|f| f.take(4096).read_to_end(&mut start));
    read.is_ok() && profile(&start).as_deref() == Some("ros2")
}
