//! Tests of teaching a row: the spacing of kept points, stretches without a trusted
//! fix refused by where they are, reversing refused, and rows too short or badly named.

use super::*;
use crate::gnss::rowmap::test_rows::field_frame;
use mechweed_hw::geo::Enu;

/// The odometer does not start at zero: distances in errors count from the first sample.
const ODOMETER_START_M: f64 = 100.0;

/// A sample `along_m` metres up a row running north, with the odometer agreeing.
fn sample(along_m: f64, fix_quality: u8) -> TeachSample {
    let g = field_frame().to_geodetic(Enu {
        east_m: 0.0,
        north_m: along_m,
        up_m: 0.0,
    });
    TeachSample {
        lat_deg: g.lat_deg,
        lon_deg: g.lon_deg,
        fix_quality,
        distance_m: ODOMETER_START_M + along_m,
    }
}

/// Drives from 0 to `length_m` with a sample every `step_m`, the fix quality by place.
fn drive(
    teacher: &mut Teacher,
    length_m: f64,
    step_m: f64,
    quality: impl Fn(f64) -> u8,
) -> Result<(), TeachError> {
    let steps = (length_m / step_m).round() as u32;
    for k in 0..=steps {
        let along_m = f64::from(k) * step_m;
        teacher.feed(sample(along_m, quality(along_m)))?;
    }
    Ok(())
}

fn teacher() -> Teacher {
    Teacher::new(TeachSettings::default()).expect("default settings")
}

#[test]
fn keeps_a_point_every_spacing_of_travel_to_the_end() {
    let mut t = teacher();
    drive(&mut t, 10.0, 0.05, |_| RTK_FIXED).expect("all fixed");
    let row = t.finish("1").expect("a good row");
    assert_eq!(row.name, "1");
    assert_eq!(row.points_deg.len(), 41, "0, 0.25, ..., 10 m");
    let frame = field_frame();
    for (k, &(lat_deg, lon_deg)) in row.points_deg.iter().enumerate() {
        let enu = frame.to_enu(mechweed_hw::geo::Geodetic {
            lat_deg,
            lon_deg,
            height_m: 500.0,
        });
        assert!(
            (enu.north_m - k as f64 * 0.25).abs() < 1e-6,
            "point {k}: {}",
            enu.north_m
        );
    }
}

#[test]
fn with_coarse_samples_each_point_is_the_first_sample_past_its_place() {
    let settings = TeachSettings {
        spacing_m: 0.5,
        ..TeachSettings::default()
    };
    let mut t = Teacher::new(settings).expect("good settings");
    drive(&mut t, 12.0, 0.12, |_| RTK_FIXED).expect("all fixed");
    assert_eq!(t.points_at_m.len(), 25, "0, 0.5, ..., 12 m");
    for (k, &at_m) in t.points_at_m.iter().enumerate() {
        let place_m = k as f64 * 0.5;
        assert!(
            (place_m - 1e-6..place_m + 0.12).contains(&at_m),
            "point {k} at {at_m}"
        );
    }
    assert_eq!(t.point_count(), 25);
}

#[test]
fn a_two_metre_float_stretch_is_refused_naming_where() {
    let mut t = teacher();
    let float_between = |along_m: f64| {
        if along_m > 4.05 && along_m < 6.05 {
            RTK_FLOAT
        } else {
            RTK_FIXED
        }
    };
    let error = drive(&mut t, 10.0, 0.1, float_between).expect_err("refused");
    let said = "no RTK fixed position from 4.0 m to 6.1 m of the row: drive it again";
    assert_eq!(error.to_string(), said);
    // Told at once, then again for every sample and at the end.
    assert_eq!(
        t.feed(sample(6.2, RTK_FIXED)).map_err(|e| e.to_string()),
        Err(said.to_string())
    );
    assert_eq!(
        t.finish("1").map_err(|e| e.to_string()),
        Err(said.to_string())
    );
}

#[test]
fn a_short_float_stretch_is_bridged_without_points_in_it() {
    let mut t = teacher();
    let float_between = |along_m: f64| {
        if (4.05..4.85).contains(&along_m) {
            RTK_FLOAT
        } else {
            RTK_FIXED
        }
    };
    drive(&mut t, 10.0, 0.1, float_between).expect("0.9 m without a fix is allowed");
    assert!(
        t.points_at_m
            .iter()
            .all(|&at_m| !(4.05..4.85).contains(&at_m))
    );
    assert!(t.finish("1").is_ok());
}

#[test]
fn float_is_good_enough_when_the_caller_trusts_it_and_the_message_says_what_is() {
    let settings = TeachSettings {
        trusted_fix: [RTK_FIXED, RTK_FLOAT].into(),
        ..TeachSettings::default()
    };
    let mut t = Teacher::new(settings).expect("good settings");
    let quality = |along_m: f64| match along_m {
        a if a < 3.0 => RTK_FLOAT,
        a if a < 5.95 => RTK_FIXED,
        _ => 1,
    };
    // The stretch at the end is judged when the row is finished.
    drive(&mut t, 8.0, 0.1, quality).expect("no trusted fix came back to end a stretch");
    assert!((t.untrusted_m() - 2.1).abs() < 1e-9, "for a live warning");
    assert_eq!(
        t.finish("1").expect_err("refused").to_string(),
        "no RTK fixed or RTK float position from 5.9 m to 8.0 m of the row: drive it again"
    );
}

#[test]
fn reversing_is_refused_but_odometry_jitter_is_not() {
    let mut t = teacher();
    drive(&mut t, 5.0, 0.1, |_| RTK_FIXED).expect("forward");
    t.feed(sample(4.99, RTK_FIXED))
        .expect("a centimetre of jitter while standing");
    let error = t.feed(sample(4.5, RTK_FIXED)).expect_err("went back");
    assert_eq!(
        error.to_string(),
        "the machine went back from 5.00 m to 4.50 m of the row: a row is taught driving \
         forward in one go: drive it again"
    );
    assert_eq!(t.finish("1"), Err(error));
}

#[test]
fn a_row_too_short_or_never_fixed_is_refused() {
    let mut t = teacher();
    drive(&mut t, 1.5, 0.05, |_| RTK_FIXED).expect("fixed");
    assert_eq!(
        t.finish("1").expect_err("too short").to_string(),
        "the taught row is 1.50 m long, shorter than 2 m: drive it again"
    );
    let mut t = teacher();
    drive(&mut t, 0.8, 0.05, |_| 2).expect("a stretch short of max_gap_m");
    assert_eq!(t.finish("1"), Err(TeachError::TooFewPoints { count: 0 }));
    let mut t = teacher();
    drive(&mut t, 3.0, 0.05, |_| 2).expect("judged at the end");
    assert_eq!(
        t.finish("1").expect_err("never fixed").to_string(),
        "no RTK fixed position from 0.0 m to 3.0 m of the row: drive it again"
    );
    assert_eq!(
        teacher().finish("1"),
        Err(TeachError::TooFewPoints { count: 0 })
    );
}

#[test]
fn the_row_name_must_do_for_the_map_file() {
    let mut t = teacher();
    drive(&mut t, 3.0, 0.05, |_| RTK_FIXED).expect("fixed");
    assert_eq!(
        t.finish("a,b").expect_err("a comma").to_string(),
        "row name 'a,b' contains a comma"
    );
}

#[test]
fn a_distance_that_is_not_a_number_is_refused() {
    let mut t = teacher();
    drive(&mut t, 2.0, 0.1, |_| RTK_FIXED).expect("fixed");
    let mut bad = sample(2.1, RTK_FIXED);
    bad.distance_m = f64::NAN;
    assert_eq!(
        t.feed(bad).expect_err("NaN").to_string(),
        "the distance driven is not a number after 2.00 m of the row"
    );
}

#[test]
fn settings_that_cannot_work_are_refused() {
    let with = |change: fn(&mut TeachSettings)| {
        let mut settings = TeachSettings::default();
        change(&mut settings);
        Teacher::new(settings)
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    assert_eq!(
        with(|s| s.spacing_m = 0.0),
        Err("teach setting spacing_m = 0: must be more than 0 and at most 100 m".to_string())
    );
    assert_eq!(
        with(|s| s.max_gap_m = f64::NAN),
        Err("teach setting max_gap_m = NaN: must be a number more than 0".to_string())
    );
    assert_eq!(
        with(|s| s.trusted_fix = [4, 9].into()),
        Err("teach setting trusted_fix = {4, 9}: GGA fix qualities are 0 to 8".to_string())
    );
    assert_eq!(
        with(|s| s.trusted_fix.clear()),
        Err("teach setting trusted_fix = {}: must name at least one fix quality".to_string())
    );
}

#[test]
fn a_taught_row_is_written_and_read_back() {
    let mut t = teacher();
    drive(&mut t, 6.0, 0.02, |_| RTK_FIXED).expect("fixed");
    let map = crate::gnss::rowmap::map::RowMap {
        rows: vec![t.finish("north-3").expect("a good row")],
    };
    let text = crate::gnss::rowmap::write::map_text("rows.csv", &map, Some("taught by a test"))
        .expect("text");
    let back = crate::gnss::rowmap::read::parse_map("rows.csv", &text).expect("reads back");
    assert_eq!(back.rows[0].points_deg.len(), 25);
}

#[test]
fn the_row_ends_at_the_last_fixed_position_not_a_spacing_short_of_it() {
    let mut t = teacher();
    drive(&mut t, 10.15, 0.05, |_| RTK_FIXED).expect("fixed");
    let row = t.finish("1").expect("a good row");
    assert_eq!(row.points_deg.len(), 42, "0, 0.25, ..., 10 m and 10.15 m");
    let last = row.points_deg.last().copied().expect("points");
    let end = sample(10.15, RTK_FIXED);
    assert!((last.0 - end.lat_deg).abs() < 1e-12 && (last.1 - end.lon_deg).abs() < 1e-12);
}
