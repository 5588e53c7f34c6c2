//! AVX-512F builds of the long (m-row) column loops, on `super::avx2`'s conventions with eight
//! rows per instruction.
//!
//! The element-wise work (loads, products, updates, stores) does not depend on the width of a
//! register. A dot product's sums do: the portable code's accumulator `l` adds the rows `l`,
//! `l + 4`, `l + 8`, ... in order. So each eight-row product is added to a four-lane
//! accumulator in two halves, rows `i..i + 4` and then `i + 4..i + 8` ([`accumulate`]), which
//! keeps every sum, and so every result, the portable one bit for bit (unit tests compare
//! them). Eight rows per instruction halve the instructions of the loads, products and
//! stores; the halves cost one extraction and two four-lane additions. The last rows (fewer
//! than eight) go to the AVX2 build's `*_from` functions, which continue from the eight-row
//! accumulators.
//!
//! Every function here requires AVX-512F and AVX2: callers run them only when the solver's
//! kernel is `avx512` (`super::dispatch`), or inside a function that did.

use super::avx2::{self, Survey, max_abs};
use std::arch::x86_64::*;

/// `acc + p`'s rows in the portable order: the four-lane accumulator `acc` adds the low half
/// of the eight-row `p`, then its high half.
#[target_feature(enable = "avx512f,avx2")]
#[inline]
pub(crate) fn accumulate(acc: __m256d, p: __m512d) -> __m256d {
    let low = _mm256_add_pd(acc, _mm512_castpd512_pd256(p));
    _mm256_add_pd(low, _mm512_extractf64x4_pd::<1>(p))
}

/// The rows of `0..n` done eight at a time; the rest (at most one four-row step and the tail)
/// is the AVX2 build's, continuing from the eight-row accumulators.
#[inline]
pub(crate) fn eight_row_body(n: usize) -> usize {
    n - n % 8
}

/// `[v . cols[g]]` (every column at least as long as `v`), each equal to `dot`'s result.
#[target_feature(enable = "avx512f,avx2")]
#[inline]
pub(crate) fn multi_dot<const G: usize>(v: &[f64], cols: [&[f64]; G]) -> [f64; G] {
    let n = v.len();
    let body8 = eight_row_body(n);
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
    avx2::multi_dot_from(v, cols, body8, acc)
}

/// `(col . col, col . r, max |col_i|)` for each of `G` columns (each `r`'s length), equal bit
/// for bit to the portable `column_survey`.
#[target_feature(enable = "avx512f,avx2")]
#[inline]
pub(crate) fn column_survey<const G: usize>(cols: [&[f64]; G], r: &[f64]) -> [(f64, f64, f64); G] {
    let n = r.len();
    let body8 = eight_row_body(n);
    let cols: [&[f64]; G] = std::array::from_fn(|g| &cols[g][..n]);
    let zero = [_mm256_setzero_pd(); G];
    let mut acc = Survey {
        sq: zero,
        jr: zero,
        lane_max: zero,
    };
    for i in (0..body8).step_by(8) {
        // SAFETY: i + 8 <= body8 <= n, and every slice has n entries.
        let y = unsafe { _mm512_loadu_pd(r.as_ptr().add(i)) };
        for g in 0..G {
            // SAFETY: as above.
            let x = unsafe { _mm512_loadu_pd(cols[g].as_ptr().add(i)) };
            acc.sq[g] = accumulate(acc.sq[g], _mm512_mul_pd(x, x));
            acc.jr[g] = accumulate(acc.jr[g], _mm512_mul_pd(x, y));
            let low = max_abs(acc.lane_max[g], _mm512_castpd512_pd256(x));
            acc.lane_max[g] = max_abs(low, _mm512_extractf64x4_pd::<1>(x));
        }
    }
    avx2::column_survey_from(cols, r, body8, acc)
}
