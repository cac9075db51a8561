//! A plan is input from the network: what each of its processes may say is checked
//! before a launcher starts it. A process's name and the names it waits for are names
//! (they become parts of keys); its restart delay is a number of seconds within the
//! graph's own range; and a mechweed program's options name no file outside the
//! launcher's working folder (a plan of `run --report /etc/passwd` would overwrite it),
//! no settings file (the launcher's machine has its own) and no identity (the launcher
//! gives each program its role's).

use std::collections::BTreeMap;

use super::plan::Launch;
use crate::bus::identities::shown_name;

/// Options a plan never gives: the settings file is the launcher's machine's, and the
/// identity is the one the launcher gives each program.
const NEVER: [&str; 3] = ["--config", "--keys", "--as"];

/// Settings that name files.
const FILE_SETTINGS: [&str; 5] = [
    "record.folder",
    "gnss.map",
    "bus.tls_ca",
    "bus.tls_cert",
    "bus.tls_key",
];

/// The longest restart delay a graph may give, s (graph.rs checks the same).
const LONGEST_DELAY_S: f64 = 3600.0;

/// Why `launch` must not run, or None.
pub(crate) fn refusal(
    launch: &Launch,
    file_options: &BTreeMap<String, Vec<String>>,
) -> Option<String> {
    let refused = |why: String| Some(format!("{} is refused: {why}", shown_name(&launch.name)));
    if let Some(bad) = std::iter::once(&launch.name)
        .chain(&launch.after)
        .find(|n| !is_name(n))
    {
        return refused(format!(
            "'{}' is not a process name (letters, digits, _ and -, at most 64)",
            shown_name(bad)
        ));
    }
    let delay = launch.restart_delay_s;
    if !(0.0..=LONGEST_DELAY_S).contains(&delay) {
        return refused(format!(
            "restart_delay_s = {delay} is not a delay: 0 to {LONGEST_DELAY_S} s"
        ));
    }
    if launch.program != "mechweed" {
        return None;
    }
    let command = launch.args.first().map(String::as_str).unwrap_or_default();
    let file_options = file_options
        .get(command)
        .map(Vec::as_slice)
        .unwrap_or_default();
    let mut args = launch.args.iter().skip(1).peekable();
    while let Some(arg) = args.next() {
        let (option, inline) = match arg.split_once('=') {
            Some((option, value)) if arg.starts_with("--") => (option, Some(value.to_string())),
            _ => (arg.as_str(), None),
        };
        if NEVER.contains(&option) {
            return refused(format!(
                "{option} does not come from a plan: the launcher's machine has its own settings, and the launcher gives each program its identity"
            ));
        }
        let next = args.peek().map(|v| v.to_string());
        let value = || inline.clone().or_else(|| next.clone());
        let named_file = if option == "--set" {
            value().and_then(|item| {
                let (key, path) = item.split_once('=')?;
                FILE_SETTINGS
                    .contains(&key)
                    .then(|| (format!("--set {key}"), path.to_string()))
            })
        } else if file_options.iter().any(|o| o == option) {
            value().map(|path| (option.to_string(), path))
        } else {
            None
        };
        if let Some((what, path)) = named_file
            && !inside_working_folder(&path)
        {
            return refused(format!(
                "{what} {} names a file outside the launcher's working folder: a plan may name files only inside it (a relative path without ..)",
                shown_name(&path)
            ));
        }
    }
    None
}

/// A relative path that stays inside the folder it is read from.
fn inside_working_folder(path: &str) -> bool {
    let path = std::path::Path::new(path);
    !path.as_os_str().is_empty()
        && path.is_relative()
        && !path.as_os_str().to_string_lossy().starts_with('~')
        && path.components().all(|c| {
            matches!(
                c,
                std::path::Component::Normal(_) | std::path::Component::CurDir
            )
        })
}

fn is_name(name: &str) -> bool {
    (1..=64).contains(&name.len())
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

#[cfg(test)]
mod tests {
    use super::*;

    /// As the program that starts a launcher gives them (programs/cluster.rs).
    fn refusal_of(launch: &Launch) -> Option<String> {
        let run = ["--report", "--config"].map(String::from).to_vec();
        let options = BTreeMap::from([("run".to_string(), run)]);
        refusal(launch, &options)
    }

    fn launch(args: &[&str], delay_s: f64) -> Launch {
        Launch {
            name: "controller".into(),
            program: "mechweed".into(),
            args: args.iter().map(|a| a.to_string()).collect(),
            env: Vec::new(),
            auto: true,
            restart: true,
            restart_delay_s: delay_s,
            after: Vec::new(),
            controller: true,
        }
    }

    #[test]
    fn a_plan_that_would_overwrite_a_file_or_crash_the_launcher_is_refused() {
        let why = refusal_of(&launch(
            &["run", "--headless", "--report", "/some/file"],
            0.0,
        ));
        let why = why.expect("--report outside the working folder");
        assert!(
            why.contains("--report /some/file names a file outside"),
            "{why}"
        );
        for outside in [
            &["run", "--report=../x.json"][..],
            &["run", "--report", "~/x"],
            &["run", "--report", "a/../../x"],
        ] {
            assert!(refusal_of(&launch(outside, 0.0)).is_some(), "{outside:?}");
        }
        let why = refusal_of(&launch(&["run", "--set", "record.folder=/etc"], 0.0)).unwrap();
        assert!(why.contains("--set record.folder /etc"), "{why}");
        let why = refusal_of(&launch(&["run", "--config", "x.ini"], 0.0)).unwrap();
        assert!(why.contains("--config does not come from a plan"), "{why}");
        for delay in [-1.0, f64::NAN, f64::INFINITY, 1e9] {
            let why = refusal_of(&launch(&["run"], delay)).expect("a delay out of range");
            assert!(why.contains("is not a delay"), "{why}");
        }
        let mut odd = launch(&["run"], 0.0);
        odd.name = "a/b*".into();
        assert!(refusal_of(&odd).unwrap().contains("is not a process name"));
    }

    #[test]
    fn the_shipped_graphs_plans_pass() {
        let ok = [
            launch(
                &["run", "--headless", "--set", "bus.listen=tls/0.0.0.0:7447"],
                1.0,
            ),
            launch(
                &[
                    "run",
                    "--report",
                    "run.json",
                    "--set",
                    "record.folder=field-records",
                ],
                0.0,
            ),
            launch(
                &["record", "--bus", "--set", "record.folder=./records/a"],
                3600.0,
            ),
        ];
        for launch in ok {
            assert_eq!(refusal_of(&launch), None, "{:?}", launch.args);
        }
    }
}
