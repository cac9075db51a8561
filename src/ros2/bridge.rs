//! `mechweed ros2`: the robot's flows, heard on its bus, published as ROS 2 topics on
//! the ROS machines' router in rmw_zenoh's format. Two sessions: a tool's on the
//! robot's bus (a viewer, when the bus is secured) and a client's of the ROS router.
//! Nothing else goes the other way: the bridge declares no subscriber on the ROS side,
//! and its one service, HALT, is offered only with `[ros2] halt_service = yes`.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use zenoh::Wait;
use zenoh::liveliness::LivelinessToken;
use zenoh::pubsub::Publisher;
use zenoh::qos::CongestionControl;
use zenoh_ext::{AdvancedPublisher, AdvancedPublisherBuilderExt, CacheConfig, MissDetectionConfig};

use mechweed_core::config::{Ros2Settings, TlsFiles};

use super::flows::Outgoing;
use super::halt::{AskHalt, HaltService};
use super::model::RobotModel;
use super::pump::Robot;
use super::topics::Topic;
use super::wire::{Node, attachment};
use crate::bus::session::{self, BusError, Role};

/// A missing router is tried again after this long.
const RETRY: Duration = Duration::from_secs(2);
/// A transient-local publisher says how far it has got this often when it has
/// published since, so that a subscriber finds what it missed: rmw_zenoh's period.
const MISS_HEARTBEAT: Duration = Duration::from_millis(500);

pub struct Options {
    /// The robot's bus.
    pub connect: String,
    pub robot: String,
    pub ros: Ros2Settings,
    /// The robot's geometry: robot_description, /tf_static and the covariances.
    pub model: RobotModel,
    /// With `[ros2] halt_service = yes`: how a call of the HALT service asks the robot.
    pub halt: Option<AskHalt>,
    /// This program's identity on a secured robot bus.
    pub tls: Option<TlsFiles>,
    /// Stop after this long (None: at Ctrl-C).
    pub seconds: Option<f64>,
}

/// The ROS side: the node's session, its tokens and a publisher per topic.
struct RosSide {
    /// Each topic's publisher, its GID and its last sequence number.
    publishers: HashMap<Topic, (Out, [u8; 16], i64)>,
    _tokens: Vec<LivelinessToken>,
    _halt: Option<HaltService>,
    /// Last: dropped after what it declared.
    _session: zenoh::Session,
}

/// Open the ROS side, trying again every 2 s while the router is not there, until
/// `stop` or the end.
fn connect_ros(opts: &Options, stop: &AtomicBool, end: Option<Instant>) -> Option<RosSide> {
    let router = &opts.ros.connect;
    loop {
        if stop.load(Ordering::Relaxed) || end.is_some_and(|end| Instant::now() >= end) {
            return None;
        }
        match open_ros(opts) {
            Ok(side) => return Some(side),
            Err(why) => eprintln!(
                "ros2: cannot reach the ROS router at {router}: {why}; trying again in {} s (is rmw_zenohd running there? [ros2] connect or --connect names it)",
                RETRY.as_secs()
            ),
        }
        std::thread::sleep(RETRY);
    }
}

fn open_ros(opts: &Options) -> Result<RosSide, String> {
    let role = Role::RosClient {
        router: opts.ros.connect.clone(),
    };
    let session = session::open(role, None).map_err(|e| match e {
        BusError::Unreachable { why, .. } => why,
        other => other.to_string(),
    })?;
    let node = Node {
        domain_id: opts.ros.domain_id,
        zid: session.zid().to_string(),
        namespace: opts.ros.namespace.clone(),
        distro: opts.ros.distro,
    };
    let z = |e: zenoh::Error| session::plain_words(&e);
    let mut tokens = vec![
        session
            .liveliness()
            .declare_token(node.node_token())
            .wait()
            .map_err(z)?,
    ];
    let mut publishers = HashMap::new();
    for topic in Topic::ALL {
        tokens.push(
            session
                .liveliness()
                .declare_token(node.publisher_token(topic))
                .wait()
                .map_err(z)?,
        );
        let publisher = session
            .declare_publisher(node.data_key(topic))
            // A slow ROS machine loses samples; it never holds the bridge up.
            .congestion_control(CongestionControl::Drop);
        let offered = topic.offered();
        let publisher = if offered.transient_local {
            // As rmw_zenoh does for a reliable transient-local publisher: a cache of
            // the last `depth` samples (attachments and all) that a late subscriber's
            // history query is answered from, found by its liveliness token.
            let cache = CacheConfig::default().max_samples(offered.depth as usize);
            let misses = MissDetectionConfig::default().sporadic_heartbeat(MISS_HEARTBEAT);
            Out::Latched(
                publisher
                    .cache(cache)
                    .sample_miss_detection(misses)
                    .publisher_detection()
                    .wait()
                    .map_err(z)?,
            )
        } else {
            Out::Plain(publisher.wait().map_err(z)?)
        };
        publishers.insert(topic, (publisher, node.gid(topic), 0));
    }
    let halt = (opts.halt.clone())
        .map(|ask| HaltService::offer(&session, &node, ask))
        .transpose()?;
    Ok(RosSide {
        publishers,
        _tokens: tokens,
        _halt: halt,
        _session: session,
    })
}

impl RosSide {
    /// Put one message with its attachment; the sequence goes up per publisher.
    fn put(&mut self, out: &Outgoing) -> bool {
        let Some((publisher, gid, sequence)) = self.publishers.get_mut(&out.topic) else {
            return false;
        };
        *sequence += 1;
        let now_ns = (crate::bus::payload::wall_s() * 1e9) as i64;
        let attachment = attachment(*sequence, now_ns, gid).to_vec();
        let bytes = out.bytes.clone();
        match publisher {
            Out::Plain(p) => p.put(bytes).attachment(attachment).wait().is_ok(),
            Out::Latched(p) => p.put(bytes).attachment(attachment).wait().is_ok(),
        }
    }
}

/// A topic's publisher: volatile, or transient local with its cache.
enum Out {
    Plain(Publisher<'static>),
    Latched(AdvancedPublisher<'static>),
}

/// Bridge until `stop` (Ctrl-C) or `seconds`; returns the closing summary.
pub fn run(opts: &Options, stop: &AtomicBool) -> Result<String, String> {
    let end = opts
        .seconds
        .map(|s| Instant::now() + Duration::from_secs_f64(s));
    let ros = &opts.ros;
    println!(
        "ros2: the flows of {} at {} to the ROS router at {}: domain {}, namespace {}, {}",
        opts.robot,
        opts.connect,
        ros.connect,
        ros.domain_id,
        ros.namespace,
        ros.distro.name()
    );
    // The router first: the robot's flows are heard only once they can go somewhere,
    // not queued while it is missing and sent late as if new.
    let Some(mut side) = connect_ros(opts, stop, end) else {
        return Ok("ros2: stopped before the ROS router was reached".to_string());
    };
    let robot = Robot::hear(&opts.connect, &opts.robot, opts.tls.as_ref(), "ros2")?;
    let names: Vec<String> = Topic::ALL.iter().map(|t| t.name(&ros.namespace)).collect();
    println!(
        "ros2: node {}/{} publishes {}",
        ros.namespace.trim_end_matches('/'),
        super::wire::NODE_NAME,
        names.join(", ")
    );
    if opts.halt.is_some() {
        println!(
            "ros2: the HALT service {}/halt is offered ([ros2] halt_service = yes)",
            ros.namespace.trim_end_matches('/')
        );
    }
    let pumped = robot.pump(ros, &opts.model, stop, end, "ros2", |m| side.put(m));
    Ok(format!(
        "ros2: {}",
        pumped.line(&opts.robot, "ROS messages")
    ))
}
