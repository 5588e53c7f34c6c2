//! faer's Householder QR with every buffer preallocated: the reference of the differential test
//! `tests/qr_faer.rs` and the competitor in `benches/qr.rs`. Same contract as
//! [`bounded_lm::qr::tall_qr`]: QR of `A S` (`S = diag(col_scale)`), writing `R` and the first
//! `cols` entries of `Q^T rhs`.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::householder::{
    apply_block_householder_sequence_transpose_on_the_left_in_place_scratch,
    apply_block_householder_sequence_transpose_on_the_left_in_place_with_conj,
};
use faer::linalg::qr::no_pivoting::factor::{
    qr_in_place, qr_in_place_scratch, recommended_block_size,
};
use faer::{Conj, MatMut, MatRef, Par};

/// Buffers for one size; [`FaerQr::factor`] allocates nothing.
pub struct FaerQr {
    rows: usize,
    cols: usize,
    block: usize,
    a: Vec<f64>,
    h: Vec<f64>,
    rhs: Vec<f64>,
    buf: MemBuffer,
}

impl FaerQr {
    /// Buffers for `rows x cols` with faer's recommended block size and its scratch query.
    pub fn new(rows: usize, cols: usize) -> Self {
        let block = recommended_block_size::<f64>(rows, cols);
        let req = qr_in_place_scratch::<f64>(rows, cols, block, Par::Seq, Default::default()).or(
            apply_block_householder_sequence_transpose_on_the_left_in_place_scratch::<f64>(
                rows, block, 1,
            ),
        );
        FaerQr {
            rows,
            cols,
            block,
            a: vec![0.0; rows * cols],
            h: vec![0.0; block * rows.min(cols)],
            rhs: vec![0.0; rows],
            buf: MemBuffer::new(req),
        }
    }

    /// QR of `A S`: `R` (`cols x cols`, zero below the diagonal) into `r`, `(Q^T rhs)[..cols]`
    /// into `c`. The scaled copy is part of the cost, as it is for the solver's in-place QR.
    pub fn factor(
        &mut self,
        a: &[f64],
        col_scale: &[f64],
        rhs: &[f64],
        r: &mut [f64],
        c: &mut [f64],
    ) {
        let (m, p) = (self.rows, self.cols);
        for j in 0..p {
            let s = col_scale[j];
            for (d, &x) in self.a[j * m..(j + 1) * m]
                .iter_mut()
                .zip(&a[j * m..(j + 1) * m])
            {
                *d = if s == 0.0 { 0.0 } else { x * s };
            }
        }
        self.rhs.copy_from_slice(&rhs[..m]);
        let k = m.min(p);
        let mut qr = MatMut::from_column_major_slice_mut(&mut self.a, m, p);
        let mut h = MatMut::from_column_major_slice_mut(&mut self.h, self.block, k);
        let stack = MemStack::new(&mut self.buf);
        qr_in_place(qr.as_mut(), h.as_mut(), Par::Seq, stack, Default::default());
        let basis = MatRef::from_column_major_slice(&self.a, m, p);
        let factor = MatRef::from_column_major_slice(&self.h, self.block, k);
        apply_block_householder_sequence_transpose_on_the_left_in_place_with_conj(
            basis.get(.., ..k),
            factor,
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut self.rhs, m, 1),
            Par::Seq,
            MemStack::new(&mut self.buf),
        );
        for j in 0..p {
            for i in 0..p {
                r[j * p + i] = if i <= j && i < m {
                    self.a[j * m + i]
                } else {
                    0.0
                };
            }
            c[j] = if j < m { self.rhs[j] } else { 0.0 };
        }
    }
}

/// Deterministic uniform entries in [-1, 1) (splitmix64), for the test, the benchmark and the
/// timing example alike.
pub struct Rng(pub u64);
impl Rng {
    /// The next entry.
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
    /// `n` entries.
    pub fn fill(&mut self, n: usize) -> Vec<f64> {
        (0..n).map(|_| self.next()).collect()
    }
}
