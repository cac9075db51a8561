//! The console of `mechweed run --headless`, as a user reads it: a fault's line says
//! what to check, and the same fault after a power-up that did not mend it says it came
//! back; the report gives both.

use crate::common;

const CHECK: &str = "what to check: the encoder and its cable, then Power up";

#[test]
fn the_fault_line_says_what_to_check_and_a_fault_after_power_up_that_it_came_back() {
    let dir = tempfile::tempdir().unwrap();
    // Driving off, the left wheel's encoder stops counting for the rest of the run; the
    // operator powers up and drives off again, as in the field.
    let events = "sim.events=1 encoder_stuck left, 2.5 power_up, 3.5 mode autonomous";
    let (out, report) = common::run_headless(
        dir.path(),
        &["--mode", "autonomous", "--duration", "5.5", "--set", events],
    );
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    // The run ends in Fault, which is its exit status (binary.rs tests that); a run that
    // did not end at all, or failed another way, left no report (run_headless says so).
    let faults: Vec<&str> = stdout.lines().filter(|l| l.contains("FAULT: ")).collect();
    assert_eq!(faults.len(), 2, "{stdout}");
    let first = "FAULT: left wheel encoder does not count while its motor is driven; what to check: the encoder and its cable, then Power up";
    assert!(faults[0].ends_with(first), "{stdout}");
    assert!(faults[1].contains("driven; came back "), "{stdout}");
    assert!(faults[1].contains(" s after power-up: its cause is still there, check again; "));
    assert!(faults[1].ends_with(CHECK), "{stdout}");

    // The report at exit, on the terminal and as JSON.
    assert!(stdout.contains(&format!("\n  {CHECK}\n")), "{stdout}");
    let faults = report["faults"].as_array().unwrap();
    assert_eq!(faults.len(), 2, "{report:#}");
    for fault in faults {
        assert_eq!(
            fault["what_to_check"],
            "the encoder and its cable, then Power up"
        );
    }
    assert!(faults[0]["came_back_after_s"].is_null(), "{report:#}");
    let after_s = faults[1]["came_back_after_s"].as_f64().unwrap();
    assert!(after_s > 0.0 && after_s < 3.0, "{report:#}");
}
