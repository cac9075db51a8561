//! How old a row estimate from the bus is. A vision program stamps each row with its
//! capture time `t_s`, on its own computer's clock. Where that clock agrees with this
//! one (both set by NTP or GNSS time, as a field's computers should be), the capture
//! time is the row's age: a row that arrives late, or is sent again, is refused as
//! stale instead of counting as fresh. Where the clocks do not agree, the row's age is
//! taken from its arrival, as for a camera computer's serial link, and the robot says so
//! once.
//!
//! The clocks agree when the first rows' capture times are all within AGREE_S before
//! their arrival (a row cannot arrive before it was taken, and a few milliseconds on a
//! network are far below AGREE_S). A row from the future, or from more than
//! ANOTHER_CLOCK_S ago, is of another clock; a run of those switches back to arrival
//! times. A row merely late (a network that stalled) says nothing about the clocks: it
//! is stale, and refused.

/// Rows taken this long or less after their capture time agree, s.
pub(crate) const AGREE_S: f64 = 0.5;
/// A capture time in the future by more than this is of another clock, s.
const FUTURE_S: f64 = 0.05;
/// A capture time this long before the arrival is of another clock, s: no network
/// holds a row a minute.
const ANOTHER_CLOCK_S: f64 = 60.0;
/// Agreeing rows needed to decide, rows.
const DECIDE_AFTER_ROWS: u32 = 10;
/// Rows of another clock in a row that give up the capture times, rows.
const GIVE_UP_AFTER_ROWS: u32 = 10;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Basis {
    /// Still looking at the first rows.
    Deciding,
    /// The capture time, on an agreeing clock.
    Capture,
    /// The arrival time: the sender's clock is another.
    Arrival,
}

/// What to do with one row.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Verdict {
    Take,
    /// Older than the link's time-out by its capture time: refused, with why.
    Stale(String),
}

#[derive(Debug)]
pub(crate) struct RowClock {
    pub basis: Basis,
    agreed: u32,
    disagreed_in_a_row: u32,
    /// A row older than this by its capture time is stale, s ([camera] link_timeout_s).
    max_age_s: f64,
}

impl RowClock {
    pub fn new(max_age_s: f64) -> RowClock {
        RowClock {
            basis: Basis::Deciding,
            agreed: 0,
            disagreed_in_a_row: 0,
            max_age_s,
        }
    }

    /// A row captured at `t_s` (None: the sender did not say) arriving at `now_s`, both
    /// in seconds since 1970. The second value is a line to say, when the basis changes.
    pub fn row(&mut self, t_s: Option<f64>, now_s: f64) -> (Verdict, Option<String>) {
        let age_s = t_s.map(|t| now_s - t);
        let agrees = age_s.is_some_and(|a| (-FUTURE_S..AGREE_S).contains(&a));
        let another_clock = age_s.is_none_or(|a| !(-FUTURE_S..ANOTHER_CLOCK_S).contains(&a));
        let mut said = None;
        match self.basis {
            Basis::Deciding if agrees => {
                self.agreed += 1;
                if self.agreed >= DECIDE_AFTER_ROWS {
                    self.basis = Basis::Capture;
                    said = Some(
                        "camera rows from the bus: the sender's clock agrees with this computer's; each row's age is taken from its capture time".to_string(),
                    );
                }
            }
            // Late: it tells nothing about the clocks; taken by its arrival meanwhile.
            Basis::Deciding if !another_clock => {}
            Basis::Deciding => {
                self.basis = Basis::Arrival;
                said = Some(match age_s {
                    Some(a) => format!(
                        "camera rows from the bus: their capture times are {a:.1} s from this computer's clock (another clock, not set alike); each row's age is taken from its arrival"
                    ),
                    None => "camera rows from the bus carry no capture time: each row's age is taken from its arrival".to_string(),
                });
            }
            Basis::Capture if !another_clock => self.disagreed_in_a_row = 0,
            Basis::Capture => {
                self.disagreed_in_a_row += 1;
                if self.disagreed_in_a_row >= GIVE_UP_AFTER_ROWS {
                    self.basis = Basis::Arrival;
                    said = Some(format!(
                        "camera rows from the bus: {GIVE_UP_AFTER_ROWS} rows in a row are no longer of this computer's clock; each row's age is taken from its arrival from now on"
                    ));
                }
            }
            Basis::Arrival => {}
        }
        let verdict = match (self.basis, age_s) {
            (Basis::Capture, Some(a)) if a > self.max_age_s => Verdict::Stale(format!(
                "captured {a:.2} s ago, more than the link's time-out of {:.2} s",
                self.max_age_s
            )),
            _ => Verdict::Take,
        };
        (verdict, said)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agreeing_clocks_refuse_a_stale_row() {
        let mut clock = RowClock::new(0.5);
        let mut said = Vec::new();
        for i in 0..12 {
            let now = 1000.0 + f64::from(i) * 0.1;
            let (verdict, line) = clock.row(Some(now - 0.02), now);
            assert_eq!(verdict, Verdict::Take);
            said.extend(line);
        }
        assert_eq!(clock.basis, Basis::Capture);
        assert_eq!(said.len(), 1, "{said:?}");
        // A row sent again two seconds later.
        let (verdict, _) = clock.row(Some(1000.0), 1002.0);
        assert!(matches!(verdict, Verdict::Stale(_)), "{verdict:?}");
    }

    #[test]
    fn another_clock_is_said_once_and_rows_are_taken_by_arrival() {
        let mut clock = RowClock::new(0.5);
        let (verdict, line) = clock.row(Some(12.5), 1_700_000_000.0);
        assert_eq!(verdict, Verdict::Take);
        assert!(line.unwrap().contains("another clock"));
        assert_eq!(clock.basis, Basis::Arrival);
        let (verdict, line) = clock.row(Some(1.0), 1_700_000_100.0);
        assert_eq!((verdict, line), (Verdict::Take, None));
    }

    #[test]
    fn a_network_that_stalls_leaves_the_capture_times_in_use() {
        let mut clock = RowClock::new(0.5);
        for i in 0..10 {
            clock.row(Some(f64::from(i)), f64::from(i) + 0.01);
        }
        // Twenty rows held up 3 s: each refused as stale, the clocks still agree.
        for i in 10..30 {
            let (verdict, said) = clock.row(Some(f64::from(i)), f64::from(i) + 3.0);
            assert!(matches!(verdict, Verdict::Stale(_)), "{verdict:?}");
            assert_eq!(said, None);
        }
        assert_eq!(clock.basis, Basis::Capture);
    }

    #[test]
    fn a_clock_that_drifts_away_is_given_up_after_a_run_of_rows() {
        let mut clock = RowClock::new(0.5);
        for i in 0..10 {
            clock.row(Some(f64::from(i)), f64::from(i) + 0.01);
        }
        assert_eq!(clock.basis, Basis::Capture);
        let mut lines = Vec::new();
        for i in 10..20 {
            // 0.3 s in the future: not a row of this clock.
            lines.extend(clock.row(Some(f64::from(i) + 0.3), f64::from(i)).1);
        }
        assert_eq!(clock.basis, Basis::Arrival);
        assert_eq!(lines.len(), 1);
    }
}
