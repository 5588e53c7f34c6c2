//! The block fold's long loops with AVX-512F: eight rows per instruction, on the conventions of
//! `crate::linalg::avx512` (the same bits as the portable build; a unit test in the parent
//! module compares them).

use super::BlockOps;
use crate::linalg::avx2::lanes_sum;
use crate::linalg::avx512::{accumulate, multi_dot};
use std::arch::x86_64::*;

/// The AVX-512 build of [`BlockOps`]. Only `TallQr::run_avx512` uses it, and that runs only
/// after `crate::linalg::avx512::available()` (AVX-512F and AVX2): the safety argument of
/// every `unsafe` call below.
pub(super) struct Avx512;

impl BlockOps for Avx512 {
    #[inline(always)]
    fn multi_dot<const G: usize>(v: &[f64], cols: [&[f64]; G]) -> [f64; G] {
        // SAFETY: the CPU has AVX-512F and AVX2 (see the type's docs).
        unsafe { multi_dot(v, cols) }
    }

    #[inline(always)]
    fn sub_scaled<const G: usize>(v: &[f64], w: &[f64; G], cols: &mut [&mut [f64]; G]) {
        // SAFETY: the CPU has AVX-512F and AVX2 (see the type's docs).
        unsafe { sub_scaled_dot::<G, false>(v, w, cols, None) };
    }

    #[inline(always)]
    fn sub_scaled_dot<const G: usize>(
        v: &[f64],
        w: &[f64; G],
        cols: &mut [&mut [f64]; G],
        next: Option<&[f64]>,
    ) -> [f64; G] {
        // SAFETY: the CPU has AVX-512F and AVX2 (see the type's docs).
        unsafe { sub_scaled_dot::<G, true>(v, w, cols, next) }
    }

    #[inline(always)]
    fn load_scaled_dot<const G: usize>(
        src: [(&[f64], f64); G],
        dst: &mut [&mut [f64]; G],
        next: Option<&[f64]>,
    ) -> [f64; G] {
        // SAFETY: the CPU has AVX-512F and AVX2 (see the type's docs).
        unsafe { load_scaled_dot(src, dst, next) }
    }
}

/// `dst[g][i] = src[g].0[i] * src[g].1` (exact zeros where the scale is 0), and `[u . dst[g]]`
/// of the new columns, `u` being `next` or else the new `dst[0]`.
#[target_feature(enable = "avx512f,avx2")]
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
    let from: [*const f64; G] = std::array::from_fn(|g| src[g].0.as_ptr());
    let to: [*mut f64; G] = std::array::from_fn(|g| dst[g].as_mut_ptr());
    // SAFETY (all three closures): they read rows below n of the sources (asserted above).
    let eight = |g: usize, i: usize| {
        if zero[g] {
            _mm512_setzero_pd()
        } else {
            let x = unsafe { _mm512_loadu_pd(from[g].add(i)) };
            _mm512_mul_pd(x, _mm512_set1_pd(src[g].1))
        }
    };
    let four = |g: usize, i: usize| {
        if zero[g] {
            _mm256_setzero_pd()
        } else {
            let x = unsafe { _mm256_loadu_pd(from[g].add(i)) };
            _mm256_mul_pd(x, _mm256_set1_pd(src[g].1))
        }
    };
    let one = |g: usize, i: usize| {
        let (col, s) = src[g];
        if s == 0.0 { 0.0 } else { col[i] * s }
    };
    // SAFETY: every destination has n rows (asserted above), the destinations are distinct
    // slices, and neither `next` nor a source is one of them.
    unsafe { store_and_dot::<G, true>(n, to, next, eight, four, one) }
}

/// `cols[g][i] -= w[g] * v[i]`; with `DOTS`, also `[u . cols[g]]` of the updated rows, `u`
/// being `next` or else the updated `cols[0]`.
#[target_feature(enable = "avx512f,avx2")]
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
    let to: [*mut f64; G] = std::array::from_fn(|g| cols[g].as_mut_ptr());
    // SAFETY (all three closures): rows below n of v and of each column (asserted above); each
    // reads a row of its column before `store_and_dot` overwrites it.
    let eight = |g: usize, i: usize| unsafe {
        let old = _mm512_loadu_pd(to[g].add(i));
        let x = _mm512_loadu_pd(v.as_ptr().add(i));
        _mm512_sub_pd(old, _mm512_mul_pd(_mm512_set1_pd(w[g]), x))
    };
    let four = |g: usize, i: usize| unsafe {
        let old = _mm256_loadu_pd(to[g].add(i));
        let x = _mm256_loadu_pd(v.as_ptr().add(i));
        _mm256_sub_pd(old, _mm256_mul_pd(_mm256_set1_pd(w[g]), x))
    };
    let one = |g: usize, i: usize| unsafe { *to[g].add(i) - w[g] * v[i] };
    // SAFETY: every column has n rows (asserted above), the columns are distinct slices and
    // `next` is not one of them.
    unsafe { store_and_dot::<G, DOTS>(n, to, next, eight, four, one) }
}

/// The loop shared by [`load_scaled_dot`] and [`sub_scaled_dot`]: rows `0..n` of each column
/// `to[g]` become `eight(g, i)` (eight rows from `i`), then at most once `four(g, i)`, then
/// `one(g, i)` row by row in the tail; with `DOTS`, returns `[u . to[g]]` of the new rows, `u`
/// being `next` or else the new `to[0]`, summed as `dot` sums. (Handing the last rows to the
/// AVX2 build instead, as `crate::linalg::avx512` does, measured 3-10% slower here: this runs
/// once per column group and step of every 128-row block.)
///
/// # Safety
/// Each `to[g]` must be valid for reads and writes of `n` rows and not overlap another or
/// `next` (which must have `n` rows).
#[target_feature(enable = "avx512f,avx2")]
#[inline]
unsafe fn store_and_dot<const G: usize, const DOTS: bool>(
    n: usize,
    to: [*mut f64; G],
    next: Option<&[f64]>,
    mut eight: impl FnMut(usize, usize) -> __m512d,
    mut four: impl FnMut(usize, usize) -> __m256d,
    mut one: impl FnMut(usize, usize) -> f64,
) -> [f64; G] {
    if let Some(u) = next {
        assert!(u.len() >= n, "next has n rows");
    }
    let body = n - n % 4;
    let body8 = body - body % 8;
    let mut acc = [_mm256_setzero_pd(); G];
    for i in (0..body8).step_by(8) {
        let mut y = [_mm512_setzero_pd(); G];
        for g in 0..G {
            y[g] = eight(g, i);
            // SAFETY: i + 8 <= n rows of to[g] (the caller's contract).
            unsafe { _mm512_storeu_pd(to[g].add(i), y[g]) };
        }
        if DOTS {
            let u = match next {
                // SAFETY: as above, `next` has n rows.
                Some(u) => unsafe { _mm512_loadu_pd(u.as_ptr().add(i)) },
                None => y[0],
            };
            for g in 0..G {
                acc[g] = accumulate(acc[g], _mm512_mul_pd(u, y[g]));
            }
        }
    }
    if body8 < body {
        let i = body8;
        let mut y = [_mm256_setzero_pd(); G];
        for g in 0..G {
            y[g] = four(g, i);
            // SAFETY: i + 4 <= n rows of to[g].
            unsafe { _mm256_storeu_pd(to[g].add(i), y[g]) };
        }
        if DOTS {
            let u = match next {
                // SAFETY: as above.
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
            y[g] = one(g, i);
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
