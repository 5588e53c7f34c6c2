//! The generic per-lobe loops of the AVX2 and portable kernels: values (and the kept powers)
//! in chunk-wise stages, and the values with the Jacobian's factors `g` and `h`.

use crate::fastmath::{
    MulAdd, all_exp_normal, ln_clamped, ln_clamped_normal, no_subnormal, pow_from_ln,
    pow_from_ln_normal,
};
use crate::lafortune::coef::Coef;
use crate::lafortune::samples::{View, g_factors};

/// Samples per pass of the generic lobe loops. Each loop over a chunk does one stage (the
/// direction products, the logarithm, the exponential): a whole `d^n` is a dependency chain
/// of about 150 cycles and 100 vector instructions, more than a small out-of-order window
/// (Zen 1's 192 micro-ops hold less than one 256-bit iteration) can overlap, while each stage
/// alone is short enough for several iterations to be in flight. The arithmetic is the same
/// as computing `d^n` sample by sample, so the results are bit-identical. On Zen 5 too an
/// AVX2 kernel written with intrinsics in one pass (as `super::avx512`) was slower than these
/// staged loops in every run (docs/performance.md).
pub(super) const CHUNK: usize = 64;

/// Adds lobe values to `out`; with `keep = Some((f, l))` also stores each sample's `d^n` in
/// `f` and `ln d` in `l` (both `out.len()` long) for a later Jacobian at the same point.
#[inline(always)]
pub(super) fn lobe_values<A: MulAdd, const R: bool>(
    c: &Coef,
    d: &View<'_>,
    out: &mut [f64],
    keep: Option<(&mut [f64], &mut [f64])>,
) {
    let m = out.len();
    let mut dd = [0.0f64; CHUNK];
    // Where `ln d` and `d^n` go when they are not kept.
    let (mut stack_l, mut stack_f) = ([0.0f64; CHUNK], [0.0f64; CHUNK]);
    let (mut kf, mut kl) = match keep {
        Some((f, l)) => (Some(f), Some(l)),
        None => (None, None),
    };
    for lo in (0..m).step_by(CHUNK) {
        let hi = (lo + CHUNK).min(m);
        let k = hi - lo;
        let pqrs = [
            &d.pxx[lo..hi],
            &d.pyy[lo..hi],
            &d.pxy[lo..hi],
            &d.pzz[lo..hi],
        ];
        let (dd, out) = (&mut dd[..k], &mut out[lo..hi]);
        direction_products::<A, R>(c, pqrs, dd);
        let ll = match kl.as_deref_mut() {
            Some(l) => &mut l[lo..hi],
            None => &mut stack_l[..k],
        };
        ln_stage::<A>(dd, ll);
        let ff = match kf.as_deref_mut() {
            Some(f) => &mut f[lo..hi],
            None => &mut stack_f[..k],
        };
        if all_exp_normal(c.n, ll) {
            add_powers::<A, true>(c.n, dd, ll, ff, out);
        } else {
            add_powers::<A, false>(c.n, dd, ll, ff, out);
        }
    }
}

/// `f = max(0, d)^n` from `l = ln d` and `out += f`, the exponential in its shorter form when
/// `NORMAL` (the caller checked [`all_exp_normal`]; the same bits).
#[inline(always)]
pub(super) fn add_powers<A: MulAdd, const NORMAL: bool>(
    n: f64,
    ds: &[f64],
    ls: &[f64],
    fs: &mut [f64],
    out: &mut [f64],
) {
    for (((o, f), &l), &x) in out.iter_mut().zip(fs).zip(ls).zip(ds) {
        *f = pow_from_ln_any::<A, NORMAL>(x, n, l);
        *o += *f;
    }
}

/// [`pow_from_ln_normal`] when `NORMAL`, else [`pow_from_ln`].
#[inline(always)]
pub(super) fn pow_from_ln_any<A: MulAdd, const NORMAL: bool>(d: f64, n: f64, l: f64) -> f64 {
    if NORMAL {
        pow_from_ln_normal::<A>(d, n, l)
    } else {
        pow_from_ln::<A>(d, n, l)
    }
}

/// `ls = ln_clamped(ds)`, through the shorter [`ln_clamped_normal`] when no `d` is subnormal
/// (the same bits).
#[inline(always)]
pub(super) fn ln_stage<A: MulAdd>(ds: &[f64], ls: &mut [f64]) {
    if no_subnormal(ds) {
        ln_loop::<A, true>(ds, ls);
    } else {
        ln_loop::<A, false>(ds, ls);
    }
}

#[inline(always)]
pub(super) fn ln_loop<A: MulAdd, const NORMAL: bool>(ds: &[f64], ls: &mut [f64]) {
    for (l, &x) in ls.iter_mut().zip(ds) {
        *l = if NORMAL {
            ln_clamped_normal::<A>(x)
        } else {
            ln_clamped::<A>(x)
        };
    }
}

/// `d = ap P + aq Q + cz S (+ ar R)` for each sample of the chunk's products `[P, Q, R, S]`.
#[inline(always)]
pub(super) fn direction_products<A: MulAdd, const R: bool>(
    c: &Coef,
    pqrs: [&[f64]; 4],
    dd: &mut [f64],
) {
    let k = dd.len();
    let [p, q, r, s] = pqrs;
    let (p, q, r, s) = (&p[..k], &q[..k], &r[..k], &s[..k]);
    let (ap, aq, ar, cz) = (c.ap, c.aq, c.ar, c.cz);
    for i in 0..k {
        let mut x = A::mad(ap, p[i], A::mad(aq, q[i], cz * s[i]));
        if R {
            x = A::mad(ar, r[i], x);
        }
        dd[i] = x;
    }
}

/// Adds lobe values to `out` and stores `g = n d^n / d` and `h = d^n ln d` (0 where `d <= 0`).
/// With `cached = Some((f, l))` (this block's `d^n` and `ln d` from [`lobe_values`] at the same
/// point) the logarithm and exponential are not recomputed; the results are the same bits.
#[inline(always)]
pub(super) fn lobe_full<A: MulAdd, const R: bool>(
    c: &Coef,
    d: &View<'_>,
    lo: usize,
    out: &mut [f64],
    g: &mut [f64],
    h: &mut [f64],
    cached: Option<(&[f64], &[f64])>,
) {
    let m = out.len();
    let hi = lo + m;
    let pqrs = [
        &d.pxx[lo..hi],
        &d.pyy[lo..hi],
        &d.pxy[lo..hi],
        &d.pzz[lo..hi],
    ];
    let (g, h) = (&mut g[..m], &mut h[..m]);
    let n = c.n;
    let (ga, gb) = g_factors(n);
    // Stages as in `lobe_values`, with `g` holding `d` and `h` holding `ln d` in between.
    direction_products::<A, R>(c, pqrs, g);
    let finish = |o: &mut f64, gi: &mut f64, hi: &mut f64, f: f64, l: f64| {
        let x = *gi;
        *o += f;
        // n = 0 must give 0 even when d^n / d overflows.
        let gv = f * ga / if x > 0.0 { x } else { 1.0 } * gb;
        *gi = if n == 0.0 { 0.0 } else { gv };
        *hi = f * l;
    };
    match cached {
        Some((cf, cl)) => {
            let (cf, cl) = (&cf[..m], &cl[..m]);
            for ((((o, gi), hi), &f), &l) in out
                .iter_mut()
                .zip(g.iter_mut())
                .zip(h.iter_mut())
                .zip(cf)
                .zip(cl)
            {
                finish(o, gi, hi, f, l);
            }
        }
        None => {
            ln_stage::<A>(g, h);
            if all_exp_normal(n, h) {
                finish_powers::<A, true>(n, out, g, h, finish);
            } else {
                finish_powers::<A, false>(n, out, g, h, finish);
            }
        }
    }
}

/// The last stage of [`lobe_full`]: `finish(out, g, h, d^n, ln d)` per sample, with `g`
/// holding `d` and `h` holding `ln d` on entry (the exponential's shorter form when `NORMAL`).
#[inline(always)]
pub(super) fn finish_powers<A: MulAdd, const NORMAL: bool>(
    n: f64,
    out: &mut [f64],
    g: &mut [f64],
    h: &mut [f64],
    finish: impl Fn(&mut f64, &mut f64, &mut f64, f64, f64),
) {
    for ((o, gi), hi) in out.iter_mut().zip(g.iter_mut()).zip(h.iter_mut()) {
        let (x, l) = (*gi, *hi);
        finish(o, gi, hi, pow_from_ln_any::<A, NORMAL>(x, n, l), l);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fastmath::{Fused, Plain};

    fn coef(n: f64) -> Coef {
        Coef {
            ap: 1.0,
            aq: 0.0,
            ar: 0.0,
            cz: 0.0,
            n,
            c2: 0.0,
            s2: 0.0,
            cs: 0.0,
            cx: 0.0,
            cy: 0.0,
            sin2: 0.0,
            cos2: 0.0,
            no_r: true,
            n_coord: crate::family::Coord::Identity,
        }
    }

    /// `d = P` for `coef`: three chunks of [`CHUNK`] samples, the first all ordinary (both
    /// fast paths), the second with a subnormal `d` (the general logarithm), the third with
    /// `n ln d` out of the fast exponential's range (the general exponential), plus a tail.
    fn directions() -> Vec<f64> {
        let mut p: Vec<f64> = (0..3 * CHUNK + 7)
            .map(|i| 0.05 + 0.9 * ((i * 37) % 101) as f64 / 101.0)
            .collect();
        p[3] = -0.25;
        p[5] = 0.0;
        p[CHUNK + 9] = 3e-310;
        p[2 * CHUNK + 4] = 1e-200;
        p
    }

    fn check<A: MulAdd>(n: f64) {
        let p = directions();
        let m = p.len();
        let zeros = vec![0.0; m];
        let view = View {
            ux: &zeros,
            uy: &zeros,
            uz: &zeros,
            vx: &zeros,
            vy: &zeros,
            vz: &zeros,
            value: &zeros,
            pxx: &p,
            pyy: &zeros,
            pxy: &zeros,
            pzz: &zeros,
        };
        let c = coef(n);
        let mut out = vec![0.0; m];
        lobe_values::<A, false>(&c, &view, &mut out, None);
        let mut ds = vec![0.0; m];
        direction_products::<A, false>(&c, [&p, &zeros, &zeros, &zeros], &mut ds);
        for (i, (&o, &d)) in out.iter().zip(&ds).enumerate() {
            let want = pow_from_ln::<A>(d, n, ln_clamped::<A>(d));
            assert_eq!(o.to_bits(), want.to_bits(), "sample {i}, d {d}, n {n}");
        }
    }

    /// The chunk-wise fast paths of the logarithm and the exponential give the bits of the
    /// general functions sample by sample, whichever chunks take them.
    #[test]
    fn lobe_values_equal_the_general_functions_in_every_chunk() {
        for n in [0.0, 1.0, 7.5, 350.0] {
            check::<Plain>(n);
            check::<Fused>(n);
        }
    }
}
