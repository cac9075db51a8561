//! A new user's first hour, continued: what the console, bench and camsim steps print,
//! through the real program.

use std::process::{Command, Output};

fn mechweed() -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_mechweed"));
    cmd.current_dir(env!("CARGO_MANIFEST_DIR"));
    cmd
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).to_string()
}

/// `mechweed ARGS` with its record in `folder`, as a busy test machine allows.
fn mechweed_recording(args: &[&str], folder: &std::path::Path) -> Output {
    mechweed()
        .args(args)
        .args([
            "--set",
            "rt.max_overruns=1000000",
            "--set",
            "rt.max_late_periods=20",
        ])
        .arg("--set")
        .arg(format!("record.folder={}", folder.display()))
        .output()
        .unwrap()
}

#[test]
fn log_lines_go_to_stderr_plain_without_timestamps_or_levels() {
    let dir = tempfile::tempdir().unwrap();
    // Nothing listens on port 1: the camera link warns that it cannot open.
    let out = mechweed_recording(
        &[
            "run",
            "--headless",
            "--duration",
            "1",
            "--set",
            "camera.port=tcp://127.0.0.1:1",
        ],
        dir.path(),
    );
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(
        stderr
            .lines()
            .any(|l| l.starts_with("warning: camera link: cannot open tcp://127.0.0.1:1")),
        "{stderr}"
    );
    for line in stdout.lines().chain(stderr.lines()) {
        assert!(
            !line.contains(" WARN ") && !line.contains(" INFO ") && !line.starts_with("20"),
            "a log line in the tracing style: {line}"
        );
    }
}

/// No X server answers on display 99 (checked), and no Wayland display is set.
fn stale_display(cmd: &mut Command) -> &mut Command {
    assert!(!std::path::Path::new("/tmp/.X11-unix/X99").exists());
    cmd.env("DISPLAY", ":99").env_remove("WAYLAND_DISPLAY")
}

#[test]
fn a_stale_display_stops_the_run_before_anything_starts_or_is_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let out = stale_display(&mut mechweed())
        .args(["run", "--duration", "2", "--set"])
        .arg(format!("record.folder={}", dir.path().display()))
        .output()
        .unwrap();
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert_eq!(out.status.code(), Some(1), "{stdout}\n{stderr}");
    assert!(
        stderr.contains("cannot open a window on DISPLAY=:99") && stderr.contains("--headless"),
        "{stderr}"
    );
    assert!(!stderr.contains(".cargo"), "{stderr}");
    assert!(!stdout.contains("recording into"), "{stdout}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn bench_loop_gui_without_a_display_advises_dropping_gui() {
    let dir = tempfile::tempdir().unwrap();
    let out = stale_display(&mut mechweed())
        .current_dir(dir.path())
        .args(["bench", "loop", "--gui", "--seconds", "1"])
        .output()
        .unwrap();
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("cannot open a window on DISPLAY=:99"),
        "{stderr}"
    );
    assert!(stderr.contains("drop --gui"), "{stderr}");
    assert!(!stderr.contains("--headless"), "{stderr}");
    assert!(!dir.path().join("records").exists());
}
