//! An array that the threads of a team read and write at once, each in
//! places no other thread touches at the same time.
//!
//! Rust's borrows say it for one split: `split_at_mut` gives two threads
//! two halves. The parallel factorization and solves need more: a thread
//! writes the rows it owns of a supernode's columns while the others write
//! theirs, interleaved in memory, then after a barrier reads what the
//! others wrote. [`SharedSlice`] is the array for that: it hands out
//! slices and values by index, and each caller promises (the `unsafe`
//! blocks, each with its reason) that no other thread writes what it reads,
//! or touches what it writes, until the next barrier. The promise rests on
//! the schedule: which thread owns which rows in which phase
//! (`sparse/subtrees.rs`, and the files that use it).

use std::marker::PhantomData;
use std::ops::Range;

/// A borrowed array shared by the threads of a team, read and written
/// through raw pointers.
#[derive(Debug)]
pub struct SharedSlice<'a, T> {
    start: *mut T,
    len: usize,
    _borrow: PhantomData<&'a mut [T]>,
}

// SAFETY: the array is borrowed mutably for `'a`, so only the team reaches
// it; each access is `unsafe` with the promise that no two threads touch one
// element at once with one of them writing.
unsafe impl<T: Send> Sync for SharedSlice<'_, T> {}
// SAFETY: as above.
unsafe impl<T: Send> Send for SharedSlice<'_, T> {}

impl<'a, T> SharedSlice<'a, T> {
    /// Shares `slice` for as long as it is borrowed.
    pub fn new(slice: &'a mut [T]) -> Self {
        SharedSlice {
            start: slice.as_mut_ptr(),
            len: slice.len(),
            _borrow: PhantomData,
        }
    }

    /// Its first element, for a caller that reaches elements through raw
    /// pointers (every read and write of them under the promise above).
    pub fn as_mut_ptr(&self) -> *mut T {
        self.start
    }

    /// Its length.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Is it empty?
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The elements `range`, to read.
    ///
    /// # Safety
    /// No thread writes any of them while the returned slice is used.
    ///
    /// # Panics
    /// When `range` is not inside the array.
    pub unsafe fn slice(&self, range: Range<usize>) -> &[T] {
        assert!(range.start <= range.end && range.end <= self.len);
        // SAFETY: inside the array (checked); not written meanwhile (the
        // caller's promise).
        unsafe { std::slice::from_raw_parts(self.start.add(range.start), range.len()) }
    }

    /// The elements `range`, to write.
    ///
    /// # Safety
    /// No other thread reads or writes any of them while the returned
    /// slice is used.
    ///
    /// # Panics
    /// When `range` is not inside the array.
    #[allow(clippy::mut_from_ref)] // the point of the type, under the caller's promise
    pub unsafe fn slice_mut(&self, range: Range<usize>) -> &mut [T] {
        assert!(range.start <= range.end && range.end <= self.len);
        // SAFETY: inside the array (checked); this thread's alone meanwhile
        // (the caller's promise).
        unsafe { std::slice::from_raw_parts_mut(self.start.add(range.start), range.len()) }
    }

    /// Element `i`.
    ///
    /// # Safety
    /// No other thread writes it meanwhile.
    ///
    /// # Panics
    /// When `i` is outside the array.
    #[inline(always)]
    pub unsafe fn get(&self, i: usize) -> T
    where
        T: Copy,
    {
        assert!(i < self.len);
        // SAFETY: inside the array (checked); not written meanwhile.
        unsafe { self.start.add(i).read() }
    }

    /// Sets element `i`.
    ///
    /// # Safety
    /// No other thread reads or writes it meanwhile.
    ///
    /// # Panics
    /// When `i` is outside the array.
    #[inline(always)]
    pub unsafe fn set(&self, i: usize, value: T)
    where
        T: Copy,
    {
        assert!(i < self.len);
        // SAFETY: inside the array (checked); this thread's alone meanwhile.
        unsafe { self.start.add(i).write(value) }
    }
}
