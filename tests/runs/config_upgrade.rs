//! `mechweed config upgrade`: every robot.ini this project has shipped, taken from its
//! history, brought up to today's and then taken by check-config, with every line the
//! older file had kept in its order; a start with missing settings names the command.

use std::process::Command;

use crate::common::{mechweed, text};

/// Each shipped robot.ini, oldest first, with its commit; None where this is not a git
/// checkout (a source archive has no history to take them from).
fn shipped_files() -> Option<Vec<(String, String)>> {
    let root = env!("CARGO_MANIFEST_DIR");
    let log = Command::new("git")
        .args([
            "-C",
            root,
            "log",
            "--reverse",
            "--format=%h",
            "--",
            "config/robot.ini",
        ])
        .output()
        .ok()
        .filter(|out| out.status.success())?;
    let commits: Vec<String> = text(&log.stdout).lines().map(str::to_string).collect();
    let files = commits.into_iter().filter_map(|commit| {
        let show = Command::new("git")
            .args(["-C", root, "show", &format!("{commit}:config/robot.ini")])
            .output()
            .ok()?;
        Some((commit, text(&show.stdout)))
    });
    Some(files.collect())
}

#[test]
fn every_shipped_robot_ini_upgrades_to_one_check_config_takes() {
    let files = shipped_files().unwrap_or_default();
    // A source archive has no history, a shallow clone only its newest commits.
    if files.len() < 20 {
        eprintln!(
            "skipped: {} shipped robot.ini files in the git history here (a shallow clone or no checkout); the project has shipped 47",
            files.len()
        );
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut upgraded = 0;
    for (commit, older) in &files {
        let file = dir.path().join(format!("robot-{commit}.ini"));
        std::fs::write(&file, older).unwrap();
        let check = mechweed()
            .args(["config", "upgrade", "--check"])
            .arg(&file)
            .output()
            .unwrap();
        let up = mechweed()
            .args(["config", "upgrade"])
            .arg(&file)
            .output()
            .unwrap();
        assert!(up.status.success(), "{commit}: {}", text(&up.stderr));
        let said = text(&up.stdout);
        if said.contains("nothing to add") {
            assert!(
                check.status.success(),
                "{commit}: --check says {}",
                text(&check.stdout)
            );
        } else {
            upgraded += 1;
            assert!(
                !check.status.success(),
                "{commit}: --check found nothing missing"
            );
            assert!(
                said.contains("settings added or retired; the file before is "),
                "{said}"
            );
        }
        let checked = mechweed().arg("check-config").arg(&file).output().unwrap();
        assert!(
            checked.status.success(),
            "{commit}: after the upgrade:\n{}{}\n{said}",
            text(&checked.stdout),
            text(&checked.stderr)
        );
        // Every line of the older file, in its order (a retired setting as a comment).
        let now = std::fs::read_to_string(&file).unwrap();
        let mut lines = now.lines();
        for line in older.lines() {
            let retired = format!("; {} ; retired: ", line.trim());
            assert!(
                lines.any(|l| l == line || l.starts_with(&retired)),
                "{commit}: {line:?} lost or moved"
            );
        }
    }
    eprintln!(
        "{} shipped robot.ini files, {upgraded} upgraded",
        files.len()
    );
    assert!(
        upgraded > 10,
        "{upgraded} of {} needed an upgrade",
        files.len()
    );
}

#[test]
fn a_start_with_missing_settings_names_the_upgrade_and_the_file_before_is_kept() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("robot.ini");
    let today = mechweed::config::DEFAULT_INI;
    let older: String = (today.lines())
        .filter(|l| !l.trim_start().starts_with("law ="))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(&file, &older).unwrap();
    let start = mechweed()
        .args(["run", "--headless", "--duration", "1", "--config"])
        .arg(&file)
        .output()
        .unwrap();
    assert!(!start.status.success());
    let said = text(&start.stderr);
    assert!(said.contains("[steer] law is missing"), "{said}");
    assert!(
        said.contains(&format!(
            "`mechweed config upgrade {}` adds every missing setting",
            file.display()
        )),
        "{said}"
    );
    let up = mechweed()
        .args(["config", "upgrade"])
        .arg(&file)
        .output()
        .unwrap();
    let out = text(&up.stdout);
    assert!(
        out.contains("added [steer] law = pursuit (the steering law of every release before [steer] law was a setting)"),
        "{out}"
    );
    let backups: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.starts_with("robot.ini.before-upgrade-"))
        .collect();
    assert_eq!(backups.len(), 1, "{backups:?}");
    assert_eq!(
        std::fs::read_to_string(dir.path().join(&backups[0])).unwrap(),
        older
    );
}

/// A record made before a setting existed: its settings lack [steer] law (as a record of
/// an older release would); the replay upgrades them as `config upgrade` does, says so,
/// and gives the same outputs.
#[test]
fn a_record_of_an_older_release_replays_with_its_settings_upgraded() {
    let dir = tempfile::tempdir().unwrap();
    let run = mechweed()
        .args([
            "run",
            "--headless",
            "--mode",
            "autonomous",
            "--duration",
            "3",
        ])
        .args(crate::common::test_run_settings(dir.path()))
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", text(&run.stderr));
    let csv = (std::fs::read_dir(dir.path()).unwrap())
        .map(|e| e.unwrap().path())
        .find(|p| {
            p.extension().is_some_and(|e| e == "csv")
                && !p.to_string_lossy().ends_with(".events.csv")
        })
        .expect("a record");
    let header = mechweed::record::header::RunHeader::beside(&csv).unwrap();
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&header).unwrap()).unwrap();
    let older: String = (json["settings_text"].as_str().unwrap().lines())
        .filter(|l| !l.trim_start().starts_with("law ="))
        .map(|l| format!("{l}\n"))
        .collect();
    json["settings_text"] = older.into();
    std::fs::write(&header, serde_json::to_string_pretty(&json).unwrap()).unwrap();
    let replay = mechweed().arg("replay").arg(&csv).output().unwrap();
    let said = format!("{}{}", text(&replay.stdout), text(&replay.stderr));
    assert!(replay.status.success(), "{said}");
    assert!(
        said.contains("the record's settings are of an older release: 1 settings it lacked were taken as `mechweed config upgrade` gives them ([steer] law = pursuit)"),
        "{said}"
    );
    assert!(said.contains("outputs identical to the record"), "{said}");
}
