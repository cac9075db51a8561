//! The Liu and Layland check of the periodic threads' measured load (rt/mod.rs keeps the
//! figures it is worked out from).
//!
//! The honest figure is the worst case of the whole run: both periodic loops (the
//! supervisor and the steer thread), each with the longest execution time of any of its
//! ticks from the first to the last, start-up and stopping included, since a
//! schedulability claim that leaves out its worst tick claims too much. Every reader
//! shows that one figure, from `liu_layland` on the loops' cumulative figures and in
//! `LiuLayland::words`: the run summary from the figures each thread returns as it ends,
//! the GUI, the console's status line and the bus from the figures the threads publish
//! four times a second and once more as they end (threads/mod.rs), so that the GUI's
//! last figure includes the run's last ticks too.

use super::LoopSummary;

/// The Liu and Layland check: is the measured worst-case load of the periodic threads
/// schedulable by fixed priorities? U = sum(C_i / T_i) <= n (2^(1/n) - 1).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct LiuLayland {
    pub utilisation: f64,
    pub bound: f64,
    pub schedulable: bool,
}

impl LiuLayland {
    /// The check in the words, and at the precision, that every reader shows.
    pub fn words(&self) -> String {
        format!(
            "worst-case load {:.4} of bound {:.3}: {}",
            self.utilisation,
            self.bound,
            if self.schedulable {
                "schedulable"
            } else {
                "NOT guaranteed schedulable"
            }
        )
    }
}

pub fn liu_layland(loops: &[LoopSummary]) -> LiuLayland {
    let n = loops.len() as f64;
    let utilisation = loops
        .iter()
        .map(|l| l.exec_us.max as f64 * 1e-6 * l.rate_hz)
        .sum();
    let bound = if n > 0.0 {
        n * (2f64.powf(1.0 / n) - 1.0)
    } else {
        1.0
    };
    LiuLayland {
        utilisation,
        bound,
        schedulable: utilisation <= bound,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rt::Percentiles;

    #[test]
    fn liu_layland_bound_for_two_threads() {
        let l = |rate_hz: f64, max_us: u64| LoopSummary {
            rate_hz,
            exec_us: Percentiles {
                max: max_us,
                ..Percentiles::default()
            },
            ..LoopSummary::default()
        };
        let check = liu_layland(&[l(100.0, 1000), l(10.0, 5000)]);
        assert!((check.utilisation - 0.15).abs() < 1e-9);
        assert!((check.bound - 2.0 * (2f64.sqrt() - 1.0)).abs() < 1e-12);
        assert!(check.schedulable);
        assert!(!liu_layland(&[l(100.0, 6000), l(10.0, 40000)]).schedulable);
    }
}
