//! Crop-row maps: the row map file (CSV of latitude and longitude per point, as taught
//! by driving a row or exported from a planting machine's RTK record), rows in a local
//! east-north frame with the projection that gives GNSS cross-track error, and the logic
//! of teaching a row by driving it.
//!
//! Pure computation apart from reading and writing the map file: no threads, no clock.

// Map files are edited by hand and by spreadsheets: outside tests, nothing here may
// panic on them.
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::indexing_slicing,
        clippy::panic
    )
)]

pub mod format;
pub mod local_row;
pub mod map;
pub mod read;
pub mod teach;
pub mod write;

#[cfg(test)]
mod test_rows;

pub use format::{MapFileError, MapFileErrors, Place};
pub use local_row::{Foot, LocalRow, RowError};
pub use map::{LocalMap, MapRow, RowMap};
pub use read::{ReadError, parse_map, parse_map_bytes, read_map};
pub use teach::{TeachError, TeachSample, TeachSettings, Teacher};
pub use write::{WriteError, map_text, write_map};
