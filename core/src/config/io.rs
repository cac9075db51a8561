//! The I/O cards' settings in [hw] (where each card is, the DDA06's range switches,
//! the A/D time-out) and the robot's wiring in [io]. The text of each [io] line is
//! parsed by the hardware crate (mechweed_hw::cards::wiring), which knows the cards; errors
//! here name the key, and a wiring that puts two signals on one channel blames the
//! second key (the watchdog output, last, for its clashes).

use mechweed_hw::cards::CardsSettings;
use mechweed_hw::cards::dda06::{DACS, DacRange};
use mechweed_hw::cards::pci::{CardLocation, parse_pci_address};
use mechweed_hw::cards::wiring::{
    self, AnalogIn, AnalogOut, Bit, Encoder, Switch, Wiring, parse_analog_in, parse_analog_out,
    parse_encoder, parse_second_contact, parse_switch_in, parse_switch_out, parse_watchdog,
};

use super::reader::Reader;

/// `auto`, `none`, or a PCI address.
fn pci(text: &str) -> Result<Option<CardLocation>, String> {
    match text {
        "auto" => Ok(Some(CardLocation::PciAuto)),
        "none" => Ok(None),
        address => parse_pci_address(address)
            .map(|a| Some(CardLocation::PciAddress(a)))
            .map_err(|e| format!("{e}; or auto, or none")),
    }
}

/// `none`, or an I/O port number (hex 0x.. or decimal).
fn port_base(text: &str) -> Result<Option<u16>, String> {
    if text == "none" {
        return Ok(None);
    }
    let number = match text.strip_prefix("0x") {
        Some(hex) => u16::from_str_radix(hex, 16),
        None => text.parse::<u16>(),
    };
    number
        .map(Some)
        .map_err(|_| format!("'{text}' is not an I/O port number (0x0000..0xffff) or none"))
}

/// Where card `prefix` is: exactly one of `PREFIX_pci` and `PREFIX_port_base` is set.
fn location(r: &mut Reader, prefix: &str) -> CardLocation {
    let pci_key = format!("{prefix}_pci");
    let base_key = format!("{prefix}_port_base");
    let pci = r.parsed("hw", &pci_key, pci);
    let base = r.parsed("hw", &base_key, port_base);
    match (pci, base) {
        (Some(Some(location)), Some(None)) => location,
        (Some(None), Some(Some(base))) => CardLocation::PortBase(base),
        (Some(None), Some(None)) => {
            let what = format!("set {pci_key} (auto or an address) or {base_key}");
            r.error_at("hw", &pci_key, what);
            CardLocation::PciAuto
        }
        (Some(Some(_)), Some(Some(_))) => {
            let what = format!("set {pci_key} = none to use {base_key}, or {base_key} = none");
            r.error_at("hw", &pci_key, what);
            CardLocation::PciAuto
        }
        // Already reported.
        _ => CardLocation::PciAuto,
    }
}

/// Six ranges, AO0..AO5, comma-separated.
fn ranges(text: &str) -> Result<[DacRange; DACS], String> {
    let items: Vec<&str> = text.split(',').collect();
    if items.len() != DACS {
        return Err(format!(
            "needs six ranges (AO0..AO5), comma-separated; found {}",
            items.len()
        ));
    }
    let mut ranges = [DacRange::Bipolar5; DACS];
    for (n, item) in items.iter().enumerate() {
        ranges[n] = DacRange::parse(item).map_err(|e| format!("AO{n}: {e}"))?;
    }
    Ok(ranges)
}

pub(super) fn cards(r: &mut Reader) -> CardsSettings {
    CardsSettings {
        das08: location(r, "das08"),
        dda06: location(r, "dda06"),
        quad04: location(r, "quad04"),
        dda06_ranges: r
            .parsed("hw", "dda06_ranges_v", ranges)
            .unwrap_or([DacRange::Bipolar5; DACS]),
        das08_eoc_timeout_us: r.f64("hw", "das08_eoc_timeout_us", 20.0, 10_000.0),
    }
}

/// Stand-ins when a line has an error: the settings are refused anyway.
const NO_AI: AnalogIn = AnalogIn {
    channel: 0,
    scale: 1.0,
};
const NO_AO: AnalogOut = AnalogOut {
    channel: 0,
    scale: 1.0,
};
const NO_ENCODER: Encoder = Encoder {
    channel: 1,
    sign: 1,
};
const NO_SWITCH: Switch = Switch {
    bit: Bit::Das08In(1),
    active_high: true,
};

/// One [io] line, or `stand_in` if it cannot be read (the error is recorded).
fn line<T>(
    r: &mut Reader,
    key: &str,
    parse: fn(&str) -> Result<T, String>,
    stand_in: T,
    all_read: &mut bool,
) -> T {
    r.parsed("io", key, parse).unwrap_or_else(|| {
        *all_read = false;
        stand_in
    })
}

/// [io] joystick_released: optional, so that a file from before it reads as a
/// dead-man with one contact.
fn second_contact(r: &mut Reader, all_read: &mut bool) -> Option<Switch> {
    r.optional("io", "joystick_released")?;
    line(r, "joystick_released", parse_second_contact, None, all_read)
}

pub(super) fn wiring(r: &mut Reader) -> Wiring {
    let ok = &mut true;
    let (ai, aout, enc) = (parse_analog_in, parse_analog_out, parse_encoder);
    let (sw_in, sw_out) = (parse_switch_in, parse_switch_out);
    let w = Wiring {
        pot_v: line(r, "pot_v", ai, NO_AI, ok),
        joystick_steer_v: line(r, "joystick_steer_v", ai, NO_AI, ok),
        joystick_speed_v: line(r, "joystick_speed_v", ai, NO_AI, ok),
        battery_v: line(r, "battery_v", ai, NO_AI, ok),
        estop_front_released: line(r, "estop_front_released", sw_in, NO_SWITCH, ok),
        estop_back_released: line(r, "estop_back_released", sw_in, NO_SWITCH, ok),
        motor_power_present: line(r, "motor_power_present", sw_in, NO_SWITCH, ok),
        end_switch_left: line(r, "end_switch_left", sw_in, NO_SWITCH, ok),
        end_switch_right: line(r, "end_switch_right", sw_in, NO_SWITCH, ok),
        joystick_enable: line(r, "joystick_enable", sw_in, NO_SWITCH, ok),
        joystick_released: second_contact(r, ok),
        enc_left_counts: line(r, "enc_left_counts", enc, NO_ENCODER, ok),
        enc_right_counts: line(r, "enc_right_counts", enc, NO_ENCODER, ok),
        enc_steer_counts: line(r, "enc_steer_counts", enc, NO_ENCODER, ok),
        amp_left_v: line(r, "amp_left_v", aout, NO_AO, ok),
        amp_right_v: line(r, "amp_right_v", aout, NO_AO, ok),
        amp_steer_v: line(r, "amp_steer_v", aout, NO_AO, ok),
        main_power_on: line(r, "main_power_on", sw_out, NO_SWITCH, ok),
        brake_release_left: line(r, "brake_release_left", sw_out, NO_SWITCH, ok),
        brake_release_right: line(r, "brake_release_right", sw_out, NO_SWITCH, ok),
        tool_on: line(r, "tool_on", sw_out, NO_SWITCH, ok),
        watchdog: line(r, "watchdog", parse_watchdog, None, ok),
    };
    // Clashes between lines mean something only when every line could be read.
    if *ok {
        for (key, what) in wiring::check(&w) {
            r.error_at("io", key, what);
        }
    }
    w
}
