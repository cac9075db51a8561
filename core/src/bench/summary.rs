//! `bench rows --seeds A-B`: the runs of many seeds summed up per source and speed, each
//! run judged by its RMS over its steering bound's RMS, like with like (the mean counts:
//! a tool that runs to one side of the crop misses as surely as one that swings), and
//! over the achievable reference.

use std::fmt::Write;

use crate::bench::rows::RowRun;

/// One source at one speed over every seed and row.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    pub source: String,
    pub speed_mps: f64,
    pub runs: usize,
    /// Runs the supervisor stopped (a fault): their figures cover only the row before it,
    /// and are left out of the ratios.
    pub stopped: usize,
    /// The tool's RMS over the steering bound's RMS, of the runs that finished: median
    /// and worst (None without a bound: the clean field, or every run stopped).
    pub median_ratio: Option<f64>,
    pub worst_ratio: Option<f64>,
    /// The tool's RMS over the achievable RMS, median, of the same runs.
    pub median_achievable_ratio: Option<f64>,
    /// Runs whose tool went farther than 8 and 10 cm from the row at some point.
    pub over_8cm: usize,
    pub over_10cm: usize,
}

/// The runs grouped by source and speed, in the order they first come.
pub fn summarise(runs: &[RowRun]) -> Vec<Summary> {
    let mut groups: Vec<(String, f64, Vec<&RowRun>)> = Vec::new();
    for run in runs {
        match (groups.iter_mut()).find(|(s, v, _)| *s == run.source && *v == run.speed_mps) {
            Some((_, _, members)) => members.push(run),
            None => groups.push((run.source.clone(), run.speed_mps, vec![run])),
        }
    }
    groups
        .into_iter()
        .map(|(source, speed_mps, members)| {
            let ratios = |reference: fn(&RowRun) -> Option<f64>| {
                let mut ratios: Vec<f64> = (members.iter())
                    .filter(|r| r.faults.is_empty())
                    .filter_map(|r| Some(r.cross_track_cm.rms_cm / reference(r)?))
                    .collect();
                ratios.sort_by(f64::total_cmp);
                ratios
            };
            let to_bound = ratios(|r| r.steering_bound_rms_cm);
            let over = |cm: f64| {
                members
                    .iter()
                    .filter(|r| r.cross_track_cm.max_cm > cm)
                    .count()
            };
            Summary {
                source,
                speed_mps,
                runs: members.len(),
                stopped: members.iter().filter(|r| !r.faults.is_empty()).count(),
                median_ratio: median(&to_bound),
                worst_ratio: to_bound.last().copied(),
                median_achievable_ratio: median(&ratios(|r| r.achievable_rms_cm)),
                over_8cm: over(8.0),
                over_10cm: over(10.0),
            }
        })
        .collect()
}

fn median(sorted: &[f64]) -> Option<f64> {
    let n = sorted.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(sorted[n / 2]),
        _ => Some((sorted[n / 2 - 1] + sorted[n / 2]) / 2.0),
    }
}

/// The summary as `bench rows --seeds` prints it.
pub fn summary_table(summaries: &[Summary]) -> String {
    let mut out = String::from(
        "source  speed  runs  stopped  RMS/bound's RMS  RMS/reach  >8cm  >10cm\n         m/s                 median  worst     median\n",
    );
    let ratio = |r: Option<f64>| r.map_or("-".to_string(), |r| format!("{r:.2}"));
    for s in summaries {
        let _ = writeln!(
            out,
            "{:<7} {:5.1} {:5} {:8} {:>7} {:>6} {:>10} {:5} {:6}",
            s.source,
            s.speed_mps,
            s.runs,
            s.stopped,
            ratio(s.median_ratio),
            ratio(s.worst_ratio),
            ratio(s.median_achievable_ratio),
            s.over_8cm,
            s.over_10cm
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use mechweed_hw::sim::CrossTrackSummary;

    fn run(source: &str, speed_mps: f64, rms_cm: f64, max_cm: f64, stopped: bool) -> RowRun {
        RowRun {
            field: "realistic".into(),
            source: source.into(),
            row: "straight".into(),
            speed_mps,
            cross_track_cm: CrossTrackSummary {
                rms_cm,
                max_cm,
                ..CrossTrackSummary::default()
            },
            filter_error_cm: None,
            filter_floor_cm: None,
            steering_bound_cm: Some(0.9),
            steering_bound_rms_cm: Some(1.0),
            achievable_rms_cm: Some(0.5),
            achievable_wheel_rate_dps: Some(20.0),
            faults: if stopped {
                vec!["0.5 s: a fault".into()]
            } else {
                vec![]
            },
            sim_time_s: 10.0,
        }
    }

    #[test]
    fn a_stopped_run_is_counted_but_left_out_of_the_ratios() {
        let runs = [
            run("camera", 1.0, 1.2, 4.0, false),
            run("camera", 1.0, 1.6, 9.0, false),
            run("camera", 1.0, 2.0, 11.0, false),
            // Stopped early with a small RMS: comparing it would flatter the law.
            run("camera", 1.0, 0.1, 30.0, true),
            run("fused", 1.0, 1.1, 3.0, false),
        ];
        let s = summarise(&runs);
        assert_eq!(s.len(), 2);
        let camera = &s[0];
        assert_eq!((camera.runs, camera.stopped), (4, 1));
        assert_eq!(
            (camera.median_ratio, camera.worst_ratio),
            (Some(1.6), Some(2.0))
        );
        assert_eq!((camera.over_8cm, camera.over_10cm), (3, 2));
        assert_eq!(s[1].median_ratio, Some(1.1));
        // Like with like: the RMS over the bound's RMS, not over its s.d.
        assert_eq!(camera.median_achievable_ratio, Some(3.2));
        let table = summary_table(&s);
        assert!(table.lines().nth(2).unwrap().contains("1.60"), "{table}");
    }
}
