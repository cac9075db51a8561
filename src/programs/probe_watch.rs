//! `mechweed probe --watch`: every input live, from one opening of the cards, until
//! Ctrl-C. Opening the QUAD04 resets its counters, so a probe that opens the cards
//! again for each reading always shows about 0 counts; here they keep counting, and
//! each encoder's motion since the start is shown in metres or degrees, so that a
//! wheel turned forwards or the steering turned left by hand shows whether its count
//! rises (the sign check of docs/robot-pc.md, "Commissioning").

use std::fmt::Write as _;
use std::io::Write as _;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use mechweed_hw::cards::CardsHw;
use mechweed_hw::{Hw, HwError, Inputs};

use crate::config::RobotSettings;

/// How often a line is printed, s: fast enough to follow a hand on a wheel.
const EVERY_S: f64 = 0.25;

/// The column heads, printed first and again every 40 lines, each over its column.
pub fn header() -> String {
    let mut head = format!(
        "{:>7} {:>7} {:>8} {:>7} {:>7} {:>7}  {:<7} {:<7} {:<6} {:<5} {:<5} {:<7}",
        "t_s",
        "pot_v",
        "pot_deg",
        "joy_st",
        "joy_sp",
        "batt_v",
        "estop_f",
        "estop_b",
        "power",
        "end_l",
        "end_r",
        "deadman"
    );
    for (name, unit) in [
        ("enc_left", "(m)"),
        ("enc_right", "(m)"),
        ("enc_steer", "(deg)"),
    ] {
        let _ = write!(head, "  {name:>9} {unit:>9}");
    }
    head
}

/// The readings so far: the counts of the first, which later ones are counted from.
pub struct Watch {
    start_counts: [i64; 3],
    counts_per_m: f64,
    counts_per_deg: f64,
    pot_centre_v: f64,
    pot_v_per_deg: f64,
}

impl Watch {
    /// From the first reading of the cards just opened.
    pub fn new(first: &Inputs, robot: &RobotSettings) -> Watch {
        Watch {
            start_counts: [
                first.enc_left_counts,
                first.enc_right_counts,
                first.enc_steer_counts,
            ],
            counts_per_m: robot.enc_counts_per_m,
            counts_per_deg: robot.steer_counts_per_deg,
            pot_centre_v: robot.pot_centre_v,
            pot_v_per_deg: robot.pot_v_per_deg,
        }
    }

    /// One line for the inputs `i`, read `t_s` after the start.
    pub fn line(&self, i: &Inputs, t_s: f64) -> String {
        let word = |on: bool, yes: &'static str, no: &'static str| if on { yes } else { no };
        let pot_deg = (i.pot_v - self.pot_centre_v) / self.pot_v_per_deg;
        let mut line = format!(
            "{t_s:7.2} {:7.3} {pot_deg:+8.1} {:+7.2} {:+7.2} {:7.2}  {:<7} {:<7} {:<6} {:<5} {:<5} {:<7}",
            i.pot_v,
            i.joystick_steer_v,
            i.joystick_speed_v,
            i.battery_v,
            word(i.estop_front_released, "ok", "PRESSED"),
            word(i.estop_back_released, "ok", "PRESSED"),
            word(i.motor_power_present, "on", "off"),
            word(i.end_switch_left, "HIT", "-"),
            word(i.end_switch_right, "HIT", "-"),
            word(i.joystick_enable, "held", "-"),
        );
        let counts = [i.enc_left_counts, i.enc_right_counts, i.enc_steer_counts];
        let per = [self.counts_per_m, self.counts_per_m, self.counts_per_deg];
        for k in 0..3 {
            let moved = counts[k].wrapping_sub(self.start_counts[k]);
            let _ = write!(line, "  {moved:+9} ({:+7.3})", moved as f64 / per[k]);
        }
        line
    }
}

/// Read the cards every `EVERY_S` and print a line, until `stop` is set (Ctrl-C) or
/// a card stops answering (the error says which).
pub fn watch(hw: &mut CardsHw, robot: &RobotSettings, stop: &AtomicBool) -> Result<(), HwError> {
    let start = Instant::now();
    let watch = Watch::new(&hw.read()?, robot);
    let mut stdout = std::io::stdout();
    let mut lines = 0u64;
    while !stop.load(Ordering::SeqCst) {
        if lines.is_multiple_of(40) {
            let _ = writeln!(stdout, "{}", header());
        }
        let inputs = hw.read()?;
        let _ = writeln!(
            stdout,
            "{}",
            watch.line(&inputs, start.elapsed().as_secs_f64())
        );
        let _ = stdout.flush();
        lines += 1;
        std::thread::sleep(Duration::from_secs_f64(EVERY_S));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Settings;
    use mechweed_hw::emulated::CardRig;

    #[test]
    fn counts_keep_counting_from_one_opening_of_the_cards() {
        let s = Settings::shipped();
        let mut rig = CardRig::new(&s.cards, &s.io).unwrap();
        let watch = Watch::new(&rig.hw.read().unwrap(), &s.robot);
        // Someone turns the left wheel forwards by hand, 1 cm, then 1 cm more; and the
        // steering 3 deg right.
        let mut lines = Vec::new();
        for (k, edges) in [100, 200].into_iter().enumerate() {
            rig.quad04.set_encoder_edges(1, edges);
            rig.quad04.set_encoder_edges(3, -300);
            lines.push(watch.line(&rig.hw.read().unwrap(), k as f64 * 0.25));
        }
        assert!(lines[0].contains("      +100 ( +0.010)"), "{}", lines[0]);
        assert!(lines[1].contains("      +200 ( +0.020)"), "{}", lines[1]);
        assert!(lines[1].contains("      -300 ( -3.000)"), "{}", lines[1]);
        // Every column under its head.
        let head = header();
        assert_eq!(lines[1].len(), head.len(), "\n{head}\n{}", lines[1]);
    }
}
