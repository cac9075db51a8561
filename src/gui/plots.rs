//! Live plots of the last 60 s: wheel speeds and their references, the wheel angle and
//! its reference, the row's offset and angle from the camera and the row filter's
//! estimate, the cross-track error of the simulated robot, and the motor voltages.
//!
//! Drawing is what costs a software renderer: each frame takes the samples' lock only
//! to thin every line to the plot's pixel columns into buffers kept from frame to
//! frame, then draws from those buffers with the lock released.

use eframe::egui::{self, RichText};
use egui_plot::{Legend, Line, Plot, PlotPoint, PlotPoints};

use super::pacer::SharedGui;
use super::plot_data::{Sample, WINDOW_S, thin};
use super::view::View;

/// A line's name and how to read its value from a sample.
type Series = (&'static str, fn(&Sample) -> f64);

/// One plot: its title, the unit of its axis, its lines.
struct Chart {
    id: &'static str,
    title: &'static str,
    unit: &'static str,
    lines: &'static [Series],
    /// The y axis spans at least this, in its unit: a flat line (a robot standing) still
    /// gets ticks, not a lone "0".
    least_y: [f64; 2],
    /// Shown only on the simulated robot (it plots the simulation's truth).
    simulated_only: bool,
}

const CHARTS: [Chart; 5] = [
    Chart {
        id: "speeds",
        title: "Wheel speeds and references",
        unit: "m/s",
        lines: &[
            ("left", |s| s.v_left_mps),
            ("right", |s| s.v_right_mps),
            ("left ref", |s| s.v_left_ref_mps),
            ("right ref", |s| s.v_right_ref_mps),
        ],
        least_y: [-0.2, 1.0],
        simulated_only: false,
    },
    Chart {
        id: "wheel",
        title: "Wheel angle and reference",
        unit: "deg",
        lines: &[
            ("angle", |s| s.wheel_deg),
            ("reference", |s| s.wheel_ref_deg),
        ],
        least_y: [-5.0, 5.0],
        simulated_only: false,
    },
    Chart {
        id: "row",
        title: "Row from the camera, and the row filter's (GNSS or fused: offset at the rear axle, +- 1 s.d.)",
        unit: "cm / deg",
        lines: &[
            ("offset cm", |s| s.row_offset_cm),
            ("angle deg", |s| s.row_angle_deg),
            ("filter offset cm", |s| s.filter_offset_cm),
            ("filter -1 s.d.", |s| s.filter_low_cm),
            ("filter +1 s.d.", |s| s.filter_high_cm),
        ],
        least_y: [-5.0, 5.0],
        simulated_only: false,
    },
    Chart {
        id: "cross",
        title: "Cross-track error of the tool (simulated robot's truth)",
        unit: "cm",
        lines: &[("tool off row", |s| s.cross_track_cm)],
        least_y: [-3.0, 3.0],
        simulated_only: true,
    },
    Chart {
        id: "volts",
        title: "Motor voltages",
        unit: "V",
        lines: &[
            ("left", |s| s.amp_left_v),
            ("right", |s| s.amp_right_v),
            ("steering", |s| s.amp_steer_v),
        ],
        least_y: [-1.0, 1.0],
        simulated_only: false,
    },
];

/// The Plots tab: the thinned lines of the last frame, kept to be refilled.
#[derive(Default)]
pub struct Plots {
    /// One buffer per line, in the order of `CHARTS` and their lines.
    buffers: Vec<Vec<PlotPoint>>,
}

impl Plots {
    pub fn show(&mut self, ui: &mut egui::Ui, view: &View, shared: &SharedGui) {
        let simulated = view.simulated;
        let lines = CHARTS.iter().map(|c| c.lines.len()).sum();
        self.buffers.resize_with(lines, Vec::new);
        // Pixel columns of a plot: its width less the axis labels.
        let columns = (ui.available_width() - 60.0).max(50.0) as usize;
        let (count, capacity, paused) = {
            let mut shared = shared.lock();
            let samples = &mut shared.samples;
            let mut buffers = self.buffers.iter_mut();
            for chart in &CHARTS {
                for (_, value) in chart.lines {
                    let out = buffers.next().expect("one buffer per line");
                    if chart.simulated_only && !simulated {
                        out.clear();
                    } else {
                        thin(&samples.ring, *value, columns, out);
                    }
                }
            }
            (samples.ring.len(), samples.ring.capacity(), samples.paused)
        };
        ui.horizontal(|ui| {
            if ui.button(if paused { "Resume" } else { "Pause" }).clicked() {
                shared.lock().samples.paused = !paused;
            }
            ui.label(format!(
                "last {WINDOW_S:.0} s (time in s from now), {count} of {capacity} samples"
            ));
        });
        let mut first = 0;
        for chart in &CHARTS {
            let mine = &self.buffers[first..first + chart.lines.len()];
            first += chart.lines.len();
            if chart.simulated_only && !simulated {
                continue;
            }
            ui.label(chart.title);
            // The field's truth says nothing of rows that came from outside: no line.
            if let (true, Some(words)) = (chart.simulated_only, view.cross_track.instead()) {
                ui.label(RichText::new(words).strong());
                continue;
            }
            let unit = chart.unit;
            Plot::new(chart.id)
                .height(150.0)
                .legend(Legend::default())
                .allow_drag(false)
                .allow_zoom(false)
                .allow_scroll(false)
                .include_x(-WINDOW_S)
                .include_x(0.0)
                .include_y(chart.least_y[0])
                .include_y(chart.least_y[1])
                .y_axis_label(unit)
                .link_axis(egui::Id::unique("plots-time"), [true, false])
                .show(ui, |plot_ui| {
                    for ((name, _), points) in chart.lines.iter().zip(mine) {
                        plot_ui.line(Line::new(*name, PlotPoints::Borrowed(points)));
                    }
                });
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_chart_names_its_unit_and_spans_enough_for_ticks() {
        for chart in &super::CHARTS {
            assert!(!chart.unit.is_empty(), "{}", chart.id);
            let [low, high] = chart.least_y;
            assert!(high - low >= 1.0, "{}: {low}..{high}", chart.id);
        }
    }
}
