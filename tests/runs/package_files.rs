//! The Debian package's system files, checked by systemd's own tools where they are
//! installed (each test skips with a message where not): the units verify clean, the
//! user and its groups and the folders come out as the package needs them.

use std::path::{Path, PathBuf};
use std::process::Command;

fn project(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

fn have(tool: &str) -> bool {
    Command::new(tool)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// A root that has what the units name: this build's program as /usr/bin/mechweed, the
/// launcher's environment file, and the system's own units (the targets they reach).
fn unit_root() -> tempfile::TempDir {
    let root = tempfile::tempdir().unwrap();
    let units = root.path().join("usr/lib/systemd/system");
    std::fs::create_dir_all(&units).unwrap();
    for system_units in ["/usr/lib/systemd/system", "/lib/systemd/system"] {
        let Ok(entries) = std::fs::read_dir(system_units) else {
            continue;
        };
        for entry in entries.flatten() {
            let to = units.join(entry.file_name());
            if entry.file_type().is_ok_and(|t| t.is_file()) && !to.exists() {
                let _ = std::fs::copy(entry.path(), to);
            }
        }
    }
    for unit in ["mechweed.service", "mechweed-launcher.service"] {
        std::fs::copy(project(&format!("packaging/{unit}")), units.join(unit)).unwrap();
    }
    std::fs::create_dir_all(root.path().join("usr/bin")).unwrap();
    std::fs::copy(
        env!("CARGO_BIN_EXE_mechweed"),
        root.path().join("usr/bin/mechweed"),
    )
    .unwrap();
    std::fs::create_dir_all(root.path().join("etc/mechweed")).unwrap();
    std::fs::copy(
        project("packaging/launcher.env"),
        root.path().join("etc/mechweed/launcher.env"),
    )
    .unwrap();
    root
}

#[test]
fn the_service_units_pass_systemd_analyze_verify_without_a_word() {
    if !have("systemd-analyze") {
        eprintln!("skipped: systemd-analyze is not installed here (Debian: systemd)");
        return;
    }
    let root = unit_root();
    let out = Command::new("systemd-analyze")
        .args(["verify", "--man=no"])
        .arg(format!("--root={}", root.path().display()))
        .args([
            "/usr/lib/systemd/system/mechweed.service",
            "/usr/lib/systemd/system/mechweed-launcher.service",
        ])
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&out.stderr);
    // verify exits 0 on warnings: any word it says is a finding.
    assert!(out.status.success() && said.trim().is_empty(), "{said}");
}

#[test]
fn the_units_run_as_mechweed_with_real_time_limits_a_watchdog_and_the_safe_outputs_after() {
    for unit in ["mechweed.service", "mechweed-launcher.service"] {
        let text = std::fs::read_to_string(project(&format!("packaging/{unit}"))).unwrap();
        let lines: Vec<&str> = text.lines().map(str::trim).collect();
        for line in [
            "User=mechweed",
            "Type=notify",
            "LimitRTPRIO=90",
            "LimitMEMLOCK=infinity",
            "ExecStopPost=/usr/bin/mechweed safe --config /etc/mechweed/robot.ini",
        ] {
            assert!(lines.contains(&line), "{unit} lacks {line}");
        }
        assert!(
            lines.iter().any(|l| l.starts_with("WatchdogSec=")),
            "{unit}"
        );
        // Each thread sets its own priority; a policy for the whole service would make
        // every thread real-time, and RestrictRealtime would refuse them all.
        for refused in [
            "CPUSchedulingPolicy=",
            "RestrictRealtime=",
            "ProtectKernelTunables=",
        ] {
            assert!(
                !lines.iter().any(|l| l.starts_with(refused)),
                "{unit} sets {refused}"
            );
        }
    }
}

#[test]
fn sysusers_and_tmpfiles_make_the_user_its_groups_and_folders() {
    if !have("systemd-sysusers") || !have("systemd-tmpfiles") {
        eprintln!(
            "skipped: systemd-sysusers or systemd-tmpfiles is not installed here (Debian: systemd)"
        );
        return;
    }
    let root = tempfile::tempdir().unwrap();
    std::fs::create_dir(root.path().join("etc")).unwrap();
    let run = |tool: &str, args: &[&str], file: &str| {
        let out = Command::new(tool)
            .arg(format!("--root={}", root.path().display()))
            .args(args)
            .arg(project(file))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{tool}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    run("systemd-sysusers", &[], "packaging/sysusers.conf");
    let passwd = std::fs::read_to_string(root.path().join("etc/passwd")).unwrap();
    let group = std::fs::read_to_string(root.path().join("etc/group")).unwrap();
    let user = passwd
        .lines()
        .find(|l| l.starts_with("mechweed:"))
        .expect("no user mechweed");
    assert!(
        user.ends_with(":/var/lib/mechweed:/usr/sbin/nologin"),
        "{user}"
    );
    let dialout = group
        .lines()
        .find(|l| l.starts_with("dialout:"))
        .expect("no group dialout");
    assert!(dialout.ends_with(":mechweed"), "{dialout}");
    assert!(group.lines().any(|l| l.starts_with("mechweed:")), "{group}");

    run("systemd-tmpfiles", &["--create"], "packaging/tmpfiles.conf");
    use std::os::unix::fs::MetadataExt;
    for (folder, mode) in [
        ("var/lib/mechweed", 0o2770),
        ("var/lib/mechweed/records", 0o2770),
        ("etc/mechweed", 0o2775),
        ("etc/mechweed/keys", 0o750),
    ] {
        let meta = std::fs::metadata(root.path().join(folder)).unwrap();
        assert_eq!(
            meta.mode() & 0o7777,
            mode,
            "{folder}: {:o}",
            meta.mode() & 0o7777
        );
    }
}
