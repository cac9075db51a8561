//! Shared helpers for the tests of the program: its runs, and the lockstep helpers
//! of the core's tests.
#![allow(dead_code)]

#[path = "../../core/tests/lockstep/common.rs"]
mod lockstep;
// Not every test program takes it.
#[allow(unused_imports)]
pub use lockstep::settings_with;

/// The `--set` items every run of the program in a test shares: its record goes to
/// `folder`, not into the repository, a busy test machine's late ticks are tolerated
/// (those faults have tests of their own), and the bus is off.
pub fn test_run_settings(folder: &std::path::Path) -> Vec<String> {
    [
        "rt.max_overruns=1000000".to_string(),
        "rt.max_late_periods=20".to_string(),
        // Tests run side by side: the bus's tests give each run a port of its own.
        "bus.enabled=no".to_string(),
        format!("record.folder={}", folder.display()),
    ]
    .into_iter()
    .flat_map(|item| ["--set".to_string(), item])
    .collect()
}

/// The program, run from the project's folder (where config/robot.ini is).
pub fn mechweed() -> std::process::Command {
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_mechweed"));
    cmd.current_dir(env!("CARGO_MANIFEST_DIR"));
    // A robot PC's own settings never reach a test.
    cmd.env("MECHWEED_SYSTEM_INI", "/nonexistent/robot.ini");
    cmd
}

/// `mechweed run --headless ARGS --report FILE` with the tests' shared settings, its
/// record and report in `folder`: what it printed, and its report (which must be there).
pub fn run_headless(
    folder: &std::path::Path,
    args: &[&str],
) -> (std::process::Output, serde_json::Value) {
    let report_path = folder.join("report.json");
    let out = mechweed()
        .args(["run", "--headless"])
        .args(test_run_settings(folder))
        .args(args)
        .arg("--report")
        .arg(&report_path)
        .output()
        .unwrap();
    let Ok(json) = std::fs::read_to_string(&report_path) else {
        panic!("no report:\n{}{}", text(&out.stdout), text(&out.stderr));
    };
    (out, serde_json::from_str(&json).unwrap())
}

/// A program's output as text.
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// `record summary` of a run whose rows came from outside the simulated camera: it
/// says that the tool's cross-track means nothing there, and gives no figure of it.
pub fn assert_no_cross_track_in_summary(summary: &mut std::process::Command, what: &str) {
    let out = summary.output().unwrap();
    let said = text(&out.stdout);
    assert!(out.status.success(), "{said}{}", text(&out.stderr));
    assert!(
        said.contains("tool cross-track: not meaningful (outside camera)"),
        "{what}: {said}"
    );
    assert!(
        !said.contains(" cm, s.d. ") && !said.contains("mean "),
        "{what}: a cross-track figure: {said}"
    );
}

/// This computer has Measurement Computing cards (PCI vendor 0x1307): tests that would
/// open them stay off a real robot's cards.
pub fn has_mcc_cards() -> bool {
    std::fs::read_dir("/sys/bus/pci/devices").is_ok_and(|dir| {
        dir.flatten().any(|d| {
            std::fs::read_to_string(d.path().join("vendor")).is_ok_and(|v| v.trim() == "0x1307")
        })
    })
}
