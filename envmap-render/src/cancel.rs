//! Stopping long work: a shared flag that a caller sets to cancel an
//! operation that is under way.
//!
//! Long operations (loading and saving files, conversion, rendering, the
//! demo) take an optional `&AtomicBool` in their options (`cancel`). They
//! check it at safe points: every band of rows of a conversion or render,
//! every read or write of a file (each at most a megabyte). Once it is set,
//! the operation stops at the next safe point and returns
//! [`Error::Cancelled`]; an output being written is removed and any existing
//! file at its place left as it was (see [`crate::image`]). The check is
//! one relaxed atomic load.
//!
//! ```
//! use std::sync::atomic::{AtomicBool, Ordering};
//! use envmap_render::{filter::{convert, ConvertOptions}, Error, image::Representation};
//! use envmap_render::scene::Builtin;
//! use envmap_core::AnyMapping;
//!
//! let src = Builtin::Sky.image(Representation::default_for(AnyMapping::LatLong), 64, 32).unwrap();
//! let stop = AtomicBool::new(true); // e.g. set by another thread, or a signal handler
//! let mut opts = ConvertOptions::default();
//! opts.cancel = Some(&stop);
//! let cube = Representation::default_for(AnyMapping::Cube);
//! let r = convert(&src, cube, 64, 48, &opts, None);
//! assert!(matches!(r, Err(Error::Cancelled)));
//! ```

use std::io::{self, Read, Seek, SeekFrom, Write};
use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::{Error, Result};

/// Whether `flag` is given and set.
#[inline]
#[must_use]
pub fn is_set(flag: Option<&AtomicBool>) -> bool {
    flag.is_some_and(|f| f.load(Ordering::Relaxed))
}

/// `Err(Error::Cancelled)` if `flag` is given and set.
#[inline]
pub fn check(flag: Option<&AtomicBool>) -> Result<()> {
    if is_set(flag) {
        Err(Error::Cancelled)
    } else {
        Ok(())
    }
}

/// A reader or writer that fails every read and write once the flag is set,
/// so that a decoder or encoder working through it stops soon after. The
/// error it gives is of kind [`io::ErrorKind::Other`] (not `Interrupted`,
/// which `read_exact` and `write_all` retry); callers turn the failure that
/// follows into [`Error::Cancelled`] by checking the flag again.
#[derive(Debug)]
pub(crate) struct Cancellable<'a, T> {
    inner: T,
    flag: Option<&'a AtomicBool>,
}

impl<'a, T> Cancellable<'a, T> {
    pub(crate) fn new(inner: T, flag: Option<&'a AtomicBool>) -> Self {
        Self { inner, flag }
    }

    /// The cancel flag it watches.
    pub(crate) fn flag(&self) -> Option<&'a AtomicBool> {
        self.flag
    }

    /// The reader or writer inside.
    #[cfg(any(feature = "ktx2", feature = "dds", feature = "babylon"))]
    pub(crate) fn into_inner(self) -> T {
        self.inner
    }

    fn check(&self) -> io::Result<()> {
        if is_set(self.flag) {
            Err(io::Error::other("cancelled"))
        } else {
            Ok(())
        }
    }
}

impl<T: Read> Read for Cancellable<'_, T> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.check()?;
        self.inner.read(buf)
    }
}

impl<T: Write> Write for Cancellable<'_, T> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.check()?;
        self.inner.write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.check()?;
        self.inner.flush()
    }
}

impl<T: Seek> Seek for Cancellable<'_, T> {
    fn seek(&mut self, pos: SeekFrom) -> io::Result<u64> {
        self.inner.seek(pos)
    }
}

/// `result`, or [`Error::Cancelled`] in its place when it failed because
/// `flag` was set (the operation's own error is then only a consequence).
pub(crate) fn or_cancelled<T>(result: Result<T>, flag: Option<&AtomicBool>) -> Result<T> {
    match result {
        Err(_) if is_set(flag) => Err(Error::Cancelled),
        other => other,
    }
}
