//! `mechweed probe [--raw]`: the first thing to run on the robot computer. It finds the
//! I/O cards, says where they are (PCI address, BAR, ports), reads every input once
//! through the wiring of robot.ini [io] and prints it in physical units; `--raw` adds
//! the cards' registers.
//!
//! It writes nothing but the safe outputs (and what reading needs: the A/D's channel
//! and start, the counters' latch; opening the QUAD04 resets its counters). The cards'
//! files are locked, so probe refuses to run beside `mechweed run`.

use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use mechweed_hw::cards::CardsHw;
use mechweed_hw::cards::das08::code_to_volts;
use mechweed_hw::cards::dda06::port_name;
use mechweed_hw::cards::quad04::CHANNELS;
use mechweed_hw::{Hw, HwError, OpenError};

use crate::config::Settings;
use crate::gamepad::PadMap;
use crate::gamepad::device::{self, Found};
use crate::programs::{load_settings, print_errors};
use crate::threads::backend::{DEV_PORT, PCI_DEVICES, open_cards};

/// Why the probe found nothing to print.
#[derive(Debug, thiserror::Error)]
pub enum ProbeError {
    /// The cards could not be found, opened or started (every card's problem).
    #[error(
        "the robot's I/O cards are not usable on this computer:\n{0}\nsee docs/robot-pc.md (in mechweed's source folder; /usr/share/doc/mechweed/robot-pc.md where the package is installed): giving the program its cards, step by step; mechweed doctor checks each card's file"
    )]
    NotUsable(OpenError),
    /// A card stopped answering while its inputs were read.
    #[error(transparent)]
    Read(#[from] HwError),
}

/// The input devices that look like gamepads, and whether each has the axes and button
/// [joystick] names; what could not be opened, with the reason.
pub fn gamepads(settings: &Settings, dir: &Path) -> String {
    let map = PadMap::new(&settings.gamepad, &settings.joystick);
    let mut out = format!("gamepads ({}):\n", dir.display());
    let (devices, refused) = match device::list(dir) {
        Ok(listed) => listed,
        Err(why) => return format!("{out}  none: {why}\n"),
    };
    let pads: Vec<Found> = devices
        .into_iter()
        .map(|(f, _)| f)
        .filter(Found::looks_like_gamepad)
        .collect();
    for pad in &pads {
        let fits = match device::lacks(pad, &map) {
            None => "fits [joystick]".to_string(),
            Some(missing) => format!("does not fit [joystick]: no {missing}"),
        };
        let _ = writeln!(out, "  {}  \"{}\"  {fits}", pad.path.display(), pad.name);
        let _ = writeln!(out, "    axes {}", pad.axes.join(" "));
        let _ = writeln!(out, "    buttons {}", pad.buttons.join(" "));
    }
    if pads.is_empty() {
        out += "  none\n";
    }
    for line in &refused {
        let _ = writeln!(
            out,
            "  not readable: {line} (see the udev rule in docs/gamepad.md)"
        );
    }
    out
}

/// Probe the cards of this computer.
pub fn probe(settings: &Settings, raw: bool) -> Result<String, ProbeError> {
    probe_at(settings, raw, Path::new(PCI_DEVICES), Path::new(DEV_PORT))
}

/// Probe the cards found under `pci_root` or through `dev_port`.
pub(crate) fn probe_at(
    settings: &Settings,
    raw: bool,
    pci_root: &Path,
    dev_port: &Path,
) -> Result<String, ProbeError> {
    let (mut hw, found) =
        open_cards(settings, pci_root, dev_port).map_err(ProbeError::NotUsable)?;
    let mut out = String::new();
    for line in found {
        let _ = writeln!(out, "found {line}");
    }
    out += &report(&mut hw, raw)?;
    Ok(out)
}

/// Every input once, in physical units with its wiring; with `raw`, the registers too.
pub fn report(hw: &mut CardsHw, raw: bool) -> Result<String, HwError> {
    let i = hw.read()?;
    let places = hw.wiring().places();
    let place = |key: &str| {
        places
            .iter()
            .find(|(k, _)| *k == key)
            .map_or(String::new(), |(_, p)| p.to_string())
    };
    let mut out = String::from("inputs (safe outputs written):\n");
    let volts = [
        ("pot_v", i.pot_v),
        ("joystick_steer_v", i.joystick_steer_v),
        ("joystick_speed_v", i.joystick_speed_v),
        ("battery_v", i.battery_v),
    ];
    for (key, v) in volts {
        let _ = writeln!(out, "  {key:<22} {v:>9.3} V       ({})", place(key));
    }
    let switches = [
        ("estop_front_released", i.estop_front_released),
        ("estop_back_released", i.estop_back_released),
        ("motor_power_present", i.motor_power_present),
        ("end_switch_left", i.end_switch_left),
        ("end_switch_right", i.end_switch_right),
        ("joystick_enable", i.joystick_enable),
    ];
    for (key, on) in switches {
        let word = if on { "yes" } else { "no" };
        let _ = writeln!(out, "  {key:<22} {word:>9}         ({})", place(key));
    }
    let counts = [
        ("enc_left_counts", i.enc_left_counts),
        ("enc_right_counts", i.enc_right_counts),
        ("enc_steer_counts", i.enc_steer_counts),
    ];
    for (key, n) in counts {
        let _ = writeln!(out, "  {key:<22} {n:>9} counts  ({})", place(key));
    }
    if raw {
        out += &registers(hw)?;
    }
    Ok(out)
}

/// The registers: DAS08 status and every A/D channel, the 8255 ports, each counter.
fn registers(hw: &mut CardsHw) -> Result<String, HwError> {
    let (das08, dda06, quad04) = hw.drivers();
    let mut out = String::from("registers:\n");
    let status = das08.read_status()?;
    let _ = writeln!(
        out,
        "  PCI-DAS08 +2 status {status:#04x} (EOC {}, IP3..IP1 {:03b}, mux {})",
        status >> 7,
        (status >> 4) & 0x07,
        status & 0x07
    );
    for channel in 0..8 {
        let code = das08.read_code(channel)?;
        let volts = code_to_volts(code);
        let _ = writeln!(
            out,
            "  PCI-DAS08 ai {channel}: code {code:#05x} ({code:4}) = {volts:+.4} V"
        );
    }
    for p in 0..3 {
        let byte = dda06.read_port(p)?;
        let _ = writeln!(
            out,
            "  PCIM-DDA06/16 8255 port {}: {byte:#04x} ({byte:08b})",
            port_name(p)
        );
    }
    for ch in 1..=CHANNELS {
        let flags = quad04.read_flags(ch)?;
        let count = quad04.read_raw(ch)?;
        let _ = writeln!(
            out,
            "  PCI-QUAD04 ch {ch}: count {count:#08x}, flags {flags:#04x}"
        );
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mechweed_hw::emulated::CardRig;

    #[test]
    fn prints_every_input_in_physical_units_with_its_wiring() {
        let s = Settings::shipped();
        let mut rig = CardRig::new(&s.cards, &s.io).unwrap();
        rig.das08.set_ai_volts(0, 2.5);
        rig.das08.set_ai_volts(3, 2.4);
        rig.das08.set_input(1, true);
        rig.quad04.set_encoder_edges(2, -12);
        let text = report(&mut rig.hw, false).unwrap();
        assert!(
            text.contains("pot_v                      2.500 V       (das08 ai 0)"),
            "{text}"
        );
        assert!(
            text.contains("battery_v                 23.999 V       (das08 ai 3)"),
            "{text}"
        );
        assert!(
            text.contains("estop_front_released         yes         (das08 ip 1)"),
            "{text}"
        );
        assert!(
            text.contains("estop_back_released           no         (das08 ip 2)"),
            "{text}"
        );
        assert!(
            text.contains("enc_right_counts             -12 counts  (quad04 ch 2)"),
            "{text}"
        );
        assert!(!text.contains("registers"));
        let raw = report(&mut rig.hw, true).unwrap();
        assert!(
            raw.contains("PCI-DAS08 ai 3: code 0xbd7 (3031) = +2.3999 V"),
            "{raw}"
        );
        assert!(raw.contains("PCI-QUAD04 ch 2: count 0xfffff4"), "{raw}");
        assert!(raw.contains("PCIM-DDA06/16 8255 port A: 0x00"), "{raw}");
    }

    #[test]
    fn without_cards_it_says_so() {
        let root = tempfile::tempdir().unwrap();
        let err = probe_at(
            &Settings::shipped(),
            false,
            root.path(),
            Path::new("/nonexistent"),
        )
        .unwrap_err()
        .to_string();
        assert!(err.starts_with("the robot's I/O cards are not usable on this computer"));
        assert!(
            err.contains("no PCI-DAS08 (PCI id 1307:0029) found"),
            "{err}"
        );
    }
}

#[derive(clap::Args)]
pub struct ProbeArgs {
    /// Also print the cards' registers.
    #[arg(long)]
    pub raw: bool,
    /// Show every input live, four times a second, from one opening of the cards
    /// (the counters keep counting), until Ctrl-C.
    #[arg(long, conflicts_with = "raw")]
    pub watch: bool,
    /// Settings file (card locations, wiring) [default: config/robot.ini, or the built-in copy]
    #[arg(long)]
    pub config: Option<PathBuf>,
}

/// `mechweed probe`: the gamepads, then every input of the cards once.
pub fn program(args: ProbeArgs) -> ExitCode {
    let ProbeArgs { raw, watch, config } = args;
    let settings = match load_settings(config.as_deref(), &[]) {
        Ok(s) => s,
        Err(errors) => {
            print_errors(&errors);
            crate::programs::safe::after_refusal(config.as_deref(), false);
            return ExitCode::FAILURE;
        }
    };
    let input_dir = std::path::Path::new(crate::gamepad::device::INPUT_DIR);
    print!("{}", crate::programs::probe::gamepads(&settings, input_dir));
    if watch {
        return watch_inputs(&settings);
    }
    match crate::programs::probe::probe(&settings, raw) {
        Ok(text) => {
            print!("{text}");
            ExitCode::SUCCESS
        }
        Err(why) => {
            eprintln!("{why}");
            ExitCode::FAILURE
        }
    }
}

/// `probe --watch`: open the cards once and show every input until Ctrl-C; the cards
/// get their safe outputs at the start and at the end.
fn watch_inputs(settings: &Settings) -> ExitCode {
    let stop = crate::console::ctrl_c();
    let opened = open_cards(settings, Path::new(PCI_DEVICES), Path::new(DEV_PORT));
    let (mut hw, found) = match opened {
        Ok(opened) => opened,
        Err(e) => {
            eprintln!("{}", ProbeError::NotUsable(e));
            return ExitCode::FAILURE;
        }
    };
    for line in found {
        println!("found {line}");
    }
    println!("every input from one opening of the cards (safe outputs written); Ctrl-C stops");
    let watched = crate::programs::probe_watch::watch(&mut hw, &settings.robot, &stop);
    drop(hw);
    match watched {
        Ok(()) => {
            println!("stopped; the outputs are safe");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}
