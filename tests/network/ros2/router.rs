//! A ROS router that is not there, or is not a router: the bridge says so clearly and
//! tries again, and takes the router once it comes. Never a crash.

use std::io::{Read, Write};
use std::time::Duration;

use zenoh::Wait;

use super::{Bridge, Router, tokens};
use crate::bus::{Robot, free_port};

#[test]
fn a_missing_router_is_said_and_tried_again_until_it_comes() {
    let _machine = crate::shared_machine();
    let robot = Robot::start(&["--duration", "24"]);
    let port = free_port();
    let router_at = format!("tcp/127.0.0.1:{port}");
    let bridge = Bridge::start(&router_at, &robot.endpoint, 16.0);
    // Two tries of 3 s and a pause of 2 s between them (8 s), then the router comes,
    // with time to spare for a slow start on a busy machine.
    std::thread::sleep(Duration::from_secs(10));
    let router = Router::at(port);
    let client = router.client();
    // The node and its 11 publishers.
    let found = tokens(&client, 12);
    assert_eq!(found.len(), 12, "{found:?}");
    let fixes = client
        .liveliness()
        .get("@ros2_lv/0/*/0/*/MP/%/%mechweed/ros2_bridge/%mechweed%odom/**")
        .wait()
        .unwrap();
    assert!(fixes.recv().is_ok(), "no /mechweed/odom publisher");
    let (ok, stdout, stderr) = bridge.finish();
    assert!(ok, "{stdout}{stderr}");
    let said = format!(
        "ros2: cannot reach the ROS router at {router_at}: nothing answered within 3 s; trying again in 2 s (is rmw_zenohd running there?"
    );
    assert!(stderr.matches(&said).count() >= 2, "{stderr}");
    assert!(
        stdout.contains("ros2: node /mechweed/ros2_bridge publishes"),
        "{stdout}"
    );
}

#[test]
fn a_router_that_speaks_something_else_is_said_and_tried_again() {
    let _machine = crate::shared_machine();
    let robot = Robot::start(&["--duration", "15"]);
    // A web server, say, on the router's port: it answers every connection with text.
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    std::thread::spawn(move || {
        for stream in listener.incoming().flatten() {
            let mut stream = stream;
            let _ = stream.write_all(b"HTTP/1.1 400 Bad Request\r\n\r\n");
            let mut buf = [0u8; 256];
            let _ = stream.read(&mut buf);
        }
    });
    let router_at = format!("tcp/127.0.0.1:{port}");
    let (ok, stdout, stderr) = {
        let bridge = Bridge::start(&router_at, &robot.endpoint, 10.0);
        bridge.finish()
    };
    assert!(ok, "{stdout}{stderr}");
    let said = format!("ros2: cannot reach the ROS router at {router_at}: ");
    assert!(stderr.matches(&said).count() >= 2, "{stderr}");
    assert!(
        stdout.contains("stopped before the ROS router was reached"),
        "{stdout}"
    );
}

#[test]
fn the_router_at_the_robots_own_endpoint_is_refused_with_the_way_out() {
    let out = Bridge::command("tcp/127.0.0.1:7447", "tcp/127.0.0.1:7447", 1.0)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let said = crate::common::text(&out.stderr);
    assert!(
        said.contains("the ROS router and the robot's bus are both at tcp/127.0.0.1:7447")
            && said.contains("--connect"),
        "{said}"
    );
}
