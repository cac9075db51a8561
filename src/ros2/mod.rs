//! ROS 2 tools see the robot (docs/ros2.md): `mechweed ros2` publishes the robot's
//! flows as standard ROS 2 messages in the wire format of ROS 2's Zenoh middleware
//! (rmw_zenoh), and `mechweed record --ros2` writes the same messages to an MCAP bag
//! that `ros2 bag` plays. Nothing from ROS drives the robot: with `[ros2]
//! halt_service = yes` ROS may ask for HALT (`halt`), and nothing else.
//!
//! - `msgs`, `types`, `cdr`: the messages, their definitions and type hashes, CDR;
//! - `wire`: keys, liveliness tokens, the attachment (rmw_zenoh's rules);
//! - `topics`, `flows`, `odom`, `diagnostics`, `clock`: which topics, made from which
//!   flow, stamped on the robot's clock; `model`: the robot's URDF and fixed frames;
//!   `covariance`: what the odometry is worth;
//! - `pump`: the robot's flows heard and made into messages, for:
//! - `bridge`: the program; `bag`: the recorder's MCAP file.

pub mod bag;
pub mod bag_read;
pub mod bridge;
pub mod cdr;
pub mod clock;
pub mod covariance;
pub mod diagnostics;
pub mod flows;
pub mod halt;
pub mod model;
pub mod msgs;
pub mod odom;
pub mod pump;
pub mod sensors;
pub mod topics;
pub mod types;
pub mod wire;

#[cfg(test)]
mod bag_tests;
#[cfg(test)]
mod cdr_tests;
#[cfg(test)]
mod flows_frames_tests;
#[cfg(test)]
mod flows_tests;
#[cfg(test)]
mod hash_tests;
