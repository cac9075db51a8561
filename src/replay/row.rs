//! One row of a record's tick table read back, column by column, as what the
//! supervisor tick was given and what it wrote; every cell that is not what its column
//! holds is named with its line.

use mechweed_hw::camproto::RowEstimate;
use mechweed_hw::cards::{das08, dda06, quad04};
use mechweed_hw::{Inputs, Outputs, Side};

use super::recorded::RecordedTick;
use crate::camlink::LinkStatus;
use crate::record::read::Table;
use crate::record::{Given, HwFailure, Place};
use crate::rt::health::{ThreadHealth, ThreadName};
use crate::state::modes::Mode;
use crate::state::steering::Steering;
use crate::steer::law::LawOutput;
use crate::steer::{EndSwitchState, RowFigures, SourceHealth, SteerCommand};

/// Every column a replay reads.
pub(crate) const WANTED: &[&str] = &[
    "t_s",
    "tick",
    "mode",
    "pot_v",
    "joystick_steer_v",
    "joystick_speed_v",
    "battery_v",
    "estop_front_released",
    "estop_back_released",
    "motor_power_present",
    "end_switch_left",
    "end_switch_right",
    "joystick_enable",
    "enc_left_counts",
    "enc_right_counts",
    "enc_steer_counts",
    "amp_left_v",
    "amp_right_v",
    "amp_steer_v",
    "main_power_on",
    "brake_release_left",
    "brake_release_right",
    "tool_on",
    "steer_speed_mps",
    "steer_wheel_angle_rad",
    "steer_t_s",
    "steer_mode",
    "steer_endswitch",
    "steer_endswitch_since_s",
    "steer_endswitch_done",
    "steer_endswitch_last",
    "steering",
    "steer_camera_good_s",
    "steer_gnss_good_s",
    "filter_offset_m",
    "link_last_row_s",
    "link_last_usable_s",
    "link_beat_s",
    "gui_beat_s",
    "thread_panicked",
    "supervisor_overruns",
    "hw_failed",
    "hw_failed_card",
    // Not given to the supervisor, but kept in a what-if's record.
    "law_lookahead_offset_m",
    "law_tool_offset_m",
    "law_row_curvature_per_m",
    "law_integral_per_m",
    "cam_offset_m",
    "cam_angle_rad",
    "cam_quality",
    "cam_seq",
    "cam_frames_ok",
    "cam_crc_errors",
    "cam_seq_gaps",
    "cam_duplicates",
    "cam_connected",
    // What the supervisor judges the sensors by before it takes Autonomous (records
    // made before these columns lack them: record::read::ADDED_LATER).
    "gnss_heard_s",
    "link_streaming_since_s",
    "link_heard_s",
];

/// One row of the tick table, read column by column.
pub struct Row<'a> {
    pub table: &'a Table,
    pub row: usize,
}

impl Row<'_> {
    fn place(&self) -> &Place {
        &self.table.places[self.row]
    }

    fn col(&self, name: &str) -> usize {
        self.table.column(name).expect("asked for in WANTED")
    }

    /// A number; None for an empty cell.
    fn maybe(&self, name: &str) -> Result<Option<f64>, String> {
        self.table
            .number(self.row, self.col(name))
            .map_err(|e| format!("{e}"))
    }

    fn num_or_nan(&self, name: &str) -> Result<f64, String> {
        Ok(self.maybe(name)?.unwrap_or(f64::NAN))
    }

    fn num(&self, name: &str) -> Result<f64, String> {
        self.maybe(name)?
            .ok_or_else(|| format!("{}: {name} is empty", self.place()))
    }

    /// A time that may not have happened yet: empty is "never" (minus infinity).
    fn time_or_never(&self, name: &str) -> Result<f64, String> {
        Ok(self.maybe(name)?.unwrap_or(f64::NEG_INFINITY))
    }

    fn whole(&self, name: &str) -> Result<i64, String> {
        let x = self.num(name)?;
        if x.fract() != 0.0 || x.abs() > 9.0e15 {
            return Err(format!(
                "{}: {name} = {x} is not a whole number",
                self.place()
            ));
        }
        Ok(x as i64)
    }

    /// A whole number that fits its kind (a count, a sequence number, a quality).
    fn count<T: TryFrom<i64>>(&self, name: &str) -> Result<T, String> {
        let x = self.whole(name)?;
        T::try_from(x).map_err(|_| format!("{}: {name} = {x} is out of its range", self.place()))
    }

    fn flag(&self, name: &str) -> Result<bool, String> {
        match self.whole(name)? {
            0 => Ok(false),
            1 => Ok(true),
            other => Err(format!(
                "{}: {name} = {other} is neither 0 nor 1",
                self.place()
            )),
        }
    }

    fn text(&self, name: &str) -> String {
        self.table.text(self.row, self.col(name))
    }

    fn word<T>(
        &self,
        name: &str,
        read: impl Fn(&str) -> Option<T>,
        what: &str,
    ) -> Result<T, String> {
        let text = self.text(name);
        read(&text).ok_or_else(|| format!("{}: {name} = '{text}' is not {what}", self.place()))
    }

    /// The tick this row records: what the supervisor was given, and what it wrote.
    pub fn tick(&self) -> Result<RecordedTick, String> {
        Ok(RecordedTick {
            tick: self.count("tick")?,
            t_s: self.num("t_s")?,
            inputs: self.inputs()?,
            steer: self.steer()?,
            link: self.link()?,
            given: self.given()?,
            outputs: self.outputs()?,
            mode: self.word("mode", Mode::from_name, "a mode")?,
            place: self.place().clone(),
        })
    }

    /// Every input the tick read.
    fn inputs(&self) -> Result<Inputs, String> {
        let inputs = Inputs {
            pot_v: self.num("pot_v")?,
            joystick_steer_v: self.num("joystick_steer_v")?,
            joystick_speed_v: self.num("joystick_speed_v")?,
            battery_v: self.num("battery_v")?,
            estop_front_released: self.flag("estop_front_released")?,
            estop_back_released: self.flag("estop_back_released")?,
            motor_power_present: self.flag("motor_power_present")?,
            end_switch_left: self.flag("end_switch_left")?,
            end_switch_right: self.flag("end_switch_right")?,
            joystick_enable: self.flag("joystick_enable")?,
            enc_left_counts: self.whole("enc_left_counts")?,
            enc_right_counts: self.whole("enc_right_counts")?,
            enc_steer_counts: self.whole("enc_steer_counts")?,
        };
        Ok(inputs)
    }

    /// The steer command the tick copied in.
    fn steer(&self) -> Result<SteerCommand, String> {
        let endswitch = match self.word("steer_endswitch", side, "left, right or empty")? {
            None => EndSwitchState::Idle,
            Some(side) => EndSwitchState::Active {
                side,
                since_s: self.num("steer_endswitch_since_s")?,
            },
        };
        let steer = SteerCommand {
            t_s: self.num("steer_t_s")?,
            mode: self.word("steer_mode", Mode::from_name, "a mode")?,
            speed_mps: self.num("steer_speed_mps")?,
            wheel_angle_rad: self.num("steer_wheel_angle_rad")?,
            endswitch,
            endswitch_done_count: self.count("steer_endswitch_done")?,
            endswitch_last_side: self.word("steer_endswitch_last", side, "left, right or empty")?,
            sources: SourceHealth {
                steering: self.word(
                    "steering",
                    Steering::from_name,
                    "camera, fused, camera_alone, gnss_alone or nothing",
                )?,
                camera_good_s: self.time_or_never("steer_camera_good_s")?,
                gnss_good_s: self.time_or_never("steer_gnss_good_s")?,
                // Empty while the camera steers alone: no filter, no row offset of its.
                row_offset_m: Some(self.num_or_nan("filter_offset_m")?)
                    .filter(|m| !m.is_nan())
                    .unwrap_or(0.0),
                // Not recorded: it only words the notice of a change, which a replay
                // compares by the change itself.
                why: None,
                // Not recorded either: a record of a start that looked for its first
                // plants replays as one that saw none.
                searching: false,
            },
            law: LawOutput {
                wheel_angle_rad: f64::NAN,
                lookahead_offset_m: self.num_or_nan("law_lookahead_offset_m")?,
                tool_offset_m: self.num_or_nan("law_tool_offset_m")?,
                row_curvature_per_m: self.num_or_nan("law_row_curvature_per_m")?,
                integral_per_m: self.num_or_nan("law_integral_per_m")?,
            },
            row: RowFigures {
                gnss_heard_s: self.gnss_heard_s()?,
                ..RowFigures::default()
            },
            ..SteerCommand::default()
        };
        Ok(steer)
    }

    /// When the receiver was last heard. A record from before the column was kept says
    /// nothing: the receiver is taken as heard at the tick, as the supervisor of its day
    /// took Autonomous without asking.
    fn gnss_heard_s(&self) -> Result<Option<f64>, String> {
        if self.table.absent.iter().any(|c| c == "gnss_heard_s") {
            return Ok(Some(self.num("steer_t_s")?));
        }
        self.maybe("gnss_heard_s")
    }

    /// The camera link's status the tick copied in.
    fn link(&self) -> Result<LinkStatus, String> {
        let mut link = LinkStatus {
            last_row_s: self.time_or_never("link_last_row_s")?,
            last_usable_s: self.time_or_never("link_last_usable_s")?,
            beat_s: self.num("link_beat_s")?,
            last_usable: RowEstimate {
                seq: self.count("cam_seq")?,
                angle_rad: self.num_or_nan("cam_angle_rad")?,
                offset_m: self.num_or_nan("cam_offset_m")?,
                quality: self.count("cam_quality")?,
            },
            connected: self.flag("cam_connected")?,
            ..LinkStatus::default()
        };
        if let Some(since_s) = self.maybe("link_streaming_since_s")? {
            (link.streaming, link.streaming_since_s) = (true, since_s);
        }
        // A record from before the column: the camera taken as heard at the tick.
        link.heard_s = if self.table.absent.iter().any(|c| c == "link_heard_s") {
            link.beat_s
        } else {
            self.time_or_never("link_heard_s")?
        };
        let c = &mut link.counters;
        c.frames_ok = self.count("cam_frames_ok")?;
        c.crc_errors = self.count("cam_crc_errors")?;
        c.seq_gaps = self.count("cam_seq_gaps")?;
        c.duplicates = self.count("cam_duplicates")?;
        Ok(link)
    }

    /// The threads' health and any card that failed.
    fn given(&self) -> Result<Given, String> {
        let panicked = |t: &str| {
            if t.is_empty() {
                Some(None)
            } else {
                ThreadName::from_label(t).map(Some)
            }
        };
        let health = ThreadHealth {
            gui_beat_s: self.maybe("gui_beat_s")?,
            panicked: self.word("thread_panicked", panicked, "a thread's name")?,
            supervisor_overruns: self.count("supervisor_overruns")?,
            // Not in the record: a replayed timing fault names no load.
            cpu_load: None,
        };
        let card = |t: &str| {
            [das08::NAME, dda06::NAME, quad04::NAME]
                .into_iter()
                .find(|c| *c == t)
        };
        let hw_failed = match self.text("hw_failed").as_str() {
            "" => None,
            "read" => Some(HwFailure {
                during: "read",
                card: self.word("hw_failed_card", card, "a card")?,
            }),
            "write" => Some(HwFailure {
                during: "write",
                card: self.word("hw_failed_card", card, "a card")?,
            }),
            other => {
                return Err(format!(
                    "{}: hw_failed = '{other}' is not read, write or empty",
                    self.place()
                ));
            }
        };
        Ok(Given { health, hw_failed })
    }

    /// Every output the tick wrote.
    fn outputs(&self) -> Result<Outputs, String> {
        let outputs = Outputs {
            amp_left_v: self.num("amp_left_v")?,
            amp_right_v: self.num("amp_right_v")?,
            amp_steer_v: self.num("amp_steer_v")?,
            main_power_on: self.flag("main_power_on")?,
            brake_release_left: self.flag("brake_release_left")?,
            brake_release_right: self.flag("brake_release_right")?,
            tool_on: self.flag("tool_on")?,
        };
        Ok(outputs)
    }
}

/// An end switch's side as recorded: empty is none.
fn side(t: &str) -> Option<Option<Side>> {
    match t {
        "" => Some(None),
        "left" => Some(Some(Side::Left)),
        "right" => Some(Some(Side::Right)),
        _ => None,
    }
}
