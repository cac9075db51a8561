//! Tests of the simulated receiver's error model: the statistics of each state, the
//! commands, the field tier's schedule, and reproducibility from the seed.

use super::*;

const RATE_HZ: f64 = 10.0;

/// Errors (measured - true) of `n` epochs from `t0_s`, driving east at 1 m/s.
fn errors(model: &mut ReceiverModel, t0_s: f64, n: usize) -> Vec<Option<(f64, f64, Measured)>> {
    (0..n)
        .map(|k| {
            let t_s = t0_s + k as f64 / RATE_HZ;
            let (east_m, north_m) = (t_s, -3.0);
            model
                .measure(t_s, t_s, east_m, north_m)
                .map(|m| (m.east_m - east_m, m.north_m - north_m, m))
        })
        .collect()
}

fn sd(xs: &[f64]) -> f64 {
    let mean = xs.iter().sum::<f64>() / xs.len() as f64;
    (xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / xs.len() as f64).sqrt()
}

fn rms(xs: &[f64]) -> f64 {
    (xs.iter().map(|x| x * x).sum::<f64>() / xs.len() as f64).sqrt()
}

/// East and north errors of a run that must have a position at every epoch.
fn axes(run: &[Option<(f64, f64, Measured)>]) -> (Vec<f64>, Vec<f64>) {
    run.iter()
        .map(|e| e.map(|(de, dn, _)| (de, dn)).expect("a position"))
        .unzip()
}

#[test]
fn rtk_fixed_scatters_about_a_centimetre_per_axis() {
    for seed in [1, 2, 3] {
        let mut model = ReceiverModel::new(seed);
        let run = errors(&mut model, 0.0, 10_000);
        let (east, north) = axes(&run);
        for (axis, xs) in [("east", &east), ("north", &north)] {
            let sd_m = sd(xs);
            assert!(
                (0.008..0.013).contains(&sd_m),
                "seed {seed} {axis}: {sd_m} m"
            );
        }
        let m = run[0].expect("a position").2;
        assert_eq!((m.quality, m.sd_m), (FixQuality::RtkFixed, 0.01));
    }
}

#[test]
fn rtk_float_and_dgps_errors_are_as_large_as_the_table_says() {
    for (state, quality, lo_m, hi_m) in [
        (GnssState::Float, FixQuality::RtkFloat, 0.05, 0.25),
        (GnssState::Dgps, FixQuality::Dgps, 0.3, 1.0),
    ] {
        let mut model = ReceiverModel::new(11);
        model.set_state(state, 0.0);
        let run = errors(&mut model, 0.0, 10_000);
        let (east, north) = axes(&run);
        for xs in [&east, &north] {
            let rms_m = rms(xs);
            assert!((lo_m..hi_m).contains(&rms_m), "{state:?}: {rms_m} m");
        }
        assert!(run.iter().flatten().all(|(_, _, m)| m.quality == quality));
    }
}

#[test]
fn lost_gives_no_position_until_the_next_command() {
    let mut model = ReceiverModel::new(5);
    model.set_state(GnssState::Lost, 1.0);
    assert!(errors(&mut model, 1.0, 50).iter().all(Option::is_none));
    model.set_state(GnssState::Fixed, 6.0);
    assert!(errors(&mut model, 6.0, 50).iter().all(Option::is_some));
}

#[test]
fn a_float_episode_returns_to_fixed_by_itself() {
    let mut model = ReceiverModel::new(9);
    model.float_for(5.0, 10.0);
    let quality_at =
        |model: &mut ReceiverModel, t_s: f64| model.measure(t_s, 0.0, 0.0, 0.0).map(|m| m.quality);
    assert_eq!(quality_at(&mut model, 5.0), Some(FixQuality::RtkFloat));
    assert_eq!(quality_at(&mut model, 14.9), Some(FixQuality::RtkFloat));
    assert_eq!(quality_at(&mut model, 15.0), Some(FixQuality::RtkFixed));
    assert_eq!(
        (model.state(), model.state_since_s()),
        (GnssState::Fixed, 15.0)
    );
    // A command during an episode ends it: the receiver stays where it was put.
    model.float_for(20.0, 10.0);
    model.set_state(GnssState::Dgps, 21.0);
    assert_eq!(quality_at(&mut model, 40.0), Some(FixQuality::Dgps));
}

#[test]
fn the_same_seed_gives_the_same_numbers_and_events_do_not_shift_them() {
    let run = |seed, episode: bool| {
        let mut model = ReceiverModel::new(seed);
        if episode {
            model.float_for(0.0, 5.0);
        }
        errors(&mut model, 0.0, 200)
    };
    assert_eq!(run(42, false), run(42, false));
    assert_ne!(run(42, false), run(43, false));
    // After the episode the two receivers report the very same numbers.
    let (plain, with_episode) = (run(42, false), run(42, true));
    assert_ne!(plain[..50], with_episode[..50]);
    assert_eq!(plain[50..], with_episode[50..]);
}

#[test]
fn the_field_tier_floats_about_once_per_200_m() {
    for seed in [1, 2, 3, 4] {
        let mut model = ReceiverModel::new(seed).with_float_schedule(FloatSchedule::default(), 0.0);
        // 10 km at 1 m/s, 5 Hz.
        let (speed_mps, rate_hz) = (1.0, 5.0);
        let mut episodes = 0u32;
        let mut float_epochs = 0u32;
        let mut previous = FixQuality::RtkFixed;
        for k in 0..(10_000.0 / speed_mps * rate_hz) as usize {
            let t_s = k as f64 / rate_hz;
            let quality = model
                .measure(t_s, t_s * speed_mps, 0.0, 0.0)
                .expect("a position")
                .quality;
            if quality == FixQuality::RtkFloat {
                float_epochs += 1;
                if previous == FixQuality::RtkFixed {
                    episodes += 1;
                }
            }
            previous = quality;
        }
        assert!(
            (25..=80).contains(&episodes),
            "seed {seed}: {episodes} episodes"
        );
        let mean_episode_s = f64::from(float_epochs) / rate_hz / f64::from(episodes);
        assert!(
            (19.0..=21.0).contains(&mean_episode_s),
            "seed {seed}: {mean_episode_s} s"
        );
        assert_eq!(u64::from(episodes), model.counters().float_episodes);
    }
}

#[test]
fn a_field_tier_that_cannot_work_is_refused() {
    assert_eq!(
        FloatSchedule::new(0.0, 20.0).map_err(|e| e.to_string()),
        Err("the mean distance between float episodes must be positive and finite, not 0 m".into())
    );
    assert!(matches!(
        FloatSchedule::new(200.0, f64::NAN),
        Err(FloatScheduleError::Duration(_))
    ));
    assert!(FloatSchedule::new(150.0, 10.0).is_ok());
}
