//! One card's register window, one byte at a time: the only thing the card drivers
//! need from Linux (docs/function_spec.md section 4a).
//!
//! Every access is exactly one byte at the register's own offset, because that is one
//! port access on the card. The LS7266R1's three count bytes, for example, are three
//! reads of the same offset; a 3-byte read would touch three different ports.
//!
//! Backends: [`SysfsBar`] (a PCI device's `resourceN` file of an I/O-port BAR, where the
//! file offset is the register offset) and [`DevPort`] (`/dev/port`, where the file
//! offset is the port number). [`CountingPort`] wraps either to count accesses. The
//! emulated cards (emulated/) implement the same trait for tests.
//!
//! Each card's file is locked, so that a second program is refused. /dev/port is one
//! file for every card: it is opened and locked once per program ([`DevPortFile`]),
//! and each card reached through it is a view of that one handle at its own base.

use std::fs::{File, OpenOptions};
use std::io;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// Read or write one byte at `offset` inside one card's register window.
pub trait PortIo: Send {
    fn read_u8(&mut self, offset: u16) -> io::Result<u8>;
    fn write_u8(&mut self, offset: u16, value: u8) -> io::Result<()>;
}

/// An error for an offset outside the window: a driver bug, never a card's fault.
fn outside(offset: u16, len: u16) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        format!("register offset {offset:#x} is outside the card's {len}-byte window"),
    )
}

/// True if the kernel is in lockdown (secure boot), which refuses all port access.
pub(crate) fn kernel_locked_down() -> bool {
    std::fs::read_to_string("/sys/kernel/security/lockdown")
        .map(|text| !text.contains("[none]"))
        .unwrap_or(false)
}

/// A file whose byte at `base + offset` is the card's register at `offset`.
///
/// A failing access returns the system's error as it is, or a bare kind for a short
/// transfer: neither allocates, so a tick whose card fails allocates nothing (only an
/// offset outside the window, a driver bug that no tick reaches, has a message). The
/// driver turns it into an error naming the card and the register; why a refused
/// access was refused (a locked-down kernel lets the file open and refuses the first
/// access) is looked up once, at start ([`crate::StartError`]).
struct ByteFile {
    /// Shared by the cards reached through /dev/port; one owner for a sysfs BAR.
    file: Arc<File>,
    base: u64,
    len: u16,
}

impl ByteFile {
    fn read_u8(&self, offset: u16) -> io::Result<u8> {
        if offset >= self.len {
            return Err(outside(offset, self.len));
        }
        let mut byte = [0u8; 1];
        match self
            .file
            .read_at(&mut byte, self.base + u64::from(offset))?
        {
            1 => Ok(byte[0]),
            _ => Err(io::ErrorKind::UnexpectedEof.into()),
        }
    }

    fn write_u8(&self, offset: u16, value: u8) -> io::Result<()> {
        if offset >= self.len {
            return Err(outside(offset, self.len));
        }
        match self
            .file
            .write_at(&[value], self.base + u64::from(offset))?
        {
            1 => Ok(()),
            _ => Err(io::ErrorKind::WriteZero.into()),
        }
    }
}

/// Open read-write and take an exclusive lock, so that two programs (a run and a
/// probe) never drive the same card at once.
fn open_locked(path: &Path) -> io::Result<File> {
    let file = OpenOptions::new().read(true).write(true).open(path)?;
    match file.try_lock() {
        Ok(()) => Ok(file),
        Err(std::fs::TryLockError::WouldBlock) => Err(io::Error::new(
            io::ErrorKind::ResourceBusy,
            format!(
                "{} is in use by another program (is mechweed already running?)",
                path.display()
            ),
        )),
        Err(std::fs::TryLockError::Error(e)) => Err(e),
    }
}

/// A card's I/O-port BAR through sysfs: `/sys/bus/pci/devices/<address>/resourceN`.
pub(crate) struct SysfsBar(ByteFile);

impl SysfsBar {
    /// Open the BAR file; `len` is the card's register window (bytes).
    pub fn open(path: &Path, len: u16) -> io::Result<SysfsBar> {
        Ok(SysfsBar(ByteFile {
            file: Arc::new(open_locked(path)?),
            base: 0,
            len,
        }))
    }
}

impl PortIo for SysfsBar {
    fn read_u8(&mut self, offset: u16) -> io::Result<u8> {
        self.0.read_u8(offset)
    }
    fn write_u8(&mut self, offset: u16, value: u8) -> io::Result<()> {
        self.0.write_u8(offset, value)
    }
}

/// `/dev/port` for this program: opened and locked by the first card that needs it,
/// shared by the others. A lock per card would refuse the second card as "in use by
/// another program"; one lock still refuses a second program.
pub struct DevPortFile {
    path: PathBuf,
    file: Option<Arc<File>>,
}

impl DevPortFile {
    /// Nothing is opened yet: a program whose cards are all on sysfs never opens it.
    pub fn new(path: &Path) -> DevPortFile {
        DevPortFile {
            path: path.to_path_buf(),
            file: None,
        }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// A card's window: `base` its first port, `len` its registers. The first call
    /// opens and locks the file; a failed open is tried again by the next card, so
    /// that each card reports it.
    pub fn card(&mut self, base: u16, len: u16) -> io::Result<DevPort> {
        let file = match &self.file {
            Some(file) => file.clone(),
            None => self.file.insert(Arc::new(open_locked(&self.path)?)).clone(),
        };
        Ok(DevPort(ByteFile {
            file,
            base: u64::from(base),
            len,
        }))
    }
}

/// A card's ports through `/dev/port`, from a base port set in robot.ini.
pub struct DevPort(ByteFile);

impl PortIo for DevPort {
    fn read_u8(&mut self, offset: u16) -> io::Result<u8> {
        self.0.read_u8(offset)
    }
    fn write_u8(&mut self, offset: u16, value: u8) -> io::Result<()> {
        self.0.write_u8(offset, value)
    }
}

/// How many port accesses went through a [`CountingPort`]; cloneable, readable anywhere.
#[derive(Clone, Default)]
pub struct AccessCount {
    reads: Arc<AtomicU64>,
    writes: Arc<AtomicU64>,
}

impl AccessCount {
    pub fn reads(&self) -> u64 {
        self.reads.load(Ordering::Relaxed)
    }
    pub fn writes(&self) -> u64 {
        self.writes.load(Ordering::Relaxed)
    }
    pub fn total(&self) -> u64 {
        self.reads() + self.writes()
    }
}

/// Counts every access to the port it wraps (for benchmarks: accesses per tick).
pub struct CountingPort<P> {
    inner: P,
    count: AccessCount,
}

impl<P: PortIo> CountingPort<P> {
    /// Wrap `inner`, adding to `count` (share one count between several cards).
    pub fn new(inner: P, count: AccessCount) -> CountingPort<P> {
        CountingPort { inner, count }
    }
}

impl<P: PortIo> PortIo for CountingPort<P> {
    fn read_u8(&mut self, offset: u16) -> io::Result<u8> {
        self.count.reads.fetch_add(1, Ordering::Relaxed);
        self.inner.read_u8(offset)
    }
    fn write_u8(&mut self, offset: u16, value: u8) -> io::Result<()> {
        self.count.writes.fetch_add(1, Ordering::Relaxed);
        self.inner.write_u8(offset, value)
    }
}

impl PortIo for Box<dyn PortIo> {
    fn read_u8(&mut self, offset: u16) -> io::Result<u8> {
        (**self).read_u8(offset)
    }
    fn write_u8(&mut self, offset: u16, value: u8) -> io::Result<()> {
        (**self).write_u8(offset, value)
    }
}

#[cfg(test)]
#[path = "port_tests.rs"]
mod tests;
