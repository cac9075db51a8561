//! The topics the bridge publishes: name, type and quality of service. /tf, /tf_static,
//! /diagnostics and /rosout are the whole ROS system's and keep their absolute names,
//! as rviz2, the diagnostic aggregator and rqt_console expect; the robot's own topics
//! are in the namespace of `[ros2] namespace`.

use super::types::{self, MsgType};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Topic {
    Diagnostics,
    Rosout,
    Tf,
    JointStates,
    Odom,
    Fix,
    Row,
    CrossTrack,
    Battery,
    RobotDescription,
    TfStatic,
}

impl Topic {
    pub const ALL: [Topic; 11] = [
        Topic::Diagnostics,
        Topic::Rosout,
        Topic::Tf,
        Topic::JointStates,
        Topic::Odom,
        Topic::Fix,
        Topic::Row,
        Topic::CrossTrack,
        Topic::Battery,
        Topic::RobotDescription,
        Topic::TfStatic,
    ];

    /// The topic's full name, e.g. /mechweed/odom or /tf.
    pub fn name(self, namespace: &str) -> String {
        let own = |name: &str| format!("{}/{name}", namespace.trim_end_matches('/'));
        match self {
            Topic::Diagnostics => "/diagnostics".to_string(),
            Topic::Rosout => "/rosout".to_string(),
            Topic::Tf => "/tf".to_string(),
            Topic::JointStates => own("joint_states"),
            Topic::Odom => own("odom"),
            Topic::Fix => own("fix"),
            Topic::Row => own("row"),
            Topic::CrossTrack => own("cross_track"),
            Topic::Battery => own("battery_state"),
            Topic::RobotDescription => own("robot_description"),
            Topic::TfStatic => "/tf_static".to_string(),
        }
    }

    pub fn msg_type(self) -> &'static MsgType {
        match self {
            Topic::Diagnostics => &types::DIAGNOSTIC_ARRAY,
            Topic::Rosout => &types::LOG,
            Topic::Tf => &types::TF_MESSAGE,
            Topic::JointStates => &types::JOINT_STATE,
            Topic::Odom => &types::ODOMETRY,
            Topic::Fix => &types::NAV_SAT_FIX,
            Topic::Row => &types::POSE_WITH_COVARIANCE_STAMPED,
            Topic::CrossTrack => &types::FLOAT64,
            Topic::Battery => &types::BATTERY_STATE,
            Topic::RobotDescription => &types::STRING,
            Topic::TfStatic => &types::TF_MESSAGE,
        }
    }

    /// What the publisher offers. Every topic is reliable; a sensor's is volatile: a
    /// late subscriber gets what comes next.
    pub fn offered(self) -> Offered {
        let volatile = |depth| Offered {
            depth,
            transient_local: false,
            lifespan_s: None,
        };
        match self {
            // As rcl offers its own /rosout: a console started after a fault still gets
            // the last 1000 faults and notices (those of the last 10 s, by DDS's rule).
            Topic::Rosout => Offered {
                depth: 1000,
                transient_local: true,
                lifespan_s: Some(10),
            },
            // Latched, as robot_state_publisher and tf2's static broadcaster offer them:
            // the last one, to whoever subscribes later.
            Topic::RobotDescription | Topic::TfStatic => Offered {
                depth: 1,
                transient_local: true,
                lifespan_s: None,
            },
            Topic::Tf => volatile(100),
            _ => volatile(10),
        }
    }
}

/// A publisher's quality of service besides its reliability (always reliable).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Offered {
    /// Keep last this many.
    pub depth: u32,
    /// A late subscriber is given the last `depth` samples (rmw_zenoh keeps them in
    /// the publisher's cache); volatile when false.
    pub transient_local: bool,
    /// How long a sample counts, whole seconds; without end when None.
    pub lifespan_s: Option<u32>,
}
