//! The core's tests that need no thread: the controller in lockstep with the simulated
//! robot (simulated time, the same tick functions as a run), the settings, the
//! decoders' properties and the benchmark's figures. `cargo test -p mechweed-core`
//! runs them with the core's own unit tests, without building the bus or the GUI.

mod common;

mod camera_gaps;
mod cards_closed_loop;
mod commission;
mod config_errors;
mod decoder_props;
mod drive_guards;
mod end_switches;
mod faults;
mod gnss_degraded;
mod gnss_safety;
mod gnss_steering;
mod hold_to_run;
mod miswire;
mod no_alloc;
mod older_file;
mod power;
mod real_robot_config;
mod records;
mod regulators;
mod row_following;
mod supervisor_tick;
