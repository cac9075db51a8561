//! `mechweed man-pages DIR` (hidden): the man pages, one a command, from the same
//! definitions as `--help`, for the package (scripts/package.sh).

use std::path::Path;

use clap::CommandFactory;

pub fn write(dir: &Path) -> Result<String, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot make {}: {e}", dir.display()))?;
    clap_mangen::generate_to(crate::programs::Cli::command(), dir)
        .map_err(|e| format!("cannot write the man pages into {}: {e}", dir.display()))?;
    let pages = std::fs::read_dir(dir).map_or(0, |d| d.count());
    Ok(format!("{pages} man pages in {}", dir.display()))
}
