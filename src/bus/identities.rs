//! Who is linked to the robot's bus on a secured bus: each link's certificate name, as
//! Zenoh's TLS transport found it, held against the roster. Zenoh tells each link as it
//! comes and goes (its link events), so that a program that stays only a moment is
//! counted too. Names with a role are
//! "seen"; names the roster gives no rights (revoked, or never in it) are "refused":
//! the access rules let them do nothing, and the robot says how often they came.
//! Two programs with the camera's role linked at once are two sources of rows: the
//! rows are then taken from neither (rows.rs), and the robot faults.
//!
//! Every table here is keyed by what a peer chooses (its certificate's name, its Zenoh
//! id), so each is bounded.

use std::collections::{BTreeMap, BTreeSet};

use crossbeam_channel::{Receiver, bounded};
use zenoh::sample::SampleKind;
use zenoh::{Session, Wait};

use crate::bus::keys::{Role, Roster};

/// Names and connections kept at most; more are counted under "others".
const MAX_NAMES: usize = 32;
const MAX_SESSIONS: usize = 256;

/// Link events waiting for the bus thread; more are lost (counted as not kept).
const QUEUE_EVENTS: usize = 256;

pub(crate) struct Identities {
    roster: Roster,
    /// Each name's Zenoh sessions seen so far (a reconnect is a new one).
    seen: BTreeMap<String, BTreeSet<String>>,
    /// The links there now: (name, session) and how many links each has.
    linked: BTreeMap<(String, String), u32>,
    others: u64,
}

/// A link came (true) or went, with its certificate's name (as `shown_name` shows it)
/// and its session.
pub(crate) type LinkChange = (bool, String, String);

/// Longest certificate name shown, characters.
const SHOWN_CHARS: usize = 48;

/// A certificate's name as the robot shows it and keeps it: control characters
/// escaped, so that no terminal escape or line break in a stranger's certificate
/// reaches a console or `bus list`, and cut at 48 characters. The roster's names are
/// short and plain, so a name that has rights is shown as it is; an escaped or cut one
/// can match none of them.
pub(crate) fn shown_name(name: &str) -> String {
    let escaped: String = name
        .chars()
        .flat_map(|c| {
            let plain = !c.is_control() && c != '\\';
            let one = plain.then_some(c).into_iter();
            one.chain((!plain).then(|| c.escape_default()).into_iter().flatten())
        })
        .collect();
    if escaped.chars().count() <= SHOWN_CHARS {
        return escaped;
    }
    let cut: String = escaped.chars().take(SHOWN_CHARS).collect();
    format!("{cut}... ({} characters)", name.chars().count())
}

/// Listen to the session's links coming and going (those there already too); the
/// callback only hands each change on.
pub(crate) fn watch_links(
    session: &Session,
) -> zenoh::Result<(Receiver<LinkChange>, zenoh::session::LinkEventsListener<()>)> {
    let (tx, rx) = bounded(QUEUE_EVENTS);
    let listener = session
        .info()
        .link_events_listener()
        .history(true)
        .callback(move |event| {
            let link = event.link();
            if let Some(name) = link.auth_identifier() {
                let came = event.kind() == SampleKind::Put;
                let _ = tx.try_send((came, shown_name(name), link.zid().to_string()));
            }
        })
        .wait()?;
    Ok((rx, listener))
}

/// One look at the links.
#[derive(Debug, Default, PartialEq)]
pub struct Look {
    /// The camera-role identities linked now, with their sessions, when more than one.
    pub rival_cameras: Vec<String>,
    /// A name that came for the first time and has no rights.
    pub newly_refused: Vec<String>,
}

impl Identities {
    pub fn new(roster: Roster) -> Identities {
        Identities {
            roster,
            seen: BTreeMap::new(),
            linked: BTreeMap::new(),
            others: 0,
        }
    }

    /// Take the links that came and went since the last look.
    pub fn take(&mut self, changes: impl IntoIterator<Item = LinkChange>) -> Look {
        let mut look = Look::default();
        for (came, name, session) in changes {
            let key = (name.clone(), session.clone());
            if !came {
                if let Some(n) = self.linked.get_mut(&key) {
                    *n -= 1;
                    if *n == 0 {
                        self.linked.remove(&key);
                    }
                }
                continue;
            }
            let first = !self.seen.contains_key(&name);
            if first && self.seen.len() >= MAX_NAMES {
                self.others += 1;
                continue;
            }
            let sessions = self.seen.entry(name.clone()).or_default();
            if sessions.len() < MAX_SESSIONS {
                sessions.insert(session);
            }
            if self.linked.len() < MAX_SESSIONS || self.linked.contains_key(&key) {
                *self.linked.entry(key).or_default() += 1;
            }
            if first && self.roster.role_of(&name).is_none() {
                look.newly_refused.push(name);
            }
        }
        let cameras: Vec<String> = self
            .linked
            .keys()
            .filter(|(name, _)| self.roster.role_of(name) == Some(Role::Camera))
            .map(|(name, session)| format!("{name} (session {session})"))
            .collect();
        if cameras.len() > 1 {
            look.rival_cameras = cameras;
        }
        look
    }

    /// Whether the roster gives `name` a role.
    pub fn has_rights(&self, name: &str) -> bool {
        self.roster.role_of(name).is_some()
    }

    /// The identity linked with Zenoh session `session`, if one is.
    pub(crate) fn name_of(&self, session: &str) -> Option<&str> {
        self.linked
            .keys()
            .find(|(_, s)| s == session)
            .map(|(name, _)| name.as_str())
    }

    /// "operator x2, camera x1; refused: laptop-1 x3", for the status line.
    pub fn summary(&self) -> String {
        let mut seen = Vec::new();
        let mut refused = Vec::new();
        for (name, sessions) in &self.seen {
            let item = format!("{name} x{}", sessions.len());
            match self.roster.role_of(name) {
                Some(_) => seen.push(item),
                None => refused.push(item),
            }
        }
        let mut text = if seen.is_empty() {
            "none".to_string()
        } else {
            seen.join(", ")
        };
        if !refused.is_empty() {
            text += &format!("; refused (no rights): {}", refused.join(", "));
        }
        if self.others > 0 {
            text += &format!("; {} more not kept", self.others);
        }
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_certificate_name_with_escapes_or_no_end_is_shown_escaped_and_cut() {
        assert_eq!(shown_name("operator"), "operator");
        assert_eq!(shown_name("evil\u{1b}[2J\nroot"), "evil\\u{1b}[2J\\nroot");
        let long = "x".repeat(500);
        let shown = shown_name(&long);
        assert!(
            shown.starts_with(&"x".repeat(48)) && shown.ends_with("... (500 characters)"),
            "{shown}"
        );
        // What the robot keeps of such a name has no control character left.
        let mut ids = Identities::new(roster());
        ids.take([(true, shown_name("a\u{7}b\rc"), "s1".to_string())]);
        assert!(
            !ids.summary().chars().any(char::is_control),
            "{}",
            ids.summary()
        );
    }

    fn roster() -> Roster {
        let text = "[cluster]\nrobot = mechweed\n[roles]\nrobot = robot\ncamera = camera\noperator = operator\n[revoked]\nlaptop-1 = yes\n";
        Roster::parse(text).unwrap()
    }

    fn came(name: &str, session: &str) -> LinkChange {
        (true, name.to_string(), session.to_string())
    }

    fn went(name: &str, session: &str) -> LinkChange {
        (false, name.to_string(), session.to_string())
    }

    #[test]
    fn names_are_seen_refused_and_counted() {
        let mut ids = Identities::new(roster());
        let look = ids.take([came("operator", "a1"), came("laptop-1", "b1")]);
        assert_eq!(look.newly_refused, ["laptop-1"]);
        let look = ids.take([went("laptop-1", "b1"), came("laptop-1", "b2")]);
        assert!(look.newly_refused.is_empty(), "said once");
        assert_eq!(
            ids.summary(),
            "operator x1; refused (no rights): laptop-1 x2"
        );
    }

    #[test]
    fn two_cameras_at_once_are_rivals_one_after_the_other_are_not() {
        let mut ids = Identities::new(roster());
        assert!(ids.take([came("camera", "c1")]).rival_cameras.is_empty());
        let look = ids.take([went("camera", "c1"), came("camera", "c2")]);
        assert!(look.rival_cameras.is_empty());
        let look = ids.take([came("camera", "c3")]);
        assert_eq!(
            look.rival_cameras,
            ["camera (session c2)", "camera (session c3)"]
        );
        assert!(ids.take([went("camera", "c3")]).rival_cameras.is_empty());
    }

    #[test]
    fn the_table_is_bounded_whatever_names_come() {
        let mut ids = Identities::new(roster());
        ids.take((0..1000).map(|i| came(&format!("n{i}"), "s")));
        assert_eq!(ids.seen.len(), MAX_NAMES);
        assert!(
            ids.summary().contains("968 more not kept"),
            "{}",
            ids.summary()
        );
    }
}
