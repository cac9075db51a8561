//! Who is on the bus: every mechweed program declares a liveliness token
//! `ROBOT/alive/NAME` while it runs, and Zenoh takes it back when the program ends or
//! its link drops. Watching the tokens is how the GUI and the report know who is there,
//! without anyone announcing or polling.

use std::collections::BTreeSet;

use crossbeam_channel::{Receiver, bounded};
use zenoh::sample::SampleKind;
use zenoh::{Session, Wait};

/// Token changes waiting to be counted; more are lost (the count is then off until the
/// next change of that token).
const QUEUE_CHANGES: usize = 256;
/// Programs kept at most: their names are the peers' to choose, so the table is bounded
/// (more are not counted).
const MAX_PRESENT: usize = 64;

pub(crate) struct Peers {
    present: BTreeSet<String>,
    /// (appeared, key) as zenoh's callback handed them on.
    changes: Receiver<(bool, String)>,
    _subscriber: zenoh::pubsub::Subscriber<()>,
}

impl Peers {
    /// Watch the tokens under `key` (e.g. mechweed/alive/**), those already there too.
    pub fn watch(session: &Session, key: &str) -> zenoh::Result<Peers> {
        let (tx, changes) = bounded(QUEUE_CHANGES);
        let subscriber = session
            .liveliness()
            .declare_subscriber(key)
            .history(true)
            .callback(move |sample| {
                let appeared = sample.kind() == SampleKind::Put;
                let _ = tx.try_send((appeared, sample.key_expr().as_str().to_string()));
            })
            .wait()?;
        Ok(Peers {
            present: BTreeSet::new(),
            changes,
            _subscriber: subscriber,
        })
    }

    /// The tokens present, as their keys, the newest changes taken.
    pub fn present(&mut self) -> Vec<String> {
        self.take_changes();
        self.present.iter().cloned().collect()
    }

    /// How many other programs are present (every token but this program's own).
    pub fn others(&mut self, own: &str) -> u32 {
        self.take_changes();
        self.present.iter().filter(|k| *k != own).count() as u32
    }

    fn take_changes(&mut self) {
        while let Ok((appeared, key)) = self.changes.try_recv() {
            if appeared {
                if self.present.len() < MAX_PRESENT {
                    self.present.insert(key);
                }
            } else {
                self.present.remove(&key);
            }
        }
    }
}
