//! `Pace` over views and times made by hand: when frames are asked for, and when the
//! GUI's heartbeat stops.

use super::*;

/// A GUI thread that draws every frame asked for at once: the times of the frames
/// asked for while `view_at(t)` is shown on `tab` for `seconds`, one look every LOOK_S.
fn frames(view_at: impl Fn(f64) -> View, tab: Tab, seconds: f64) -> Vec<f64> {
    let mut pace = Pace::default();
    let mut passes = 0;
    let mut asked = Vec::new();
    let looks = (seconds / LOOK_S) as usize;
    for k in 0..looks {
        let t_s = k as f64 * LOOK_S;
        let look = pace.look(&view_at(t_s), tab, passes, t_s);
        if look.draw {
            asked.push(t_s);
            passes += 1;
        }
    }
    asked
}

/// A robot standing in Halt whose status advances with the clock (loop figures and
/// counters change, nothing the operator must see at once).
fn standing(t_s: f64) -> View {
    let mut view = View {
        now_s: t_s,
        ..View::default()
    };
    view.status.t_s = t_s;
    view.status.tick = 1 + (t_s * 100.0) as u64;
    view
}

fn driving(t_s: f64) -> View {
    let mut view = standing(t_s);
    view.status.mode = Mode::Autonomous;
    view.status.measured.speed_mps = 0.5;
    view.status.measured.v_left_mps = 0.5 + 0.01 * (t_s * 7.0).sin();
    view
}

#[test]
fn an_idle_gui_draws_its_first_frame_and_then_none() {
    // Nothing in the view changes but the clock: ten seconds without a frame. (Tick 0:
    // a status of a later tick that stops changing is a silent controller, drawn.)
    let mut still = standing(0.0);
    still.status.tick = 0;
    let asked = frames(
        |t_s| View {
            now_s: t_s,
            ..still.clone()
        },
        Tab::Status,
        10.0,
    );
    assert_eq!(asked, [0.0]);
}

#[test]
fn standing_values_are_redrawn_once_a_second() {
    let asked = frames(standing, Tab::Status, 10.0);
    assert!((10..=11).contains(&asked.len()), "{asked:?}");
    for pair in asked.windows(2) {
        let gap_s = pair[1] - pair[0];
        assert!(
            (STANDING_S - LOOK_S..=STANDING_S + LOOK_S).contains(&gap_s),
            "{asked:?}"
        );
    }
}

#[test]
fn while_driving_values_show_within_150_ms_and_plots_five_times_a_second() {
    let asked = frames(driving, Tab::Status, 10.0);
    let worst_gap_s = asked.windows(2).map(|p| p[1] - p[0]).fold(0.0, f64::max);
    assert!(
        worst_gap_s <= 0.15,
        "a value waited {worst_gap_s} s for its frame"
    );
    assert!(asked.len() <= 105, "{} frames in 10 s", asked.len());
    let plots = frames(driving, Tab::Plots, 10.0);
    assert!(
        (45..=55).contains(&plots.len()),
        "{} frames in 10 s",
        plots.len()
    );
}

#[test]
fn a_change_of_mode_is_drawn_at_the_next_look() {
    let asked = frames(
        |t_s| {
            let mut view = standing(t_s);
            if t_s >= 0.5 {
                view.status.mode = Mode::Fault;
            }
            view
        },
        Tab::Status,
        0.8,
    );
    // The first frame at 0, then the fault at the first look from 0.5 s on.
    assert_eq!(asked.len(), 2, "{asked:?}");
    assert!(asked[1] >= 0.5 && asked[1] < 0.5 + LOOK_S, "{asked:?}");
}

#[test]
fn a_controller_that_stops_publishing_is_drawn_at_once() {
    // The status stops at 2 s; the header must say so once it is a second old.
    let asked = frames(
        |t_s| {
            let mut view = standing(t_s.min(2.0));
            view.now_s = t_s;
            view
        },
        Tab::Status,
        3.5,
    );
    let silent_s = 2.0 + SUPERVISOR_SILENT_S;
    assert!(
        asked
            .iter()
            .any(|&t| t > silent_s && t < silent_s + LOOK_S + 1e-9),
        "{asked:?}"
    );
}

#[test]
fn a_gui_thread_that_does_not_draw_stops_the_heartbeat() {
    let mut pace = Pace::default();
    // The first frame is asked for and drawn: beats.
    assert!(pace.look(&driving(0.0), Tab::Status, 0, 0.0).draw);
    let look = pace.look(&driving(LOOK_S), Tab::Status, 1, LOOK_S);
    assert!(look.beat);
    // The next frame is asked for, and the GUI thread never runs it again (passes stay
    // at 1): no beat from then on, and no second request piled on the first.
    let mut drew = 0;
    for k in 2..100 {
        let t_s = k as f64 * LOOK_S;
        let look = pace.look(&driving(t_s), Tab::Status, 1, t_s);
        drew += usize::from(look.draw);
        if drew == 1 && !look.draw {
            assert!(!look.beat, "beat at {t_s} s with a frame owed");
        }
    }
    assert_eq!(drew, 1);
    // The GUI thread runs again: the beat is back.
    assert!(pace.look(&driving(4.0), Tab::Status, 2, 4.0).beat);
}
