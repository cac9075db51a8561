//! Tests of the field tier: the layout a seed gives, the profiles, the correlated error.

use super::*;
use crate::sim::params::RowShape;

fn tier(field: FieldKind, length_m: f64, seed: u64) -> FieldTier {
    let params = SimParams {
        seed,
        field,
        row: RowShape::Straight,
        ..SimParams::default()
    };
    FieldTier::new(&params.sanitized(), length_m)
}

/// Every stretch of `list` as `row_at` reports it: inside at its middle, and each
/// stretch's (length, weed offset).
fn checked(t: &FieldTier, list: &[Stretch], gap: bool) -> Vec<(f64, f64)> {
    list.iter()
        .map(|st| {
            let middle = t.row_at(0.5 * (st.from_m + st.to_m));
            assert!(if gap {
                middle.gap
            } else {
                middle.weed_offset_m == st.offset_m
            });
            (st.to_m - st.from_m, st.offset_m)
        })
        .collect()
}

/// Share of the row, sampled every centimetre, where `row_at` says gap (or weeds).
fn share(t: &FieldTier, length_m: f64, gap: bool) -> f64 {
    let n = (length_m * 100.0) as usize;
    let hits = (0..n)
        .map(|k| t.row_at(k as f64 * 0.01))
        .filter(|at| if gap { at.gap } else { at.weed_offset_m != 0.0 })
        .count();
    hits as f64 / n as f64
}

#[test]
fn a_realistic_row_has_gaps_and_weed_patches_as_often_and_as_long_as_the_tier_says() {
    let length_m = 3000.0;
    let t = tier(FieldKind::Realistic, length_m, 11);
    let gaps = checked(&t, &t.gaps, true);
    // One every 15 m on average plus its own 1.25 m: about 185 in 3 km.
    assert!((150..=220).contains(&gaps.len()), "{} gaps", gaps.len());
    assert!(gaps.iter().all(|g| (0.5..=2.0).contains(&g.0)), "{gaps:?}");
    // About 1.25 m of every 16.25 m is gap.
    let gap_share = share(&t, length_m, true);
    assert!((0.06..=0.095).contains(&gap_share), "gap share {gap_share}");
    let weeds = checked(&t, &t.weeds, false);
    // One every 25 m plus its 1 m: about 115.
    assert!(
        (85..=150).contains(&weeds.len()),
        "{} weed patches",
        weeds.len()
    );
    for (long_m, offset_m) in &weeds {
        assert_eq!(*long_m, 1.0);
        assert!((0.05..=0.10).contains(&offset_m.abs()), "offset {offset_m}");
    }
    assert!(weeds.iter().any(|w| w.1 > 0.0) && weeds.iter().any(|w| w.1 < 0.0));
    // Outside every stretch the row is clean.
    let first = t.gaps[0];
    assert!(!t.row_at(first.from_m - 1e-6).gap && !t.row_at(first.to_m).gap);
}

#[test]
fn the_clean_field_adds_nothing_and_keeps_its_constant_side_slip() {
    let mut t = tier(FieldKind::Clean, 500.0, 11);
    assert!(t.gaps.is_empty() && t.weeds.is_empty());
    assert_eq!(
        (share(&t, 500.0, true), share(&t, 500.0, false)),
        (0.0, 0.0)
    );
    assert_eq!(t.bump_reached(500.0), None);
    for d_m in [0.0, 7.3, 120.0, 480.0] {
        assert_eq!(t.wheel_slip(d_m), 0.0);
        assert_eq!(t.side_slip_rad(d_m), 1f64.to_radians());
    }
}

#[test]
fn slope_and_wheel_slip_wander_within_their_range_without_jumps() {
    let t = tier(FieldKind::Realistic, 300.0, 3);
    let (mut slope_deg, mut slip) = (Vec::new(), Vec::new());
    for k in 0..30_000 {
        let d_m = k as f64 * 0.01;
        slope_deg.push(t.side_slip_rad(d_m).to_degrees());
        slip.push(t.wheel_slip(d_m));
    }
    let range = |v: &[f64]| {
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    let (lo, hi) = range(&slope_deg);
    assert!(
        lo >= 0.0 && hi <= 3.0 && hi - lo > 1.5,
        "slope {lo}..{hi} deg"
    );
    let (lo, hi) = range(&slip);
    assert!(
        lo >= 0.0 && hi <= 0.05 && hi - lo > 0.025,
        "wheel slip {lo}..{hi}"
    );
    // Over 1 cm a level changes by at most pi/2 * range * 0.01 / 10 m.
    let steepest = slope_deg
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .fold(0.0, f64::max);
    assert!(
        steepest < 3.0 * 1.6 * 0.001 + 1e-12,
        "slope jumps {steepest} deg in 1 cm"
    );
}

#[test]
fn bumps_come_every_two_metres_on_average_each_once() {
    let mut t = tier(FieldKind::Realistic, 1000.0, 5);
    let mut kicks_deg = Vec::new();
    let mut d_m = 0.0;
    while d_m < 1000.0 {
        d_m += 0.01;
        while let Some(bump) = t.bump_reached(d_m) {
            assert!(bump.at_m <= d_m);
            kicks_deg.push(bump.heading_rad.to_degrees());
        }
    }
    assert!(
        (430..=570).contains(&kicks_deg.len()),
        "{} bumps",
        kicks_deg.len()
    );
    let sd = (kicks_deg.iter().map(|k| k * k).sum::<f64>() / kicks_deg.len() as f64).sqrt();
    assert!((0.42..=0.58).contains(&sd), "heading kicks s.d. {sd} deg");
}

#[test]
fn the_same_seed_lays_out_the_same_field_and_another_seed_another() {
    let a = tier(FieldKind::Realistic, 200.0, 9).gaps;
    let b = tier(FieldKind::Realistic, 200.0, 9).gaps;
    let c = tier(FieldKind::Realistic, 200.0, 10).gaps;
    assert_eq!(a, b);
    assert_ne!(a, c);
}
