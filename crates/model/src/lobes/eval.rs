//! [`LobeEval`]: the [`Evaluate`] of every [`LobeShape`] family, with the sample loops compiled
//! once per kernel.

use super::shape::{FusedMath, Libm, LobeShape, MAX_COLUMNS, MAX_FIELDS, Math, PlainMath};
use crate::evaluate::{Evaluate, all_finite, grown};
use crate::family::{Coord, LayoutParam, LobeKind};
use crate::samples::Samples;
use brdf_simd::Kernel;

/// Samples per block of the Jacobian: the block's field derivatives stay in L1 while the
/// lobe's columns are written.
const BLOCK: usize = 256;

/// Where a parameter's value comes from.
#[derive(Clone, Copy, Debug)]
enum Src {
    /// Free-vector entry `j`, in coordinate `coord`.
    Free(usize, Coord),
    /// A fixed physical value.
    Fixed(f64),
}

/// One parameter of the layout as the evaluator decodes it.
#[derive(Clone, Copy, Debug)]
struct ParamPlan {
    src: Src,
    /// The lobe, `None` for `kd`.
    lobe: Option<usize>,
    /// The fields it sets.
    fields: &'static [usize],
}

/// One free parameter of a lobe, as a Jacobian column: its index in the free vector and the
/// lobe fields whose derivatives it sums.
#[derive(Clone, Copy, Debug)]
struct LobeColumn {
    j: usize,
    fields: &'static [usize],
}

/// The evaluation plan of one layout of shape `S` and its scratch space.
pub(crate) struct LobeEval<S: LobeShape> {
    kernel: Kernel,
    params: Vec<ParamPlan>,
    aniso: Vec<bool>,
    /// Free parameters per lobe, as Jacobian columns.
    columns: Vec<Vec<LobeColumn>>,
    /// The free index of `kd`, if free.
    kd_column: Option<usize>,
    /// Lobe field values with every field at its default (the start of each decoding).
    defaults: [f64; MAX_FIELDS],
    // The state at the point of the last `set_point`:
    kd: f64,
    fields: Vec<[f64; MAX_FIELDS]>,
    coefs: Vec<S::Coef>,
    /// `dv / dx` of each free parameter.
    scales: Vec<f64>,
    /// Field derivatives of one block: `MAX_FIELDS` rows of `BLOCK`.
    grad: Vec<f64>,
}

impl<S: LobeShape> LobeEval<S> {
    pub(crate) fn new(kinds: &[LobeKind], layout_params: &[LayoutParam], kernel: Kernel) -> Self {
        let lobes = kinds.len();
        let mut params = Vec::new();
        let mut columns = vec![Vec::new(); lobes];
        let mut kd_column = None;
        let mut j = 0;
        for p in layout_params {
            let src = match p.fixed {
                Some(v) => Src::Fixed(v),
                None => {
                    match p.lobe {
                        None => kd_column = Some(j),
                        Some(k) => columns[k].push(LobeColumn {
                            j,
                            fields: p.def.fields,
                        }),
                    }
                    j += 1;
                    Src::Free(j - 1, p.coord)
                }
            };
            params.push(ParamPlan {
                src,
                lobe: p.lobe,
                fields: p.def.fields,
            });
        }
        let mut defaults = [0.0; MAX_FIELDS];
        for (d, f) in defaults.iter_mut().zip(S::LOBE_FIELDS) {
            *d = f.default;
        }
        LobeEval {
            kernel,
            params,
            aniso: kinds.iter().map(|&k| k == LobeKind::Anisotropic).collect(),
            columns,
            kd_column,
            defaults,
            kd: 0.0,
            fields: vec![defaults; lobes],
            coefs: vec![S::Coef::default(); lobes],
            scales: vec![1.0; j],
            grad: vec![0.0; MAX_FIELDS * BLOCK],
        }
    }

    /// Adds lobe `l`'s values at samples `lo..lo + r.len()` to `r`.
    fn add_values(&self, l: usize, data: &Samples, lo: usize, r: &mut [f64]) {
        let (c, aniso) = (&self.coefs[l], self.aniso[l]);
        let cols = columns::<S>(data, lo, r.len());
        macro_rules! run {
            ($m:ty) => {
                if aniso {
                    add_values::<S, $m, true>(c, &cols, r)
                } else {
                    add_values::<S, $m, false>(c, &cols, r)
                }
            };
        }
        match self.kernel {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: a kernel is only selected when the CPU reports its features.
            Kernel::Avx512 => unsafe { values512::<S>(c, aniso, &cols, r) },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: as above.
            Kernel::Avx2 => unsafe { values256::<S>(c, aniso, &cols, r) },
            Kernel::Scalar => run!(Libm),
            _ => run!(PlainMath),
        }
    }

    /// Adds lobe `l`'s values at samples `lo..lo + r.len()` to `r` and writes its field
    /// derivatives into `grad` (`MAX_FIELDS` rows of `BLOCK`).
    fn add_values_grad(
        &self,
        l: usize,
        data: &Samples,
        lo: usize,
        r: &mut [f64],
        grad: &mut [f64],
    ) {
        let (c, aniso) = (&self.coefs[l], self.aniso[l]);
        let cols = columns::<S>(data, lo, r.len());
        macro_rules! run {
            ($m:ty) => {
                if aniso {
                    add_values_grad::<S, $m, true>(c, &cols, r, grad)
                } else {
                    add_values_grad::<S, $m, false>(c, &cols, r, grad)
                }
            };
        }
        match self.kernel {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: a kernel is only selected when the CPU reports its features.
            Kernel::Avx512 => unsafe { grad512::<S>(c, aniso, &cols, r, grad) },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: as above.
            Kernel::Avx2 => unsafe { grad256::<S>(c, aniso, &cols, r, grad) },
            Kernel::Scalar => run!(Libm),
            _ => run!(PlainMath),
        }
    }
}

/// The first `S::COLUMNS` columns of samples `lo..lo + m` (the rest empty).
fn columns<S: LobeShape>(data: &Samples, lo: usize, m: usize) -> [&[f64]; MAX_COLUMNS] {
    std::array::from_fn(|k| {
        if k < S::COLUMNS {
            &data.column(k)[lo..lo + m]
        } else {
            &[][..]
        }
    })
}

/// Sample `i`'s columns.
#[inline(always)]
fn row<S: LobeShape>(cols: &[&[f64]; MAX_COLUMNS], i: usize) -> [f64; MAX_COLUMNS] {
    let mut s = [0.0; MAX_COLUMNS];
    for k in 0..S::COLUMNS {
        s[k] = cols[k][i];
    }
    s
}

#[inline(always)]
fn add_values<S: LobeShape, M: Math, const ANISO: bool>(
    c: &S::Coef,
    cols: &[&[f64]; MAX_COLUMNS],
    r: &mut [f64],
) {
    for (i, ri) in r.iter_mut().enumerate() {
        *ri += S::value::<M, ANISO>(c, &row::<S>(cols, i));
    }
}

#[inline(always)]
fn add_values_grad<S: LobeShape, M: Math, const ANISO: bool>(
    c: &S::Coef,
    cols: &[&[f64]; MAX_COLUMNS],
    r: &mut [f64],
    grad: &mut [f64],
) {
    let nf = S::LOBE_FIELDS.len();
    for (i, ri) in r.iter_mut().enumerate() {
        let mut g = [0.0; MAX_FIELDS];
        *ri += S::value_grad::<M, ANISO>(c, &row::<S>(cols, i), &mut g);
        for f in 0..nf {
            grad[f * BLOCK + i] = g[f];
        }
    }
}

/// # Safety
/// The CPU must support AVX-512F, AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx2,fma")]
unsafe fn values512<S: LobeShape>(
    c: &S::Coef,
    aniso: bool,
    cols: &[&[f64]; MAX_COLUMNS],
    r: &mut [f64],
) {
    if aniso {
        add_values::<S, FusedMath, true>(c, cols, r)
    } else {
        add_values::<S, FusedMath, false>(c, cols, r)
    }
}

/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn values256<S: LobeShape>(
    c: &S::Coef,
    aniso: bool,
    cols: &[&[f64]; MAX_COLUMNS],
    r: &mut [f64],
) {
    if aniso {
        add_values::<S, FusedMath, true>(c, cols, r)
    } else {
        add_values::<S, FusedMath, false>(c, cols, r)
    }
}

/// # Safety
/// The CPU must support AVX-512F, AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx2,fma")]
unsafe fn grad512<S: LobeShape>(
    c: &S::Coef,
    aniso: bool,
    cols: &[&[f64]; MAX_COLUMNS],
    r: &mut [f64],
    grad: &mut [f64],
) {
    if aniso {
        add_values_grad::<S, FusedMath, true>(c, cols, r, grad)
    } else {
        add_values_grad::<S, FusedMath, false>(c, cols, r, grad)
    }
}

/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn grad256<S: LobeShape>(
    c: &S::Coef,
    aniso: bool,
    cols: &[&[f64]; MAX_COLUMNS],
    r: &mut [f64],
    grad: &mut [f64],
) {
    if aniso {
        add_values_grad::<S, FusedMath, true>(c, cols, r, grad)
    } else {
        add_values_grad::<S, FusedMath, false>(c, cols, r, grad)
    }
}

impl<S: LobeShape> Evaluate for LobeEval<S> {
    fn kernel(&self) -> Kernel {
        self.kernel
    }

    fn set_point(&mut self, x: &[f64]) {
        for f in &mut self.fields {
            *f = self.defaults;
        }
        for p in &self.params {
            let v = match p.src {
                Src::Fixed(v) => v,
                Src::Free(j, coord) => {
                    let v = coord.to_physical(x[j]);
                    self.scales[j] = coord.dv_dx(v);
                    v
                }
            };
            match p.lobe {
                None => self.kd = v,
                Some(k) => {
                    for &f in p.fields {
                        self.fields[k][f] = v;
                    }
                }
            }
        }
        let nf = S::LOBE_FIELDS.len();
        for ((c, f), &aniso) in self.coefs.iter_mut().zip(&self.fields).zip(&self.aniso) {
            *c = S::coef(&f[..nf], aniso);
        }
    }

    fn values(
        &mut self,
        _x: &[f64],
        data: &Samples,
        lo: usize,
        r: &mut [f64],
        _keep: bool,
    ) -> bool {
        debug_assert_eq!(data.family(), S::NAME);
        let y = &data.values()[lo..lo + r.len()];
        for (ri, &yi) in r.iter_mut().zip(y) {
            *ri = self.kd - yi;
        }
        for l in 0..self.coefs.len() {
            self.add_values(l, data, lo, r);
        }
        all_finite(r)
    }

    fn residuals_and_jacobian(
        &mut self,
        x: &[f64],
        data: &Samples,
        r: &mut [f64],
        jac: &mut [f64],
    ) -> bool {
        debug_assert_eq!(data.family(), S::NAME);
        self.set_point(x);
        let m = data.len();
        for (ri, &yi) in r.iter_mut().zip(data.values()) {
            *ri = self.kd - yi;
        }
        if m == 0 {
            return true;
        }
        if let Some(j) = self.kd_column {
            let s = self.scales[j];
            jac[j * m..(j + 1) * m].fill(s);
        }
        let mut grad = std::mem::take(&mut self.grad);
        grown(&mut grad, MAX_FIELDS * BLOCK);
        let mut ok = true;
        for l in 0..self.coefs.len() {
            for lo in (0..m).step_by(BLOCK) {
                let hi = (lo + BLOCK).min(m);
                self.add_values_grad(l, data, lo, &mut r[lo..hi], &mut grad);
                for col in &self.columns[l] {
                    let s = self.scales[col.j];
                    let out = &mut jac[col.j * m + lo..col.j * m + hi];
                    let first = &grad[col.fields[0] * BLOCK..][..hi - lo];
                    for (o, &g) in out.iter_mut().zip(first) {
                        *o = g;
                    }
                    for &f in &col.fields[1..] {
                        for (o, &g) in out.iter_mut().zip(&grad[f * BLOCK..][..hi - lo]) {
                            *o += g;
                        }
                    }
                    for o in out.iter_mut() {
                        *o *= s;
                    }
                    ok &= all_finite(out);
                }
            }
        }
        self.grad = grad;
        ok && all_finite(r)
    }
}
