//! The cluster's identities: its own certificate authority, and a key and certificate
//! for each program, made here (rcgen; nothing to install). A certificate's common
//! name is the identity's name and its organisational unit is its role; the roster
//! (roster.rs) is what the access rules are written from.
//!
//! The authority's private key (ca.key) is needed only to make certificates: it never
//! has to be on the robot.

pub mod roster;

use std::fs::OpenOptions;
use std::io::Write;
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use rcgen::{
    BasicConstraints, CertificateParams, DistinguishedName, DnType, ExtendedKeyUsagePurpose, IsCa,
    Issuer, KeyPair, KeyUsagePurpose,
};

pub use roster::{Role, Roster};

/// How long a certificate is valid, years: a field season and then some. A lost one is
/// revoked through the roster, not by waiting for it to end.
const VALID_YEARS: i32 = 5;

/// The files of one identity in a keys folder: NAME.pem and NAME.key.
pub(crate) fn identity_files(dir: &Path, name: &str) -> (PathBuf, PathBuf) {
    (
        dir.join(format!("{name}.pem")),
        dir.join(format!("{name}.key")),
    )
}

fn current_year() -> i32 {
    let secs = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    1970 + (secs / 31_556_952) as i32
}

fn validity(params: &mut CertificateParams) {
    let year = current_year();
    // From last year: a computer whose clock is a little behind still takes it.
    params.not_before = rcgen::date_time_ymd(year - 1, 1, 1);
    params.not_after = rcgen::date_time_ymd(year + VALID_YEARS, 12, 31);
}

/// Write `text` to `path`, which must not exist; `private`: readable by its owner only.
fn write_new(path: &Path, text: &str, private: bool) -> Result<(), String> {
    let mut options = OpenOptions::new();
    options.write(true).create_new(true);
    if private {
        options.mode(0o600);
    }
    let mut file = options.open(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::AlreadyExists => {
            format!("{} exists already: nothing is overwritten", path.display())
        }
        _ => format!("cannot write {}: {e}", path.display()),
    })?;
    file.write_all(text.as_bytes())
        .and_then(|()| file.sync_all())
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// What is wrong with how an identity's files lie, each with its fix: the authority's
/// key beside them (whoever reads it can make identities), or the private key readable
/// by every user of the computer.
pub fn exposure(tls: &crate::config::TlsFiles) -> Vec<(String, String)> {
    use std::os::unix::fs::PermissionsExt;
    let mut found = Vec::new();
    if let Ok(meta) = std::fs::metadata(&tls.key)
        && meta.permissions().mode() & 0o007 != 0
    {
        let mode = meta.permissions().mode() & 0o777;
        found.push((
            format!(
                "{} is readable by every user (mode {mode:o})",
                tls.key.display()
            ),
            format!("sudo chmod 0640 {}", tls.key.display()),
        ));
    }
    let ca_key = tls.ca.with_file_name("ca.key");
    if ca_key.exists() {
        found.push((
            format!("{} is here: whoever reads it can make identities", ca_key.display()),
            format!("move {} to the machine that makes the keys (mechweed keys), off the robot and the field's computers", ca_key.display()),
        ));
    }
    found
}

/// The keys and certificates (`*.key`, `*.pem`) in `dir`, sorted; none if it is not there.
fn key_files_in(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut found: Vec<_> = (std::fs::read_dir(dir).into_iter().flatten().flatten())
        .map(|entry| entry.path())
        .filter(|p| p.extension().is_some_and(|e| e == "key" || e == "pem"))
        .collect();
    found.sort();
    found
}

fn rcgen_error(what: &str) -> impl Fn(rcgen::Error) -> String + '_ {
    move |e| format!("cannot make {what}: {e}")
}

/// Make a new authority and the first identity of each role in `dir` (made if missing;
/// refused if it holds an authority already).
/// `robot_hosts`: host names and addresses the robot's certificate names besides its
/// role, so that a standard TLS client that checks the name it dialled accepts it.
pub(crate) fn new_cluster(
    dir: &Path,
    robot: &str,
    robot_hosts: &[String],
) -> Result<Vec<String>, String> {
    crate::config::parse_prefix(robot)?;
    let roster_path = roster::path_in(dir);
    if dir.join("ca.key").exists() || roster_path.exists() {
        return Err(format!(
            "{} holds a cluster's keys already: a new authority would lock out every computer that has the old one. Use keys add for one more identity, or name a new folder",
            dir.display()
        ));
    }
    // Any key or certificate there: refused before anything is written, naming it,
    // so that no half-made authority is left beside a stray file.
    if let Some(stray) = key_files_in(dir).first() {
        return Err(format!(
            "{} holds {} already: keys new makes a new cluster's keys in a folder of their own; move that file away or name a new folder",
            dir.display(),
            stray.display()
        ));
    }
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot make {}: {e}", dir.display()))?;
    let ca_key = KeyPair::generate().map_err(rcgen_error("the authority's key"))?;
    let mut params = CertificateParams::default();
    let mut name = DistinguishedName::new();
    name.push(DnType::CommonName, format!("mechweed {robot} authority"));
    name.push(DnType::OrganizationName, "mechweed");
    params.distinguished_name = name;
    params.is_ca = IsCa::Ca(BasicConstraints::Constrained(0));
    params.key_usages = vec![KeyUsagePurpose::KeyCertSign, KeyUsagePurpose::CrlSign];
    validity(&mut params);
    let ca_cert = params
        .self_signed(&ca_key)
        .map_err(rcgen_error("the authority's certificate"))?;
    write_new(&dir.join("ca.key"), &ca_key.serialize_pem(), true)?;
    write_new(&dir.join("ca.pem"), &ca_cert.pem(), false)?;
    let issuer = Issuer::new(params, ca_key);
    let mut roster = Roster {
        robot: robot.to_string(),
        roles: Default::default(),
        revoked: Vec::new(),
    };
    let mut made = vec!["ca.pem".to_string(), "ca.key".to_string()];
    for role in Role::ALL {
        let hosts = if role == Role::Robot {
            robot_hosts
        } else {
            &[]
        };
        made.extend(make_identity(dir, &issuer, role, role.name(), hosts)?);
        roster.roles.insert(role.name().to_string(), role);
    }
    write_new(&roster_path, &roster.to_text(), false)?;
    made.push("roles.ini".to_string());
    Ok(made)
}

/// One more identity `name` with `role`, signed by the authority in `dir`, naming
/// `hosts` (host names, addresses) besides its name.
pub(crate) fn add_identity(
    dir: &Path,
    role: Role,
    name: &str,
    hosts: &[String],
) -> Result<Vec<String>, String> {
    roster::check_name(name)?;
    let roster_path = roster::path_in(dir);
    let mut roster = Roster::read(&roster_path)?;
    if roster.revoked.iter().any(|n| n == name) {
        return Err(format!(
            "{name} was revoked: a name is never given again (its old certificate would regain the rights); choose another name"
        ));
    }
    if let Some(has) = roster.role_of(name) {
        return Err(format!("{name} is in the roster already, as {has}"));
    }
    let read = |file: &str| {
        let path = dir.join(file);
        std::fs::read_to_string(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))
    };
    let ca_key = KeyPair::from_pem(&read("ca.key")?)
        .map_err(|e| format!("{}/ca.key is not a private key: {e}", dir.display()))?;
    let issuer = Issuer::from_ca_cert_pem(&read("ca.pem")?, ca_key)
        .map_err(|e| format!("{}/ca.pem is not a certificate: {e}", dir.display()))?;
    let made = make_identity(dir, &issuer, role, name, hosts)?;
    roster.roles.insert(name.to_string(), role);
    replace(&roster_path, &roster.to_text())?;
    Ok(made)
}

/// Take `name` out of the roster: its certificate keeps working for the TLS handshake,
/// but has no rights on any computer that has the new roster.
pub fn revoke(dir: &Path, name: &str) -> Result<Role, String> {
    let roster_path = roster::path_in(dir);
    let mut roster = Roster::read(&roster_path)?;
    let role = roster
        .roles
        .remove(name)
        .ok_or_else(|| format!("{name} is not in {}", roster_path.display()))?;
    roster.revoked.push(name.to_string());
    replace(&roster_path, &roster.to_text())?;
    Ok(role)
}

/// Write `text` over `path` through a temporary file, so a crash leaves the old one.
fn replace(path: &Path, text: &str) -> Result<(), String> {
    let temporary = path.with_extension("ini.new");
    let _ = std::fs::remove_file(&temporary);
    write_new(&temporary, text, false)?;
    std::fs::rename(&temporary, path).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

fn make_identity(
    dir: &Path,
    issuer: &Issuer<'_, KeyPair>,
    role: Role,
    name: &str,
    hosts: &[String],
) -> Result<Vec<String>, String> {
    let (cert_path, key_path) = identity_files(dir, name);
    if cert_path.exists() || key_path.exists() {
        return Err(format!(
            "{} exists already: nothing is overwritten",
            cert_path.display()
        ));
    }
    let key = KeyPair::generate().map_err(rcgen_error("a key"))?;
    // The name as a host name too: TLS wants one, though the cluster checks the
    // authority and the name in the roster, not addresses. A standard client checks the
    // host it dialled (robot-pc, 192.168.1.10): `hosts` names those (an address is taken
    // as an IP address).
    let names: Vec<String> = std::iter::once(name.to_string())
        .chain(hosts.iter().cloned())
        .collect();
    let mut params = CertificateParams::new(names).map_err(rcgen_error("a certificate"))?;
    let mut dn = DistinguishedName::new();
    dn.push(DnType::CommonName, name);
    dn.push(DnType::OrganizationalUnitName, role.name());
    dn.push(DnType::OrganizationName, "mechweed");
    params.distinguished_name = dn;
    params.key_usages = vec![KeyUsagePurpose::DigitalSignature];
    // Both ends of a link show a certificate: each is a server and a client.
    params.extended_key_usages = vec![
        ExtendedKeyUsagePurpose::ServerAuth,
        ExtendedKeyUsagePurpose::ClientAuth,
    ];
    validity(&mut params);
    let cert = params
        .signed_by(&key, issuer)
        .map_err(rcgen_error("a certificate"))?;
    write_new(&key_path, &key.serialize_pem(), true)?;
    write_new(&cert_path, &cert.pem(), false)?;
    Ok(vec![format!("{name}.pem"), format!("{name}.key")])
}

/// The name a certificate file carries (its common name): the name the links and the
/// access rules know it by, whatever its file is called.
pub fn certificate_name(cert: &Path) -> Result<String, String> {
    let pem = std::fs::read(cert)
        .map_err(|e| format!("cannot read the certificate {}: {e}", cert.display()))?;
    let not_one =
        |e: &dyn std::fmt::Display| format!("{} is not a certificate: {e}", cert.display());
    let (_, pem) = x509_parser::pem::parse_x509_pem(&pem).map_err(|e| not_one(&e))?;
    let parsed = pem.parse_x509().map_err(|e| not_one(&e))?;
    let name = parsed.subject().iter_common_name().next();
    name.and_then(|n| n.as_str().ok())
        .map(crate::bus::identities::shown_name)
        .ok_or_else(|| format!("the certificate {} names nobody", cert.display()))
}

#[cfg(test)]
mod tests {
    #[test]
    fn keys_new_into_a_folder_with_a_stray_key_writes_nothing_and_names_it() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("laptop.key"), "not ours").unwrap();
        let why = super::new_cluster(dir.path(), "mechweed", &[]).unwrap_err();
        assert!(why.contains("laptop.key"), "{why}");
        let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().flatten().collect();
        assert_eq!(left.len(), 1, "only the stray file: {left:?}");
        // An empty folder, or one that is not there yet, is taken.
        assert!(super::new_cluster(&dir.path().join("new"), "mechweed", &[]).is_ok());
    }
}
