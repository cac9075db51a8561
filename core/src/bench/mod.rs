//! The row-following benchmark (`mechweed bench rows`): three row shapes at three
//! speeds, every disturbance on, in lockstep simulation (rows.rs); and the two figures
//! each run is held against: the steering bound, the least RMS that any linear filter
//! and law can leave on a linear model of the field (bound.rs), and the row filter's
//! own floor (floor.rs); and what such a law reaches with the loop's delay and the
//! wheel's rate limit (achievable.rs).

pub mod achievable;
pub mod bound;
pub mod floor;
pub mod rows;
pub mod summary;
