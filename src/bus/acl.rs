//! The access rules of a secured bus, written from the roster at every start: Zenoh's
//! access control, deny unless a rule allows. Each identity (its certificate's common
//! name) may send only what its role is for; what a program sends to others is its own
//! doing and allowed to every identity in the roster, so a name outside the roster gets
//! nothing at all.
//!
//! Every program of the cluster applies the same table to the peers it is linked to:
//! the robot checks what operators ask, a launcher checks that its plan comes from the
//! master. ROBOT is the robot's key prefix, C = ROBOT/cluster.
//!
//! | role     | sends                                                                    |
//! |----------|--------------------------------------------------------------------------|
//! | robot    | status, tick, event; answers requests and settings; takes camera rows     |
//! | camera   | camera rows                                                              |
//! | operator | takes status, tick, event; asks every request, gets and sets settings    |
//! | viewer   | takes status, tick, event; asks HALT (ROBOT/request) and gets settings   |
//! | recorder | takes status, tick, event; gets settings                                 |
//! | master   | answers plans and the cluster's status; takes process states; asks stops |
//! | launcher | its own machine's process states; asks its own plan; answers its stops   |
//!
//! Requests are split by key so that a rule can tell them apart: ROBOT/request answers
//! HALT only when the bus is secured, ROBOT/request/operator every request, and
//! ROBOT/set/SECTION/KEY changes a setting (ROBOT/config/SECTION/KEY only reads it).
//! Each identity may ask the same under ROBOT/as/NAME/, its own name alone, so that the
//! robot counts what it asks by its link's certificate (bus/asked_as.rs).

use serde_json::{Value, json};

use crate::bus::keys::{Role, Roster};

const PUT: &str = "put";
const SUBSCRIBE: &str = "declare_subscriber";
const QUERY: &str = "query";
const QUERYABLE: &str = "declare_queryable";
const REPLY: &str = "reply";
const TOKEN: &str = "liveliness_token";
const WATCH: &str = "declare_liveliness_subscriber";
const LOOK: &str = "liveliness_query";

/// One rule: these messages on these keys, allowed from an identity.
struct Rule {
    messages: &'static [&'static str],
    keys: Vec<String>,
}

fn rule(messages: &'static [&'static str], keys: &[String]) -> Rule {
    Rule {
        messages,
        keys: keys.to_vec(),
    }
}

/// What an identity of `role` named `name` may send to the others.
fn rules_of(role: Role, name: &str, robot: &str) -> Vec<Rule> {
    let r = |rest: &str| format!("{robot}/{rest}");
    let c = |rest: &str| format!("{robot}/cluster/{rest}");
    let flows = [r("status"), r("tick"), r("event")];
    // Who is there: every program of the cluster may look.
    let mut rules = vec![rule(&[WATCH, LOOK], &[r("alive/**"), c("**")])];
    let own_token = |rules: &mut Vec<Rule>| rules.push(rule(&[TOKEN], &[r("alive/*")]));
    // What a receiver gets, reported to the robot, which names it in its status.
    let heard = rule(&[PUT], &[r("heard/*")]);
    // What an identity asks of the robot: on the keys all share, and on its own.
    let asks = |rests: &[&str]| {
        let keys: Vec<String> = (rests.iter())
            .flat_map(|rest| [r(rest), r(&format!("as/{name}/{rest}"))])
            .collect();
        rule(&[QUERY], &keys)
    };
    match role {
        Role::Robot => {
            rules.push(rule(&[PUT], &flows));
            rules.push(rule(
                &[QUERYABLE, REPLY],
                &[
                    r("request"),
                    r("request/**"),
                    r("config/**"),
                    r("set/**"),
                    r("as/*/request"),
                    r("as/*/request/**"),
                    r("as/*/config/**"),
                    r("as/*/set/**"),
                ],
            ));
            rules.push(rule(&[SUBSCRIBE], &[r("camera/row"), r("heard/*")]));
            own_token(&mut rules);
        }
        Role::Camera => {
            rules.push(rule(&[PUT], &[r("camera/row"), r("heard/*")]));
            // The robot's status as the heartbeat of its session (bus/hearing.rs).
            rules.push(rule(&[SUBSCRIBE], &[r("status")]));
            own_token(&mut rules);
        }
        Role::Operator => {
            rules.push(rule(&[SUBSCRIBE], &flows));
            rules.push(asks(&["request", "request/**", "config/**", "set/**"]));
            rules.push(rule(&[QUERY], &[c("status")]));
            rules.push(heard);
            own_token(&mut rules);
        }
        Role::Viewer => {
            rules.push(rule(&[SUBSCRIBE], &flows));
            // Not the cluster's status: it holds every machine's command lines.
            rules.push(asks(&["request", "config/**"]));
            rules.push(heard);
            own_token(&mut rules);
        }
        Role::Recorder => {
            rules.push(rule(&[SUBSCRIBE], &flows));
            rules.push(asks(&["config/**"]));
            rules.push(heard);
            own_token(&mut rules);
        }
        Role::Master => {
            rules.push(rule(
                &[QUERYABLE, REPLY],
                &[c("plan/*"), c("status"), c("states")],
            ));
            rules.push(rule(&[SUBSCRIBE], &[c("state/**")]));
            rules.push(rule(&[QUERY], &[c("stop/*")]));
            rules.push(rule(&[TOKEN], &[c("master")]));
        }
        Role::Launcher => {
            // A launcher's name is its machine's: it speaks for that machine alone.
            rules.push(rule(&[PUT], &[c(&format!("state/{name}/*"))]));
            // Its plan, and the processes' states (whether those its own wait for
            // run); not the cluster's status, which holds every machine's command lines.
            rules.push(rule(&[QUERY], &[c(&format!("plan/{name}")), c("states")]));
            rules.push(rule(&[QUERYABLE, REPLY], &[c(&format!("stop/{name}"))]));
            rules.push(rule(
                &[TOKEN],
                &[
                    c(&format!("launcher/{name}")),
                    c(&format!("process/{name}/**")),
                ],
            ));
        }
    }
    rules
}

/// Zenoh's `access_control` section for `roster`.
pub(crate) fn access_control(roster: &Roster) -> Value {
    let robot = &roster.robot;
    let mut rules = Vec::new();
    let mut subjects = Vec::new();
    let mut policies = Vec::new();
    let mut known = Vec::new();
    for (name, role) in &roster.roles {
        let subject = format!("id-{name}");
        subjects.push(json!({ "id": subject, "cert_common_names": [name] }));
        known.push(subject.clone());
        let mut ids = Vec::new();
        for (i, r) in rules_of(*role, name, robot).into_iter().enumerate() {
            let id = format!("{name}-{i}");
            rules.push(json!({
                "id": id,
                "messages": r.messages,
                "flows": ["ingress"],
                "permission": "allow",
                "key_exprs": r.keys,
            }));
            ids.push(id);
        }
        if *role != Role::Robot {
            // Only the robot program is the controller that tools wait for.
            let id = format!("{name}-not-controller");
            rules.push(json!({
                "id": id,
                "messages": [TOKEN],
                "flows": ["ingress"],
                "permission": "deny",
                "key_exprs": [format!("{robot}/alive/controller")],
            }));
            ids.push(id);
        }
        policies.push(json!({ "rules": ids, "subjects": [subject] }));
    }
    if !known.is_empty() {
        rules.push(json!({
            "id": "send-to-the-cluster",
            "messages": [PUT, SUBSCRIBE, QUERY, QUERYABLE, REPLY, TOKEN, WATCH, LOOK],
            "flows": ["egress"],
            "permission": "allow",
            "key_exprs": [format!("{robot}/**")],
        }));
        policies.push(json!({ "rules": ["send-to-the-cluster"], "subjects": known }));
    }
    json!({
        "enabled": true,
        "default_permission": "deny",
        "rules": rules,
        "subjects": subjects,
        "policies": policies,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    fn roster() -> Roster {
        let mut roles = BTreeMap::new();
        for role in Role::ALL {
            roles.insert(role.name().to_string(), role);
        }
        roles.insert("robot-pc".to_string(), Role::Launcher);
        Roster {
            robot: "mechweed".to_string(),
            roles,
            revoked: Vec::new(),
        }
    }

    /// The keys `name` may send `message` on.
    fn allowed(acl: &Value, name: &str, message: &str) -> Vec<String> {
        let subject = format!("id-{name}");
        let policy = acl["policies"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| p["subjects"] == json!([subject]))
            .unwrap();
        let ids = policy["rules"].as_array().unwrap();
        acl["rules"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|r| ids.contains(&r["id"]) && r["permission"] == "allow")
            .filter(|r| r["messages"].as_array().unwrap().contains(&json!(message)))
            .flat_map(|r| r["key_exprs"].as_array().unwrap().clone())
            .map(|k| k.as_str().unwrap().to_string())
            .collect()
    }

    #[test]
    fn only_the_operator_asks_for_more_than_halt() {
        let acl = access_control(&roster());
        let viewer = allowed(&acl, "viewer", QUERY);
        assert!(viewer.contains(&"mechweed/request".to_string()));
        assert!(!viewer.iter().any(|k| k.starts_with("mechweed/request/")));
        assert!(!viewer.iter().any(|k| k.starts_with("mechweed/set")));
        let operator = allowed(&acl, "operator", QUERY);
        assert!(operator.contains(&"mechweed/request/**".to_string()));
        assert!(operator.contains(&"mechweed/set/**".to_string()));
        for role in ["camera", "recorder", "robot", "master"] {
            let asks = allowed(&acl, role, QUERY);
            assert!(
                !asks.iter().any(|k| k.contains("request")),
                "{role}: {asks:?}"
            );
        }
    }

    #[test]
    fn each_identity_asks_under_its_own_name_alone() {
        let acl = access_control(&roster());
        for (name, own) in [
            (
                "operator",
                &["request", "request/**", "config/**", "set/**"][..],
            ),
            ("viewer", &["request", "config/**"][..]),
            ("recorder", &["config/**"][..]),
        ] {
            let asks = allowed(&acl, name, QUERY);
            let named: Vec<&String> = asks.iter().filter(|k| k.contains("/as/")).collect();
            let expected: Vec<String> = (own.iter())
                .map(|rest| format!("mechweed/as/{name}/{rest}"))
                .collect();
            assert_eq!(named, expected.iter().collect::<Vec<_>>(), "{name}");
        }
        for name in ["camera", "master", "robot-pc", "robot"] {
            let asks = allowed(&acl, name, QUERY);
            assert!(!asks.iter().any(|k| k.contains("/as/")), "{name}: {asks:?}");
        }
        // The robot answers every name's questions.
        assert!(allowed(&acl, "robot", QUERYABLE).contains(&"mechweed/as/*/config/**".to_string()));
    }

    #[test]
    fn rows_come_from_the_camera_and_plans_from_the_master() {
        let acl = access_control(&roster());
        for (name, roles) in [("camera", true), ("operator", false), ("viewer", false)] {
            let puts = allowed(&acl, name, PUT);
            assert_eq!(puts.contains(&"mechweed/camera/row".to_string()), roles);
        }
        assert_eq!(
            allowed(&acl, "master", REPLY),
            [
                "mechweed/cluster/plan/*",
                "mechweed/cluster/status",
                "mechweed/cluster/states"
            ]
        );
        assert!(allowed(&acl, "operator", REPLY).is_empty());
        // A launcher asks for its own machine's plan and the processes' states (not
        // the status with every command line), and reports its own processes.
        assert_eq!(
            allowed(&acl, "robot-pc", QUERY),
            ["mechweed/cluster/plan/robot-pc", "mechweed/cluster/states"]
        );
        assert_eq!(
            allowed(&acl, "robot-pc", PUT),
            ["mechweed/cluster/state/robot-pc/*"]
        );
    }

    #[test]
    fn the_table_is_deny_unless_allowed() {
        let acl = access_control(&roster());
        assert_eq!(acl["default_permission"], "deny");
        assert_eq!(acl["enabled"], true);
        // Every subject is one name of the roster: nobody else matches.
        let names: Vec<&Value> = acl["subjects"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| &s["cert_common_names"][0])
            .collect();
        assert_eq!(names.len(), roster().roles.len());
    }
}
