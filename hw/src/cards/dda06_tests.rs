//! The DDA06 driver against the emulated card: codes per range, the order of the
//! writes at open, the 8255 directions and the switches on port A.

use super::*;
use crate::emulated::EmulatedDda06;
use crate::emulated::recording::{Access, Recording};
use DacRange::*;

const RANGES: [DacRange; 6] = [
    Bipolar10, Bipolar10, Bipolar10, Bipolar5, Unipolar10, Unipolar5,
];

fn open(card: &EmulatedDda06) -> Dda06 {
    Dda06::open(
        Box::new(card.clone()),
        RANGES,
        PortDirections::default(),
        [0; 3],
    )
    .unwrap()
}

#[test]
fn codes_are_offset_binary_on_bipolar_ranges_and_clamped() {
    assert_eq!(Bipolar10.code(0.0), 0x8000);
    assert_eq!(Bipolar10.code(5.0), 0xC000);
    assert_eq!(Bipolar10.code(-10.0), 0x0000);
    assert_eq!(
        Bipolar10.code(10.0),
        0xFFFF,
        "+full scale is one step short"
    );
    assert_eq!(Bipolar10.code(25.0), 0xFFFF);
    assert_eq!(Bipolar5.code(-2.5), 0x4000);
    assert_eq!(Unipolar10.code(5.0), 0x8000);
    assert_eq!(Unipolar10.code(-3.0), 0x0000);
    assert_eq!(Unipolar5.code(5.0), 0xFFFF);
    for range in DacRange::ALL {
        assert_eq!(range.code(f64::NAN), range.zero_code(), "{range:?}");
        assert_eq!(range.code(f64::INFINITY), range.zero_code(), "{range:?}");
    }
}

#[test]
fn ranges_parse_as_written_in_robot_ini() {
    for range in DacRange::ALL {
        assert_eq!(DacRange::parse(range.name()), Ok(range));
    }
    assert!(DacRange::parse("+-20").unwrap_err().contains("not one of"));
}

#[test]
fn every_range_puts_the_asked_volts_on_the_output() {
    let card = EmulatedDda06::new(RANGES);
    let mut dda = open(&card);
    let asked = [7.3, -9.99, 0.0, -4.2, 3.3, 4.9];
    for (n, &volts) in asked.iter().enumerate() {
        dda.write_volts(n, volts).unwrap();
        let step = RANGES[n].full_scale_v() / 32768.0;
        assert!(
            (card.dac_volts(n) - volts).abs() <= step,
            "DAC {n}: {}",
            card.dac_volts(n)
        );
    }
    dda.write_volts(4, -5.0).unwrap();
    assert_eq!(card.dac_volts(4), 0.0, "a unipolar range clamps at 0 V");
    dda.write_volts(0, 12.0).unwrap();
    assert!(
        (card.dac_volts(0) - 10.0).abs() < 1e-3,
        "clamped at +full scale"
    );
}

#[test]
fn open_zeroes_every_dac_then_configures_the_8255_then_its_outputs() {
    let card = EmulatedDda06::new(RANGES);
    let (port, log) = Recording::new(card.clone());
    let directions = PortDirections {
        output_bits: [0, 0x01, 0],
    };
    Dda06::open(Box::new(port), RANGES, directions, [0, 0x01, 0]).unwrap();
    let log = log.lock().unwrap();
    let dacs: Vec<Access> = (0..6u16)
        .flat_map(|n| {
            let [low, high] = RANGES[n as usize].zero_code().to_le_bytes();
            [Access::Write(2 * n, low), Access::Write(2 * n + 1, high)]
        })
        .collect();
    assert_eq!(log[..12], dacs[..]);
    assert_eq!(log[12], Access::Write(0x0F, 0x99), "A and C in, B out");
    assert_eq!(log[13], Access::Write(0x0D, 0x01));
    assert_eq!(log.len(), 14);
    assert!(
        card.pin(1, 0),
        "the output set after the control word stays set"
    );
}

#[test]
fn the_robots_wiring_makes_every_port_an_input_and_reads_the_switches() {
    assert_eq!(PortDirections::default().control_word(), 0x9B);
    let card = EmulatedDda06::new(RANGES);
    let mut dda = open(&card);
    card.set_pin(0, 0, true);
    card.set_pin(0, 2, true);
    assert_eq!(dda.read_port(0).unwrap(), 0b101);
    card.set_pin(0, 0, false);
    assert_eq!(dda.read_port(0).unwrap(), 0b100);
}
