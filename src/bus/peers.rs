//! Who is on the bus: every mechweed program declares a liveliness token
//! `ROBOT/alive/NAME` while it runs, and Zenoh takes it back when the program ends or
//! its link drops. Watching the tokens is how `bus list`, the GUI and the report know
//! who is there, without anyone announcing or polling.

use std::collections::BTreeSet;
use std::sync::Arc;

use parking_lot::Mutex;
use zenoh::sample::SampleKind;
use zenoh::{Session, Wait};

pub struct Peers {
    present: Arc<Mutex<BTreeSet<String>>>,
    _subscriber: zenoh::pubsub::Subscriber<()>,
}

impl Peers {
    /// Watch the tokens under `key` (e.g. mechweed/alive/**), those already there too.
    pub fn watch(session: &Session, key: &str) -> zenoh::Result<Peers> {
        let present: Arc<Mutex<BTreeSet<String>>> = Arc::default();
        let seen = Arc::clone(&present);
        let subscriber = session
            .liveliness()
            .declare_subscriber(key)
            .history(true)
            .callback(move |sample| {
                let name = sample.key_expr().as_str().to_string();
                match sample.kind() {
                    SampleKind::Put => seen.lock().insert(name),
                    SampleKind::Delete => seen.lock().remove(&name),
                };
            })
            .wait()?;
        Ok(Peers {
            present,
            _subscriber: subscriber,
        })
    }

    /// The keys of the tokens present now, sorted.
    pub fn present(&self) -> Vec<String> {
        self.present.lock().iter().cloned().collect()
    }

    /// How many other programs are present (every token but this program's own).
    pub fn others(&self, own: &str) -> u32 {
        self.present.lock().iter().filter(|k| *k != own).count() as u32
    }
}
