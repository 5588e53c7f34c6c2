//! The generic residual and Jacobian loops of the Lafortune kernels (each compiled once per
//! kernel by the callers): the per-lobe stages of `lobe`, the columns of `columns`, and the
//! hand-written AVX-512 lobe kernels where the AVX-512 copy runs.

use super::columns::{column, four_columns, lobe_columns};
use super::lobe::{lobe_full, lobe_values};
use crate::evaluate::all_finite;
use crate::fastmath::MulAdd;
use crate::lafortune::coef::{AVX512, BLOCK, Coef, Col, JacWork, lobe_powers, lobe_powers_mut};
use crate::lafortune::samples::View;

#[inline(always)]
pub(crate) fn residuals_impl<A: MulAdd, const K: u8>(
    coefs: &[Coef],
    kd: f64,
    data: &View<'_>,
    r: &mut [f64],
    mut keep: Option<&mut [f64]>,
) -> bool {
    let m = r.len();
    for (ri, &y) in r.iter_mut().zip(&data.value[..m]) {
        *ri = kd - y;
    }
    for (lobe, c) in coefs.iter().enumerate() {
        let keep = keep.as_deref_mut().map(|p| lobe_powers_mut(p, m, lobe));
        if K == AVX512 {
            // SAFETY: K == AVX512 is only instantiated inside AVX-512F functions; the kept
            // columns have m entries.
            #[cfg(target_arch = "x86_64")]
            unsafe {
                crate::lafortune::avx512::lobe_values(
                    &[c.ap, c.aq, c.ar, c.cz],
                    c.n,
                    !c.no_r,
                    data,
                    r,
                    keep,
                )
            };
        } else if c.no_r {
            lobe_values::<A, false>(c, data, r, keep);
        } else {
            lobe_values::<A, true>(c, data, r, keep);
        }
    }
    all_finite(r)
}

#[inline(always)]
pub(crate) fn jacobian_impl<A: MulAdd, const K: u8>(
    w: &JacWork<'_>,
    r: &mut [f64],
    jac: &mut [f64],
    g: &mut [f64],
    h: &mut [f64],
) -> bool {
    let m = r.len();
    let data = w.data;
    for (ri, &y) in r.iter_mut().zip(&data.value[..m]) {
        *ri = w.kd - y;
    }
    if m == 0 {
        return true;
    }
    let mut ok = true;
    for (j, col) in jac.chunks_exact_mut(m).enumerate() {
        if let Col::Kd = w.cols[j] {
            col.fill(1.0);
        }
    }
    for (l, c) in w.coefs.iter().enumerate() {
        let (mut cols, rows) = lobe_columns(jac, m, w.cols, l, c);
        let n_scale = c.n_coord.dv_dx(c.n);
        #[cfg(target_arch = "x86_64")]
        if K == AVX512 {
            // One pass per lobe: value and all its columns, the data loaded once.
            let coef = [c.ap, c.aq, c.ar, c.cz];
            // SAFETY: K == AVX512 is only instantiated inside AVX-512F functions; every
            // column has m entries.
            ok &= unsafe {
                crate::lafortune::avx512::lobe_jacobian(
                    &coef,
                    c.n,
                    !c.no_r,
                    &data,
                    r,
                    &mut cols,
                    &rows,
                    n_scale,
                    w.powers.map(|p| lobe_powers(p, m, l)),
                )
            };
            continue;
        }
        let powers = w.powers.map(|p| lobe_powers(p, m, l));
        for lo in (0..m).step_by(BLOCK) {
            let hi = (lo + BLOCK).min(m);
            let (gb, hb) = (&mut g[..hi - lo], &mut h[..hi - lo]);
            let cached = powers.map(|(f, lg)| (&f[lo..hi], &lg[lo..hi]));
            if c.no_r {
                lobe_full::<A, false>(c, &data, lo, &mut r[lo..hi], gb, hb, cached);
            } else {
                lobe_full::<A, true>(c, &data, lo, &mut r[lo..hi], gb, hb, cached);
            }
            ok &= all_finite(gb);
            let [c0, c1, c2, _, c4] = &mut cols;
            if let (Some(c0), Some(c1), Some(c2), Some(c4)) = (c0, c1, c2, c4) {
                let cbs = [
                    &mut c0[lo..hi],
                    &mut c1[lo..hi],
                    &mut c2[lo..hi],
                    &mut c4[lo..hi],
                ];
                four_columns::<A>(&data, lo, gb, cbs, [rows[0], rows[1], rows[2], rows[4]]);
            } else {
                for k in [0, 1, 2, 4] {
                    if let Some(col) = &mut cols[k] {
                        column::<A>(&data, lo, gb, &mut col[lo..hi], rows[k]);
                    }
                }
            }
            if let Some(col) = &mut cols[3] {
                let cb = &mut col[lo..hi];
                for (o, &hv) in cb.iter_mut().zip(hb.iter()) {
                    *o = hv * n_scale;
                }
                ok &= all_finite(cb);
            }
        }
    }
    ok && all_finite(r)
}
