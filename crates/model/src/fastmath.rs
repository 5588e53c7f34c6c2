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
//! `2^k` in two steps so overflow gives `+inf` and underflow goes gradually to 0.

// Constants are copied digit for digit from fdlibm so they can be checked against it.
#![allow(clippy::excessive_precision)]

const MAGIC: f64 = 6755399441055744.0; // 1.5 * 2^52: x + MAGIC - MAGIC rounds x to an integer
const TWO52: f64 = 4503599627370496.0;
const LN2_HI: f64 = 6.931_471_803_691_238_164_90e-1;
const LN2_LO: f64 = 1.908_214_929_270_587_700_02e-10;
const LOG2E: f64 = std::f64::consts::LOG2_E;
const SQRT2: f64 = std::f64::consts::SQRT_2;
const LG1: f64 = 6.666_666_666_666_735_130e-1;
const LG2: f64 = 3.999_999_999_940_941_908e-1;
const LG3: f64 = 2.857_142_874_366_239_149e-1;
const LG4: f64 = 2.222_219_843_214_978_396e-1;
const LG5: f64 = 1.818_357_216_161_805_012e-1;
const LG6: f64 = 1.531_383_769_920_937_332e-1;
const LG7: f64 = 1.479_819_860_511_658_591e-1;

/// How `a * b + c` is computed: [`Plain`] (two roundings, any CPU) or [`Fused`] (`mul_add`,
/// only used inside functions compiled with FMA enabled, where it is one instruction).
pub trait MulAdd {
    /// `a * b + c`.
    fn mad(a: f64, b: f64, c: f64) -> f64;
}

/// Separate multiply and add.
pub struct Plain;
/// Fused multiply-add.
pub struct Fused;

impl MulAdd for Plain {
    #[inline(always)]
    fn mad(a: f64, b: f64, c: f64) -> f64 {
        a * b + c
    }
}

impl MulAdd for Fused {
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
    let sub = d < f64::MIN_POSITIVE;
    let d = sel(sub, d * 18014398509481984.0, d); // * 2^54
    let bits = d.to_bits();
    let ebits = bits >> 52;
    let m = f64::from_bits((bits & 0x000F_FFFF_FFFF_FFFF) | 0x3FF0_0000_0000_0000);
    let big = m > SQRT2;
    let m = sel(big, m * 0.5, m);
    // The biased exponent as a float without an int->float conversion instruction.
    let e = f64::from_bits(ebits | 0x4330_0000_0000_0000) - TWO52 - 1023.0 + sel(big, 1.0, 0.0)
        - sel(sub, 54.0, 0.0);
    let f = m - 1.0;
    let s = f / (2.0 + f);
    let z = s * s;
    let w = z * z;
    let t1 = w * A::mad(w, A::mad(w, LG6, LG4), LG2);
    let t2 = z * A::mad(w, A::mad(w, A::mad(w, LG7, LG5), LG3), LG1);
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

/// `e^x`; `+inf` above ~709.78, gradual underflow to 0 below ~-708, NaN stays NaN.
#[inline(always)]
pub fn exp<A: MulAdd>(x: f64) -> f64 {
    let xc = sel(x > 800.0, 800.0, x);
    let xc = sel(xc < -800.0, -800.0, xc);
    let k = A::mad(xc, LOG2E, MAGIC) - MAGIC;
    // k * LN2_HI is exact (LN2_HI has 32 significant bits, |k| <= 1155).
    let r = A::mad(-k, LN2_LO, xc - k * LN2_HI);
    // Taylor series of e^r to degree 11, Horner form.
    let mut p = 1.0 / 39916800.0;
    p = A::mad(p, r, 1.0 / 3628800.0);
    p = A::mad(p, r, 1.0 / 362880.0);
    p = A::mad(p, r, 1.0 / 40320.0);
    p = A::mad(p, r, 1.0 / 5040.0);
    p = A::mad(p, r, 1.0 / 720.0);
    p = A::mad(p, r, 1.0 / 120.0);
    p = A::mad(p, r, 1.0 / 24.0);
    p = A::mad(p, r, 1.0 / 6.0);
    p = A::mad(p, r, 0.5);
    p = A::mad(p, r, 1.0);
    p = A::mad(p, r, 1.0);
    // Scale in two steps so |k| up to 1154 neither wraps the exponent field nor loses the
    // overflow to +inf / underflow to 0.
    let k1 = (k * 0.5 + MAGIC) - MAGIC;
    let k2 = k - k1;
    let y = p * pow2i(k1) * pow2i(k2);
    sel(x.is_nan(), x, y)
}

/// `ln d`, or 0 when `d <= 0`: the first stage of the lobe kernel.
#[inline(always)]
pub fn ln_clamped<A: MulAdd>(d: f64) -> f64 {
    ln_pos::<A>(sel(d > 0.0, d, 1.0))
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
            }
        }
        assert!(worst < 1e-14, "worst relative error {worst}");
        assert_eq!(exp::<Plain>(710.0), f64::INFINITY);
        assert_eq!(exp::<Plain>(1e300), f64::INFINITY);
        assert_eq!(exp::<Plain>(-1e300), 0.0);
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
