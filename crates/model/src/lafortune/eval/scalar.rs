//! The reference kernel: one sample at a time, std's libm `powf` and `ln`, no FMA, no
//! blocking. Mirrors the failure rules of the fast kernels: a value, `g = n d^n / d` (computed
//! as in [`g_factors`], so it fails only when `g` itself overflows) or
//! (when the exponent is free) `d^n ln d` that is not finite fails the evaluation.

use super::columns::lobe_columns;
use crate::lafortune::coef::{Coef, Col, JacWork};
use crate::lafortune::samples::{View, g_factors};

/// `(P, Q, R, S)` and `d` of lobe `c` at sample `i`.
#[inline]
fn products(c: &Coef, d: &View<'_>, i: usize) -> ([f64; 4], f64) {
    let p = d.ux[i] * d.vx[i];
    let q = d.uy[i] * d.vy[i];
    let r = d.ux[i] * d.vy[i] + d.uy[i] * d.vx[i];
    let s = d.uz[i] * d.vz[i];
    let mut dd = c.ap * p + c.aq * q + c.cz * s;
    if !c.no_r {
        dd += c.ar * r;
    }
    ([p, q, r, s], dd)
}

#[inline]
fn power(dd: f64, n: f64) -> f64 {
    if dd > 0.0 { dd.powf(n) } else { 0.0 }
}

pub(super) fn residuals(coefs: &[Coef], kd: f64, d: &View<'_>, r: &mut [f64]) -> bool {
    let mut ok = true;
    for (i, ri) in r.iter_mut().enumerate() {
        let mut f = kd;
        for c in coefs {
            f += power(products(c, d, i).1, c.n);
        }
        *ri = f - d.value[i];
        ok &= ri.is_finite();
    }
    ok
}

pub(super) fn jacobian(w: &JacWork<'_>, r: &mut [f64], jac: &mut [f64]) -> bool {
    let m = r.len();
    let d = w.data;
    for (ri, &y) in r.iter_mut().zip(d.value) {
        *ri = w.kd - y;
    }
    if m == 0 {
        return true;
    }
    for (j, col) in jac.chunks_exact_mut(m).enumerate() {
        if let Col::Kd = w.cols[j] {
            col.fill(1.0);
        }
    }
    let mut ok = true;
    for (l, c) in w.coefs.iter().enumerate() {
        let (mut cols, rows) = lobe_columns(jac, m, w.cols, l, c);
        let n_scale = c.n_coord.dv_dx(c.n);
        for i in 0..m {
            let (pqrs, dd) = products(c, &d, i);
            let f = power(dd, c.n);
            r[i] += f;
            let (g, h) = if dd > 0.0 {
                let (ga, gb) = g_factors(c.n);
                let g = if c.n == 0.0 { 0.0 } else { f * ga / dd * gb };
                (g, f * dd.ln())
            } else {
                (0.0, 0.0)
            };
            ok &= g.is_finite();
            for (k, col) in cols.iter_mut().enumerate() {
                let Some(col) = col else { continue };
                col[i] = if k == 3 {
                    let v = h * n_scale;
                    ok &= v.is_finite();
                    v
                } else {
                    let wk = &rows[k];
                    g * (wk[0] * pqrs[0] + wk[1] * pqrs[1] + wk[2] * pqrs[2] + wk[3] * pqrs[3])
                };
            }
        }
    }
    ok && r.iter().all(|v| v.is_finite())
}
