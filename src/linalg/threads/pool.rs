//! The pool: threads spawned once, each running every closure it is given
//! with the caller's thread.
//!
//! [`Threads::run`] publishes the closure (a pointer to it) and a new
//! *generation* number; the waiting threads see the number change, run the
//! closure as team members `1 .. size`, and count themselves out. The
//! caller runs it as member 0, then waits until all have counted out, so
//! that the closure, which borrows the caller's data, outlives every use.
//! A run allocates nothing. Dropping the pool ends its threads.
//!
//! The caller's choice of kernels ([`kernels`](crate::linalg::kernels),
//! a choice each thread holds) goes with the closure: every thread of a
//! run computes with the kernels the caller computes with, so a run with
//! portable kernels gives the portable bits on any number of threads.

use super::barrier::{Barrier, Team};
use super::signal::Signal;
use crate::linalg::kernels::{self, Kernels};
use std::cell::UnsafeCell;
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

/// The closure of a run, its lifetime erased: valid while its run lasts.
type Job = *const (dyn Fn(&Team) + Sync);

/// What the caller and the pool's threads share.
struct Shared {
    size: usize,
    /// The closure of the run in progress and the caller's kernels
    /// (written only between runs).
    job: UnsafeCell<Option<(Job, Kernels)>>,
    /// Incremented by each run; the threads wait for it to change.
    generation: AtomicUsize,
    /// Threads still running the current closure.
    running: AtomicUsize,
    /// Set when the pool is dropped.
    quit: AtomicBool,
    /// Set when a thread's closure panicked during the current run.
    panicked: AtomicBool,
    barrier: Barrier,
    /// The pool's threads wait here for a run.
    jobs: Signal,
    /// The caller waits here for the end of a run.
    done: Signal,
}

// SAFETY: `job` is written by the caller only while no run is in progress
// (no pool thread reads it), and read by the pool's threads only during a
// run, after the generation they wait on was changed (sequentially
// consistent), which orders the write before the reads. The closure it
// points to is `Sync`.
unsafe impl Sync for Shared {}
// SAFETY: as above; the raw pointer is only a borrowed closure.
unsafe impl Send for Shared {}

/// A pool of threads kept for the whole simulation (or factorization).
/// Cloning it makes a new pool of the same size.
pub struct Threads {
    shared: Arc<Shared>,
    handles: Vec<JoinHandle<()>>,
    /// One run at a time (a clone has a pool of its own, but a pool may be
    /// shared by reference).
    busy: Mutex<()>,
}

impl Threads {
    /// A pool of `count` threads, the caller's included: spawns
    /// `count − 1`, or as many as the system gives (none on a platform
    /// without threads). `0` counts as 1.
    pub fn new(count: usize) -> Self {
        let wanted = count.max(1);
        let mut handles = Vec::with_capacity(wanted - 1);
        let shared = Arc::new(Shared::new(wanted));
        for index in 1..wanted {
            let mine = Arc::clone(&shared);
            let spawned = std::thread::Builder::new()
                .name(format!("masssprings-{index}"))
                .spawn(move || serve(&mine, index));
            match spawned {
                Ok(handle) => handles.push(handle),
                Err(_) => break,
            }
        }
        let size = handles.len() + 1;
        let shared = if size == wanted {
            shared
        } else {
            Self::shrunk(shared, &mut handles, size)
        };
        Threads {
            shared,
            handles,
            busy: Mutex::new(()),
        }
    }

    /// When fewer threads could be spawned than asked for: ends those made
    /// and starts again with their number, which the system did give.
    fn shrunk(shared: Arc<Shared>, handles: &mut Vec<JoinHandle<()>>, size: usize) -> Arc<Shared> {
        end(&shared, handles);
        let shared = Arc::new(Shared::new(size));
        for index in 1..size {
            let mine = Arc::clone(&shared);
            match std::thread::Builder::new().spawn(move || serve(&mine, index)) {
                Ok(handle) => handles.push(handle),
                Err(_) => {
                    end(&shared, handles);
                    return Arc::new(Shared::new(1));
                }
            }
        }
        shared
    }

    /// The number of threads, the caller's included.
    pub fn count(&self) -> usize {
        self.shared.size
    }

    /// Runs `job` on every thread of the pool at once, the caller's thread
    /// being team member 0, and returns when every thread has finished it.
    /// Allocates nothing.
    ///
    /// # Panics
    /// When `job` panicked on any thread (after every thread has stopped).
    pub fn run(&self, job: &(dyn Fn(&Team) + Sync)) {
        let shared = &*self.shared;
        if shared.size == 1 {
            job(&Team::alone());
            return;
        }
        let _one_run = self.busy.lock().unwrap_or_else(|e| e.into_inner());
        // SAFETY: no run is in progress (the threads read `job` only
        // between a change of generation and their count-out, and the last
        // run waited for every count-out); the lifetime is erased because
        // this function does not return before every thread is done with it.
        unsafe {
            *shared.job.get() = Some((std::mem::transmute::<_, Job>(job), kernels::chosen()));
        }
        shared.running.store(shared.size - 1, Ordering::SeqCst);
        shared.generation.fetch_add(1, Ordering::SeqCst);
        shared.jobs.notify();
        let mine = catch_unwind(AssertUnwindSafe(|| {
            job(&Team::new(0, shared.size, &shared.barrier))
        }));
        if mine.is_err() {
            shared.barrier.poison();
        }
        shared
            .done
            .wait(|| shared.running.load(Ordering::SeqCst) == 0);
        // SAFETY: every thread has counted out: none reads `job` now.
        unsafe { *shared.job.get() = None };
        shared.barrier.reset();
        let theirs = shared.panicked.swap(false, Ordering::SeqCst);
        if let Err(payload) = mine {
            resume_unwind(payload);
        }
        assert!(!theirs, "a thread of the pool panicked");
    }
}

impl Shared {
    fn new(size: usize) -> Self {
        Shared {
            size,
            job: UnsafeCell::new(None),
            generation: AtomicUsize::new(0),
            running: AtomicUsize::new(0),
            quit: AtomicBool::new(false),
            panicked: AtomicBool::new(false),
            barrier: Barrier::new(size),
            jobs: Signal::default(),
            done: Signal::default(),
        }
    }
}

/// What pool thread `index` does until the pool is dropped: wait for a
/// run, run its closure, count out.
fn serve(shared: &Shared, index: usize) {
    let mut seen = 0;
    loop {
        shared.jobs.wait(|| {
            shared.generation.load(Ordering::SeqCst) != seen || shared.quit.load(Ordering::SeqCst)
        });
        if shared.quit.load(Ordering::SeqCst) {
            return;
        }
        seen = shared.generation.load(Ordering::SeqCst);
        // SAFETY: the generation changed, so a run is in progress and its
        // closure is published; it stays valid until this thread counts out.
        let (job, chosen) = unsafe { (*shared.job.get()).expect("a run publishes its closure") };
        let team = Team::new(index, shared.size, &shared.barrier);
        // SAFETY: see above.
        let run = || kernels::with(chosen, || unsafe { (*job)(&team) });
        if catch_unwind(AssertUnwindSafe(run)).is_err() {
            shared.panicked.store(true, Ordering::SeqCst);
            shared.barrier.poison();
        }
        if shared.running.fetch_sub(1, Ordering::SeqCst) == 1 {
            shared.done.notify();
        }
    }
}

/// Tells the threads of `shared` to end, and waits for them.
fn end(shared: &Shared, handles: &mut Vec<JoinHandle<()>>) {
    shared.quit.store(true, Ordering::SeqCst);
    shared.jobs.notify();
    for handle in handles.drain(..) {
        let _ = handle.join();
    }
}

impl Drop for Threads {
    fn drop(&mut self) {
        end(&self.shared, &mut self.handles);
    }
}

impl Clone for Threads {
    fn clone(&self) -> Self {
        Threads::new(self.count())
    }
}

impl std::fmt::Debug for Threads {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Threads")
            .field("count", &self.count())
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::threads::even_part;
    use std::sync::atomic::AtomicU64;

    #[test]
    fn every_thread_runs_the_closure_once_with_its_own_number() {
        for count in [1, 2, 3, 8] {
            let threads = Threads::new(count);
            assert_eq!(threads.count(), count);
            let seen: Vec<AtomicUsize> = (0..count).map(|_| AtomicUsize::new(0)).collect();
            for _ in 0..50 {
                threads.run(&|team: &Team| {
                    assert_eq!(team.size(), count);
                    assert_eq!(team.leads(), team.index() == 0);
                    seen[team.index()].fetch_add(1, Ordering::SeqCst);
                });
            }
            assert!(seen.iter().all(|s| s.load(Ordering::SeqCst) == 50));
        }
    }

    #[test]
    fn what_one_thread_writes_before_a_barrier_every_thread_reads_after_it() {
        let threads = Threads::new(4);
        let slots: Vec<AtomicU64> = (0..4).map(|_| AtomicU64::new(0)).collect();
        for round in 1..=200u64 {
            threads.run(&|team: &Team| {
                slots[team.index()].store(round * 10 + team.index() as u64, Ordering::Relaxed);
                team.barrier();
                for (i, slot) in slots.iter().enumerate() {
                    assert_eq!(slot.load(Ordering::Relaxed), round * 10 + i as u64);
                }
                team.barrier(); // nobody writes the next round before all have read
            });
        }
    }

    #[test]
    fn a_panic_on_any_thread_reaches_the_caller_and_the_pool_goes_on() {
        let threads = Threads::new(3);
        for culprit in 0..3 {
            let outcome = catch_unwind(AssertUnwindSafe(|| {
                threads.run(&|team: &Team| {
                    if team.index() == culprit {
                        panic!("thread {culprit} fails");
                    }
                    team.barrier(); // the others must not wait here forever
                })
            }));
            assert!(outcome.is_err(), "thread {culprit}'s panic was lost");
        }
        let ran = AtomicUsize::new(0);
        threads.run(&|team: &Team| {
            team.barrier();
            ran.fetch_add(1, Ordering::SeqCst);
        });
        assert_eq!(ran.load(Ordering::SeqCst), 3);
    }

    #[test]
    fn one_thread_runs_on_the_caller_and_a_clone_has_threads_of_its_own() {
        let caller = std::thread::current().id();
        let alone = Threads::new(1);
        alone.run(&|team: &Team| {
            assert_eq!(std::thread::current().id(), caller);
            team.barrier(); // does nothing
        });
        assert_eq!(Threads::new(0).count(), 1);
        let pool = Threads::new(2);
        let copy = pool.clone();
        assert_eq!(copy.count(), 2);
        drop(pool);
        let ran = AtomicUsize::new(0);
        copy.run(&|_: &Team| {
            ran.fetch_add(1, Ordering::SeqCst);
        });
        assert_eq!(ran.load(Ordering::SeqCst), 2);
    }

    #[test]
    fn even_parts_cover_the_range_in_order() {
        for (len, parts) in [(0, 3), (1, 3), (10, 3), (12, 4), (7, 7), (5, 8)] {
            let mut next = 0;
            for i in 0..parts {
                let part = even_part(len, parts, i);
                assert_eq!(part.start, next);
                assert!(part.len() <= len.div_ceil(parts) && part.len() >= len / parts);
                next = part.end;
            }
            assert_eq!(next, len);
        }
    }
}
