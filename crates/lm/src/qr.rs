//! Householder QR factorisations of the (scaled) Jacobian.
//!
//! Public so that the differential tests against faer and the benchmarks (`benches/qr.rs`) can
//! call them; the solver is their only user in this crate.
//!
//! * [`householder_qr`] reduces the whole `rows x cols` matrix in place, one reflector at a
//!   time. Each reflector sweeps the whole trailing matrix, so a 10000 x 7 Jacobian (560 KB, more
//!   than this machine's L2) streams from memory about `cols` times.
//! * [`tall_qr`] reads the matrix once, in blocks of [`TALL_QR_BLOCK`] rows that stay in L1, and
//!   folds each block into a `cols x cols` triangle with reflectors of the stacked matrix
//!   `[R; B]` (LAPACK's `tpqrt` structure, the sequential form of TSQR). The column scaling
//!   `J D^-1`, the dead-column zeroing and `Q^T r` are fused into the same pass, so no `m x p`
//!   copy of `J` and no `m`-vector copy of `r` is written.
//!
//! Both give `R` with diagonal entries of either sign and `c` = the first `cols` entries of
//! `Q^T rhs`; `R^T R = A^T A` and `R^T c = A^T rhs` up to round-off.

use crate::linalg::{dot, norm};

/// Rows per block of [`tall_qr`]: 128 rows of up to 31 columns (plus the right-hand side) are
/// about 32 KB, L1-sized (not tuned further).
pub const TALL_QR_BLOCK: usize = 128;

/// Leading dimension of the block, padded so that no two columns are a multiple of 4 KiB apart
/// (a precaution against 4K aliasing of loads and stores; no difference was measurable at
/// 10000 x 7 on this machine).
const LD: usize = TALL_QR_BLOCK + 4;

/// The solver uses [`tall_qr`] from this many rows on and [`householder_qr`] below. Above the
/// largest NIST StRD problem (250 rows), so the golden tests' round-off is unchanged.
pub const TALL_QR_MIN_ROWS: usize = 256;

/// Below this norm or above its inverse the column is rescaled before squaring (a column
/// of 1e-160 gave inf and NaN in `R` before).
const SAFE_MIN_NORM: f64 = 1e-140;
const SAFE_MAX_NORM: f64 = 1e140;

/// In-place Householder QR of the column-major `rows x cols` matrix `a` (leading dimension
/// `rows`), applying the same reflections to `rhs` (length `rows`). On return the upper triangle
/// of `a` holds `R` (diagonal entries may be negative), everything below it is zero, and `rhs`
/// holds `Q^T rhs`. Working on `J` itself instead of `J^T J` keeps the condition number from
/// being squared, which the ill-conditioned NIST problems (Lanczos, Bennett5) need.
pub fn householder_qr(a: &mut [f64], rows: usize, cols: usize, rhs: &mut [f64]) {
    for k in 0..rows.min(cols) {
        let (head, tail) = a.split_at_mut((k + 1) * rows);
        let v = &mut head[k * rows + k..(k + 1) * rows];
        let mut alpha0 = norm(v);
        // Far from 1 the squares under- or overflow: rescale the column first. The reflector
        // `I - beta v v^T` does not depend on the scale of v, only R's diagonal entry does
        // (restored below).
        let mut scale = 1.0;
        if !(alpha0 > SAFE_MIN_NORM && alpha0 < SAFE_MAX_NORM) {
            let amax = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            if amax == 0.0 || !amax.is_finite() {
                continue;
            }
            scale = amax;
            for x in v.iter_mut() {
                *x /= amax;
            }
            alpha0 = norm(v);
        }
        if alpha0 == 0.0 {
            continue;
        }
        let alpha = if v[0] > 0.0 { -alpha0 } else { alpha0 };
        v[0] -= alpha;
        let vtv = dot(v, v);
        if vtv == 0.0 {
            v[0] += alpha;
            for x in v.iter_mut() {
                *x *= scale;
            }
            continue;
        }
        let beta = 2.0 / vtv;
        for j in 0..cols - k - 1 {
            let col = &mut tail[j * rows + k..(j + 1) * rows];
            let w = beta * dot(v, col);
            for (c, &vi) in col.iter_mut().zip(v.iter()) {
                *c -= w * vi;
            }
        }
        let rr = &mut rhs[k..rows];
        let w = beta * dot(v, rr);
        for (c, &vi) in rr.iter_mut().zip(v.iter()) {
            *c -= w * vi;
        }
        // Store R's diagonal; the reflector below it is no longer needed.
        v[0] = alpha * scale;
        for vi in v[1..].iter_mut() {
            *vi = 0.0;
        }
    }
}

/// Length of the scratch slice [`tall_qr`] needs for `cols` columns.
pub fn tall_qr_scratch_len(cols: usize) -> usize {
    LD * (cols + 1)
}

/// QR of the column-scaled tall matrix `A S` (`a` column-major `rows x cols`, `S =
/// diag(col_scale)`) without modifying `a`: writes `R` (`cols x cols`, column-major, zero below
/// the diagonal) into `r` and the first `cols` entries of `Q^T rhs` into `c`.
///
/// A column whose `col_scale` is 0 is treated as exactly zero (whatever `a` holds there), so
/// its diagonal entry of `R` is exactly 0, as with [`householder_qr`] on a zeroed column.
/// Intended for `rows >= cols`; with fewer rows `R` is still a valid triangle (`R^T R = S A^T A
/// S`) but its trailing diagonal is round-off rather than exact zeros. `scratch` must hold
/// [`tall_qr_scratch_len`]`(cols)` values. Allocates nothing.
#[allow(clippy::too_many_arguments)]
pub fn tall_qr(
    a: &[f64],
    rows: usize,
    cols: usize,
    col_scale: &[f64],
    rhs: &[f64],
    r: &mut [f64],
    c: &mut [f64],
    scratch: &mut [f64],
) {
    let m = TallQr {
        a: &a[..rows * cols],
        rows,
        cols,
        col_scale: &col_scale[..cols],
        rhs: &rhs[..rows],
    };
    let (r, c) = (&mut r[..cols * cols], &mut c[..cols]);
    let scratch = &mut scratch[..tall_qr_scratch_len(cols)];
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked just above).
        unsafe { m.run_avx2(r, c, scratch) };
        return;
    }
    m.run(r, c, scratch);
}

/// The input of [`tall_qr`].
struct TallQr<'a> {
    a: &'a [f64],
    rows: usize,
    cols: usize,
    col_scale: &'a [f64],
    rhs: &'a [f64],
}

impl TallQr<'_> {
    /// The same code compiled for 256-bit vectors: 257 against 281 us at 10000 x 7 for the
    /// baseline SSE2 build (`examples/qr_timing.rs`, two runs, so only roughly). No fused
    /// multiply-add (Rust never contracts `a * b + c`), so the results are bit-identical to
    /// [`TallQr::run`]'s (a unit test checks it) and do not depend on the machine.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn run_avx2(&self, r: &mut [f64], c: &mut [f64], scratch: &mut [f64]) {
        self.run(r, c, scratch);
    }

    /// Block by block: load (scaled), fold into `[R | c]`.
    #[inline(always)]
    fn run(&self, r: &mut [f64], c: &mut [f64], scratch: &mut [f64]) {
        r.fill(0.0);
        c.fill(0.0);
        let mut start = 0;
        while start < self.rows {
            let nb = TALL_QR_BLOCK.min(self.rows - start);
            self.load_block(start, nb, scratch);
            fold_block(scratch, nb, self.cols, r, c);
            start += nb;
        }
    }

    /// Copies rows `start..start + nb` of `A S` and of `rhs` into the block (leading dimension
    /// [`TALL_QR_BLOCK`], the right-hand side as column `cols`).
    #[inline(always)]
    fn load_block(&self, start: usize, nb: usize, block: &mut [f64]) {
        let (rows, cols) = (self.rows, self.cols);
        for j in 0..cols {
            let dst = &mut block[j * LD..j * LD + nb];
            let s = self.col_scale[j];
            if s == 0.0 {
                dst.fill(0.0);
            } else {
                let src = &self.a[j * rows + start..j * rows + start + nb];
                for (d, &x) in dst.iter_mut().zip(src) {
                    *d = x * s;
                }
            }
        }
        block[cols * LD..cols * LD + nb].copy_from_slice(&self.rhs[start..start + nb]);
    }
}

/// Folds an `nb`-row block `B` (with its right-hand side column) into `[R | c]`: Householder QR
/// of `[R; B]`, where the reflector of column `k` touches only row `k` of `R` and the block.
#[inline(always)]
fn fold_block(block: &mut [f64], nb: usize, cols: usize, r: &mut [f64], c: &mut [f64]) {
    for k in 0..cols {
        let (head, tail) = block.split_at_mut((k + 1) * LD);
        let bk = &mut head[k * LD..k * LD + nb];
        let Some((v0, beta, diag)) = block_reflector(r[k * cols + k], bk) else {
            continue;
        };
        r[k * cols + k] = diag;
        let refl = Reflector { v0, beta, bk };
        // Columns k+1..cols of the block (the last one is the right-hand side), four at a time
        // so that the update loop loads `bk` once per four columns.
        let mut j = k + 1;
        for group in tail[..(cols - k) * LD].chunks_mut(4 * LD) {
            let g = group.len() / LD;
            let mut tops = [0.0; 4];
            for (t, jj) in tops.iter_mut().zip(j..j + g) {
                *t = if jj < cols { r[jj * cols + k] } else { c[k] };
            }
            match g {
                4 => refl.apply::<4>(group, nb, &mut tops),
                3 => refl.apply::<3>(group, nb, &mut tops),
                2 => refl.apply::<2>(group, nb, &mut tops),
                _ => refl.apply::<1>(group, nb, &mut tops),
            }
            for (t, jj) in tops.iter().zip(j..j + g) {
                if jj < cols {
                    r[jj * cols + k] = *t;
                } else {
                    c[k] = *t;
                }
            }
            j += g;
        }
    }
}

/// The reflector `I - beta v v^T`, `v = [v0; bk]`, of one column of a block.
struct Reflector<'a> {
    v0: f64,
    beta: f64,
    bk: &'a [f64],
}

impl Reflector<'_> {
    /// Applies the reflector to `G` columns `[top_g; group[g]]` (leading dimension [`LD`],
    /// `nb` rows used), reading `bk` once for all of them.
    #[inline(always)]
    fn apply<const G: usize>(&self, group: &mut [f64], nb: usize, tops: &mut [f64; 4]) {
        let bk = &self.bk[..nb];
        let mut chunks = group.chunks_mut(LD);
        let cols: [&mut [f64]; G] = std::array::from_fn(|_| match chunks.next() {
            Some(col) => &mut col[..nb],
            None => unreachable!("the group has G columns"),
        });
        let dots = multi_dot(bk, &cols);
        let mut w = [0.0; G];
        for g in 0..G {
            w[g] = self.beta * (self.v0 * tops[g] + dots[g]);
            tops[g] -= w[g] * self.v0;
        }
        for (i, &vi) in bk.iter().enumerate() {
            for g in 0..G {
                cols[g][i] -= w[g] * vi;
            }
        }
    }
}

/// `[v . cols[g]]` with four accumulators per column (all slices of equal length), summed in
/// the order of [`dot`].
#[inline(always)]
fn multi_dot<const G: usize>(v: &[f64], cols: &[&mut [f64]; G]) -> [f64; G] {
    let n = v.len();
    let body = n - n % 4;
    let mut out = [0.0; G];
    for (g, o) in out.iter_mut().enumerate() {
        let col = &cols[g][..n];
        let mut acc = [0.0f64; 4];
        for (x, y) in v[..body].chunks_exact(4).zip(col[..body].chunks_exact(4)) {
            for l in 0..4 {
                acc[l] += x[l] * y[l];
            }
        }
        let mut tail = 0.0;
        for (x, y) in v[body..].iter().zip(&col[body..]) {
            tail += x * y;
        }
        *o = (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail;
    }
    out
}

/// The reflector `I - beta v v^T` with `v = [v0; bk]` that maps `[rkk; bk]` to `[diag; 0]`,
/// as `(v0, beta, diag)`; `None` when `bk` is zero (nothing to eliminate) or `v` not finite.
/// `bk` may be rescaled in place (the reflector does not depend on the scale of `v`).
#[inline(always)]
fn block_reflector(rkk: f64, bk: &mut [f64]) -> Option<(f64, f64, f64)> {
    let sigma = dot(bk, bk);
    let alpha0 = (rkk * rkk + sigma).sqrt();
    if sigma > 0.0 && alpha0 > SAFE_MIN_NORM && alpha0 < SAFE_MAX_NORM {
        let alpha = if rkk > 0.0 { -alpha0 } else { alpha0 };
        let v0 = rkk - alpha;
        return Some((v0, 2.0 / (v0 * v0 + sigma), alpha));
    }
    // Zero, or squares out of range: rescale v by its max-abs entry (as householder_qr does).
    let bmax = bk.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let amax = bmax.max(rkk.abs());
    if bmax == 0.0 || !amax.is_finite() {
        return None;
    }
    for x in bk.iter_mut() {
        *x /= amax;
    }
    let rs = rkk / amax;
    let sigma = dot(bk, bk);
    let alpha = (rs * rs + sigma).sqrt();
    let alpha = if rs > 0.0 { -alpha } else { alpha };
    let v0 = rs - alpha;
    Some((v0, 2.0 / (v0 * v0 + sigma), alpha * amax))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The AVX2 build of the block loop must not change a bit (no FMA, same summation order), so
    /// results do not depend on the machine.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn avx2_and_portable_paths_agree_bitwise() {
        if !std::arch::is_x86_feature_detected!("avx2") {
            return;
        }
        let (rows, cols) = (1000 + 37, 9);
        let a: Vec<f64> = (0..rows * cols)
            .map(|k| ((k * 7919) % 1013) as f64 / 97.0 - 5.0)
            .collect();
        let rhs: Vec<f64> = (0..rows).map(|i| (i as f64 * 0.37).sin()).collect();
        let scale: Vec<f64> = (0..cols)
            .map(|j| if j == 3 { 0.0 } else { 1.0 / (1.0 + j as f64) })
            .collect();
        let m = TallQr {
            a: &a,
            rows,
            cols,
            col_scale: &scale,
            rhs: &rhs,
        };
        let mut out = [
            (vec![0.0; cols * cols], vec![0.0; cols]),
            (vec![0.0; cols * cols], vec![0.0; cols]),
        ];
        let mut scratch = vec![0.0; tall_qr_scratch_len(cols)];
        m.run(&mut out[0].0, &mut out[0].1, &mut scratch);
        // SAFETY: AVX2 was detected above.
        unsafe { m.run_avx2(&mut out[1].0, &mut out[1].1, &mut scratch) };
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&out[0].0), bits(&out[1].0));
        assert_eq!(bits(&out[0].1), bits(&out[1].1));
        assert_eq!(out[0].0[3 * cols + 3], 0.0);
        assert!(out[0].0.iter().all(|v| v.is_finite()));
    }
}
