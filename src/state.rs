//! Protected objects: state shared between threads, with exactly one writing thread.
//!
//! `shared(initial)` gives one `Writer` (not `Clone`: it is handed to the owning thread
//! at start, so the type system says who may write) and a `Reader` that any thread may
//! clone. Values are `Copy`: a reader copies a snapshot out and never holds the lock
//! across I/O, a sleep or a GUI frame; the writer holds it only to copy a value in.

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
}
