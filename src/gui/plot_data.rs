//! The plots' data: samples of the last 60 s in a ring of fixed size (allocated once,
//! the oldest overwritten), taken by the GUI's pacer thread whatever the frame rate,
//! and thinned to the pixels of a plot (the lowest and highest value of each pixel
//! column) into buffers that are reused from frame to frame.

use egui_plot::PlotPoint;

use super::view::View;

/// Seconds shown, and samples a second (a sample is due after 0.8 of its period, for a
/// caller's jitter: one asking a thousand times a second gets 37).
pub(crate) const WINDOW_S: f64 = 60.0;
pub(crate) const SAMPLES_PER_S: f64 = 30.0;
/// Ring buffer length: the window at the highest sample rate.
pub(crate) const CAPACITY: usize = (WINDOW_S * SAMPLES_PER_S) as usize;

/// One instant of everything plotted, in the units shown.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Sample {
    pub t_s: f64,
    pub v_left_mps: f64,
    pub v_right_mps: f64,
    pub v_left_ref_mps: f64,
    pub v_right_ref_mps: f64,
    pub wheel_deg: f64,
    pub wheel_ref_deg: f64,
    pub row_offset_cm: f64,
    pub row_angle_deg: f64,
    /// The row filter's offset at the rear axle and one s.d. either side (NaN when the
    /// camera steers alone).
    pub filter_offset_cm: f64,
    pub filter_low_cm: f64,
    pub filter_high_cm: f64,
    pub cross_track_cm: f64,
    pub amp_left_v: f64,
    pub amp_right_v: f64,
    pub amp_steer_v: f64,
}

impl Sample {
    pub fn of(view: &View) -> Sample {
        let st = &view.status;
        let o = &st.outputs;
        let filter = view.steer.row.filter;
        Sample {
            t_s: view.now_s,
            v_left_mps: st.measured.v_left_mps,
            v_right_mps: st.measured.v_right_mps,
            v_left_ref_mps: st.v_left_ref_mps,
            v_right_ref_mps: st.v_right_ref_mps,
            wheel_deg: st.measured.wheel_angle_rad.to_degrees(),
            wheel_ref_deg: st.wheel_angle_ref_rad.to_degrees(),
            row_offset_cm: view.link.last_row.offset_m * 100.0,
            row_angle_deg: view.link.last_row.angle_rad.to_degrees(),
            filter_offset_cm: filter.map_or(f64::NAN, |f| f.offset_m * 100.0),
            filter_low_cm: filter.map_or(f64::NAN, |f| (f.offset_m - f.offset_sd_m) * 100.0),
            filter_high_cm: filter.map_or(f64::NAN, |f| (f.offset_m + f.offset_sd_m) * 100.0),
            cross_track_cm: view.truth.tool_cross_track_m * 100.0,
            amp_left_v: o.amp_left_v,
            amp_right_v: o.amp_right_v,
            amp_steer_v: o.amp_steer_v,
        }
    }
}

/// A fixed-size ring of samples: pushing never allocates, the oldest is overwritten.
pub struct Ring {
    buf: Box<[Sample]>,
    /// Next slot to write.
    head: usize,
    len: usize,
}

impl Ring {
    pub fn new(capacity: usize) -> Ring {
        Ring {
            buf: vec![Sample::default(); capacity.max(1)].into_boxed_slice(),
            head: 0,
            len: 0,
        }
    }

    pub fn push(&mut self, s: Sample) {
        self.buf[self.head] = s;
        self.head = (self.head + 1) % self.buf.len();
        self.len = (self.len + 1).min(self.buf.len());
    }

    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub(crate) fn capacity(&self) -> usize {
        self.buf.len()
    }

    /// Oldest first.
    pub fn iter(&self) -> impl Iterator<Item = &Sample> {
        let cap = self.buf.len();
        let start = (self.head + cap - self.len) % cap;
        (0..self.len).map(move |k| &self.buf[(start + k) % cap])
    }

    pub fn last(&self) -> Option<&Sample> {
        self.len.checked_sub(1).map(|_| {
            let cap = self.buf.len();
            &self.buf[(self.head + cap - 1) % cap]
        })
    }
}

/// The samples and whether the operator paused them.
pub struct PlotSamples {
    pub ring: Ring,
    pub paused: bool,
    last_sample_s: f64,
}

impl Default for PlotSamples {
    fn default() -> Self {
        PlotSamples {
            ring: Ring::new(CAPACITY),
            paused: false,
            last_sample_s: f64::NEG_INFINITY,
        }
    }
}

impl PlotSamples {
    /// Take a sample if one is due (and the plots are not paused). A sample is due a
    /// little before its period has passed, so that a caller polling at the sample rate
    /// with some jitter misses none.
    pub fn record(&mut self, view: &View) {
        if self.paused || view.now_s - self.last_sample_s < 0.8 / SAMPLES_PER_S {
            return;
        }
        self.last_sample_s = view.now_s;
        self.ring.push(Sample::of(view));
    }
}

/// Thin one series of `ring` to `columns` pixel columns across the window ending at the
/// newest sample: for each column, its lowest and its highest value, in the order they
/// came, so that a spike of one sample is still drawn. Times are s from the newest
/// sample (negative). `out` is cleared and refilled: it allocates only while it grows.
pub(crate) fn thin(
    ring: &Ring,
    value: fn(&Sample) -> f64,
    columns: usize,
    out: &mut Vec<PlotPoint>,
) {
    out.clear();
    let Some(newest) = ring.last() else {
        return;
    };
    let columns = columns.max(1);
    let column_s = WINDOW_S / columns as f64;
    // The column being filled: its index and its lowest and highest point.
    let mut current: Option<(i64, PlotPoint, PlotPoint)> = None;
    let flush = |out: &mut Vec<PlotPoint>, low: PlotPoint, high: PlotPoint| {
        let (first, second) = if low.x <= high.x {
            (low, high)
        } else {
            (high, low)
        };
        out.push(first);
        if second.x != first.x || second.y != first.y {
            out.push(second);
        }
    };
    for s in ring.iter() {
        let x = s.t_s - newest.t_s;
        let point = PlotPoint::new(x, value(s));
        let column = ((x + WINDOW_S) / column_s).floor() as i64;
        match &mut current {
            Some((c, low, high)) if *c == column => {
                // NaN (nothing yet) never replaces a number, and a number replaces NaN.
                if point.y < low.y || low.y.is_nan() {
                    *low = point;
                }
                if point.y > high.y || high.y.is_nan() {
                    *high = point;
                }
            }
            _ => {
                if let Some((_, low, high)) = current {
                    flush(out, low, high);
                }
                current = Some((column, point, point));
            }
        }
    }
    if let Some((_, low, high)) = current {
        flush(out, low, high);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ring_of(values: &[(f64, f64)]) -> Ring {
        let mut ring = Ring::new(CAPACITY);
        for &(t_s, v) in values {
            ring.push(Sample {
                t_s,
                wheel_deg: v,
                ..Sample::default()
            });
        }
        ring
    }

    #[test]
    fn the_ring_keeps_the_newest_in_order() {
        let mut ring = Ring::new(3);
        assert!(ring.is_empty());
        for t in 0..5 {
            ring.push(Sample {
                t_s: t as f64,
                ..Sample::default()
            });
        }
        let times: Vec<f64> = ring.iter().map(|s| s.t_s).collect();
        assert_eq!(times, [2.0, 3.0, 4.0]);
        assert_eq!(ring.len(), 3);
        assert_eq!(ring.last().unwrap().t_s, 4.0);
    }

    #[test]
    fn about_thirty_samples_a_second_however_often_asked_and_none_while_paused() {
        let mut samples = PlotSamples::default();
        let mut view = View::default();
        for k in 0..1000 {
            view.now_s = k as f64 * 0.001; // a frame every millisecond for a second
            samples.record(&view);
        }
        let n = samples.ring.len();
        assert!((30..=38).contains(&n), "{n}");
        samples.paused = true;
        view.now_s = 5.0;
        samples.record(&view);
        assert_eq!(samples.ring.len(), n);
    }

    #[test]
    fn a_poll_at_the_sample_rate_with_jitter_misses_no_sample() {
        let mut samples = PlotSamples::default();
        let mut view = View::default();
        for k in 0..300 {
            // 30 polls a second, each up to 3 ms early or late
            view.now_s = k as f64 / 30.0 + if k % 2 == 0 { 0.003 } else { -0.003 };
            samples.record(&view);
        }
        assert_eq!(samples.ring.len(), 300);
    }

    #[test]
    fn thinning_keeps_each_columns_extremes_and_a_one_sample_spike() {
        // 60 s at 30 samples/s, a flat line with one spike at -30 s, onto 100 columns
        let values: Vec<(f64, f64)> = (0..1800)
            .map(|k| {
                let t = k as f64 / 30.0;
                (t, if k == 900 { 25.0 } else { 1.0 })
            })
            .collect();
        let ring = ring_of(&values);
        let mut out = Vec::new();
        thin(&ring, |s| s.wheel_deg, 100, &mut out);
        assert!(out.len() <= 2 * 101, "{} points", out.len());
        assert!(
            out.iter().any(|p| p.y == 25.0),
            "the spike was thinned away"
        );
        assert!(
            out.windows(2).all(|w| w[0].x <= w[1].x),
            "time goes forward"
        );
        assert_eq!(out.last().unwrap().x, 0.0, "ends at the newest sample");
        // Reused: refilling does not grow the buffer again.
        let capacity = out.capacity();
        thin(&ring, |s| s.wheel_deg, 100, &mut out);
        assert_eq!(out.capacity(), capacity);
    }

    #[test]
    fn thinning_fewer_samples_than_columns_keeps_every_sample() {
        let ring = ring_of(&[(0.0, 1.0), (1.0, 3.0), (2.0, 2.0)]);
        let mut out = Vec::new();
        thin(&ring, |s| s.wheel_deg, 600, &mut out);
        let ys: Vec<f64> = out.iter().map(|p| p.y).collect();
        assert_eq!(ys, [1.0, 3.0, 2.0]);
        thin(&Ring::new(4), |s| s.wheel_deg, 600, &mut out);
        assert!(out.is_empty());
    }
}
