//! Records never fill the disk: the recorder looks at the free space of its folder's
//! disk every few seconds and stops writing (its files closed, said once) when it is
//! nearly full, so that the robot PC's journal, settings and the next run's record
//! still fit; the robot runs on. `[record] keep_gb` (keep.rs) bounds the folder itself.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Below this much free space the recorder stops: about two and a half hours of
/// records at 100 Hz in both formats, and room for the files' closing index.
pub const NEARLY_FULL_BYTES: u64 = 1 << 30;

/// How often the free space is looked at: a record grows about 0.1 MB a second.
const LOOK_EVERY: Duration = Duration::from_secs(5);

/// How the free space is read (the disk's, or a test's).
pub type FreeBytes = fn(&Path) -> Option<u64>;

/// The recorder's watch on its folder's disk.
pub struct SpaceWatch {
    folder: PathBuf,
    free_bytes: FreeBytes,
    nearly_full_bytes: u64,
    look_every: Duration,
    last_look: Option<Instant>,
}

impl SpaceWatch {
    /// Watch the disk of `folder`.
    pub fn of(folder: &Path) -> SpaceWatch {
        SpaceWatch::with(folder, disk_free_bytes, NEARLY_FULL_BYTES, LOOK_EVERY)
    }

    /// Watch with another reading of the free space, threshold and pace (the tests'
    /// full disk).
    pub fn with(
        folder: &Path,
        free_bytes: FreeBytes,
        nearly_full_bytes: u64,
        look_every: Duration,
    ) -> SpaceWatch {
        SpaceWatch {
            folder: folder.to_path_buf(),
            free_bytes,
            nearly_full_bytes,
            look_every,
            last_look: None,
        }
    }

    /// Why the recorder must stop now, if the disk is nearly full (looked at every
    /// `look_every`, and at the first call). A free space that cannot be read is no
    /// reason to stop.
    pub fn nearly_full(&mut self) -> Option<String> {
        if self
            .last_look
            .is_some_and(|t| t.elapsed() < self.look_every)
        {
            return None;
        }
        self.last_look = Some(Instant::now());
        let free = (self.free_bytes)(&self.folder)?;
        (free < self.nearly_full_bytes).then(|| {
            format!(
                "the disk of {} is nearly full ({} MB free, below {} MB): recording stopped, the record so far is kept and closed, the robot runs on; free space, or set [record] keep_gb",
                self.folder.display(),
                free / 1_000_000,
                self.nearly_full_bytes / 1_000_000
            )
        })
    }
}

/// Free bytes for an ordinary user on the disk that holds `folder`.
pub fn disk_free_bytes(folder: &Path) -> Option<u64> {
    let c_path = std::ffi::CString::new(folder.as_os_str().as_encoded_bytes()).ok()?;
    // SAFETY: an all-zero statvfs is a valid value for statvfs to write into.
    let mut st: libc::statvfs = unsafe { std::mem::zeroed() };
    // SAFETY: statvfs reads the NUL-terminated path and writes into the struct we own.
    let rc = unsafe { libc::statvfs(c_path.as_ptr(), &mut st) };
    (rc == 0).then(|| st.f_bavail * st.f_frsize)
}

#[cfg(test)]
#[path = "space_tests.rs"]
mod tests;
