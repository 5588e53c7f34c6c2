//! Small dense linear algebra, hand-written for p up to ~40 (why: docs/solver.md, "Linear algebra").
//!
//! Matrices are column-major `n x n` slices; only what the solver needs.

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2;
#[cfg(target_arch = "x86_64")]
pub(crate) mod avx512;
pub(crate) mod dispatch;

#[cfg(target_arch = "x86_64")]
use brdf_simd::Kernel;

/// Dot product with four accumulators so the compiler can vectorise the long (m-row) sums.
#[inline]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; 4];
    let mut ca = a.chunks_exact(4);
    let mut cb = b.chunks_exact(4);
    for (x, y) in (&mut ca).zip(&mut cb) {
        acc[0] += x[0] * y[0];
        acc[1] += x[1] * y[1];
        acc[2] += x[2] * y[2];
        acc[3] += x[3] * y[3];
    }
    let mut tail = 0.0;
    for (x, y) in ca.remainder().iter().zip(cb.remainder()) {
        tail += x * y;
    }
    (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail
}

/// The survey of each new Jacobian: for every column `j` of the column-major `m x p` `jac`,
/// `sq[j] = col . col`, `jr[j] = col . r` and `amax[j] = max |col_i|`, in one pass over `jac`.
/// Each sum equals [`dot`]'s result bit for bit (see [`column_survey`]).
///
/// With the solver's kernel ([`dispatch::kernel`]) `avx2` the pass runs with intrinsics
/// ([`avx2::column_survey`]), four columns at
/// a time (at 10000 x 7, 14.8 us one column at a time, 10.4 two, 8.7-9.3 four, in one run),
/// and with `avx512` eight rows per instruction ([`avx512::column_survey`], the same bits).
/// The baseline SSE2 build split the four lanes over shuffled half registers, and this pass
/// took 20% of an RPLS run (`perf`), twice the Jacobian kernel.
#[allow(clippy::too_many_arguments)]
pub(crate) fn survey_columns(
    jac: &[f64],
    r: &[f64],
    m: usize,
    p: usize,
    sq: &mut [f64],
    jr: &mut [f64],
    amax: &mut [f64],
) {
    let (jac, r) = (&jac[..m * p], &r[..m]);
    let mut out = |j: usize, s: (f64, f64, f64)| (sq[j], jr[j], amax[j]) = s;
    #[cfg(target_arch = "x86_64")]
    match dispatch::kernel() {
        // SAFETY: the solver's kernel is one the CPU has, and the AVX-512 kernel's features
        // (AVX-512F, AVX2, FMA) and the AVX2 kernel's (AVX2, FMA) include the builds'.
        Kernel::Avx512 => return unsafe { survey_columns_avx512(jac, r, m, p, &mut out) },
        // SAFETY: as above.
        Kernel::Avx2 => return unsafe { survey_columns_avx2(jac, r, m, p, &mut out) },
        _ => {}
    }
    for j in 0..p {
        out(j, column_survey(&jac[j * m..(j + 1) * m], r));
    }
}

/// The AVX2 and AVX-512 builds of [`survey_columns`] and [`jt_vec`], four columns per pass.
macro_rules! column_passes {
    ($survey:ident, $jt_vec:ident, $simd:ident, $features:literal) => {
        #[doc = concat!("[`survey_columns`] with the intrinsics of [`", stringify!($simd), "`].")]
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $features)]
        fn $survey(
            jac: &[f64],
            r: &[f64],
            m: usize,
            p: usize,
            out: &mut impl FnMut(usize, (f64, f64, f64)),
        ) {
            let col = |j: usize| &jac[j * m..(j + 1) * m];
            for (j, g) in column_groups(p) {
                let results: &[(f64, f64, f64)] = match g {
                    4 => &$simd::column_survey([col(j), col(j + 1), col(j + 2), col(j + 3)], r),
                    3 => &$simd::column_survey([col(j), col(j + 1), col(j + 2)], r),
                    2 => &$simd::column_survey([col(j), col(j + 1)], r),
                    _ => &$simd::column_survey([col(j)], r),
                };
                for (k, &s) in results.iter().enumerate() {
                    out(j + k, s);
                }
            }
        }

        #[doc = concat!("[`jt_vec`] with the intrinsics of [`", stringify!($simd), "`].")]
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $features)]
        fn $jt_vec(jac: &[f64], v: &[f64], m: usize, p: usize, out: &mut [f64]) {
            let v = &v[..m];
            let col = |j: usize| &jac[j * m..(j + 1) * m];
            for (j, g) in column_groups(p) {
                let d: &[f64] = match g {
                    4 => &$simd::multi_dot(v, [col(j), col(j + 1), col(j + 2), col(j + 3)]),
                    3 => &$simd::multi_dot(v, [col(j), col(j + 1), col(j + 2)]),
                    2 => &$simd::multi_dot(v, [col(j), col(j + 1)]),
                    _ => &$simd::multi_dot(v, [col(j)]),
                };
                out[j..j + g].copy_from_slice(d);
            }
        }
    };
}

column_passes!(survey_columns_avx2, jt_vec_avx2, avx2, "avx2");
column_passes!(survey_columns_avx512, jt_vec_avx512, avx512, "avx512f,avx2");

/// Consecutive groups `(first column, count)` of at most four columns covering `0..p`: the
/// AVX2 loops take four columns per pass, so that their sums form independent chains.
#[cfg(target_arch = "x86_64")]
fn column_groups(p: usize) -> impl Iterator<Item = (usize, usize)> {
    (0..p).step_by(4).map(move |j| (j, (p - j).min(4)))
}

/// `(col . col, col . r, max |col_i|)` in one pass, the dot products accumulated exactly as
/// [`dot`] above does (four lanes over chunks of four, then the tail), so each equals `dot`'s
/// result; a change to one must be made to both and to [`avx2`] (the test below compares the
/// bits).
#[inline(always)]
pub(crate) fn column_survey(col: &[f64], r: &[f64]) -> (f64, f64, f64) {
    let n = col.len().min(r.len());
    let (col, r) = (&col[..n], &r[..n]);
    let (mut sq, mut jr, mut lane_max) = ([0.0f64; 4], [0.0f64; 4], [0.0f64; 4]);
    let mut cc = col.chunks_exact(4);
    let mut cr = r.chunks_exact(4);
    for (x, y) in (&mut cc).zip(&mut cr) {
        for k in 0..4 {
            sq[k] += x[k] * x[k];
            jr[k] += x[k] * y[k];
            // A plain comparison (not f64::max, whose NaN rule blocks a vector max) in four
            // independent lanes; a NaN entry is caught by the sum of squares anyway.
            let a = x[k].abs();
            lane_max[k] = if a > lane_max[k] { a } else { lane_max[k] };
        }
    }
    let (mut sq_tail, mut jr_tail) = (0.0, 0.0);
    let mut amax = lane_max[0]
        .max(lane_max[1])
        .max(lane_max[2].max(lane_max[3]));
    for (x, y) in cc.remainder().iter().zip(cr.remainder()) {
        sq_tail += x * x;
        jr_tail += x * y;
        amax = amax.max(x.abs());
    }
    (
        (sq[0] + sq[2]) + (sq[1] + sq[3]) + sq_tail,
        (jr[0] + jr[2]) + (jr[1] + jr[3]) + jr_tail,
        amax,
    )
}

/// Euclidean norm (no overflow protection is needed: inputs are scaled steps and gradients).
#[inline]
pub(crate) fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// Given upper-triangular `t` (`n x n`) and `u`, computes upper-triangular `tl` with
/// `tl^T tl = t^T t + lam I` and the correspondingly rotated `ul` (Givens rotations eliminating
/// the rows `sqrt(lam) e_i`, MINPACK's qrsolv). `w` is scratch of length
/// [`shifted_scratch_len`]`(n)`.
///
/// Rotation `(i, k)` eliminates entry `k` of row `i` against `tl`'s row `k`; it needs only
/// rotations `(i - 1, k)` and `(i, k - 1)`. MINPACK does the rotations row after row, which
/// makes one long chain of square roots and divisions (a profile of AED put a third of this
/// function's time on waiting for them). Here they run in anti-diagonal sweeps `i + k = s`,
/// whose rotations are independent of one another and so overlap, while each entry still
/// receives its updates in the row-after-row order: the result is the same to the bit.
#[allow(clippy::too_many_arguments)]
pub(crate) fn shifted_triangular(
    t: &[f64],
    u: &[f64],
    n: usize,
    lam: f64,
    tl: &mut [f64],
    ul: &mut [f64],
    w: &mut [f64],
    scale_tiny: bool,
) {
    tl[..n * n].copy_from_slice(&t[..n * n]);
    ul[..n].copy_from_slice(&u[..n]);
    let stride = n + 1;
    let rows = &mut w[..n * stride];
    rows.fill(0.0);
    let sl = lam.sqrt();
    for i in 0..n {
        rows[i * stride + i] = sl;
    }
    for s in 0..(2 * n).saturating_sub(1) {
        for i in s.saturating_sub(n - 1)..=s / 2 {
            let row = &mut rows[i * stride..(i + 1) * stride];
            eliminate_entry(tl, ul, n, s - i, row, scale_tiny);
        }
    }
}

/// Scratch length of [`shifted_triangular`]: each shifted row and its right-hand side.
pub(crate) fn shifted_scratch_len(n: usize) -> usize {
    n * (n + 1)
}

/// Sums of squares below which a Givens rotation's `r` is computed by `hypot`: below it the
/// squares may have lost bits to gradual underflow, or vanished.
const HYPOT_BELOW: f64 = f64::MIN_POSITIVE * (1u64 << 53) as f64;

/// One Givens rotation of [`shifted_triangular`]: zeroes `row[k]` against `tl`'s row `k`;
/// `row[n]` carries the row's right-hand side.
#[inline(always)]
fn eliminate_entry(
    tl: &mut [f64],
    ul: &mut [f64],
    n: usize,
    k: usize,
    row: &mut [f64],
    scale_tiny: bool,
) {
    let wk = row[k];
    if wk == 0.0 {
        return;
    }
    let tkk = tl[k * n + k];
    // Plain sqrt instead of hypot (5% of a small solve in a profile): the entries are
    // D-scaled, far from overflow. Not from underflow: a dead lobe's entries (1e-175) square
    // to 0, which makes r = 0 and the rotation NaN. With `scale_tiny`
    // (`Safeguards::scale_tiny_rotations`) such pairs take hypot, which scales them.
    let r2 = tkk * tkk + wk * wk;
    let r = if r2 >= HYPOT_BELOW || !scale_tiny {
        r2.sqrt()
    } else {
        tkk.hypot(wk)
    };
    let (cs, sn) = (tkk / r, wk / r);
    for j in k..n {
        let a = tl[j * n + k];
        let b = row[j];
        tl[j * n + k] = cs * a + sn * b;
        row[j] = -sn * a + cs * b;
    }
    let a = ul[k];
    let b = row[n];
    ul[k] = cs * a + sn * b;
    row[n] = -sn * a + cs * b;
}

/// Solves `T z = b` in place for upper-triangular `t` (`n x n`, column-major).
pub(crate) fn upper_solve(t: &[f64], n: usize, b: &mut [f64]) {
    for j in (0..n).rev() {
        let v = b[j] / t[j * n + j];
        b[j] = v;
        for i in 0..j {
            b[i] -= t[j * n + i] * v;
        }
    }
}

/// Solves `T^T q = b` in place for upper-triangular `t` (forward substitution).
pub(crate) fn upper_transpose_solve(t: &[f64], n: usize, b: &mut [f64]) {
    for j in 0..n {
        let col = &t[j * n..(j + 1) * n];
        let mut s = b[j];
        for i in 0..j {
            s -= col[i] * b[i];
        }
        b[j] = s / col[j];
    }
}

/// `out = J^T v`, each entry exactly [`dot`]'s result; with the solver's kernel `avx2` or
/// `avx512`, intrinsics, four columns per pass over `v` ([`avx2::multi_dot`],
/// [`avx512::multi_dot`], the same bits).
pub(crate) fn jt_vec(jac: &[f64], v: &[f64], m: usize, p: usize, out: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    match dispatch::kernel() {
        // SAFETY: as in `survey_columns`.
        Kernel::Avx512 => return unsafe { jt_vec_avx512(jac, v, m, p, out) },
        // SAFETY: as above.
        Kernel::Avx2 => return unsafe { jt_vec_avx2(jac, v, m, p, out) },
        _ => {}
    }
    for j in 0..p {
        out[j] = dot(&jac[j * m..(j + 1) * m], v);
    }
}

/// `out = A v` for a symmetric (full storage) `n x n` matrix.
pub(crate) fn sym_mat_vec(a: &[f64], v: &[f64], n: usize, out: &mut [f64]) {
    for o in out[..n].iter_mut() {
        *o = 0.0;
    }
    for (j, &vj) in v[..n].iter().enumerate() {
        if vj != 0.0 {
            let col = &a[j * n..(j + 1) * n];
            for (o, &c) in out[..n].iter_mut().zip(col) {
                *o += c * vj;
            }
        }
    }
}

/// In-place Cholesky `A + shift I = L L^T` of the symmetric `n x n` matrix `a` into `l`
/// (lower triangle, column-major). Fails (returns false) when a pivot is not above
/// `rel_tol * max(diag(A + shift I))`: the matrix is then treated as not positive definite,
/// which is how rank deficiency of `J` shows up.
pub(crate) fn cholesky_shifted(
    a: &[f64],
    shift: f64,
    n: usize,
    rel_tol: f64,
    l: &mut [f64],
) -> bool {
    let mut dmax = 0.0f64;
    for i in 0..n {
        dmax = dmax.max(a[i * n + i] + shift);
    }
    if !(dmax > 0.0) || !dmax.is_finite() {
        return n == 0;
    }
    let tol = rel_tol * dmax;
    for j in 0..n {
        // Column j of L: l_ij = (a_ij - sum_k<j l_ik l_jk) / l_jj.
        let mut s = a[j * n + j] + shift;
        for k in 0..j {
            let v = l[k * n + j];
            s -= v * v;
        }
        if !(s > tol) {
            return false;
        }
        let d = s.sqrt();
        l[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[j * n + i];
            for k in 0..j {
                s -= l[k * n + i] * l[k * n + j];
            }
            l[j * n + i] = s / d;
        }
    }
    true
}

/// Solves `L y = b` in place (forward substitution).
pub(crate) fn forward_solve(l: &[f64], n: usize, b: &mut [f64]) {
    for j in 0..n {
        let v = b[j] / l[j * n + j];
        b[j] = v;
        for i in j + 1..n {
            b[i] -= l[j * n + i] * v;
        }
    }
}

/// Solves `L^T y = b` in place (back substitution).
pub(crate) fn backward_solve(l: &[f64], n: usize, b: &mut [f64]) {
    for j in (0..n).rev() {
        let col = &l[j * n..(j + 1) * n];
        let mut s = b[j];
        for i in j + 1..n {
            s -= col[i] * b[i];
        }
        b[j] = s / col[j];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type Passes = (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>);

    /// `(sq, jr, amax, J^T v)` from the dispatched functions and from each intrinsics build
    /// this CPU has.
    fn column_passes_of_every_build(
        jac: &[f64],
        v: &[f64],
        m: usize,
        p: usize,
    ) -> Vec<(&'static str, Passes)> {
        let empty = || (vec![0.0; p], vec![0.0; p], vec![0.0; p], vec![0.0; p]);
        let mut out = vec![];
        let mut d = empty();
        survey_columns(jac, v, m, p, &mut d.0, &mut d.1, &mut d.2);
        jt_vec(jac, v, m, p, &mut d.3);
        out.push(("dispatched", d));
        #[cfg(target_arch = "x86_64")]
        {
            type Survey = unsafe fn(&[f64], &[f64], usize, usize, &mut Passes);
            let avx2: Survey = |jac, v, m, p, o| unsafe {
                survey_columns_avx2(jac, v, m, p, &mut |j, s| (o.0[j], o.1[j], o.2[j]) = s);
                jt_vec_avx2(jac, v, m, p, &mut o.3);
            };
            let avx512: Survey = |jac, v, m, p, o| unsafe {
                survey_columns_avx512(jac, v, m, p, &mut |j, s| (o.0[j], o.1[j], o.2[j]) = s);
                jt_vec_avx512(jac, v, m, p, &mut o.3);
            };
            for (build, has, run) in [
                ("avx2", Kernel::Avx2.is_available(), avx2),
                ("avx512", Kernel::Avx512.is_available(), avx512),
            ] {
                if has {
                    let mut o = empty();
                    // SAFETY: the CPU has the build's features (checked in `has`).
                    unsafe { run(jac, v, m, p, &mut o) };
                    out.push((build, o));
                }
            }
        }
        out
    }

    /// The fused survey must give exactly the separate passes' numbers (the goldens depend on
    /// it), for every tail length, and flag a non-finite column through its sum of squares.
    #[test]
    fn column_survey_equals_the_separate_passes_bit_for_bit() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 10f64.powi((state % 7) as i32)
        };
        for n in [0, 1, 3, 4, 5, 25, 131] {
            let col: Vec<f64> = (0..n).map(|_| next()).collect();
            let r: Vec<f64> = (0..n).map(|_| next()).collect();
            let (sq, jr, amax) = column_survey(&col, &r);
            assert_eq!(sq.to_bits(), dot(&col, &col).to_bits(), "n = {n}");
            assert_eq!(sq.sqrt().to_bits(), norm(&col).to_bits(), "n = {n}");
            assert_eq!(jr.to_bits(), dot(&col, &r).to_bits(), "n = {n}");
            let expected = col.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            assert_eq!(amax.to_bits(), expected.to_bits(), "n = {n}");
        }
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let mut col = vec![1.0; 9];
            col[6] = bad;
            assert!(!column_survey(&col, &[0.5; 9]).0.is_finite(), "{bad}");
        }
        // survey_columns and jt_vec, dispatched and in each intrinsics build the CPU can run
        // (several columns per pass; eight-row steps followed or not by a four-row step and a
        // tail), against the portable column_survey and dot, column by column.
        for (m, p) in [(131, 3), (64, 4), (7, 6), (12, 5), (1001, 9), (1005, 2)] {
            let jac: Vec<f64> = (0..m * p).map(|_| next()).collect();
            let v: Vec<f64> = (0..m).map(|_| next()).collect();
            for (build, (sq, jr, amax, jtv)) in column_passes_of_every_build(&jac, &v, m, p) {
                for j in 0..p {
                    let col = &jac[j * m..(j + 1) * m];
                    let (esq, ejr, eamax) = column_survey(col, &v);
                    let got = [sq[j], jr[j], amax[j], jtv[j]].map(f64::to_bits);
                    let expected = [esq, ejr, eamax, dot(col, &v)].map(f64::to_bits);
                    assert_eq!(got, expected, "{build}: m = {m}, p = {p}, column {j}");
                }
            }
        }
        // Finite entries whose squares overflow: the sum is infinite, the entries are not.
        let (sq, _, amax) = column_survey(&[1e200, -3.0], &[1.0, 1.0]);
        assert!(sq.is_infinite() && amax == 1e200);
    }

    #[test]
    fn cholesky_solves_spd_system() {
        let a = [4.0, 2.0, 0.6, 2.0, 5.0, 1.0, 0.6, 1.0, 3.0];
        let mut l = [0.0; 9];
        assert!(cholesky_shifted(&a, 0.0, 3, 1e-14, &mut l));
        let mut b = [1.0, 2.0, 3.0];
        forward_solve(&l, 3, &mut b);
        backward_solve(&l, 3, &mut b);
        let mut ax = [0.0; 3];
        sym_mat_vec(&a, &b, 3, &mut ax);
        for (v, e) in ax.iter().zip([1.0, 2.0, 3.0]) {
            assert!((v - e).abs() < 1e-12);
        }
    }

    #[test]
    fn cholesky_rejects_singular_and_accepts_shift() {
        let a = [1.0, 1.0, 1.0, 1.0];
        let mut l = [0.0; 4];
        assert!(!cholesky_shifted(&a, 0.0, 2, 1e-14, &mut l));
        assert!(cholesky_shifted(&a, 1e-3, 2, 1e-14, &mut l));
    }

    /// MINPACK's qrsolv order: each shifted row rotated in to the end before the next.
    fn shifted_triangular_row_by_row(t: &[f64], u: &[f64], n: usize, lam: f64) -> Vec<f64> {
        let (mut tl, mut ul) = (t[..n * n].to_vec(), u[..n].to_vec());
        let mut w = vec![0.0; n];
        for i in 0..n {
            w.fill(0.0);
            w[i] = lam.sqrt();
            let mut wr = 0.0;
            for k in i..n {
                if w[k] == 0.0 {
                    continue;
                }
                let tkk = tl[k * n + k];
                let r = (tkk * tkk + w[k] * w[k]).sqrt();
                let (cs, sn) = (tkk / r, w[k] / r);
                for j in k..n {
                    let (a, b) = (tl[j * n + k], w[j]);
                    tl[j * n + k] = cs * a + sn * b;
                    w[j] = -sn * a + cs * b;
                }
                let a = ul[k];
                ul[k] = cs * a + sn * wr;
                wr = -sn * a + cs * wr;
            }
        }
        tl.extend_from_slice(&ul);
        tl
    }

    /// The anti-diagonal sweeps give the row-by-row result to the bit, including zero
    /// entries of `t` (skipped rotations), a zero shift and sizes 1 to 13.
    #[test]
    fn shifted_sweeps_equal_the_row_by_row_rotations_bit_for_bit() {
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for n in 1..=13 {
            for lam in [0.0, 1e-9, 0.37, 52.0] {
                let mut t = vec![0.0; n * n];
                for j in 0..n {
                    for i in 0..=j {
                        // Every fifth entry zero, diagonal included.
                        t[j * n + i] = if (i + 3 * j) % 5 == 0 { 0.0 } else { next() };
                    }
                }
                let u: Vec<f64> = (0..n).map(|_| next()).collect();
                let (mut tl, mut ul) = (vec![0.0; n * n], vec![0.0; n]);
                let mut w = vec![f64::NAN; shifted_scratch_len(n)];
                shifted_triangular(&t, &u, n, lam, &mut tl, &mut ul, &mut w, true);
                tl.extend_from_slice(&ul);
                let want = shifted_triangular_row_by_row(&t, &u, n, lam);
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&tl), bits(&want), "n {n} lam {lam}");
            }
        }
    }

    /// A dead lobe's tiny entries (1e-175: their squares underflow to 0) give `r = 0` in a
    /// plain rotation and NaN in the factor; with the scaling `tl^T tl = t^T t + lam I` holds
    /// there too.
    #[test]
    fn shifted_factor_of_tiny_columns_is_finite() {
        let n = 3;
        // Column-major upper triangle: a live column and two dead ones.
        let t = [1.0, 0.0, 0.0, 1e-175, 5e-176, 0.0, 2e-175, 1e-176, 3e-185];
        let u = [-3.9, 0.1, 0.09];
        for lam in [3.5, 1e-9, 1e-300] {
            let (mut tl, mut ul) = (vec![0.0; n * n], vec![0.0; n]);
            let mut w = vec![0.0; shifted_scratch_len(n)];
            shifted_triangular(&t, &u, n, lam, &mut tl, &mut ul, &mut w, true);
            assert!(
                tl.iter().chain(&ul).all(|v| v.is_finite()),
                "lam {lam}: {tl:?}"
            );
            for a in 0..n {
                for b in 0..n {
                    let col = |m: &[f64], j: usize| m[j * n..(j + 1) * n].to_vec();
                    let got = dot(&col(&tl, a), &col(&tl, b));
                    let want = dot(&col(&t, a), &col(&t, b)) + if a == b { lam } else { 0.0 };
                    let scale = want.abs().max(1e-300);
                    assert!(
                        (got - want).abs() <= 1e-14 * scale,
                        "lam {lam} [{a},{b}]: {got} {want}"
                    );
                }
            }
        }
        // Without the scaling (the searches' descents keep the plain rotation): NaN.
        let (mut tl, mut ul) = (vec![0.0; n * n], vec![0.0; n]);
        let mut w = vec![0.0; shifted_scratch_len(n)];
        shifted_triangular(&t, &u, n, 3.5, &mut tl, &mut ul, &mut w, false);
        assert!(tl.iter().any(|v| v.is_nan()), "plain rotations: {tl:?}");
    }

    #[test]
    fn dot_matches_naive() {
        let a: Vec<f64> = (0..11).map(|i| i as f64 * 0.5).collect();
        let b: Vec<f64> = (0..11).map(|i| 1.0 - i as f64).collect();
        let naive: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
        assert!((dot(&a, &b) - naive).abs() < 1e-12);
    }
}
