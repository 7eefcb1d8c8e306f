//! Which kernels run: the native ones, or the portable ones every CPU runs.
//!
//! The hot loops (the triangular solves, the supernodal factorization's
//! dense blocks, the local step, the spring pass, the vector algebra of
//! the accelerated methods) are written once as plain loops, the
//! **portable** kernels. On x86-64 each is also compiled a second time for
//! the vector instructions of the CPU it runs on (AVX2, FMA, AVX-512,
//! detected at run time): the **native** kernels, the default.
//!
//! Both compute the same formulas, but not always to the same bits: a fused
//! multiply-add rounds once where a multiplication and an addition round
//! twice, and four lanes add a sum in another order than one running sum.
//! A WebAssembly build has no such instructions and runs the portable
//! kernels; run natively with them (`--kernels portable` on the command
//! line, `SimulationOptions::kernels` in the library), a simulation
//! computes what the browser's page computes, to the bit.
//!
//! The choice belongs to the thread: [`with`] runs a closure with a choice
//! (a simulation runs its precomputation and its steps so), and every
//! dispatcher asks [`avx2`], [`avx2_fma`] or [`avx512_fma`] before it takes
//! the native way. Asking costs a thread-local read and the standard
//! library's cached feature test, once per call of a kernel (a whole
//! solve, a whole pass over the springs), not per number.

use std::cell::Cell;
use std::fmt;
use std::str::FromStr;

/// The kernels a computation runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum Kernels {
    /// The vector instructions this CPU has (on x86-64: AVX2, FMA and
    /// AVX-512 where present), else the portable loops.
    #[default]
    Native,
    /// The plain loops, as every CPU (and WebAssembly) runs them.
    Portable,
}

impl Kernels {
    /// Both choices.
    pub const ALL: [Kernels; 2] = [Kernels::Native, Kernels::Portable];

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Kernels::Native => "native",
            Kernels::Portable => "portable",
        }
    }
}

impl fmt::Display for Kernels {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Kernels {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        Kernels::ALL
            .into_iter()
            .find(|k| k.name() == text)
            .ok_or_else(|| format!("unknown kernels '{text}' (expected native or portable)"))
    }
}

thread_local! {
    /// This thread's choice, outside [`with`]: native.
    static CHOSEN: Cell<Kernels> = const { Cell::new(Kernels::Native) };
}

/// The kernels this thread runs now.
pub fn chosen() -> Kernels {
    CHOSEN.with(Cell::get)
}

/// Runs `work` on this thread with `kernels`, then restores the choice
/// that was in force (also when `work` panics).
pub fn with<R>(kernels: Kernels, work: impl FnOnce() -> R) -> R {
    /// Puts the earlier choice back when dropped.
    struct Restore(Kernels);
    impl Drop for Restore {
        fn drop(&mut self) {
            CHOSEN.with(|chosen| chosen.set(self.0));
        }
    }
    let _restore = Restore(CHOSEN.with(|chosen| chosen.replace(kernels)));
    work()
}

/// May a dispatcher run its AVX2 kernel: native kernels chosen, on a CPU
/// with AVX2?
#[cfg(target_arch = "x86_64")]
pub fn avx2() -> bool {
    chosen() == Kernels::Native && std::arch::is_x86_feature_detected!("avx2")
}

/// May a dispatcher run its AVX2 + FMA kernel?
#[cfg(target_arch = "x86_64")]
pub fn avx2_fma() -> bool {
    avx2() && std::arch::is_x86_feature_detected!("fma")
}

/// May a dispatcher run its AVX-512 (with AVX2 and FMA) kernel?
#[cfg(target_arch = "x86_64")]
pub fn avx512_fma() -> bool {
    avx2_fma() && std::arch::is_x86_feature_detected!("avx512f")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_choice_holds_inside_with_and_is_undone_after() {
        assert_eq!(chosen(), Kernels::Native);
        let inside = with(Kernels::Portable, || {
            let nested = with(Kernels::Native, chosen);
            (chosen(), nested)
        });
        assert_eq!(inside, (Kernels::Portable, Kernels::Native));
        assert_eq!(chosen(), Kernels::Native);
        let unwound = std::panic::catch_unwind(|| with(Kernels::Portable, || panic!("in work")));
        assert!(unwound.is_err());
        assert_eq!(chosen(), Kernels::Native);
        assert_eq!("portable".parse(), Ok(Kernels::Portable));
        assert!("fast"
            .parse::<Kernels>()
            .unwrap_err()
            .contains("native or portable"));
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn portable_kernels_never_take_the_native_way() {
        with(Kernels::Portable, || {
            assert!(!avx2() && !avx2_fma() && !avx512_fma());
        });
    }
}
