//! Tests of the row map reader: good files as people and spreadsheets write them, every
//! kind of error by its exact line and words, all of them from one file, and a fuzz
//! test that no text makes it panic.

use proptest::prelude::*;

use super::*;

fn messages(text: &str) -> Vec<String> {
    match parse_map("rows.csv", text) {
        Ok(map) => panic!("expected errors, read {map:?}"),
        Err(errors) => errors.errors.iter().map(ToString::to_string).collect(),
    }
}

#[test]
fn reads_rows_in_file_order_with_comments_and_blank_lines() {
    let text = "# field 7\n\nrow,lat_deg,lon_deg\n\
                1,48.000000000,11.000000000\n  # a comment inside\n\
                1,48.000010000,11.000000000\n\n\
                north-3,48.000000000,11.000010000\n\
                north-3,48.000010000,11.000010000\n\
                north-3,48.000020000,11.000010000\n";
    let map = parse_map("rows.csv", text).expect("a good file");
    assert_eq!(map.rows.len(), 2);
    assert_eq!(map.rows[0].name, "1");
    assert_eq!(map.rows[0].points_deg, vec![(48.0, 11.0), (48.00001, 11.0)]);
    let north = map.row("north-3").expect("the second row by name");
    assert_eq!(north.points_deg.len(), 3);
    assert_eq!(north.points_deg[2], (48.00002, 11.00001));
}

#[test]
fn reads_a_spreadsheet_export_with_bom_crlf_quotes_padding_and_notes() {
    let text = "\u{feff}\"row\",\"lat_deg\",\"lon_deg\",\"note\"\r\n\
                \"1\",\"48.0\",\"11.0\",\"start, by the gate\"\r\n\
                \"1\", 48.00001 ,\"11.0\",\r\n\
                ,,,\r\n\
                \"2\",48.0,11.00001,\"he said \"\"here\"\"\"\r\n\
                \"2\",48.00001,11.00001,\r\n";
    let map = parse_map("rows.csv", text).expect("a spreadsheet's file");
    assert_eq!(map.rows.len(), 2);
    assert_eq!(map.rows[0].points_deg, vec![(48.0, 11.0), (48.00001, 11.0)]);
    assert_eq!(map.rows[1].name, "2");
    assert_eq!(map.rows[1].points_deg[1], (48.00001, 11.00001));
}

#[test]
fn counts_lines_for_lone_cr_line_ends_as_an_editor_does() {
    let text = "row,lat_deg,lon_deg\r1,48.0,11.0\r1,48.0x,11.0\r";
    assert_eq!(
        messages(text),
        ["rows.csv line 3: latitude '48.0x' is not a number"]
    );
}

#[test]
fn reports_every_kind_of_error_of_one_file_by_line() {
    let text = "\
# one of every mistake
row,lat,lon
a,48.00000,11.0
a,48.00001,11.0,5
a,48.00002,11.0x
b,NaN,11.0
b,48.0,inf
b,91.0,11.0
b,48.0,-181.5
c,48.1,11.1
d,48.2,11.2
d,48.2,11.2
e,48.3,11.3
e,48.3,11.31
f,48.40000,11.4
f,48.40001,11.4
f,48.40000,11.4
g,48.50000,11.5
h,48.60000,11.6
h,48.60001,11.6
g,48.50001,11.5
g,48.50002,11.5
\"#7\",48.7,11.7
\"i,48.8,11.8
";
    let expected = [
        "rows.csv line 2: the header must be 'row,lat_deg,lon_deg' (or \
         'row,lat_deg,lon_deg,note'), found 'row,lat,lon'",
        "rows.csv line 4: expected 3 fields (row,lat_deg,lon_deg), found 4: numbers must \
         use '.', not ',', as the decimal point",
        "rows.csv line 5: longitude '11.0x' is not a number",
        "rows.csv line 6: latitude 'NaN' is not a finite number",
        "rows.csv line 7: longitude 'inf' is not a finite number",
        "rows.csv line 8: latitude 91.0 is outside -90..90",
        "rows.csv line 9: longitude -181.5 is outside -180..180",
        "rows.csv line 10: row 'c' has only 1 point: a row needs at least 2",
        "rows.csv line 12: this point of row 'd' is 0.00 mm from the point before it \
         (line 11): a repeated line?",
        "rows.csv line 14: this point of row 'e' is 741.9 m from the point before it \
         (line 13), more than 100 m: a typo in a digit?",
        "rows.csv line 16: row 'f' turns by 180 degrees at this point (between line 15 \
         and line 17), more than 90: a point out of order?",
        "rows.csv line 21: row 'g' comes back after row 'h': a row's points must be on \
         consecutive lines (row 'g' is on line 18)",
        "rows.csv line 23: row name '#7' starts with '#', which would make its lines \
         comments",
        "rows.csv line 24: the quote that opens field 1 is not closed",
    ];
    assert_eq!(messages(text), expected);
}

#[test]
fn the_reported_distance_is_the_distance_on_the_ground() {
    // 0.01 degree of longitude at 48.3 degrees north, from the WGS-84 parallel's
    // radius a cos(lat) / sqrt(1 - e^2 sin^2 lat): 741.9 m, as the message above says.
    let (a_m, e2) = (6_378_137.0_f64, 0.006_694_379_990_14_f64);
    let lat_rad = 48.3_f64.to_radians();
    let radius_m = a_m * lat_rad.cos() / (1.0 - e2 * lat_rad.sin().powi(2)).sqrt();
    let distance_m = radius_m * 0.01_f64.to_radians();
    assert!((distance_m - 741.9).abs() < 0.05, "{distance_m}");
}

#[test]
fn refuses_a_file_without_a_header_or_rows() {
    assert_eq!(
        messages("# nothing yet\n\n"),
        ["rows.csv: is empty: a row map starts with the header line 'row,lat_deg,lon_deg'"]
    );
    assert_eq!(
        messages("row,lat_deg,lon_deg\n# no points\n"),
        [
            "rows.csv: has no rows: after the header, one line per point \
             ('row,lat_deg,lon_deg')"
        ]
    );
    assert_eq!(
        messages("1,48.0,11.0\n1,48.00001,11.0\n"),
        [
            "rows.csv line 1: the header must be 'row,lat_deg,lon_deg' (or \
             'row,lat_deg,lon_deg,note'), found '1,48.0,11.0'"
        ]
    );
}

#[test]
fn says_when_a_spreadsheet_used_semicolons() {
    let text = "row;lat_deg;lon_deg\n1;48,0;11,0\n";
    let got = messages(text);
    assert!(
        got[0].ends_with(
            "the fields are separated by ';': save with ',' between fields and '.' as \
             the decimal point"
        ),
        "{got:?}"
    );
}

#[test]
fn lists_twenty_errors_and_counts_the_rest() {
    let mut text = String::from("row,lat_deg,lon_deg\n");
    for _ in 0..30 {
        text.push_str("1,x,11.0\n");
    }
    let errors = parse_map("rows.csv", &text).expect_err("30 bad lines");
    assert_eq!(errors.errors.len(), 20);
    assert_eq!(errors.more, 10);
    let shown = errors.to_string();
    assert!(shown.starts_with("rows.csv line 2: latitude 'x' is not a number\n"));
    assert!(shown.ends_with("rows.csv line 21: latitude 'x' is not a number\nand 10 more errors"));
}

#[test]
fn names_the_line_that_is_not_utf8() {
    let bytes = b"row,lat_deg,lon_deg\r\n1,48.0,11.0\r\nk\xf6ln,48.0,11.0\r\n";
    let errors = parse_map_bytes("rows.csv", bytes).expect_err("Latin-1 text");
    assert_eq!(
        errors.to_string(),
        "rows.csv line 3: this line is not UTF-8 text: save the file as 'CSV UTF-8'"
    );
}

#[test]
fn read_map_names_a_missing_file() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("none.csv");
    let error = read_map(&path).expect_err("no such file");
    let text = error.to_string();
    assert!(
        text.starts_with(&format!("{}: cannot read the row map: ", path.display())),
        "{text}"
    );
}

/// Lines that look like a row map's, mostly right and sometimes slightly wrong, so that
/// some files are accepted and the rest fail in many ways.
fn plausible_line() -> impl Strategy<Value = String> {
    let name = prop_oneof![
        6 => Just("1"),
        3 => Just("2"),
        1 => Just("\"3\""),
        1 => Just(""),
        1 => Just("#"),
    ];
    let number = prop_oneof![
        20 => (47.99999..48.00002f64).prop_map(|v| format!("{v:.9}")),
        1 => (-91.0..91.0f64).prop_map(|v| v.to_string()),
        1 => Just("NaN".to_string()),
        1 => Just("1e400".to_string()),
        1 => "[0-9.x\"-]{0,6}",
    ];
    prop_oneof![
        12 => (name, number.clone(), number).prop_map(|(n, a, b)| format!("{n},{a},{b}")),
        1 => Just("row,lat_deg,lon_deg".to_string()),
        1 => Just("# comment".to_string()),
        1 => "[,\" \r\n#a-z0-9]{0,12}",
    ]
}

proptest! {
    #[test]
    fn arbitrary_text_never_panics_the_reader(text in any::<String>()) {
        if let Ok(map) = parse_map("fuzz.csv", &text) {
            prop_assert!(map.rows.iter().all(|row| row.points_deg.len() >= 2));
        }
    }

    #[test]
    fn arbitrary_bytes_never_panic_the_reader(bytes in proptest::collection::vec(any::<u8>(), 0..200)) {
        let _ = parse_map_bytes("fuzz.csv", &bytes);
    }

    #[test]
    fn any_accepted_map_has_rows_of_two_points_or_more(
        lines in proptest::collection::vec(plausible_line(), 0..6)
    ) {
        let text = format!("row,lat_deg,lon_deg\n{}", lines.join("\n"));
        if let Ok(map) = parse_map("fuzz.csv", &text) {
            prop_assert!(!map.rows.is_empty());
            prop_assert!(map.rows.iter().all(|row| row.points_deg.len() >= 2));
        }
    }
}

#[test]
fn the_example_in_the_format_documentation_reads() {
    let source = include_str!("format.rs");
    let example: Vec<&str> = source
        .lines()
        .skip_while(|line| *line != "//! ```text")
        .skip(1)
        .take_while(|line| *line != "//! ```")
        .map(|line| line.trim_start_matches("//!").trim_start())
        .collect();
    let map = parse_map("example.csv", &example.join("\n")).expect("the example is good");
    let names: Vec<&str> = map.rows.iter().map(|row| row.name.as_str()).collect();
    assert_eq!(names, ["1", "north-3"]);
}
