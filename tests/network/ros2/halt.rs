//! The HALT service from the ROS side: absent as shipped, and with `[ros2]
//! halt_service = yes` a call in rmw_zenoh's service format halts an autonomous run
//! and is answered with the robot's reply, matched to the call by its attachment.

use std::process::Stdio;
use std::time::Duration;

use mechweed::ros2::cdr::{decode, encode};
use mechweed::ros2::msgs::{TriggerRequest, TriggerResponse};
use mechweed::ros2::wire::{attachment, read_attachment};
use zenoh::Wait;

use super::{Bridge, Router, tokens};
use crate::bus::Robot;

const KEY: &str = "0/mechweed/halt/std_srvs::srv::dds_::Trigger_/RIHS01_eeff2cd6fa5ad9d27cdf4dec64818317839b62f212a91e6b5304b634b2062c5f";
const CLIENT_GID: [u8; 16] = [7; 16];

/// A call as rclcpp's client makes it: the CDR request, the 33-byte attachment. The
/// reply's payload and attachment, or None when nothing answered.
fn call(client: &zenoh::Session, sequence: i64) -> Option<(Vec<u8>, Vec<u8>)> {
    let request = encode(&TriggerRequest::default()).unwrap();
    let replies = client
        .get(KEY)
        .payload(request)
        .attachment(attachment(sequence, 1, &CLIENT_GID).to_vec())
        .timeout(Duration::from_secs(8))
        .wait()
        .unwrap();
    let reply = replies.recv().ok()?;
    let sample = reply.result().expect("a reply, not an error");
    let attachment = sample.attachment().map(|a| a.to_bytes().into_owned());
    Some((
        sample.payload().to_bytes().into_owned(),
        attachment.unwrap_or_default(),
    ))
}

#[test]
fn with_the_halt_service_on_a_ros_call_halts_an_autonomous_run_and_as_shipped_there_is_none() {
    let _machine = crate::shared_machine();
    let router = Router::start();
    let robot = Robot::start(&["--mode", "autonomous", "--duration", "20"]);
    let client = router.client();

    // As shipped: no service server's token, and a call is answered by nothing.
    let off = Bridge::start(&router.endpoint, &robot.endpoint, 5.0);
    let found = tokens(&client, 12);
    assert!(found.iter().all(|t| !t.contains("/SS/")), "{found:?}");
    assert_eq!(call(&client, 1), None);
    let (ok, stdout, stderr) = off.finish();
    assert!(ok && !stdout.contains("HALT"), "{stdout}{stderr}");

    let on = Bridge::command(&router.endpoint, &robot.endpoint, 8.0)
        .args(["--set", "ros2.halt_service=yes"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let found = tokens(&client, 13);
    let service = found
        .iter()
        .find(|t| t.contains("/SS/"))
        .expect("a service token");
    let zid = service.split('/').nth(2).unwrap();
    assert_eq!(
        *service,
        format!(
            "@ros2_lv/0/{zid}/0/12/SS/%/%mechweed/ros2_bridge/%mechweed%halt/std_srvs::srv::dds_::Trigger_/RIHS01_eeff2cd6fa5ad9d27cdf4dec64818317839b62f212a91e6b5304b634b2062c5f/::,10:,:,:,,"
        )
    );
    let (payload, reply_attachment) = call(&client, 41).expect("an answer");
    let response: TriggerResponse = decode(&payload).unwrap();
    assert!(
        response.success && !response.message.is_empty(),
        "{response:?}"
    );
    // The reply names the call: its sequence number and the client's id.
    let (sequence, _, gid) = read_attachment(&reply_attachment).unwrap();
    assert_eq!((sequence, gid), (41, CLIENT_GID));
    let out = on.wait_with_output().unwrap();
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(said.contains("ros2: HALT asked from ROS: done"), "{said}");
    assert!(
        said.contains("the HALT service /mechweed/halt is offered"),
        "{said}"
    );

    let (stdout, stderr, _) = robot.finish();
    assert!(
        stdout.contains("mode: autonomous -> halt"),
        "{stdout}{stderr}"
    );
}
