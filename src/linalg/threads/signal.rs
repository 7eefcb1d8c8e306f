//! Waiting for a condition another thread makes true: spin a little, then
//! sleep.
//!
//! A thread that waits for something a few microseconds away (the next
//! phase of a solve) should not go to sleep: waking it costs the operating
//! system tens of microseconds. A thread that waits longer (for the next
//! time step, while the program writes a frame) should not spin and burn
//! a core. So a waiter checks its condition in a loop for a short while,
//! then sleeps on a condition variable until a [`Signal::notify`].
//!
//! No wake-up is lost: a sleeper counts itself (`sleepers`) under the
//! mutex before its last look at the condition, and the notifier makes the
//! condition true before it reads `sleepers`; all of it in sequentially
//! consistent order, so either the sleeper sees the condition true, or the
//! notifier sees the sleeper and wakes it under the same mutex.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::{Duration, Instant};

/// How long a waiter spins before it sleeps: one phase of a step's
/// iteration often waits tens of microseconds for another (the threads'
/// shares are not equal), and put to sleep then it would be woken late.
/// With 50 µs two threads stepped the flag no faster than one (a 2-vCPU
/// EPYC VM); with 300 µs and 1 ms, 1.14–1.15× faster (`simulate
/// data/flag.json --steps 40 --threads 1|2`, interleaved).
const SPIN: Duration = Duration::from_micros(1000);

/// How long it spins before it starts yielding its core between checks.
const PATIENCE: Duration = Duration::from_micros(2);

/// A place to wait for conditions that other threads make true.
#[derive(Debug, Default)]
pub(super) struct Signal {
    lock: Mutex<()>,
    wake: Condvar,
    sleepers: AtomicUsize,
}

impl Signal {
    /// Returns once `ready()` is true. `ready` must read what it tests
    /// with sequentially consistent loads.
    pub(super) fn wait(&self, ready: impl Fn() -> bool) {
        if spin_until(&ready) {
            return;
        }
        let mut guard = self.lock.lock().unwrap_or_else(|e| e.into_inner());
        self.sleepers.fetch_add(1, Ordering::SeqCst);
        while !ready() {
            guard = self.wake.wait(guard).unwrap_or_else(|e| e.into_inner());
        }
        self.sleepers.fetch_sub(1, Ordering::SeqCst);
    }

    /// Wakes every sleeper; call it after making a condition true (with a
    /// sequentially consistent store).
    pub(super) fn notify(&self) {
        if self.sleepers.load(Ordering::SeqCst) > 0 {
            let _guard = self.lock.lock().unwrap_or_else(|e| e.into_inner());
            self.wake.notify_all();
        }
    }
}

/// Checks `ready` for [`SPIN`]; true once it holds. After the first
/// microseconds it gives its core away between checks
/// (`yield_now`): on a loaded machine the thread it waits for may be
/// waiting for that very core.
fn spin_until(ready: &impl Fn() -> bool) -> bool {
    let start = Instant::now();
    loop {
        for _ in 0..64 {
            if ready() {
                return true;
            }
            std::hint::spin_loop();
        }
        let waited = start.elapsed();
        if waited > SPIN {
            return false;
        }
        if waited > PATIENCE {
            std::thread::yield_now();
        }
    }
}
