//! The robot's link to a viewer on another computer cut and restored, as a pulled cable
//! or a radio out of reach does: the viewer (the off-board recorder, which runs for
//! hours) hears the robot's status again after each restore, without being restarted.

use std::time::{Duration, Instant};

use super::Robot;
use super::netns::Netns;
use crate::common::text;

#[test]
fn a_viewer_hears_the_robot_again_after_each_cut_of_its_link() {
    let _machine = crate::shared_machine();
    let link = match Netns::make(3, None) {
        Ok(link) => link,
        Err(why) => {
            eprintln!("skipped: a viewer in a network namespace, its link cut: {why}");
            return;
        }
    };
    let listen = format!("tcp/{}:{}", link.host, super::free_port());
    // Plain TCP beyond loopback, on a link between two namespaces of this computer.
    let robot = Robot::spawn(
        Some(listen.clone()),
        &["--duration", "45", "--set", "bus.trusted_network=yes"],
    );
    robot.wait_until_answering();
    let folder = tempfile::tempdir().unwrap();
    let recorder = link
        .command(env!("CARGO_BIN_EXE_mechweed"))
        .args(["record", "--bus", "--connect", &listen, "--seconds", "38"])
        .arg("--set")
        .arg(format!("record.folder={}", folder.path().display()))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_secs(4));
    // Two short cuts, within Zenoh's lease (the link survives), and one long enough
    // that the link is given up and made again.
    let cuts_s = [3, 3, 12];
    let start = Instant::now();
    for cut_s in cuts_s {
        link.carrier(false);
        std::thread::sleep(Duration::from_secs(cut_s));
        link.carrier(true);
        std::thread::sleep(Duration::from_secs(5));
    }
    eprintln!(
        "cut and restored {} times in {:?}",
        cuts_s.len(),
        start.elapsed()
    );
    let out = recorder.wait_with_output().unwrap();
    let said = text(&out.stderr);
    let again: Vec<&str> = said
        .lines()
        .filter(|l| l.contains("status comes again"))
        .collect();
    assert!(
        again.len() >= cuts_s.len(),
        "{} of {} restores heard again:\n{said}\n{}",
        again.len(),
        cuts_s.len(),
        text(&out.stdout)
    );
    eprintln!("{}", again.join("\n"));
    // And it recorded to its end: ticks came after the last restore.
    let newest = mechweed::record::keep::latest(folder.path()).expect("a record");
    let ticks = mechweed::record::read::read(&newest, &["t_s"])
        .unwrap()
        .ticks;
    let t = ticks.column("t_s").unwrap();
    let last_s = ticks.number(ticks.rows.len() - 1, t).unwrap().unwrap();
    let first_s = ticks.number(0, t).unwrap().unwrap();
    assert!(
        last_s - first_s > 30.0,
        "recorded {first_s:.1} to {last_s:.1} s"
    );
    drop(robot);
}
