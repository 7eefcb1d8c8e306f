//! Asking Linux for 2 MB pages under the factor and the solve's buffer.
//!
//! Every memory access goes through a translation from virtual to physical
//! address, cached in the TLB. With 4 KB pages the TLB of a core here
//! (2,048 entries in its second level) covers 8 MB; grid-316's `L` is 35 MB
//! and grid-1000's 450 MB, and each solve streams it twice while gathering
//! rows of the right-hand side from all over an `n × 4` buffer (32 MB at
//! grid-1000). So the solve keeps missing the TLB: once per 4 KB of `L`,
//! and on many gathered rows. With 2 MB pages the same TLB covers 4 GB.
//!
//! Linux gives 2 MB pages ("transparent huge pages") to anonymous memory
//! either always or, the common default (`/sys/kernel/mm/transparent_hugepage/enabled`
//! reads `madvise`), only to ranges the program marks with
//! `madvise(addr, len, MADV_HUGEPAGE)`. [`advise_huge_pages`] marks the
//! 2 MB-aligned part of a freshly allocated array, before it is first
//! written, so that its pages are made huge as they are touched. It is a
//! hint: if the kernel has no huge page free it uses small ones, and the
//! results are the same either way. On other systems it does nothing.
//!
//! Measured (`masssprings analyze grid-N.mtx`, this machine, interleaved
//! with the same program without the hint): the solve 5% faster at
//! grid-316 (8.6 against 9.1 ms) and 8% at grid-1000 (113.7 against 124
//! ms); no change on the skirt, whose `L` (2.7 MB) the TLB already covers.
//!
//! Source: the Linux kernel's documentation,
//! `Documentation/admin-guide/mm/transhuge.rst`; `madvise(2)`.

/// The size of a huge page on x86-64 Linux.
const HUGE_PAGE: usize = 2 << 20;

/// Marks the whole 2 MB pages inside `array` for huge pages (Linux only; a
/// hint with no other effect). Call it before the array is first written.
pub fn advise_huge_pages<T>(array: &mut [T]) {
    let start = array.as_mut_ptr() as usize;
    let end = start + std::mem::size_of_val(array);
    let first = start.div_ceil(HUGE_PAGE) * HUGE_PAGE;
    let last = end / HUGE_PAGE * HUGE_PAGE;
    if last > first {
        mark(first, last - first);
    }
}

#[cfg(target_os = "linux")]
fn mark(address: usize, length: usize) {
    /// `MADV_HUGEPAGE` of `<sys/mman.h>`.
    const MADV_HUGEPAGE: i32 = 14;
    extern "C" {
        fn madvise(address: *mut std::ffi::c_void, length: usize, advice: i32) -> i32;
    }
    // SAFETY: the range lies inside an allocation this program owns, and
    // MADV_HUGEPAGE changes how it is backed, never its contents. A failure
    // (an old kernel, huge pages switched off) leaves it as it was, which
    // is fine for a hint, so the result is not checked.
    unsafe { madvise(address as *mut std::ffi::c_void, length, MADV_HUGEPAGE) };
}

#[cfg(not(target_os = "linux"))]
fn mark(_address: usize, _length: usize) {}
