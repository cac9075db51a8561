//! A field's row map: rows as lines of WGS-84 points (what the file holds), and the
//! same rows in metres east and north of a reference point, where the robot looks up
//! which row it is on.

use crate::gnss::rowmap::local_row::{Foot, LocalRow, RowError};
use mechweed_hw::geo::LocalFrame;

/// The rows of a field, in the order of the file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RowMap {
    pub rows: Vec<MapRow>,
}

/// One row: a name and its points in driving order.
#[derive(Debug, Clone, PartialEq)]
pub struct MapRow {
    /// As in the file: `1`, `north-3`.
    pub name: String,
    /// (latitude, longitude), degrees, WGS-84.
    pub points_deg: Vec<(f64, f64)>,
}

impl RowMap {
    /// The row called `name`, if there is one.
    pub fn row(&self, name: &str) -> Option<&MapRow> {
        self.rows.iter().find(|row| row.name == name)
    }

    /// Every row in metres east and north of `frame`'s origin.
    pub(crate) fn to_local(&self, frame: &LocalFrame) -> Result<LocalMap, RowError> {
        let rows = self
            .rows
            .iter()
            .map(|row| LocalRow::new(row, frame))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(LocalMap { rows })
    }
}

/// The rows of a map in one east-north frame, in the map's order.
#[derive(Debug, Clone, PartialEq)]
pub struct LocalMap {
    pub rows: Vec<LocalRow>,
}

impl LocalMap {
    /// The row a point is on: of the rows whose stretch (extended by
    /// `ROW_END_MARGIN_M` at both ends) the point lies beside, the one nearest
    /// sideways. The index is into `rows`; `None` if the point is beside no row.
    /// Scans every segment of every row: for choosing a row, not for every cycle
    /// (then `LocalRow::project` with a hint).
    pub(crate) fn nearest_row(&self, east_m: f64, north_m: f64) -> Option<(usize, Foot)> {
        let mut best: Option<(usize, Foot)> = None;
        for (index, row) in self.rows.iter().enumerate() {
            let Some(foot) = row.project_scan(east_m, north_m) else {
                continue;
            };
            let beside = row.is_beside(foot.s_m);
            let nearer = best
                .as_ref()
                .is_none_or(|(_, b)| foot.offset_m.abs() < b.offset_m.abs());
            if beside && nearer {
                best = Some((index, foot));
            }
        }
        best
    }
}

#[cfg(test)]
#[path = "map_tests.rs"]
mod tests;
