//! AVX-512F lobe kernels (8 lanes, mask registers for the tail, `getexp`/`getmant` for the
//! logarithm and `scalef` for the exponential's scaling, which also gives correct overflow to
//! `+inf`). Same formulas, polynomials and flush to 0 below `2^-1010` as [`crate::fastmath`].

#![cfg(target_arch = "x86_64")]

use super::samples::{View, g_factors};
use crate::fastmath::{EXP_FLUSH_K, EXP_TAYLOR, LG, LN2_HI, LN2_LO};
use std::arch::x86_64::*;

#[inline]
#[target_feature(enable = "avx512f")]
fn splat(v: f64) -> __m512d {
    _mm512_set1_pd(v)
}

/// `(max(0, d)^n, ln d)` per lane; `(0, 0)` where `d <= 0`.
#[inline]
#[target_feature(enable = "avx512f")]
fn pow_clamped(d: __m512d, n: __m512d) -> (__m512d, __m512d) {
    let zero = _mm512_setzero_pd();
    let pos = _mm512_cmp_pd_mask::<_CMP_GT_OQ>(d, zero);
    let dd = _mm512_mask_blend_pd(pos, splat(1.0), d);
    // dd = m 2^e with m in [1, 2), then m in [sqrt(1/2), sqrt(2)) as in fdlibm.
    let m = _mm512_getmant_pd::<_MM_MANT_NORM_1_2, _MM_MANT_SIGN_SRC>(dd);
    let e = _mm512_getexp_pd(dd);
    let big = _mm512_cmp_pd_mask::<_CMP_GT_OQ>(m, splat(std::f64::consts::SQRT_2));
    let m = _mm512_mask_mul_pd(m, big, m, splat(0.5));
    let e = _mm512_mask_add_pd(e, big, e, splat(1.0));
    let f = _mm512_sub_pd(m, splat(1.0));
    let s = _mm512_div_pd(f, _mm512_add_pd(splat(2.0), f));
    let z = _mm512_mul_pd(s, s);
    let w = _mm512_mul_pd(z, z);
    let t1 = _mm512_fmadd_pd(w, splat(LG[5]), splat(LG[3]));
    let t1 = _mm512_fmadd_pd(w, t1, splat(LG[1]));
    let t1 = _mm512_mul_pd(w, t1);
    let t2 = _mm512_fmadd_pd(w, splat(LG[6]), splat(LG[4]));
    let t2 = _mm512_fmadd_pd(w, t2, splat(LG[2]));
    let t2 = _mm512_fmadd_pd(w, t2, splat(LG[0]));
    let t2 = _mm512_mul_pd(z, t2);
    let r = _mm512_add_pd(t2, t1);
    // fdlibm's rearrangement, as in `fastmath::ln_pos` (< 1 ulp):
    // ln d = e ln2_hi - ((hfsq - (s (hfsq + R) + e ln2_lo)) - f) with hfsq = f^2 / 2.
    // The shorter `2s + sR` was a few ulp, which with the degree-10 exponential below put the
    // values up to 870 ulps off, outside brdf-stress's forward-error bound.
    let hfsq = _mm512_mul_pd(splat(0.5), _mm512_mul_pd(f, f));
    let inner = _mm512_fmadd_pd(s, _mm512_add_pd(hfsq, r), _mm512_mul_pd(e, splat(LN2_LO)));
    // e ln2_hi - x in one rounding is fma(e, ln2_hi, -x), the scalar code's form: negation
    // is exact, and both give +0 for x = +0 or -0.
    let l = _mm512_fmsub_pd(
        e,
        splat(LN2_HI),
        _mm512_sub_pd(_mm512_sub_pd(hfsq, inner), f),
    );
    // exp(n l). No clamping of x: |n l| <= MAX_EXPONENT * 745 = 7.45e8 (the widest exponent
    // bound, 1e6), so k stays an exact integer; r is accurate wherever the result is
    // representable (|x| <= 745) thanks to the fused reduction, and scalef saturates to +inf
    // (or the flush below to 0) for any larger k.
    let x = _mm512_mul_pd(n, l);
    let k = _mm512_roundscale_pd::<{ _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC }>(
        _mm512_mul_pd(x, splat(std::f64::consts::LOG2_E)),
    );
    let r = _mm512_fnmadd_pd(k, splat(LN2_HI), x);
    let r = _mm512_fnmadd_pd(k, splat(LN2_LO), r);
    // Degree 11, as in `fastmath::exp` (truncation < 7e-15 relative on |r| <= ln2/2; degree 10
    // was 2.3e-13, about 1000 ulps).
    let mut p = splat(EXP_TAYLOR[11]);
    for &c in EXP_TAYLOR[..11].iter().rev() {
        p = _mm512_fmadd_pd(p, r, splat(c));
    }
    // As `fastmath::exp`: 0 below 2^EXP_FLUSH_K, with k clamped so that no lane makes a
    // subnormal (see `EXP_FLUSH_K`).
    // Not-less-than keeps NaN lanes, as the generic code does.
    let keep = _mm512_cmp_pd_mask::<_CMP_NLT_UQ>(k, splat(EXP_FLUSH_K));
    let f = _mm512_scalef_pd(p, _mm512_max_pd(k, splat(EXP_FLUSH_K)));
    (
        _mm512_maskz_mov_pd(pos & keep, f),
        _mm512_maskz_mov_pd(pos, l),
    )
}

/// Vectors of 8 lanes per iteration of the unrolled loops: four took 6% off the Jacobian
/// against two (docs/performance.md), and each lane's operations stay the same.
const UNROLL: usize = 4;

/// Loads lanes `i..i+8` of `v` (masked to `mask`; masked lanes read as 0).
#[inline]
#[target_feature(enable = "avx512f")]
fn load(v: &[f64], i: usize, mask: __mmask8) -> __m512d {
    debug_assert!(i + (mask.count_ones() as usize) <= v.len());
    // SAFETY: the caller guarantees lanes selected by `mask` are in bounds of `v`; masked
    // loads never touch unselected lanes.
    unsafe { _mm512_maskz_loadu_pd(mask, v.as_ptr().add(i)) }
}

#[inline]
#[target_feature(enable = "avx512f")]
fn store(v: &mut [f64], i: usize, mask: __mmask8, x: __m512d) {
    debug_assert!(i + (mask.count_ones() as usize) <= v.len());
    // SAFETY: as in `load`.
    unsafe { _mm512_mask_storeu_pd(v.as_mut_ptr().add(i), mask, x) }
}

/// Lane masks covering `0..m` in steps of 8.
fn lanes(m: usize) -> impl Iterator<Item = (usize, __mmask8)> {
    (0..m).step_by(8).map(move |i| {
        let k = (m - i).min(8);
        (
            i,
            if k == 8 {
                0xFF
            } else {
                ((1u16 << k) - 1) as u8
            },
        )
    })
}

/// Adds `max(0, d)^n` to `out` for coefficients `c = [ap, aq, ar, cz]`; with
/// `keep = Some((f, l))` also stores each sample's `d^n` in `f` and `ln d` in `l` for a later
/// [`lobe_jacobian`] at the same point.
///
/// # Safety
/// The CPU must support AVX-512F; `d` (and `f`, `l`) must hold at least `out.len()` samples.
#[target_feature(enable = "avx512f")]
pub(crate) unsafe fn lobe_values(
    c: &[f64; 4],
    n: f64,
    with_r: bool,
    d: &View<'_>,
    out: &mut [f64],
    keep: Option<(&mut [f64], &mut [f64])>,
) {
    let nn = splat(n);
    let mut keep = keep;
    let m = out.len();
    // UNROLL vectors per iteration: one `d^n` is a long dependency chain (the logarithm's
    // division and two polynomials), and independent chains in one block let the core overlap
    // them. Each lane's operations are the same, so are the bits.
    let unrolled_end = m / (8 * UNROLL) * (8 * UNROLL);
    for i in (0..unrolled_end).step_by(8 * UNROLL) {
        let dd: [__m512d; UNROLL] =
            std::array::from_fn(|k| products(c, with_r, d, i + 8 * k, 0xFF).1);
        let fl: [(__m512d, __m512d); UNROLL] = std::array::from_fn(|k| pow_clamped(dd[k], nn));
        for (k, &fl) in fl.iter().enumerate() {
            add_and_keep(out, &mut keep, i + 8 * k, 0xFF, fl);
        }
    }
    for (i, mask) in lanes(m - unrolled_end).map(|(i, mask)| (i + unrolled_end, mask)) {
        let dd = products(c, with_r, d, i, mask).1;
        add_and_keep(out, &mut keep, i, mask, pow_clamped(dd, nn));
    }
}

/// Adds `f` to lanes `at..at + 8` of `out` (selected by `mask`) and, with `keep`, stores `f`
/// and `l` there.
#[inline]
#[target_feature(enable = "avx512f")]
fn add_and_keep(
    out: &mut [f64],
    keep: &mut Option<(&mut [f64], &mut [f64])>,
    at: usize,
    mask: __mmask8,
    (f, l): (__m512d, __m512d),
) {
    let o = load(out, at, mask);
    store(out, at, mask, _mm512_add_pd(o, f));
    if let Some((kf, kl)) = keep.as_mut() {
        store(kf, at, mask, f);
        store(kl, at, mask, l);
    }
}

/// Value and Jacobian columns of one lobe in a single pass over the data.
///
/// Adds `max(0, d)^n` to `out`; for each `Some` column `k` writes
/// `g (rows[k][0] P + rows[k][1] Q + rows[k][2] R + rows[k][3] S)` with `g = n d^n / d`,
/// except column 3 (the exponent), which gets `d^n ln d * n_scale`. Returns false when a
/// value or derivative is not finite. With `cached = Some((f, l))` (this lobe's `d^n` and
/// `ln d` from [`lobe_values`] at the same point and samples) the logarithm and exponential are
/// not recomputed; `d` is recomputed with the same operations, so the results are the same
/// bits.
///
/// # Safety
/// The CPU must support AVX-512F; `d`, every column (and `f`, `l`) must hold at least
/// `out.len()` entries.
#[target_feature(enable = "avx512f")]
#[allow(clippy::too_many_arguments)]
pub(crate) unsafe fn lobe_jacobian(
    c: &[f64; 4],
    n: f64,
    with_r: bool,
    d: &View<'_>,
    out: &mut [f64],
    cols: &mut [Option<&mut [f64]>; 5],
    rows: &[[f64; 4]; 5],
    n_scale: f64,
    cached: Option<(&[f64], &[f64])>,
) -> bool {
    let nn = splat(n);
    // g = n d^n / d without a spurious overflow of n d^n (see `g_factors`).
    let (ga, gb) = g_factors(n);
    let k = JacConsts {
        n_is_zero: n == 0.0,
        ga: splat(ga),
        gb: splat(gb),
        n_scale: splat(n_scale),
        has_n: cols[3].is_some(),
    };
    let power = |dd: __m512d, at: usize, mask: __mmask8| match cached {
        Some((cf, cl)) => (load(cf, at, mask), load(cl, at, mask)),
        None => pow_clamped(dd, nn),
    };
    let m = out.len();
    let mut bad: __mmask8 = 0;
    // UNROLL vectors per iteration, as in `lobe_values`: independent `d^n` chains in one
    // block. The same operations per lane, so the same bits.
    let unrolled_end = m / (8 * UNROLL) * (8 * UNROLL);
    for i in (0..unrolled_end).step_by(8 * UNROLL) {
        let pd: [([__m512d; 4], __m512d); UNROLL] =
            std::array::from_fn(|j| products(c, with_r, d, i + 8 * j, 0xFF));
        let fl: [(__m512d, __m512d); UNROLL] =
            std::array::from_fn(|j| power(pd[j].1, i + 8 * j, 0xFF));
        for j in 0..UNROLL {
            let lanes = Lanes {
                at: i + 8 * j,
                mask: 0xFF,
            };
            bad |= jacobian_lanes(lanes, pd[j], fl[j], &k, out, cols, rows);
        }
    }
    for (at, mask) in lanes(m - unrolled_end).map(|(i, mask)| (i + unrolled_end, mask)) {
        let pd = products(c, with_r, d, at, mask);
        let fl = power(pd.1, at, mask);
        bad |= jacobian_lanes(Lanes { at, mask }, pd, fl, &k, out, cols, rows);
    }
    bad == 0
}

/// What [`jacobian_lanes`] needs of the lobe: whether `n = 0`, the factors of `g` (see
/// `g_factors`), `d(n)/d(coordinate)` and whether the exponent's column is free.
struct JacConsts {
    n_is_zero: bool,
    ga: __m512d,
    gb: __m512d,
    n_scale: __m512d,
    has_n: bool,
}

/// Lanes `at..at + 8` selected by `mask`.
#[derive(Clone, Copy)]
struct Lanes {
    at: usize,
    mask: __mmask8,
}

/// The direction products `[P, Q, R, S]` and the argument `d` of one lobe for lanes
/// `i..i+8` (masked lanes read as 0).
#[inline]
#[target_feature(enable = "avx512f")]
fn products(
    c: &[f64; 4],
    with_r: bool,
    d: &View<'_>,
    i: usize,
    mask: __mmask8,
) -> ([__m512d; 4], __m512d) {
    let ux = load(d.ux, i, mask);
    let uy = load(d.uy, i, mask);
    let uz = load(d.uz, i, mask);
    let vx = load(d.vx, i, mask);
    let vy = load(d.vy, i, mask);
    let vz = load(d.vz, i, mask);
    let p = _mm512_mul_pd(ux, vx);
    let q = _mm512_mul_pd(uy, vy);
    let r = _mm512_fmadd_pd(ux, vy, _mm512_mul_pd(uy, vx));
    let s = _mm512_mul_pd(uz, vz);
    let mut dd = _mm512_mul_pd(splat(c[3]), s);
    dd = _mm512_fmadd_pd(splat(c[1]), q, dd);
    dd = _mm512_fmadd_pd(splat(c[0]), p, dd);
    if with_r {
        dd = _mm512_fmadd_pd(splat(c[2]), r, dd);
    }
    ([p, q, r, s], dd)
}

/// Adds `f = d^n` to `out` and writes the lobe's columns for one set of lanes (see
/// [`lobe_jacobian`]); returns the selected lanes whose `g` (or, with the exponent free, `h`)
/// is not finite.
#[inline]
#[target_feature(enable = "avx512f")]
fn jacobian_lanes(
    lanes: Lanes,
    (pqrs, dd): ([__m512d; 4], __m512d),
    (f, l): (__m512d, __m512d),
    k: &JacConsts,
    out: &mut [f64],
    cols: &mut [Option<&mut [f64]>; 5],
    rows: &[[f64; 4]; 5],
) -> __mmask8 {
    let Lanes { at, mask } = lanes;
    let zero = _mm512_setzero_pd();
    let inf = splat(f64::INFINITY);
    let [p, q, r, s] = pqrs;
    let o = load(out, at, mask);
    store(out, at, mask, _mm512_add_pd(o, f));
    let pos = _mm512_cmp_pd_mask::<_CMP_GT_OQ>(dd, zero);
    let den = _mm512_mask_blend_pd(pos, splat(1.0), dd);
    // n = 0 must give 0 even when d^n / d overflows.
    let g = if k.n_is_zero {
        zero
    } else {
        _mm512_mul_pd(_mm512_div_pd(_mm512_mul_pd(f, k.ga), den), k.gb)
    };
    let h = _mm512_mul_pd(_mm512_mul_pd(f, l), k.n_scale);
    // |v| < inf is false for inf and NaN.
    // h only matters (and is only checked, as in the generic loops) when n is free.
    let ok_h = if k.has_n {
        _mm512_cmp_pd_mask::<_CMP_LT_OQ>(_mm512_abs_pd(h), inf)
    } else {
        0xFF
    };
    let ok = _mm512_cmp_pd_mask::<_CMP_LT_OQ>(_mm512_abs_pd(g), inf) & ok_h;
    for (slot, col) in cols.iter_mut().enumerate() {
        let Some(col) = col else { continue };
        let v = if slot == 3 {
            h
        } else {
            let w = &rows[slot];
            let mut t = _mm512_mul_pd(splat(w[3]), s);
            t = _mm512_fmadd_pd(splat(w[0]), p, t);
            t = _mm512_fmadd_pd(splat(w[1]), q, t);
            t = _mm512_fmadd_pd(splat(w[2]), r, t);
            _mm512_mul_pd(g, t)
        };
        store(col, at, mask, v);
    }
    mask & !ok
}
