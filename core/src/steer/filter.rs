//! A Kalman filter of the crop row near the robot, fusing the row camera, GNSS and odometry.
//!
//! # Frames, signs and state
//! Robot frame: origin at the rear axle centre, x forward, y left, angles counter-clockwise
//! positive (as in `steer::law`). Near the robot the row is the parabola
//!     y(x) = offset + heading x + curvature/2 x^2,
//! tan(heading) taken as heading: row angles stay within a few degrees, and only a model
//! linear in the state keeps the filter an exact Kalman filter. The state has five parts:
//! - `offset_m`: the row's y at the rear axle (positive: the row lies to the left);
//! - `heading_rad`: the row's heading relative to the robot's (positive: ahead, the row
//!   runs further to the left);
//! - `curvature_per_m`: the row's curvature (positive: it bends left);
//! - `map_bias_m`: how far the GNSS map's row line lies left of the row the camera sees;
//! - `slip_rad`: the crab angle, direction of travel minus the robot's heading (positive:
//!   the robot slides left, as on a slope falling to the left). It earns its place: without
//!   it a crab of 1, 2, 3° raised the offset's RMS error from 2.0 to 6.5, 12.9, 19.3 mm.
//! - `camera_bias_m`: how far the camera misreads the row's offset now. A camera misreads a
//!   stretch of row the same way (light, leaves, soil): an error that lasts a few metres,
//!   modelled as a first-order Gauss-Markov process over distance (s.d. and length in
//!   `FilterSettings`; s.d. 0 leaves it out). With GNSS beside the camera its short
//!   lasting error can be told from the map's long one.
//!
//! # Predict (ds travelled, dθ turned; products of two small quantities dropped)
//! Along an arc turned by dθ the rear axle ends ds forward and ds (dθ/2 + slip) to the
//! left, the axes rotated by dθ. The row point now beside the axle is the one that was at
//! x = ds, seen from a point that moved left and a frame that turned left:
//!     offset'    = offset + heading ds + curvature ds²/2 - slip ds - dθ ds/2
//!     heading'   = heading + curvature ds - dθ
//!     curvature' = curvature,  map_bias' = map_bias,  slip' = slip,
//!     camera_bias' = exp(-ds/L) camera_bias, gaining sd² (1 - exp(-2|ds|/L)) of variance
//! that is x' = F(ds) x + u, u = (-dθ ds/2, -dθ, 0, 0, 0). F(ds) = exp(A ds) with A the
//! nilpotent matrix of the row's shape, so F(-ds) is its exact inverse. The covariance
//! grows as P' = F P Fᵀ + Q |ds|, Q = diag(sd_per_sqrt_m²) of `FilterSettings`: the row,
//! the map, the slope and odometry's errors change with distance along the row, not time,
//! so the noise means the same at every speed, and standing still adds none. No per-second
//! floor: nothing here changes while the robot stands (the live receiver's slow drift,
//! which map_bias also absorbs, moves millimetres over the stops a weeder makes).
//!
//! # Camera update, expressed at the capture pose
//! The camera gives the row's offset and angle at x = x_c (`camera_x_m`) as the robot stood
//! when the image was taken; `since_capture` (s travelled, t turned) reaches now. The state
//! at capture is the present one run backwards by the exact inverse of predict, less the
//! process noise w that came after it: x_cap = F(-s) (x - u(s, t) - w), so
//!     z = H' (x - u(s, t)) + v - H' w,   H' = H(x_c) F(-s),
//!     H(x_c) = [1 x_c x_c²/2 0 0 1; 0 1 x_c 0 0 0] (the camera's bias on its offset),
//! which works out to the present row at x_c - s plus the turn and the slide:
//!     offset: offset + (x_c-s) heading + (x_c-s)²/2 curvature + s slip + t (x_c - s/2)
//!     angle:  heading + (x_c-s) curvature + t.
//! The error v - H' w shares w with the state's error (Q_s = Q s): its variance is
//! R' = R + H' Q_s H'ᵀ, its covariance with the state's error C = -Q_s H'ᵀ, and together
//! S = H' (P - Q_s) H'ᵀ + R. Without C the filter was overconfident (mean camera NIS 0.7 %
//! high at 0.5 m/s and 0.1 s of latency; with it, 0.2 %). Why at the capture pose rather
//! than moving the measurement into the present frame: the camera's numbers stay as it gave
//! them, with its own diagonal R, and the model is exact within predict's approximations.
//!
//! # GNSS update
//! z = where the map's row line lies from the rear axle, robot frame (positive: left), so
//! h(x) = offset + map_bias, at the pose where the receiver measured it: like the
//! camera's, expressed at that pose with H' = H F(-s) and Q_s (the receiver's latency
//! and the wait for the next steer tick are 0.05-0.15 s: 10-30 cm at 2 m/s). map_bias
//! learns the map's planting error and the live receiver's slow error together, which is
//! what lets GNSS hold the row when the camera is lost. A GNSS heading update did not
//! earn its place: in 50 m without the camera a course over ground at 0.5° s.d. changed
//! the offset's RMS error by -1.8 mm (of 11.5) when the map drifts and by +1.9 mm (of
//! 3.2) when it does not; a body heading by under 0.5 mm.
//!
//! # Update, gate and lock-out
//! y = z - h(x), S = H P Hᵀ + R' + H C + Cᵀ Hᵀ, NIS = yᵀ S⁻¹ y.
//! If NIS exceeds the chi-square quantile of the gate probability for the measurement's
//! dimension, or one number's own y_i²/S_ii exceeds the quantile for one (a weed patch
//! moves the camera's offset and not its angle), the update is rejected: state and
//! covariance are left as they were. Otherwise
//! K = (P Hᵀ + C) S⁻¹, x⁺ = x + K y and, in Joseph's form widened for C (it keeps P
//! symmetric and positive where P - K S Kᵀ can lose it to rounding),
//!     P⁺ = (I - K H) P (I - K H)ᵀ + K R' Kᵀ - (I - K H) C Kᵀ - K Cᵀ (I - K H)ᵀ.
//! A sensor rejected three times in a row is suspect, and its measurements are used
//! again from the third in a row that passes the gate (the two before are counted as
//! rejected): a weed patch's frames that happen to fall near the row do not let it in.
//! After `*_rejections_to_reset` consecutive rejections of one sensor the filter resets the
//! part that sensor speaks for, widening it to ten times its initial s.d. with no
//! correlation to the rest, and applies the measurement: the camera's offset and heading
//! (the camera is the reference of the row: the robot really drifted), GNSS's map_bias (an
//! RTK jump must not move the row; GNSS alone, the map the row: offset, heading). Resetting
//! rather than only reporting keeps the truth from being locked out; each is counted.
//! Both sensors rejected at once say the filter is off, not either sensor: then the third
//! rejection in a row resets (filter_gate.rs).
//!
//! Bad input (not finite, a s.d. not above zero or too large to square, a step beyond the
//! linear model) and an S not positive definite are refused and counted, the state kept.

use nalgebra::{SMatrix, SVector};

#[path = "filter_gate.rs"]
mod gate;
#[path = "filter_measurement.rs"]
mod measurement;
#[path = "filter_types.rs"]
mod types;
use gate::{GateMemory, Verdict};
use measurement::Measurement;
use types::Sensor;
pub use types::{FilterCounters, FilterSettings, GateProbability, Outcome, RowState, Travel};

const N: usize = 6;
type Vector = SVector<f64, N>;
/// The state's covariance, in the order offset, heading, curvature, map_bias, slip,
/// camera_bias.
pub(crate) type Covariance = SMatrix<f64, N, N>;

const OFFSET: usize = 0;
const HEADING: usize = 1;
const CURVATURE: usize = 2;
const MAP_BIAS: usize = 3;
const SLIP: usize = 4;
const CAMERA_BIAS: usize = 5;

/// Longest step predict and latency compensation take: a longer step is a missed call
/// or a wrong input ([gnss] latency_s is checked against it with the top speed).
const MAX_STEP_M: f64 = crate::config::FILTER_MAX_STEP_M;
const MAX_TURN_RAD: f64 = 0.5;
/// A reset widens a part to this many times its initial s.d.: wide enough that the
/// measurement alone sets it, narrow enough to keep S well conditioned.
const RESET_WIDEN: f64 = 10.0;

/// Fixed-size throughout, so predict and the updates never touch the heap.
#[derive(Debug, Clone)]
pub struct RowFilter {
    settings: FilterSettings,
    x: Vector,
    p: Covariance,
    counters: FilterCounters,
    /// Per `Sensor`: the last NIS.
    last_nis: [Option<f64>; 2],
    gate: GateMemory,
}

/// F(ds) of the module doc; the camera's bias keeps exp(-ds/L) of itself over ds
/// (signed, so that F(-ds) stays F(ds)'s exact inverse for the capture pose).
fn transition(ds: f64, camera_bias_length_m: f64) -> Covariance {
    let mut f = Covariance::identity();
    f[(OFFSET, HEADING)] = ds;
    f[(OFFSET, CURVATURE)] = ds * ds / 2.0;
    f[(OFFSET, SLIP)] = -ds;
    f[(HEADING, CURVATURE)] = ds;
    if camera_bias_length_m.is_finite() && camera_bias_length_m > 0.0 {
        f[(CAMERA_BIAS, CAMERA_BIAS)] = (-ds / camera_bias_length_m).exp();
    }
    f
}

/// The mean's part of predict: F(ds) x + u.
fn moved(x: &Vector, ds: f64, turned: f64, camera_bias_length_m: f64) -> Vector {
    let mut next = transition(ds, camera_bias_length_m) * x;
    next[OFFSET] -= turned * ds / 2.0;
    next[HEADING] -= turned;
    next
}

fn motion_ok(travelled_m: f64, turned_rad: f64) -> bool {
    travelled_m.abs() <= MAX_STEP_M && turned_rad.abs() <= MAX_TURN_RAD
}

/// Its square, the variance, must be a normal positive number: 1e200 would make S
/// infinite and 1e-200 would make it zero.
fn sd_ok(sd: f64) -> bool {
    sd > 0.0 && (sd * sd).is_normal()
}

fn all_finite<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> bool {
    m.iter().all(|v| v.is_finite())
}

fn symmetric(p: &Covariance) -> Covariance {
    (p + p.transpose()) * 0.5
}

impl RowFilter {
    /// A filter at the row straight ahead, with `settings.initial_sd`.
    pub fn new(settings: FilterSettings) -> RowFilter {
        let mut filter = RowFilter {
            settings,
            x: Vector::zeros(),
            p: Covariance::zeros(),
            counters: FilterCounters::default(),
            last_nis: [None; 2],
            gate: GateMemory::new(),
        };
        filter.reset(RowState::default(), settings.initial_sd);
        filter
    }

    /// Start again from `state` with a diagonal covariance of `sd` (zero: known exactly).
    /// The counters are kept; a refused reset (not finite, negative s.d.) changes nothing.
    pub fn reset(&mut self, state: RowState, sd: RowState) -> Outcome {
        let (x, sd) = (state.to_vector(), sd.to_vector());
        if !all_finite(&x) || !all_finite(&sd) || sd.iter().any(|&v| v < 0.0) {
            return self.refuse(false);
        }
        self.x = x;
        self.p = Covariance::from_diagonal(&sd.component_mul(&sd));
        self.gate = GateMemory::new();
        Outcome::Used
    }

    /// The robot drove `travelled_m` forward (negative: back) and turned `turned_rad`
    /// (positive: left) since the last predict.
    pub fn predict(&mut self, travelled_m: f64, turned_rad: f64) -> Outcome {
        if !motion_ok(travelled_m, turned_rad) {
            return self.refuse(false);
        }
        let q = self.process_noise(travelled_m);
        let length_m = self.settings.camera_bias_length_m;
        let f = transition(travelled_m, length_m);
        let x = moved(&self.x, travelled_m, turned_rad, length_m);
        let p = symmetric(&(f * self.p * f.transpose() + q));
        if !all_finite(&x) || !all_finite(&p) {
            return self.refuse(false);
        }
        self.x = x;
        self.p = p;
        self.gate.travelled(travelled_m);
        Outcome::Used
    }

    /// Q |ds| of the module doc; the camera's bias gains what it forgets over |ds|,
    /// sd² (1 - exp(-2|ds|/L)), so that its s.d. stays sd.
    fn process_noise(&self, travelled_m: f64) -> Covariance {
        let s = &self.settings;
        let per_m = Vector::new(
            s.offset_sd_per_sqrt_m,
            s.heading_sd_per_sqrt_m,
            s.curvature_sd_per_sqrt_m,
            s.map_bias_sd_per_sqrt_m,
            s.slip_sd_per_sqrt_m,
            0.0,
        );
        let mut q = per_m.component_mul(&per_m) * travelled_m.abs();
        let length_m = s.camera_bias_length_m;
        if length_m.is_finite() && length_m > 0.0 {
            let kept = (-2.0 * travelled_m.abs() / length_m).exp();
            q[CAMERA_BIAS] = s.camera_bias_sd_m.powi(2) * (1.0 - kept);
        }
        Covariance::from_diagonal(&q)
    }

    /// The camera's row offset and angle at `camera_x_m`, as seen from the pose at capture;
    /// `since_capture` is the robot's motion from then to now.
    pub fn update_camera(
        &mut self,
        offset_m: f64,
        angle_rad: f64,
        camera_x_m: f64,
        sd_offset_m: f64,
        sd_angle_rad: f64,
        since_capture: Travel,
    ) -> Outcome {
        let finite = [offset_m, angle_rad, camera_x_m]
            .iter()
            .all(|v| v.is_finite());
        if !(finite && sd_ok(sd_offset_m) && sd_ok(sd_angle_rad)) {
            return self.refuse(false);
        }
        let (x_c, half_sq) = (camera_x_m, camera_x_m * camera_x_m / 2.0);
        // The camera sees the row at x_c and its own lasting error on the offset.
        let h_rows = [
            1.0, x_c, half_sq, 0.0, 0.0, 1.0, //
            0.0, 1.0, x_c, 0.0, 0.0, 0.0,
        ];
        let h_capture = SMatrix::<f64, 2, N>::from_row_slice(&h_rows);
        let z = SVector::<f64, 2>::new(offset_m, angle_rad);
        let variances = SVector::<f64, 2>::new(sd_offset_m.powi(2), sd_angle_rad.powi(2));
        let r = SMatrix::<f64, 2, 2>::from_diagonal(&variances);
        self.update_before(Sensor::Camera, h_capture, z, r, since_capture)
    }

    /// Where the map's row line lay from the rear axle, robot frame, from GNSS (positive:
    /// left), as the robot stood when the receiver measured it; `since_fix` is the robot's
    /// motion from then to now (the receiver's latency and the wait for a steer tick).
    pub fn update_gnss(&mut self, offset_m: f64, sd_m: f64, since_fix: Travel) -> Outcome {
        if !offset_m.is_finite() || !sd_ok(sd_m) {
            return self.refuse(false);
        }
        let mut h_fix = SMatrix::<f64, 1, N>::zeros();
        h_fix[OFFSET] = 1.0;
        h_fix[MAP_BIAS] = 1.0;
        let z = SVector::<f64, 1>::new(offset_m);
        let r = SMatrix::<f64, 1, 1>::new(sd_m * sd_m);
        self.update_before(Sensor::Gnss, h_fix, z, r, since_fix)
    }

    /// The state as it was before the robot moved `since`: predict run backwards, exactly.
    pub(crate) fn state_before(&self, since: Travel) -> RowState {
        let (since_m, length_m) = (since.travelled_m, self.settings.camera_bias_length_m);
        RowState::from_vector(&moved(&self.x, -since_m, -since.turned_rad, length_m))
    }

    /// Update by z = h x + v taken before the robot moved `since` (module doc, "Camera
    /// update, expressed at the capture pose": H' = H F(-s), the process noise since).
    fn update_before<const M: usize>(
        &mut self,
        sensor: Sensor,
        h: SMatrix<f64, M, N>,
        z: SVector<f64, M>,
        r: SMatrix<f64, M, M>,
        since: Travel,
    ) -> Outcome {
        let (since_m, since_rad) = (since.travelled_m, since.turned_rad);
        if !motion_ok(since_m, since_rad) {
            return self.refuse(false);
        }
        let length_m = self.settings.camera_bias_length_m;
        let y = z - h * moved(&self.x, -since_m, -since_rad, length_m);
        let h = h * transition(-since_m, length_m);
        let q_since = self.process_noise(since_m);
        self.update(sensor, Measurement { y, h, r, q_since })
    }

    fn refuse(&mut self, singular: bool) -> Outcome {
        if singular {
            self.counters.refused_singular += 1;
        } else {
            self.counters.refused_bad_input += 1;
        }
        Outcome::Refused
    }

    fn update<const M: usize>(&mut self, sensor: Sensor, m: Measurement<M>) -> Outcome {
        let (Some((nis, _)), Some(single)) = (m.innovation(&self.p), m.worst_single_nis(&self.p))
        else {
            return self.refuse(true);
        };
        let (i, mut p) = (sensor as usize, self.p);
        self.last_nis[i] = Some(nis);
        let gate = &self.settings.gate;
        let verdict = if nis <= gate.threshold(M) && single <= gate.threshold(1) {
            self.gate.passed(sensor)
        } else {
            let limit = match sensor {
                Sensor::Camera => self.settings.camera_rejections_to_reset,
                Sensor::Gnss => self.settings.gnss_rejections_to_reset,
            };
            // The map's bias is estimated only where the camera steers beside GNSS.
            let fused = self.settings.initial_sd.map_bias_m > 0.0;
            self.gate.failed(sensor, m.y[0], limit, fused)
        };
        let outcome = match verdict {
            Verdict::Use => Outcome::Used,
            Verdict::Reject => return self.counters.count(sensor, Outcome::Rejected),
            Verdict::Reset(part) => {
                let initial_sd = self.settings.initial_sd.to_vector();
                for &k in part {
                    p.row_mut(k).fill(0.0);
                    p.column_mut(k).fill(0.0);
                    p[(k, k)] = (RESET_WIDEN * initial_sd[k]).powi(2);
                }
                Outcome::Reset
            }
        };
        let Some((x, p)) = m.corrected(&self.x, &p) else {
            return self.refuse(true);
        };
        self.x = x;
        self.p = p;
        self.counters.count(sensor, outcome)
    }

    /// GNSS's own error may have moved by `sd_m` (its solution changed, or is not RTK
    /// fixed and wanders): the map's bias, which carries it, is widened by that much, so
    /// that the fixes to come move it and not the row.
    pub(crate) fn widen_map_bias(&mut self, sd_m: f64) -> Outcome {
        if !sd_m.is_finite() || sd_m < 0.0 || !(sd_m * sd_m).is_finite() {
            return self.refuse(false);
        }
        self.p[(MAP_BIAS, MAP_BIAS)] += sd_m * sd_m;
        Outcome::Used
    }

    /// The fused row at `x_m` ahead of the rear axle, now: (offset_m, angle_rad), as a
    /// fresh camera estimate at `x_m` would give it.
    pub(crate) fn row_at(&self, x_m: f64) -> (f64, f64) {
        let (a, b, c) = (self.x[OFFSET], self.x[HEADING], self.x[CURVATURE]);
        (a + b * x_m + c * x_m * x_m / 2.0, b + c * x_m)
    }
}

#[cfg(test)]
#[path = "filter_tests.rs"]
mod tests;

#[cfg(test)]
#[path = "filter_gnss_tests.rs"]
mod gnss_tests;
