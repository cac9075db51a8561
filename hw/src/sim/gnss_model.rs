//! The simulated RTK receiver's errors: what it reports for a true position, by the
//! state of its solution, from one seed.
//!
//! | state | quality | white s.d. per axis | bias per axis (Gauss-Markov s.d., tau) |
//! | --- | --- | --- | --- |
//! | Fixed | 4 | 1.0 cm | 0.5 cm, 120 s: wanders by millimetres over minutes |
//! | Float | 5 | 10 cm | 10 cm, 30 s: 5-20 cm horizontally, changing within an episode |
//! | Dgps | 2 | 40 cm | 50 cm, 100 s: 0.3-1 m, as SBAS/DGPS drifts |
//! | Lost | 0 | no position | |
//!
//! The biases' sizes and correlation times are what RTK receivers show: a fixed
//! solution wanders by millimetres over minutes, a float one by 5-20 cm within a
//! 10-60 s episode, DGPS by decimetres to a metre over minutes. Every bias runs all the time, whatever the
//! state, and every epoch draws the same numbers in the same order: a change of state
//! changes which numbers are used, never which are drawn, so the noise after an event
//! is the same with or without it. The field tier's float episodes come from a
//! separate stream for the same reason. Time and distance are passed in; nothing here
//! reads a clock or allocates.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Exp1, StandardNormal};

use super::gauss_markov::GaussMarkov;
use crate::nmea::FixQuality;

/// Added to the simulation's seed, so this receiver's numbers differ from every other
/// simulated device's drawn from the same seed.
pub(crate) const SEED_GNSS_NOISE: u64 = 0x6e55_0001;
pub(crate) const SEED_GNSS_SCHEDULE: u64 = 0x6e55_0002;

/// The solution states, as the simulation's events gnss_fixed, gnss_float, gnss_dgps
/// and gnss_lost set them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GnssState {
    Fixed,
    Float,
    Dgps,
    Lost,
}

/// One state's error model and what the receiver reports in it.
#[derive(Debug, Clone, Copy)]
struct StateModel {
    quality: FixQuality,
    white_sd_m: f64,
    bias_sd_m: f64,
    bias_tau_s: f64,
    /// Typical of a dual-frequency receiver in open sky, and fewer as it degrades.
    satellites: u8,
    hdop: f64,
}

const FIXED: StateModel = StateModel {
    quality: FixQuality::RtkFixed,
    white_sd_m: 0.01,
    bias_sd_m: 0.005,
    bias_tau_s: 120.0,
    satellites: 20,
    hdop: 0.7,
};
const FLOAT: StateModel = StateModel {
    quality: FixQuality::RtkFloat,
    white_sd_m: 0.10,
    bias_sd_m: 0.10,
    bias_tau_s: 30.0,
    satellites: 16,
    hdop: 0.9,
};
const DGPS: StateModel = StateModel {
    quality: FixQuality::Dgps,
    white_sd_m: 0.40,
    bias_sd_m: 0.50,
    bias_tau_s: 100.0,
    satellites: 12,
    hdop: 1.2,
};
/// The RTK fixed solution's error from epoch to epoch, per axis, m.
pub const RTK_FIXED_WHITE_SD_M: f64 = FIXED.white_sd_m;
/// Fixed, Float, Dgps: the states with a position, in the order of `biases`.
const MODELS: [StateModel; 3] = [FIXED, FLOAT, DGPS];

/// What the receiver reports at one epoch, in the local frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measured {
    pub east_m: f64,
    pub north_m: f64,
    pub quality: FixQuality,
    /// The s.d. per axis the receiver reports (its GST), i.e. the state's white noise:
    /// like a real receiver, it does not know its own bias.
    pub sd_m: f64,
    pub satellites: u8,
    pub hdop: f64,
}

/// The field tier's float episodes: one of `episode_s` every `mean_spacing_m` of travel
/// on average, at exponentially distributed distances, as under tree lines and near
/// buildings along a real field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FloatSchedule {
    mean_spacing_m: f64,
    episode_s: f64,
}

/// A field tier that could not work as asked; says which number to change.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub(crate) enum FloatScheduleError {
    #[error("the mean distance between float episodes must be positive and finite, not {0} m")]
    Spacing(f64),
    #[error("a float episode must last a positive, finite time, not {0} s")]
    Duration(f64),
}

impl FloatSchedule {
    pub fn new(mean_spacing_m: f64, episode_s: f64) -> Result<FloatSchedule, FloatScheduleError> {
        if !(mean_spacing_m.is_finite() && mean_spacing_m > 0.0) {
            return Err(FloatScheduleError::Spacing(mean_spacing_m));
        }
        if !(episode_s.is_finite() && episode_s > 0.0) {
            return Err(FloatScheduleError::Duration(episode_s));
        }
        Ok(FloatSchedule {
            mean_spacing_m,
            episode_s,
        })
    }
}

impl Default for FloatSchedule {
    /// One 20 s float episode per 200 m.
    fn default() -> Self {
        FloatSchedule {
            mean_spacing_m: 200.0,
            episode_s: 20.0,
        }
    }
}

/// Counts for tests and the simulator's display.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ReceiverCounters {
    pub epochs: u64,
    /// Float episodes begun by `float_for` or the field tier.
    pub float_episodes: u64,
    /// Field-tier episodes that fell while the receiver was not fixed, and were skipped.
    pub episodes_skipped: u64,
}

pub struct ReceiverModel {
    state: GnssState,
    /// When the state began, for the simulator's display.
    state_since_s: f64,
    /// When a float episode started by `float_for` or the field tier ends.
    float_until_s: Option<f64>,
    /// Per state with a position (order of `MODELS`): east and north bias.
    biases: [[GaussMarkov; 2]; 3],
    last_t_s: Option<f64>,
    tier: Option<FloatSchedule>,
    next_episode_at_m: f64,
    noise_rng: ChaCha8Rng,
    schedule_rng: ChaCha8Rng,
    counters: ReceiverCounters,
}

impl ReceiverModel {
    /// A receiver in RTK fixed, without the field tier.
    pub fn new(seed: u64) -> ReceiverModel {
        let mut noise_rng = ChaCha8Rng::seed_from_u64(seed.wrapping_add(SEED_GNSS_NOISE));
        let biases = MODELS.map(|m| {
            [(); 2].map(|()| {
                GaussMarkov::new(m.bias_sd_m, m.bias_tau_s, noise_rng.sample(StandardNormal))
            })
        });
        ReceiverModel {
            state: GnssState::Fixed,
            state_since_s: 0.0,
            float_until_s: None,
            biases,
            last_t_s: None,
            tier: None,
            next_episode_at_m: f64::INFINITY,
            noise_rng,
            schedule_rng: ChaCha8Rng::seed_from_u64(seed.wrapping_add(SEED_GNSS_SCHEDULE)),
            counters: ReceiverCounters::default(),
        }
    }

    /// Add the field tier's float episodes, counted from `distance_m` travelled now.
    pub(crate) fn with_float_schedule(
        mut self,
        tier: FloatSchedule,
        distance_m: f64,
    ) -> ReceiverModel {
        self.tier = Some(tier);
        self.next_episode_at_m = distance_m + self.episode_spacing_m(tier);
        self
    }

    pub fn state(&self) -> GnssState {
        self.state
    }

    /// When the current state began, s.
    pub fn state_since_s(&self) -> f64 {
        self.state_since_s
    }

    pub fn counters(&self) -> ReceiverCounters {
        self.counters
    }

    /// The state from now on, until the next command; ends any float episode.
    pub fn set_state(&mut self, state: GnssState, t_s: f64) {
        self.state = state;
        self.state_since_s = t_s;
        self.float_until_s = None;
    }

    /// Lose the corrections' ambiguity fix for `duration_s` from `t_s`, then return
    /// to Fixed by itself (a non-finite or negative duration is no episode).
    pub(crate) fn float_for(&mut self, t_s: f64, duration_s: f64) {
        if duration_s.is_finite() && duration_s > 0.0 {
            self.state = GnssState::Float;
            self.state_since_s = t_s;
            self.float_until_s = Some(t_s + duration_s);
            self.counters.float_episodes += 1;
        }
    }

    /// The receiver's report for one epoch at `t_s`, with the robot `distance_m` along
    /// its path (for the field tier) and truly at (`true_east_m`, `true_north_m`).
    /// `None` when it has no position.
    pub fn measure(
        &mut self,
        t_s: f64,
        distance_m: f64,
        true_east_m: f64,
        true_north_m: f64,
    ) -> Option<Measured> {
        self.counters.epochs += 1;
        self.end_episode(t_s);
        self.follow_tier(t_s, distance_m);

        let dt_s = self.last_t_s.map_or(0.0, |last| t_s - last);
        if dt_s > 0.0 || self.last_t_s.is_none() {
            self.last_t_s = Some(t_s);
        }
        // Every number, every epoch, whatever the state.
        for axes in &mut self.biases {
            for bias in axes {
                bias.step(dt_s, self.noise_rng.sample(StandardNormal));
            }
        }
        let white_east: f64 = self.noise_rng.sample(StandardNormal);
        let white_north: f64 = self.noise_rng.sample(StandardNormal);

        let index = match self.state {
            GnssState::Fixed => 0,
            GnssState::Float => 1,
            GnssState::Dgps => 2,
            GnssState::Lost => return None,
        };
        let model = MODELS.get(index)?;
        let [bias_east, bias_north] = self.biases.get(index)?;
        Some(Measured {
            east_m: true_east_m + bias_east.value_m() + model.white_sd_m * white_east,
            north_m: true_north_m + bias_north.value_m() + model.white_sd_m * white_north,
            quality: model.quality,
            sd_m: model.white_sd_m,
            satellites: model.satellites,
            hdop: model.hdop,
        })
    }

    fn end_episode(&mut self, t_s: f64) {
        if let Some(until_s) = self.float_until_s
            && t_s >= until_s
        {
            self.state = GnssState::Fixed;
            self.state_since_s = until_s;
            self.float_until_s = None;
        }
    }

    fn follow_tier(&mut self, t_s: f64, distance_m: f64) {
        let Some(tier) = self.tier else { return };
        if distance_m.is_nan() || distance_m < self.next_episode_at_m {
            return;
        }
        if self.state == GnssState::Fixed {
            self.float_for(t_s, tier.episode_s);
        } else {
            self.counters.episodes_skipped += 1;
        }
        // From here, not from the missed mark: a jump in distance gives one episode.
        self.next_episode_at_m = distance_m + self.episode_spacing_m(tier);
    }

    fn episode_spacing_m(&mut self, tier: FloatSchedule) -> f64 {
        let unit: f64 = self.schedule_rng.sample(Exp1);
        tier.mean_spacing_m * unit
    }
}

#[cfg(test)]
#[path = "gnss_model_tests.rs"]
mod tests;
