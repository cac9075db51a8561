//! `mechweed ros2` between real processes on loopback: the robot program, the bridge,
//! and a Zenoh router in this test (as rmw_zenohd is one), with a separate client
//! session that looks at what a ROS 2 tool would see: the liveliness tokens, the exact
//! data keys, the attachment on each sample, and the messages.

mod bag;
mod bridge;
mod halt;
mod heard;
mod router;

use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use zenoh::{Session, Wait};

use crate::bus::free_port;
use crate::common::{mechweed, text};

/// A Zenoh router on a loopback port of its own, as rmw_zenohd is on a ROS machine.
pub struct Router {
    pub endpoint: String,
    _session: Session,
}

fn config(mode: &str, listen: &[String], connect: &[String]) -> zenoh::Config {
    let mut config = zenoh::Config::default();
    let json = |items: &[String]| serde_json::to_string(items).unwrap();
    for (key, value) in [
        ("mode", format!("\"{mode}\"")),
        ("listen/endpoints", json(listen)),
        ("connect/endpoints", json(connect)),
        ("scouting/multicast/enabled", "false".to_string()),
        ("scouting/gossip/enabled", "false".to_string()),
    ] {
        config.insert_json5(key, &value).unwrap();
    }
    config
}

impl Router {
    pub fn start() -> Router {
        Router::at(free_port())
    }

    pub fn at(port: u16) -> Router {
        let endpoint = format!("tcp/127.0.0.1:{port}");
        let session = zenoh::open(config("router", std::slice::from_ref(&endpoint), &[]))
            .wait()
            .unwrap();
        Router {
            endpoint,
            _session: session,
        }
    }

    /// A client of this router: a ROS 2 tool's view.
    pub fn client(&self) -> Session {
        zenoh::open(config("client", &[], std::slice::from_ref(&self.endpoint)))
            .wait()
            .unwrap()
    }
}

/// `mechweed ros2` to the ROS router at `router`, from the robot's bus at `robot`.
pub struct Bridge {
    child: Option<Child>,
}

impl Drop for Bridge {
    fn drop(&mut self) {
        if let Some(child) = &mut self.child {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

impl Bridge {
    pub fn start(router: &str, robot: &str, seconds: f64) -> Bridge {
        let child = Bridge::command(router, robot, seconds)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        Bridge { child: Some(child) }
    }

    pub fn command(router: &str, robot: &str, seconds: f64) -> Command {
        let mut cmd = mechweed();
        cmd.args(["ros2", "--connect", router, "--robot-connect", robot])
            .args(["--seconds", &seconds.to_string()]);
        cmd
    }

    /// Wait for its end; its exit, stdout and stderr.
    pub fn finish(mut self) -> (bool, String, String) {
        let out = self.child.take().unwrap().wait_with_output().unwrap();
        (out.status.success(), text(&out.stdout), text(&out.stderr))
    }
}

/// The liveliness tokens under `@ros2_lv/0/` that `client` sees, once there are at
/// least `count` of them (at most 15 s).
pub fn tokens(client: &Session, count: usize) -> Vec<String> {
    let end = Instant::now() + Duration::from_secs(15);
    loop {
        let replies = client.liveliness().get("@ros2_lv/0/**").wait().unwrap();
        let mut found = Vec::new();
        while let Ok(reply) = replies.recv() {
            if let Ok(sample) = reply.result() {
                found.push(sample.key_expr().to_string());
            }
        }
        if found.len() >= count || Instant::now() > end {
            found.sort();
            return found;
        }
        std::thread::sleep(Duration::from_millis(200));
    }
}
