//! Safe writes: every output goes to a temporary file beside its target and
//! is renamed over it only once complete.
//!
//! An error (a full disk, a missing directory, a target that is a
//! directory), or the operation's cancel flag (see [`crate::cancel`]),
//! removes the temporary file and leaves any existing file at the target
//! untouched. Writing over an input file (compared by canonical path, and on
//! Unix by device and inode) is refused unless asked for.
//!
//! [`Outputs`] stages the files of one run and renames them together; see
//! [`crate::image::io`] ("Safe writes") for what that promises. The same
//! run made with [`Outputs::in_memory`] encodes every file into memory
//! instead ([`Outputs::into_memory`]), with the same encoders, so a library
//! gets the bytes a command would have written without touching a disk.

use std::fs;
use std::io::{BufWriter, Cursor, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use crate::cancel::{self, Cancellable};
use crate::error::{Error, Result};
use crate::image::io::SyncPolicy;

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

/// What an output's bytes are written to: a 1 MiB buffer over its
/// temporary file (or, in an in-memory run, its buffer), which fails once
/// the cancel flag is set.
pub(crate) type TempWriter<'a> = BufWriter<Cancellable<'a, Sink<'a>>>;

/// Where a staged output goes: its temporary file, or memory.
#[derive(Debug)]
pub(crate) enum Sink<'a> {
    /// A temporary file beside the target.
    File(&'a mut fs::File),
    /// A buffer of an in-memory run.
    Memory(&'a mut Cursor<Vec<u8>>),
}

impl Write for Sink<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match self {
            Sink::File(f) => f.write(buf),
            Sink::Memory(m) => m.write(buf),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        match self {
            Sink::File(f) => f.flush(),
            Sink::Memory(m) => m.flush(),
        }
    }
}

impl Seek for Sink<'_> {
    fn seek(&mut self, pos: SeekFrom) -> std::io::Result<u64> {
        match self {
            Sink::File(f) => f.seek(pos),
            Sink::Memory(m) => m.seek(pos),
        }
    }
}

/// A file at a hidden name beside its target, removed when dropped
/// unless it was renamed over the target ([`TempFile::persist`]) or kept
/// ([`TempFile::keep`]).
#[derive(Debug)]
pub(crate) struct TempFile {
    /// Its name; empty once persisted or kept.
    path: PathBuf,
    /// The open file, if it was made by opening one.
    file: Option<fs::File>,
}

impl TempFile {
    fn file_mut(&mut self) -> std::io::Result<&mut fs::File> {
        self.file
            .as_mut()
            .ok_or_else(|| std::io::Error::other("no open file"))
    }

    /// Renames the file over `target` (closing it first); on failure the
    /// error, and the temporary file is removed.
    fn persist(mut self, target: &Path) -> std::io::Result<()> {
        self.file = None;
        fs::rename(&self.path, target)?;
        self.path = PathBuf::new();
        Ok(())
    }

    /// Its name, no longer removed when dropped.
    fn keep(mut self) -> PathBuf {
        std::mem::take(&mut self.path)
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        self.file = None;
        if !self.path.as_os_str().is_empty() {
            let _ = fs::remove_file(&self.path);
        }
    }
}

/// A name no other process or thread is choosing at the same moment: a
/// hash of the process, the thread and the clock under std's randomly
/// keyed hasher (whose keys differ from call to call), as 12 hex digits.
/// A name taken anyway is found when the file is created, and another
/// is tried.
fn random_tag() -> String {
    use std::hash::{BuildHasher, Hash, Hasher};
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_u32(std::process::id());
    std::thread::current().id().hash(&mut h);
    if let Ok(t) = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH) {
        h.write_u128(t.as_nanos());
    }
    format!("{:012x}", h.finish() & 0xffff_ffff_ffff)
}

/// The hidden temporary name beside `path`: `.<name>.<random><suffix>`,
/// through `make` (which creates the file at the name it is given, failing
/// with `AlreadyExists` if something is there: another name is tried).
fn beside(
    path: &Path,
    suffix: &str,
    mut make: impl FnMut(&Path) -> std::io::Result<Option<fs::File>>,
) -> Result<TempFile> {
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
    if !dir.is_dir() {
        let msg = format!("directory {} does not exist", dir.display());
        let e = std::io::Error::new(std::io::ErrorKind::NotFound, msg);
        return Err(Error::write(path, e));
    }
    let mut last = None;
    for _ in 0..64 {
        let mut temp = std::ffi::OsString::from(".");
        temp.push(name);
        temp.push(".");
        temp.push(random_tag());
        temp.push(suffix);
        let temp = dir.join(temp);
        match make(&temp) {
            Ok(file) => return Ok(TempFile { path: temp, file }),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = Some(e),
            Err(e) => return Err(Error::write(path, e)),
        }
    }
    Err(Error::write(
        path,
        last.unwrap_or_else(|| std::io::Error::other("no free temporary name")),
    ))
}

/// A new temporary file beside `path`, filled by `write` (through a 1 MiB
/// buffer) and synced to disk as `sync` says (a target that exists now is
/// one being replaced); on error, or once `cancel` is set, it is
/// removed and the error returned ([`Error::Cancelled`] for the latter).
pub(crate) fn write_temp(
    path: &Path,
    cancel: Option<&AtomicBool>,
    sync: SyncPolicy,
    write: impl FnOnce(&mut TempWriter<'_>) -> Result<()>,
) -> Result<TempFile> {
    cancel::check(cancel)?;
    let mut temp = beside(path, ".tmp", |p| {
        let mut options = fs::OpenOptions::new();
        options.read(true).write(true).create_new(true);
        #[cfg(unix)]
        {
            // As an ordinary new file: 0666 less the umask.
            use std::os::unix::fs::OpenOptionsExt;
            options.mode(0o666);
        }
        options.open(p).map(Some)
    })?;
    let written = (|| {
        let file = temp.file_mut().map_err(|e| Error::write(path, e))?;
        let mut out = BufWriter::with_capacity(1 << 20, Cancellable::new(Sink::File(file), cancel));
        write(&mut out)?;
        out.flush().map_err(|e| Error::write(path, e))
    })();
    cancel::or_cancelled(written, cancel)?;
    let file = temp.file_mut().map_err(|e| Error::write(path, e))?;
    let replacing = fs::symlink_metadata(path).is_ok();
    if sync == SyncPolicy::Always || (sync == SyncPolicy::Replacing && replacing) {
        file.sync_all().map_err(|e| Error::write(path, e))?;
    }
    // Replacing a file keeps its permissions.
    if let Ok(meta) = fs::metadata(path) {
        if meta.is_file() {
            let _ = file.set_permissions(meta.permissions());
        }
    }
    Ok(temp)
}

/// The bytes `write` gives for `path` in an in-memory run, through the
/// same buffer and cancel checks as [`write_temp`].
fn write_memory(
    path: &Path,
    cancel: Option<&AtomicBool>,
    write: impl FnOnce(&mut TempWriter<'_>) -> Result<()>,
) -> Result<Vec<u8>> {
    cancel::check(cancel)?;
    let mut buf = Cursor::new(Vec::new());
    let written = (|| {
        let mut out =
            BufWriter::with_capacity(1 << 20, Cancellable::new(Sink::Memory(&mut buf), cancel));
        write(&mut out)?;
        out.flush().map_err(|e| Error::write(path, e))
    })();
    cancel::or_cancelled(written, cancel)?;
    Ok(buf.into_inner())
}

/// Renames a finished temporary file over `path`; on failure the temporary
/// file is removed.
pub(crate) fn persist(temp: TempFile, path: &Path) -> Result<()> {
    temp.persist(path).map_err(|e| Error::write(path, e))
}

/// The files of one run, written to temporary files as they are staged and
/// renamed into place together by [`Outputs::commit`]: all of them, or
/// (after an error, or when dropped without committing) none. See the
/// [`crate::image`] ("Safe writes") for what a rename failing midway
/// does.
///
/// ```
/// use envmap_render::image::{Outputs, SaveOptions};
/// let dir = tempfile::tempdir().unwrap();
/// let mut run = Outputs::new(&SaveOptions::default());
/// run.stage_bytes(dir.path().join("a.txt"), b"one").unwrap();
/// run.stage_bytes(dir.path().join("b.txt"), b"two").unwrap();
/// assert!(!dir.path().join("a.txt").exists()); // nothing in place yet
/// let written = run.commit().unwrap();
/// assert_eq!(written.len(), 2);
/// assert_eq!(std::fs::read(dir.path().join("b.txt")).unwrap(), b"two");
/// ```
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[derive(Debug)]
pub(crate) struct Outputs<'a> {
    staged: Vec<(Staged, PathBuf)>,
    inputs: Vec<PathBuf>,
    overwrite_input: bool,
    cancel: Option<&'a AtomicBool>,
    /// An in-memory run ([`Outputs::in_memory`]).
    memory: bool,
    /// When the temporary files are synced.
    sync: SyncPolicy,
}

/// A staged output: its complete temporary file, or its bytes.
#[derive(Debug)]
enum Staged {
    File(TempFile),
    Bytes(Vec<u8>),
}

/// A file of an in-memory run: its path as staged and its bytes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MemoryFile {
    /// The path the file was staged for (as given: nothing was checked or
    /// created there).
    pub path: PathBuf,
    /// Its bytes, as `Outputs::commit` would have written them.
    pub bytes: Vec<u8>,
}

#[cfg_attr(not(feature = "instruments"), allow(unreachable_pub, dead_code))]
impl<'a> Outputs<'a> {
    /// An empty run: targets may not be one of `inputs` unless
    /// `overwrite_input`; staging stops with [`Error::Cancelled`] once
    /// `cancel` is set.
    #[must_use]
    pub fn with(inputs: &[PathBuf], overwrite_input: bool, cancel: Option<&'a AtomicBool>) -> Self {
        Self {
            staged: Vec::new(),
            inputs: inputs.to_vec(),
            overwrite_input,
            cancel,
            memory: false,
            sync: SyncPolicy::Replacing,
        }
    }

    /// The run with outputs synced to the disk as `sync` says (the default
    /// [`SyncPolicy::Replacing`]).
    #[must_use]
    pub(crate) fn with_sync(mut self, sync: SyncPolicy) -> Self {
        self.sync = sync;
        self
    }

    /// A run that encodes every staged file into memory: the paths are
    /// names only (no directory need exist, nothing on disk is read or
    /// written); [`Outputs::into_memory`] returns the files. Staging stops
    /// with [`Error::Cancelled`] once `cancel` is set.
    ///
    /// ```
    /// use envmap_render::image::Outputs;
    /// let mut run = Outputs::in_memory(None);
    /// run.stage_bytes("out/a.txt", b"one").unwrap();
    /// let files = run.into_memory().unwrap();
    /// assert_eq!(files[0].bytes, b"one");
    /// assert!(!std::path::Path::new("out/a.txt").exists());
    /// ```
    #[must_use]
    pub fn in_memory(cancel: Option<&'a AtomicBool>) -> Self {
        Self {
            memory: true,
            ..Self::with(&[], false, cancel)
        }
    }

    /// The targets staged so far, in order.
    #[cfg_attr(not(feature = "instruments"), allow(dead_code))]
    pub fn targets(&self) -> impl Iterator<Item = &Path> {
        self.staged.iter().map(|(_, t)| t.as_path())
    }

    /// Writes the bytes `write` gives into a temporary file for `target`.
    /// Errors (nothing is staged) if the target is a directory, an input,
    /// already staged in this run, or the write fails or is cancelled.
    pub(crate) fn stage_with(
        &mut self,
        target: &Path,
        write: impl FnOnce(&mut TempWriter<'_>) -> Result<()>,
    ) -> Result<()> {
        if !self.memory {
            check_target(target, &self.inputs, self.overwrite_input)?;
        }
        if self.staged.iter().any(|(_, t)| t == target) {
            return Err(Error::write(
                target,
                std::io::Error::new(
                    std::io::ErrorKind::AlreadyExists,
                    "named twice among the outputs of one run",
                ),
            ));
        }
        let staged = if self.memory {
            Staged::Bytes(write_memory(target, self.cancel, write)?)
        } else {
            Staged::File(write_temp(target, self.cancel, self.sync, write)?)
        };
        self.staged.push((staged, target.to_path_buf()));
        Ok(())
    }

    /// An in-memory run's files, in the order they were staged. With the
    /// cancel flag set, [`Error::Cancelled`].
    ///
    /// # Errors
    ///
    /// A run that writes files ([`Outputs::new`], [`Outputs::with`]):
    /// commit it instead; the cancel flag.
    pub fn into_memory(self) -> Result<Vec<MemoryFile>> {
        cancel::check(self.cancel)?;
        self.staged
            .into_iter()
            .map(|(s, path)| match s {
                Staged::Bytes(bytes) => Ok(MemoryFile { path, bytes }),
                Staged::File(_) => Err(Error::usage(format!(
                    "{}: staged as a file; an in-memory run is made with Outputs::in_memory",
                    path.display()
                ))),
            })
            .collect()
    }

    /// Bytes as they are (a report, a manifest) for `target`.
    pub fn stage_bytes(&mut self, target: impl AsRef<Path>, bytes: &[u8]) -> Result<()> {
        let target = target.as_ref();
        self.stage_with(target, |out| {
            out.write_all(bytes).map_err(|e| Error::write(target, e))
        })
    }

    /// Renames every staged file over its target; returns the targets. With
    /// the cancel flag set before the renames begin, renames nothing and
    /// returns [`Error::Cancelled`]; once they have begun, they are finished.
    pub fn commit(self) -> Result<Vec<PathBuf>> {
        cancel::check(self.cancel)?;
        let targets: Vec<PathBuf> = self.staged.iter().map(|(_, t)| t.clone()).collect();
        if self.memory {
            return Err(Error::usage(
                "an in-memory run is not committed to files: take them with Outputs::into_memory",
            ));
        }
        let staged: Vec<(TempFile, PathBuf)> = self
            .staged
            .into_iter()
            .filter_map(|(s, t)| match s {
                Staged::File(f) => Some((f, t)),
                Staged::Bytes(_) => None,
            })
            .collect();
        if staged.len() == 1 {
            // One rename is atomic by itself.
            for (temp, target) in staged {
                persist(temp, &target)?;
            }
            return Ok(targets);
        }
        // A second name for every existing target, made before any rename,
        // from which it can be put back.
        let mut backups: Vec<Option<TempFile>> = Vec::with_capacity(staged.len());
        for (_, target) in &staged {
            backups.push(if target.is_file() {
                Some(backup(target)?)
            } else {
                None
            });
        }
        let n = staged.len();
        for (k, (temp, target)) in staged.into_iter().enumerate() {
            if let Err(e) = temp.persist(&target) {
                let failed = e;
                return Err(roll_back(&targets[..k], &mut backups, &target, failed, n));
            }
        }
        // Done: dropping the backups removes the old files' second names.
        Ok(targets)
    }
}

/// A second name beside `target` for the same file (a hard link, or a copy).
fn backup(target: &Path) -> Result<TempFile> {
    let made = beside(target, ".old", |p| {
        fs::hard_link(target, p)
            .or_else(|_| fs::copy(target, p).map(drop))
            .map(|()| None)
    })
    .map_err(|e| {
        Error::write(
            target,
            std::io::Error::other(format!(
                "cannot keep the old file to restore it if a later output failed: {e}"
            )),
        )
    })?;
    Ok(made)
}

/// Puts back the targets already replaced (`done`, in order) after the
/// rename over `failed_target` failed; returns the error to report.
fn roll_back(
    done: &[PathBuf],
    backups: &mut [Option<TempFile>],
    failed_target: &Path,
    failed: std::io::Error,
    n: usize,
) -> Error {
    let mut not_restored = Vec::new();
    for (target, b) in done.iter().zip(backups.iter_mut()) {
        match b.take() {
            Some(old) => match fs::rename(&old.path, target) {
                // Its name now belongs to the target again: nothing to remove.
                Ok(()) => drop(old.keep()),
                Err(e) => {
                    let kept = old.keep();
                    not_restored.push(format!(
                        "{} could not be restored ({e}; its old contents are in {})",
                        target.display(),
                        kept.display()
                    ));
                }
            },
            // There was no file before: remove the new one.
            None => {
                if let Err(e) = fs::remove_file(target) {
                    not_restored.push(format!("{} could not be removed ({e})", target.display()));
                }
            }
        }
    }
    let what = if not_restored.is_empty() {
        format!("{failed}; none of the {n} outputs of this run were written, the old files are as they were")
    } else {
        format!(
            "{failed}; the outputs of this run were undone except: {}",
            not_restored.join("; ")
        )
    };
    Error::write(failed_target, std::io::Error::new(failed.kind(), what))
}
