//! The program's tests on real threads and real time: the controller's threads in this
//! process, and the `mechweed` binary run as a user runs it (its commands, its exit
//! codes, its records, its links over pseudo-terminals); the settings file's checks;
//! and the checks of the project's own layout and documents.

#[path = "../common/mod.rs"]
mod common;
#[path = "../config_file/mod.rs"]
mod config_file;

mod binary;
mod camera_link;
mod cards_watchdog;
mod check_config;
mod config_safety;
mod config_upgrade;
mod docs_references;
mod fault_advice;
mod first_hour;
mod first_hour_2;
mod gamepad;
mod gnss_link;
mod layers;
mod link_recovery;
mod package_files;
mod real_robot;
mod record_binary;
mod records_keep;
mod replay;
mod replay_words;
mod row_end;
mod safe_outputs;
mod sensors_down;
mod service;
mod teach;
mod test_mode;
mod threads;
