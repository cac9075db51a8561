//! How busy the computer is, for the words of a stall or overrun fault: a supervisor
//! that misses its deadlines on a computer whose other programs take the CPU is a busy
//! computer, not a broken robot, and the operator should be told which it is.
//!
//! The kernel's load average (/proc/loadavg) is read once a second by a thread of
//! normal priority into a `LoadGauge`; the supervisor's tick only copies the last
//! reading (an atomic load), so that reading a file never delays a tick.

use std::fmt;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// The computer's load at one moment: its 1-minute load average and its CPUs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CpuLoad {
    /// Runnable and waiting tasks, averaged over the last minute.
    pub load_1min: f64,
    pub cpus: u32,
}

impl CpuLoad {
    /// More work than CPUs: some of it, the supervisor's included, waits for a CPU.
    pub fn high(&self) -> bool {
        self.load_1min >= f64::from(self.cpus)
    }
}

impl fmt::Display for CpuLoad {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the computer's load was {:.1} on {} CPUs",
            self.load_1min, self.cpus
        )?;
        if self.high() {
            write!(f, ": other programs took the CPU")?;
        } else if self.load_1min < 0.5 * f64::from(self.cpus) {
            write!(f, " (not busy)")?;
        }
        Ok(())
    }
}

/// The last reading, shared between the thread that reads it and the supervisor.
#[derive(Debug)]
pub struct LoadGauge {
    /// The load average's f64 bits; NaN until the first reading.
    load_bits: AtomicU64,
    cpus: u32,
}

impl Default for LoadGauge {
    fn default() -> Self {
        let cpus = std::thread::available_parallelism().map_or(1, |n| n.get() as u32);
        LoadGauge {
            load_bits: AtomicU64::new(f64::NAN.to_bits()),
            cpus,
        }
    }
}

impl LoadGauge {
    /// The last reading, None before the first or where /proc/loadavg cannot be read.
    pub fn now(&self) -> Option<CpuLoad> {
        let load_1min = f64::from_bits(self.load_bits.load(Ordering::Relaxed));
        (!load_1min.is_nan()).then_some(CpuLoad {
            load_1min,
            cpus: self.cpus,
        })
    }

    /// Read /proc/loadavg now (not from the supervisor's thread: it reads a file).
    pub fn sample(&self) {
        if let Some(load) = std::fs::read_to_string("/proc/loadavg")
            .ok()
            .and_then(|text| parse_loadavg(&text))
        {
            self.load_bits.store(load.to_bits(), Ordering::Relaxed);
        }
    }
}

/// Read the load about once a second until `stop` (the run's own thread for it).
pub fn sample_until(gauge: &LoadGauge, stop: &AtomicBool) {
    while !stop.load(Ordering::Relaxed) {
        gauge.sample();
        // In steps, so that the end of the run is not kept waiting.
        for _ in 0..10 {
            if stop.load(Ordering::Relaxed) {
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(100));
        }
    }
}

/// The 1-minute figure of /proc/loadavg ("0.52 0.58 0.59 1/467 12345").
fn parse_loadavg(text: &str) -> Option<f64> {
    text.split_whitespace()
        .next()?
        .parse()
        .ok()
        .filter(|l: &f64| l.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_load_above_the_cpus_says_other_programs_took_the_cpu() {
        let busy = CpuLoad {
            load_1min: 4.2,
            cpus: 2,
        };
        assert!(busy.high());
        let words = busy.to_string();
        assert!(
            words.starts_with("the computer's load was 4.2 on 2 CPUs: other programs took the CPU"),
            "{words}"
        );
        let idle = CpuLoad {
            load_1min: 0.3,
            cpus: 2,
        };
        assert_eq!(
            idle.to_string(),
            "the computer's load was 0.3 on 2 CPUs (not busy)"
        );
        assert_eq!(parse_loadavg("0.52 0.58 0.59 1/467 12345\n"), Some(0.52));
        assert_eq!(parse_loadavg("nonsense"), None);
    }

    #[test]
    fn the_gauge_reads_this_computers_load() {
        let gauge = LoadGauge::default();
        assert_eq!(gauge.now(), None, "nothing before the first reading");
        gauge.sample();
        if std::path::Path::new("/proc/loadavg").exists() {
            let load = gauge.now().expect("read /proc/loadavg");
            assert!(load.load_1min >= 0.0 && load.cpus >= 1);
        }
    }
}
