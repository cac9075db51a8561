//! `mechweed replay`: its options, its lines and its JSON.

use std::path::PathBuf;
use std::process::ExitCode;

use crate::replay::{
    ANGLE_TOLERANCE_DEG, Fault, Outcome, ReplayOptions, SPEED_TOLERANCE_MPS, SteerFigures,
    replay as run_replay,
};
use clap::Args;

use crate::programs::{load_settings, print_errors};

#[derive(Args)]
pub struct ReplayArgs {
    /// The record: NAME.csv (with NAME.events.csv and NAME.run.json beside it) or
    /// NAME.mcap, or `latest` for the newest record in robot.ini's [record] folder.
    record: PathBuf,
    /// Replay with this setting changed, a what-if on the same inputs (repeatable);
    /// writes NAME-whatif beside the record.
    #[arg(long = "set", value_name = "SECTION.KEY=VALUE")]
    set: Vec<String>,
    /// Compare and report from this time of the run on, s (the supervisor still runs
    /// from the start: its filters remember).
    #[arg(long, value_name = "S", default_value_t = 0.0)]
    from: f64,
    /// Compare and report up to this time of the run, s.
    #[arg(long, value_name = "S", default_value_t = f64::INFINITY)]
    to: f64,
    /// Also write the outcome as JSON to this file.
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
}

pub fn replay(args: ReplayArgs) -> ExitCode {
    let record = if args.record.as_os_str() == "latest" {
        let settings = match load_settings(None, &[]) {
            Ok(s) => s,
            Err(errors) => {
                print_errors(&errors);
                return ExitCode::FAILURE;
            }
        };
        match crate::record::keep::latest(&settings.record.folder) {
            Ok(newest) => newest,
            Err(why) => {
                eprintln!("{why}");
                return ExitCode::FAILURE;
            }
        }
    } else {
        args.record.clone()
    };
    let whatif = !args.set.is_empty();
    let opts = ReplayOptions {
        record: record.clone(),
        set: args.set.clone(),
        from_s: args.from,
        to_s: args.to,
    };
    println!("replaying {}{}", record.display(), with_settings(&args.set));
    let outcome = match run_replay(&opts) {
        Ok(outcome) => outcome,
        Err(why) => {
            eprintln!("cannot replay: {why}");
            return ExitCode::FAILURE;
        }
    };
    for note in &outcome.notes {
        println!("note: {note}");
    }
    print!("{}", words(&outcome, whatif));
    if let Some(path) = &args.json {
        let text = serde_json::to_string_pretty(&json(&outcome, &record, &args.set));
        if let Err(e) = text
            .map_err(std::io::Error::other)
            .and_then(|t| std::fs::write(path, t))
        {
            eprintln!("cannot write {}: {e}", path.display());
            return ExitCode::FAILURE;
        }
    }
    if whatif || outcome.first_difference.is_none() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

fn with_settings(set: &[String]) -> String {
    if set.is_empty() {
        String::new()
    } else {
        format!(" with {}", set.join(", "))
    }
}

fn fault_line(f: &Fault) -> String {
    format!("{:.3} s (tick {}): {}", f.t_s, f.tick, f.words)
}

/// What the replay found, in lines.
pub fn words(o: &Outcome, whatif: bool) -> String {
    let mut out = String::new();
    let window = if o.compared == o.ticks {
        String::new()
    } else {
        format!(" ({} compared)", o.compared)
    };
    match (&o.first_difference, whatif) {
        (None, false) => {
            let answers = match o.requests {
                0 => "",
                _ if o.compared < o.ticks => ", and the answers to the requests among them",
                _ => ", and the answers to the operator's requests",
            };
            out += &format!(
                "{} ticks{window}, outputs identical to the record: the mode, the amplifiers (to the bit), the main power relay, the brakes and the tool{answers}\n",
                o.ticks
            )
        }
        (None, true) => {
            out += &format!(
                "{} ticks{window}: the what-if's outputs are the run's\n",
                o.ticks
            )
        }
        (Some(d), _) => {
            let (run, now) = if whatif {
                ("the run", "the what-if")
            } else {
                ("recorded", "replayed")
            };
            out += &format!(
                "{} ticks{window}; first difference at tick {} ({:.3} s): {}: {run} {}, {now} {}\n",
                o.ticks, d.tick, d.t_s, d.what, d.recorded, d.replayed
            );
        }
    }
    let same = o
        .faults_recorded
        .iter()
        .map(|f| (f.tick, &f.words))
        .eq(o.faults_replayed.iter().map(|f| (f.tick, &f.words)));
    if !same || whatif {
        let (run, now) = if whatif {
            ("the run", "the what-if")
        } else {
            ("recorded", "replayed")
        };
        for (who, faults) in [(run, &o.faults_recorded), (now, &o.faults_replayed)] {
            if faults.is_empty() {
                out += &format!("{who}: no fault\n");
            }
            for f in faults.iter() {
                out += &format!("{who}: fault at {}\n", fault_line(f));
            }
        }
    }
    out += &steer_words(&o.steer, whatif);
    if !o.written.is_empty() {
        out += &format!("the what-if's record: {}\n", o.written.join(", "));
    }
    out
}

/// The steer commands made again beside the supervisor, and how far they are from the
/// recorded: said apart from the outputs, since the supervisor was given the recorded
/// commands and its outputs do not depend on these (replay/steer.rs says why they differ).
fn steer_words(st: &SteerFigures, whatif: bool) -> String {
    let tolerance = format!("{ANGLE_TOLERANCE_DEG} deg and {SPEED_TOLERANCE_MPS} m/s");
    let apart = format!(
        "{:.3} deg and {:.4} m/s",
        st.max_angle_diff_deg, st.max_speed_diff_mps
    );
    let first = |run: &str, again: &str| {
        st.first_beyond
            .map_or(String::new(), |(t_s, recorded, made)| {
                format!(
                    ", the first at {t_s:.3} s ({run} {recorded:.3} deg, {again} {made:.3} deg)"
                )
            })
    };
    if whatif {
        return format!(
            "steer commands: {} made by the what-if's steering law from the run's estimates, at most {apart} from the run's; {} of them beyond {tolerance}{}\n",
            st.commands,
            st.beyond,
            first("the run", "the what-if")
        );
    }
    let made = format!(
        "steer commands: {} made again by the steering law from the recorded estimates",
        st.commands
    );
    if st.beyond == 0 {
        return format!("{made}, all within {tolerance} of the recorded (at most {apart})\n");
    }
    let mut out = format!(
        "{made}: {} within {tolerance} of the recorded, {} differ from it by at most {apart}{}\n",
        st.commands - st.beyond,
        st.beyond,
        first("recorded", "made again")
    );
    out += "steer commands: such differences are expected and do not touch the outputs above, which the supervisor made from the recorded commands: the record keeps the last steer command of each supervisor tick, not every one, nor which status the steer thread had copied, so the law made again can miss a step that moved its filters\n";
    out
}

fn json(o: &Outcome, record: &std::path::Path, set: &[String]) -> serde_json::Value {
    let faults = |list: &[Fault]| {
        (list.iter())
            .map(|f| serde_json::json!({"tick": f.tick, "t_s": f.t_s, "fault": f.words}))
            .collect::<Vec<_>>()
    };
    let difference = o.first_difference.as_ref().map(|d| {
        serde_json::json!({"tick": d.tick, "t_s": d.t_s, "what": d.what, "recorded": d.recorded, "replayed": d.replayed})
    });
    serde_json::json!({
        "record": record.display().to_string(),
        "set": set,
        "ticks": o.ticks,
        "compared": o.compared,
        "requests": o.requests,
        "identical": o.first_difference.is_none(),
        "first_difference": difference,
        "faults_recorded": faults(&o.faults_recorded),
        "faults_replayed": faults(&o.faults_replayed),
        "steer": {
            "commands": o.steer.commands,
            "max_angle_diff_deg": o.steer.max_angle_diff_deg,
            "max_speed_diff_mps": o.steer.max_speed_diff_mps,
            "beyond_tolerance": o.steer.beyond,
            "tolerance_deg": ANGLE_TOLERANCE_DEG,
            "tolerance_mps": SPEED_TOLERANCE_MPS,
        },
        "written": o.written,
        "notes": o.notes,
    })
}
