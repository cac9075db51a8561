//! `mechweed check-config`: read a settings file and say "ok" or every error in it.

use std::path::PathBuf;
use std::process::ExitCode;

use crate::config::Settings;
use crate::programs::print_errors;

#[derive(clap::Args)]
pub struct CheckConfigArgs {
    /// The settings file [default: config/robot.ini]
    pub file: Option<PathBuf>,
}

pub fn check_config(args: CheckConfigArgs) -> ExitCode {
    let file = args.file;
    let path = file.unwrap_or_else(|| PathBuf::from("config/robot.ini"));
    match Settings::load(&path, &[]) {
        Ok(_) => {
            crate::say!("ok");
            ExitCode::SUCCESS
        }
        Err(errors) => {
            print_errors(&errors);
            ExitCode::FAILURE
        }
    }
}
