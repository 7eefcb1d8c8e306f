//! Stopping a long computation from another thread.
//!
//! The dense path's precomputation is the product `AᵀA` (`n² m`
//! multiply-adds) and the Cholesky factorization of `Q` (`n³/3`): on the
//! skirt (`n` = 9,840) that is minutes, and gigabytes held meanwhile. A
//! program that lets a person start it (the viewer) must let that person
//! stop it. So these operations take a [`Cancel`]: a flag another thread
//! may set, which they look at as they go (before each row of the factor,
//! every few hundred rows of `A` in `AᵀA`), and then give up with
//! [`LinalgError::Cancelled`], dropping what they had allocated. A look
//! costs one relaxed load, against thousands of multiply-adds between two.

use super::error::LinalgError;
use std::sync::atomic::{AtomicBool, Ordering};

/// A flag that asks an operation in progress to stop, or none.
#[derive(Debug, Clone, Copy, Default)]
pub struct Cancel<'a> {
    flag: Option<&'a AtomicBool>,
}

impl<'a> Cancel<'a> {
    /// Nothing can stop the operation: it runs to its end.
    pub const NEVER: Cancel<'static> = Cancel { flag: None };

    /// The operation stops once `flag` is set (`None`: never).
    pub fn on(flag: Option<&'a AtomicBool>) -> Self {
        Cancel { flag }
    }

    /// `Err(`[`LinalgError::Cancelled`]`)` once the flag is set.
    ///
    /// # Errors
    /// [`LinalgError::Cancelled`] when someone has asked to stop.
    pub fn check(&self) -> Result<(), LinalgError> {
        match self.flag {
            Some(flag) if flag.load(Ordering::Relaxed) => Err(LinalgError::Cancelled),
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_set_flag_cancels() {
        assert_eq!(Cancel::NEVER.check(), Ok(()));
        let flag = AtomicBool::new(false);
        let cancel = Cancel::on(Some(&flag));
        assert_eq!(cancel.check(), Ok(()));
        flag.store(true, Ordering::Relaxed);
        assert_eq!(cancel.check(), Err(LinalgError::Cancelled));
    }
}
