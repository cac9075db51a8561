//! `mechweed record --ros2`: the bridge's messages in an MCAP file of the `ros2`
//! profile, which `ros2 bag info` and `ros2 bag play` take and Foxglove decodes
//! without a plug-in: one `ros2msg` schema per type (its `.msg` text and those it
//! uses), one `cdr` channel per topic with the metadata rosbag2 writes (the offered
//! QoS and the type hash), the messages' bytes as on the wire, and the summary with
//! its statistics. The JSON records of `record --bus` are another file, unchanged.

use std::collections::{BTreeMap, HashMap};
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use mcap::records::MessageHeader;
use mcap::{Compression, WriteOptions, Writer};

use mechweed_core::config::{Distro, RecordSettings, Ros2Settings, TlsFiles};

use super::flows::Outgoing;
use super::model::RobotModel;
use super::pump::Robot;
use super::topics::{Offered, Topic};
use super::types::{MsgType, schema_text};

/// rosbag2's word for a duration without end.
const INFINITE: &str = "\n    sec: 9223372036\n    nsec: 854775807";

/// The QoS a publisher offers, as rosbag2 (Jazzy) writes it in a channel's metadata:
/// reliable, keep last, no deadline or lease; durability and lifespan as offered.
pub fn offered_qos_profiles(offered: Offered) -> String {
    let depth = offered.depth;
    let durability = if offered.transient_local {
        "transient_local"
    } else {
        "volatile"
    };
    let lifespan = match offered.lifespan_s {
        Some(s) => format!("\n    sec: {s}\n    nsec: 0"),
        None => INFINITE.to_string(),
    };
    format!(
        "- history: keep_last\n  depth: {depth}\n  reliability: reliable\n  durability: {durability}\n  deadline:{INFINITE}\n  lifespan:{lifespan}\n  liveliness: automatic\n  liveliness_lease_duration:{INFINITE}\n  avoid_ros_namespace_conventions: false"
    )
}

pub struct Bag {
    writer: Writer<BufWriter<File>>,
    channels: HashMap<Topic, u16>,
    sequence: u32,
    pub path: PathBuf,
}

fn mcap_error(path: &Path) -> impl Fn(mcap::McapError) -> String + '_ {
    move |e| format!("cannot write {}: {e}", path.display())
}

impl Bag {
    /// A new bag at `path` (which must not exist) with a channel per topic.
    pub fn create(path: &Path, namespace: &str, distro: Distro) -> Result<Bag, String> {
        let file = File::options()
            .write(true)
            .create_new(true)
            .open(path)
            .map_err(|e| format!("cannot make {}: {e}", path.display()))?;
        let err = mcap_error(path);
        let mut writer = WriteOptions::new()
            .compression(Some(Compression::Zstd))
            .profile("ros2")
            .create(BufWriter::new(file))
            .map_err(&err)?;
        let mut schemas: HashMap<&str, u16> = HashMap::new();
        let mut channels = HashMap::new();
        for topic in Topic::ALL {
            let t: &MsgType = topic.msg_type();
            let schema = match schemas.get(t.name) {
                Some(id) => *id,
                None => {
                    let id = writer
                        .add_schema(t.name, "ros2msg", schema_text(t).as_bytes())
                        .map_err(&err)?;
                    schemas.insert(t.name, id);
                    id
                }
            };
            let metadata = BTreeMap::from([
                (
                    "offered_qos_profiles".to_string(),
                    offered_qos_profiles(topic.offered()),
                ),
                ("topic_type_hash".to_string(), t.hash(distro).to_string()),
            ]);
            let channel = writer
                .add_channel(schema, &topic.name(namespace), "cdr", &metadata)
                .map_err(&err)?;
            channels.insert(topic, channel);
        }
        Ok(Bag {
            writer,
            channels,
            sequence: 0,
            path: path.to_path_buf(),
        })
    }

    /// One message: logged now (when it was received, as rosbag2 does), published at
    /// its stamp.
    pub fn write(&mut self, out: &Outgoing) -> Result<(), String> {
        let channel_id = self.channels[&out.topic];
        self.sequence = self.sequence.wrapping_add(1);
        let now_ns = (crate::bus::payload::wall_s() * 1e9) as u64;
        let header = MessageHeader {
            channel_id,
            sequence: self.sequence,
            log_time: now_ns,
            publish_time: out.stamp.unix_ns(),
        };
        self.writer
            .write_to_known_channel(&header, &out.bytes)
            .map_err(mcap_error(&self.path))
    }

    /// The summary and the file's end.
    pub fn finish(mut self) -> Result<PathBuf, String> {
        self.writer.finish().map_err(mcap_error(&self.path))?;
        Ok(self.path)
    }
}

/// The file for a new bag in `folder`: mechweed-ros2-UTC.mcap.
pub fn new_path(folder: &Path) -> Result<PathBuf, String> {
    std::fs::create_dir_all(folder)
        .map_err(|e| format!("cannot make the record folder {}: {e}", folder.display()))?;
    let utc = mechweed_core::record::utc_stamp(std::time::SystemTime::now());
    Ok(folder.join(format!("mechweed-ros2-{utc}.mcap")))
}

pub struct Options {
    pub connect: String,
    pub robot: String,
    pub seconds: Option<f64>,
    pub record: RecordSettings,
    pub ros: Ros2Settings,
    pub model: RobotModel,
    pub tls: Option<TlsFiles>,
}

/// Record the robot's flows as a ROS 2 bag until `stop` or `seconds`; the summary.
pub fn record(opts: &Options, stop: &AtomicBool) -> Result<String, String> {
    let end = opts
        .seconds
        .map(|s| Instant::now() + Duration::from_secs_f64(s));
    let robot = Robot::hear(&opts.connect, &opts.robot, opts.tls.as_ref(), "record-ros2")?;
    let mut bag = Bag::create(
        &new_path(&opts.record.folder)?,
        &opts.ros.namespace,
        opts.ros.distro,
    )?;
    println!(
        "ROS 2 recorder: the flows of {} at {} into {}",
        opts.robot,
        opts.connect,
        bag.path.display()
    );
    let mut broken = None;
    let pumped = robot.pump(
        &opts.ros,
        &opts.model,
        stop,
        end,
        "ROS 2 recorder",
        |m| match bag.write(m) {
            Ok(()) => true,
            Err(why) => {
                broken.get_or_insert(why);
                false
            }
        },
    );
    let path = bag.finish()?;
    if let Some(why) = broken {
        return Err(format!("ROS 2 recorder: {why}"));
    }
    Ok(format!(
        "ROS 2 bag {}: {}",
        path.display(),
        pumped.line(&opts.robot, "messages")
    ))
}
