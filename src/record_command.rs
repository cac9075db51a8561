//! `mechweed record ...`: a record's summary, and the off-board recorder.

use std::process::ExitCode;

use crate::cli::{RecordArgs, RecordCommand};
use crate::{load_settings, print_errors};
use mechweed::console::ctrl_c;

pub fn record(args: RecordArgs) -> ExitCode {
    match (args.bus, args.command) {
        (false, Some(command)) => summary(command),
        (true, _) => from_bus(
            args.connect,
            args.robot,
            args.seconds,
            args.config,
            &args.set,
            args.identity.files(),
        ),
        (false, None) => {
            eprintln!(
                "say what to do with records: `mechweed record summary FILE`, or `mechweed record --bus` to record the robot's flows here"
            );
            ExitCode::FAILURE
        }
    }
}

fn from_bus(
    connect: String,
    robot: String,
    seconds: Option<f64>,
    config: Option<std::path::PathBuf>,
    set: &[String],
    tls: Option<mechweed::config::TlsFiles>,
) -> ExitCode {
    let settings = match load_settings(config.as_deref(), set) {
        Ok(settings) => settings,
        Err(errors) => {
            print_errors(&errors);
            return ExitCode::FAILURE;
        }
    };
    let opts = mechweed::bus_record::Options {
        connect,
        robot,
        seconds,
        record: settings.record,
        tls,
    };
    match mechweed::bus_record::record(&opts, &ctrl_c()) {
        Ok(summary) => {
            println!("{summary}");
            ExitCode::SUCCESS
        }
        Err(why) => {
            eprintln!("{why}");
            ExitCode::FAILURE
        }
    }
}

fn summary(command: RecordCommand) -> ExitCode {
    let RecordCommand::Summary {
        file,
        from_m,
        config,
        set,
    } = command;
    let file = if file.as_os_str() == "latest" {
        let settings = match load_settings(config.as_deref(), &set) {
            Ok(settings) => settings,
            Err(errors) => {
                print_errors(&errors);
                return ExitCode::FAILURE;
            }
        };
        match mechweed::record::keep::latest(&settings.record.folder) {
            Ok(newest) => {
                println!("the newest record: {}", newest.display());
                newest
            }
            Err(why) => {
                eprintln!("{why}");
                return ExitCode::FAILURE;
            }
        }
    } else {
        file
    };
    match mechweed::record::summary::summarise(&file, from_m) {
        Ok(summary) => {
            print!("{}", summary.text());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}
