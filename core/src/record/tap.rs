//! The supervisor thread's end of the recording queue. `offer` copies the tick into a
//! bounded queue with `try_send`: it never allocates, never blocks and makes no system
//! call. When the recorder falls behind, whole ticks are dropped and counted.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use crossbeam_channel::{Sender, TrySendError};
use mechweed_hw::sim::{Truth, TruthHandle};

use super::event::{EventKind, RecordEvent};
use super::row::{Given, TickSample};
use crate::camlink::LinkStatus;
use crate::state::modes::{Mode, Refusal, Request};
use crate::state::status::{Notice, Status};
use crate::steer::SteerCommand;

/// What to do when the queue is full.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Delivery {
    /// Real time: drop the tick and count it; the robot never waits for the disk.
    NeverWait,
    /// Simulated time (lockstep): wait for room, so a record of a simulation is whole.
    WaitForRoom,
}

/// Counts shared by the tap and the recorder's handle.
#[derive(Debug, Default)]
pub(super) struct Counters {
    pub ticks_dropped: AtomicU64,
    pub events_dropped: AtomicU64,
}

/// Hands ticks and events to the recorder thread. A tap from `RecordTap::off()`
/// does nothing.
pub struct RecordTap {
    queue: Option<Queues>,
    last_mode: Mode,
    last_fault_tick: Option<u64>,
    last_notice: Option<Notice>,
}

struct Queues {
    ticks: Sender<TickSample>,
    events: Sender<RecordEvent>,
    every_n_ticks: u64,
    delivery: Delivery,
    counters: Arc<Counters>,
    truth: Option<TruthHandle>,
}

impl RecordTap {
    /// A tap that records nothing (recording off, or the record could not be made).
    pub fn off() -> RecordTap {
        RecordTap {
            queue: None,
            last_mode: Mode::Halt,
            last_fault_tick: None,
            last_notice: None,
        }
    }

    pub(super) fn new(
        ticks: Sender<TickSample>,
        events: Sender<RecordEvent>,
        every_n_ticks: u64,
        delivery: Delivery,
        counters: Arc<Counters>,
        truth: Option<TruthHandle>,
    ) -> RecordTap {
        RecordTap {
            queue: Some(Queues {
                ticks,
                events,
                every_n_ticks: every_n_ticks.max(1),
                delivery,
                counters,
                truth,
            }),
            ..RecordTap::off()
        }
    }

    /// The real-time supervisor thread's call, after it published `status`, with the
    /// steer command and link status it ticked with: for this tap (the recorder's) and
    /// `also` (the bus's). The simulated robot's truth, behind a lock the plant shares,
    /// is read once for both, and only on a tick one of them keeps.
    pub fn after_tick(
        &mut self,
        also: &mut RecordTap,
        status: &Status,
        steer: &SteerCommand,
        link: &LinkStatus,
        given: &Given,
    ) {
        let truth = [&*self, &*also]
            .into_iter()
            .filter_map(|tap| tap.queue.as_ref())
            .find(|q| status.tick.is_multiple_of(q.every_n_ticks))
            .and_then(|q| q.truth.as_ref())
            .map(TruthHandle::truth);
        self.offer(status, steer, link, truth.as_ref(), given);
        also.offer(status, steer, link, truth.as_ref(), given);
    }

    /// Offer one tick (every tick: events are found here, ticks kept every Nth).
    pub fn offer(
        &mut self,
        status: &Status,
        steer: &SteerCommand,
        link: &LinkStatus,
        truth: Option<&Truth>,
        given: &Given,
    ) {
        self.offer_events(status);
        let Some(q) = &self.queue else { return };
        if !status.tick.is_multiple_of(q.every_n_ticks) {
            return;
        }
        let sample = TickSample {
            status: *status,
            steer: *steer,
            link: *link,
            truth: truth.copied(),
            given: *given,
        };
        let sent = match q.delivery {
            Delivery::NeverWait => match q.ticks.try_send(sample) {
                Err(TrySendError::Full(_)) => false,
                // The recorder has ended (it logged why): nothing to count.
                Ok(()) | Err(TrySendError::Disconnected(_)) => true,
            },
            Delivery::WaitForRoom => {
                let _ = q.ticks.send(sample);
                true
            }
        };
        if !sent {
            q.counters.ticks_dropped.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// A request the supervisor handled just before tick `tick` (at `t_s`), and its
    /// answer: a replay gives it again at the same tick.
    pub fn requested(
        &mut self,
        t_s: f64,
        tick: u64,
        request: Request,
        answer: Result<(), Refusal>,
    ) {
        let kind = EventKind::Request { request, answer };
        self.send_event(RecordEvent { t_s, tick, kind });
    }

    fn send_event(&self, event: RecordEvent) {
        let Some(q) = &self.queue else { return };
        let sent = match q.delivery {
            Delivery::NeverWait => !matches!(q.events.try_send(event), Err(TrySendError::Full(_))),
            Delivery::WaitForRoom => {
                let _ = q.events.send(event);
                true
            }
        };
        if !sent {
            q.counters.events_dropped.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// Mode changes, new faults and new notices, from one status to the next.
    fn offer_events(&mut self, status: &Status) {
        let mut found: [Option<EventKind>; 3] = [None; 3];
        if status.mode != self.last_mode {
            found[0] = Some(EventKind::Mode {
                from: self.last_mode,
                to: status.mode,
            });
            self.last_mode = status.mode;
        }
        if let Some(fault) = status.fault
            && self.last_fault_tick != Some(fault.tick_seen)
        {
            self.last_fault_tick = Some(fault.tick_seen);
            found[1] = Some(EventKind::Fault(fault.cause));
        }
        if status.notice != self.last_notice {
            self.last_notice = status.notice;
            found[2] = status.notice.map(EventKind::Notice);
        }
        for kind in found.into_iter().flatten() {
            self.send_event(RecordEvent {
                t_s: status.t_s,
                tick: status.tick,
                kind,
            });
        }
    }
}
