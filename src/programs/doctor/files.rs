//! The files and ports a run needs: the disk for records, the bus's ports, and the
//! cluster's keys.

use std::net::TcpListener;
use std::path::{Path, PathBuf};

use super::{Check, Level, Machine};
use crate::config::{RecordFormats, Settings};

pub(super) fn checks(m: &Machine, s: &Settings) -> Vec<Check> {
    let mut checks = vec![disk(free_bytes(&s.record.folder), s)];
    if s.bus.enabled && m.is_this_pc() {
        for endpoint in &s.bus.listen {
            checks.push(bus_port(m, endpoint));
        }
    }
    checks.push(keys(s));
    checks
}

/// A record's size, MB a minute, at 100 Hz with every tick recorded (measured on a
/// 60 s autonomous run at the shipped settings, docs/records.md).
const CSV_MB_PER_MIN: f64 = 4.84;
const MCAP_MB_PER_MIN: f64 = 1.94;

/// What the records take, MB a minute, at these settings.
pub(super) fn record_mb_per_min(s: &Settings) -> f64 {
    let per_tick = match s.record.formats {
        RecordFormats::Both => CSV_MB_PER_MIN + MCAP_MB_PER_MIN,
        RecordFormats::Csv => CSV_MB_PER_MIN,
        RecordFormats::Mcap => MCAP_MB_PER_MIN,
    };
    per_tick * (s.supervisor.rate_hz / 100.0) / s.record.every_n_ticks as f64
}

/// Free bytes on the disk of `folder` (or of the nearest folder above it that exists:
/// the recorder makes it).
fn free_bytes(folder: &Path) -> Option<(PathBuf, u64)> {
    let absolute = std::path::absolute(folder).ok()?;
    let existing = absolute.ancestors().find(|p| p.exists())?.to_path_buf();
    let free = crate::record::space::disk_free_bytes(&existing)?;
    Some((existing, free))
}

/// Hours of records the disk holds: under one a field day fills it; under eight it
/// may, without a limit on the folder.
pub(super) fn disk(free: Option<(PathBuf, u64)>, s: &Settings) -> Check {
    if !s.record.enabled {
        return Check::ok("disk", "[record] enabled = no: nothing is recorded");
    }
    let Some((folder, bytes)) = free else {
        return Check::new(
            "disk",
            Level::Warning,
            format!(
                "the free space at {} could not be read",
                s.record.folder.display()
            ),
            "df -h tells",
        );
    };
    let mb_per_min = record_mb_per_min(s);
    let hours = bytes as f64 / 1e6 / mb_per_min / 60.0;
    let says = format!(
        "{:.1} GB free at {}: {hours:.1} h of records at {mb_per_min:.1} MB a minute",
        bytes as f64 / 1e9,
        folder.display()
    );
    let fix = "free space, record every Nth tick ([record] every_n_ticks) or one format ([record] formats), and keep a limit ([record] keep_gb)";
    if hours < 1.0 {
        Check::new("disk", Level::Fail, says, fix)
    } else if hours < 8.0 {
        Check::new("disk", Level::Warning, says, fix)
    } else {
        Check::ok("disk", says)
    }
}

/// A listening endpoint's port: free, or held by whom (a Zenoh router's, most often).
fn bus_port(m: &Machine, endpoint: &str) -> Check {
    let Some(address) = endpoint
        .split_once('/')
        .map(|(_, a)| a.split('#').next().unwrap_or(a))
    else {
        return Check::ok(
            "bus_port",
            format!("{endpoint}: not a TCP endpoint, not checked"),
        );
    };
    match TcpListener::bind(address) {
        Ok(_) => Check::ok("bus_port", format!("{endpoint}: free")),
        Err(e) if e.kind() == std::io::ErrorKind::AddrInUse => {
            let port = address
                .rsplit(':')
                .next()
                .and_then(|p| p.parse().ok())
                .unwrap_or(0);
            let holder = match port_holder(m, port) {
                Some((pid, name)) if name.contains("zenoh") => format!(
                    "a Zenoh router ({name}, process {pid}) holds it: its peers would meet the robot's bus unasked"
                ),
                Some((pid, name)) if name.contains("mechweed") => format!(
                    "a mechweed program (process {pid}) holds it: a run is already going on"
                ),
                Some((pid, name)) => format!("{name} (process {pid}) holds it"),
                None => "another program holds it".to_string(),
            };
            Check::new(
                "bus_port",
                Level::Fail,
                format!("{endpoint}: in use: {holder}"),
                "stop that program, or give [bus] listen another port",
            )
        }
        Err(e) => Check::new(
            "bus_port",
            Level::Fail,
            format!("{endpoint}: cannot listen: {e}"),
            "give [bus] listen an address of this PC (ip -br addr)",
        ),
    }
}

/// The process listening on TCP `port`: its socket's inode in /proc/net/tcp{,6}, then
/// the process with that socket open.
pub(super) fn port_holder(m: &Machine, port: u16) -> Option<(u32, String)> {
    let inode = ["/proc/net/tcp", "/proc/net/tcp6"]
        .iter()
        .find_map(|table| {
            let text = std::fs::read_to_string(m.path(table)).ok()?;
            text.lines().skip(1).find_map(|line| {
                let f: Vec<&str> = line.split_whitespace().collect();
                let local_port = f.get(1)?.rsplit(':').next()?;
                let listening = *f.get(3)? == "0A";
                (listening && u16::from_str_radix(local_port, 16).ok()? == port)
                    .then(|| f.get(9).map(|i| i.to_string()))?
            })
        })?;
    let socket = format!("socket:[{inode}]");
    let processes = std::fs::read_dir(m.path("/proc")).ok()?;
    processes.flatten().find_map(|p| {
        let pid: u32 = p.file_name().to_str()?.parse().ok()?;
        let fds = std::fs::read_dir(p.path().join("fd")).ok()?;
        let holds = fds.flatten().any(|fd| {
            std::fs::read_link(fd.path()).is_ok_and(|l| l.as_os_str() == socket.as_str())
        });
        let name = std::fs::read_to_string(p.path().join("comm")).ok()?;
        holds.then(|| (pid, name.trim().to_string()))
    })
}

/// The bus's TLS files: there, the private key for the group only, the certificates
/// in date, and the authority's key nowhere near the robot.
pub(super) fn keys(s: &Settings) -> Check {
    let Some(tls) = &s.bus.tls else {
        return Check::ok("keys", "[bus] without TLS: no keys needed");
    };
    // Each problem with how bad it is; only a certificate near its end is a warning.
    let mut problems: Vec<(Level, String)> = Vec::new();
    let mut fix = Vec::new();
    for cert in [&tls.ca, &tls.cert] {
        match days_left(cert) {
            Err(why) => problems.push((Level::Fail, why)),
            Ok(days) if days < 0 => problems.push((
                Level::Fail,
                format!("{} expired {} days ago", cert.display(), -days),
            )),
            Ok(days) if days < 30 => problems.push((
                Level::Warning,
                format!("{} expires in {days} days", cert.display()),
            )),
            Ok(_) => {}
        }
    }
    if let Err(e) = std::fs::metadata(&tls.key) {
        problems.push((Level::Fail, format!("{}: {e}", tls.key.display())));
    }
    for (problem, mend) in crate::bus::keys::exposure(tls) {
        problems.push((Level::Fail, problem));
        fix.push(mend);
    }
    if problems.is_empty() {
        return Check::ok(
            "keys",
            format!(
                "{}, {} and its key: in date, the key not readable by others",
                tls.ca.display(),
                tls.cert.display()
            ),
        );
    }
    if fix.is_empty() {
        fix.push("make new ones with mechweed keys (docs/bus.md)".to_string());
    }
    let level = problems
        .iter()
        .map(|(level, _)| *level)
        .max_by_key(|l| *l == Level::Fail)
        .unwrap_or(Level::Warning);
    let words: Vec<String> = problems.into_iter().map(|(_, p)| p).collect();
    Check::new("keys", level, words.join("; "), fix.join("; "))
}

/// Days until the certificate's end (negative: past it).
fn days_left(cert: &Path) -> Result<i64, String> {
    let pem = std::fs::read(cert).map_err(|e| format!("{}: {e}", cert.display()))?;
    let not_one =
        |e: &dyn std::fmt::Display| format!("{} is not a certificate: {e}", cert.display());
    let (_, pem) = x509_parser::pem::parse_x509_pem(&pem).map_err(|e| not_one(&e))?;
    let parsed = pem.parse_x509().map_err(|e| not_one(&e))?;
    let end_s = parsed.validity().not_after.timestamp();
    let now_s = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() as i64);
    Ok((end_s - now_s).div_euclid(86_400))
}
