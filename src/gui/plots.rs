//! Live plots of the last 60 s: wheel speeds and their references, the wheel angle and
//! its reference, the row's offset and angle from the camera, the cross-track error of
//! the simulated robot, and the motor voltages. Samples go into a ring buffer of fixed
//! size, allocated once, at most 30 a second whatever the frame rate.

use eframe::egui;
use egui_plot::{Legend, Line, Plot, PlotPoints};

use super::view::View;

/// Seconds shown, and samples a second at most.
pub const WINDOW_S: f64 = 60.0;
pub const SAMPLES_PER_S: f64 = 30.0;
/// Ring buffer length: the window at the highest sample rate.
pub const CAPACITY: usize = (WINDOW_S * SAMPLES_PER_S) as usize;
/// Points drawn per line at most: a plot is a few hundred pixels wide, and every
/// point drawn costs the GUI thread (and a software renderer) time at each frame.
const MAX_POINTS: usize = 600;

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
    pub cross_track_cm: f64,
    pub amp_left_v: f64,
    pub amp_right_v: f64,
    pub amp_steer_v: f64,
}

impl Sample {
    pub fn of(view: &View) -> Sample {
        let st = &view.status;
        let o = &st.outputs;
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

    pub fn capacity(&self) -> usize {
        self.buf.len()
    }

    /// Oldest first.
    pub fn iter(&self) -> impl Iterator<Item = &Sample> {
        let cap = self.buf.len();
        let start = (self.head + cap - self.len) % cap;
        (0..self.len).map(move |k| &self.buf[(start + k) % cap])
    }

    pub fn last(&self) -> Option<&Sample> {
        self.iter().last()
    }
}

/// A line's name and how to read its value from a sample.
type Series<'a> = (&'a str, fn(&Sample) -> f64);

pub struct Plots {
    pub ring: Ring,
    pub paused: bool,
    last_sample_s: f64,
}

impl Default for Plots {
    fn default() -> Self {
        Plots {
            ring: Ring::new(CAPACITY),
            paused: false,
            last_sample_s: f64::NEG_INFINITY,
        }
    }
}

impl Plots {
    /// Take a sample if one is due (and the plots are not paused).
    pub fn record(&mut self, view: &View) {
        if self.paused || view.now_s - self.last_sample_s < 1.0 / SAMPLES_PER_S {
            return;
        }
        self.last_sample_s = view.now_s;
        self.ring.push(Sample::of(view));
    }

    /// One plot: each line is a name and how to read its value from a sample.
    fn plot(&self, ui: &mut egui::Ui, id: &str, unit: &str, lines: &[Series]) {
        let now_s = self.ring.last().map_or(0.0, |s| s.t_s);
        let step = self.ring.len().div_ceil(MAX_POINTS).max(1);
        Plot::new(id)
            .height(150.0)
            .legend(Legend::default())
            .allow_drag(false)
            .allow_zoom(false)
            .allow_scroll(false)
            .include_x(-WINDOW_S)
            .include_x(0.0)
            .y_axis_label(unit)
            .link_axis(egui::Id::unique("plots-time"), [true, false])
            .show(ui, |plot_ui| {
                for (name, value) in lines {
                    let points: PlotPoints = self
                        .ring
                        .iter()
                        .step_by(step)
                        .map(|s| [s.t_s - now_s, value(s)])
                        .collect();
                    plot_ui.line(Line::new(*name, points));
                }
            });
    }

    pub fn show(&mut self, ui: &mut egui::Ui, simulated: bool) {
        ui.horizontal(|ui| {
            let label = if self.paused { "Resume" } else { "Pause" };
            if ui.button(label).clicked() {
                self.paused = !self.paused;
            }
            ui.label(format!(
                "last {WINDOW_S:.0} s (time in s from now), {} of {} samples",
                self.ring.len(),
                self.ring.capacity()
            ));
        });
        ui.label("Wheel speeds and references");
        self.plot(
            ui,
            "speeds",
            "m/s",
            &[
                ("left", |s| s.v_left_mps),
                ("right", |s| s.v_right_mps),
                ("left ref", |s| s.v_left_ref_mps),
                ("right ref", |s| s.v_right_ref_mps),
            ],
        );
        ui.label("Wheel angle and reference");
        self.plot(
            ui,
            "wheel",
            "deg",
            &[
                ("angle", |s| s.wheel_deg),
                ("reference", |s| s.wheel_ref_deg),
            ],
        );
        ui.label("Row from the camera");
        self.plot(
            ui,
            "row",
            "cm / deg",
            &[
                ("offset cm", |s| s.row_offset_cm),
                ("angle deg", |s| s.row_angle_deg),
            ],
        );
        if simulated {
            ui.label("Cross-track error of the tool (simulated robot's truth)");
            self.plot(ui, "cross", "cm", &[("tool off row", |s| s.cross_track_cm)]);
        }
        ui.label("Motor voltages");
        self.plot(
            ui,
            "volts",
            "V",
            &[
                ("left", |s| s.amp_left_v),
                ("right", |s| s.amp_right_v),
                ("steering", |s| s.amp_steer_v),
            ],
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn at_most_thirty_samples_a_second_and_none_while_paused() {
        let mut plots = Plots::default();
        let mut view = View::default();
        for k in 0..1000 {
            view.now_s = k as f64 * 0.001; // a frame every millisecond for a second
            plots.record(&view);
        }
        assert!(
            (30..=31).contains(&plots.ring.len()),
            "{}",
            plots.ring.len()
        );
        plots.paused = true;
        view.now_s = 5.0;
        plots.record(&view);
        assert!(plots.ring.len() <= 31);
    }
}
