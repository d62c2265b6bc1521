//! Ctrl-C and SIGTERM: stop at the next safe point, clean up, say so.
//!
//! The first SIGINT or SIGTERM (Ctrl-C on Windows) sets the flag every
//! long operation of the command was given (see [`envmap_render::cancel`]): the
//! work stops at its next safe point (a band of rows, a read or write of at
//! most a megabyte), every temporary file is removed, nothing is renamed
//! into place, and the command prints one line and exits 130 (SIGINT) or
//! 143 (SIGTERM). A second signal while that happens exits at once with the
//! same status: targets are still never half written (they are only ever
//! replaced by a rename), but a temporary file being written may stay.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

use signal_hook::consts::{SIGINT, SIGTERM};
use signal_hook::flag;

/// The flag the handlers set, and which signal came first.
pub(crate) struct Signals {
    stop: Arc<AtomicBool>,
    which: Arc<AtomicUsize>,
}

impl Signals {
    /// Installs the handlers for SIGINT and SIGTERM. If that fails (it
    /// should not), the signals keep their default action, which ends the
    /// process at once.
    pub(crate) fn install() -> Signals {
        let stop = Arc::new(AtomicBool::new(false));
        let which = Arc::new(AtomicUsize::new(0));
        for sig in [SIGINT, SIGTERM] {
            // The order matters: the shutdown runs first and does nothing
            // until the flag is set, which the first signal does after it.
            let _ = flag::register_conditional_shutdown(sig, exit_status(sig), Arc::clone(&stop))
                .and_then(|_| flag::register_usize(sig, Arc::clone(&which), sig as usize))
                .and_then(|_| flag::register(sig, Arc::clone(&stop)));
        }
        Signals { stop, which }
    }

    /// The flag to pass as the `cancel` option of long operations.
    pub(crate) fn flag(&self) -> &AtomicBool {
        &self.stop
    }

    /// The exit status for the signal that came, if one did: 130 for
    /// SIGINT, 143 for SIGTERM (128 + the signal's number).
    pub(crate) fn exit_status(&self) -> Option<u8> {
        if !self.stop.load(Ordering::SeqCst) {
            return None;
        }
        let sig = self.which.load(Ordering::SeqCst) as i32;
        Some(exit_status(sig) as u8)
    }
}

/// 128 + the signal's number, as a shell reports a process it ended (SIGINT
/// is 2 and SIGTERM 15 on every platform).
const fn exit_status(sig: i32) -> i32 {
    if sig == SIGTERM {
        143
    } else {
        130
    }
}
