//! What the bus refuses, said on the robot's console without drowning it: the first
//! refusal at once, then at most one line a second with how many more there were. A
//! flood of refused requests (thousands a second) is then one line a second, not one
//! line each.

use std::time::{Duration, Instant};

/// At most one line this often.
const SAY_EVERY: Duration = Duration::from_secs(1);

/// The longest refusal said on the console, characters: a stranger's value echoed
/// whole once made a line of 120 146.
const LONGEST_CHARS: usize = 300;

/// `why`, cut at LONGEST_CHARS with how long it was.
fn shortened(why: String) -> String {
    let length = why.chars().count();
    if length <= LONGEST_CHARS {
        return why;
    }
    let cut: String = why.chars().take(LONGEST_CHARS).collect();
    format!("{cut}... ({length} characters)")
}

/// A rate limit: at most `per_s` a second, with a burst of as many.
#[derive(Debug)]
pub(crate) struct RateLimit {
    per_s: f64,
    tokens: f64,
    last: Instant,
}

impl RateLimit {
    pub fn new(per_s: f64, now: Instant) -> RateLimit {
        RateLimit {
            per_s,
            tokens: per_s,
            last: now,
        }
    }

    /// Whether one more may go now.
    pub fn take(&mut self, now: Instant) -> bool {
        let since_s = now.saturating_duration_since(self.last).as_secs_f64();
        self.tokens = (self.tokens + since_s * self.per_s).min(self.per_s);
        self.last = now;
        if self.tokens >= 1.0 {
            self.tokens -= 1.0;
            true
        } else {
            false
        }
    }
}

/// Requesters kept apart at most; a new one beyond takes the place of the one heard
/// from longest ago (a table keyed by what peers choose is bounded).
const MAX_REQUESTERS: usize = 16;

/// A rate limit per requester: one program's flood uses up its own allowance, not
/// another's. A requester is the Zenoh session a tool names in its query's attachment;
/// queries that name none share one allowance.
#[derive(Debug)]
pub(crate) struct PerRequester {
    per_s: f64,
    limits: Vec<(String, RateLimit)>,
}

impl PerRequester {
    pub fn new(per_s: f64) -> PerRequester {
        PerRequester {
            per_s,
            limits: Vec::new(),
        }
    }

    /// Whether `requester` may have one more now.
    pub fn take(&mut self, requester: &str, now: Instant) -> bool {
        if let Some((_, limit)) = self.limits.iter_mut().find(|(r, _)| r == requester) {
            return limit.take(now);
        }
        if self.limits.len() >= MAX_REQUESTERS {
            let oldest = (0..self.limits.len())
                .min_by_key(|&i| self.limits[i].1.last)
                .unwrap_or(0);
            self.limits.swap_remove(oldest);
        }
        let mut limit = RateLimit::new(self.per_s, now);
        let taken = limit.take(now);
        self.limits.push((requester.to_string(), limit));
        taken
    }
}

#[derive(Debug, Default)]
pub(crate) struct Refusals {
    last_said: Option<Instant>,
    /// Refused since the last line, and the newest of them.
    unsaid: u64,
    newest: String,
}

impl Refusals {
    /// One refusal; the line to say now, if one is due.
    pub fn refused(&mut self, why: String, now: Instant) -> Option<String> {
        let why = shortened(why);
        let due = self
            .last_said
            .is_none_or(|at| now.saturating_duration_since(at) >= SAY_EVERY);
        if due && self.unsaid == 0 {
            self.last_said = Some(now);
            return Some(format!("bus: refused: {why}"));
        }
        self.unsaid += 1;
        self.newest = why;
        self.due(now)
    }

    /// The line for the refusals not yet said, once a second has passed.
    pub(crate) fn due(&mut self, now: Instant) -> Option<String> {
        let due = self
            .last_said
            .is_none_or(|at| now.saturating_duration_since(at) >= SAY_EVERY);
        if !due || self.unsaid == 0 {
            return None;
        }
        let line = format!(
            "bus: {} more refused since the last line (the newest: {})",
            self.unsaid, self.newest
        );
        self.unsaid = 0;
        self.last_said = Some(now);
        Some(line)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flood_is_one_line_a_second_with_its_count() {
        let start = Instant::now();
        let mut log = Refusals::default();
        let mut lines = Vec::new();
        // 10 000 refusals over 3 s.
        for i in 0..10_000u64 {
            let now = start + Duration::from_micros(i * 300);
            lines.extend(log.refused(format!("mode autonomous #{i}"), now));
        }
        lines.extend(log.due(start + Duration::from_secs(4)));
        assert!(lines.len() <= 5, "{lines:?}");
        assert!(lines[0].contains("#0"), "{}", lines[0]);
        assert!(lines[1].contains("more refused"), "{}", lines[1]);
        let counted: u64 = lines[1..]
            .iter()
            .map(|l| l.split(' ').nth(1).unwrap().parse::<u64>().unwrap())
            .sum();
        assert_eq!(counted + 1, 10_000, "every refusal is counted: {lines:?}");
    }

    #[test]
    fn one_requesters_flood_leaves_anothers_allowance_whole() {
        let start = Instant::now();
        let mut limits = PerRequester::new(5.0);
        for i in 0..1000u64 {
            limits.take("flooder", start + Duration::from_micros(i));
        }
        assert!(!limits.take("flooder", start + Duration::from_millis(2)));
        assert!(limits.take("operator", start + Duration::from_millis(2)));
        // Names without end keep the table at its size.
        for i in 0..100 {
            limits.take(&format!("n{i}"), start);
        }
        assert_eq!(limits.limits.len(), MAX_REQUESTERS);
    }

    #[test]
    fn a_rate_limit_lets_its_rate_through() {
        let start = Instant::now();
        let mut limit = RateLimit::new(5.0, start);
        let mut taken = 0;
        for i in 0..2000u64 {
            if limit.take(start + Duration::from_millis(i)) {
                taken += 1;
            }
        }
        // A burst of 5, then 5 a second for 2 s.
        assert!((14..=16).contains(&taken), "{taken}");
    }
}
