//! Rewrites values in robot.ini and nothing else: every comment, blank line, the order
//! of sections and keys, spacing and line endings (and a Windows byte-order mark) stay
//! byte-for-byte. The write is atomic (a temporary file in the same directory, then
//! rename, then the directory flushed to disk), so a crash, a power cut or a full disk
//! leaves either the old file or the new one, never half of one. A robot.ini that is a
//! symbolic link stays one: the file it points to is replaced.

use std::fs;
use std::io::Write;
use std::path::Path;

/// One value to set: `[section] key = value`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct NewValue {
    pub section: String,
    pub key: String,
    pub value: String,
}

/// `text` with each of `values` replaced where its key stands in its section. Only the
/// value's characters change; a key that is not in the file is an error (the settings
/// file must hold every setting, so a missing one means the wrong file).
pub(crate) fn set_values(text: &str, values: &[NewValue]) -> Result<String, String> {
    let mut found = vec![false; values.len()];
    let mut section = String::new();
    let mut out = String::with_capacity(text.len() + 64);
    // split_inclusive keeps each line's own ending ("\n", "\r\n" or none at the end).
    for line in text.split_inclusive('\n') {
        let body = line.trim_end_matches(['\n', '\r']);
        let ending = &line[body.len()..];
        // A byte-order mark before the first heading is not part of the heading.
        let trimmed = body.trim_start_matches('\u{feff}').trim();
        if let Some(name) = trimmed.strip_prefix('[').and_then(|t| t.strip_suffix(']')) {
            section = name.trim().to_string();
            out.push_str(line);
            continue;
        }
        let is_comment = trimmed.starts_with(';') || trimmed.starts_with('#');
        let replaced = match body.split_once('=') {
            Some((key, old)) if !is_comment => {
                let wanted = values
                    .iter()
                    .position(|v| v.section == section && v.key == key.trim());
                wanted.map(|i| {
                    found[i] = true;
                    // Keep the spaces after '=' and any after the old value.
                    let lead = old.len() - old.trim_start().len();
                    let trail = old.len() - old.trim_end().len();
                    let trail = if old.trim().is_empty() { 0 } else { trail };
                    format!(
                        "{key}={}{}{}{ending}",
                        &old[..lead],
                        values[i].value,
                        &old[old.len() - trail..]
                    )
                })
            }
            _ => None,
        };
        out.push_str(replaced.as_deref().unwrap_or(line));
    }
    let missing: Vec<String> = values
        .iter()
        .zip(&found)
        .filter(|(_, found)| !**found)
        .map(|(v, _)| format!("[{}] {}", v.section, v.key))
        .collect();
    if missing.is_empty() {
        Ok(out)
    } else {
        Err(format!("not in the file: {}", missing.join(", ")))
    }
}

/// Replace the file at `path` with `text`, atomically. A file that has vanished or is
/// read-only is not replaced (a rename would otherwise succeed over a read-only file).
/// If `path` is a symbolic link, the file it points to is replaced and the link kept.
pub(crate) fn write_atomic(path: &Path, text: &str) -> Result<(), String> {
    let shown = path.display();
    let meta = fs::metadata(path).map_err(|e| format!("cannot find {shown} any more: {e}"))?;
    if meta.permissions().readonly() {
        return Err(format!("{shown} is read-only: nothing was written"));
    }
    // Renaming onto the link itself would replace the link with a plain file.
    let target =
        fs::canonicalize(path).map_err(|e| format!("cannot find {shown} any more: {e}"))?;
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "robot.ini".to_string());
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let written = (|| -> std::io::Result<()> {
        let mut file = fs::File::create(&tmp)?;
        file.write_all(text.as_bytes())?;
        file.set_permissions(meta.permissions())?;
        file.sync_all()?;
        fs::rename(&tmp, &target)
    })();
    if let Err(e) = written {
        let _ = fs::remove_file(&tmp);
        return Err(format!("cannot write {shown}: {e}"));
    }
    // The rename lives in the directory: until the directory is on disk, a power cut
    // can bring back the old file (or, on some file systems, none).
    fs::File::open(dir)
        .and_then(|d| d.sync_all())
        .map_err(|e| {
            format!(
                "wrote {shown} but could not flush its folder to disk ({e}): a power cut now may lose the save"
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(section: &str, key: &str, value: &str) -> NewValue {
        NewValue {
            section: section.into(),
            key: key.into(),
            value: value.into(),
        }
    }

    const TEXT: &str = "; head\r\n\n[pid.left]\n; gain\nkp = 16.7\nki=167   \n\n[pid.right]\nkp = 16.7\n; kp = 3\nkff =\nlast = 1";

    #[test]
    fn only_the_values_named_change() {
        let out = set_values(
            TEXT,
            &[v("pid.right", "kp", "20"), v("pid.left", "ki", "150")],
        )
        .unwrap();
        assert_eq!(
            out,
            "; head\r\n\n[pid.left]\n; gain\nkp = 16.7\nki=150   \n\n[pid.right]\nkp = 20\n; kp = 3\nkff =\nlast = 1"
        );
    }

    #[test]
    fn empty_values_and_the_last_line_without_ending() {
        let out = set_values(
            TEXT,
            &[v("pid.right", "kff", "8"), v("pid.right", "last", "2")],
        )
        .unwrap();
        assert!(out.ends_with("kff =8\nlast = 2"), "{out}");
    }

    #[test]
    fn a_missing_key_is_an_error_naming_it() {
        let e = set_values(TEXT, &[v("pid.steer", "kp", "1")]).unwrap_err();
        assert!(e.contains("[pid.steer] kp"), "{e}");
    }

    #[test]
    fn no_values_is_the_same_text() {
        assert_eq!(set_values(TEXT, &[]).unwrap(), TEXT);
    }

    #[test]
    fn a_windows_file_with_a_byte_order_mark_keeps_it() {
        let text = "\u{feff}[pid.left]\r\nkp = 16.7\r\n";
        let out = set_values(text, &[v("pid.left", "kp", "20")]).unwrap();
        assert_eq!(out, "\u{feff}[pid.left]\r\nkp = 20\r\n");
    }

    #[test]
    fn a_symbolic_link_stays_a_link_to_the_new_text() {
        let dir = tempfile::tempdir().unwrap();
        let real_dir = dir.path().join("settings");
        fs::create_dir(&real_dir).unwrap();
        let target = real_dir.join("robot-2026.ini");
        fs::write(&target, "a = 1\n").unwrap();
        let link = dir.path().join("robot.ini");
        std::os::unix::fs::symlink("settings/robot-2026.ini", &link).unwrap();

        // The folder is flushed after the rename; that it does not fail is all a test
        // can see of it.
        write_atomic(&link, "a = 2\n").unwrap();
        assert!(
            fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(
            fs::read_link(&link).unwrap(),
            Path::new("settings/robot-2026.ini")
        );
        assert_eq!(fs::read_to_string(&target).unwrap(), "a = 2\n");
        assert_eq!(
            fs::read_dir(&real_dir).unwrap().count(),
            1,
            "no temporary file left"
        );
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 2);
    }

    #[test]
    fn writes_atomically_and_refuses_read_only_and_vanished_files() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("robot.ini");
        fs::write(&path, "a = 1\n").unwrap();
        write_atomic(&path, "a = 2\n").unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "a = 2\n");
        assert_eq!(
            fs::read_dir(dir.path()).unwrap().count(),
            1,
            "no temporary file left"
        );

        let mut perms = fs::metadata(&path).unwrap().permissions();
        perms.set_readonly(true);
        fs::set_permissions(&path, perms).unwrap();
        let e = write_atomic(&path, "a = 3\n").unwrap_err();
        assert!(e.contains("read-only"), "{e}");
        assert_eq!(fs::read_to_string(&path).unwrap(), "a = 2\n");

        let gone = dir.path().join("gone.ini");
        let e = write_atomic(&gone, "a = 3\n").unwrap_err();
        assert!(e.contains("cannot find"), "{e}");
        assert!(!gone.exists());
    }
}
