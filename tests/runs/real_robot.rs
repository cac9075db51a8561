//! The real robot never runs on simulated parts, from outside: `check-config` and a
//! start of the binary refuse `[hw] backend = cards` with the simulated camera, receiver
//! and map, each by its key and line and with what to set; `check-config --real-robot`
//! refuses a file still on the simulated robot.

use std::process::Command;

use crate::config_file;

use config_file::{File, assert_refused, line_of, shipped_with};

const CARDS: &str = "with [hw] backend = cards the outputs go to the real robot";

#[test]
fn check_config_refuses_the_cards_with_a_simulated_camera_receiver_and_map() {
    // The unsafe state: real amplifiers, simulated rows and fixes.
    let text = shipped_with(&[
        ("hw", "backend", "cards"),
        ("gnss", "port", "sim"),
        ("steer", "source", "fused"),
    ]);
    let camera = format!(
        "[camera] port = sim is the simulated camera computer, and {CARDS}: it would steer the real robot along a simulated row. Set [camera] port to the camera computer's serial device (e.g. /dev/ttyS0), tcp://HOST:PORT or bus"
    );
    let gnss = format!(
        "[gnss] port = sim is the simulated receiver, and {CARDS}: it would steer the real robot by simulated fixes. Set [gnss] port to the receiver's serial device (e.g. /dev/ttyACM0) or tcp://HOST:PORT, or to none with [steer] source = camera"
    );
    let map = format!(
        "[gnss] map = sim is the simulated field's map, and {CARDS}: the real field's rows are elsewhere. Set [gnss] map to the field's row map file (mechweed teach writes one)"
    );
    assert_refused(
        &text,
        &[
            (line_of(&text, "camera", "port"), &camera),
            (line_of(&text, "gnss", "port"), &gnss),
            (line_of(&text, "gnss", "map"), &map),
        ],
    );
}

/// `mechweed run --headless --duration 1` with `file`.
fn run_one_second(file: &File) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_mechweed"))
        .args(["run", "--headless", "--duration", "1", "--config"])
        .arg(&file.path)
        .output()
        .unwrap()
}

#[test]
fn a_run_on_the_cards_with_the_simulated_camera_does_not_start() {
    let file = File::new(shipped_with(&[("hw", "backend", "cards")]));
    let out = run_one_second(&file);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("[camera] port = sim is the simulated camera computer"),
        "{stderr}"
    );
    // Nothing started; the cards were opened only to write their safe outputs (on a
    // computer without them: it says which is missing), in case a killed run left the
    // robot driving.
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(!stdout.contains("mechweed on the"), "{stdout}");
    assert!(
        stderr.contains("safe outputs written") || stderr.contains("no PCI-DAS08"),
        "{stderr}"
    );
}

#[test]
fn check_config_real_robot_refuses_a_file_on_the_simulated_robot_and_takes_one_set_up() {
    let check = |text: &str| {
        let file = File::new(text);
        let out = Command::new(env!("CARGO_BIN_EXE_mechweed"))
            .args(["check-config", "--real-robot"])
            .arg(&file.path)
            .output()
            .unwrap();
        let said = String::from_utf8_lossy(&out.stdout).to_string()
            + &String::from_utf8_lossy(&out.stderr);
        (out.status.code(), said)
    };
    let shipped = shipped_with(&[]);
    let (code, said) = check(&shipped);
    assert_eq!(code, Some(1), "{said}");
    let backend = line_of(&shipped, "hw", "backend");
    assert!(
        said.contains(&format!(
            "line {backend}: [hw] backend = sim runs the simulated robot"
        )),
        "{said}"
    );
    let set_up = shipped_with(&[("hw", "backend", "cards"), ("camera", "port", "/dev/ttyS0")]);
    let (code, said) = check(&set_up);
    assert_eq!(code, Some(0), "{said}");
    assert!(said.contains("ok: set up for the real robot"), "{said}");
}

#[test]
fn a_start_on_the_cards_without_a_watchdog_relay_says_so_and_a_file_without_the_words_is_refused() {
    let cards = [
        ("hw", "backend", "cards"),
        ("camera", "port", "/dev/ttyS0"),
        ("io", "watchdog", "none"),
    ];
    let refused = File::new(shipped_with(&cards));
    let out = run_one_second(&refused);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("[io] watchdog = none"), "{stderr}");
    let mut accepted = cards.to_vec();
    accepted.push(("io", "watchdog_relay", "none_accepted"));
    let file = File::new(shipped_with(&accepted));
    let out = run_one_second(&file);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("no watchdog relay ([io] watchdog_relay = none_accepted)"),
        "{stdout}"
    );
}
