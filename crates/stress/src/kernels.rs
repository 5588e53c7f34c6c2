//! Section 1: accuracy of every evaluation kernel against the double-double reference over the
//! whole Table 1 box, its edges and the overflow boundary.
//!
//! Work is split into *batches*: one layout, one regime, one seeded internal vector `x` and
//! [`BATCH`] seeded direction pairs. Every kernel the CPU runs ([`Kernel::available`],
//! including brdf-model's scalar libm kernel) and the scalar `powf` model
//! ([`brdf_model::BrdfParams::value`], values only, a second yardstick) evaluates the batch; the values and the Jacobian are compared with [`Reference`].

use crate::dd::DD;
use crate::reference::{Reference, Role};
use crate::{derive_seed, percentile};
use brdf_model::{
    BrdfParams, DataSet, Evaluator, ExponentCoord, Kernel, Layout, LobeKind, uniform_hemisphere,
};
use rand::{Rng, RngExt, SeedableRng};
use rand_pcg::Pcg64;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Direction pairs per batch.
pub const BATCH: usize = 64;

/// How a batch's parameters and directions are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Regime {
    /// Uniform in the internal box.
    Uniform,
    /// Exponents near 0 (0, 1e-300, 1e-12, 1e-6, 1e-3, 0.5, 1).
    SmallN,
    /// Exponents at the upper bound (10000).
    MaxN,
    /// `d^n` from 1e150 to 1e330 on the batch: around the overflow of values and derivatives.
    Overflow,
    /// Directions within 1e-3 rad of the horizon (and exactly on it).
    Grazing,
    /// Lobes with `d <= 0` on most samples, and exact zeros of `d`.
    NegativeD,
    /// Pan at -90, -45, 0, 45, 90 degrees with `Cx != Cy`.
    PanEdges,
    /// C's at -1.5, 0, 1.5 and kd at 0 or 1.
    CEdges,
    /// Directions taken from the supplied data sets.
    DataDirections,
}

const REGIMES: [Regime; 8] = [
    Regime::Uniform,
    Regime::SmallN,
    Regime::MaxN,
    Regime::Overflow,
    Regime::Grazing,
    Regime::NegativeD,
    Regime::PanEdges,
    Regime::CEdges,
];

/// The layouts exercised: both lobe kinds, both exponent coordinates, fixed pan (the loop
/// without the `R` term at pan 0, and with it at 60 degrees) and a fixed exponent.
pub fn layouts() -> Vec<(String, Layout)> {
    let a = LobeKind::Anisotropic;
    let i = LobeKind::Isotropic;
    let b = |k: &[LobeKind]| Layout::builder(k);
    vec![
        ("aniso/log1p".into(), b(&[a]).build().expect("layout")),
        (
            "aniso+iso/raw".into(),
            b(&[a, i])
                .exponent_coord(ExponentCoord::Raw)
                .build()
                .expect("layout"),
        ),
        ("iso+iso/log1p".into(), b(&[i, i]).build().expect("layout")),
        (
            "aniso pan=0 fixed/log1p".into(),
            b(&[a])
                .fix("lobe1.pan", 0.0)
                .expect("fix")
                .build()
                .expect("layout"),
        ),
        (
            "aniso pan=60 n=2.5 fixed + aniso/raw".into(),
            b(&[a, a])
                .fix("lobe1.pan", 60.0)
                .expect("fix")
                .fix("lobe1.n", 2.5)
                .expect("fix")
                .exponent_coord(ExponentCoord::Raw)
                .build()
                .expect("layout"),
        ),
    ]
}

/// Error statistics of one kernel's values in one regime.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RegimeStat {
    /// The regime.
    pub regime: Regime,
    /// Values judged (finite reference above the floor).
    pub count: usize,
    /// Largest error in ulps of the reference value.
    pub max_ulps: f64,
    /// 99.9th percentile of the error in ulps.
    pub p999_ulps: f64,
    /// Largest error divided by the allowed forward-error bound (must be <= 1).
    pub max_normalised: f64,
}

/// Accuracy of one Jacobian column kind (`cx`, `n`, ...) of one kernel.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ColumnStat {
    /// Column kind (`kd`, `cx`, `cy`, `cxy`, `cz`, `n`, `pan`).
    pub role: String,
    /// Batch-columns whose relative error is measured (norm at least 1e-6 of the Jacobian's).
    pub columns: usize,
    /// Largest `||J_kernel - J_ref||_2 / ||J_ref||_2` over batch-columns.
    pub max_rel_error: f64,
    /// 99.9th percentile of that relative error.
    pub p999_rel_error: f64,
    /// Largest entry error divided by its allowed bound (must be <= 1).
    pub max_normalised: f64,
    /// Entries not judged: within rounding of the clamp `d = 0`, where the derivative jumps.
    pub excluded_near_clamp: u64,
}

/// Everything measured for one kernel.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct KernelStats {
    /// Kernel name (brdf-model's `avx512`, `avx2`, `portable`, `scalar`; `scalar-libm` for
    /// `BrdfParams::value`).
    pub kernel: String,
    /// Values judged.
    pub values: usize,
    /// Largest value error in ulps.
    pub max_ulps: f64,
    /// 99.9th percentile of the value error in ulps.
    pub p999_ulps: f64,
    /// Median value error in ulps.
    pub median_ulps: f64,
    /// Largest value error over its forward-error bound (must be <= 1).
    pub max_normalised: f64,
    /// The point of the largest normalised value error (a reproducer).
    pub worst_value: String,
    /// Histogram of value errors: `(upper edge in ulps, count)`; edges 0, 0.5, 1, 2, 4, ...
    /// 2^40, then `inf` for anything larger.
    pub ulps_histogram: Vec<(f64, u64)>,
    /// Per-regime value statistics.
    pub by_regime: Vec<RegimeStat>,
    /// Per-column-kind Jacobian statistics (empty for `scalar-libm`).
    pub columns: Vec<ColumnStat>,
    /// Values whose class differs from the reference: NaN anywhere, or `+inf` versus finite
    /// (outside the rounding band of the overflow threshold). Must be 0.
    pub class_mismatches: u64,
    /// NaN or infinite Jacobian entries from a call that reported success. Must be 0.
    pub jacobian_nonfinite_on_success: u64,
    /// Calls that reported success although a value (or, for the Jacobian, a derivative)
    /// overflows. Must be 0.
    pub missed_overflow: u64,
    /// Calls that reported failure although nothing overflows in exact arithmetic (e.g. an
    /// intermediate product overflowing). Must be 0.
    pub spurious_failures: u64,
    /// Batches in which the reference overflows (the overflow path was exercised).
    pub overflow_batches: u64,
    /// Example of the first class or flag mismatch (a reproducer), if any.
    pub first_mismatch: Option<String>,
}

/// Result of section 1.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct KernelSection {
    /// Batches evaluated.
    pub batches: usize,
    /// Direction pairs per batch.
    pub batch_size: usize,
    /// Layout names, in the order batches cycle through them.
    pub layouts: Vec<String>,
    /// One entry per kernel.
    pub kernels: Vec<KernelStats>,
}

/// Per-kernel raw results of one batch.
#[derive(Default)]
struct Partial {
    /// (regime index, ulps or NaN when not resolved, normalised error).
    values: Vec<(u8, f64, f64)>,
    worst: (f64, String),
    /// (role kind, relative column error, max normalised, excluded).
    cols: Vec<(&'static str, f64, f64, u64)>,
    class_mismatches: u64,
    jac_nonfinite: u64,
    missed: u64,
    spurious: u64,
    first_mismatch: Option<String>,
}

const LIBM: &str = "scalar-libm";

/// Runs section 1: `batches` batches cycling through the layouts and regimes (plus
/// [`Regime::DataDirections`] when `data` is non-empty).
pub fn run(batches: usize, seed: u64, data: &[&DataSet]) -> KernelSection {
    let layouts = layouts();
    let mut regimes = REGIMES.to_vec();
    if data.iter().any(|d| !d.is_empty()) {
        regimes.push(Regime::DataDirections);
    }
    let levels = Kernel::available();
    let mut names: Vec<String> = levels.iter().map(|l| l.name().to_string()).collect();
    names.push(LIBM.into());
    let parts: Vec<(bool, Vec<Partial>)> = (0..batches)
        .into_par_iter()
        .map(|b| {
            let (lname, layout) = &layouts[b % layouts.len()];
            let regime = regimes[(b / layouts.len()) % regimes.len()];
            let mut rng = Pcg64::seed_from_u64(derive_seed(seed, 1, b as u64));
            let (x, set) = draw_batch(&mut rng, layout, regime, data);
            let tag = format!("batch {b} layout `{lname}` regime {regime:?} x = {x:?}");
            one_batch(layout, &x, &set, regime, &levels, &tag)
        })
        .collect();
    let overflow_batches = parts.iter().filter(|p| p.0).count() as u64;
    let kernels = names
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let ps: Vec<&Partial> = parts.iter().map(|p| &p.1[k]).collect();
            merge(name, &ps, &regimes, overflow_batches)
        })
        .collect();
    KernelSection {
        batches,
        batch_size: BATCH,
        layouts: layouts.into_iter().map(|l| l.0).collect(),
        kernels,
    }
}

fn merge(name: &str, ps: &[&Partial], regimes: &[Regime], overflow_batches: u64) -> KernelStats {
    let mut ulps: Vec<f64> = Vec::new();
    let mut max_norm: f64 = 0.0;
    let mut worst = String::new();
    let mut hist = vec![0u64; 43];
    let mut by_regime = Vec::new();
    for (ri, &regime) in regimes.iter().enumerate() {
        let mut u: Vec<f64> = Vec::new();
        let mut mn: f64 = 0.0;
        for p in ps {
            for &(r, ul, nm) in &p.values {
                if r as usize == ri {
                    mn = mn.max(nm);
                    if ul.is_finite() {
                        u.push(ul);
                    }
                }
            }
        }
        by_regime.push(RegimeStat {
            regime,
            count: u.len(),
            max_ulps: u.iter().copied().fold(0.0, f64::max),
            p999_ulps: percentile(&mut u, 0.999),
            max_normalised: mn,
        });
    }
    for p in ps {
        if p.worst.0 > max_norm {
            max_norm = p.worst.0;
            worst = p.worst.1.clone();
        }
        for &(_, ul, _) in &p.values {
            if ul.is_finite() {
                ulps.push(ul);
                let bin = if ul <= 0.5 {
                    0
                } else {
                    ((ul.log2().ceil() as i64) + 2).clamp(1, 42) as usize
                };
                hist[bin] += 1;
            }
        }
    }
    let edges = std::iter::once(0.5)
        .chain((0..41).map(|k| 2f64.powi(k)))
        .chain(std::iter::once(f64::INFINITY));
    let ulps_histogram = edges.zip(hist.iter().copied()).collect();
    let mut columns = Vec::new();
    for role in ["kd", "cx", "cy", "cxy", "cz", "n", "pan"] {
        let mut rel: Vec<f64> = Vec::new();
        let mut mn: f64 = 0.0;
        let mut excl = 0;
        for p in ps {
            for &(r, e, m, x) in &p.cols {
                if r == role {
                    if e.is_finite() {
                        rel.push(e);
                    }
                    mn = mn.max(m);
                    excl += x;
                }
            }
        }
        if rel.is_empty() && excl == 0 {
            continue;
        }
        columns.push(ColumnStat {
            role: role.into(),
            columns: rel.len(),
            max_rel_error: rel.iter().copied().fold(0.0, f64::max),
            p999_rel_error: percentile(&mut rel, 0.999),
            max_normalised: mn,
            excluded_near_clamp: excl,
        });
    }
    let values = ulps.len();
    KernelStats {
        kernel: name.into(),
        values,
        max_ulps: ulps.iter().copied().fold(0.0, f64::max),
        p999_ulps: percentile(&mut ulps, 0.999),
        median_ulps: percentile(&mut ulps, 0.5),
        max_normalised: max_norm,
        worst_value: worst,
        ulps_histogram,
        by_regime,
        columns,
        class_mismatches: ps.iter().map(|p| p.class_mismatches).sum(),
        jacobian_nonfinite_on_success: ps.iter().map(|p| p.jac_nonfinite).sum(),
        missed_overflow: ps.iter().map(|p| p.missed).sum(),
        spurious_failures: ps.iter().map(|p| p.spurious).sum(),
        overflow_batches,
        first_mismatch: ps.iter().find_map(|p| p.first_mismatch.clone()),
    }
}

/// A seeded internal vector and direction set for `regime`.
pub fn draw_batch(
    rng: &mut Pcg64,
    layout: &Layout,
    regime: Regime,
    data: &[&DataSet],
) -> (Vec<f64>, DataSet) {
    let (lo, hi) = (layout.lower(), layout.upper());
    let mut x: Vec<f64> = lo
        .iter()
        .zip(hi)
        .map(|(&l, &h)| l + (h - l) * rng.random::<f64>())
        .collect();
    let coord = layout.exponent_coord();
    let set = |x: &mut Vec<f64>, name: String, v: f64| {
        if let Some(j) = layout.free_index(&name) {
            x[j] = v;
        }
    };
    let lobes = layout.lobe_count();
    let pick = |rng: &mut Pcg64, v: &[f64]| v[rng.random_range(0..v.len())];
    for k in 1..=lobes {
        let c = |f: &str| format!("lobe{k}.{f}");
        match regime {
            Regime::SmallN => {
                let n = pick(rng, &[0.0, 1e-300, 1e-12, 1e-6, 1e-3, 0.5, 1.0]);
                set(&mut x, c("n"), coord.to_internal(n));
            }
            Regime::MaxN => {
                if let Some(j) = layout.free_index(&c("n")) {
                    x[j] = hi[j];
                }
            }
            Regime::NegativeD => {
                set(&mut x, c("cz"), -1.5 * rng.random::<f64>());
            }
            Regime::PanEdges => {
                set(
                    &mut x,
                    c("pan"),
                    pick(rng, &[-90.0, -45.0, 0.0, 45.0, 90.0]),
                );
                set(&mut x, c("cx"), pick(rng, &[-1.5, -1.0, 0.5]));
                set(&mut x, c("cy"), pick(rng, &[1.5, 0.8, -0.2]));
            }
            Regime::CEdges => {
                for f in ["cx", "cy", "cxy", "cz"] {
                    set(&mut x, c(f), pick(rng, &[-1.5, 0.0, 1.5]));
                }
            }
            _ => {}
        }
    }
    if regime == Regime::CEdges {
        set(&mut x, "kd".into(), pick(rng, &[0.0, 1.0]));
    }
    let mut d = DataSet::with_capacity(BATCH);
    for i in 0..BATCH {
        let (u, v) = match regime {
            Regime::DataDirections => {
                let src: Vec<&&DataSet> = data.iter().filter(|s| !s.is_empty()).collect();
                let s = src[rng.random_range(0..src.len())];
                let r = rng.random_range(0..s.len());
                (s.u(r), s.v(r))
            }
            Regime::Grazing if i % 5 != 0 => (grazing(rng), grazing(rng)),
            Regime::NegativeD if i % 4 == 0 => {
                // Orthogonal axes: every product is exactly 0, so d = 0 exactly.
                ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
            }
            Regime::Overflow if i == 0 => ([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]),
            _ => direction_pair(rng, i),
        };
        d.push(u, v, 0.0);
    }
    if regime == Regime::Overflow {
        // Lobe 1 gets Cz = 1.5 so d = 1.5 at normal incidence (sample 0); its exponent is
        // chosen so that the largest d^n of the batch is 10^t, t in [150, 330].
        set(&mut x, "lobe1.cz".into(), 1.5);
        let p = BrdfParams::try_from(&layout.decode(&x)).expect("a Lafortune layout");
        let l = p.lobes[0];
        let dmax = (0..BATCH)
            .map(|i| {
                let mut q = l;
                q.n = 1.0;
                q.value(d.u(i), d.v(i))
            })
            .fold(0.0, f64::max);
        let t = 150.0 + 180.0 * rng.random::<f64>();
        if dmax > 1.0 {
            let n = (t * std::f64::consts::LN_10 / dmax.ln()).min(10000.0);
            set(&mut x, "lobe1.n".into(), coord.to_internal(n));
        }
    }
    // Keep every coordinate inside the box (edges included).
    for (j, xj) in x.iter_mut().enumerate() {
        *xj = xj.clamp(lo[j], hi[j]);
    }
    (x, d)
}

fn grazing<R: Rng + ?Sized>(rng: &mut R) -> [f64; 3] {
    let phi = std::f64::consts::TAU * rng.random::<f64>();
    let z = match rng.random_range(0..4) {
        0 => 0.0,
        1 => 1e-8,
        _ => 1e-3 * rng.random::<f64>(),
    };
    let s = (1.0 - z * z).sqrt();
    [s * phi.cos(), s * phi.sin(), z]
}

/// A mix of uniform, in-plane, mirror, normal and axis-aligned pairs.
fn direction_pair<R: Rng + ?Sized>(rng: &mut R, i: usize) -> ([f64; 3], [f64; 3]) {
    match i % 10 {
        0 => {
            let ti = std::f64::consts::FRAC_PI_2 * rng.random::<f64>();
            let to = std::f64::consts::FRAC_PI_2 * rng.random::<f64>();
            let sgn = if rng.random::<bool>() { 1.0 } else { -1.0 };
            ([ti.sin(), 0.0, ti.cos()], [sgn * to.sin(), 0.0, to.cos()])
        }
        1 => {
            let u = uniform_hemisphere(rng);
            (u, [-u[0], -u[1], u[2]])
        }
        2 => ([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]),
        3 => ([1.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
        _ => (uniform_hemisphere(rng), uniform_hemisphere(rng)),
    }
}

fn ulp(x: f64) -> f64 {
    let a = x.abs();
    a.next_up() - a
}

/// Evaluates one batch with every kernel; returns whether the reference overflowed and one
/// partial result per kernel (the levels, then `scalar-libm`).
fn one_batch(
    layout: &Layout,
    x: &[f64],
    data: &DataSet,
    regime: Regime,
    levels: &[Kernel],
    tag: &str,
) -> (bool, Vec<Partial>) {
    let m = data.len();
    let p = layout.dim();
    let mut reference = Reference::new(layout, x);
    let roles: Vec<Role> = reference.roles().to_vec();
    let mut jref = vec![0.0; m * p];
    let mut jallow = vec![0.0; m * p];
    let mut row = vec![0.0; p];
    let mut row_allow = vec![0.0; p];
    let mut refs = Vec::with_capacity(m);
    for i in 0..m {
        let s = reference.sample(data.u(i), data.v(i), &mut row, &mut row_allow);
        for j in 0..p {
            jref[j * m + i] = row[j];
            jallow[j * m + i] = row_allow[j];
        }
        refs.push(s);
    }
    let ambiguous = refs.iter().any(|s| s.ambiguous);
    let value_overflow = refs.iter().any(|s| s.overflow_value);
    let deriv_overflow = value_overflow || refs.iter().any(|s| s.overflow_deriv);
    let ri = regime as u8;
    let mut out = Vec::new();
    let mut r = vec![0.0; m];
    let mut r2 = vec![0.0; m];
    let mut jac = vec![0.0; m * p];
    let samples = layout.prepare(data);
    for &level in levels {
        let mut part = Partial::default();
        let mut ev = Evaluator::new(layout);
        // Only available kernels are listed, so this cannot fail.
        let _ = ev.set_kernel(level);
        let ok_r = ev.residuals(x, &samples, &mut r);
        let ok_j = ev.residuals_and_jacobian(x, &samples, &mut r2, &mut jac);
        judge_values(&mut part, &refs, &r, ri, tag, data, "residuals");
        judge_values(
            &mut part,
            &refs,
            &r2,
            ri,
            tag,
            data,
            "residuals_and_jacobian",
        );
        if !ambiguous {
            for (flag, expect_fail, what) in [
                (ok_r, value_overflow, "residuals"),
                (ok_j, deriv_overflow, "residuals_and_jacobian"),
            ] {
                if flag == expect_fail {
                    if flag {
                        part.missed += 1;
                    } else {
                        part.spurious += 1;
                    }
                    part.first_mismatch.get_or_insert_with(|| {
                        format!("{tag}: {what} returned {flag}, reference overflow {expect_fail}")
                    });
                }
            }
        }
        if ok_j {
            let total: f64 = jref.iter().filter(|v| v.is_finite()).map(|v| v * v).sum();
            for (j, role) in roles.iter().enumerate() {
                let (mut num, mut den, mut mx, mut excl) = (0.0, 0.0, 0.0f64, 0u64);
                for i in 0..m {
                    let k = jac[j * m + i];
                    let (rf, al) = (jref[j * m + i], jallow[j * m + i]);
                    if !k.is_finite() {
                        part.jac_nonfinite += 1;
                        part.first_mismatch.get_or_insert_with(|| {
                            format!("{tag}: column {j} sample {i}: kernel {k} on success")
                        });
                        continue;
                    }
                    if al.is_infinite() {
                        excl += 1;
                        continue;
                    }
                    let e = (k - rf).abs();
                    num += e * e;
                    den += rf * rf;
                    mx = mx.max(e / al);
                }
                // Relative errors of columns negligible next to the whole Jacobian (1e-6 of its
                // norm, e.g. sin(2 pan) at pan = 90 rounded to 1.2e-16 instead of 0) are
                // meaningless; the entry bounds still judge them.
                let rel = if den > 1e-12 * total {
                    (num / den).sqrt()
                } else {
                    f64::NAN
                };
                part.cols.push((role.kind(), rel, mx, excl));
            }
        }
        out.push(part);
    }
    // The scalar powf model as a yardstick (values only).
    let mut part = Partial::default();
    let params = layout.decode(x);
    for (i, ri_) in r.iter_mut().enumerate() {
        *ri_ = params.value(data.u(i), data.v(i));
    }
    judge_values(&mut part, &refs, &r, ri, tag, data, LIBM);
    out.push(part);
    (value_overflow, out)
}

fn judge_values(
    part: &mut Partial,
    refs: &[crate::reference::SampleRef],
    vals: &[f64],
    regime: u8,
    tag: &str,
    data: &DataSet,
    what: &str,
) {
    for (i, (s, &k)) in refs.iter().zip(vals).enumerate() {
        let rf = s.value;
        let mismatch = if k.is_nan() {
            true
        } else if s.ambiguous {
            false
        } else {
            rf.hi.is_infinite() != k.is_infinite()
        };
        if mismatch {
            part.class_mismatches += 1;
            part.first_mismatch.get_or_insert_with(|| {
                format!(
                    "{tag}: {what} sample {i} u = {:?} v = {:?}: kernel {k}, reference {}",
                    data.u(i),
                    data.v(i),
                    rf.to_f64()
                )
            });
            continue;
        }
        if !(k.is_finite() && rf.hi.is_finite()) {
            continue;
        }
        let e = (DD::new(k) - rf).to_f64().abs();
        let norm = e / s.allowed;
        let r64 = rf.to_f64();
        let ulps = if r64.abs() >= crate::reference::FLOOR {
            e / ulp(r64)
        } else {
            f64::NAN
        };
        if norm > part.worst.0 {
            part.worst = (
                norm,
                format!(
                    "{tag}: {what} sample {i} u = {:?} v = {:?}: kernel {k:e}, reference {r64:e}, \
                     error {e:e} = {ulps:.1} ulps, allowed {:e}",
                    data.u(i),
                    data.v(i),
                    s.allowed
                ),
            );
        }
        part.values.push((regime, ulps, norm));
    }
}

/// How a set of values compares with the reference ([`judge`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Judgement {
    /// Values compared.
    pub values: usize,
    /// Largest error in ulps (values above the floor).
    pub max_ulps: f64,
    /// Largest error over its forward-error bound (a correct kernel stays <= 1).
    pub max_normalised: f64,
    /// NaN values, or `+inf` versus finite.
    pub class_mismatches: u64,
}

/// Compares `values[i]` (claimed `f(u_i, v_i)` of `layout` at internal `x`) with the
/// double-double reference: the same judgement the sweep applies to each kernel, for checking
/// any other implementation (or a deliberately wrong one).
pub fn judge(layout: &Layout, x: &[f64], data: &DataSet, values: &[f64]) -> Judgement {
    let mut reference = Reference::new(layout, x);
    let p = layout.dim();
    let (mut row, mut allow) = (vec![0.0; p], vec![0.0; p]);
    let refs: Vec<_> = (0..data.len())
        .map(|i| reference.sample(data.u(i), data.v(i), &mut row, &mut allow))
        .collect();
    let mut part = Partial::default();
    judge_values(&mut part, &refs, values, 0, "judge", data, "values");
    Judgement {
        values: part.values.len(),
        max_ulps: part
            .values
            .iter()
            .map(|v| v.1)
            .filter(|v| v.is_finite())
            .fold(0.0, f64::max),
        max_normalised: part.values.iter().map(|v| v.2).fold(0.0, f64::max),
        class_mismatches: part.class_mismatches,
    }
}
