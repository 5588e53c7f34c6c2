//! Branch-free `ln` and `exp` written so that loops calling them auto-vectorise.
//!
//! Only adds, multiplies, one division, comparisons/selects and integer bit operations that
//! AVX2 has (64-bit add/sub/shift/and/or): no libm calls and no float<->int conversions (those
//! are done with the 1.5*2^52 "magic number" trick), so LLVM can vectorise a loop over a
//! slice. The evaluator compiles these loops twice: once with `avx2,fma` enabled (using
//! [`Fused`]) and once for the baseline target (using [`Plain`]), and picks one at run time;
//! CPUs with AVX-512F use the intrinsics kernels of `crate::avx512` instead.
//!
//! Accuracy: `ln` follows fdlibm's `__ieee754_log` (< 1 ulp); `exp` uses a degree-11 Taylor
//! polynomial on `|r| <= ln2/2` (truncation error < 7e-15 relative) and exact scaling by
//! `2^k` in two steps so overflow gives `+inf`; results below `2^-1010` are 0
//! ([`EXP_FLUSH_K`]), so no subnormal is ever computed.
//!
//! The lobe loops run each stage over a chunk of samples, so they can check the chunk first
//! and take shorter forms that give the same bits where they apply: [`ln_normal`] when no `d`
//! is subnormal ([`no_subnormal`]) and [`exp_normal`] when every argument is within
//! ±[`EXP_NORMAL_MAX`] ([`all_exp_normal`]), which is nearly always. Measured with
//! `cpu_throughput` (2026-12-03): values 8.0-8.8 to 6.6-7.6 ns per lobe-sample portable, 2.8-3.1
//! to 2.3-2.7 AVX2.

// Constants are copied digit for digit from fdlibm so they can be checked against it.
#![allow(clippy::excessive_precision)]

const MAGIC: f64 = 6755399441055744.0; // 1.5 * 2^52: x + MAGIC - MAGIC rounds x to an integer
const TWO52: f64 = 4503599627370496.0;
pub(crate) const LN2_HI: f64 = 6.931_471_803_691_238_164_90e-1;
pub(crate) const LN2_LO: f64 = 1.908_214_929_270_587_700_02e-10;
const LOG2E: f64 = std::f64::consts::LOG2_E;
const SQRT2: f64 = std::f64::consts::SQRT_2;
/// fdlibm's `Lg1..Lg7`, the logarithm's polynomial in `s^2` (`LG[0]` is `Lg1`); shared with
/// the AVX-512 kernel.
pub(crate) const LG: [f64; 7] = [
    6.666_666_666_666_735_130e-1,
    3.999_999_999_940_941_908e-1,
    2.857_142_874_366_239_149e-1,
    2.222_219_843_214_978_396e-1,
    1.818_357_216_161_805_012e-1,
    1.531_383_769_920_937_332e-1,
    1.479_819_860_511_658_591e-1,
];

/// How `a * b + c` is computed: [`Plain`] (two roundings, any CPU) or [`Fused`] (`mul_add`,
/// only used inside functions compiled with FMA enabled, where it is one instruction).
pub trait MulAdd {
    /// Whether the exponential's polynomial is evaluated in Estrin's form (a shorter
    /// dependency chain, a few more multiplies) rather than Horner's; see `exp_taylor`.
    const ESTRIN: bool;
    /// `a * b + c`.
    fn mad(a: f64, b: f64, c: f64) -> f64;
}

/// Separate multiply and add.
pub struct Plain;
/// Fused multiply-add.
pub struct Fused;

impl MulAdd for Plain {
    const ESTRIN: bool = true;
    #[inline(always)]
    fn mad(a: f64, b: f64, c: f64) -> f64 {
        a * b + c
    }
}

impl MulAdd for Fused {
    const ESTRIN: bool = false;
    #[inline(always)]
    fn mad(a: f64, b: f64, c: f64) -> f64 {
        a.mul_add(b, c)
    }
}

#[inline(always)]
fn sel(c: bool, a: f64, b: f64) -> f64 {
    if c { a } else { b }
}

/// Natural logarithm of a positive finite `d` (subnormals handled). Other inputs give garbage:
/// callers substitute 1 for `d <= 0` first.
#[inline(always)]
pub fn ln_pos<A: MulAdd>(d: f64) -> f64 {
    ln_core::<A, true>(d)
}

/// [`ln_pos`] for a normal positive `d` (not checked), bit for bit the same there: without the
/// rescaling of subnormals. A chunk of a lobe loop takes this path when no `d` in it is
/// subnormal ([`no_subnormal`]).
#[inline(always)]
pub fn ln_normal<A: MulAdd>(d: f64) -> f64 {
    ln_core::<A, false>(d)
}

/// Whether no entry of `ds` is a positive subnormal (the only inputs of [`ln_clamped`] that
/// need [`ln_pos`]'s rescaling: `d <= 0` is replaced by 1).
#[inline(always)]
pub fn no_subnormal(ds: &[f64]) -> bool {
    let mut out = 0u64;
    for &d in ds {
        out |= u64::from(d > 0.0 && d < f64::MIN_POSITIVE);
    }
    out == 0
}

#[inline(always)]
fn ln_core<A: MulAdd, const SUBNORMAL: bool>(d: f64) -> f64 {
    let sub = SUBNORMAL && d < f64::MIN_POSITIVE;
    let d = if SUBNORMAL {
        sel(sub, d * 18014398509481984.0, d) // * 2^54
    } else {
        d
    };
    let bits = d.to_bits();
    let ebits = bits >> 52;
    let m = f64::from_bits((bits & 0x000F_FFFF_FFFF_FFFF) | 0x3FF0_0000_0000_0000);
    let big = m > SQRT2;
    let m = sel(big, m * 0.5, m);
    // The biased exponent as a float without an int->float conversion instruction.
    let e = f64::from_bits(ebits | 0x4330_0000_0000_0000) - TWO52 - 1023.0 + sel(big, 1.0, 0.0);
    let e = if SUBNORMAL {
        e - sel(sub, 54.0, 0.0)
    } else {
        e
    };
    let f = m - 1.0;
    let s = f / (2.0 + f);
    let z = s * s;
    let w = z * z;
    let t1 = w * A::mad(w, A::mad(w, LG[5], LG[3]), LG[1]);
    let t2 = z * A::mad(w, A::mad(w, A::mad(w, LG[6], LG[4]), LG[2]), LG[0]);
    let r = t2 + t1;
    let hfsq = 0.5 * f * f;
    A::mad(e, LN2_HI, -((hfsq - A::mad(s, hfsq + r, e * LN2_LO)) - f))
}

/// `2^k` for an integer-valued float `k` in [-1022, 1023].
#[inline(always)]
fn pow2i(k: f64) -> f64 {
    let ki = (k + MAGIC).to_bits().wrapping_sub(MAGIC.to_bits());
    f64::from_bits(ki.wrapping_add(1023) << 52)
}

/// Smallest `k = round(x log2 e)` whose `p 2^k` [`exp`] keeps: below it the result is 0. At
/// `k >= EXP_FLUSH_K` the result is at least `0.7 * 2^-1010`, a normal number that stays normal
/// through the lobe kernels' products, so they never compute with subnormals. Each operation
/// that makes or reads a subnormal costs a microcode assist of about a hundred cycles on Intel
/// cores, and in raw n (`d^n` with `n` in the thousands) `d^n` underflows at most samples: the
/// measured cost is in docs/performance.md (issue 38). A lobe value below `2^-1010` changes no
/// residual's bits beside a data value of normal size; the Jacobian
/// entries computed from it become 0: a dead lobe's (which were below 1e-304 or so), and
/// `n d^(n-1)` at the very edge of a lobe (`d` below 1e-304 with `n` near 1), where the
/// derivative of `max(0, d)^n` jumps anyway. The scalar reference kernel (libm `powf`) keeps
/// gradual underflow.
pub const EXP_FLUSH_K: f64 = -1010.0;

/// `e^x`; `+inf` above ~709.78, 0 below about -700.1 ([`EXP_FLUSH_K`]: no subnormal results),
/// NaN stays NaN.
#[inline(always)]
pub fn exp<A: MulAdd>(x: f64) -> f64 {
    let xc = sel(x > 800.0, 800.0, x);
    let xc = sel(xc < -800.0, -800.0, xc);
    let (k, p) = exp_reduced::<A>(xc);
    // Flushed results are scaled by 2^EXP_FLUSH_K instead, so no subnormal is made and dropped.
    let flush = k < EXP_FLUSH_K;
    let ks = sel(flush, EXP_FLUSH_K, k);
    // Scale in two steps so k up to 1154 neither wraps the exponent field nor loses the
    // overflow to +inf.
    let k1 = (ks * 0.5 + MAGIC) - MAGIC;
    let k2 = ks - k1;
    let y = sel(flush, 0.0, p * pow2i(k1) * pow2i(k2));
    sel(x.is_nan(), x, y)
}

/// Largest `|x|` for which [`exp_normal`] equals [`exp`]: `k = round(x log2 e)` stays within
/// ±1010, so `p 2^k` (`p` in [0.7, 1.42]) is a normal number and one exact scaling gives the
/// same bits as the two-step one.
pub const EXP_NORMAL_MAX: f64 = 700.0;

/// `e^x` for `|x| <= EXP_NORMAL_MAX` (not checked): [`exp`] without the clamps, the two-step
/// scaling and the NaN select, bit for bit the same there. A whole chunk of a lobe loop takes
/// this path when every argument is in range ([`all_exp_normal`]), about 12 of `exp`'s 45
/// vector operations fewer.
#[inline(always)]
pub fn exp_normal<A: MulAdd>(x: f64) -> f64 {
    let (k, p) = exp_reduced::<A>(x);
    p * pow2i(k)
}

/// `(k, p)` with `e^x = p 2^k`: `k = round(x log2 e)` and `p = e^r` on the reduced
/// `r = x - k ln 2`, `|r| <= ln2 / 2` (both exponentials share it, so their bits agree).
#[inline(always)]
fn exp_reduced<A: MulAdd>(x: f64) -> (f64, f64) {
    let k = A::mad(x, LOG2E, MAGIC) - MAGIC;
    // k * LN2_HI is exact (LN2_HI has 32 significant bits, |k| <= 1155).
    let r = A::mad(-k, LN2_LO, x - k * LN2_HI);
    (k, exp_taylor::<A>(r))
}

/// `1/k!` for k = 0..=11: the coefficients of [`exp_taylor`], shared with the AVX-512 kernel.
pub(crate) const EXP_TAYLOR: [f64; 12] = [
    1.0,
    1.0,
    0.5,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5040.0,
    1.0 / 40320.0,
    1.0 / 362880.0,
    1.0 / 3628800.0,
    1.0 / 39916800.0,
];

/// The degree-11 Taylor polynomial of `e^r`: in Horner's form with fused multiply-adds and in
/// Estrin's form without ([`MulAdd::ESTRIN`]). Without FMA each Horner step is a multiply and
/// then an add, a chain of 22 dependent operations per sample that held the out-of-order core
/// waiting: in Estrin's form the baseline kernel's values took 6.46 instead of 7.13 ns per
/// lobe-sample (medians of six `cpu_throughput` runs alternated with Horner's, 2026-12-03).
/// With FMA the chain is half as long and Estrin's extra multiplies gained nothing, so the
/// fused form keeps Horner's bits.
#[inline(always)]
fn exp_taylor<A: MulAdd>(r: f64) -> f64 {
    if A::ESTRIN {
        let r2 = r * r;
        let r4 = r2 * r2;
        let pair = |i: usize| A::mad(EXP_TAYLOR[i + 1], r, EXP_TAYLOR[i]);
        let quad = |i: usize| A::mad(pair(i + 2), r2, pair(i));
        A::mad(
            A::mad(pair(10), r2, pair(8)),
            r4 * r4,
            A::mad(quad(4), r4, quad(0)),
        )
    } else {
        EXP_TAYLOR
            .iter()
            .rev()
            .skip(1)
            .fold(EXP_TAYLOR[11], |p, &c| A::mad(p, r, c))
    }
}

/// Whether every `n l` (the exponential's argument in [`pow_from_ln`]) is within
/// [`EXP_NORMAL_MAX`]; false for NaN.
#[inline(always)]
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub fn all_exp_normal(n: f64, ls: &[f64]) -> bool {
    let mut out = 0u64;
    for &l in ls {
        // `!(a <= b)` is true for NaN as well as for out-of-range values.
        out |= u64::from(!((n * l).abs() <= EXP_NORMAL_MAX));
    }
    out == 0
}

/// [`pow_from_ln`] when the caller knows `|n l| <= EXP_NORMAL_MAX` ([`all_exp_normal`]).
#[inline(always)]
pub fn pow_from_ln_normal<A: MulAdd>(d: f64, n: f64, l: f64) -> f64 {
    sel(d > 0.0, exp_normal::<A>(n * l), 0.0)
}

/// `ln d`, or 0 when `d <= 0`: the first stage of the lobe kernel.
#[inline(always)]
pub fn ln_clamped<A: MulAdd>(d: f64) -> f64 {
    ln_pos::<A>(sel(d > 0.0, d, 1.0))
}

/// [`ln_clamped`] when no `d` is a positive subnormal ([`no_subnormal`]).
#[inline(always)]
pub fn ln_clamped_normal<A: MulAdd>(d: f64) -> f64 {
    ln_normal::<A>(sel(d > 0.0, d, 1.0))
}

/// `max(0, d)^n` from `l = ln_clamped(d)`: the second stage. `d <= 0` gives 0 for every `n`;
/// `n = 0` with `d > 0` gives 1.
#[inline(always)]
pub fn pow_from_ln<A: MulAdd>(d: f64, n: f64, l: f64) -> f64 {
    sel(d > 0.0, exp::<A>(n * l), 0.0)
}

/// `(max(0, d)^n, ln d)` in one call (the two stages composed).
#[cfg(test)]
fn pow_clamped<A: MulAdd>(d: f64, n: f64) -> (f64, f64) {
    let l = ln_clamped::<A>(d);
    (pow_from_ln::<A>(d, n, l), l)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    /// The chunk fast paths give the very bits of the general functions wherever their
    /// guards let them run, including the edges of the guarded ranges.
    #[test]
    fn fast_paths_equal_the_general_functions_bit_for_bit() {
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(7);
        let mut xs: Vec<f64> = (0..200_000)
            .map(|_| rng.random_range(-EXP_NORMAL_MAX..=EXP_NORMAL_MAX))
            .collect();
        xs.extend([EXP_NORMAL_MAX, -EXP_NORMAL_MAX, 0.0, -0.0, 1e-300, -1e-300]);
        for &x in &xs {
            same_bits(exp_normal::<Plain>, exp::<Plain>, x);
            same_bits(exp_normal::<Fused>, exp::<Fused>, x);
        }
        let mut ds: Vec<f64> = (0..200_000)
            .map(|_| 10f64.powf(rng.random_range(-307.6..308.0)))
            .collect();
        ds.extend([
            f64::MIN_POSITIVE,
            f64::MAX,
            1.0,
            SQRT2,
            f64::from_bits(SQRT2.to_bits() + 1),
        ]);
        for &d in &ds {
            same_bits(ln_normal::<Plain>, ln_pos::<Plain>, d);
            same_bits(ln_normal::<Fused>, ln_pos::<Fused>, d);
        }
    }

    fn same_bits(fast: fn(f64) -> f64, general: fn(f64) -> f64, v: f64) {
        assert_eq!(fast(v).to_bits(), general(v).to_bits(), "{v}");
    }

    #[test]
    fn the_guards_refuse_what_the_fast_paths_cannot_do() {
        assert!(all_exp_normal(2.0, &[350.0, -350.0, 0.0]));
        assert!(!all_exp_normal(2.0, &[0.0, 350.1]));
        assert!(!all_exp_normal(1.0, &[0.0, f64::NAN]));
        assert!(!all_exp_normal(f64::INFINITY, &[1.0]));
        assert!(no_subnormal(&[f64::MIN_POSITIVE, 0.0, -1e-310, 1.0]));
        assert!(!no_subnormal(&[1.0, 1e-310]));
        assert!(!no_subnormal(&[5e-324]));
    }

    #[test]
    fn ln_and_exp_match_libm() {
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(1);
        let mut worst: f64 = 0.0;
        for _ in 0..200_000 {
            let d: f64 = 10f64.powf(rng.random_range(-310.0..5.0));
            let b = d.ln();
            for a in [ln_pos::<Plain>(d), ln_pos::<Fused>(d)] {
                worst = worst.max((a - b).abs() / b.abs().max(1e-300));
            }
            let x: f64 = rng.random_range(-745.0..709.7);
            let b = x.exp();
            for a in [exp::<Plain>(x), exp::<Fused>(x)] {
                if b > 1e-300 {
                    worst = worst.max((a - b).abs() / b);
                }
                // Flushed below 2^-1010 (about 1e-304), and never subnormal.
                assert!(a == 0.0 || a >= f64::MIN_POSITIVE, "{x}: {a}");
                assert!(a == 0.0 || b > 6e-305, "{x}: {a} {b}");
                assert!(a > 0.0 || b < 1.5e-304, "{x}: {a} {b}");
            }
        }
        assert!(worst < 1e-14, "worst relative error {worst}");
        assert_eq!(exp::<Plain>(710.0), f64::INFINITY);
        assert_eq!(exp::<Plain>(1e300), f64::INFINITY);
        assert_eq!(exp::<Plain>(-1e300), 0.0);
        assert_eq!(exp::<Plain>(-720.0), 0.0);
        assert!(exp::<Plain>(-700.0) > 0.0);
        assert!(exp::<Plain>(f64::NAN).is_nan());
        assert_eq!(exp::<Plain>(0.0), 1.0);
        assert_eq!(ln_pos::<Plain>(1.0), 0.0);
        assert!((ln_pos::<Plain>(5e-324) - 5e-324f64.ln()).abs() < 1e-12);
        assert_eq!(pow_clamped::<Plain>(-0.5, 0.0), (0.0, 0.0));
        assert_eq!(pow_clamped::<Plain>(0.0, 3.0).0, 0.0);
        assert_eq!(pow_clamped::<Plain>(0.3, 0.0).0, 1.0);
        assert_eq!(pow_clamped::<Plain>(1.5, 10000.0).0, f64::INFINITY);
    }
}
