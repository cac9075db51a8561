//! Protected objects: state shared between threads, with exactly one writing thread.
//!
//! `shared(initial)` gives one `Writer` (not `Clone`: it is handed to the owning thread
//! at start, so the type system says who may write) and a `Reader` that any thread may
//! clone. Values are `Copy`: a reader copies a snapshot out and never holds the lock
//! across I/O, a sleep or a GUI frame; the writer holds it only to copy a value in.
//!
//! The supervisor runs at the highest priority and must never wait for a thread of
//! lower priority that holds a lock and is preempted (the lock has no priority
//! inheritance): it uses `try_snapshot` and `try_publish`, which never wait, keeps its
//! last copy when the lock is busy, and counts how often it was.

pub mod commission;
pub mod cross_track;
pub mod fault_advice;
pub mod fault_cause;
pub mod measure;
pub mod modes;
pub mod operator;
pub mod request_channel;
pub mod sensor_down;
pub mod status;
pub mod steering;

use std::sync::Arc;

use parking_lot::RwLock;

/// The one handle that may change the object.
pub struct Writer<T: Copy> {
    cell: Arc<RwLock<T>>,
}

/// A handle that may only read snapshots of the object.
pub struct Reader<T: Copy> {
    cell: Arc<RwLock<T>>,
}

impl<T: Copy> Clone for Reader<T> {
    fn clone(&self) -> Self {
        Reader {
            cell: Arc::clone(&self.cell),
        }
    }
}

/// Create a protected object holding `initial`.
pub fn shared<T: Copy>(initial: T) -> (Writer<T>, Reader<T>) {
    let cell = Arc::new(RwLock::new(initial));
    (
        Writer {
            cell: Arc::clone(&cell),
        },
        Reader { cell },
    )
}

impl<T: Copy> Writer<T> {
    /// Replace the object's value.
    pub fn publish(&self, value: &T) {
        *self.cell.write() = *value;
    }

    /// Replace the value unless a reader holds the lock right now; never waits.
    /// Returns false if the lock was busy (the caller publishes again next time).
    pub(crate) fn try_publish(&self, value: &T) -> bool {
        match self.cell.try_write() {
            Some(mut cell) => {
                *cell = *value;
                true
            }
            None => false,
        }
    }

    /// Another reader of the same object.
    pub fn reader(&self) -> Reader<T> {
        Reader {
            cell: Arc::clone(&self.cell),
        }
    }
}

impl<T: Copy> Reader<T> {
    /// A copy of the object's value now.
    pub fn snapshot(&self) -> T {
        *self.cell.read()
    }

    /// A copy of the value, or None if the writer holds the lock right now; never waits.
    pub(crate) fn try_snapshot(&self) -> Option<T> {
        self.cell.try_read().map(|cell| *cell)
    }
}

/// The latest value of an object written by a thread of lower priority, read without
/// ever waiting: a busy lock gives the copy from last time, and is counted.
pub struct Latest<T: Copy> {
    reader: Reader<T>,
    last: T,
}

impl<T: Copy> Latest<T> {
    pub fn new(reader: Reader<T>) -> Latest<T> {
        let last = reader.snapshot();
        Latest { reader, last }
    }

    /// The newest value there is to be had without waiting; adds 1 to `busy` if the
    /// lock was held.
    pub fn get(&mut self, busy: &mut u64) -> T {
        match self.reader.try_snapshot() {
            Some(value) => self.last = value,
            None => *busy += 1,
        }
        self.last
    }
}

/// The sending end of a one-place mailbox: a newer letter replaces one not yet taken,
/// and neither side ever waits. (A plain one-place channel would keep the older letter
/// and drop the newer one.)
pub struct Mailbox<T> {
    tx: crossbeam_channel::Sender<T>,
    unread: crossbeam_channel::Receiver<T>,
}

/// A one-place mailbox: the sender, and the receiver for the one thread that takes.
pub fn mailbox<T>() -> (Mailbox<T>, crossbeam_channel::Receiver<T>) {
    let (tx, rx) = crossbeam_channel::bounded(1);
    (
        Mailbox {
            tx,
            unread: rx.clone(),
        },
        rx,
    )
}

impl<T> Mailbox<T> {
    /// Post `letter`, taking back one not yet read.
    pub fn post(&self, letter: T) {
        while self.unread.try_recv().is_ok() {}
        // The place is free now: the receiver only takes, and a Mailbox is not Clone.
        let _ = self.tx.try_send(letter);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn readers_see_what_the_writer_publishes() {
        let (writer, reader) = shared(1u32);
        let other = reader.clone();
        writer.publish(&7);
        assert_eq!(reader.snapshot(), 7);
        assert_eq!(other.snapshot(), 7);
        let from_thread = std::thread::spawn(move || other.snapshot()).join().unwrap();
        assert_eq!(from_thread, 7);
    }

    #[test]
    fn the_supervisors_reads_and_writes_never_wait_for_a_lock_holder() {
        let (writer, reader) = shared(1u32);
        let mut latest = Latest::new(reader.clone());
        let mut busy = 0;
        writer.publish(&2);
        assert_eq!(latest.get(&mut busy), 2);
        {
            // A lower-priority writer preempted while it holds the lock.
            let _held = writer.cell.write();
            assert_eq!(latest.get(&mut busy), 2, "the last copy, at once");
            assert_eq!(busy, 1);
        }
        {
            // A lower-priority reader preempted while it holds the lock.
            let _held = reader.cell.read();
            assert!(!writer.try_publish(&3), "gave up at once");
        }
        assert!(writer.try_publish(&3));
        assert_eq!(latest.get(&mut busy), 3);
        assert_eq!(busy, 1);
    }

    #[test]
    fn a_newer_letter_replaces_one_not_yet_taken() {
        let (mailbox, rx) = mailbox();
        mailbox.post(1);
        mailbox.post(2);
        assert_eq!(rx.try_recv(), Ok(2));
        assert!(rx.try_recv().is_err());
    }
}
