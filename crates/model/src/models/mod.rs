//! The model families beyond Lafortune, each a [`crate::lobes::LobeShape`]: the formula, its
//! derivatives, its parameters and bounds, with the source of the formula in each module.

pub mod ashikhmin_shirley;
pub mod blinn_phong;
pub mod cook_torrance;
pub mod geometry;
pub mod ggx;
pub mod ward;
