//! Safe writes: every output goes to a temporary file beside its target and
//! is renamed over it only once complete.
//!
//! An error (a full disk, a missing directory, a target that is a
//! directory) removes the temporary file and leaves any existing file at the
//! target untouched. Writing over an input file (compared by canonical path,
//! and on Unix by device and inode) is refused unless asked for.

use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use tempfile::NamedTempFile;

use crate::error::{Error, Result};

/// Checks a target before any encoding: not a directory (so that a six-file
/// write does not fail halfway through its renames), not one of `inputs`
/// unless `overwrite_input`.
pub(crate) fn check_target(target: &Path, inputs: &[PathBuf], overwrite_input: bool) -> Result<()> {
    if target.is_dir() {
        return Err(Error::write(
            target,
            std::io::Error::new(std::io::ErrorKind::IsADirectory, "is a directory"),
        ));
    }
    check_not_input(target, inputs, overwrite_input)
}

/// Refuses `target` if it is one of `inputs` (same canonical path, or on
/// Unix the same device and inode) unless overwriting was asked for.
fn check_not_input(target: &Path, inputs: &[PathBuf], overwrite_input: bool) -> Result<()> {
    if overwrite_input || inputs.is_empty() {
        return Ok(());
    }
    // A target that does not exist cannot be an existing input.
    let Ok(t) = fs::canonicalize(target) else {
        return Ok(());
    };
    let t_meta = fs::metadata(&t).ok();
    for input in inputs {
        let same_path = fs::canonicalize(input).is_ok_and(|i| i == t);
        let same_file = match (&t_meta, fs::metadata(input).ok()) {
            (Some(a), Some(b)) => same_inode(a, &b),
            _ => false,
        };
        if same_path || same_file {
            return Err(Error::WouldOverwriteInput {
                path: target.to_path_buf(),
            });
        }
    }
    Ok(())
}

#[cfg(unix)]
fn same_inode(a: &fs::Metadata, b: &fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    a.dev() == b.dev() && a.ino() == b.ino()
}

#[cfg(not(unix))]
fn same_inode(_: &fs::Metadata, _: &fs::Metadata) -> bool {
    false
}

/// A new temporary file beside `path`, filled by `write` (through a 1 MiB
/// buffer) and synced to disk; on error it is removed.
pub(crate) fn write_temp(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<&mut fs::File>) -> Result<()>,
) -> Result<NamedTempFile> {
    let name = path.file_name().ok_or_else(|| {
        Error::write(
            path,
            std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file name"),
        )
    })?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut prefix = std::ffi::OsString::from(".");
    prefix.push(name);
    prefix.push(".");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    {
        // As an ordinary new file: 0666 less the umask (not tempfile's 0600).
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(fs::Permissions::from_mode(0o666));
    }
    if !dir.is_dir() {
        let msg = format!("directory {} does not exist", dir.display());
        let e = std::io::Error::new(std::io::ErrorKind::NotFound, msg);
        return Err(Error::write(path, e));
    }
    let mut temp = builder
        .tempfile_in(dir)
        .map_err(|e| Error::write(path, plain_io_error(e)))?;
    {
        let mut out = BufWriter::with_capacity(1 << 20, temp.as_file_mut());
        write(&mut out)?;
        out.flush().map_err(|e| Error::write(path, e))?;
    }
    temp.as_file()
        .sync_all()
        .map_err(|e| Error::write(path, e))?;
    // Replacing a file keeps its permissions.
    if let Ok(meta) = fs::metadata(path) {
        if meta.is_file() {
            let _ = temp.as_file().set_permissions(meta.permissions());
        }
    }
    Ok(temp)
}

/// The operating system's error inside one of `tempfile`'s, which adds the
/// temporary file's name (of no interest to the user, who named the target).
fn plain_io_error(e: std::io::Error) -> std::io::Error {
    if e.get_ref().is_none() {
        return e; // a plain operating-system error
    }
    // tempfile's wrapper displays as "<error> at path \"<temporary file>\"".
    let msg = e.to_string();
    let inner = msg
        .rsplit_once(" at path ")
        .map_or(msg.as_str(), |(m, _)| m);
    let code = inner
        .strip_suffix(')')
        .and_then(|m| m.rsplit_once("(os error "))
        .and_then(|(_, n)| n.parse::<i32>().ok());
    match code {
        Some(code) => std::io::Error::from_raw_os_error(code),
        None => std::io::Error::new(e.kind(), inner.to_owned()),
    }
}

/// Renames a finished temporary file over `path`; on failure the temporary
/// file is removed.
pub(crate) fn persist(temp: NamedTempFile, path: &Path) -> Result<()> {
    temp.persist(path)
        .map(drop)
        .map_err(|e| Error::write(path, plain_io_error(e.error)))
}
