//! The direction columns of the generic Jacobian: `g` times a weighted sum of the products
//! `P, Q, R, S`, with the structural zero weights left out.

use crate::fastmath::MulAdd;
use crate::lafortune::coef::{Coef, Col, Field};
use crate::lafortune::samples::View;

/// `col_i = g_i (a P + b Q + c R + e S)` for samples `lo..lo + col.len()`, `w = [a, b, c, e]`.
/// Every direction column but Cz's has `e = 0` and Cz's is `[0, 0, 0, 1]`; those weights are
/// left out of the sums ([`Weights`]), which (the products being finite) changes nothing but
/// the sign of a zero entry and took 9 to 15% off the AVX2 and portable Jacobians
/// (docs/performance.md).
#[inline(always)]
pub(super) fn column<A: MulAdd>(d: &View<'_>, lo: usize, g: &[f64], col: &mut [f64], w: [f64; 4]) {
    match Weights::of(w) {
        Weights::Pqr(w) => column_with(d, lo, g, col, |p, q, r, _| pqr::<A>(&w, p, q, r)),
        Weights::S => column_with(d, lo, g, col, |_, _, _, s| s),
        Weights::All(w) => column_with(d, lo, g, col, |p, q, r, s| weighted::<A>(&w, p, q, r, s)),
    }
}

/// `col_i = g_i t(P_i, Q_i, R_i, S_i)` for samples `lo..lo + col.len()`.
#[inline(always)]
pub(super) fn column_with(
    d: &View<'_>,
    lo: usize,
    g: &[f64],
    col: &mut [f64],
    t: impl Fn(f64, f64, f64, f64) -> f64,
) {
    let m = col.len();
    let hi = lo + m;
    let (p, q) = (&d.pxx[lo..hi], &d.pyy[lo..hi]);
    let (r, s) = (&d.pxy[lo..hi], &d.pzz[lo..hi]);
    let g = &g[..m];
    for i in 0..m {
        col[i] = g[i] * t(p[i], q[i], r[i], s[i]);
    }
}

/// The weights of `P, Q, R, S` in a direction column, by which of them can be left out.
#[derive(Clone, Copy)]
pub(super) enum Weights {
    /// `[a, b, c, 0]` (Cx, Cy, Cxy and pan).
    Pqr([f64; 3]),
    /// `[0, 0, 0, 1]` (Cz).
    S,
    /// Any other weights.
    All([f64; 4]),
}

impl Weights {
    fn of(w: [f64; 4]) -> Self {
        if w == [0.0, 0.0, 0.0, 1.0] {
            Weights::S
        } else if w[3] == 0.0 {
            Weights::Pqr([w[0], w[1], w[2]])
        } else {
            Weights::All(w)
        }
    }
}

/// `a P + b Q + c R + e S` for `w = [a, b, c, e]`, in the order every column uses.
#[inline(always)]
pub(super) fn weighted<A: MulAdd>(w: &[f64; 4], p: f64, q: f64, r: f64, s: f64) -> f64 {
    A::mad(w[0], p, A::mad(w[1], q, A::mad(w[2], r, w[3] * s)))
}

/// [`weighted`] with `e = 0`: the same value, but for the sign of a zero result.
#[inline(always)]
pub(super) fn pqr<A: MulAdd>(w: &[f64; 3], p: f64, q: f64, r: f64) -> f64 {
    A::mad(w[0], p, A::mad(w[1], q, w[2] * r))
}

/// [`column`] for the four direction columns of a lobe with every direction parameter free
/// (slots 0, 1, 2 and 4: Cx, Cy, Cz and pan): one pass, the products and `g` loaded once for
/// all four, each entry computed as [`column`] computes it.
#[inline(always)]
pub(super) fn four_columns<A: MulAdd>(
    d: &View<'_>,
    lo: usize,
    g: &[f64],
    cols: [&mut [f64]; 4],
    w: [[f64; 4]; 4],
) {
    let m = g.len();
    let hi = lo + m;
    let (p, q) = (&d.pxx[lo..hi], &d.pyy[lo..hi]);
    let (r, s) = (&d.pxy[lo..hi], &d.pzz[lo..hi]);
    let [c0, c1, c2, c3] = cols;
    let (c0, c1, c2, c3) = (&mut c0[..m], &mut c1[..m], &mut c2[..m], &mut c3[..m]);
    if let [
        Weights::Pqr(w0),
        Weights::Pqr(w1),
        Weights::S,
        Weights::Pqr(w3),
    ] = w.map(Weights::of)
    {
        for i in 0..m {
            c0[i] = g[i] * pqr::<A>(&w0, p[i], q[i], r[i]);
            c1[i] = g[i] * pqr::<A>(&w1, p[i], q[i], r[i]);
            c2[i] = g[i] * s[i];
            c3[i] = g[i] * pqr::<A>(&w3, p[i], q[i], r[i]);
        }
        return;
    }
    let entry = |w: &[f64; 4], i: usize| g[i] * weighted::<A>(w, p[i], q[i], r[i], s[i]);
    for i in 0..m {
        c0[i] = entry(&w[0], i);
        c1[i] = entry(&w[1], i);
        c2[i] = entry(&w[2], i);
        c3[i] = entry(&w[3], i);
    }
}

/// The free columns of lobe `l` (slots: Cx or Cxy, Cy, Cz, n, pan) and the weights of
/// `P, Q, R, S` in `∂d/∂θ` for each.
#[allow(clippy::type_complexity)]
pub(super) fn lobe_columns<'j>(
    jac: &'j mut [f64],
    m: usize,
    cols: &[Col],
    l: usize,
    c: &Coef,
) -> ([Option<&'j mut [f64]>; 5], [[f64; 4]; 5]) {
    let mut out: [Option<&mut [f64]>; 5] = [None, None, None, None, None];
    let mut rows = [[0.0; 4]; 5];
    for (j, col) in jac.chunks_exact_mut(m).enumerate() {
        let Col::Lobe(lobe, field) = cols[j] else {
            continue;
        };
        if lobe != l {
            continue;
        }
        let (slot, row) = match field {
            Field::Cx => (0, [c.c2, c.s2, c.cs, 0.0]),
            Field::Cxy => (0, [1.0, 1.0, 0.0, 0.0]),
            Field::Cy => (1, [c.s2, c.c2, -c.cs, 0.0]),
            Field::Cz => (2, [0.0, 0.0, 0.0, 1.0]),
            Field::N => (3, [0.0; 4]),
            Field::Pan => {
                let k = std::f64::consts::PI / 180.0 * (c.cx - c.cy);
                (4, [-k * c.sin2, k * c.sin2, k * c.cos2, 0.0])
            }
            Field::Kd => continue,
        };
        out[slot] = Some(col);
        rows[slot] = row;
    }
    (out, rows)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fastmath::{Fused, Plain};
    use crate::lafortune::samples::view;
    use crate::samples::Samples;

    /// Directions from a small grid with many zero and negative products, and a `g` with
    /// zeros, so that the columns meet zero sums and zero factors of both signs.
    fn column_data() -> (Samples, Vec<f64>) {
        let axis = [-1.0, -0.6, 0.0, 0.6, 1.0];
        let mut data = crate::DataSet::new();
        for &a in &axis {
            for &b in &axis {
                for &c in &[0.0, 0.5, 1.0] {
                    data.push([a, b, c], [b, -a, 1.0 - c], 0.25);
                }
            }
        }
        let g = (0..data.len())
            .map(|i| {
                if i % 7 == 0 {
                    0.0
                } else {
                    0.5 - (i % 11) as f64 * 0.13
                }
            })
            .collect();
        (crate::lafortune::prepare(&data), g)
    }

    /// Every column of [`column`] and [`four_columns`] with the structural zero weights left
    /// out equals the full weighted sum (values compared with `==`: only the sign of a zero may
    /// differ), for the weights of Cx, Cy, Cz, pan, the isotropic Cxy and arbitrary ones.
    fn check_columns<A: MulAdd>() {
        let (samples, g) = column_data();
        let m = samples.len();
        let data = view(&samples, 0, m);
        let (c, s) = (0.3f64.cos(), 0.3f64.sin());
        let rows = [
            [c * c, s * s, c * s, 0.0],
            [s * s, c * c, -c * s, 0.0],
            [0.0, 0.0, 0.0, 1.0],
            [
                -0.4 * (0.6f64).sin(),
                0.4 * (0.6f64).sin(),
                0.4 * (0.6f64).cos(),
                0.0,
            ],
            [1.0, 1.0, 0.0, 0.0],
            [0.3, -0.2, 0.7, 0.4],
        ];
        let full = |w: &[f64; 4]| -> Vec<f64> {
            (0..m)
                .map(|i| {
                    g[i] * weighted::<A>(w, data.pxx[i], data.pyy[i], data.pxy[i], data.pzz[i])
                })
                .collect()
        };
        for w in &rows {
            let mut col = vec![f64::NAN; m];
            column::<A>(&data, 0, &g, &mut col, *w);
            assert_eq!(col, full(w), "weights {w:?}");
        }
        for w4 in [
            [rows[0], rows[1], rows[2], rows[3]],
            [rows[0], rows[5], rows[2], rows[3]],
        ] {
            let mut cols = vec![vec![f64::NAN; m]; 4];
            let [c0, c1, c2, c3] = &mut cols[..] else {
                unreachable!()
            };
            four_columns::<A>(&data, 0, &g, [c0, c1, c2, c3], w4);
            for (col, w) in cols.iter().zip(&w4) {
                assert_eq!(col, &full(w), "weights {w:?}");
            }
        }
    }

    #[test]
    fn columns_without_zero_weights_equal_the_full_sums() {
        check_columns::<Plain>();
        check_columns::<Fused>();
    }
}
