//! The watchdog output for a charge-pump relay (robot.ini `[io] watchdog`), through the
//! settings file and through the real supervisor on the emulated cards: it changes
//! every supervisor tick while the controller runs, and stops when a card fails.

use crate::common;

use std::process::Command;

use common::settings_with;
use mechweed::config::Settings;
use mechweed::state::fault_cause::FaultCause;
use mechweed::state::modes::Mode;
use mechweed::threads::lockstep::{Io, Lockstep};
use mechweed_hw::cards::wiring::{Bit, Switch};
use mechweed_hw::emulated::CardRig;

const SHIPPED: &str = include_str!("../../config/robot.ini");
const SHIPPED_LINE: &str = "watchdog = dda06 port b bit 0, active high";

/// The shipped file with the watchdog line replaced: the settings or the errors, and
/// the line's number.
fn with_watchdog(value: &str) -> (Result<Settings, Vec<String>>, usize) {
    let line = SHIPPED
        .lines()
        .position(|l| l == SHIPPED_LINE)
        .expect("shipped")
        + 1;
    let text = SHIPPED.replacen(SHIPPED_LINE, &format!("watchdog = {value}"), 1);
    let parsed = Settings::parse("robot.ini", &text, &[])
        .map_err(|e| e.iter().map(|e| e.to_string()).collect());
    (parsed, line)
}

#[test]
fn the_watchdog_setting_is_a_free_output_or_none_and_a_clash_names_it() {
    let shipped = Settings::shipped();
    assert_eq!(
        shipped.io.watchdog,
        Some(Switch {
            bit: Bit::Dda06 { port: 1, bit: 0 },
            active_high: true
        })
    );
    let (none, _) = with_watchdog("none");
    assert_eq!(none.unwrap().io.watchdog, None);
    let (low, _) = with_watchdog("dda06 port c bit 7, active low");
    assert!(!low.unwrap().io.watchdog.unwrap().active_high);

    let (clash, line) = with_watchdog("das08 op 1, active high");
    assert_eq!(
        clash.unwrap_err(),
        [format!(
            "robot.ini line {line}: [io] watchdog: das08 op 1 is already wired to main_power_on"
        )]
    );
    let (input_group, line) = with_watchdog("dda06 port a bit 5, active high");
    let errors = input_group.unwrap_err();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].starts_with(&format!(
            "robot.ini line {line}: [io] watchdog: dda06 port a bit 5 is in the same 8255 \
             port group as the input end_switch_left"
        )),
        "{errors:?}"
    );
    let (missing, _) = with_watchdog("");
    assert!(missing.unwrap_err()[0].contains("[io] watchdog: "));
}

#[test]
fn check_config_names_the_watchdog_key_of_a_doubly_used_output() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("robot.ini");
    let text = SHIPPED.replacen(SHIPPED_LINE, "watchdog = das08 op 4, active high", 1);
    std::fs::write(&bad, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_mechweed"))
        .arg("check-config")
        .arg(&bad)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("[io] watchdog: das08 op 4 is already wired to tool_on"),
        "{stderr}"
    );
}

fn rig(sim: &mut Lockstep) -> &mut CardRig {
    match &mut sim.io {
        Io::Cards(rig) => rig,
        Io::Direct => panic!("not through the cards"),
    }
}

/// The watchdog line's level after each of `ticks` supervisor ticks.
fn watchdog_levels(sim: &mut Lockstep, ticks: usize) -> Vec<bool> {
    (0..ticks)
        .map(|_| {
            sim.tick();
            rig(sim).dda06.pin(1, 0)
        })
        .collect()
}

#[test]
fn the_supervisor_toggles_the_watchdog_every_tick_and_a_dead_card_stops_it() {
    let s = settings_with("", &[]);
    let mut sim = Lockstep::with_io(&s, Mode::Autonomous, Io::cards(&s).unwrap());
    sim.run_for(2.0);
    assert_eq!(sim.supervisor.mode(), Mode::Autonomous);
    let running = watchdog_levels(&mut sim, 100);
    assert!(
        running.windows(2).all(|pair| pair[0] != pair[1]),
        "a square wave at half the tick rate: {running:?}"
    );

    // A DAS08 that reads 0xFF may still hold the contactor closed.
    rig(&mut sim).das08.set_dead(true);
    let stopped = watchdog_levels(&mut sim, 100);
    assert_eq!(
        sim.supervisor.status().fault.map(|f| f.cause),
        Some(FaultCause::Hardware { card: "PCI-DAS08" })
    );
    assert_eq!(stopped, vec![false; 100], "held inactive: the relay drops");
}
