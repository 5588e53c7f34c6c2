//! Families of the form "a constant diffuse term plus a sum of lobes of one formula", written
//! once per formula ([`LobeShape`]) and turned into a [`Family`] with fast kernels by
//! [`LobeFamily`].
//!
//! A shape gives its lobe fields and parameters, the per-sample columns it wants prepared from
//! the directions (half vectors, cosines: whatever does not depend on the parameters), the
//! per-lobe constants it derives from a lobe's fields once per evaluation, and two per-sample
//! functions: the lobe's value, and its value with the derivative by each lobe field. Both are
//! written once over a [`Math`] (how `exp`, `ln`, `sqrt` and `a * b + c` are computed), and
//! the framework compiles them into every kernel:
//! - [`Kernel::Avx512`] and [`Kernel::Avx2`]: the sample loops compiled with AVX-512F (8
//!   lanes) or AVX2 and FMA (4 lanes), auto-vectorised, with the branch-free `exp`/`ln` of
//!   [`crate::fastmath`];
//! - [`Kernel::Portable`]: the same loops for the baseline target;
//! - [`Kernel::Scalar`]: one sample at a time with std's libm (`exp`, `ln`), the reference the
//!   others are tested against.
//!
//! The framework handles the rest the same way for every shape: the free vector (fixed and
//! tied parameters, the coordinates of [`Coord`] and their chain-rule factors), the constant
//! term `kd` (the BRDF's constant part, as in Lafortune's model: `f = kd + sum_k lobe_k`),
//! residuals, Jacobian columns, failure on non-finite values, and the early-exit sums of
//! [`crate::Evaluator::sum_squares_below`].

mod eval;
mod shape;

pub use shape::{
    EXP_CUT, Fast, FusedMath, Libm, LobeShape, MAX_COLUMNS, MAX_FIELDS, Math, PlainMath,
};

use crate::data::DataSet;
use crate::evaluate::Evaluate;
use crate::family::{Coord, Family, FieldDef, LayoutParam, LobeKind, ParamDef, Role};
use crate::samples::Samples;
use brdf_simd::{Kernel, KernelError};
use std::marker::PhantomData;

/// The bounds of the constant term `kd` (as Lafortune's).
pub const KD_BOUNDS: (f64, f64) = (0.0, 1.0);

const SHARED_FIELDS: [FieldDef; 1] = [FieldDef {
    name: "kd",
    key: "kd",
    default: 0.0,
    optional: false,
    bounds: KD_BOUNDS,
}];

const SHARED_PARAMS: [ParamDef; 1] = [ParamDef {
    name: "kd",
    fields: &[0],
    coord: Coord::Identity,
    role: Role::Linear,
}];

/// The [`Family`] of a [`LobeShape`]: `f = kd + sum_k lobe_k`.
pub struct LobeFamily<S>(PhantomData<S>);

impl<S> Default for LobeFamily<S> {
    fn default() -> Self {
        LobeFamily(PhantomData)
    }
}

impl<S: LobeShape> LobeFamily<S> {
    /// The family of shape `S`.
    pub fn new() -> Self {
        Self::default()
    }
}

/// The columns of a sample set of shape `S` (used by [`Family::prepare`]).
pub fn prepare<S: LobeShape>(data: &DataSet) -> Samples {
    let n = data.len();
    let mut cols: Vec<Vec<f64>> = (0..S::COLUMNS).map(|_| Vec::with_capacity(n)).collect();
    let mut row = [0.0; MAX_COLUMNS];
    for i in 0..n {
        S::prepare(data.u(i), data.v(i), &mut row[..S::COLUMNS]);
        for (c, &v) in cols.iter_mut().zip(&row) {
            c.push(v);
        }
    }
    Samples::new(S::NAME, cols, data.values().to_vec())
}

impl<S: LobeShape> Family for LobeFamily<S> {
    fn name(&self) -> &'static str {
        S::NAME
    }

    fn summary(&self) -> &'static str {
        S::SUMMARY
    }

    fn shared_fields(&self) -> &'static [FieldDef] {
        &SHARED_FIELDS
    }

    fn lobe_fields(&self) -> &'static [FieldDef] {
        S::LOBE_FIELDS
    }

    fn shared_params(&self) -> &'static [ParamDef] {
        &SHARED_PARAMS
    }

    fn lobe_params(&self, kind: LobeKind) -> Option<&'static [ParamDef]> {
        match kind {
            LobeKind::Anisotropic => S::ANISOTROPIC,
            LobeKind::Isotropic => S::ISOTROPIC,
        }
    }

    fn prepare(&self, data: &DataSet) -> Samples {
        prepare::<S>(data)
    }

    /// The reference: the shape's formula with std's libm on freshly prepared columns; a lobe
    /// is taken as anisotropic (its tied fields are equal when it is isotropic, so both forms
    /// agree).
    fn value(&self, shared: &[f64], lobes: &[Vec<f64>], u: [f64; 3], v: [f64; 3]) -> f64 {
        let mut s = [0.0; MAX_COLUMNS];
        S::prepare(u, v, &mut s[..S::COLUMNS]);
        let lobes = lobes.iter().map(|l| {
            let c = S::coef(l, true);
            S::value::<Libm, true>(&c, &s)
        });
        shared[0] + lobes.sum::<f64>()
    }

    fn evaluator(
        &self,
        kinds: &[LobeKind],
        params: &[LayoutParam],
        kernel: Kernel,
    ) -> Result<Box<dyn Evaluate>, KernelError> {
        let kernel = kernel.resolve()?;
        Ok(Box::new(eval::LobeEval::<S>::new(kinds, params, kernel)))
    }
}
