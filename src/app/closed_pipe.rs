//! What a command does when the reader of its output goes away, as in
//! `masssprings trace --compare ours yours | head`: it ends quietly, the
//! way `cat` and `grep` do, ended by the signal `SIGPIPE` at its next
//! write, instead of panicking on a `println!` that fails.
//!
//! Rust's runtime ignores `SIGPIPE` before `main`, so that a server sees a
//! closed connection as an error it can handle (`EPIPE`) rather than being
//! ended by it. The viewer is such a server (a browser may close a
//! connection at any time) and keeps that; every other command writes
//! only to its terminal, pipes and files, and gets the default back. A
//! command ended this way mid-run is like one killed: its files are the
//! earlier complete ones or its own finished ones (docs/reliability.md).
//!
//! Source: POSIX `signal(3p)`; the behaviour of the standard Unix filters.

/// Restores the default action of `SIGPIPE` (end the process) for this
/// process; a no-op where there are no Unix signals.
pub fn end_quietly_when_the_reader_goes() {
    #[cfg(unix)]
    {
        use std::ffi::c_int;
        /// `SIGPIPE` of `<signal.h>` (13 on Linux and the BSDs) and
        /// `SIG_DFL`, the default action (the null handler).
        const SIGPIPE: c_int = 13;
        const SIG_DFL: usize = 0;
        extern "C" {
            fn signal(signal: c_int, handler: usize) -> usize;
        }
        // SAFETY: SIG_DFL is a valid action for SIGPIPE, and the call
        // changes only how the process answers that signal.
        unsafe { signal(SIGPIPE, SIG_DFL) };
    }
}
