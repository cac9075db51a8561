//! `mechweed check-config`: read a settings file and say "ok" or every error in it.

use std::path::PathBuf;
use std::process::ExitCode;

use crate::config::Settings;
use crate::programs::print_errors;

#[derive(clap::Args)]
pub struct CheckConfigArgs {
    /// The settings file [default: config/robot.ini]
    pub file: Option<PathBuf>,
    /// The file is meant for the real robot: also refuse it unless `[hw] backend =
    /// cards` (a simulated camera, receiver or map is refused with the cards anyway)
    #[arg(long)]
    pub real_robot: bool,
}

pub fn check_config(args: CheckConfigArgs) -> ExitCode {
    let path = args
        .file
        .unwrap_or_else(|| PathBuf::from("config/robot.ini"));
    let read = if args.real_robot {
        Settings::load_real_robot(&path)
    } else {
        Settings::load(&path, &[])
    };
    match read {
        Ok(_) if args.real_robot => {
            crate::say!("ok: set up for the real robot (the cards, no simulated part)");
            ExitCode::SUCCESS
        }
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
