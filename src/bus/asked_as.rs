//! Who asked, from the link: a program with an identity asks the robot on keys that name
//! it, ROBOT/as/NAME/REST (REST: request, request/operator, config/SECTION/KEY,
//! set/SECTION/KEY), and the access rules of a secured bus let only the certificate
//! named NAME ask under ROBOT/as/NAME (bus/acl.rs). So the robot counts each identity's
//! queries by the certificate of the link they came on, never by what a query says, and
//! no other identity's flood can use an operator's allowance (bus/gate.rs).
//!
//! The keys without `as/NAME` still work, for a program that names no one (a lab's own
//! client): those share one allowance, which anyone's flood can use up. On a bus that is
//! not secured there are no certificates: NAME is then only what the asker says.

use super::identities::Identities;

/// Who asked a query, as the robot counts it.
#[derive(Debug, PartialEq)]
pub(crate) struct Asker {
    /// What the asker is counted by: its identity's name, or what it says.
    pub asker: String,
    /// Its identity by the roster, on a secured bus.
    pub name: Option<String>,
    /// The name is its link's certificate: it asked under ROBOT/as/NAME of a secured bus.
    pub from_link: bool,
}

/// Who asked under `named` (split's name), with `attachment` (what the query says:
/// mechweed's tools name their Zenoh session), on a secured bus with `identities`.
pub(crate) fn asker(
    named: Option<String>,
    attachment: String,
    identities: Option<&Identities>,
) -> Asker {
    match (named, identities) {
        // The access rules let only NAME's certificate ask there.
        (Some(name), Some(ids)) if ids.has_rights(&name) => Asker {
            asker: name.clone(),
            name: Some(name),
            from_link: true,
        },
        // A session's name by its link, or the attachment as it is.
        (_, Some(ids)) => Asker {
            name: ids.name_of(&attachment).map(str::to_string),
            asker: attachment,
            from_link: false,
        },
        // Not secured: anyone may say anything.
        (named, None) => Asker {
            asker: named.unwrap_or(attachment),
            name: None,
            from_link: false,
        },
    }
}

/// Where a program named `name` asks `rest` of `robot`: ROBOT/as/NAME/REST with a name
/// (an identity on a secured bus), ROBOT/REST without.
pub fn key(robot: &str, name: Option<&str>, rest: &str) -> String {
    match name {
        Some(name) => format!("{robot}/as/{name}/{rest}"),
        None => format!("{robot}/{rest}"),
    }
}

/// A query's key as the robot answers it: ROBOT/REST, and the NAME it was asked as,
/// if any. A key that is not under ROBOT/as/NAME/ is given back whole.
pub fn split(robot: &str, key: &str) -> (String, Option<String>) {
    let named = key
        .strip_prefix(robot)
        .and_then(|k| k.strip_prefix("/as/"))
        .and_then(|k| k.split_once('/'))
        .filter(|(name, rest)| !name.is_empty() && !rest.is_empty());
    match named {
        Some((name, rest)) => (format!("{robot}/{rest}"), Some(name.to_string())),
        None => (key.to_string(), None),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_named_key_splits_into_the_robots_key_and_the_name() {
        let asked = key("farm/robot2", Some("operator-2"), "config/steer/kp");
        assert_eq!(asked, "farm/robot2/as/operator-2/config/steer/kp");
        assert_eq!(
            split("farm/robot2", &asked),
            (
                "farm/robot2/config/steer/kp".to_string(),
                Some("operator-2".to_string())
            )
        );
        assert_eq!(key("mechweed", None, "request"), "mechweed/request");
    }

    #[test]
    fn keys_that_name_no_one_are_given_back_whole() {
        for plain in [
            "mechweed/request",
            "mechweed/request/operator",
            "mechweed/as/operator",
            "mechweed/as//request",
            "mechweed/asx/operator/request",
        ] {
            assert_eq!(split("mechweed", plain), (plain.to_string(), None));
        }
    }
}
