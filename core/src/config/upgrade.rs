//! `mechweed config upgrade FILE`: a robot.ini of an older release brought up to this
//! one without losing a technician's work. Every setting and section this release has
//! and the file lacks is added, with the shipped comment above it, at the end of its
//! section (a missing section at the end of the file); every line already there stays
//! as it is, where it is. A setting whose older behaviour differs from today's shipped
//! value gets the value that keeps the older behaviour (`OLDER`); every other gets its
//! shipped value, the behaviour the file's robot had before there was a choice. A
//! setting that an older release had and this one has replaced (`RETIRED`) is kept as
//! a comment, and its value goes to the setting that took its place.

use super::DEFAULT_INI;
use super::lines::scan;

/// Settings whose shipped value changes what an older robot did: the value that keeps
/// the older behaviour, and why.
const OLDER: &[(&str, &str, &str, &str)] = &[
    (
        "steer",
        "law",
        "pursuit",
        "the steering law of every release before [steer] law was a setting",
    ),
    (
        "record",
        "keep_gb",
        "0",
        "no limit in space, as every release before [record] keep_gb",
    ),
    (
        "ros2",
        "frame_prefix",
        "",
        "frame ids without a prefix, as every release before [ros2] frame_prefix",
    ),
    (
        "ros2",
        "halt_service",
        "no",
        "nothing from ROS reaches the robot, as in every release before [ros2] halt_service",
    ),
];

/// Settings of older releases that a setting of this one replaced, with the same
/// meaning and unit: (section, key, the section and key that took its place).
const RETIRED: &[(&str, &str, &str, &str)] =
    &[("faults", "steer_silent_s", "rt", "heartbeat_timeout_s")];

/// One thing added (or, `retired`, one line made a comment).
#[derive(Debug, Clone, PartialEq)]
pub struct Added {
    pub section: String,
    pub key: String,
    pub value: String,
    /// Why this value, where it is not the shipped one.
    pub why: Option<String>,
    /// The whole section was missing.
    pub new_section: bool,
    /// A setting of an older release, kept as a comment.
    pub retired: bool,
}

impl Added {
    /// "[steer] law = pursuit (the steering law of ...)", or "(the shipped value)".
    pub fn line(&self) -> String {
        let why = self.why.as_deref().unwrap_or("the shipped value");
        format!("[{}] {} = {} ({why})", self.section, self.key, self.value)
    }
}

/// A line of robot.ini as this file sorts them.
#[derive(Debug, Clone, PartialEq)]
enum Line {
    Blank,
    Comment,
    Heading(String),
    Key(String),
}

fn sort(line: &str) -> Line {
    let line = line.trim().trim_start_matches('\u{feff}');
    if line.is_empty() {
        Line::Blank
    } else if line.starts_with(';') || line.starts_with('#') {
        Line::Comment
    } else if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
        Line::Heading(name.trim().to_string())
    } else {
        let key = line.split_once('=').map_or(line, |(key, _)| key);
        Line::Key(key.trim().to_string())
    }
}

/// A shipped section: the comment lines above its heading, the heading, and each key
/// with the comment lines just above it.
struct ShippedSection {
    name: String,
    intro: Vec<String>,
    keys: Vec<(String, Vec<String>)>,
}

fn shipped() -> Vec<ShippedSection> {
    let mut sections: Vec<ShippedSection> = Vec::new();
    let mut comments: Vec<String> = Vec::new();
    for line in DEFAULT_INI.lines() {
        match sort(line) {
            Line::Blank => comments.clear(),
            Line::Comment => comments.push(line.to_string()),
            Line::Heading(name) => sections.push(ShippedSection {
                name,
                intro: std::mem::take(&mut comments),
                keys: Vec::new(),
            }),
            Line::Key(key) => {
                comments.push(line.to_string());
                if let Some(section) = sections.last_mut() {
                    section.keys.push((key, std::mem::take(&mut comments)));
                }
            }
        }
    }
    sections
}

/// A retired setting's value carried to the one that took its place:
/// (section, key, value, why).
type Carried = Vec<(String, String, String, String)>;

/// The key's line as shipped, or with the older behaviour's value or a retired
/// setting's; with what was added.
fn key_lines(
    (section, key): (&str, &str),
    block: &[String],
    new_section: bool,
    carried: &Carried,
) -> (Vec<String>, Added) {
    let mut lines = block.to_vec();
    let shipped_line = lines.pop().unwrap_or_default();
    let shipped_value = shipped_line.split_once('=').map_or("", |(_, v)| v).trim();
    let older = OLDER.iter().find(|(s, k, _, _)| *s == section && *k == key);
    let carried = carried.iter().find(|(s, k, _, _)| s == section && k == key);
    let (value, why) = match (carried, older) {
        (Some((_, _, value, why)), _) => (value.clone(), Some(why.clone())),
        (None, Some((_, _, value, why))) => (value.to_string(), Some(why.to_string())),
        (None, None) => (shipped_value.to_string(), None),
    };
    lines.push(format!("{key} = {value}"));
    let added = Added {
        section: section.to_string(),
        key: key.to_string(),
        value,
        why,
        new_section,
        retired: false,
    };
    (lines, added)
}

/// The upgraded text, and what was added to it.
pub type Upgraded = (String, Vec<Added>);

/// `text` with every missing setting and section added, and what was added; or the
/// lines that are wrong, (line, why) (an upgrade of a file that cannot be read would
/// guess).
pub fn upgrade(text: &str) -> Result<Upgraded, Vec<(usize, String)>> {
    let layout = scan(text, false);
    if !layout.errors.is_empty() {
        return Err(layout.errors);
    }
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let mut added = Vec::new();
    let carried = retire(&mut lines, &mut added);
    // Where each section's last line of its own is (its last key, or its heading), and
    // which keys it has.
    let mut last_line: Vec<(String, usize)> = Vec::new();
    let mut present: Vec<(String, String)> = Vec::new();
    let mut section = String::new();
    for (i, line) in lines.iter().enumerate() {
        match sort(line) {
            Line::Heading(name) => {
                section = name.clone();
                last_line.push((name, i));
            }
            Line::Key(key) => {
                present.push((section.clone(), key));
                if let Some(last) = last_line.iter_mut().rev().find(|(s, _)| *s == section) {
                    last.1 = i;
                }
            }
            Line::Blank | Line::Comment => {}
        }
    }
    let mut after: Vec<Vec<String>> = vec![Vec::new(); lines.len().max(1)];
    let mut at_end: Vec<String> = Vec::new();
    for s in shipped() {
        let here = last_line.iter().rev().find(|(name, _)| *name == s.name);
        let Some(&(_, last)) = here else {
            at_end.push(String::new());
            at_end.extend(s.intro.iter().cloned());
            at_end.push(format!("[{}]", s.name));
            for (key, block) in &s.keys {
                let (key_lines, one) = key_lines((&s.name, key), block, true, &carried);
                at_end.extend(key_lines);
                added.push(one);
            }
            continue;
        };
        for (key, block) in &s.keys {
            if present.iter().any(|(sec, k)| *sec == s.name && k == key) {
                continue;
            }
            let (key_lines, one) = key_lines((&s.name, key), block, false, &carried);
            after[last].extend(key_lines);
            added.push(one);
        }
    }
    let mut out = String::with_capacity(text.len() + 64 * added.len());
    for (i, line) in lines.iter().enumerate() {
        out.push_str(line);
        out.push('\n');
        for new in &after[i] {
            out.push_str(new);
            out.push('\n');
        }
    }
    if lines.is_empty() {
        after[0]
            .iter()
            .for_each(|l| out.push_str(&format!("{l}\n")));
    }
    for line in at_end {
        out.push_str(&line);
        out.push('\n');
    }
    Ok((out, added))
}

/// Make each retired setting of `lines` a comment that says what took its place, and
/// return the values to carry there.
fn retire(lines: &mut [String], added: &mut Vec<Added>) -> Carried {
    let mut carried = Vec::new();
    let mut section = String::new();
    for line in lines.iter_mut() {
        match sort(line) {
            Line::Heading(name) => section = name,
            Line::Key(key) => {
                let Some(&(_, _, to_section, to_key)) = RETIRED
                    .iter()
                    .find(|(s, k, _, _)| *s == section && *k == key)
                else {
                    continue;
                };
                let value = line
                    .split_once('=')
                    .map_or("", |(_, v)| v)
                    .trim()
                    .to_string();
                let why = format!("from [{section}] {key}, which it replaces");
                carried.push((to_section.into(), to_key.into(), value.clone(), why));
                added.push(Added {
                    why: Some(format!(
                        "no longer a setting: [{to_section}] {to_key} took its place; kept as a comment"
                    )),
                    section: section.clone(),
                    key,
                    value,
                    new_section: false,
                    retired: true,
                });
                *line = format!(
                    "; {} ; retired: [{to_section}] {to_key} took its place",
                    line.trim()
                );
            }
            Line::Blank | Line::Comment => {}
        }
    }
    carried
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn todays_file_needs_nothing() {
        let (text, added) = upgrade(DEFAULT_INI).unwrap();
        assert!(added.is_empty(), "{added:?}");
        assert_eq!(text.lines().count(), DEFAULT_INI.lines().count());
    }

    #[test]
    fn a_missing_key_comes_with_its_comment_at_the_end_of_its_section_and_the_rest_stays() {
        // Today's file without [steer] law, [record] keep_gb, [ros2] frame_prefix and
        // halt_service, and without [test]; a tuned gain kept.
        let mut older = String::new();
        let mut skip = false;
        for line in DEFAULT_INI.lines() {
            if line.trim() == "[test]" {
                skip = true;
            } else if line.trim().starts_with('[') {
                skip = false;
            }
            let dropped = ["law =", "keep_gb =", "frame_prefix =", "halt_service ="];
            if skip || dropped.iter().any(|d| line.trim_start().starts_with(d)) {
                continue;
            }
            older.push_str(&line.replace("kp = ", "kp =  "));
            older.push('\n');
        }
        let (text, added) = upgrade(&older).unwrap();
        let law = added.iter().find(|a| a.key == "law").unwrap();
        assert_eq!(
            law.line(),
            "[steer] law = pursuit (the steering law of every release before [steer] law was a setting)"
        );
        // Records of any size, as before there was a limit in space.
        let keep_gb = added.iter().find(|a| a.key == "keep_gb").unwrap();
        assert_eq!(keep_gb.value, "0", "{keep_gb:?}");
        let upgraded = crate::config::Settings::parse("upgraded", &text, &[]).unwrap();
        assert_eq!(upgraded.record.keep_gb, None);
        // The robot's frames keep their names, as before there was a prefix.
        let prefix = added.iter().find(|a| a.key == "frame_prefix").unwrap();
        assert_eq!((prefix.value.as_str(), prefix.why.is_some()), ("", true));
        assert_eq!(upgraded.ros2.as_ref().unwrap().frame_prefix, "");
        // And ROS may not HALT it, as before there was a HALT service.
        let halt = added.iter().find(|a| a.key == "halt_service").unwrap();
        assert_eq!(halt.value, "no");
        assert!(!upgraded.ros2.as_ref().unwrap().halt_service);
        assert!(added.iter().any(|a| a.section == "test" && a.new_section));
        // Every line of the older file is there, in its order.
        let mut new_lines = text.lines();
        for line in older.lines() {
            assert!(new_lines.any(|l| l == line), "{line} lost or moved");
        }
        let (_, again) = upgrade(&text).unwrap();
        assert!(again.is_empty(), "{again:?}");
    }
}
