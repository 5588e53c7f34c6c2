//! [`KernelCell`]: a process-wide kernel choice.

use std::sync::atomic::{AtomicU8, Ordering};

use crate::kernel::{Kernel, KernelError};

/// A kernel choice that a `static` can hold: set from anywhere, read on every dispatch with
/// one relaxed atomic load (no lock, no CPU query).
///
/// It always holds a concrete kernel: [`KernelCell::set`] resolves `auto` (and refuses what
/// the CPU cannot run), and a cell never set reads as [`Kernel::best`].
#[derive(Debug)]
pub struct KernelCell(AtomicU8);

impl KernelCell {
    /// A cell that reads as [`Kernel::best`] until set.
    pub const fn new() -> Self {
        KernelCell(AtomicU8::new(Kernel::Auto.index()))
    }

    /// Stores `kernel` resolved ([`Kernel::resolve`]) and returns the concrete kernel now in
    /// the cell; on error the cell is unchanged.
    ///
    /// # Errors
    /// [`KernelError::Unavailable`] when the running CPU lacks the kernel's instructions.
    pub fn set(&self, kernel: Kernel) -> Result<Kernel, KernelError> {
        let concrete = kernel.resolve()?;
        self.0.store(concrete.index(), Ordering::Relaxed);
        Ok(concrete)
    }

    /// The concrete kernel in the cell (never [`Kernel::Auto`]).
    #[inline]
    pub fn get(&self) -> Kernel {
        match Kernel::ALL.get(usize::from(self.0.load(Ordering::Relaxed))) {
            Some(Kernel::Auto) | None => Kernel::best(),
            Some(&k) => k,
        }
    }
}

impl Default for KernelCell {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_new_cell_reads_best_and_set_resolves() {
        let cell = KernelCell::new();
        assert_eq!(cell.get(), Kernel::best());
        assert_eq!(cell.set(Kernel::Scalar), Ok(Kernel::Scalar));
        assert_eq!(cell.get(), Kernel::Scalar);
        assert_eq!(cell.set(Kernel::Auto), Ok(Kernel::best()));
        assert_eq!(cell.get(), Kernel::best());
    }

    /// Refusing an unavailable kernel leaves the previous choice in place.
    #[test]
    fn an_unavailable_kernel_changes_nothing() {
        let cell = KernelCell::new();
        cell.set(Kernel::Portable).unwrap();
        for k in Kernel::ALL {
            if k.resolve().is_err() {
                assert!(cell.set(k).is_err());
                assert_eq!(cell.get(), Kernel::Portable);
            }
        }
    }
}
