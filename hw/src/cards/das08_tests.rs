//! The DAS08 driver against the emulated card: the register sequence, the outputs'
//! shadow, the A/D scaling, and the card that never finishes or is not there.

use std::time::{Duration, Instant};

use super::*;
use crate::emulated::EmulatedDas08;
use crate::emulated::recording::{Access, Recording};

const TIMEOUT: Duration = Duration::from_micros(200);

fn open(card: &EmulatedDas08) -> Das08 {
    Das08::open(Box::new(card.clone()), 0, TIMEOUT).unwrap()
}

#[test]
fn open_writes_the_safe_outputs_before_anything_else() {
    let card = EmulatedDas08::new();
    assert!(
        card.output(1),
        "the emulated card powers up with its outputs on"
    );
    let (port, log) = Recording::new(card.clone());
    Das08::open(Box::new(port), 0, TIMEOUT).unwrap();
    assert_eq!(log.lock().unwrap()[0], Access::Write(2, 0x00));
    assert!((1..=4).all(|n| !card.output(n)));
}

#[test]
fn a_conversion_follows_the_manuals_sequence() {
    let card = EmulatedDas08::new();
    card.set_busy_reads(2);
    let (port, log) = Recording::new(card.clone());
    let mut das = Das08::open(Box::new(port), 0b0101, TIMEOUT).unwrap();
    log.lock().unwrap().clear();
    das.read_code(3).unwrap();
    let expected = [
        Access::Write(2, 0x53), // outputs OP1 and OP3 with channel 3
        Access::Write(1, 0),    // start a 12-bit conversion
        Access::Read(2),        // busy
        Access::Read(2),        // busy
        Access::Read(2),        // done
        Access::Read(1),
        Access::Read(0),
    ];
    assert_eq!(log.lock().unwrap()[..], expected);
    assert!(card.output(1) && !card.output(2) && card.output(3) && !card.output(4));
}

#[test]
fn volts_are_read_to_one_step_across_the_range() {
    let card = EmulatedDas08::new();
    let mut das = open(&card);
    for (channel, volts) in [(0, 0.5), (1, -4.0), (2, 4.0), (3, 2.4), (4, 0.0), (7, -5.0)] {
        card.set_ai_volts(channel, volts);
        let read = das.read_volts(channel as u8).unwrap();
        assert!(
            (read - volts).abs() <= 2.45e-3,
            "channel {channel}: {read} V"
        );
    }
    card.set_ai_volts(5, 7.0);
    assert_eq!(
        das.read_code(5).unwrap(),
        4095,
        "beyond +5 V reads full scale"
    );
    assert!((code_to_volts(4095) - 4.9976).abs() < 1e-4);
}

#[test]
fn digital_inputs_come_from_status_bits_6_to_4() {
    let card = EmulatedDas08::new();
    let mut das = open(&card);
    card.set_input(1, true);
    card.set_input(3, true);
    assert_eq!(das.read_inputs().unwrap(), 0b101);
    card.set_input(1, false);
    card.set_input(2, true);
    assert_eq!(das.read_inputs().unwrap(), 0b110);
}

#[test]
fn a_slow_conversion_is_waited_for() {
    let card = EmulatedDas08::new();
    card.set_busy_reads(30);
    let mut das = open(&card);
    card.set_ai_volts(0, 1.0);
    assert!((das.read_volts(0).unwrap() - 1.0).abs() < 2.45e-3);
}

#[test]
fn an_a_d_that_never_finishes_is_an_error_naming_the_card_within_the_time_out() {
    let card = EmulatedDas08::new();
    let mut das = open(&card);
    card.set_eoc_stuck(true);
    let start = Instant::now();
    let err = das.read_code(2).unwrap_err();
    let took = start.elapsed();
    assert!(took >= TIMEOUT, "gave up after {took:?}");
    assert!(took < TIMEOUT + Duration::from_millis(20), "took {took:?}");
    let HwError::CardNotAnswering {
        card: name,
        register,
        fault,
    } = err;
    assert_eq!(name, "PCI-DAS08");
    assert_eq!(register, 2, "the status register");
    assert!(
        matches!(fault, CardFault::ConversionTimeout { channel: 2, .. }),
        "{fault:?}"
    );
    let text = err.to_string();
    assert!(
        text.contains("did not finish a conversion of channel 2"),
        "{text}"
    );
    assert!(text.starts_with("PCI-DAS08 stopped answering"));
}

#[test]
fn a_card_that_reads_0xff_is_an_error_at_open_and_at_once_later() {
    let card = EmulatedDas08::new();
    card.set_dead(true);
    let Err(err) = Das08::open(Box::new(card.clone()), 0, TIMEOUT) else {
        panic!("a dead card opened")
    };
    assert!(err.to_string().contains("reads 0xFF"), "{err}");

    card.set_dead(false);
    let mut das = open(&card);
    card.set_dead(true);
    let start = Instant::now();
    let err = das.read_code(0).unwrap_err();
    assert!(
        start.elapsed() < TIMEOUT,
        "found without waiting for the time-out"
    );
    assert!(err.to_string().contains("PCI-DAS08"), "{err}");
    assert!(das.read_inputs().is_err());
}

#[test]
fn a_wait_cut_short_by_the_clock_still_asks_the_card_a_few_times() {
    // A zero time-out stands for a thread preempted for longer than the time-out
    // right after the start: a card that finishes within a few reads is not blamed.
    let card = EmulatedDas08::new();
    card.set_busy_reads(5);
    let mut das = Das08::open(Box::new(card.clone()), 0, Duration::ZERO).unwrap();
    card.set_ai_volts(2, -1.5);
    assert!((das.read_volts(2).unwrap() + 1.5).abs() < 2.45e-3);
    card.set_eoc_stuck(true);
    assert!(das.read_code(2).is_err(), "a stuck one still is");
}
