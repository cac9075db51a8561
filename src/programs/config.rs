//! `mechweed config upgrade FILE [--check]`: a robot.ini of an older release brought up
//! to this one (config/upgrade.rs does the work): every setting and section it lacks
//! added with its comment, every line of the technician's kept where it stands, the
//! file written whole or not at all, with the file before beside it.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Subcommand};

use crate::config::upgrade::{Added, upgrade};

#[derive(Subcommand)]
pub enum ConfigCommand {
    /// Add every setting and section of this release that FILE lacks, with its comment
    /// and the value that keeps the older behaviour (else the shipped one); every line
    /// already there stays. The file before is kept beside it.
    Upgrade(UpgradeArgs),
}

#[derive(Args)]
pub struct UpgradeArgs {
    /// The settings file, e.g. /etc/mechweed/robot.ini
    pub file: PathBuf,
    /// Only list what is missing; exit 1 if anything is, 0 if nothing is.
    #[arg(long)]
    pub check: bool,
}

pub fn config(command: ConfigCommand) -> ExitCode {
    match command {
        ConfigCommand::Upgrade(args) => match upgrade_file(&args.file, args.check) {
            Ok(code) => code,
            Err(why) => {
                eprintln!("{why}");
                ExitCode::FAILURE
            }
        },
    }
}

fn upgrade_file(file: &Path, check: bool) -> Result<ExitCode, String> {
    let name = file.display();
    let text = crate::config::read_text(file, "the settings file").map_err(|errors| {
        errors
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join("\n")
    })?;
    let (upgraded, added) = upgrade(&text).map_err(|lines| {
        let lines: Vec<String> = (lines.iter())
            .map(|(n, why)| format!("{name} line {n}: {why}"))
            .collect();
        format!(
            "{}\nnothing was changed: mend these lines first",
            lines.join("\n")
        )
    })?;
    if added.is_empty() {
        crate::say!("{name} has every setting of this release: nothing to add");
        return Ok(ExitCode::SUCCESS);
    }
    let word = |a: &Added| if a.retired { "retired" } else { "added" };
    let lines: Vec<String> = added
        .iter()
        .map(|a| format!("{} {}", word(a), a.line()))
        .collect();
    if check {
        lines.iter().for_each(|l| crate::say!("to be {l}"));
        crate::say!(
            "{name}: {} settings of this release to add or retire; `mechweed config upgrade {name}` does it",
            added.len()
        );
        return Ok(ExitCode::FAILURE);
    }
    let stamp = crate::record::utc_stamp(std::time::SystemTime::now());
    let backup = PathBuf::from(format!("{name}.before-upgrade-{stamp}"));
    std::fs::copy(file, &backup).map_err(|e| {
        format!(
            "cannot keep the file before as {}: {e}: nothing was changed",
            backup.display()
        )
    })?;
    write_whole(file, &upgraded)
        .map_err(|e| format!("cannot write {name}: {e}: nothing was changed"))?;
    lines.iter().for_each(|l| crate::say!("{l}"));
    crate::say!(
        "{name}: {} settings added or retired; the file before is {}",
        added.len(),
        backup.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// Write `text` to a new file beside `file`, onto the disk, then put it in `file`'s
/// place: a power cut leaves the old file or the new, never half of one.
fn write_whole(file: &Path, text: &str) -> std::io::Result<()> {
    let mut temporary = file.as_os_str().to_owned();
    temporary.push(".upgrading");
    let temporary = PathBuf::from(temporary);
    let mut out = std::fs::File::create(&temporary)?;
    out.write_all(text.as_bytes())?;
    out.sync_all()?;
    if let Ok(before) = std::fs::metadata(file) {
        std::fs::set_permissions(&temporary, before.permissions())?;
    }
    std::fs::rename(&temporary, file)
}
