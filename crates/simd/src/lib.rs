//! The SIMD kernel choice shared by `brdf-model` (the residual and Jacobian loops) and
//! `bounded-lm` (the QR and dot-product loops), so that both crates speak one vocabulary and
//! ask the CPU once.
//!
//! * [`Kernel`]: the user-facing choice `auto|avx512|avx2|portable|scalar` (parsing with an
//!   error listing the choices, [`Display`](std::fmt::Display), serde), its availability on the
//!   running CPU, [`Kernel::resolve`] of `auto` to the fastest kernel the CPU has, and
//!   [`Kernel::available`].
//! * [`cpu`]: the CPU's SIMD features, detected once per process and cached.
//! * [`KernelCell`]: a process-wide kernel choice in an atomic (what `bounded_lm::set_kernel`
//!   keeps), read on every dispatch without locking.
//!
//! A leaf crate: it depends on no other crate of the workspace, so `bounded-lm` can use it
//! without depending on the model.

#![warn(missing_docs)]

mod cell;
mod cpu;
mod kernel;

pub use cell::KernelCell;
pub use cpu::{Cpu, cpu};
pub use kernel::{Kernel, KernelError};
