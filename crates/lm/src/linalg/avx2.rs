//! AVX2 builds of the long (m-row) column loops, shared by the survey of each Jacobian,
//! `J^T v` and the tall QR's block fold.
//!
//! Lane `l` of every accumulator register is the portable code's accumulator `l`, the lanes
//! are summed in [`super::dot`]'s order (`(l0 + l2) + (l1 + l3)`, then the tail rows in
//! order), and there is no fused multiply-add (Rust never contracts `a * b + c`), so every
//! result is the portable one bit for bit and does not depend on the machine (unit tests
//! compare the bits). Left to the compiler, an AVX2 build of the portable loops stayed partly
//! in shuffled 128-bit halves. Several columns go through one loop so that their sums form
//! independent dependency chains: one column's chain of adds alone is latency-bound.
//!
//! Every function here requires AVX2: callers run them only when the solver's kernel is
//! `avx2` or `avx512` (`super::dispatch`), or inside a function that did.

use std::arch::x86_64::*;

/// The four lanes of `acc` summed as `dot` sums them, plus the tail.
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) fn lanes_sum(acc: __m256d, tail: f64) -> f64 {
    let l = lanes(acc);
    (l[0] + l[2]) + (l[1] + l[3]) + tail
}

/// The four lanes of a register.
#[target_feature(enable = "avx2")]
#[inline]
fn lanes(v: __m256d) -> [f64; 4] {
    let mut l = [0.0f64; 4];
    // SAFETY: `l` holds four f64.
    unsafe { _mm256_storeu_pd(l.as_mut_ptr(), v) };
    l
}

/// `[v . cols[g]]` (every column at least as long as `v`), each equal to `dot`'s result.
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) fn multi_dot<const G: usize>(v: &[f64], cols: [&[f64]; G]) -> [f64; G] {
    multi_dot_from(v, cols, 0, [_mm256_setzero_pd(); G])
}

/// [`multi_dot`] from row `start` (a multiple of 4) on, its lanes starting from `acc`: the
/// rest of a sum that a wider build began.
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) fn multi_dot_from<const G: usize>(
    v: &[f64],
    cols: [&[f64]; G],
    start: usize,
    mut acc: [__m256d; G],
) -> [f64; G] {
    let n = v.len();
    let body = n - n % 4;
    assert!(
        start.is_multiple_of(4) && start <= body,
        "start on a four-row boundary"
    );
    let cols: [&[f64]; G] = std::array::from_fn(|g| &cols[g][..n]);
    for i in (start..body).step_by(4) {
        // SAFETY: i + 4 <= body <= n, and every slice has n entries.
        let x = unsafe { _mm256_loadu_pd(v.as_ptr().add(i)) };
        for g in 0..G {
            // SAFETY: as above.
            let y = unsafe { _mm256_loadu_pd(cols[g].as_ptr().add(i)) };
            acc[g] = _mm256_add_pd(acc[g], _mm256_mul_pd(x, y));
        }
    }
    std::array::from_fn(|g| {
        let mut tail = 0.0;
        for (x, y) in v[body..].iter().zip(&cols[g][body..]) {
            tail += x * y;
        }
        lanes_sum(acc[g], tail)
    })
}

/// `(col . col, col . r, max |col_i|)` for each of `G` columns (each `r`'s length), equal bit
/// for bit to the portable `column_survey`.
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) fn column_survey<const G: usize>(cols: [&[f64]; G], r: &[f64]) -> [(f64, f64, f64); G] {
    let zero = [_mm256_setzero_pd(); G];
    column_survey_from(
        cols,
        r,
        0,
        Survey {
            sq: zero,
            jr: zero,
            lane_max: zero,
        },
    )
}

/// The lane accumulators of a column survey: sums of squares, sums of products with `r`, and
/// largest magnitudes.
#[derive(Clone, Copy)]
pub(crate) struct Survey<const G: usize> {
    pub(crate) sq: [__m256d; G],
    pub(crate) jr: [__m256d; G],
    pub(crate) lane_max: [__m256d; G],
}

/// `max(|x|, m)` per lane, with the portable comparison (`max_pd(a, m)` is `a > m ? a : m`).
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) fn max_abs(m: __m256d, x: __m256d) -> __m256d {
    let abs_mask = _mm256_castsi256_pd(_mm256_set1_epi64x(i64::MAX));
    _mm256_max_pd(_mm256_and_pd(x, abs_mask), m)
}

/// [`column_survey`] from row `start` (a multiple of 4) on, its lanes starting from `acc`.
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) fn column_survey_from<const G: usize>(
    cols: [&[f64]; G],
    r: &[f64],
    start: usize,
    acc: Survey<G>,
) -> [(f64, f64, f64); G] {
    let n = r.len();
    let body = n - n % 4;
    assert!(
        start.is_multiple_of(4) && start <= body,
        "start on a four-row boundary"
    );
    let cols: [&[f64]; G] = std::array::from_fn(|g| &cols[g][..n]);
    let Survey {
        mut sq,
        mut jr,
        mut lane_max,
    } = acc;
    for i in (start..body).step_by(4) {
        // SAFETY: i + 4 <= body <= n, and every slice has n entries.
        let y = unsafe { _mm256_loadu_pd(r.as_ptr().add(i)) };
        for g in 0..G {
            // SAFETY: as above.
            let x = unsafe { _mm256_loadu_pd(cols[g].as_ptr().add(i)) };
            sq[g] = _mm256_add_pd(sq[g], _mm256_mul_pd(x, x));
            jr[g] = _mm256_add_pd(jr[g], _mm256_mul_pd(x, y));
            lane_max[g] = max_abs(lane_max[g], x);
        }
    }
    std::array::from_fn(|g| {
        let (mut sq_tail, mut jr_tail) = (0.0, 0.0);
        let m = lanes(lane_max[g]);
        let mut amax = m[0].max(m[1]).max(m[2].max(m[3]));
        for (x, y) in cols[g][body..].iter().zip(&r[body..]) {
            sq_tail += x * x;
            jr_tail += x * y;
            amax = amax.max(x.abs());
        }
        (lanes_sum(sq[g], sq_tail), lanes_sum(jr[g], jr_tail), amax)
    })
}
