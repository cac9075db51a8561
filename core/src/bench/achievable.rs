//! What a linear steering can reach on this robot, `bench rows`'s `achievable_rms_cm`:
//! the bound's model and LQG (bound.rs) with the two limits of the real loop that cost
//! the most added.
//!
//! - The delay. The camera's rows reach the steering about 100 ms after their frame
//!   ([sim] camera_latency_s), the receiver's fixes 50 ms late and then wait for the next
//!   steer tick: the steering acts on what was measured a frame before, the filter's
//!   prediction rather than its estimate updated with the frame's own measurement. The
//!   model allows a whole frame or none: a sensor that is late at all counts a frame
//!   late. The wheel's encoder, which is not late, is then taken a frame late too; its
//!   angle follows from the commands already given, so that costs next to nothing.
//! - The wheel's rate limit: the reference's ramp ([supervisor] wheel_angle_rate_dps)
//!   or the amplifier's most ([pid.steer] out_max_v times [sim] steer_rate_dps_per_v),
//!   whichever is lower. The bound's steering turns the wheel as fast as it likes; here
//!   the wheel's rate has a price, the smallest that keeps its RMS rate at half the
//!   limit or below, so that its peaks (two to three times the RMS) stay near it.
//!
//! Left out: the steer thread's command held twice per frame (it runs at its rate and
//! on each frame), the supervisor's discrete PD with its derivative filter, the wheel
//! angle read up to a supervisor tick old; and, as from the bound, gaps, weed patches,
//! float episodes, wheel slip, a curved row and the wheel's largest angle. So a law can
//! come close to this figure but not reach it on the simulated field.

use mechweed_hw::sim::SimParams;

use crate::bench::bound::{Law, Reference, reference};
use crate::bench::floor::Geometry;
use crate::config::{Settings, SteerSource};

/// The wheel's RMS rate the price aims at, as a share of its limit.
const RMS_RATE_OF_LIMIT: f64 = 0.5;
/// The prices searched, m² s² per rad², and the halvings of their ratio's logarithm.
const PRICES: (f64, f64) = (1e-9, 1e2);
const HALVINGS: usize = 40;

/// The fastest the wheel's angle can change on the robot of `s`, deg/s.
pub(crate) fn wheel_rate_limit_dps(s: &Settings) -> f64 {
    let amplifier_dps = s.sim.steer_rate_dps_per_v * s.pid_steer.out_max_v;
    s.supervisor.wheel_angle_rate_dps.min(amplifier_dps)
}

/// Whether `source`'s sensors reach the steering late on `plant`.
pub(crate) fn late(plant: &SimParams, source: SteerSource) -> bool {
    let camera = plant.camera_latency_s > 0.0;
    let gnss = plant.gnss.latency_s > 0.0;
    match source {
        SteerSource::Camera => camera,
        SteerSource::Gnss => gnss,
        SteerSource::Fused => camera || gnss,
    }
}

/// The achievable figures of the robot of `s` on its plant's realistic field (None
/// where the model has none), with the rate price they took.
pub(crate) fn achievable(
    s: &Settings,
    at: Geometry,
    (source, speed_mps, measured_m): (SteerSource, f64, f64),
    limit_dps: f64,
    delayed: bool,
) -> Option<(Reference, f64)> {
    let at_price = |rate_price| {
        let law = Law {
            rate_price,
            delayed,
        };
        reference(
            &s.sim,
            at,
            &s.pid_steer,
            (source, speed_mps, measured_m),
            law,
        )
    };
    let aim_dps = RMS_RATE_OF_LIMIT * limit_dps;
    let free = at_price(0.0)?;
    if free.wheel_rate_rms_dps <= aim_dps {
        return Some((free, 0.0));
    }
    // The RMS rate falls as its price rises: the smallest price that keeps it at the aim,
    // by halving the search's span on a logarithmic scale.
    let (mut cheap, mut dear) = PRICES;
    let dearest = at_price(dear)?;
    if dearest.wheel_rate_rms_dps > aim_dps {
        return Some((dearest, dear));
    }
    for _ in 0..HALVINGS {
        let middle = (cheap * dear).sqrt();
        match at_price(middle) {
            Some(r) if r.wheel_rate_rms_dps <= aim_dps => dear = middle,
            _ => cheap = middle,
        }
    }
    Some((at_price(dear)?, dear))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::bound::bound;
    use crate::bench::floor::tests::{AT, realistic};

    fn settings() -> Settings {
        let mut s = Settings::shipped();
        s.sim = realistic();
        s
    }

    const RUN: (SteerSource, f64, f64) = (SteerSource::Fused, 1.0, 55.0);

    #[test]
    fn with_nothing_late_and_no_rate_limit_it_is_the_bound() {
        let s = settings();
        let (free, price) = achievable(&s, AT, RUN, f64::INFINITY, false).unwrap();
        let the_bound = bound(&s.sim, AT, &s.pid_steer, RUN.0, RUN.1, RUN.2).unwrap();
        assert_eq!((free, price), (the_bound, 0.0));
    }

    #[test]
    fn the_rate_price_keeps_the_wheels_rms_rate_at_half_its_limit_and_costs_the_tool() {
        let s = settings();
        let (free, _) = achievable(&s, AT, RUN, f64::INFINITY, true).unwrap();
        // A limit that binds: its half is a third of the free steering's RMS rate.
        let limit_dps = free.wheel_rate_rms_dps / 3.0 * 2.0;
        let (held, price) = achievable(&s, AT, RUN, limit_dps, true).unwrap();
        assert!(price > 0.0, "{price}");
        let aim_dps = limit_dps / 2.0;
        assert!(
            held.wheel_rate_rms_dps <= aim_dps && held.wheel_rate_rms_dps > 0.95 * aim_dps,
            "{held:?} aimed at {aim_dps} deg/s"
        );
        assert!(held.rms_cm > free.rms_cm, "{held:?} {free:?}");
        // And a dearer wheel turns slower still.
        let law = Law {
            rate_price: 10.0 * price,
            delayed: true,
        };
        let dearer = reference(&s.sim, AT, &s.pid_steer, RUN, law).unwrap();
        assert!(dearer.wheel_rate_rms_dps < held.wheel_rate_rms_dps);
    }

    #[test]
    fn the_shipped_robot_is_late_and_rate_limited_so_it_stands_above_the_bound() {
        let s = settings();
        assert!(late(&s.sim, SteerSource::Camera) && late(&s.sim, SteerSource::Gnss));
        let mut prompt = s.sim.clone();
        prompt.camera_latency_s = 0.0;
        assert!(!late(&prompt, SteerSource::Camera) && late(&prompt, SteerSource::Fused));
        assert_eq!(wheel_rate_limit_dps(&s), 40.0);
        let limit = wheel_rate_limit_dps(&s);
        let (reach, _) = achievable(&s, AT, RUN, limit, true).unwrap();
        let the_bound = bound(&s.sim, AT, &s.pid_steer, RUN.0, RUN.1, RUN.2).unwrap();
        assert!(reach.rms_cm > the_bound.rms_cm, "{reach:?} {the_bound:?}");
        assert!(reach.wheel_rate_rms_dps <= limit / 2.0, "{reach:?}");
    }
}
