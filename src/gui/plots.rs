//! Live plots of the last 60 s: wheel speeds and their references, the wheel angle and
//! its reference, the row's offset and angle from the camera and the row filter's
//! estimate, the cross-track error of the simulated robot, and the motor voltages.
//!
//! Drawing is what costs a software renderer: each frame takes the samples' lock only
//! to thin every line to the plot's pixel columns into buffers kept from frame to
//! frame, then draws from those buffers with the lock released.

use eframe::egui::{self, RichText};
use egui_plot::{GridInput, Legend, Line, Plot, PlotPoint, PlotPoints, uniform_grid_spacer};

use super::pacer::SharedGui;
use super::plot_data::{Sample, WINDOW_S, thin};
use super::view::View;

/// The closest two grid lines may be, px (egui_plot's `base_step_size` is this many
/// pixels in the plot's unit).
const GRID_MIN_PX: f32 = 8.0;
/// A labelled y step is at least this tall, px: egui_plot labels from 20 px on.
const LABEL_PX: f64 = 30.0;

/// The y axis's steps: 1, 2 or 5 times a power of ten, the labelled one at least
/// LABEL_PX apart. egui_plot's own powers of ten left a 150 px plot of a few degrees
/// with a lone "0".
fn steps_1_2_5(input: GridInput) -> [f64; 3] {
    let least = input.base_step_size / f64::from(GRID_MIN_PX) * LABEL_PX;
    let decade = 10f64.powf(least.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .map(|m| m * decade)
        .into_iter()
        .find(|&s| s >= least)
        .unwrap_or(10.0 * decade);
    [step / 5.0, step, step * 5.0]
}

/// A tick's value with as many decimals as its step needs (0.5 is "0.5", not "0").
fn tick_label(value: f64, step: f64) -> String {
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    format!("{value:.decimals$}")
}

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
                .grid_spacing(GRID_MIN_PX..=300.0)
                .y_grid_spacer(uniform_grid_spacer(steps_1_2_5))
                .y_axis_formatter(|mark, _| tick_label(mark.value, mark.step_size))
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

    #[test]
    fn the_labelled_y_step_is_a_round_number_tall_enough_for_its_label() {
        // A plot of -6..6 deg, 120 px tall: 0.1 deg a pixel, 0.8 deg per 8 px.
        let input = egui_plot::GridInput {
            bounds: (-6.0, 6.0),
            base_step_size: 0.8,
        };
        let [_, step, _] = super::steps_1_2_5(input);
        assert_eq!(step, 5.0, "3 deg (30 px) rounds up to 5");
        assert_eq!(super::tick_label(0.5, 0.5), "0.5");
        assert_eq!(super::tick_label(-5.0, 5.0), "-5");
        assert_eq!(super::tick_label(0.25, 0.05), "0.25");
    }
}
