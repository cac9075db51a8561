//! Tests of the row map writer: what is written reads back to the same numbers, the
//! file is replaced whole or not at all, and a map that would not read back is refused.

use proptest::prelude::*;

use super::*;
use crate::gnss::rowmap::map::MapRow;
use crate::gnss::rowmap::read::{parse_map, read_map};

fn two_rows() -> RowMap {
    RowMap {
        rows: vec![
            MapRow {
                name: "1".to_string(),
                points_deg: vec![
                    (48.123_456_789_4, 11.987_654_321_2),
                    (48.123_459_000_6, 11.987_654_400_9),
                    (48.123_461_234_5, 11.987_654_500_1),
                ],
            },
            MapRow {
                name: "north-3".to_string(),
                points_deg: vec![(-33.000_000_001, -70.5), (-33.000_010_001, -70.500_000_2)],
            },
        ],
    }
}

fn assert_same_within_1e9_deg(a: &RowMap, b: &RowMap) {
    assert_eq!(a.rows.len(), b.rows.len());
    for (row_a, row_b) in a.rows.iter().zip(&b.rows) {
        assert_eq!(row_a.name, row_b.name);
        assert_eq!(row_a.points_deg.len(), row_b.points_deg.len());
        for (p, q) in row_a.points_deg.iter().zip(&row_b.points_deg) {
            assert!((p.0 - q.0).abs() <= 1e-9, "latitude {} became {}", p.0, q.0);
            assert!(
                (p.1 - q.1).abs() <= 1e-9,
                "longitude {} became {}",
                p.1,
                q.1
            );
        }
    }
}

#[test]
fn written_map_reads_back_to_the_same_numbers() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("rows.csv");
    let map = two_rows();
    write_map(&path, &map, Some("taught on 2026-11-25 by mechweed teach")).expect("written");
    let back = read_map(&path).expect("reads back");
    assert_same_within_1e9_deg(&map, &back);
}

#[test]
fn the_file_says_what_it_is_then_the_callers_comment_then_the_header() {
    let text = map_text(
        "rows.csv",
        &two_rows(),
        Some("taught on 2026-11-25\nfield 7"),
    )
    .expect("text");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], format!("# {FILE_COMMENT}"));
    assert_eq!(lines[1], "# taught on 2026-11-25");
    assert_eq!(lines[2], "# field 7");
    assert_eq!(lines[3], "row,lat_deg,lon_deg");
    assert_eq!(lines[4], "1,48.123456789,11.987654321");
    assert_eq!(lines[8], "north-3,-33.000010001,-70.500000200");
    assert!(
        !FILE_COMMENT.contains(','),
        "a spreadsheet would split the comment"
    );
}

#[test]
fn writing_replaces_the_old_file_and_leaves_no_temporary_file() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("rows.csv");
    std::fs::write(&path, "old contents").expect("an old file");
    write_map(&path, &two_rows(), None).expect("written");
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .expect("the folder lists")
        .map(|entry| {
            entry
                .expect("an entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    assert_eq!(names, ["rows.csv"]);
    assert_eq!(read_map(&path).expect("the new map").rows.len(), 2);
}

#[test]
fn a_map_that_would_not_read_back_is_refused_and_the_old_file_kept() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("rows.csv");
    std::fs::write(&path, "old contents").expect("an old file");
    let mut map = two_rows();
    map.rows[1].name = "1".to_string();
    map.rows.push(MapRow {
        name: "a,b".to_string(),
        points_deg: vec![(48.0, 11.0)],
    });
    // 0.4e-9 degree apart: distinct in memory, the same once written with 9 decimals.
    map.rows.push(MapRow {
        name: "close".to_string(),
        points_deg: vec![(48.0, 11.0), (48.000_000_000_4, 11.0), (48.00001, 11.0)],
    });
    let file = path.display().to_string();
    let error = write_map(&path, &map, None).expect_err("four mistakes");
    assert_eq!(
        error.to_string(),
        [
            format!(
                "{file}: row 2 of the map: the name '1' is already row 1's: every row needs \
                 its own name"
            ),
            format!("{file}: row 3 of the map: row name 'a,b' contains a comma"),
            format!("{file} row 'a,b' point 1: row 'a,b' has only 1 point: a row needs at least 2"),
            format!(
                "{file} row 'close' point 2: this point of row 'close' is 0.00 mm from the \
                 point before it (point 1): a repeated line?"
            ),
        ]
        .join("\n")
    );
    assert_eq!(
        std::fs::read_to_string(&path).expect("kept"),
        "old contents"
    );
}

#[test]
fn an_empty_map_is_refused() {
    let error = map_text("rows.csv", &RowMap::default(), None).expect_err("no rows");
    assert_eq!(error.to_string(), "rows.csv: the map has no rows to write");
}

#[test]
fn a_missing_folder_is_named() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("no-such-folder").join("rows.csv");
    let text = write_map(&path, &two_rows(), None)
        .expect_err("no folder")
        .to_string();
    assert!(
        text.starts_with(&format!(
            "{}: cannot create a temporary file beside it: ",
            path.display()
        )),
        "{text}"
    );
}

/// A row as a random walk of steps 0.1 to 20 m turning at most 60 degrees at a point.
fn walked_row() -> impl Strategy<Value = Vec<(f64, f64)>> {
    (
        -60.0..60.0f64,
        -179.0..179.0f64,
        -3.2..3.2f64,
        proptest::collection::vec((0.1..20.0f64, -1.0..1.0f64), 1..30),
    )
        .prop_map(|(lat0_deg, lon0_deg, heading0_rad, steps)| {
            let m_per_deg_lat = 111_000.0;
            let m_per_deg_lon = m_per_deg_lat * lat0_deg.to_radians().cos();
            let (mut east_m, mut north_m, mut heading_rad) = (0.0, 0.0, heading0_rad);
            let mut points = vec![(lat0_deg, lon0_deg)];
            for (step_m, turn_rad) in steps {
                heading_rad += turn_rad;
                east_m += step_m * f64::cos(heading_rad);
                north_m += step_m * f64::sin(heading_rad);
                points.push((
                    lat0_deg + north_m / m_per_deg_lat,
                    lon0_deg + east_m / m_per_deg_lon,
                ));
            }
            points
        })
}

proptest! {
    #[test]
    fn any_good_row_reads_back_within_1e9_degree(points_deg in walked_row()) {
        let map = RowMap { rows: vec![MapRow { name: "walk".to_string(), points_deg }] };
        let text = map_text("walk.csv", &map, None).expect("a good row writes");
        let back = parse_map("walk.csv", &text).expect("and reads back");
        assert_same_within_1e9_deg(&map, &back);
    }
}
