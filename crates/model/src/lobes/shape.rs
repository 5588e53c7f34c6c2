//! What a lobe formula implements ([`LobeShape`]) and the arithmetic it is written over
//! ([`Math`]: the fast functions or std's libm).

use crate::family::{FieldDef, ParamDef};
use crate::fastmath::{Fused, MulAdd, Plain};
use std::marker::PhantomData;

/// Most prepared columns a shape may ask for.
pub const MAX_COLUMNS: usize = 12;
/// Most fields a lobe may have.
pub const MAX_FIELDS: usize = 8;

/// The argument below which [`Math::exp_cut`] gives 0. Below it `e^x` is under `3e-300`; the
/// fast `exp` flushes to 0 below about -700.1 and libm's goes subnormal below -708.4, so
/// without a common cut the kernels would disagree there in relative terms (0 against a
/// subnormal) even though both are 0 for any purpose.
pub const EXP_CUT: f64 = -690.0;

/// How the per-sample formulas compute `a * b + c`, `exp`, `ln` and `sqrt`: the fast
/// branch-free functions of [`crate::fastmath`] (what the vectorised kernels use) or std's
/// libm (the scalar reference kernel).
pub trait Math {
    /// `a * b + c` (fused or not, as the kernel is compiled).
    fn mad(a: f64, b: f64, c: f64) -> f64;
    /// `e^x`: `+inf` on overflow, 0 on underflow (the fast one flushes below about -700).
    fn exp(x: f64) -> f64;
    /// `ln x` for a positive finite `x` (other inputs give an unspecified value: callers
    /// select a safe input first, as in `ln(if x > 0 { x } else { 1 })`).
    fn ln(x: f64) -> f64;
    /// `sqrt x` (the hardware instruction in every kernel).
    #[inline(always)]
    fn sqrt(x: f64) -> f64 {
        x.sqrt()
    }
    /// `e^x` for `x >= EXP_CUT`, 0 below ([`EXP_CUT`]): the same cut in every kernel, so the
    /// fast and the libm kernels agree on which tail values are exactly 0 (a lobe of the form
    /// `exp(-t)` reaches every `t` in its tails).
    #[inline(always)]
    fn exp_cut(x: f64) -> f64 {
        let e = Self::exp(x);
        if x >= EXP_CUT { e } else { 0.0 }
    }
    /// `x^p = exp(p ln x)` for `x > 0`, 0 for `x <= 0` (also when `p = 0`).
    #[inline(always)]
    fn pow_pos(x: f64, p: f64) -> f64 {
        let l = Self::ln(if x > 0.0 { x } else { 1.0 });
        if x > 0.0 { Self::exp(p * l) } else { 0.0 }
    }
}

/// The fast functions of [`crate::fastmath`] with `a * b + c` computed as `A` says.
pub struct Fast<A>(PhantomData<A>);

impl<A: MulAdd> Math for Fast<A> {
    #[inline(always)]
    fn mad(a: f64, b: f64, c: f64) -> f64 {
        A::mad(a, b, c)
    }
    #[inline(always)]
    fn exp(x: f64) -> f64 {
        crate::fastmath::exp::<A>(x)
    }
    #[inline(always)]
    fn ln(x: f64) -> f64 {
        crate::fastmath::ln_pos::<A>(x)
    }
}

/// std's libm, one rounding per operation: the reference.
pub struct Libm;

impl Math for Libm {
    #[inline(always)]
    fn mad(a: f64, b: f64, c: f64) -> f64 {
        a * b + c
    }
    #[inline(always)]
    fn exp(x: f64) -> f64 {
        x.exp()
    }
    #[inline(always)]
    fn ln(x: f64) -> f64 {
        x.ln()
    }
}

/// The portable kernel's math.
pub type PlainMath = Fast<Plain>;
/// The AVX2 and AVX-512 kernels' math.
pub type FusedMath = Fast<Fused>;

/// One lobe formula: what a family of the form `kd + sum_k lobe_k(u, v)` implements (see the
/// module documentation). Every function must be total over the lobe fields' bounds: a value
/// that overflows is `+inf` (the evaluation then fails), never NaN for finite inputs.
pub trait LobeShape: Send + Sync + 'static {
    /// The family's name (lowercase; specs say `family = "..."`).
    const NAME: &'static str;
    /// One line: the model and its source.
    const SUMMARY: &'static str;
    /// The lobe's fields, in canonical order (at most [`MAX_FIELDS`]).
    const LOBE_FIELDS: &'static [FieldDef];
    /// The parameters of an anisotropic lobe, if the model has one.
    const ANISOTROPIC: Option<&'static [ParamDef]>;
    /// The parameters of an isotropic lobe, if the model has one.
    const ISOTROPIC: Option<&'static [ParamDef]>;
    /// Prepared columns per sample (at most [`MAX_COLUMNS`]).
    const COLUMNS: usize;
    /// Constants of one lobe at one parameter vector (derived once per evaluation).
    type Coef: Copy + Default + Send + Sync + std::fmt::Debug;

    /// The columns of one sample (`cols.len() == COLUMNS`), from the incident `u` and exitant
    /// `v` (unit vectors, both pointing away from the surface, z the normal).
    fn prepare(u: [f64; 3], v: [f64; 3], cols: &mut [f64]);

    /// A lobe's constants from its physical field values (`fields.len()` is the number of lobe
    /// fields); `aniso` says whether the lobe is anisotropic (an isotropic lobe's tied fields
    /// are equal and its pan is 0).
    fn coef(fields: &[f64], aniso: bool) -> Self::Coef;

    /// The lobe's value at one sample (`s[k]` its column `k`).
    fn value<M: Math, const ANISO: bool>(c: &Self::Coef, s: &[f64; MAX_COLUMNS]) -> f64;

    /// The lobe's value and, in `g[f]`, its derivative by lobe field `f` (physical units;
    /// angles per degree). Entries of fields an isotropic lobe ties are each the derivative by
    /// that field alone (the framework adds tied ones up).
    fn value_grad<M: Math, const ANISO: bool>(
        c: &Self::Coef,
        s: &[f64; MAX_COLUMNS],
        g: &mut [f64; MAX_FIELDS],
    ) -> f64;
}
