//! `mechweed bench rows`: the row-following benchmark's command (the benchmark itself
//! is the core's, mechweed_core::bench).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::ValueEnum;
use mechweed_hw::sim::FieldKind;

use crate::bench::rows::{field_line, run_all, table, unused_overrides};
use crate::bench::summary::{summarise, summary_table};
use crate::config::SteerSource;
use crate::programs::{load_settings, print_errors, settings_file, write_json};

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum BenchSource {
    Camera,
    Gnss,
    Fused,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum BenchField {
    Clean,
    Realistic,
}

#[derive(clap::Args)]
pub struct RowsArgs {
    /// Settings file (the controller's; [sim] is the benchmark's own) [default: config/robot.ini, or the built-in copy]
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Override one setting (SECTION.KEY=VALUE); repeatable.
    #[arg(long, value_name = "SECTION.KEY=VALUE")]
    pub set: Vec<String>,
    /// Seed of the simulation.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Many seeds, A-B (for example 1-10): every run of each, then a summary per source
    /// and speed (median and worst RMS over the steering bound, runs stopped, runs over
    /// 8 and 10 cm). Instead of --seed.
    #[arg(long, value_name = "A-B", value_parser = parse_seeds, conflicts_with = "seed")]
    pub seeds: Option<(u64, u64)>,
    /// The field: clean (0.3, 0.5, 1.0 m/s) or realistic (what real fields add, [sim]
    /// field_*; 0.5, 1.0, 2.0 m/s).
    #[arg(long, value_enum, default_value_t = BenchField::Clean)]
    pub field: BenchField,
    /// Which sensors steer, each over every row and speed, side by side: camera, gnss,
    /// fused (comma-separated; the simulated robot's GNSS receiver on its field's map).
    #[arg(long, value_enum, value_delimiter = ',', default_value = "camera")]
    pub sources: Vec<BenchSource>,
    /// Also write the results as JSON to this file.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
}

/// `mechweed bench rows`: every row and speed, for each source asked, as a table.
pub fn program(args: RowsArgs) -> ExitCode {
    let RowsArgs {
        config,
        set,
        seed,
        seeds,
        field,
        sources,
        json,
    } = args;
    let settings = match load_settings(config.as_deref(), &set) {
        Ok(s) => s,
        Err(errors) => {
            print_errors(&errors);
            return ExitCode::FAILURE;
        }
    };
    let field = match field {
        BenchField::Clean => FieldKind::Clean,
        BenchField::Realistic => FieldKind::Realistic,
    };
    let unused = unused_overrides(&set, field);
    unused.iter().for_each(|message| eprintln!("{message}"));
    if !unused.is_empty() {
        return ExitCode::FAILURE;
    }
    let file = settings_file(config.as_deref()) // said: the figures depend on it
        .map_or("the built-in robot.ini".into(), |p| p.display().to_string());
    crate::say!("settings: {file} ([sim] is the benchmark's own)");
    let sources: Vec<SteerSource> = (sources.iter())
        .map(|source| match source {
            BenchSource::Camera => SteerSource::Camera,
            BenchSource::Gnss => SteerSource::Gnss,
            BenchSource::Fused => SteerSource::Fused,
        })
        .collect();
    if let Some(line) = field_line(field) {
        println!("{line}");
    }
    let (first, last) = seeds.unwrap_or((seed, seed));
    let mut runs = Vec::new();
    for seed in first..=last {
        if seeds.is_some() {
            eprintln!("seed {seed} of {first}-{last}");
        }
        runs.extend(run_all(&settings, field, &sources, seed));
    }
    print!("{}", table(&runs));
    if seeds.is_some() {
        print!("\n{}", summary_table(&summarise(&runs)));
    }
    write_json(json, &runs)
}

/// "A-B", the first and last seed.
fn parse_seeds(text: &str) -> Result<(u64, u64), String> {
    let bad = || format!("'{text}' is not a range of seeds A-B, such as 1-10");
    let (a, b) = text.split_once('-').ok_or_else(bad)?;
    let (a, b): (u64, u64) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    match a <= b {
        true => Ok((a, b)),
        false => Err(format!("'{text}': the first seed is after the last")),
    }
}
