//! One linear measurement of the row filter: its innovation, the gate's numbers, and the
//! correction (the equations of filter.rs's module doc, "Update, gate and lock-out").

use nalgebra::{SMatrix, SVector};

use super::{Covariance, N, Vector, all_finite, symmetric};

/// One linear measurement: innovation y, model H, noise R, and Q_s, the process noise
/// since it was taken (zero for one taken now).
pub(super) struct Measurement<const M: usize> {
    pub y: SVector<f64, M>,
    pub h: SMatrix<f64, M, N>,
    pub r: SMatrix<f64, M, M>,
    pub q_since: Covariance,
}

impl<const M: usize> Measurement<M> {
    /// Its error relative to the present state, v - H w, has the variance R + H Q_s Hᵀ
    /// and the covariance C = -Q_s Hᵀ with the state's error.
    fn noise(&self) -> (SMatrix<f64, M, M>, SMatrix<f64, N, M>) {
        let q_ht = self.q_since * self.h.transpose();
        (self.r + self.h * q_ht, -q_ht)
    }

    /// (NIS, S⁻¹) with S = H P Hᵀ + R' + H C + Cᵀ Hᵀ, or None when S is not positive
    /// definite or anything is not finite.
    pub(super) fn innovation(&self, p: &Covariance) -> Option<(f64, SMatrix<f64, M, M>)> {
        let (_, s_inv) = self.s_and_inverse(p)?;
        let nis = (self.y.transpose() * s_inv * self.y)[0].max(0.0);
        nis.is_finite().then_some((nis, s_inv))
    }

    /// The largest of each number's own NIS, y_i² / S_ii: a weed patch moves the offset
    /// and not the angle, and hides in the two-number NIS where the offset's alone
    /// shows it.
    pub(super) fn worst_single_nis(&self, p: &Covariance) -> Option<f64> {
        let (s, _) = self.s_and_inverse(p)?;
        let worst = (0..M)
            .map(|i| self.y[i] * self.y[i] / s[(i, i)])
            .fold(0.0, f64::max);
        worst.is_finite().then_some(worst)
    }

    fn s_and_inverse(&self, p: &Covariance) -> Option<(SMatrix<f64, M, M>, SMatrix<f64, M, M>)> {
        let (r, c) = self.noise();
        let h_c = self.h * c;
        let s = self.h * p * self.h.transpose() + r + h_c + h_c.transpose();
        if !all_finite(&s) || !all_finite(&self.y) {
            return None;
        }
        let s_inv = s.cholesky()?.inverse();
        Some((s, s_inv))
    }

    /// K = (P Hᵀ + C) S⁻¹ and Joseph's form widened for C, or None when anything is not
    /// finite or a variance came out negative.
    pub(super) fn corrected(&self, x: &Vector, p: &Covariance) -> Option<(Vector, Covariance)> {
        let (_, s_inv) = self.innovation(p)?;
        let (r, c) = self.noise();
        let k = (p * self.h.transpose() + c) * s_inv;
        let i_kh = Covariance::identity() - k * self.h;
        let cross = i_kh * c * k.transpose();
        let joseph = i_kh * p * i_kh.transpose() + k * r * k.transpose();
        let p = symmetric(&(joseph - cross - cross.transpose()));
        let x = x + k * self.y;
        let variances_ok = p.diagonal().iter().all(|&v| v >= 0.0);
        (all_finite(&x) && all_finite(&p) && variances_ok).then_some((x, p))
    }
}
