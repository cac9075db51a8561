//! `mechweed watch`: the operator GUI on another computer, fed by the robot's flows on
//! the bus (src/gui/remote.rs).

use std::process::ExitCode;

use crate::console::ctrl_c;
use crate::gui::Tab;
use crate::programs::{done, load_settings, print_errors};

#[derive(clap::Args)]
pub struct WatchArgs {
    /// Where the robot program listens ([bus] listen on the robot).
    #[arg(long, value_name = "ENDPOINT", default_value = crate::programs::bus::tools::DEFAULT_ENDPOINT)]
    pub connect: String,
    /// The robot's name on the bus ([bus] robot on the robot).
    #[arg(long, value_name = "NAME", default_value = "mechweed")]
    pub robot: String,
    /// Close the window after this many seconds.
    #[arg(long, value_name = "SECONDS", value_parser = crate::config::parse_seconds)]
    pub duration: Option<f64>,
    /// The tab at start.
    #[arg(long, value_enum, default_value = "status")]
    pub tab: Tab,
    /// This program's identity on a secured bus (--keys DIR --as operator).
    #[command(flatten)]
    pub identity: crate::programs::keys::IdentityArgs,
}

/// `mechweed watch`: the operator GUI fed by the robot's flows.
pub fn watch(args: WatchArgs) -> ExitCode {
    let settings = match load_settings(None, &[]) {
        Ok(settings) => settings,
        Err(errors) => {
            print_errors(&errors);
            return ExitCode::FAILURE;
        }
    };
    let remote = match crate::gui::remote::RemoteView::connect(
        &args.connect,
        &args.robot,
        args.identity.files().as_ref(),
    ) {
        Ok(remote) => remote.unknown_after(settings.gui.remote_stale_s),
        Err(why) => return done(Err(why)),
    };
    println!("watching {} at {}", args.robot, args.connect);
    let advice = "watch needs a window; on a computer without one, `mechweed bus echo status` prints the status";
    let shown = crate::gui::run_watch(remote, settings, args.duration, args.tab, ctrl_c(), advice);
    done(shown.map(|frames| println!("window closed after {frames} frames")))
}
