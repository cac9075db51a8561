//! `mechweed replay`: its options, its lines and its JSON.

use std::path::PathBuf;
use std::process::ExitCode;

use crate::replay::{
    ANGLE_TOLERANCE_DEG, Fault, Outcome, ReplayOptions, SPEED_TOLERANCE_MPS, replay as run_replay,
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
        (None, false) => out += &format!("{} ticks{window}, outputs identical\n", o.ticks),
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
    let st = &o.steer;
    if whatif {
        out += &format!(
            "steering law: {} commands of the what-if's law on the run's estimates, up to {:.3} deg and {:.4} m/s from the run's\n",
            st.commands, st.max_angle_diff_deg, st.max_speed_diff_mps
        );
    } else {
        out += &format!(
            "steering law: {} commands made again from the recorded estimates, within {:.3} deg and {:.4} m/s of the recorded (tolerance {ANGLE_TOLERANCE_DEG} deg, {SPEED_TOLERANCE_MPS} m/s: the record keeps the last steer command of each supervisor tick, not every one)\n",
            st.commands, st.max_angle_diff_deg, st.max_speed_diff_mps
        );
    }
    if let Some((t_s, recorded, again)) = st.first_beyond {
        out += &format!(
            "steering law: {} commands beyond {ANGLE_TOLERANCE_DEG} deg or {SPEED_TOLERANCE_MPS} m/s, the first at {t_s:.3} s: {} {recorded:.3} deg, {} {again:.3} deg\n",
            st.beyond,
            if whatif { "the run" } else { "recorded" },
            if whatif { "the what-if" } else { "made again" },
        );
    }
    if !o.written.is_empty() {
        out += &format!("the what-if's record: {}\n", o.written.join(", "));
    }
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
