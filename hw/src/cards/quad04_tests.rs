//! The QUAD04 driver against the emulated card: the initialisation sequence, counting,
//! the 24-bit wrap in both directions, a counter that stops and a card not there.

use super::*;
use crate::emulated::EmulatedQuad04;
use crate::emulated::recording::{Access, Recording};

fn open(card: &EmulatedQuad04) -> Quad04 {
    Quad04::open(Box::new(card.clone())).unwrap()
}

#[test]
fn open_initialises_every_channel_in_the_documented_order() {
    let card = EmulatedQuad04::new();
    let (port, log) = Recording::new(card.clone());
    Quad04::open(Box::new(port)).unwrap();
    let log = log.lock().unwrap();
    for ch in 0..4u16 {
        let (d, c) = (2 * ch, 2 * ch + 1);
        let expected = [
            Access::Write(c, 0x02),
            Access::Write(c, 0x04),
            Access::Write(c, 0x06),
            Access::Write(c, 0x01),
            Access::Write(d, 0x01),
            Access::Write(c, 0x18),
            Access::Write(c, 0x01),
            Access::Write(c, 0x38),
            Access::Write(c, 0x41),
            Access::Write(c, 0x60),
        ];
        let at = 10 * usize::from(ch);
        assert_eq!(log[at..at + 10], expected, "channel {}", ch + 1);
    }
    assert_eq!(
        log[40..42],
        [Access::Write(8, 0x0F), Access::Write(9, 0x00)]
    );
    let resets: Vec<Access> = (0..4).map(|ch| Access::Write(2 * ch + 1, 0x02)).collect();
    assert_eq!(log[42..46], resets[..]);
    for ch in 1..=4 {
        assert_eq!(card.counter(ch), (0, PRESCALER, 0x18), "channel {ch}");
    }
    assert_eq!(card.board_registers(), (0x0F, 0x00));
}

#[test]
fn a_count_is_latched_then_read_as_three_bytes_of_one_port() {
    let card = EmulatedQuad04::new();
    let (port, log) = Recording::new(card.clone());
    let mut quad = Quad04::open(Box::new(port)).unwrap();
    card.set_encoder_edges(3, 0x012345);
    log.lock().unwrap().clear();
    assert_eq!(quad.read_counts(3).unwrap(), 0x012345);
    let expected = [
        Access::Write(5, 0x11),
        Access::Read(4),
        Access::Read(4),
        Access::Read(4),
    ];
    assert_eq!(log.lock().unwrap()[..], expected);
}

#[test]
fn counts_from_zero_at_open_whatever_the_card_held_at_power_up() {
    let card = EmulatedQuad04::new();
    card.set_encoder_edges(1, 777); // before open: not counting yet, garbage in the counter
    let mut quad = open(&card);
    assert_eq!(quad.read_counts(1).unwrap(), 0);
    card.set_encoder_edges(1, 777 + 1000);
    assert_eq!(quad.read_counts(1).unwrap(), 1000);
    card.set_encoder_edges(1, 777 - 500);
    assert_eq!(quad.read_counts(1).unwrap(), -500);
}

#[test]
fn the_24_bit_wrap_is_unwrapped_both_ways() {
    let mut card = EmulatedQuad04::new();
    let mut quad = open(&card);
    // Preset channel 2 to 0xFFFFFD (that is, -3) through its registers.
    card.write_u8(3, 0x01).unwrap();
    for byte in [0xFD, 0xFF, 0xFF] {
        card.write_u8(2, byte).unwrap();
    }
    card.write_u8(3, 0x08).unwrap();
    assert_eq!(quad.read_counts(2).unwrap(), -3);
    card.set_encoder_edges(2, 10); // up across 0xFFFFFF -> 0
    assert_eq!(quad.read_counts(2).unwrap(), 7);
    assert_eq!(quad.read_raw(2).unwrap(), 7);
    card.set_encoder_edges(2, -10); // down across 0 -> 0xFFFFFF
    assert_eq!(quad.read_counts(2).unwrap(), -13);
    assert_eq!(quad.read_raw(2).unwrap(), 0xFF_FFF3);

    // Many wraps, in steps of 5 million counts (under 2^23), up then down.
    let mut edges = -10i64;
    for _ in 0..20 {
        edges += 5_000_000;
        card.set_encoder_edges(2, edges);
        assert_eq!(quad.read_counts(2).unwrap(), edges - 3);
    }
    for _ in 0..45 {
        edges -= 5_000_000;
        card.set_encoder_edges(2, edges);
        assert_eq!(quad.read_counts(2).unwrap(), edges - 3);
    }
    assert!(edges < -(1 << 26), "wrapped several times below zero");
}

#[test]
fn steps_are_signed_24_bit_differences() {
    assert_eq!(step_24(0xFF_FFFF, 0), 1);
    assert_eq!(step_24(0, 0xFF_FFFF), -1);
    assert_eq!(step_24(0, 0x7F_FFFF), 8_388_607);
    assert_eq!(step_24(0, 0x80_0000), -8_388_608);
    assert_eq!(step_24(0x12_3456, 0x12_3456), 0);
}

#[test]
fn a_counter_that_stops_holds_its_count_while_the_others_go_on() {
    let card = EmulatedQuad04::new();
    let mut quad = open(&card);
    card.set_encoder_edges(1, 100);
    card.set_encoder_edges(2, 100);
    assert_eq!(quad.read_counts(2).unwrap(), 100);
    card.stop_counter(2);
    card.set_encoder_edges(1, 400);
    card.set_encoder_edges(2, 400);
    assert_eq!(quad.read_counts(1).unwrap(), 400);
    assert_eq!(
        quad.read_counts(2).unwrap(),
        100,
        "the stopped counter holds"
    );
}

#[test]
fn a_card_that_reads_0xff_is_an_error_at_open_and_later() {
    let card = EmulatedQuad04::new();
    card.set_dead(true);
    let Err(err) = Quad04::open(Box::new(card.clone())) else {
        panic!("a dead card opened")
    };
    assert!(
        err.to_string().starts_with("PCI-QUAD04 stopped answering"),
        "{err}"
    );

    card.set_dead(false);
    let mut quad = open(&card);
    card.set_dead(true);
    let err = quad.read_counts(1).unwrap_err();
    assert!(err.to_string().contains("reads 0xFF"), "{err}");
}

#[test]
fn a_count_of_all_ones_on_a_live_card_is_minus_one() {
    let card = EmulatedQuad04::new();
    let mut quad = open(&card);
    card.set_encoder_edges(4, -1);
    assert_eq!(quad.read_counts(4).unwrap(), -1);
}
