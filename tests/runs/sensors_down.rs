//! A mode that needs a sensor is refused while the sensor's link is down, with the
//! reason, instead of being accepted and faulting a moment later: the binary, started
//! as a user starts it, with a camera port that does not exist.

use crate::common;

#[test]
fn autonomous_with_the_camera_link_down_is_refused_with_its_reason_and_nothing_moves() {
    let dir = tempfile::tempdir().unwrap();
    // The unsafe state: a start in autonomous, and no camera computer where it is said
    // to be.
    let no_camera = "camera.port=/dev/mechweed-test-no-camera";
    let (out, report) = common::run_headless(
        dir.path(),
        &[
            "--mode",
            "autonomous",
            "--duration",
            "3",
            "--set",
            no_camera,
        ],
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let said = format!("{stdout}{stderr}");
    let refusals: Vec<&str> = said
        .lines()
        .filter(|l| l.contains("refused: autonomous needs its sensors: the camera link is down"))
        .collect();
    assert_eq!(refusals.len(), 1, "asked once, said why once:\n{said}");
    assert!(refusals[0].contains("check [camera] port"), "{said}");
    assert_eq!(report["mode_final"], "halt", "{report:#}");
    assert_eq!(report["faults"].as_array().unwrap().len(), 0, "{report:#}");
    assert!(report["distance_m"].as_f64().unwrap() < 0.01, "{report:#}");
    assert_eq!(out.status.code(), Some(0), "{said}");
}
