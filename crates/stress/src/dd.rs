//! Double-double arithmetic (about 106 significant bits) with `exp`, `ln`, `expm1`, `sin`,
//! `cos`: the higher-precision reference the kernels are measured against.
//!
//! The algorithms are the classical ones of Dekker, Knuth and the QD library (Hida, Li and
//! Bailey): error-free `two_sum` / `two_prod` (the latter with a fused multiply-add), `exp` by
//! reduction `x = k ln 2 + r`, a Taylor series of `expm1(r / 1024)` and ten doublings,
//! `ln` by one Newton step on `exp` from the `f64` logarithm, `sin`/`cos` by their Taylor series
//! on `|x| <= pi/2` (the only range the model needs: pan is in `[-90, 90]` degrees).
//! Measured against 200-bit mpmath values in the tests: relative error below 1e-30 for `exp`
//! and `ln` on the model's ranges (the reduction `k ln 2` limits `exp` to about `|k| * 5e-33`
//! absolute in the reduced argument, i.e. below 1e-29 relative even at the overflow end).
//!
//! Written here rather than taken from `twofloat` because that crate does not document the
//! accuracy of its transcendental functions, and these five functions are all the reference
//! needs; `rug`/GMP would add a C build dependency.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A double-double number `hi + lo` with `|lo| <= ulp(hi) / 2`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct DD {
    /// Leading part (the value rounded to `f64`).
    pub hi: f64,
    /// Trailing part.
    pub lo: f64,
}

#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

#[inline]
fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// `ln 2` to double-double precision (mpmath, 200 bits).
pub const LN2: DD = DD {
    hi: std::f64::consts::LN_2,
    lo: 2.319_046_813_846_299_6e-17,
};
/// `pi / 180` to double-double precision.
pub const DEG: DD = DD {
    hi: 0.017_453_292_519_943_295,
    lo: 2.948_652_270_870_168_7e-19,
};
/// `ln(f64::MAX)` to double-double precision: `exp` above it overflows `f64`.
pub const LN_MAX: DD = DD {
    hi: 709.782_712_893_384,
    lo: 2.363_601_707_132_359_2e-14,
};

impl DD {
    /// Zero.
    pub const ZERO: DD = DD { hi: 0.0, lo: 0.0 };
    /// One.
    pub const ONE: DD = DD { hi: 1.0, lo: 0.0 };
    /// Positive infinity (`lo = 0` so that it never produces NaN when read).
    pub const INF: DD = DD {
        hi: f64::INFINITY,
        lo: 0.0,
    };

    /// An exact `f64`.
    pub const fn new(x: f64) -> DD {
        DD { hi: x, lo: 0.0 }
    }

    /// The exact product of two `f64`.
    pub fn prod(a: f64, b: f64) -> DD {
        let (hi, lo) = two_prod(a, b);
        DD { hi, lo }
    }

    /// Rounded to `f64`.
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }

    /// Absolute value.
    pub fn abs(self) -> DD {
        if self.hi < 0.0 { -self } else { self }
    }

    /// True when finite.
    pub fn is_finite(self) -> bool {
        self.hi.is_finite() && self.lo.is_finite()
    }

    /// Multiplication by `2^k` (exact unless the result leaves the normal range); done in two
    /// steps so `|k|` up to about 2000 neither wraps the exponent field nor overflows early.
    pub fn ldexp(self, k: i32) -> DD {
        let k1 = k / 2;
        let k2 = k - k1;
        let s1 = pow2(k1);
        let s2 = pow2(k2);
        DD {
            hi: self.hi * s1 * s2,
            lo: self.lo * s1 * s2,
        }
    }

    /// `e^x`; `+inf` (as [`DD::INF`]) above [`LN_MAX`], 0 below -746.
    pub fn exp(self) -> DD {
        if self.hi.is_nan() {
            return DD::new(f64::NAN);
        }
        if self > LN_MAX {
            return DD::INF;
        }
        if self.hi < -746.0 {
            return DD::ZERO;
        }
        let k = (self.hi / LN2.hi).round();
        let r = self - LN2 * k;
        let s = expm1_reduced(r);
        (s + DD::ONE).ldexp(k as i32)
    }

    /// `e^x - 1`, accurate also for small `|x|` (no cancellation: the series is summed directly).
    pub fn exp_m1(self) -> DD {
        if self.hi.abs() < 0.34 {
            expm1_reduced(self)
        } else {
            self.exp() - DD::ONE
        }
    }

    /// Natural logarithm of a positive finite value (NaN for `x <= 0`); one Newton step
    /// `y + x e^-y - 1` from the `f64` logarithm doubles its ~53 correct bits.
    pub fn ln(self) -> DD {
        if self.hi.is_nan() || self.hi <= 0.0 || !self.hi.is_finite() {
            return DD::new(f64::NAN);
        }
        // Scale tiny values so that e^-y stays finite in the Newton step.
        let (x, shift) = if self.hi < 1e-200 {
            (self.ldexp(1000), -1000.0)
        } else {
            (self, 0.0)
        };
        let y = DD::new(x.hi.ln());
        let y = y + x * (-y).exp() - DD::ONE;
        y + LN2 * shift
    }

    /// The square root (one Newton step from the `f64` root: full double-double accuracy);
    /// 0 for `self <= 0`.
    pub fn sqrt(self) -> DD {
        if self.hi <= 0.0 {
            return DD::ZERO;
        }
        if !self.hi.is_finite() {
            return DD::INF;
        }
        let s = self.hi.sqrt();
        let r = (self - DD::prod(s, s)) / (2.0 * s);
        DD::new(s) + r
    }

    /// `(sin x, cos x)` for `|x| <= 2` by the Taylor series (terms fall below 1e-34).
    pub fn sin_cos(self) -> (DD, DD) {
        debug_assert!(self.hi.abs() <= 2.0);
        let x2 = self * self;
        let mut sin = self;
        let mut cos = DD::ONE;
        let mut term_s = self;
        let mut term_c = DD::ONE;
        let mut k = 1.0;
        loop {
            term_c = -(term_c * x2) / ((k) * (k + 1.0));
            cos = cos + term_c;
            term_s = -(term_s * x2) / ((k + 1.0) * (k + 2.0));
            sin = sin + term_s;
            k += 2.0;
            if term_c.hi.abs() < 1e-36 && term_s.hi.abs() < 1e-36 {
                break;
            }
        }
        (sin, cos)
    }
}

/// `2^k` for `k` in `[-1022, 1023]`.
fn pow2(k: i32) -> f64 {
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// `e^r - 1` for `|r| <= 0.35`: Taylor series of `e^(r/1024) - 1` and ten doublings
/// `e^2t - 1 = 2 (e^t - 1) + (e^t - 1)^2` (which keep the relative accuracy of `e^t - 1`).
fn expm1_reduced(r: DD) -> DD {
    let t = r.ldexp(-10);
    let mut s = t;
    let mut term = t;
    let mut k = 2.0;
    while k < 30.0 {
        term = term * t / k;
        s = s + term;
        if term.hi.abs() <= 1e-36 * s.hi.abs() {
            break;
        }
        k += 1.0;
    }
    for _ in 0..10 {
        s = s.ldexp(1) + s * s;
    }
    s
}

impl Add for DD {
    type Output = DD;
    #[inline]
    fn add(self, b: DD) -> DD {
        if !(self.hi.is_finite() && b.hi.is_finite()) {
            return DD::new(self.hi + b.hi);
        }
        let (s1, s2) = two_sum(self.hi, b.hi);
        let (t1, t2) = two_sum(self.lo, b.lo);
        let (s1, s2) = quick_two_sum(s1, s2 + t1);
        let (hi, lo) = quick_two_sum(s1, s2 + t2);
        if hi.is_finite() {
            DD { hi, lo }
        } else {
            DD { hi, lo: 0.0 }
        }
    }
}

impl Sub for DD {
    type Output = DD;
    #[inline]
    fn sub(self, b: DD) -> DD {
        self + (-b)
    }
}

impl Neg for DD {
    type Output = DD;
    #[inline]
    fn neg(self) -> DD {
        DD {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Mul for DD {
    type Output = DD;
    #[inline]
    fn mul(self, b: DD) -> DD {
        let (p1, p2) = two_prod(self.hi, b.hi);
        if !p1.is_finite() {
            return DD::new(p1);
        }
        let p2 = p2 + (self.hi * b.lo + self.lo * b.hi);
        let (hi, lo) = quick_two_sum(p1, p2);
        if hi.is_finite() {
            DD { hi, lo }
        } else {
            DD { hi, lo: 0.0 }
        }
    }
}

impl Mul<f64> for DD {
    type Output = DD;
    #[inline]
    fn mul(self, b: f64) -> DD {
        self * DD::new(b)
    }
}

impl Div for DD {
    type Output = DD;
    #[inline]
    fn div(self, b: DD) -> DD {
        let q1 = self.hi / b.hi;
        let r = self - b * q1;
        let q2 = r.hi / b.hi;
        let r = r - b * q2;
        let q3 = r.hi / b.hi;
        let (hi, lo) = quick_two_sum(q1, q2);
        let out = DD { hi, lo } + DD::new(q3);
        if out.hi.is_finite() {
            out
        } else {
            DD {
                hi: out.hi,
                lo: 0.0,
            }
        }
    }
}

impl Div<f64> for DD {
    type Output = DD;
    #[inline]
    fn div(self, b: f64) -> DD {
        self / DD::new(b)
    }
}

impl PartialOrd for DD {
    fn partial_cmp(&self, o: &DD) -> Option<std::cmp::Ordering> {
        match self.hi.partial_cmp(&o.hi) {
            Some(std::cmp::Ordering::Equal) => self.lo.partial_cmp(&o.lo),
            c => c,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Relative difference of a dd value and a (hi, lo) pair from mpmath at 200 bits.
    fn rel(a: DD, hi: f64, lo: f64) -> f64 {
        let d = (a - DD { hi, lo }).to_f64();
        (d / hi).abs()
    }

    #[test]
    fn transcendental_functions_match_mpmath() {
        let cases: [(DD, f64, f64); 7] = [
            (
                DD::ONE.exp(),
                std::f64::consts::E,
                1.445_646_891_729_250_2e-16,
            ),
            (
                DD::new(0.3).exp(),
                1.349_858_807_576_003_2,
                -9.447_314_673_432_387e-17,
            ),
            (
                DD::new(709.5).exp(),
                1.354_986_319_314_632_8e308,
                -1.950_359_478_583_155e290,
            ),
            (
                DD::new(10.0).ln(),
                std::f64::consts::LN_10,
                -2.170_756_223_382_249_4e-16,
            ),
            (
                DD::new(0.3).ln(),
                -1.203_972_804_325_936_1,
                8.935_521_583_403_776e-17,
            ),
            (
                DD::new(1e-300).ln(),
                -690.775_527_898_213_7,
                -2.367_009_617_670_983_2e-14,
            ),
            (
                DD::new(1e-5).exp_m1(),
                1.000_005_000_016_666_8e-5,
                -3.111_926_571_619_883e-22,
            ),
        ];
        for (i, (v, hi, lo)) in cases.into_iter().enumerate() {
            let e = rel(v, hi, lo);
            assert!(e < 1e-30, "case {i}: relative error {e:e}");
        }
        let (s, c) = DD::ONE.sin_cos();
        assert!(rel(s, 0.841_470_984_807_896_5, 1.776_845_092_935_536e-18) < 1e-30);
        assert!(rel(c, 0.540_302_305_868_139_8, -4.760_954_612_604_417e-17) < 1e-30);
        let (s, _) = (DEG * 45.0).sin_cos();
        assert!(
            rel(
                s,
                std::f64::consts::FRAC_1_SQRT_2,
                -4.833_646_656_726_457e-17
            ) < 1e-30
        );
        // exp(ln 2) = 2 and the overflow boundary.
        assert!(((LN2.exp() - DD::new(2.0)).to_f64()).abs() < 1e-31);
        assert_eq!(DD::new(710.0).exp(), DD::INF);
        assert_eq!(DD::new(-800.0).exp(), DD::ZERO);
        assert!(DD::new(-1.0).ln().hi.is_nan());
    }

    #[test]
    fn arithmetic_is_error_free_where_it_should_be() {
        let a = DD::prod(0.1, 0.3);
        // 0.1 * 0.3 in f64 loses the low part; the dd product keeps it exactly.
        assert_eq!(a.hi, 0.1 * 0.3);
        assert_ne!(a.lo, 0.0);
        let b = (a / DD::new(0.3)) - DD::new(0.1);
        assert!(b.to_f64().abs() < 1e-32);
        assert_eq!(DD::new(3.0).ldexp(-2).hi, 0.75);
    }
}
