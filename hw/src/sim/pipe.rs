//! An in-memory serial line: a duplex byte pipe between the simulated camera computer
//! and the robot computer's camera link.
//!
//! It behaves like a UART with a receive buffer: reading blocks until a byte arrives or
//! the read time-out passes (then `TimedOut`, as the serialport crate does); writing never
//! blocks, and bytes that find the receiver's buffer full are lost and counted as
//! overruns. Both buffers are allocated once, at their full capacity, and never grow.

use std::collections::VecDeque;
use std::io;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::Duration;

/// The read time-out of a new end, like a serial port opened with 10 ms.
const DEFAULT_READ_TIMEOUT: Duration = Duration::from_millis(10);

/// The bytes travelling in one direction.
struct Direction {
    buffer: Mutex<Buffer>,
    arrived: Condvar,
}

struct Buffer {
    bytes: VecDeque<u8>,
    capacity: usize,
    overruns: u64,
}

impl Direction {
    fn new(capacity: usize) -> Direction {
        Direction {
            buffer: Mutex::new(Buffer {
                bytes: VecDeque::with_capacity(capacity),
                capacity,
                overruns: 0,
            }),
            arrived: Condvar::new(),
        }
    }

    /// A poisoned lock only means another thread panicked while holding it; the bytes
    /// are still a valid queue, so carry on with them.
    fn lock(&self) -> MutexGuard<'_, Buffer> {
        self.buffer
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

/// One end of the pipe.
pub struct PipeEnd {
    /// [0]: camera side -> robot side, [1]: robot side -> camera side.
    directions: Arc<[Direction; 2]>,
    /// Index of the direction this end reads from (it writes to the other one).
    rx: usize,
    read_timeout: Duration,
}

/// A pipe whose buffers hold `capacity` bytes each way. The first end is the camera
/// computer's, the second the robot computer's.
pub fn byte_pipe(capacity: usize) -> (PipeEnd, PipeEnd) {
    let directions = Arc::new([Direction::new(capacity), Direction::new(capacity)]);
    let camera = PipeEnd {
        directions: Arc::clone(&directions),
        rx: 1,
        read_timeout: DEFAULT_READ_TIMEOUT,
    };
    let robot = PipeEnd {
        directions,
        rx: 0,
        read_timeout: DEFAULT_READ_TIMEOUT,
    };
    (camera, robot)
}

impl PipeEnd {
    pub fn set_read_timeout(&mut self, timeout: Duration) {
        self.read_timeout = timeout;
    }

    /// Take what has arrived, without waiting; returns the number of bytes copied.
    pub fn try_read(&mut self, buf: &mut [u8]) -> usize {
        let mut rx = self.directions[self.rx].lock();
        take(&mut rx.bytes, buf)
    }

    /// Bytes lost on the way to this end because its receive buffer was full (a UART's
    /// overrun count).
    pub fn overruns(&self) -> u64 {
        self.directions[self.rx].lock().overruns
    }

    /// Put bytes on the line; those that do not fit in the receiver's buffer are lost.
    pub(crate) fn send(&self, bytes: &[u8]) {
        let direction = &self.directions[1 - self.rx];
        let mut tx = direction.lock();
        let room = tx.capacity.saturating_sub(tx.bytes.len());
        let fits = bytes.len().min(room);
        tx.bytes.extend(&bytes[..fits]);
        tx.overruns += (bytes.len() - fits) as u64;
        drop(tx);
        if fits > 0 {
            direction.arrived.notify_all();
        }
    }
}

fn take(queue: &mut VecDeque<u8>, buf: &mut [u8]) -> usize {
    let n = buf.len().min(queue.len());
    for (slot, byte) in buf.iter_mut().zip(queue.drain(..n)) {
        *slot = byte;
    }
    n
}

impl io::Read for PipeEnd {
    /// Wait up to the read time-out for at least one byte, then return what is there.
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if buf.is_empty() {
            return Ok(0);
        }
        let direction = &self.directions[self.rx];
        let guard = direction.lock();
        let (mut rx, _) = direction
            .arrived
            .wait_timeout_while(guard, self.read_timeout, |b| b.bytes.is_empty())
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        if rx.bytes.is_empty() {
            return Err(io::Error::from(io::ErrorKind::TimedOut));
        }
        Ok(take(&mut rx.bytes, buf))
    }
}

impl io::Write for PipeEnd {
    /// Never blocks; always reports every byte written, as a UART does (the receiver
    /// counts what it lost).
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.send(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::{Read, Write};
    use std::time::Instant;

    #[test]
    fn bytes_cross_both_ways() {
        let (mut camera, mut robot) = byte_pipe(64);
        robot.write_all(&[0x10, 0x12]).unwrap();
        camera.write_all(b"hello").unwrap();
        let mut buf = [0u8; 8];
        assert_eq!(camera.try_read(&mut buf), 2);
        assert_eq!(&buf[..2], &[0x10, 0x12]);
        assert_eq!(robot.read(&mut buf).unwrap(), 5);
        assert_eq!(&buf[..5], b"hello");
        assert_eq!(robot.try_read(&mut buf), 0);
    }

    #[test]
    fn full_buffer_drops_and_counts_the_excess() {
        let (mut camera, mut robot) = byte_pipe(4);
        assert_eq!(camera.write(&[1, 2, 3, 4, 5, 6]).unwrap(), 6);
        assert_eq!(robot.overruns(), 2);
        assert_eq!(camera.overruns(), 0);
        let mut buf = [0u8; 8];
        assert_eq!(robot.try_read(&mut buf), 4);
        assert_eq!(&buf[..4], &[1, 2, 3, 4]);
    }

    #[test]
    fn read_times_out_like_a_serial_port() {
        let (_camera, mut robot) = byte_pipe(4);
        robot.set_read_timeout(Duration::from_millis(20));
        let start = Instant::now();
        let err = robot.read(&mut [0u8; 4]).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::TimedOut);
        assert!(start.elapsed() >= Duration::from_millis(20));
    }

    #[test]
    fn blocked_read_wakes_when_a_byte_arrives() {
        let (mut camera, mut robot) = byte_pipe(16);
        robot.set_read_timeout(Duration::from_secs(5));
        let writer = std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(20));
            camera.write_all(&[0xA5]).unwrap();
        });
        let start = Instant::now();
        let mut buf = [0u8; 4];
        assert_eq!(robot.read(&mut buf).unwrap(), 1);
        assert_eq!(buf[0], 0xA5);
        assert!(start.elapsed() < Duration::from_secs(2));
        writer.join().unwrap();
    }
}
