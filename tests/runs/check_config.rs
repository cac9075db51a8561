//! `mechweed check-config FILE` on broken settings files: each is refused (exit 1) with
//! an error naming the file, the line, the key and, in plain words, what is wrong. This
//! file: the shape of the file (sections, lines, Windows files).

use crate::config_file;

use std::path::Path;

use config_file::{File, SHIPPED, assert_refused, check, line_of, with};

#[test]
fn the_shipped_file_passes() {
    let (code, errors) = check(Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/config/robot.ini"
    )));
    assert_eq!((code, errors), (Some(0), Vec::<String>::new()));
}

// Item 2: a repeated section was silently dropped by rust-ini.

#[test]
fn a_repeated_section_is_refused_naming_both_lines() {
    let text = format!("{SHIPPED}\n[faults]\nbattery_min_v = 23\n");
    let at = SHIPPED.lines().count();
    let first = SHIPPED.lines().position(|l| l == "[faults]").unwrap() + 1;
    let key = line_of(SHIPPED, "faults", "battery_min_v");
    assert_refused(
        &text,
        &[
            (
                at + 2,
                &format!(
                    "[faults] appears again (first at line {first}): put its keys in one section"
                ),
            ),
            (
                at + 3,
                &format!(
                    "[faults] battery_min_v is set more than once (first at line {key}): keep one"
                ),
            ),
        ],
    );
}

#[test]
fn a_repeated_key_is_refused_naming_both_lines() {
    let n = line_of(SHIPPED, "sim", "seed");
    let text = SHIPPED.replacen("\nseed = 1\n", "\nseed = 1\nseed = 2\n", 1);
    assert_refused(
        &text,
        &[(
            n + 1,
            &format!("[sim] seed is set more than once (first at line {n}): keep one"),
        )],
    );
}

// Item 3: a line that is not ini was reported a line too far down, in parser words.

#[test]
fn a_line_that_is_not_ini_is_named_by_its_own_line() {
    let at_end = format!("{SHIPPED}this line is not ini\n");
    let what = "`this line is not ini` is neither [section] nor key = value";
    assert_refused(&at_end, &[(SHIPPED.lines().count() + 1, what)]);

    // In the middle, rust-ini joined it to the next line's key.
    let n = line_of(SHIPPED, "steer", "lookahead_m");
    let mut lines: Vec<&str> = SHIPPED.lines().collect();
    lines.insert(n - 1, "this line is not ini");
    assert_refused(&(lines.join("\n") + "\n"), &[(n, what)]);
}

#[test]
fn a_key_before_any_section_and_a_broken_heading_are_named() {
    assert_refused(
        &format!("speed_mps = 0.5\n{SHIPPED}"),
        &[(
            1,
            "`speed_mps = 0.5` stands before any [section]: move it into its section",
        )],
    );
    // The keys below a broken heading are not taken for the section above it.
    let n = SHIPPED.lines().position(|l| l == "[record]").unwrap() + 1;
    let file = File::new(SHIPPED.replacen("[record]", "[record", 1));
    let (code, errors) = check(&file.path);
    assert_eq!(code, Some(1));
    assert_eq!(
        errors,
        vec![
            file.error(
                n,
                "`[record` starts a [section] heading but does not end with ]"
            ),
            format!("{}: missing section [record]", file.path.display()),
        ]
    );
}

// Item 4: Windows files: a byte-order mark, CR-LF line ends, or both.

#[test]
fn windows_files_with_a_byte_order_mark_and_crlf_pass() {
    let crlf = SHIPPED.replace('\n', "\r\n");
    for text in [
        format!("\u{feff}{SHIPPED}"),
        crlf.clone(),
        format!("\u{feff}{crlf}"),
    ] {
        let file = File::new(&text);
        assert_eq!(
            check(&file.path),
            (Some(0), Vec::new()),
            "{:?}",
            &text[..20]
        );
    }
    // And their errors still name the right line.
    let n = line_of(SHIPPED, "pid.steer", "kd");
    let broken =
        format!("\u{feff}{}", with(SHIPPED, "pid.steer", "kd", "abc")).replace('\n', "\r\n");
    assert_refused(&broken, &[(n, "[pid.steer] kd = 'abc' is not a number")]);
}

#[test]
fn a_file_that_is_not_utf8_is_named_by_line() {
    let n = line_of(SHIPPED, "record", "folder");
    let mut bytes = SHIPPED.as_bytes().to_vec();
    let at = SHIPPED.find("folder = records").unwrap() + "folder = ".len();
    bytes[at] = 0xE9; // 'é' in Latin-1
    let file = File::new(bytes);
    let (code, errors) = check(&file.path);
    assert_eq!(code, Some(1));
    assert_eq!(
        errors,
        vec![file.error(n, "is not UTF-8 text: save the file as UTF-8 (plain text)")]
    );
}
