use super::*;

#[path = "filter_sim.rs"]
mod sim;
use sim::{EVERY, STEP_M, Sim};

#[path = "filter_gate_tests.rs"]
mod gate_tests;

/// A row state from its parts in the filter's order.
fn row(offset_m: f64, heading_rad: f64, curvature_per_m: f64, map_bias_m: f64) -> RowState {
    let slip_rad = 0.0;
    RowState {
        offset_m,
        heading_rad,
        curvature_per_m,
        map_bias_m,
        slip_rad,
        camera_bias_m: 0.0,
    }
}

fn close(got: f64, want: f64, tolerance: f64) -> bool {
    (got - want).abs() <= tolerance
}

#[test]
fn hand_worked_predict_then_camera() {
    // Settings: 0.01 per √m on offset, heading, curvature (q = 1e-4 per m), 0.002 on
    // map_bias (4e-6), slip off. On (a, b, c) = (offset, heading, curvature):
    // x0 = (0.02, 0.01, 0.02), map_bias 0.005; P0 = diag(1e-4, 4e-4, 1e-4), map_bias 1e-4.
    // predict(ds = 0.5, dθ = 0.04): F = [1 0.5 0.125; 0 1 0.5; 0 0 1], map_bias alone.
    //   a⁻ = 0.02 + 0.01·0.5 + 0.02·0.125 - 0.04·0.5/2 = 0.0175
    //   b⁻ = 0.01 + 0.02·0.5 - 0.04 = -0.02,  c⁻ = 0.02,  map_bias⁻ = 0.005
    //   F P0 = [1e-4 2e-4 1.25e-5; 0 4e-4 5e-5; 0 0 1e-4]
    //   F P0 Fᵀ = [2.015625e-4 2.0625e-4 1.25e-5; . 4.25e-4 5e-5; . . 1e-4]
    //     ([0,0] = 1e-4 + 0.5·2e-4 + 0.125·1.25e-5, [1,1] = 4e-4 + 0.5·5e-5)
    //   P⁻ = F P0 Fᵀ + 0.5 Q = [2.515625e-4 2.0625e-4 1.25e-5; . 4.75e-4 5e-5; . . 1.5e-4],
    //     map_bias 1e-4 + 0.5·4e-6 = 1.02e-4
    // update_camera(z = (0.03, 0.02), x_c = 0.8, s.d. 0.01 m and 0.01 rad, since capture
    // s = 0.3 m, t = 0.02 rad): the present row at x_c - s = 0.5, H = [1 0.5 0.125; 0 1 0.5]
    //   h = (a⁻ + 0.5 b⁻ + 0.125 c⁻ + t (x_c - s/2), b⁻ + 0.5 c⁻ + t)
    //     = (0.0175 - 0.01 + 0.0025 + 0.013, -0.02 + 0.01 + 0.02) = (0.023, 0.01)
    //   y = z - h = (0.007, 0.01)
    //   Q_s = 0.3 Q = diag(3e-5, 3e-5, 3e-5), the noise since capture
    //   P⁻ - Q_s = [2.215625e-4 2.0625e-4 1.25e-5; . 4.45e-4 5e-5; . . 1.2e-4]
    //   (P⁻ - Q_s) Hᵀ = [3.2625e-4 2.125e-4; 4.35e-4 4.7e-4; 5.25e-5 1.1e-4]
    //   S = H (P⁻ - Q_s) Hᵀ + R = [5.503125e-4 + 1e-4, 4.6125e-4; ., 5.25e-4 + 1e-4]
    //   det S = 6.503125e-4·6.25e-4 - 4.6125e-4² = 1.9369375e-7
    //   S⁻¹ = [6.25e-4 -4.6125e-4; -4.6125e-4 6.503125e-4] / det S
    //   NIS = (6.25e-4·0.007² - 2·4.6125e-4·0.007·0.01 + 6.503125e-4·0.01²) / det S
    //       = 3.108125e-8 / 1.9369375e-7 = 4973/30991 = 0.16046594 (gate 13.816: used)
    //   K = (P⁻ - Q_s) Hᵀ S⁻¹ = [0.546691 -0.063458; 0.284405 0.542109; -0.092543 0.244297]
    //   x⁺ = x⁻ + K y = (2565095, -1560468, 2701816) / 123964000, map_bias unchanged
    //   P⁺ = P⁻ - K S Kᵀ
    //      = [4298545 -86048 -457224; . 4784640 -1217984; . . 6346256] / 49585600000
    let mut s = FilterSettings::default();
    (s.offset_sd_per_sqrt_m, s.heading_sd_per_sqrt_m) = (0.01, 0.01);
    (s.curvature_sd_per_sqrt_m, s.map_bias_sd_per_sqrt_m) = (0.01, 0.002);
    s.slip_sd_per_sqrt_m = 0.0;
    let mut f = RowFilter::new(s);
    let (x0, sd0) = (row(0.02, 0.01, 0.02, 0.005), row(0.01, 0.02, 0.01, 0.01));
    assert_eq!(f.reset(x0, sd0), Outcome::Used);

    assert_eq!(f.predict(0.5, 0.04), Outcome::Used);
    let (x, p) = (f.state().to_vector(), f.covariance());
    for (i, want) in [0.0175, -0.02, 0.02, 0.005, 0.0].into_iter().enumerate() {
        assert!(close(x[i], want, 1e-9), "x⁻[{i}] = {}", x[i]);
    }
    let p_minus = [
        [2.515625e-4, 2.0625e-4, 1.25e-5],
        [2.0625e-4, 4.75e-4, 5e-5],
        [1.25e-5, 5e-5, 1.5e-4],
    ];
    for (i, row) in p_minus.iter().enumerate() {
        for (j, &want) in row.iter().enumerate() {
            assert!(close(p[(i, j)], want, 1e-13), "P⁻[{i},{j}] = {}", p[(i, j)]);
        }
    }
    assert!(close(p[(MAP_BIAS, MAP_BIAS)], 1.02e-4, 1e-13));

    let since = Travel {
        travelled_m: 0.3,
        turned_rad: 0.02,
    };
    assert_eq!(
        f.update_camera(0.03, 0.02, 0.8, 0.01, 0.01, since),
        Outcome::Used
    );
    assert!(close(f.last_camera_nis().unwrap(), 4973.0 / 30991.0, 1e-9));
    let (x, p) = (f.state().to_vector(), f.covariance());
    let x_plus = [2565095.0, -1560468.0, 2701816.0].map(|n| n / 123964000.0);
    for (i, &want) in x_plus.iter().chain(&[0.005, 0.0]).enumerate() {
        assert!(close(x[i], want, 1e-9), "x⁺[{i}] = {} want {want}", x[i]);
    }
    let p_plus = [
        [4298545.0, -86048.0, -457224.0],
        [-86048.0, 4784640.0, -1217984.0],
        [-457224.0, -1217984.0, 6346256.0],
    ]
    .map(|row| row.map(|n| n / 49585600000.0));
    // Covariances are of order 1e-4: 1e-9 of that scale.
    for (i, row) in p_plus.iter().enumerate() {
        for (j, &want) in row.iter().enumerate() {
            assert!(close(p[(i, j)], want, 1e-13), "P⁺[{i},{j}] = {}", p[(i, j)]);
        }
    }
    assert!(close(p[(MAP_BIAS, MAP_BIAS)], 1.02e-4, 1e-13));
    assert!(
        p.row(SLIP)
            .iter()
            .chain(p.column(SLIP).iter())
            .all(|&v| v == 0.0)
    );
    assert_eq!((p[(OFFSET, MAP_BIAS)], p[(HEADING, MAP_BIAS)]), (0.0, 0.0));
}

/// Chi-square quantile by Wilson and Hilferty (1931): k (1 - 2/(9k) + z √(2/(9k)))³,
/// z the standard normal quantile; within 0.1 % for k in the thousands.
fn chi_square_quantile(k: f64, z: f64) -> f64 {
    let v = 2.0 / (9.0 * k);
    k * (1.0 - v + z * v.sqrt()).powi(3)
}

#[test]
fn consistent_on_its_own_model() {
    // The mean of n NIS of dimension m lies, for a consistent filter, in
    // [χ²(0.025; n m) / n, χ²(0.975; n m) / n] with probability 0.95.
    let settings = FilterSettings::default();
    let mut sim = Sim::new(2024, settings);
    let sd = settings.initial_sd;
    sim.truth = RowState {
        offset_m: sim.gauss(sd.offset_m),
        heading_rad: sim.gauss(sd.heading_rad),
        curvature_per_m: sim.gauss(sd.curvature_per_m),
        map_bias_m: sim.gauss(sd.map_bias_m),
        slip_rad: sim.gauss(sd.slip_rad),
        camera_bias_m: 0.0,
    };
    let mut f = RowFilter::new(settings);
    let (mut camera, mut gnss, mut inside, steps) = (vec![], vec![], 0, 30_000);
    for k in 0..steps {
        sim.drive(&mut f);
        if k % EVERY == 0 {
            sim.camera(&mut f, 0.0);
            camera.push(f.last_camera_nis().unwrap());
        }
        if k % EVERY == 2 {
            sim.gnss(&mut f, 0.0);
            gnss.push(f.last_gnss_nis().unwrap());
        }
        let error_m = f.state().offset_m - sim.truth.offset_m;
        inside += usize::from(error_m.abs() <= 3.0 * f.sd().offset_m);
    }
    for (name, nis, dof) in [("camera", &camera, 2.0), ("gnss", &gnss, 1.0)] {
        let n = nis.len() as f64;
        let mean = nis.iter().sum::<f64>() / n;
        let low = chi_square_quantile(n * dof, -1.959964) / n;
        let high = chi_square_quantile(n * dof, 1.959964) / n;
        assert!(
            low <= mean && mean <= high,
            "{name}: mean NIS {mean} outside [{low}, {high}]"
        );
    }
    let share = inside as f64 / steps as f64;
    assert!(share >= 0.99, "offset within 3 s.d. only {share}");
}

#[test]
fn gate_rejects_a_weed_patch_and_an_rtk_jump() {
    let mut sim = Sim::new(3, FilterSettings::default());
    let mut f = RowFilter::new(FilterSettings::default());
    sim.settle(&mut f, 2000);
    assert!(f.sd().offset_m < 0.012, "not settled: {:?}", f.sd());
    sim.drive(&mut f);
    let (state, p, counters) = (f.state(), f.covariance(), f.counters());
    assert_eq!(sim.camera(&mut f, 0.08), Outcome::Rejected);
    assert_eq!(sim.gnss(&mut f, 0.5), Outcome::Rejected);
    assert_eq!((f.state(), f.covariance()), (state, p));
    assert_eq!(f.counters().camera_rejected, counters.camera_rejected + 1);
    assert_eq!(f.counters().gnss_rejected, counters.gnss_rejected + 1);
    assert!(f.last_camera_nis().unwrap() > 13.816 && f.last_gnss_nis().unwrap() > 10.828);
}

#[test]
fn a_lasting_disagreement_resets_that_sensors_part() {
    let mut sim = Sim::new(4, FilterSettings::default());
    let mut f = RowFilter::new(FilterSettings::default());
    sim.settle(&mut f, 2000);
    // The receiver jumps 0.5 m for good: after 20 rejections map_bias takes it, the row stays.
    let mut outcomes = vec![];
    for _ in 0..20 {
        (0..EVERY).for_each(|_| sim.drive(&mut f));
        sim.camera(&mut f, 0.0);
        outcomes.push(sim.gnss(&mut f, 0.5));
    }
    assert!(
        outcomes[..19].iter().all(|&o| o == Outcome::Rejected),
        "{outcomes:?}"
    );
    assert_eq!(
        (outcomes[19], f.counters().gnss_resets),
        (Outcome::Reset, 1)
    );
    let (state, truth) = (f.state(), sim.truth);
    assert!(close(state.offset_m, truth.offset_m, 0.01), "{state:?}");
    assert!(
        close(state.map_bias_m, truth.map_bias_m + 0.5, 0.02),
        "{state:?}"
    );
    // A stone knocks the robot 10 cm right, unseen by odometry: the row is 10 cm further
    // left. After 10 rejected frames the camera's offset and heading are taken.
    sim.truth.offset_m += 0.10;
    let mut outcomes = vec![];
    for _ in 0..10 {
        (0..EVERY).for_each(|_| sim.drive(&mut f));
        outcomes.push(sim.camera(&mut f, 0.0));
    }
    assert!(
        outcomes[..9].iter().all(|&o| o == Outcome::Rejected),
        "{outcomes:?}"
    );
    assert_eq!(
        (outcomes[9], f.counters().camera_resets),
        (Outcome::Reset, 1)
    );
    sim.settle(&mut f, 100);
    let (state, truth) = (f.state(), sim.truth);
    assert!(close(state.offset_m, truth.offset_m, 0.02), "{state:?}");
}

#[test]
fn with_gnss_alone_a_lasting_disagreement_moves_the_row() {
    // GNSS alone steering: the map is the row (its error 0 and known to be).
    let mut settings = FilterSettings {
        map_bias_sd_per_sqrt_m: 0.0,
        ..FilterSettings::default()
    };
    settings.initial_sd.map_bias_m = 0.0;
    let mut sim = Sim::new(6, FilterSettings::default());
    let mut f = RowFilter::new(settings);
    for k in 0..2000 {
        sim.drive(&mut f);
        if k % EVERY == 0 {
            sim.gnss(&mut f, 0.0);
        }
    }
    // A stone knocks the robot 30 cm right, unseen by odometry: after 20 rejected fixes
    // the row is where GNSS says, not a step of the way there.
    sim.truth.offset_m += 0.30;
    let mut outcomes = vec![];
    for _ in 0..20 {
        (0..EVERY).for_each(|_| sim.drive(&mut f));
        outcomes.push(sim.gnss(&mut f, 0.0));
    }
    assert_eq!(outcomes[19], Outcome::Reset, "{outcomes:?}");
    let (state, truth) = (f.state(), sim.truth);
    assert!(
        close(state.offset_m, truth.offset_m, 0.01),
        "{state:?} {truth:?}"
    );
}

#[test]
fn gnss_holds_the_row_when_the_camera_is_lost() {
    // The map lies 3 cm left of the row, slowly varying: GNSS alone, taken at its word,
    // would be 2.7 to 3.3 cm off. The robot crabs 1°.
    let mut noise = FilterSettings::default();
    (noise.map_bias_sd_per_sqrt_m, noise.slip_sd_per_sqrt_m) = (0.0, 0.0);
    let mut sim = Sim::new(5, noise);
    sim.truth.slip_rad = 1f64.to_radians();
    let map_bias_m =
        |k: usize| 0.03 + 0.003 * (k as f64 * STEP_M / 60.0 * std::f64::consts::TAU).sin();
    let mut f = RowFilter::new(FilterSettings::default());
    let (settle, lost) = (3000, 5000); // 30 m, then 50 m
    for k in 0..settle + lost {
        sim.truth.map_bias_m = map_bias_m(k);
        sim.drive(&mut f);
        if k % EVERY == 0 && k < settle {
            sim.camera(&mut f, 0.0);
        }
        if k % EVERY == 2 {
            sim.gnss(&mut f, 0.0);
        }
        if k == settle {
            let learned_m = f.state().map_bias_m - sim.truth.map_bias_m;
            assert!(learned_m.abs() < 0.005, "map_bias {learned_m} m off");
        }
        let error_m = f.state().offset_m - sim.truth.offset_m;
        assert!(
            k < settle || error_m.abs() < 0.02,
            "{error_m} m off at step {k}"
        );
    }
}

#[test]
fn bad_input_is_refused_and_counted() {
    let mut sim = Sim::new(6, FilterSettings::default());
    let mut f = RowFilter::new(FilterSettings::default());
    sim.settle(&mut f, 500);
    let (state, p, before) = (f.state(), f.covariance(), f.counters());
    let (nan, inf, still) = (f64::NAN, f64::INFINITY, Travel::default());
    let bad_motion = Travel {
        travelled_m: nan,
        ..still
    };
    let (mut bad_state, mut bad_sd) = (state, f.sd());
    (bad_state.offset_m, bad_sd.heading_rad) = (nan, -1.0);
    let outcomes = [
        f.predict(nan, 0.0),
        f.predict(0.01, inf),
        f.predict(2.0, 0.0),
        f.update_camera(nan, 0.0, 0.8, 0.01, 0.01, still),
        f.update_camera(0.0, inf, 0.8, 0.01, 0.01, still),
        f.update_camera(0.0, 0.0, nan, 0.01, 0.01, still),
        f.update_camera(0.0, 0.0, 0.8, -0.01, 0.01, still),
        f.update_camera(0.0, 0.0, 0.8, 0.01, 0.0, still),
        f.update_camera(0.0, 0.0, 0.8, 0.01, 0.01, bad_motion),
        f.update_gnss(inf, 0.01, still),
        f.update_gnss(0.0, -0.01, still),
        f.update_gnss(0.0, nan, still),
        f.update_gnss(0.0, 1e200, still),
        f.update_gnss(0.0, 0.01, bad_motion),
        f.reset(bad_state, f.sd()),
        f.reset(state, bad_sd),
    ];
    assert!(
        outcomes.iter().all(|&o| o == Outcome::Refused),
        "{outcomes:?}"
    );
    // A camera 1e200 m ahead makes S infinite: refused as singular.
    let far = f.update_camera(0.0, 0.0, 1e200, 0.01, 0.01, still);
    assert_eq!(
        (far, f.state(), f.covariance()),
        (Outcome::Refused, state, p)
    );
    let mut expected = before;
    expected.refused_bad_input += outcomes.len() as u64;
    expected.refused_singular += 1;
    assert_eq!(f.counters(), expected);
}

#[test]
fn standing_still_adds_no_noise() {
    let mut sim = Sim::new(7, FilterSettings::default());
    let mut f = RowFilter::new(FilterSettings::default());
    sim.settle(&mut f, 500);
    let (state, p) = (f.state(), f.covariance());
    for _ in 0..1000 {
        assert_eq!(f.predict(0.0, 0.0), Outcome::Used);
    }
    assert_eq!((f.state(), f.covariance()), (state, p));
}

/// RMS error of the offset over 80 m with both sensors, the robot crabbing at `slip_deg`.
fn rms_offset_error_m(settings: FilterSettings, slip_deg: f64) -> f64 {
    let mut noise = FilterSettings::default();
    (noise.slip_sd_per_sqrt_m, noise.curvature_sd_per_sqrt_m) = (0.0, 0.002);
    let mut sim = Sim::new(8, noise);
    sim.truth.slip_rad = slip_deg.to_radians();
    let mut f = RowFilter::new(settings);
    sim.settle(&mut f, 2000);
    let mut sum = 0.0;
    for _ in 0..8000 {
        sim.settle(&mut f, 1);
        sum += (f.state().offset_m - sim.truth.offset_m).powi(2);
    }
    (sum / 8000.0).sqrt()
}

#[test]
fn slip_state_holds_a_crabbing_robot() {
    // Without it (slip known to be 0) the camera's angle and the offset's drift disagree:
    // the offset's RMS error grew from 2.0 mm to 6.5, 12.9, 19.3 mm at 1, 2, 3 degrees.
    let mut without = FilterSettings::default();
    (without.slip_sd_per_sqrt_m, without.initial_sd.slip_rad) = (0.0, 0.0);
    for slip_deg in [1.0, 2.0, 3.0] {
        let with_m = rms_offset_error_m(FilterSettings::default(), slip_deg);
        let without_m = rms_offset_error_m(without, slip_deg);
        assert!(
            with_m < 0.004,
            "{slip_deg}°: {with_m} m with the slip state"
        );
        assert!(
            without_m > 2.0 * with_m,
            "{slip_deg}°: {without_m} m without"
        );
    }
}
