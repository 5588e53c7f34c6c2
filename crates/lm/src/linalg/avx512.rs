//! AVX-512F builds of the long (m-row) column loops, on `super::avx2`'s conventions with eight
//! rows per instruction.
//!
//! The element-wise work (loads, products, updates, stores) does not depend on the width of a
//! register. A dot product's sums do: the portable code's accumulator `l` adds the rows `l`,
//! `l + 4`, `l + 8`, ... in order. So each eight-row product is added to a four-lane
//! accumulator in two halves, rows `i..i + 4` and then `i + 4..i + 8` ([`accumulate`]), which
//! keeps every sum, and so every result, the portable one bit for bit (unit tests compare
//! them). Eight rows per instruction halve the instructions of the loads, products and
//! stores; the halves cost one extraction and two four-lane additions.
//!
//! Every function here requires AVX-512F and AVX2: callers check [`available`] (or run
//! inside a function that did).

use super::avx2::lanes_sum;
use std::arch::x86_64::*;

/// Whether this CPU runs the functions of this module (and `crate::qr`'s AVX-512 build):
/// AVX-512F and AVX2, both enabled in each of them.
pub(crate) fn available() -> bool {
    std::arch::is_x86_feature_detected!("avx512f") && std::arch::is_x86_feature_detected!("avx2")
}

/// `acc + p`'s rows in the portable order: the four-lane accumulator `acc` adds the low half
/// of the eight-row `p`, then its high half.
#[target_feature(enable = "avx512f,avx2")]
#[inline]
pub(crate) fn accumulate(acc: __m256d, p: __m512d) -> __m256d {
    let low = _mm256_add_pd(acc, _mm512_castpd512_pd256(p));
    _mm256_add_pd(low, _mm512_extractf64x4_pd::<1>(p))
}

/// The number of rows of `0..n` done eight at a time, and whether four more follow (before
/// the tail of `n % 4` rows).
#[inline]
fn split_rows(n: usize) -> (usize, bool) {
    let body = n - n % 4;
    (body - body % 8, body % 8 == 4)
}

/// `[v . cols[g]]` (every column at least as long as `v`), each equal to `dot`'s result.
#[target_feature(enable = "avx512f,avx2")]
#[inline]
pub(crate) fn multi_dot<const G: usize>(v: &[f64], cols: [&[f64]; G]) -> [f64; G] {
    let n = v.len();
    let (body8, four) = split_rows(n);
    let cols: [&[f64]; G] = std::array::from_fn(|g| &cols[g][..n]);
    let mut acc = [_mm256_setzero_pd(); G];
    for i in (0..body8).step_by(8) {
        // SAFETY: i + 8 <= body8 <= n, and every slice has n entries.
        let x = unsafe { _mm512_loadu_pd(v.as_ptr().add(i)) };
        for g in 0..G {
            // SAFETY: as above.
            let y = unsafe { _mm512_loadu_pd(cols[g].as_ptr().add(i)) };
            acc[g] = accumulate(acc[g], _mm512_mul_pd(x, y));
        }
    }
    if four {
        // SAFETY: body8 + 4 <= n.
        let x = unsafe { _mm256_loadu_pd(v.as_ptr().add(body8)) };
        for g in 0..G {
            // SAFETY: as above.
            let y = unsafe { _mm256_loadu_pd(cols[g].as_ptr().add(body8)) };
            acc[g] = _mm256_add_pd(acc[g], _mm256_mul_pd(x, y));
        }
    }
    let body = n - n % 4;
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
#[target_feature(enable = "avx512f,avx2")]
#[inline]
pub(crate) fn column_survey<const G: usize>(cols: [&[f64]; G], r: &[f64]) -> [(f64, f64, f64); G] {
    let n = r.len();
    let (body8, four) = split_rows(n);
    let cols: [&[f64]; G] = std::array::from_fn(|g| &cols[g][..n]);
    let mut sq = [_mm256_setzero_pd(); G];
    let mut jr = [_mm256_setzero_pd(); G];
    let mut lane_max = [_mm256_setzero_pd(); G];
    let abs_mask = _mm256_castsi256_pd(_mm256_set1_epi64x(i64::MAX));
    // The AVX2 build's lane update: max_pd(a, m) is `a > m ? a : m`, the portable comparison.
    let max_abs = |m: __m256d, x: __m256d| _mm256_max_pd(_mm256_and_pd(x, abs_mask), m);
    for i in (0..body8).step_by(8) {
        // SAFETY: i + 8 <= body8 <= n, and every slice has n entries.
        let y = unsafe { _mm512_loadu_pd(r.as_ptr().add(i)) };
        for g in 0..G {
            // SAFETY: as above.
            let x = unsafe { _mm512_loadu_pd(cols[g].as_ptr().add(i)) };
            sq[g] = accumulate(sq[g], _mm512_mul_pd(x, x));
            jr[g] = accumulate(jr[g], _mm512_mul_pd(x, y));
            lane_max[g] = max_abs(lane_max[g], _mm512_castpd512_pd256(x));
            lane_max[g] = max_abs(lane_max[g], _mm512_extractf64x4_pd::<1>(x));
        }
    }
    if four {
        // SAFETY: body8 + 4 <= n.
        let y = unsafe { _mm256_loadu_pd(r.as_ptr().add(body8)) };
        for g in 0..G {
            // SAFETY: as above.
            let x = unsafe { _mm256_loadu_pd(cols[g].as_ptr().add(body8)) };
            sq[g] = _mm256_add_pd(sq[g], _mm256_mul_pd(x, x));
            jr[g] = _mm256_add_pd(jr[g], _mm256_mul_pd(x, y));
            lane_max[g] = max_abs(lane_max[g], x);
        }
    }
    let body = n - n % 4;
    std::array::from_fn(|g| {
        super::avx2::survey_result(sq[g], jr[g], lane_max[g], &cols[g][body..], &r[body..])
    })
}
