//! Section 1b: every model family beside Lafortune against a double-double reference of its
//! own formula, over the whole box, its edges, grazing directions and the horizon itself.
//!
//! For each family ([`references`] lists those with a reference) and each kernel the CPU runs,
//! seeded batches draw one layout (one anisotropic lobe, one isotropic lobe, two lobes), one
//! point `x` in the optimiser's coordinates from a [`FamilyRegime`] and [`BATCH`] direction
//! pairs. The values are compared with the family's formula evaluated in double-double
//! arithmetic ([`crate::dd`]); each Jacobian column with central differences of that formula
//! in double-double (step `1e-9 (1 + |x_j|)`, so truncation and rounding stay below 1e-16
//! relative), scaled by the column's largest reference entry (at least [`VALUE_FLOOR`]).
//! Values below [`VALUE_FLOOR`] (the far tails of narrow lobes) are compared absolutely. A
//! kernel that reports a failed evaluation where the reference is finite and below `f64::MAX`
//! (or the other way round) counts as a mismatch: a family whose value on the horizon is
//! `+inf` (Ward's) fails every [`FamilyRegime::Horizon`] batch, in the kernels as in its
//! reference.

mod ashikhmin_shirley;
mod blinn_phong;
mod cook_torrance;
mod ggx;
mod ward;

use crate::dd::DD;
use crate::derive_seed;
use brdf_model::{
    Coord, DataSet, Evaluator, FamilyRef, Kernel, Layout, LobeKind, family, uniform_hemisphere,
};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Direction pairs per batch.
pub const BATCH: usize = 32;

/// Values below this are compared absolutely (the relative error is taken against it), and
/// it is the smallest scale of a Jacobian column. The kernels' `exp` gives 0 below `e^-690`
/// (`brdf_model::lobes::EXP_CUT`) where double-double still has a value (down to `e^-746`),
/// and a lobe multiplies that by at most about `1e7`: values under `1e-285` that are 0 in the
/// kernels. Nothing of use is that small.
pub const VALUE_FLOOR: f64 = 1e-250;

/// A family's lobe in double-double: `fields` are the lobe's physical field values (the
/// family's order), `u` and `v` the directions.
pub type LobeReference = fn(fields: &[DD], u: [f64; 3], v: [f64; 3]) -> DD;

/// The families with a double-double reference, by name.
pub fn references() -> Vec<(&'static str, LobeReference)> {
    use brdf_model::models::{ashikhmin_shirley as asm, blinn_phong as bpm, cook_torrance as ctm};
    use brdf_model::models::{ggx as ggxm, ward as wm};
    vec![
        (ggxm::NAME, ggx::lobe as LobeReference),
        (ctm::NAME, cook_torrance::lobe as LobeReference),
        (bpm::NAME, blinn_phong::lobe as LobeReference),
        (wm::NAME, ward::lobe as LobeReference),
        (wm::GMD_NAME, ward::lobe_gmd as LobeReference),
        (asm::NAME, ashikhmin_shirley::lobe as LobeReference),
    ]
}

/// How a batch's point and directions are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FamilyRegime {
    /// Uniform in the optimiser's box.
    Uniform,
    /// Shape parameters (roughness, exponent) at their lower bound: the sharpest lobes.
    SharpestShape,
    /// Shape parameters at their upper bound.
    WidestShape,
    /// Linear parameters at their bounds.
    Edges,
    /// Directions within 1e-3 rad of the horizon, not on it.
    Grazing,
    /// Directions exactly on the horizon: the incident one, the exitant one or both (a third
    /// each). Where a family's value there is `+inf` (Ward's), every such batch must fail in
    /// the kernels as in the reference; apart from [`FamilyRegime::Grazing`] so that the
    /// grazing batches of such a family still compare values.
    Horizon,
}

const REGIMES: [FamilyRegime; 6] = [
    FamilyRegime::Uniform,
    FamilyRegime::SharpestShape,
    FamilyRegime::WidestShape,
    FamilyRegime::Edges,
    FamilyRegime::Grazing,
    FamilyRegime::Horizon,
];

/// One family and kernel over all batches.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct FamilyKernelStats {
    /// The family.
    pub family: String,
    /// The kernel.
    pub kernel: String,
    /// Values compared.
    pub values: usize,
    /// Largest relative error of a value (`|f - ref| / |ref|`; reference values of 0 compared
    /// absolutely, those below [`VALUE_FLOOR`] relative to it).
    pub max_value_error: f64,
    /// Largest Jacobian error relative to its column's largest reference entry.
    pub max_jacobian_error: f64,
    /// Evaluations where the kernel's success differs from the reference's finiteness.
    pub mismatches: usize,
    /// NaN values or Jacobian entries.
    pub nans: usize,
}

/// The section: one entry per family and kernel.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct FamilySection {
    /// Batches per family.
    pub batches: usize,
    /// Statistics per family and kernel.
    pub stats: Vec<FamilyKernelStats>,
}

/// Runs `batches` batches per family with a reference.
pub fn run(batches: usize, seed: u64) -> FamilySection {
    let mut stats = Vec::new();
    for (fi, (name, reference)) in references().into_iter().enumerate() {
        let fam = family(name).expect("a registered family");
        let per_batch: Vec<Vec<FamilyKernelStats>> = (0..batches)
            .into_par_iter()
            .map(|b| {
                batch(
                    &fam,
                    reference,
                    derive_seed(seed, 40 + fi as u64, b as u64),
                    b,
                )
            })
            .collect();
        for k in Kernel::available() {
            let mut s = FamilyKernelStats {
                family: name.to_string(),
                kernel: k.name().to_string(),
                ..FamilyKernelStats::default()
            };
            for one in per_batch.iter().flatten().filter(|o| o.kernel == k.name()) {
                s.values += one.values;
                s.max_value_error = s.max_value_error.max(one.max_value_error);
                s.max_jacobian_error = s.max_jacobian_error.max(one.max_jacobian_error);
                s.mismatches += one.mismatches;
                s.nans += one.nans;
            }
            stats.push(s);
        }
    }
    FamilySection { batches, stats }
}

fn layout_for(fam: &FamilyRef, b: usize) -> Layout {
    let kinds = fam.kinds();
    let shape: Vec<LobeKind> = match b % 3 {
        0 => vec![kinds[0]],
        1 => vec![*kinds.last().expect("a family has a lobe kind")],
        _ => vec![kinds[0], *kinds.last().expect("a family has a lobe kind")],
    };
    Layout::builder_for(fam, &shape)
        .and_then(|b| b.build())
        .expect("a family's own kinds and bounds make a layout")
}

fn point(layout: &Layout, regime: FamilyRegime, rng: &mut Pcg64) -> Vec<f64> {
    let (lo, hi) = (layout.lower(), layout.upper());
    (0..layout.dim())
        .map(|j| {
            let p = layout.free_param(j).expect("a free parameter");
            let shape = p.def.role == brdf_model::Role::Shape;
            match regime {
                FamilyRegime::SharpestShape if shape => lo[j],
                FamilyRegime::WidestShape if shape => hi[j],
                FamilyRegime::Edges if !shape => {
                    if rng.random::<bool>() {
                        lo[j]
                    } else {
                        hi[j]
                    }
                }
                _ => rng.random_range(lo[j]..=hi[j]),
            }
        })
        .collect()
}

fn directions(regime: FamilyRegime, rng: &mut Pcg64) -> DataSet {
    let mut d = DataSet::new();
    for i in 0..BATCH {
        let mut u = uniform_hemisphere(rng);
        let mut v = uniform_hemisphere(rng);
        let on_horizon = |w: &mut [f64; 3], t: f64| {
            let r = (w[0] * w[0] + w[1] * w[1]).sqrt().max(1e-300);
            let s = t.cos();
            *w = [w[0] / r * s, w[1] / r * s, t.sin()];
        };
        match regime {
            FamilyRegime::Grazing => {
                for w in [&mut u, &mut v] {
                    // Never exactly 0: `random` is in [0, 1).
                    let t = 1e-3 * (1.0 - rng.random::<f64>());
                    on_horizon(w, t);
                }
            }
            FamilyRegime::Horizon => {
                if i % 3 != 1 {
                    on_horizon(&mut u, 0.0);
                }
                if i % 3 != 0 {
                    on_horizon(&mut v, 0.0);
                }
            }
            _ => {}
        }
        d.push(u, v, 0.0);
    }
    d
}

/// The model's value in double-double at internal point `x` (the coordinates mapped in
/// double-double too).
fn reference_value(layout: &Layout, x: &[DD], lobe: LobeReference, u: [f64; 3], v: [f64; 3]) -> DD {
    let nf = layout.family().lobe_fields().len();
    let mut kd = DD::ZERO;
    let mut lobes: Vec<Vec<DD>> = (0..layout.lobe_count())
        .map(|_| {
            layout
                .family()
                .lobe_fields()
                .iter()
                .map(|f| DD::new(f.default))
                .collect()
        })
        .collect();
    let mut next = 0;
    for p in layout.params() {
        let value = match p.fixed {
            Some(v) => DD::new(v),
            None => {
                let xi = x[next];
                next += 1;
                match p.coord {
                    Coord::Identity => xi,
                    Coord::Log1p => xi.exp_m1(),
                    Coord::Log => xi.exp(),
                }
            }
        };
        match p.lobe {
            None => kd = value,
            Some(k) => {
                for &f in p.def.fields {
                    lobes[k][f] = value;
                }
            }
        }
    }
    debug_assert!(lobes.iter().all(|l| l.len() == nf));
    lobes.iter().fold(kd, |acc, l| acc + lobe(l, u, v))
}

fn batch(fam: &FamilyRef, lobe: LobeReference, seed: u64, b: usize) -> Vec<FamilyKernelStats> {
    let mut rng = Pcg64::seed_from_u64(seed);
    let regime = REGIMES[b % REGIMES.len()];
    let layout = layout_for(fam, b / REGIMES.len());
    let x = point(&layout, regime, &mut rng);
    let data = directions(regime, &mut rng);
    let samples = layout.prepare(&data);
    let (m, p) = (data.len(), layout.dim());
    let xdd: Vec<DD> = x.iter().map(|&v| DD::new(v)).collect();
    let refs: Vec<DD> = (0..m)
        .map(|i| reference_value(&layout, &xdd, lobe, data.u(i), data.v(i)))
        .collect();
    let mut jref = vec![0.0; m * p];
    for j in 0..p {
        let h = 1e-9 * (1.0 + x[j].abs());
        let (mut xp, mut xm) = (xdd.clone(), xdd.clone());
        xp[j] = xp[j] + DD::new(h);
        xm[j] = xm[j] - DD::new(h);
        for i in 0..m {
            let fp = reference_value(&layout, &xp, lobe, data.u(i), data.v(i));
            let fm = reference_value(&layout, &xm, lobe, data.u(i), data.v(i));
            jref[j * m + i] = ((fp - fm) / (2.0 * h)).to_f64();
        }
    }
    let finite_ref = refs.iter().all(|r| r.is_finite() && r.hi.abs() <= f64::MAX);
    // A column whose derivative vanishes (pan of a lobe with ax = ay) is compared absolutely,
    // against 1e-10 of the largest value: its analytic entries are rounding noise of that size.
    // A batch whose values all lie in a narrow lobe's far tails is compared against
    // VALUE_FLOOR.
    let largest = refs.iter().fold(0.0f64, |a, r| a.max(r.to_f64().abs()));
    let floor = (1e-10 * largest).max(VALUE_FLOOR);
    let mut out = Vec::new();
    for k in Kernel::available() {
        let mut ev = Evaluator::with_kernel(&layout, k).expect("an available kernel");
        let (mut r, mut jac) = (vec![0.0; m], vec![0.0; m * p]);
        let ok_r = ev.residuals(&x, &samples, &mut r);
        let mut r2 = vec![0.0; m];
        let ok_j = ev.residuals_and_jacobian(&x, &samples, &mut r2, &mut jac);
        let mut s = FamilyKernelStats {
            family: fam.name().to_string(),
            kernel: k.name().to_string(),
            values: m,
            ..FamilyKernelStats::default()
        };
        s.nans = r.iter().chain(&jac).filter(|v| v.is_nan()).count();
        s.mismatches = usize::from(ok_r != finite_ref) + usize::from(ok_j != ok_r);
        if ok_r {
            for (v, rf) in r.iter().zip(&refs) {
                let rf = rf.to_f64();
                let e = if rf == 0.0 {
                    v.abs()
                } else {
                    (v - rf).abs() / rf.abs().max(VALUE_FLOOR)
                };
                s.max_value_error = s.max_value_error.max(e);
            }
        }
        if ok_j {
            for (col, rc) in jac.chunks(m.max(1)).zip(jref.chunks(m.max(1))) {
                let scale = rc.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                if !scale.is_finite() {
                    continue;
                }
                let scale = scale.max(floor);
                for (a, b) in col.iter().zip(rc) {
                    s.max_jacobian_error = s.max_jacobian_error.max((a - b).abs() / scale);
                }
            }
        }
        out.push(s);
    }
    out
}
