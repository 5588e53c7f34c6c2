//! The block fold's long loops with intrinsics, written once and generated for two register
//! widths: [`Avx2`] (four rows per instruction) and [`Avx512`] (eight), on the conventions of
//! `crate::linalg::avx2` and `crate::linalg::avx512`. Both give the portable build's bits (a
//! unit test in the parent module compares them).
//!
//! A generic function cannot carry the target features its instantiation needs (an AVX2
//! instantiation compiled with AVX-512 enabled could execute AVX-512 instructions), so the
//! source is a macro, `block_ops!`, expanded in a module of each width's register operations
//! (`w4`, `w8`), each compiled with exactly its features.
//!
//! The element-wise work (loads, products, updates, stores) runs at the register's width. The
//! dot products always add into four-lane accumulators in the portable order: an eight-row
//! product is added as its low half, then its high half (`crate::linalg::avx512::accumulate`).
//! At eight lanes the rows left after the last eight-row step go through at most one four-row
//! step, then the tail row by row. (Handing those rows to the AVX2 build instead, as
//! `crate::linalg::avx512` does, measured 3-10% slower here: this runs once per column group
//! and step of every 128-row block.)

pub(super) use w4::Avx2;
pub(super) use w8::Avx512;

/// Generates, in a module of one register width (its `V`, `WIDTH`, `load`, `store`, `splat`,
/// `zero`, `mul`, `sub` and `accumulate`), the [`BlockOps`] build `$name`: its loops compiled
/// with `$features` (which must include AVX2: the four-row step and the lane sums are AVX2
/// code), its dot products those of `$multi_dot` (same features).
macro_rules! block_ops {
    ($name:ident, $features:literal, $multi_dot:path) => {
        use crate::linalg::avx2::lanes_sum;
        use crate::qr::BlockOps;

        #[doc = concat!("The `", $features, "` build of [`BlockOps`]. Only `TallQr::run_with` ",
            "uses it, and only where the solver's kernel (`crate::linalg::dispatch`) has these ",
            "features: the safety argument of every `unsafe` call below.")]
        pub(in crate::qr) struct $name;

        impl BlockOps for $name {
            #[inline(always)]
            fn multi_dot<const G: usize>(v: &[f64], cols: [&[f64]; G]) -> [f64; G] {
                // SAFETY: the CPU has the features (see the type's docs).
                unsafe { $multi_dot(v, cols) }
            }

            #[inline(always)]
            fn sub_scaled<const G: usize>(v: &[f64], w: &[f64; G], cols: &mut [&mut [f64]; G]) {
                // SAFETY: the CPU has the features (see the type's docs).
                unsafe { sub_scaled_dot::<G, false>(v, w, cols, None) };
            }

            #[inline(always)]
            fn sub_scaled_dot<const G: usize>(
                v: &[f64],
                w: &[f64; G],
                cols: &mut [&mut [f64]; G],
                next: Option<&[f64]>,
            ) -> [f64; G] {
                // SAFETY: the CPU has the features (see the type's docs).
                unsafe { sub_scaled_dot::<G, true>(v, w, cols, next) }
            }

            #[inline(always)]
            fn load_scaled_dot<const G: usize>(
                src: [(&[f64], f64); G],
                dst: &mut [&mut [f64]; G],
                next: Option<&[f64]>,
            ) -> [f64; G] {
                // SAFETY: the CPU has the features (see the type's docs).
                unsafe { load_scaled_dot(src, dst, next) }
            }
        }

        /// `dst[g][i] = src[g].0[i] * src[g].1` (exact zeros where the scale is 0), and
        /// `[u . dst[g]]` of the new columns, `u` being `next` or else the new `dst[0]`.
        #[target_feature(enable = $features)]
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
            // SAFETY (all three closures): they read rows below n of the sources (asserted
            // above).
            let wide = |g: usize, i: usize| {
                if zero[g] {
                    self::zero()
                } else {
                    mul(unsafe { load(from[g].add(i)) }, splat(src[g].1))
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
            // SAFETY: every destination has n rows (asserted above), the destinations are
            // distinct slices, and neither `next` nor a source is one of them.
            unsafe { store_and_dot::<G, true>(n, to, next, wide, four, one) }
        }

        /// `cols[g][i] -= w[g] * v[i]`; with `DOTS`, also `[u . cols[g]]` of the updated
        /// rows, `u` being `next` or else the updated `cols[0]`.
        #[target_feature(enable = $features)]
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
            // SAFETY (all three closures): rows below n of v and of each column (asserted
            // above); each reads a row of its column before `store_and_dot` overwrites it.
            let wide = |g: usize, i: usize| unsafe {
                let old = load(to[g].add(i));
                sub(old, mul(splat(w[g]), load(v.as_ptr().add(i))))
            };
            let four = |g: usize, i: usize| unsafe {
                let old = _mm256_loadu_pd(to[g].add(i));
                let x = _mm256_loadu_pd(v.as_ptr().add(i));
                _mm256_sub_pd(old, _mm256_mul_pd(_mm256_set1_pd(w[g]), x))
            };
            let one = |g: usize, i: usize| unsafe { *to[g].add(i) - w[g] * v[i] };
            // SAFETY: every column has n rows (asserted above), the columns are distinct
            // slices and `next` is not one of them.
            unsafe { store_and_dot::<G, DOTS>(n, to, next, wide, four, one) }
        }

        /// The loop shared by [`load_scaled_dot`] and [`sub_scaled_dot`]: rows `0..n` of
        /// each column `to[g]` become `wide(g, i)` (`WIDTH` rows from `i`), then (eight-row
        /// registers only) at most once `four(g, i)`, then `one(g, i)` row by row in the
        /// tail; with `DOTS`, returns `[u . to[g]]` of the new rows, `u` being `next` or else
        /// the new `to[0]`, summed as `dot` sums.
        ///
        /// # Safety
        /// Each `to[g]` must be valid for reads and writes of `n` rows and not overlap
        /// another or `next` (which must have `n` rows).
        #[target_feature(enable = $features)]
        #[inline]
        unsafe fn store_and_dot<const G: usize, const DOTS: bool>(
            n: usize,
            to: [*mut f64; G],
            next: Option<&[f64]>,
            mut wide: impl FnMut(usize, usize) -> V,
            mut four: impl FnMut(usize, usize) -> __m256d,
            mut one: impl FnMut(usize, usize) -> f64,
        ) -> [f64; G] {
            if let Some(u) = next {
                assert!(u.len() >= n, "next has n rows");
            }
            let body = n - n % 4;
            let body_wide = body - body % WIDTH;
            let mut acc = [_mm256_setzero_pd(); G];
            for i in (0..body_wide).step_by(WIDTH) {
                let mut y = [self::zero(); G];
                for g in 0..G {
                    y[g] = wide(g, i);
                    // SAFETY: i + WIDTH <= n rows of to[g] (the caller's contract).
                    unsafe { store(to[g].add(i), y[g]) };
                }
                if DOTS {
                    let u = match next {
                        // SAFETY: as above, `next` has n rows.
                        Some(u) => unsafe { load(u.as_ptr().add(i)) },
                        None => y[0],
                    };
                    for g in 0..G {
                        acc[g] = accumulate(acc[g], mul(u, y[g]));
                    }
                }
            }
            if body_wide < body {
                let i = body_wide;
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
    };
}

/// Four rows per register: the AVX2 operations, and the AVX2 build.
mod w4 {
    use std::arch::x86_64::*;

    /// One register of rows.
    pub(super) type V = __m256d;
    /// Rows per register.
    pub(super) const WIDTH: usize = 4;

    /// `WIDTH` rows from `p`.
    ///
    /// # Safety
    /// `p` must be valid for reads of `WIDTH` values.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn load(p: *const f64) -> V {
        // SAFETY: the caller's contract.
        unsafe { _mm256_loadu_pd(p) }
    }

    /// Writes `WIDTH` rows to `p`.
    ///
    /// # Safety
    /// `p` must be valid for writes of `WIDTH` values.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn store(p: *mut f64, v: V) {
        // SAFETY: the caller's contract.
        unsafe { _mm256_storeu_pd(p, v) }
    }

    /// `x` in every lane.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) fn splat(x: f64) -> V {
        _mm256_set1_pd(x)
    }

    /// Zero in every lane.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) fn zero() -> V {
        _mm256_setzero_pd()
    }

    /// Lane-wise product.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) fn mul(a: V, b: V) -> V {
        _mm256_mul_pd(a, b)
    }

    /// Lane-wise difference.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) fn sub(a: V, b: V) -> V {
        _mm256_sub_pd(a, b)
    }

    /// The four-lane accumulator `acc` plus the rows of `p`.
    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) fn accumulate(acc: __m256d, p: V) -> __m256d {
        _mm256_add_pd(acc, p)
    }

    block_ops!(Avx2, "avx2", crate::linalg::avx2::multi_dot);
}

/// Eight rows per register: the AVX-512F operations, and the AVX-512 build.
mod w8 {
    use std::arch::x86_64::*;

    /// One register of rows.
    pub(super) type V = __m512d;
    /// Rows per register.
    pub(super) const WIDTH: usize = 8;

    /// `WIDTH` rows from `p`.
    ///
    /// # Safety
    /// `p` must be valid for reads of `WIDTH` values.
    #[target_feature(enable = "avx512f,avx2")]
    #[inline]
    pub(super) unsafe fn load(p: *const f64) -> V {
        // SAFETY: the caller's contract.
        unsafe { _mm512_loadu_pd(p) }
    }

    /// Writes `WIDTH` rows to `p`.
    ///
    /// # Safety
    /// `p` must be valid for writes of `WIDTH` values.
    #[target_feature(enable = "avx512f,avx2")]
    #[inline]
    pub(super) unsafe fn store(p: *mut f64, v: V) {
        // SAFETY: the caller's contract.
        unsafe { _mm512_storeu_pd(p, v) }
    }

    /// `x` in every lane.
    #[target_feature(enable = "avx512f,avx2")]
    #[inline]
    pub(super) fn splat(x: f64) -> V {
        _mm512_set1_pd(x)
    }

    /// Zero in every lane.
    #[target_feature(enable = "avx512f,avx2")]
    #[inline]
    pub(super) fn zero() -> V {
        _mm512_setzero_pd()
    }

    /// Lane-wise product.
    #[target_feature(enable = "avx512f,avx2")]
    #[inline]
    pub(super) fn mul(a: V, b: V) -> V {
        _mm512_mul_pd(a, b)
    }

    /// Lane-wise difference.
    #[target_feature(enable = "avx512f,avx2")]
    #[inline]
    pub(super) fn sub(a: V, b: V) -> V {
        _mm512_sub_pd(a, b)
    }

    pub(super) use crate::linalg::avx512::accumulate;

    block_ops!(Avx512, "avx512f,avx2", crate::linalg::avx512::multi_dot);
}
