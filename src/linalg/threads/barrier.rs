//! The team of threads running one closure, and its barrier.
//!
//! A barrier holds each thread until every thread of the team has reached
//! it: what one thread wrote before the barrier, every thread reads after
//! it. The last thread to arrive starts the next *generation*; the others
//! wait for the generation to change ([`Signal`]).
//!
//! When one thread of the team panics, its barrier is *poisoned*: the
//! threads waiting at it, and any that reach it later, panic too instead of
//! waiting forever, and [`Threads::run`](super::Threads::run) reports the
//! panic to its caller.

use super::signal::Signal;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// A barrier for a fixed number of threads.
#[derive(Debug)]
pub(super) struct Barrier {
    size: usize,
    arrived: AtomicUsize,
    generation: AtomicUsize,
    poisoned: AtomicBool,
    signal: Signal,
}

impl Barrier {
    pub(super) fn new(size: usize) -> Self {
        Barrier {
            size,
            arrived: AtomicUsize::new(0),
            generation: AtomicUsize::new(0),
            poisoned: AtomicBool::new(false),
            signal: Signal::default(),
        }
    }

    /// Waits until all `size` threads have called it.
    ///
    /// # Panics
    /// When the barrier is poisoned.
    fn wait(&self) {
        let generation = self.generation.load(Ordering::SeqCst);
        if self.arrived.fetch_add(1, Ordering::SeqCst) + 1 == self.size {
            self.arrived.store(0, Ordering::SeqCst);
            self.generation.fetch_add(1, Ordering::SeqCst);
            self.signal.notify();
        } else {
            self.signal.wait(|| {
                self.generation.load(Ordering::SeqCst) != generation
                    || self.poisoned.load(Ordering::SeqCst)
            });
        }
        assert!(
            !self.poisoned.load(Ordering::SeqCst),
            "another thread of the team panicked"
        );
    }

    /// Releases every waiter, now and later, with a panic.
    pub(super) fn poison(&self) {
        self.poisoned.store(true, Ordering::SeqCst);
        self.signal.notify();
    }

    /// Ready for the next run (after every thread has left it).
    pub(super) fn reset(&self) {
        self.arrived.store(0, Ordering::SeqCst);
        self.poisoned.store(false, Ordering::SeqCst);
    }
}

/// One thread's view of the team running a closure: which one it is, how
/// many there are, and their barrier.
#[derive(Debug, Clone, Copy)]
pub struct Team<'a> {
    index: usize,
    size: usize,
    barrier: Option<&'a Barrier>,
}

impl<'a> Team<'a> {
    /// Thread `index` of a team of `size` with `barrier`.
    pub(super) fn new(index: usize, size: usize, barrier: &'a Barrier) -> Self {
        Team {
            index,
            size,
            barrier: Some(barrier),
        }
    }

    /// A team of one: the caller's thread alone (its barrier does nothing).
    pub fn alone() -> Team<'static> {
        Team {
            index: 0,
            size: 1,
            barrier: None,
        }
    }

    /// This thread's number, `0 .. size()`; thread 0 is the caller's.
    pub fn index(&self) -> usize {
        self.index
    }

    /// The number of threads in the team.
    pub fn size(&self) -> usize {
        self.size
    }

    /// Is this the caller's thread (number 0), which does the team's
    /// bookkeeping?
    pub fn leads(&self) -> bool {
        self.index == 0
    }

    /// Waits until every thread of the team has reached this barrier.
    ///
    /// # Panics
    /// When another thread of the team panicked.
    pub fn barrier(&self) {
        if let Some(barrier) = self.barrier {
            barrier.wait();
        }
    }
}
