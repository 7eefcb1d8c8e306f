//! Threads for the parallel factorization, solves and passes over the
//! springs: a small pool made once and kept, a barrier, and shared arrays.
//!
//! ```text
//! let threads = Threads::new(4);            spawns 3 threads (the caller is the 4th)
//! threads.run(&|team: &Team| { … });        every thread runs the closure once,
//!                                           team.index() = 0, 1, 2, 3; returns when all are done
//!     team.barrier();                       inside: wait until the whole team is here
//! ```
//!
//! The pool is made once (with a simulation, or a factorization) so that
//! no step spawns a thread, and [`Threads::run`] allocates nothing: a step
//! stays free of allocations. Between two runs, and at a barrier, the
//! threads wait, first spinning for up to a millisecond (yielding their
//! core after the first microseconds), then asleep ([`signal`]).
//!
//! The results never depend on the number of threads: the callers split
//! their work so that every sum is formed in the same order as on one
//! thread (`docs/performance.md`, "Threads"). `Threads::new(1)` spawns
//! nothing and runs each closure on the caller's thread, which is the
//! single-threaded code path. Where threads cannot be made (WebAssembly
//! without threads) the pool has as many as it could make, at least the
//! caller's.
//!
//! Source: the fork–join model of OpenMP's parallel regions, with threads
//! kept between regions; the barrier is a centralized sense-reversing
//! barrier (Mellor-Crummey & Scott, ACM TOCS 9(1), 1991), here counting
//! generations.

mod barrier;
mod pool;
mod shared;
mod signal;

pub use barrier::Team;
pub use pool::Threads;
pub use shared::SharedSlice;

/// The threads this process may run at once (the cores it may use), at
/// least 1: the default of `--threads`.
pub fn available() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// `0..len` cut into `parts` consecutive ranges of sizes as equal as they
/// can be (the first ones one longer), and the range of part `index`.
pub fn even_part(len: usize, parts: usize, index: usize) -> std::ops::Range<usize> {
    let (size, extra) = (len / parts, len % parts);
    let start = index * size + index.min(extra);
    start..start + size + usize::from(index < extra)
}
