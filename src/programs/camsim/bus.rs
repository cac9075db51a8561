//! `camsim --bus`: the simulated camera's rows published on ROBOT/camera/row, as a
//! vision program on another computer would publish them. Its session mends itself as
//! a viewer's does (bus/hearing.rs): it hears the robot's status as a heartbeat, and a
//! session linked to the robot that hears none for 3 s is opened again, so that rows
//! keep reaching the robot after a link flap.

use std::time::{Duration, Instant};

use zenoh::Wait;

use super::computer::{CamSim, CamSimOptions};
use crate::bus::hearing::{Ear, Hearing};
use crate::bus::payload::{row_json, wall_s};
use crate::bus::session::plain_words;
use crate::config::TlsFiles;

/// Publish until the program is stopped, with a line a second of what went out.
pub(super) fn publish_rows(
    endpoint: &str,
    robot: &str,
    tls: Option<TlsFiles>,
    options: CamSimOptions,
) -> Result<(), String> {
    let hearing = Hearing::<()>::start(Ear {
        endpoint: endpoint.to_string(),
        robot: robot.to_string(),
        tls,
        token: "alive/camsim".to_string(),
        flows: Vec::new(),
        program: "camsim",
        queue: 1,
    })?;
    let key = format!("{robot}/camera/row");
    println!("simulated camera publishing row estimates on {key} (via {endpoint})");
    let mut sim = CamSim::new(options);
    sim.receive(mechweed_hw::camproto::CMD_START, 0.0);
    let clock = Instant::now();
    let (mut next_line_s, mut sent_before) = (1.0, 0);
    loop {
        let now_s = clock.elapsed().as_secs_f64();
        let session = hearing.session();
        while let Some(row) = sim.next_row(now_s) {
            // Stamped with this computer's clock, as a vision program stamps its
            // capture time: the robot takes its age from it where the clocks agree.
            let payload = row_json(&row, wall_s()).to_string();
            (session.put(&key, payload))
                .encoding(zenoh::bytes::Encoding::APPLICATION_JSON)
                .wait()
                .map_err(|e| plain_words(&e))?;
        }
        if now_s >= next_line_s {
            next_line_s += 1.0;
            let sent = sim.sent.row_frames;
            println!(
                "{now_s:8.3} s  published {} row estimates ({} left out by --drop so far)",
                sent - sent_before,
                sim.sent.dropped
            );
            sent_before = sent;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}
