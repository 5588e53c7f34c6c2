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
//!   copy of `J` and no `m`-vector copy of `r` is written. Within a block, the pass that applies
//!   one column's reflector also accumulates the next column's dot products (and the load of
//!   the block those of the first step), so each step reads the block once instead of three
//!   times; on x86-64 the long loops run with AVX2 intrinsics or, with AVX-512F, eight rows per
//!   instruction (one source for both widths, private module `wide`), as the solver's kernel
//!   says ([`crate::set_kernel`]). All of these
//!   leave every result bit for bit as before (unit tests), and together they more than halved
//!   the QR's time at 10000 x 7 (the README has the one-run comparisons).
//!
//! Both give `R` with diagonal entries of either sign and `c` = the first `cols` entries of
//! `Q^T rhs`; `R^T R = A^T A` and `R^T c = A^T rhs` up to round-off.

use crate::linalg::{dot, norm};
#[cfg(target_arch = "x86_64")]
use brdf_simd::Kernel;

/// Rows per block of [`tall_qr`]: 256 rows of up to 15 columns (plus the right-hand side) are
/// about 32 KB, L1-sized. Each block costs a chain of scalar square roots and divisions per
/// column besides its vector work, so longer blocks are faster: 256 rows against 128 took the QR
/// at 10000 x 7 from 65 / 86 / 77 to 57 / 57 / 72 us and at 10000 x 13 from 205 / 157 / 209 to
/// 142 / 140 / 195 us (`examples/qr_timing.rs --reps 200`, builds alternated three times,
/// 2026-12-02, AMD Zen 5). The block size sets the order of the fold, so it decides the last
/// bits of `R`.
pub const TALL_QR_BLOCK: usize = 256;

/// Leading dimension of the block, padded so that no two columns are a multiple of 4 KiB apart
/// (a precaution against 4K aliasing of loads and stores; no difference was measurable at
/// 10000 x 7 on this machine).
const LD: usize = TALL_QR_BLOCK + 4;

/// The solver uses [`tall_qr`] from this many rows on and [`householder_qr`] below: just
/// above the largest Moré-Garbow-Hillstrom problem (Osborne 2, 65 rows). The tall QR for
/// every size changed that table (64 instead of 65 unbounded runs with a success code, 74
/// instead of 75 boxed runs at a KKT point); from 66 rows it is unchanged, NIST StRD stays at
/// 52/54, and AED's subsamples of 69 rows and more take the faster QR (docs/performance.md).
pub const TALL_QR_MIN_ROWS: usize = 66;

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
    // The block with its right-hand side column, then one step's dot products.
    LD * (cols + 1) + cols + 1
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
    match crate::linalg::dispatch::kernel() {
        // SAFETY: the solver's kernel is one the CPU has, and AVX-512 (AVX-512F, AVX2, FMA)
        // and AVX2 (AVX2, FMA) include the features of the builds.
        Kernel::Avx512 => return unsafe { m.run_avx512(r, c, scratch) },
        // SAFETY: as above.
        Kernel::Avx2 => return unsafe { m.run_avx2(r, c, scratch) },
        _ => {}
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
    /// The same algorithm with AVX2 intrinsics for the long loops ([`wide::Avx2`]). Lane `k`
    /// of each register is the portable code's accumulator `k` and there is no fused
    /// multiply-add (Rust never contracts `a * b + c`), so the results are bit-identical to
    /// [`TallQr::run`]'s (a unit test checks it) and do not depend on the machine.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn run_avx2(&self, r: &mut [f64], c: &mut [f64], scratch: &mut [f64]) {
        self.run_with::<wide::Avx2>(r, c, scratch);
    }

    /// [`TallQr::run_avx2`] with eight rows per instruction ([`wide::Avx512`]); the dot
    /// products still add four lanes in the portable order, so the bits are again
    /// [`TallQr::run`]'s.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx2")]
    fn run_avx512(&self, r: &mut [f64], c: &mut [f64], scratch: &mut [f64]) {
        self.run_with::<wide::Avx512>(r, c, scratch);
    }

    /// The portable build.
    fn run(&self, r: &mut [f64], c: &mut [f64], scratch: &mut [f64]) {
        self.run_with::<Portable>(r, c, scratch);
    }

    /// Block by block: load (scaled), fold into `[R | c]`.
    #[inline(always)]
    fn run_with<V: BlockOps>(&self, r: &mut [f64], c: &mut [f64], scratch: &mut [f64]) {
        r.fill(0.0);
        c.fill(0.0);
        let (block, dots) = scratch.split_at_mut(LD * (self.cols + 1));
        let mut start = 0;
        while start < self.rows {
            let nb = TALL_QR_BLOCK.min(self.rows - start);
            self.load_block_with_dots::<V>(start, nb, block, dots);
            fold_block::<V>(block, nb, self.cols, r, c, dots);
            start += nb;
        }
    }

    /// Copies rows `start..start + nb` of `A S` and of `rhs` into the block (leading dimension
    /// [`LD`], the right-hand side as column `cols`) and, in the same pass, writes the first
    /// step's dot products (column 0 of the block with every column, the right-hand side last)
    /// into `dots[..=cols]`.
    #[inline(always)]
    fn load_block_with_dots<V: BlockOps>(
        &self,
        start: usize,
        nb: usize,
        block: &mut [f64],
        dots: &mut [f64],
    ) {
        let (rows, cols) = (self.rows, self.cols);
        let source = |j: usize| -> (&[f64], f64) {
            if j < cols {
                let col = &self.a[j * rows + start..j * rows + start + nb];
                (col, self.col_scale[j])
            } else {
                // The right-hand side, copied: times 1 is exact for every finite value, and
                // the solver factors only finite residuals.
                (&self.rhs[start..start + nb], 1.0)
            }
        };
        let (first, rest) = block[..(cols + 1) * LD].split_at_mut(LD * 4.min(cols + 1));
        load_group::<V>(first, 0, nb, None, &source, dots);
        let first = &first[..nb];
        for (gi, group) in rest.chunks_mut(4 * LD).enumerate() {
            load_group::<V>(group, 4 + 4 * gi, nb, Some(first), &source, dots);
        }
    }

    /// The copy of [`TallQr::load_block_with_dots`] alone, as it was before the passes were
    /// fused: the reference of the unit tests.
    #[cfg(test)]
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

/// Loads the group of block columns `first..` (each `source(j)` = column and scale; a scale of
/// 0 gives exact zeros, as a dead column needs) and writes into `dots[j]` the loaded column 0
/// (`next`, or the group's first) dotted with each loaded column.
#[inline(always)]
fn load_group<'s, V: BlockOps>(
    group: &mut [f64],
    first: usize,
    nb: usize,
    next: Option<&[f64]>,
    source: &impl Fn(usize) -> (&'s [f64], f64),
    dots: &mut [f64],
) {
    let g = group.len().div_ceil(LD);
    match g {
        4 => load_columns::<V, 4>(group, first, nb, next, source, dots),
        3 => load_columns::<V, 3>(group, first, nb, next, source, dots),
        2 => load_columns::<V, 2>(group, first, nb, next, source, dots),
        _ => load_columns::<V, 1>(group, first, nb, next, source, dots),
    }
}

/// [`load_group`] for a group of `G` columns. The dot products go straight into
/// `dots[first..first + G]`, a copy of constant length (a slice of run-time length compiled to
/// a call to `memcpy`, 1.2% of an RPLS profile).
#[inline(always)]
fn load_columns<'s, V: BlockOps, const G: usize>(
    group: &mut [f64],
    first: usize,
    nb: usize,
    next: Option<&[f64]>,
    source: &impl Fn(usize) -> (&'s [f64], f64),
    dots: &mut [f64],
) {
    let mut chunks = group.chunks_mut(LD);
    let mut dst: [&mut [f64]; G] = std::array::from_fn(|_| match chunks.next() {
        Some(col) => &mut col[..nb],
        None => unreachable!("the group has G columns"),
    });
    let src: [(&[f64], f64); G] = std::array::from_fn(|g| source(first + g));
    dots[first..first + G].copy_from_slice(&V::load_scaled_dot(src, &mut dst, next));
}

/// Folds an `nb`-row block `B` (with its right-hand side column) into `[R | c]`: Householder QR
/// of `[R; B]`, where the reflector of column `k` touches only row `k` of `R` and the block.
///
/// Each step needs the dot products of the block's column `k` with itself and with every later
/// column, taken after the previous steps' updates. The pass that applies step `k`'s reflector
/// also accumulates those of step `k + 1` from the freshly updated rows, so each step reads the
/// block once instead of three times (squares, dot products, update); the sums are the same bit
/// for bit. On entry `dots` (length `cols + 1`) holds the first step's dot products, which
/// the load of the block computed ([`TallQr::load_block_with_dots`]).
#[inline(always)]
fn fold_block<V: BlockOps>(
    block: &mut [f64],
    nb: usize,
    cols: usize,
    r: &mut [f64],
    c: &mut [f64],
    dots: &mut [f64],
) {
    // Whether `dots[k..=cols]` hold step k's dot products (column k with columns k..=cols).
    let mut fresh = true;
    for k in 0..cols {
        let (head, tail) = block.split_at_mut((k + 1) * LD);
        let bk = &mut head[k * LD..k * LD + nb];
        if !fresh {
            dots_with_column::<V>(bk, tail, nb, cols - k, &mut dots[k..=cols]);
        }
        fresh = false;
        let Some(refl) = block_reflector::<V>(r[k * cols + k], dots[k], bk) else {
            continue;
        };
        r[k * cols + k] = refl.diag;
        if refl.rescaled {
            // The reflector's vector changed scale: the dot products must be taken again.
            dots_with_column::<V>(bk, tail, nb, cols - k, &mut dots[k..=cols]);
        }
        let bk = &*bk;
        // Columns k+1..=cols of the block (the last one is the right-hand side), four at a
        // time so that the update loop loads `bk` once per four columns. The first group starts
        // with column k + 1, whose updated rows give the next step's dot products.
        let tail = &mut tail[..(cols - k) * LD];
        let (first, rest) = tail.split_at_mut(LD * 4.min(cols - k));
        let has_next = k + 1 < cols;
        let pos = Position {
            k,
            first: k + 1,
            cols,
        };
        refl.apply_group::<V>(bk, pos, first, nb, None, has_next, r, c, dots);
        let next = &first[..nb];
        for (gi, group) in rest.chunks_mut(4 * LD).enumerate() {
            let pos = Position {
                k,
                first: k + 5 + 4 * gi,
                cols,
            };
            refl.apply_group::<V>(bk, pos, group, nb, Some(next), has_next, r, c, dots);
        }
        fresh = has_next;
    }
}

/// `dots[i] = bk . column i of [bk | tail]` for `i < count + 1` (`tail` holds `count` columns
/// at the leading dimension [`LD`]), each summed as [`dot`] sums.
#[inline(always)]
fn dots_with_column<V: BlockOps>(
    bk: &[f64],
    tail: &[f64],
    nb: usize,
    count: usize,
    dots: &mut [f64],
) {
    dots[0] = V::multi_dot(bk, [bk])[0];
    for (i, group) in tail[..count * LD].chunks(4 * LD).enumerate() {
        let col = |g: usize| &group[g * LD..g * LD + nb];
        let out = &mut dots[1 + 4 * i..];
        match group.len().div_ceil(LD) {
            4 => out[..4].copy_from_slice(&V::multi_dot(bk, [col(0), col(1), col(2), col(3)])),
            3 => out[..3].copy_from_slice(&V::multi_dot(bk, [col(0), col(1), col(2)])),
            2 => out[..2].copy_from_slice(&V::multi_dot(bk, [col(0), col(1)])),
            _ => out[0] = V::multi_dot(bk, [col(0)])[0],
        }
    }
}

/// Where a group of columns sits: step `k` of a block of `cols` columns (plus the right-hand
/// side, column `cols`), the group starting at column `first`.
#[derive(Clone, Copy)]
struct Position {
    k: usize,
    first: usize,
    cols: usize,
}

/// The reflector `I - beta v v^T`, `v = [v0; bk]`, of one column of a block, mapping
/// `[rkk; bk]` to `[diag; 0]`.
struct Reflector {
    v0: f64,
    beta: f64,
    diag: f64,
    /// Whether `bk` was divided by its largest entry (squares out of range).
    rescaled: bool,
}

impl Reflector {
    /// Applies the reflector (vector `bk`, block column `pos.k`) to the group of block columns
    /// `pos.first..` (leading dimension [`LD`], `nb` rows used) and to their entries in row `k`
    /// of `[R | c]`. With `has_next`, also writes into `dots[j]` the next step's dot products
    /// (updated column `k + 1` with updated column `j`): `next` is that column, or `None` when
    /// it is the group's first.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn apply_group<V: BlockOps>(
        &self,
        bk: &[f64],
        pos: Position,
        group: &mut [f64],
        nb: usize,
        next: Option<&[f64]>,
        has_next: bool,
        r: &mut [f64],
        c: &mut [f64],
        dots: &mut [f64],
    ) {
        let g = group.len().div_ceil(LD);
        let Position { k, first, cols } = pos;
        let mut w = [0.0; 4];
        for (gi, wg) in w[..g].iter_mut().enumerate() {
            let j = first + gi;
            let top = if j < cols {
                &mut r[j * cols + k]
            } else {
                &mut c[k]
            };
            *wg = self.beta * (self.v0 * *top + dots[j]);
            *top -= *wg * self.v0;
        }
        let dots = has_next.then_some(&mut dots[first..]);
        match g {
            4 => update::<V, 4>(bk, group, nb, &w, next, dots),
            3 => update::<V, 3>(bk, group, nb, &w, next, dots),
            2 => update::<V, 2>(bk, group, nb, &w, next, dots),
            _ => update::<V, 1>(bk, group, nb, &w, next, dots),
        }
    }
}

/// The `G` columns of `group` minus `w[g] bk`, and (with `dots`) the dot products of the
/// updated `next` (or of the updated first column) with each updated column, written to
/// `dots[..G]` (a copy of constant length, see [`load_columns`]).
#[inline(always)]
fn update<V: BlockOps, const G: usize>(
    bk: &[f64],
    group: &mut [f64],
    nb: usize,
    w: &[f64; 4],
    next: Option<&[f64]>,
    dots: Option<&mut [f64]>,
) {
    let mut chunks = group.chunks_mut(LD);
    let mut cols: [&mut [f64]; G] = std::array::from_fn(|_| match chunks.next() {
        Some(col) => &mut col[..nb],
        None => unreachable!("the group has G columns"),
    });
    let w: [f64; G] = std::array::from_fn(|g| w[g]);
    match dots {
        Some(dots) => dots[..G].copy_from_slice(&V::sub_scaled_dot(bk, &w, &mut cols, next)),
        None => V::sub_scaled(bk, &w, &mut cols),
    }
}

/// The long loops of the block fold, in two builds that give the same bits: [`Portable`] and,
/// on x86-64, [`wide::Avx2`] and [`wide::Avx512`]. Every dot product is summed as [`dot`] sums: four lanes over
/// chunks of four (lane `l` adds `x[4i + l] * y[4i + l]` in order), `(l0 + l2) + (l1 + l3)`,
/// then the tail rows in order.
trait BlockOps {
    /// `[v . cols[g]]` (all slices of `v`'s length).
    fn multi_dot<const G: usize>(v: &[f64], cols: [&[f64]; G]) -> [f64; G];
    /// `cols[g] -= w[g] v` for every `g`, reading `v` once.
    fn sub_scaled<const G: usize>(v: &[f64], w: &[f64; G], cols: &mut [&mut [f64]; G]);
    /// [`BlockOps::sub_scaled`], then `[u . cols[g]]` of the updated columns, where `u` is
    /// `next` or else the updated `cols[0]`; in one pass, with the sums of a separate
    /// [`BlockOps::multi_dot`] after the update.
    fn sub_scaled_dot<const G: usize>(
        v: &[f64],
        w: &[f64; G],
        cols: &mut [&mut [f64]; G],
        next: Option<&[f64]>,
    ) -> [f64; G];
    /// `dst[g] = src[g].0 * src[g].1` (exact zeros where the scale is 0), then `[u . dst[g]]`
    /// with `u` = `next` or else the new `dst[0]`; in one pass, with the sums of a separate
    /// [`BlockOps::multi_dot`] after the copy.
    fn load_scaled_dot<const G: usize>(
        src: [(&[f64], f64); G],
        dst: &mut [&mut [f64]; G],
        next: Option<&[f64]>,
    ) -> [f64; G];
}

/// Plain Rust, vectorised (or not) by the compiler.
struct Portable;

impl BlockOps for Portable {
    #[inline(always)]
    fn multi_dot<const G: usize>(v: &[f64], cols: [&[f64]; G]) -> [f64; G] {
        std::array::from_fn(|g| dot(v, cols[g]))
    }

    #[inline(always)]
    fn sub_scaled<const G: usize>(v: &[f64], w: &[f64; G], cols: &mut [&mut [f64]; G]) {
        for (i, &vi) in v.iter().enumerate() {
            for g in 0..G {
                cols[g][i] -= w[g] * vi;
            }
        }
    }

    #[inline(always)]
    fn sub_scaled_dot<const G: usize>(
        v: &[f64],
        w: &[f64; G],
        cols: &mut [&mut [f64]; G],
        next: Option<&[f64]>,
    ) -> [f64; G] {
        let n = v.len();
        let body = n - n % 4;
        let mut acc = [[0.0f64; 4]; G];
        for i in (0..body).step_by(4) {
            for g in 0..G {
                for l in 0..4 {
                    cols[g][i + l] -= w[g] * v[i + l];
                }
            }
            for l in 0..4 {
                let u = next.map_or(cols[0][i + l], |x| x[i + l]);
                for g in 0..G {
                    acc[g][l] += u * cols[g][i + l];
                }
            }
        }
        let mut tail = [0.0; G];
        for i in body..n {
            for g in 0..G {
                cols[g][i] -= w[g] * v[i];
            }
            let u = next.map_or(cols[0][i], |x| x[i]);
            for g in 0..G {
                tail[g] += u * cols[g][i];
            }
        }
        std::array::from_fn(|g| (acc[g][0] + acc[g][2]) + (acc[g][1] + acc[g][3]) + tail[g])
    }

    #[inline(always)]
    fn load_scaled_dot<const G: usize>(
        src: [(&[f64], f64); G],
        dst: &mut [&mut [f64]; G],
        next: Option<&[f64]>,
    ) -> [f64; G] {
        let n = dst[0].len();
        for g in 0..G {
            let (col, s) = src[g];
            for (d, &x) in dst[g].iter_mut().zip(&col[..n]) {
                *d = if s == 0.0 { 0.0 } else { x * s };
            }
        }
        let u = next.unwrap_or(&*dst[0]);
        std::array::from_fn(|g| dot(u, &*dst[g]))
    }
}

/// The reflector that maps `[rkk; bk]` to `[diag; 0]`, given `sigma = bk . bk`; `None` when
/// `bk` is zero (nothing to eliminate) or `v` not finite. `bk` may be rescaled in place (the
/// reflector does not depend on the scale of `v`).
#[inline(always)]
fn block_reflector<V: BlockOps>(rkk: f64, sigma: f64, bk: &mut [f64]) -> Option<Reflector> {
    let alpha0 = (rkk * rkk + sigma).sqrt();
    if sigma > 0.0 && alpha0 > SAFE_MIN_NORM && alpha0 < SAFE_MAX_NORM {
        let alpha = if rkk > 0.0 { -alpha0 } else { alpha0 };
        let v0 = rkk - alpha;
        return Some(Reflector {
            v0,
            beta: 2.0 / (v0 * v0 + sigma),
            diag: alpha,
            rescaled: false,
        });
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
    let [sigma] = V::multi_dot(bk, [&*bk]);
    let alpha = (rs * rs + sigma).sqrt();
    let alpha = if rs > 0.0 { -alpha } else { alpha };
    let v0 = rs - alpha;
    Some(Reflector {
        v0,
        beta: 2.0 / (v0 * v0 + sigma),
        diag: alpha * amax,
        rescaled: true,
    })
}

#[cfg(target_arch = "x86_64")]
mod wide;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::{shifted_triangular, upper_solve, upper_transpose_solve};

    /// The fold one pass at a time, as it was before the passes were fused: per step, the
    /// squares of column `k`, then each later column's dot product and update. Each dot
    /// product is [`dot`]'s.
    fn reference_tall_qr(m: &TallQr, r: &mut [f64], c: &mut [f64]) {
        let cols = m.cols;
        let mut block = vec![0.0; LD * (cols + 1)];
        r.fill(0.0);
        c.fill(0.0);
        let mut start = 0;
        while start < m.rows {
            let nb = TALL_QR_BLOCK.min(m.rows - start);
            m.load_block(start, nb, &mut block);
            for k in 0..cols {
                let (head, tail) = block.split_at_mut((k + 1) * LD);
                let bk = &mut head[k * LD..k * LD + nb];
                let sigma = dot(bk, bk);
                let Some(refl) = block_reflector::<Portable>(r[k * cols + k], sigma, bk) else {
                    continue;
                };
                r[k * cols + k] = refl.diag;
                for j in k + 1..=cols {
                    let col = &mut tail[(j - k - 1) * LD..(j - k - 1) * LD + nb];
                    let top = if j < cols {
                        &mut r[j * cols + k]
                    } else {
                        &mut c[k]
                    };
                    let w = refl.beta * (refl.v0 * *top + dot(bk, col));
                    *top -= w * refl.v0;
                    for (x, &v) in col.iter_mut().zip(bk.iter()) {
                        *x -= w * v;
                    }
                }
            }
            start += nb;
        }
    }

    /// The fused fold gives the one-pass-at-a-time fold's bits in every build (the portable
    /// one, the dispatched one, and AVX2 and AVX-512 where the CPU has them, so results do not
    /// depend on the machine), on a plain matrix, with a zeroed column (an exactly zero
    /// diagonal entry), with a column whose squares underflow (the rescaled reflector) and
    /// with row counts that leave partial blocks, four-row steps and tails of 1 to 3 rows.
    #[test]
    fn fused_fold_equals_the_pass_at_a_time_fold_bit_for_bit() {
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        for (rows, cols, case) in [(1037, 9, 0), (300, 7, 1), (257, 13, 2), (129, 5, 3)] {
            let mut a: Vec<f64> = (0..rows * cols)
                .map(|k| ((k * 7919) % 1013) as f64 / 97.0 - 5.0 + (k as f64 * 0.01).cos())
                .collect();
            if case == 2 {
                for x in &mut a[4 * rows..5 * rows] {
                    *x *= 1e-170;
                }
            }
            let rhs: Vec<f64> = (0..rows).map(|i| (i as f64 * 0.37).sin()).collect();
            let scale: Vec<f64> = (0..cols)
                .map(|j| {
                    if case == 1 && j == 2 {
                        0.0
                    } else {
                        1.0 / (1.0 + j as f64)
                    }
                })
                .collect();
            let m = TallQr {
                a: &a,
                rows,
                cols,
                col_scale: &scale,
                rhs: &rhs,
            };
            let (mut r0, mut c0) = (vec![0.0; cols * cols], vec![0.0; cols]);
            reference_tall_qr(&m, &mut r0, &mut c0);
            assert!(r0.iter().chain(&c0).all(|v| v.is_finite()), "case {case}");
            let (mut r1, mut c1) = (vec![f64::NAN; cols * cols], vec![f64::NAN; cols]);
            let mut scratch = vec![f64::NAN; tall_qr_scratch_len(cols)];
            m.run(&mut r1, &mut c1, &mut scratch);
            assert_eq!(bits(&r0), bits(&r1), "portable R, case {case}");
            assert_eq!(bits(&c0), bits(&c1), "portable c, case {case}");
            tall_qr(&a, rows, cols, &scale, &rhs, &mut r1, &mut c1, &mut scratch);
            assert_eq!(bits(&r0), bits(&r1), "dispatched R, case {case}");
            assert_eq!(bits(&c0), bits(&c1), "dispatched c, case {case}");
            #[cfg(target_arch = "x86_64")]
            for (build, has) in [
                ("avx2", Kernel::Avx2.is_available()),
                ("avx512", Kernel::Avx512.is_available()),
            ] {
                if !has {
                    continue;
                }
                r1.fill(f64::NAN);
                // SAFETY: the CPU has the build's features (checked in `has`).
                match build {
                    "avx2" => unsafe { m.run_avx2(&mut r1, &mut c1, &mut scratch) },
                    _ => unsafe { m.run_avx512(&mut r1, &mut c1, &mut scratch) },
                }
                assert_eq!(bits(&r0), bits(&r1), "{build} R, case {case}");
                assert_eq!(bits(&c0), bits(&c1), "{build} c, case {case}");
            }
            if case == 1 {
                assert_eq!(r1[2 * cols + 2], 0.0, "the zeroed column's diagonal");
            }
        }
    }

    #[test]
    fn qr_and_shift_match_normal_equations() {
        // J is 4x3; check R^T R = J^T J, and tl^T tl = R^T R + lam I.
        let j = [1.0, 2.0, 0.5, -1.0, 0.3, 1.0, 2.0, 0.0, -2.0, 1.0, 1.0, 3.0];
        let mut a = j;
        let mut rhs = [1.0, -1.0, 2.0, 0.5];
        householder_qr(&mut a, 4, 3, &mut rhs);
        let mut r = [0.0; 9];
        for c in 0..3 {
            for i in 0..=c {
                r[c * 3 + i] = a[c * 4 + i];
            }
        }
        let lam = 0.7;
        let (mut tl, mut ul, mut w) = ([0.0; 9], [0.0; 3], [0.0; 12]);
        shifted_triangular(&r, &rhs[..3], 3, lam, &mut tl, &mut ul, &mut w, true);
        for c1 in 0..3 {
            for c2 in 0..3 {
                let jtj: f64 = (0..4).map(|i| j[c1 * 4 + i] * j[c2 * 4 + i]).sum();
                let rtr: f64 = (0..3).map(|i| r[c1 * 3 + i] * r[c2 * 3 + i]).sum();
                let ttt: f64 = (0..3).map(|i| tl[c1 * 3 + i] * tl[c2 * 3 + i]).sum();
                assert!((jtj - rtr).abs() < 1e-12);
                let shift = if c1 == c2 { lam } else { 0.0 };
                assert!((jtj + shift - ttt).abs() < 1e-12);
            }
        }
        // Solves: T z = b and T^T q = b.
        let mut z = [1.0, 2.0, 3.0];
        upper_solve(&r, 3, &mut z);
        let mut q = z;
        for i in 0..3 {
            let v: f64 = (i..3).map(|c| r[c * 3 + i] * z[c]).sum();
            assert!((v - [1.0, 2.0, 3.0][i]).abs() < 1e-12);
        }
        upper_transpose_solve(&r, 3, &mut q);
        for i in 0..3 {
            let v: f64 = (0..=i).map(|k| r[i * 3 + k] * q[k]).sum();
            assert!((v - z[i]).abs() < 1e-12);
        }
    }
}
