//! The doctor's checks against fakes of what they read: a sysfs tree, serial devices
//! missing or not this user's, a full disk, a Zenoh router on the bus's port, keys.

use std::path::{Path, PathBuf};

use super::machine::Machine;
use super::{Check, Level, devices, files, latency, machine};
use crate::config::{DEFAULT_INI, Settings};

fn settings(overrides: &[&str]) -> Settings {
    let overrides: Vec<String> = overrides.iter().map(|o| o.to_string()).collect();
    Settings::parse("test robot.ini", DEFAULT_INI, &overrides).unwrap()
}

/// The shipped settings on the cards, the camera on a serial device.
fn on_cards(camera: &Path) -> Settings {
    settings(&[
        "hw.backend=cards",
        &format!("camera.port={}", camera.display()),
    ])
}

fn fake_machine(root: &Path) -> Machine {
    Machine {
        root: root.to_path_buf(),
        clock_synchronised: Some(true),
    }
}

/// One of the cards in a fake /sys/bus/pci/devices, switched on.
fn fake_card(root: &Path, address: &str, device_id: u16) -> PathBuf {
    let dir = root.join("sys/bus/pci/devices").join(address);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("vendor"), "0x1307\n").unwrap();
    std::fs::write(dir.join("device"), format!("0x{device_id:04x}\n")).unwrap();
    std::fs::write(dir.join("enable"), "1\n").unwrap();
    let none = "0x0000000000000000 0x0000000000000000 0x0000000000000000";
    let bar = "0x000000000000e000 0x000000000000e00f 0x0000000000040101";
    std::fs::write(
        dir.join("resource"),
        format!("{none}\n{none}\n{bar}\n{bar}\n"),
    )
    .unwrap();
    for file in ["resource2", "resource3"] {
        std::fs::write(dir.join(file), [0u8; 16]).unwrap();
    }
    dir
}

fn named<'a>(checks: &'a [Check], name: &str) -> &'a Check {
    checks
        .iter()
        .find(|c| c.check == name)
        .unwrap_or_else(|| panic!("no {name} in {checks:#?}"))
}

/// Run `f` as an ordinary user would see the files: this thread's filesystem ids set to
/// nobody's (root passes every permission check).
fn as_nobody<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    std::thread::scope(|scope| {
        scope
            .spawn(|| {
                // SAFETY: setfsuid/setfsgid change only this thread's filesystem ids.
                unsafe {
                    libc::setfsgid(65534);
                    libc::setfsuid(65534);
                }
                f()
            })
            .join()
            .unwrap()
    })
}

#[test]
fn each_card_is_found_in_sysfs_and_a_missing_one_or_a_file_not_this_users_fails() {
    let root = tempfile::tempdir().unwrap();
    let m = fake_machine(root.path());
    let s = on_cards(Path::new("/dev/null"));
    fake_card(root.path(), "0000:03:00.0", 0x0029);
    let dda06 = fake_card(root.path(), "0000:04:00.0", 0x0053);
    let checks = devices::checks(&m, &s);
    assert_eq!(named(&checks, "card_das08").level, Level::Ok, "{checks:#?}");
    assert_eq!(named(&checks, "card_dda06").level, Level::Ok, "{checks:#?}");
    let quad04 = named(&checks, "card_quad04");
    assert_eq!(quad04.level, Level::Fail);
    assert!(quad04.says.contains("PCI-QUAD04"), "{quad04:?}");

    // The register file root's alone, as before the udev rule: refused, and the fix
    // names the rule.
    std::fs::set_permissions(
        dda06.join("resource3"),
        std::os::unix::fs::PermissionsExt::from_mode(0o600),
    )
    .unwrap();
    let checks = as_nobody(|| devices::checks(&m, &s));
    let refused = named(&checks, "card_dda06");
    assert_eq!(refused.level, Level::Fail, "{refused:?}");
    assert!(
        refused
            .says
            .contains("not readable and writable by this user"),
        "{refused:?}"
    );
    assert!(refused.fix.contains("udev"), "{refused:?}");

    // A card whose decoding is off (the rule did not run).
    std::fs::write(dda06.join("enable"), "0\n").unwrap();
    let checks = devices::checks(&m, &s);
    assert!(named(&checks, "card_dda06").says.contains("enable = 0"));
}

#[test]
fn the_simulated_robot_needs_no_cards() {
    let root = tempfile::tempdir().unwrap();
    let checks = devices::checks(&fake_machine(root.path()), &settings(&[]));
    assert_eq!(named(&checks, "cards").level, Level::Ok);
    assert!(!checks.iter().any(|c| c.check.starts_with("card_")));
}

#[test]
fn a_serial_port_missing_not_a_device_or_not_this_users_fails_with_its_setting() {
    let root = tempfile::tempdir().unwrap();
    let m = fake_machine(root.path());
    let missing = root.path().join("ttyUSB7");
    let checks = devices::checks(&m, &on_cards(&missing));
    let c = named(&checks, "camera_port");
    assert_eq!(c.level, Level::Fail);
    assert!(
        c.says.contains("[camera] port") && c.says.contains("not there"),
        "{c:?}"
    );

    let plain = root.path().join("plain");
    std::fs::write(&plain, "").unwrap();
    let c = devices::checks(&m, &on_cards(&plain));
    assert!(
        named(&c, "camera_port")
            .says
            .contains("not a serial device"),
        "{c:?}"
    );

    // A character device (the null device's numbers) for root alone.
    let device = root.path().join("ttyS9");
    let c_path = std::ffi::CString::new(device.as_os_str().as_encoded_bytes()).unwrap();
    // SAFETY: mknod reads the path we own.
    let made =
        unsafe { libc::mknod(c_path.as_ptr(), libc::S_IFCHR | 0o600, libc::makedev(1, 3)) } == 0;
    if !made {
        eprintln!("skipped the device half: mknod needs root here");
        return;
    }
    let s = on_cards(&device);
    assert_eq!(
        named(&devices::checks(&m, &s), "camera_port").level,
        Level::Ok
    );
    let c = as_nobody(|| devices::checks(&m, &s));
    let c = named(&c, "camera_port");
    assert_eq!(c.level, Level::Fail);
    assert!(
        c.says.contains("not readable and writable by this user") && c.fix.contains("dialout"),
        "{c:?}"
    );
}

#[test]
fn a_disk_that_holds_less_than_an_hour_of_records_fails() {
    let s = settings(&[]);
    let mb_per_min = files::record_mb_per_min(&s);
    assert!((mb_per_min - 6.78).abs() < 0.01, "{mb_per_min}");
    let at = |bytes: u64| files::disk(Some((PathBuf::from("/var/lib/mechweed"), bytes)), &s);
    let full = at(100_000_000);
    assert_eq!(full.level, Level::Fail);
    assert!(full.says.contains("0.2 h of records"), "{full:?}");
    assert_eq!(at(1_000_000_000).level, Level::Warning);
    assert_eq!(at(100_000_000_000).level, Level::Ok);
    // Every tenth tick in CSV alone: ten times the hours and more.
    let thin = settings(&["record.every_n_ticks=10", "record.formats=csv"]);
    assert_eq!(
        files::disk(Some((PathBuf::from("/"), 1_000_000_000)), &thin).level,
        Level::Ok
    );
    let off = settings(&["record.enabled=no"]);
    assert_eq!(files::disk(None, &off).level, Level::Ok);
}

#[test]
fn the_process_holding_the_bus_port_is_named() {
    let root = tempfile::tempdir().unwrap();
    let proc = root.path().join("proc");
    std::fs::create_dir_all(proc.join("net")).unwrap();
    let header = "  sl  local_address rem_address   st tx_queue rx_queue tr tm->when retrnsmt   uid  timeout inode\n";
    // 0x1D17 = 7447, listening (0A), socket inode 51234.
    let line = "   0: 00000000:1D17 00000000:0000 0A 00000000:00000000 00:00000000 00000000  1000        0 51234 1 0000000000000000 100 0 0 10 0\n";
    std::fs::write(proc.join("net/tcp"), format!("{header}{line}")).unwrap();
    std::fs::create_dir_all(proc.join("4242/fd")).unwrap();
    std::os::unix::fs::symlink("socket:[51234]", proc.join("4242/fd/7")).unwrap();
    std::fs::write(proc.join("4242/comm"), "zenohd\n").unwrap();
    std::fs::create_dir_all(proc.join("99/fd")).unwrap();
    std::fs::write(proc.join("99/comm"), "bash\n").unwrap();
    let m = fake_machine(root.path());
    assert_eq!(
        files::port_holder(&m, 7447),
        Some((4242, "zenohd".to_string()))
    );
    assert_eq!(files::port_holder(&m, 7510), None);
}

#[test]
fn keys_readable_by_all_or_beside_the_authoritys_key_fail() {
    let dir = tempfile::tempdir().unwrap();
    crate::bus::keys::new_cluster(dir.path(), "robot", &[]).unwrap();
    let file = |name: &str| dir.path().join(name).display().to_string();
    let ca = format!("bus.tls_ca={}", file("ca.pem"));
    let cert = format!("bus.tls_cert={}", file("robot.pem"));
    let key = format!("bus.tls_key={}", file("robot.key"));
    let s = settings(&[&ca, &cert, &key, "bus.listen=tls/127.0.0.1:7510"]);
    let c = files::keys(&s);
    assert_eq!(c.level, Level::Fail, "{c:?}");
    assert!(c.says.contains("ca.key is here"), "{c:?}");

    std::fs::remove_file(dir.path().join("ca.key")).unwrap();
    let c = files::keys(&s);
    assert_eq!(c.level, Level::Ok, "{c:?}");

    let key = dir.path().join("robot.key");
    std::fs::set_permissions(&key, std::os::unix::fs::PermissionsExt::from_mode(0o644)).unwrap();
    let c = files::keys(&s);
    assert_eq!(c.level, Level::Fail, "{c:?}");
    assert!(c.fix.contains("chmod 0640"), "{c:?}");
}

#[test]
fn lockdown_fails_the_cards_and_the_kernel_and_clock_are_reported() {
    let root = tempfile::tempdir().unwrap();
    let security = root.path().join("sys/kernel/security");
    std::fs::create_dir_all(&security).unwrap();
    std::fs::write(
        security.join("lockdown"),
        "none [integrity] confidentiality\n",
    )
    .unwrap();
    let mut m = fake_machine(root.path());
    m.clock_synchronised = Some(false);
    let cards = machine::checks(&m, &on_cards(Path::new("/dev/null")));
    assert_eq!(named(&cards, "lockdown").level, Level::Fail);
    assert_eq!(named(&cards, "clock").level, Level::Warning);
    assert_eq!(
        named(&cards, "kernel").level,
        Level::Warning,
        "no /sys/kernel/realtime"
    );
    let sim = machine::checks(&m, &settings(&[]));
    assert_eq!(named(&sim, "lockdown").level, Level::Warning);

    std::fs::write(
        security.join("lockdown"),
        "[none] integrity confidentiality\n",
    )
    .unwrap();
    std::fs::write(root.path().join("sys/kernel/realtime"), "1\n").unwrap();
    m.clock_synchronised = Some(true);
    let mended = machine::checks(&m, &on_cards(Path::new("/dev/null")));
    assert!(mended.iter().all(|c| c.level == Level::Ok), "{mended:#?}");
}

#[test]
fn a_tick_later_than_its_period_fails_the_latency_test() {
    let period_us = 10_000.0;
    assert_eq!(
        latency::judge(String::new(), 80.0, 0, period_us).level,
        Level::Ok
    );
    assert_eq!(
        latency::judge(String::new(), 2_500.0, 0, period_us).level,
        Level::Warning
    );
    assert_eq!(
        latency::judge(String::new(), 12_000.0, 0, period_us).level,
        Level::Fail
    );
    assert_eq!(
        latency::judge(String::new(), 50.0, 1, period_us).level,
        Level::Fail
    );
}

#[test]
fn settings_that_do_not_load_fail_and_leave_the_rest_out() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("robot.ini");
    std::fs::write(&file, "[supervisor]\nrate_hz = fast\n").unwrap();
    let checks = super::examine(&fake_machine(dir.path()), Some(&file), 0.0, false);
    assert_eq!(checks[0].level, Level::Fail);
    assert!(checks[0].says.contains("robot.ini"), "{:?}", checks[0]);
    assert_eq!(checks.len(), 2, "{checks:#?}");
}
