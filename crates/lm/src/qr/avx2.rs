//! The block fold's long loops with AVX2 intrinsics, on the conventions of
//! `crate::linalg::avx2` (the same bits as the portable build; a unit test in the parent module
//! compares them).

use super::BlockOps;
use crate::linalg::avx2::{lanes_sum, multi_dot};
use std::arch::x86_64::*;

/// The AVX2 build of [`BlockOps`]. Only `TallQr::run_avx2` uses it, and that runs only after
/// `is_x86_feature_detected!("avx2")`: the safety argument of every `unsafe` call below.
pub(super) struct Avx2;

impl BlockOps for Avx2 {
    #[inline(always)]
    fn multi_dot<const G: usize>(v: &[f64], cols: [&[f64]; G]) -> [f64; G] {
        // SAFETY: the CPU has AVX2 (see the type's docs).
        unsafe { multi_dot(v, cols) }
    }

    #[inline(always)]
    fn sub_scaled<const G: usize>(v: &[f64], w: &[f64; G], cols: &mut [&mut [f64]; G]) {
        // SAFETY: the CPU has AVX2 (see the type's docs).
        unsafe { sub_scaled_dot::<G, false>(v, w, cols, None) };
    }

    #[inline(always)]
    fn sub_scaled_dot<const G: usize>(
        v: &[f64],
        w: &[f64; G],
        cols: &mut [&mut [f64]; G],
        next: Option<&[f64]>,
    ) -> [f64; G] {
        // SAFETY: the CPU has AVX2 (see the type's docs).
        unsafe { sub_scaled_dot::<G, true>(v, w, cols, next) }
    }

    #[inline(always)]
    fn load_scaled_dot<const G: usize>(
        src: [(&[f64], f64); G],
        dst: &mut [&mut [f64]; G],
        next: Option<&[f64]>,
    ) -> [f64; G] {
        // SAFETY: the CPU has AVX2 (see the type's docs).
        unsafe { load_scaled_dot(src, dst, next) }
    }
}

/// `dst[g][i] = src[g].0[i] * src[g].1` (exact zeros where the scale is 0), four rows at a
/// time, and `[u . dst[g]]` of the new columns, `u` being `next` or else the new `dst[0]`.
#[target_feature(enable = "avx2")]
#[inline]
fn load_scaled_dot<const G: usize>(
    src: [(&[f64], f64); G],
    dst: &mut [&mut [f64]; G],
    next: Option<&[f64]>,
) -> [f64; G] {
    let n = dst[0].len();
    for g in 0..G {
        assert!(
            dst[g].len() == n && src[g].0.len() >= n,
            "columns of n rows"
        );
    }
    let zero: [bool; G] = std::array::from_fn(|g| src[g].1 == 0.0);
    let scale: [__m256d; G] = std::array::from_fn(|g| _mm256_set1_pd(src[g].1));
    let from: [*const f64; G] = std::array::from_fn(|g| src[g].0.as_ptr());
    let to: [*mut f64; G] = std::array::from_fn(|g| dst[g].as_mut_ptr());
    // SAFETY: the closures read rows below n of the sources (asserted above).
    let chunk = |g: usize, i: usize| {
        if zero[g] {
            _mm256_setzero_pd()
        } else {
            _mm256_mul_pd(unsafe { _mm256_loadu_pd(from[g].add(i)) }, scale[g])
        }
    };
    let row = |g: usize, i: usize| {
        let (col, s) = src[g];
        if s == 0.0 { 0.0 } else { col[i] * s }
    };
    // SAFETY: every destination has n rows (asserted above), the destinations are distinct
    // slices, and neither `next` nor a source is one of them.
    unsafe { store_and_dot::<G, true>(n, to, next, chunk, row) }
}

/// `cols[g][i] -= w[g] * v[i]`, four rows at a time; with `DOTS`, also `[u . cols[g]]` of the
/// updated rows, `u` being `next` or else the updated `cols[0]`.
#[target_feature(enable = "avx2")]
#[inline]
fn sub_scaled_dot<const G: usize, const DOTS: bool>(
    v: &[f64],
    w: &[f64; G],
    cols: &mut [&mut [f64]; G],
    next: Option<&[f64]>,
) -> [f64; G] {
    let n = v.len();
    for col in cols.iter() {
        assert!(col.len() >= n, "every column has v's length");
    }
    let wv: [__m256d; G] = std::array::from_fn(|g| _mm256_set1_pd(w[g]));
    let to: [*mut f64; G] = std::array::from_fn(|g| cols[g].as_mut_ptr());
    // SAFETY (both closures): rows below n of v and of each column (asserted above); each
    // reads a row of its column before `store_and_dot` overwrites it.
    let chunk = |g: usize, i: usize| unsafe {
        let old = _mm256_loadu_pd(to[g].add(i));
        _mm256_sub_pd(
            old,
            _mm256_mul_pd(wv[g], _mm256_loadu_pd(v.as_ptr().add(i))),
        )
    };
    let row = |g: usize, i: usize| unsafe { *to[g].add(i) - w[g] * v[i] };
    // SAFETY: every column has n rows (asserted above), the columns are distinct slices and
    // `next` is not one of them.
    unsafe { store_and_dot::<G, DOTS>(n, to, next, chunk, row) }
}

/// The loop shared by [`load_scaled_dot`] and [`sub_scaled_dot`]: rows `0..n` of each column
/// `to[g]` become `chunk(g, i)` (four rows from `i`) or, in the tail, `row(g, i)`; with `DOTS`,
/// returns `[u . to[g]]` of the new rows, `u` being `next` or else the new `to[0]`, summed as
/// `dot` sums.
///
/// # Safety
/// Each `to[g]` must be valid for reads and writes of `n` rows and not overlap another or
/// `next` (which must have `n` rows).
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn store_and_dot<const G: usize, const DOTS: bool>(
    n: usize,
    to: [*mut f64; G],
    next: Option<&[f64]>,
    mut chunk: impl FnMut(usize, usize) -> __m256d,
    mut row: impl FnMut(usize, usize) -> f64,
) -> [f64; G] {
    if let Some(u) = next {
        assert!(u.len() >= n, "next has n rows");
    }
    let body = n - n % 4;
    let mut acc = [_mm256_setzero_pd(); G];
    for i in (0..body).step_by(4) {
        let mut y = [_mm256_setzero_pd(); G];
        for g in 0..G {
            y[g] = chunk(g, i);
            // SAFETY: i + 4 <= n rows of to[g] (the caller's contract).
            unsafe { _mm256_storeu_pd(to[g].add(i), y[g]) };
        }
        if DOTS {
            let u = match next {
                // SAFETY: as above, `next` has n rows.
                Some(u) => unsafe { _mm256_loadu_pd(u.as_ptr().add(i)) },
                None => y[0],
            };
            for g in 0..G {
                acc[g] = _mm256_add_pd(acc[g], _mm256_mul_pd(u, y[g]));
            }
        }
    }
    let mut tail = [0.0; G];
    for i in body..n {
        let mut y = [0.0; G];
        for g in 0..G {
            y[g] = row(g, i);
            // SAFETY: i < n rows of to[g].
            unsafe { *to[g].add(i) = y[g] };
        }
        let u = next.map_or(y[0], |x| x[i]);
        for g in 0..G {
            tail[g] += u * y[g];
        }
    }
    std::array::from_fn(|g| lanes_sum(acc[g], tail[g]))
}
