//! The roster: who is who in a cluster. Each identity's name (its certificate's common
//! name) and its role, in `roles.ini` beside the authority's certificate. The access
//! rules are written from it at every start (bus/acl.rs), so a name that is not in it
//! may do nothing, even with a certificate the authority signed: taking a lost
//! laptop's name out of the roster on each computer revokes it.

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// What a program of the cluster is for; its rights follow from it (bus/acl.rs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Role {
    Robot,
    Camera,
    Operator,
    Viewer,
    Recorder,
    Master,
    Launcher,
}

impl Role {
    pub(crate) const ALL: [Role; 7] = [
        Role::Robot,
        Role::Camera,
        Role::Operator,
        Role::Viewer,
        Role::Recorder,
        Role::Master,
        Role::Launcher,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Role::Robot => "robot",
            Role::Camera => "camera",
            Role::Operator => "operator",
            Role::Viewer => "viewer",
            Role::Recorder => "recorder",
            Role::Master => "master",
            Role::Launcher => "launcher",
        }
    }

    pub fn parse(text: &str) -> Result<Role, String> {
        Role::ALL
            .into_iter()
            .find(|r| r.name() == text)
            .ok_or_else(|| {
                let names: Vec<&str> = Role::ALL.iter().map(|r| r.name()).collect();
                format!("'{text}' is not a role (one of {})", names.join(", "))
            })
    }
}

impl fmt::Display for Role {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An identity's name: letters, digits and `-`, so that it is a file name, a host
/// name in the certificate and a key part on the bus alike.
pub(crate) fn check_name(name: &str) -> Result<(), String> {
    let ok = !name.is_empty()
        && name.len() <= 63
        && !name.starts_with('-')
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-');
    if ok && name != "ca" && name != "roles" {
        Ok(())
    } else {
        Err(format!(
            "'{name}' is not an identity's name: lower-case letters, digits and -, at most 63, not ca or roles (for example laptop-2)"
        ))
    }
}

/// The cluster's identities: the robot's name on the bus and each identity's role.
#[derive(Debug, Clone, PartialEq)]
pub struct Roster {
    /// The first part of every key of the robot's flows ([bus] robot).
    pub robot: String,
    pub roles: BTreeMap<String, Role>,
    /// Names taken out: never given again, so an old certificate of that name stays
    /// without rights.
    pub revoked: Vec<String>,
}

/// The roster's file in a keys folder.
pub(crate) fn path_in(dir: &Path) -> PathBuf {
    dir.join(crate::config::ROSTER_FILE)
}

impl Roster {
    /// The names that have `role`.
    pub fn names(&self, role: Role) -> impl Iterator<Item = &str> {
        self.roles
            .iter()
            .filter(move |(_, r)| **r == role)
            .map(|(n, _)| n.as_str())
    }

    pub(crate) fn role_of(&self, name: &str) -> Option<Role> {
        self.roles.get(name).copied()
    }

    /// Read `path`; every error names the file and the line.
    pub fn read(path: &Path) -> Result<Roster, String> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            format!(
                "cannot read the cluster's roster {}: {e} (mechweed keys new writes it beside ca.pem; copy it with ca.pem)",
                path.display()
            )
        })?;
        Roster::parse(&text).map_err(|(line, why)| format!("{}:{line}: {why}", path.display()))
    }

    /// The text of roles.ini; an error is (line number, what is wrong).
    pub fn parse(text: &str) -> Result<Roster, (usize, String)> {
        let mut roster = Roster {
            robot: String::new(),
            roles: BTreeMap::new(),
            revoked: Vec::new(),
        };
        let mut section = "";
        for (i, raw) in text.lines().enumerate() {
            let n = i + 1;
            let line = raw.trim();
            if line.is_empty() || line.starts_with(';') || line.starts_with('#') {
                continue;
            }
            if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
                section = match name {
                    "cluster" => "cluster",
                    "roles" => "roles",
                    "revoked" => "revoked",
                    other => return Err((n, format!("unknown section [{other}]"))),
                };
                continue;
            }
            let Some((key, value)) = line.split_once('=') else {
                return Err((n, format!("'{line}' is not KEY = VALUE")));
            };
            let (key, value) = (key.trim(), value.trim());
            match section {
                "cluster" if key == "robot" => {
                    roster.robot = crate::config::parse_prefix(value).map_err(|e| (n, e))?
                }
                "roles" => {
                    check_name(key).map_err(|e| (n, e))?;
                    let role = Role::parse(value).map_err(|e| (n, e))?;
                    if roster.roles.insert(key.to_string(), role).is_some() {
                        return Err((n, format!("{key} is named twice")));
                    }
                }
                "revoked" if value == "yes" => roster.revoked.push(key.to_string()),
                _ => return Err((n, format!("'{line}' means nothing here"))),
            }
        }
        if roster.robot.is_empty() {
            return Err((1, "no [cluster] robot = NAME".to_string()));
        }
        if let Some(name) = roster
            .revoked
            .iter()
            .find(|n| roster.roles.contains_key(*n))
        {
            return Err((1, format!("{name} is both in [roles] and [revoked]")));
        }
        Ok(roster)
    }

    pub(crate) fn to_text(&self) -> String {
        let mut text = String::from(
            "; Who is who in this cluster: each identity's name (its certificate's common name)\n\
             ; and its role. mechweed writes it (keys new, keys add, keys revoke); copy it with\n\
             ; ca.pem to every computer of the cluster. A name not here may do nothing on the bus.\n",
        );
        text += &format!("[cluster]\nrobot = {}\n\n[roles]\n", self.robot);
        for (name, role) in &self.roles {
            text += &format!("{name} = {role}\n");
        }
        if !self.revoked.is_empty() {
            text += "\n; Taken out: their certificates still exist, but have no rights; never reused.\n[revoked]\n";
            for name in &self.revoked {
                text += &format!("{name} = yes\n");
            }
        }
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_roster_reads_back_what_it_wrote() {
        let mut roles = BTreeMap::new();
        roles.insert("robot".to_string(), Role::Robot);
        roles.insert("laptop-2".to_string(), Role::Operator);
        let roster = Roster {
            robot: "farm/robot2".to_string(),
            roles,
            revoked: vec!["laptop-1".to_string()],
        };
        assert_eq!(Roster::parse(&roster.to_text()), Ok(roster));
    }

    #[test]
    fn a_bad_line_is_named() {
        let text = "[cluster]\nrobot = mechweed\n[roles]\nrobot = robot\nlaptop = pilot\n";
        let (line, why) = Roster::parse(text).unwrap_err();
        assert_eq!(line, 5);
        assert!(why.contains("'pilot' is not a role"), "{why}");
        assert!(check_name("Laptop").is_err());
        assert!(check_name("ca").is_err());
        assert!(check_name("robot-pc").is_ok());
    }
}
