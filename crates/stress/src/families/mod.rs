//! Section 1b: every model family beside Lafortune against a double-double reference of its
//! own formula, over the whole box, its edges, grazing directions and the horizon itself.
//!
//! For each family ([`references`] lists those with a reference) and each kernel the CPU runs,
//! seeded batches draw one layout (one anisotropic lobe, one isotropic lobe, two lobes), one
//! point `x` in the optimiser's coordinates from a [`FamilyRegime`] and [`BATCH`] direction
//! pairs. The values are compared with the family's formula evaluated in double-double
//! arithmetic ([`crate::dd`]), within [`VALUE_TOLERANCE`] of the value plus a term for the
//! lobes' condition ([`CONDITION_FACTOR`], [`LobeCondition`]: the rounding of the kernels'
//! inputs through an ill-conditioned exponent); each Jacobian column with five-point
//! differences of that formula in double-double (step [`STEP`]` (1 + |x_j|)`), scaled by the
//! column's largest reference entry (at least [`VALUE_FLOOR`]), within
//! [`JACOBIAN_TOLERANCE`]. Values below [`VALUE_FLOOR`] (the far tails of narrow lobes) are
//! compared absolutely. [`trace`] locates the largest errors (`examples/families_full.rs`). A
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

/// The step of the reference's differences, relative to `1 + |x_j|`. The five-point stencil
/// `(8 (f(x + h) - f(x - h)) - (f(x + 2h) - f(x - 2h))) / (12 h)` truncates at about
/// `h^4 f^(5) / 30`: for a Gaussian lobe `exp(-T)`, `(T' h)^4 / 30` relative with `T'` the
/// exponent's derivative by the coordinate (up to about 250 per degree of pan for a lobe of
/// roughness 0.001 turned by 90 degrees, 1400 per unit of `ln m`), 1e-20 at this step; the
/// central difference it replaced truncated at `(T' h)^2 / 6`, up to 8e-11 of a pan column.
/// Rounding: double-double values are good to about 1e-29 relative, so `1.5e-29 f / h`,
/// below 1e-19 of `f` and 2e-10 of the smallest column scale (`1e-10` of the largest value).
pub const STEP: f64 = 1e-9;

/// Values below this are compared absolutely (the relative error is taken against it), and
/// it is the smallest scale of a Jacobian column. The kernels' `exp` gives 0 below `e^-690`
/// (`brdf_model::lobes::EXP_CUT`) where double-double still has a value (down to `e^-746`),
/// and a lobe multiplies that by at most about `1e7`: values under `1e-285` that are 0 in the
/// kernels. Nothing of use is that small.
pub const VALUE_FLOOR: f64 = 1e-250;

/// A family's lobe in double-double: `fields` are the lobe's physical field values (the
/// family's order), `u` and `v` the directions.
pub type LobeReference = fn(fields: &[DD], u: [f64; 3], v: [f64; 3]) -> DD;

/// `u.h` (`= v.h`) of the directions normalised in double-double: `u` and `v` are unit only to
/// rounding, and the formulas' `u.h` is defined for unit vectors. Of the raw `f64` directions,
/// `u.h` and `v.h` differ by `(|u|^2 - |v|^2) / (2 |u + v|)`, up to 1e-10 relative near grazing
/// back-scatter (`u.h` small, where a lobe divides by it), and `1 - u.h` moves by about
/// `(|u|^2 + |v|^2 - 2) / 4` absolute, up to 1e-11 relative of Fresnel's `(1 - u.h)^5` near
/// retro-reflection: both are sensitivities to the rounding of the directions' lengths, not
/// errors of a kernel (the kernels compute `u.h = |u + v| / 2` and `1 - u.h = |u - v|^2 /
/// (2 (2 + |u + v|))`, identities of unit vectors that agree with this to a few ulps). The
/// half vector's direction is taken from the raw sum `u + v` in the references as in the
/// kernels: its direction is what sharp lobes are sensitive to, and the sum is the input.
pub(crate) fn cos_half(u: [f64; 3], v: [f64; 3]) -> DD {
    let unit = |w: [f64; 3]| {
        let w = w.map(DD::new);
        let l = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
        [w[0] / l, w[1] / l, w[2] / l]
    };
    let (u, v) = (unit(u), unit(v));
    let s = [u[0] + v[0], u[1] + v[1], u[2] + v[2]];
    let l = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
    (u[0] * s[0] + u[1] * s[1] + u[2] * s[2]) / l
}

/// A lobe's condition for the value check ([`CONDITION_FACTOR`]): `kappa` such that the
/// roundings of the kernels' inputs (the prepared columns, the pan's cosine and sine, the
/// physical parameters) move the lobe's logarithm by about `kappa eps`, of which the rounding
/// count is [`CONDITION_FACTOR`]. `fields` are the lobe's physical field values (the family's
/// order), `u`, `v` the directions. Finite wherever the lobe is not 0.
pub type LobeCondition = fn(fields: &[f64], u: [f64; 3], v: [f64; 3]) -> f64;

/// A family's reference: its lobe in double-double and the lobe's condition.
#[derive(Clone, Copy, Debug)]
pub struct FamilyReference {
    /// The family's name.
    pub name: &'static str,
    /// The lobe in double-double.
    pub lobe: LobeReference,
    /// The lobe's condition.
    pub condition: LobeCondition,
}

/// The relative value error the check allows whatever the condition: a formula rounds a
/// fixed number of times (a few tens of ulps with the fast `exp`'s truncation, 32 ulps), so
/// 1e-12 (4500 eps) is a wide margin, which a cancellation the check is meant to find (a
/// difference of nearly equal terms: `1 - u.h`, `1 - hz^2`, `ln` of a number near 1) leaves.
pub const VALUE_TOLERANCE: f64 = 1e-12;

/// The factor of the condition term of the value check: a value may be off by
/// [`VALUE_TOLERANCE`] of itself plus `CONDITION_FACTOR eps sum_k |lobe_k| kappa_k`
/// ([`LobeCondition`]), the error the roundings of the kernels' inputs cause through an
/// ill-conditioned exponent.
///
/// A lobe whose exponent is a quadratic form of rotated components, `T = x'^2 / ax^2 +
/// y'^2 / ay^2` with `x' = cos(p) x + sin(p) y` (Cook-Torrance's and Ward's slopes, GGX's `t`
/// and masking sums, Ashikhmin-Shirley's `(nu h'x^2 + nv h'y^2) g`), gets the prepared
/// components and the pan's cosine and sine rounded (`u + v`, the division by its z
/// component, `sin` of a rounded angle), so `x'` is off by about `3.5 eps A_x` with `A_x =
/// |cos(p) x| + |sin(p) y|`, and `T` by `2 |x'| A_x / ax^2` times that, plus `4 eps T` from
/// the roughness (`exp` of its coordinate, then `1 / (ax ax)`). Where `x'` is a small
/// difference of large terms (a sharp axis, `ax` = 0.001, across a half vector far from the
/// normal along a wide axis) this is far more than `T eps`: a search of such configurations
/// (`examples/families_condition.rs`) found 3.3e-10 relative for Cook-Torrance, 1.4e-10 for
/// Ward and 1.2e-12 for GGX, an error no `f64` evaluation from these inputs avoids. Each
/// family's `kappa` is the condition of its lobe's logarithm, `2 sum_a |x'_a| A_a / a^2` for
/// such a form (at least `2 T`, equal where nothing cancels; see each family's module); 8
/// covers the count above (about 5.5 per unit of `kappa`) with margin: the search's largest
/// error is 2.7 `eps kappa`.
pub const CONDITION_FACTOR: f64 = 8.0;

/// The Jacobian error the check allows, relative to the column's scale: an analytic
/// derivative is exact to rounding (the same conditions as the value's, relative to the
/// column's largest entry); a missing or wrong term of the chain rule shows at 1e-3 or worse.
pub const JACOBIAN_TOLERANCE: f64 = 1e-8;

/// `2 (wx |x'| A_x + wy |y'| A_y)` for `(x, y)` rotated by `pan` degrees (`x' = c x + s y`,
/// `y' = c y - s x`, `A_x = |c x| + |s y|`, `A_y = |c y| + |s x|`): the condition, in units of
/// the rounding of the components, of `wx x'^2 + wy y'^2` ([`CONDITION_FACTOR`]).
pub(crate) fn rotated_condition(x: f64, y: f64, pan: f64, wx: f64, wy: f64) -> f64 {
    let (s, c) = pan.to_radians().sin_cos();
    let (xr, yr) = (c * x + s * y, c * y - s * x);
    let (ax, ay) = ((c * x).abs() + (s * y).abs(), (c * y).abs() + (s * x).abs());
    2.0 * (wx * xr.abs() * ax + wy * yr.abs() * ay)
}

/// The families with a double-double reference.
pub fn references() -> Vec<FamilyReference> {
    use brdf_model::models::{ashikhmin_shirley as asm, blinn_phong as bpm, cook_torrance as ctm};
    use brdf_model::models::{ggx as ggxm, ward as wm};
    let r = |name, lobe, condition| FamilyReference {
        name,
        lobe,
        condition,
    };
    vec![
        r(ggxm::NAME, ggx::lobe, ggx::condition),
        r(ctm::NAME, cook_torrance::lobe, cook_torrance::condition),
        r(bpm::NAME, blinn_phong::lobe, blinn_phong::condition),
        r(wm::NAME, ward::lobe, ward::condition),
        r(wm::GMD_NAME, ward::lobe_gmd, ward::condition),
        r(
            asm::NAME,
            ashikhmin_shirley::lobe,
            ashikhmin_shirley::condition,
        ),
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
    /// Largest value error over its bound ([`VALUE_TOLERANCE`] of the value plus the
    /// condition term, [`CONDITION_FACTOR`]); the check wants at most 1.
    #[serde(default)]
    pub max_value_normalised: f64,
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
    for (fi, reference) in references().into_iter().enumerate() {
        let name = reference.name;
        let fam = family(name).expect("a registered family");
        let per_batch = run_family(&fam, &reference, fi, batches, seed);
        for k in Kernel::available() {
            let mut s = FamilyKernelStats {
                family: name.to_string(),
                kernel: k.name().to_string(),
                ..FamilyKernelStats::default()
            };
            for (one, _) in per_batch
                .iter()
                .flatten()
                .filter(|o| o.0.kernel == k.name())
            {
                s.values += one.values;
                s.max_value_error = s.max_value_error.max(one.max_value_error);
                s.max_value_normalised = s.max_value_normalised.max(one.max_value_normalised);
                s.max_jacobian_error = s.max_jacobian_error.max(one.max_jacobian_error);
                s.mismatches += one.mismatches;
                s.nans += one.nans;
            }
            stats.push(s);
        }
    }
    FamilySection { batches, stats }
}

/// The batches of one family (`fi` its index in [`references`]), in parallel.
fn run_family(
    fam: &FamilyRef,
    reference: &FamilyReference,
    fi: usize,
    batches: usize,
    seed: u64,
) -> Vec<Vec<(FamilyKernelStats, Where)>> {
    (0..batches)
        .into_par_iter()
        .map(|b| batch(fam, reference, family_seed(seed, fi, b), b).0)
        .collect()
}

fn family_seed(seed: u64, fi: usize, b: usize) -> u64 {
    derive_seed(seed, 40 + fi as u64, b as u64)
}

/// Where one kernel's largest errors of a batch are: the sample of the largest value error
/// over its bound, and the column and sample of the largest Jacobian error.
#[derive(Clone, Copy, Debug, Default)]
struct Where {
    value_sample: usize,
    jacobian: (usize, usize),
}

/// One of the largest errors of a family, located (see [`trace`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TracedError {
    /// The error, as the section measures it (relative to `scale`).
    pub error: f64,
    /// The error over the check's bound: for a value, over [`VALUE_TOLERANCE`] of `scale`
    /// plus the condition term ([`CONDITION_FACTOR`]); for a Jacobian entry, over
    /// [`JACOBIAN_TOLERANCE`] of `scale`.
    pub normalised: f64,
    /// For a value, the condition term's share of the bound: `CONDITION_FACTOR eps
    /// sum_k |lobe_k| kappa_k` over `scale` (0 for a Jacobian entry).
    pub condition: f64,
    /// The batch (its regime and layout follow from it).
    pub batch: usize,
    /// The batch's regime.
    pub regime: FamilyRegime,
    /// The layout's lobe kinds.
    pub kinds: Vec<LobeKind>,
    /// The point in the optimiser's coordinates.
    pub x: Vec<f64>,
    /// The point's physical fields, as the family's JSON.
    pub params: String,
    /// The Jacobian column's free parameter (`None` for a value error).
    pub column: Option<String>,
    /// The incident and exitant direction of the sample.
    pub u: [f64; 3],
    /// The exitant direction.
    pub v: [f64; 3],
    /// The kernel's value (or Jacobian entry).
    pub kernel: f64,
    /// The reference's value (or central difference).
    pub reference: f64,
    /// The scale the error is relative to (the reference value, the floor, or the column's
    /// largest reference entry).
    pub scale: f64,
}

/// The largest value and Jacobian errors of one family and kernel, located.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FamilyTrace {
    /// The family.
    pub family: String,
    /// The kernel.
    pub kernel: String,
    /// The largest relative value error (as [`FamilyKernelStats::max_value_error`]).
    pub max_value_error: f64,
    /// The `top` largest value errors over their bounds, largest first (one per batch).
    pub values: Vec<TracedError>,
    /// The `top` largest Jacobian errors, largest first (one per batch).
    pub jacobians: Vec<TracedError>,
}

/// Runs the section as [`run`] does (the same batches for the same `batches` and `seed`) and
/// locates, per family and kernel, the batches of the `top` largest value and Jacobian
/// errors: the regime, the layout, the point and the direction pair of each, so that an
/// excess can be traced to its cause (`examples/families_full.rs` prints them).
pub fn trace(batches: usize, seed: u64, top: usize) -> Vec<FamilyTrace> {
    let mut out = Vec::new();
    for (fi, reference) in references().into_iter().enumerate() {
        let name = reference.name;
        let fam = family(name).expect("a registered family");
        let per_batch = run_family(&fam, &reference, fi, batches, seed);
        for k in Kernel::available() {
            let mut rows: Vec<(usize, &FamilyKernelStats, Where)> = per_batch
                .iter()
                .enumerate()
                .flat_map(|(b, v)| v.iter().map(move |(s, w)| (b, s, *w)))
                .filter(|(_, s, _)| s.kernel == k.name())
                .collect();
            let locate = |b: usize, w: Where, value: bool| {
                let mut t = batch(&fam, &reference, family_seed(seed, fi, b), b)
                    .1
                    .locate(k, w, value);
                t.batch = b;
                t
            };
            rows.sort_by(|a, b| {
                b.1.max_value_normalised
                    .total_cmp(&a.1.max_value_normalised)
            });
            let values = rows
                .iter()
                .take(top)
                .map(|&(b, _, w)| locate(b, w, true))
                .collect();
            rows.sort_by(|a, b| b.1.max_jacobian_error.total_cmp(&a.1.max_jacobian_error));
            let jacobians = rows
                .iter()
                .take(top)
                .map(|&(b, _, w)| locate(b, w, false))
                .collect();
            out.push(FamilyTrace {
                family: name.to_string(),
                kernel: k.name().to_string(),
                max_value_error: rows.iter().fold(0.0, |a, r| r.1.max_value_error.max(a)),
                values,
                jacobians,
            });
        }
    }
    out
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

/// The physical fields at internal point `x` in double-double (the coordinates mapped in
/// double-double too): `kd` and each lobe's fields.
fn reference_fields(layout: &Layout, x: &[DD]) -> (DD, Vec<Vec<DD>>) {
    let defaults: Vec<DD> = layout
        .family()
        .lobe_fields()
        .iter()
        .map(|f| DD::new(f.default))
        .collect();
    let mut kd = DD::ZERO;
    let mut lobes = vec![defaults; layout.lobe_count()];
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
    (kd, lobes)
}

/// The reference Jacobian (column-major, `m` rows): five-point differences ([`STEP`]) of the
/// one term each free parameter moves (`kd` or its lobe), the other terms being equal at every
/// point of the stencil.
fn reference_jacobian(layout: &Layout, x: &[f64], lobe: LobeReference, data: &DataSet) -> Vec<f64> {
    let (m, p) = (data.len(), layout.dim());
    let mut jref = vec![0.0; m * p];
    for j in 0..p {
        let h = STEP * (1.0 + x[j].abs());
        let at = |k: f64| {
            let mut xk: Vec<DD> = x.iter().map(|&v| DD::new(v)).collect();
            xk[j] = xk[j] + DD::new(k * h);
            reference_fields(layout, &xk)
        };
        let stencil = [at(1.0), at(-1.0), at(2.0), at(-2.0)];
        let owner = layout.free_param(j).expect("a free parameter").lobe;
        for i in 0..m {
            let term = |(kd, lobes): &(DD, Vec<Vec<DD>>)| match owner {
                None => *kd,
                Some(k) => lobe(&lobes[k], data.u(i), data.v(i)),
            };
            let [f1, fm1, f2, fm2] = stencil.each_ref().map(term);
            jref[j * m + i] = (((f1 - fm1) * 8.0 - (f2 - fm2)) / (12.0 * h)).to_f64();
        }
    }
    jref
}

/// One batch's inputs and references, kept to locate its largest errors.
struct Batch {
    regime: FamilyRegime,
    layout: Layout,
    x: Vec<f64>,
    data: DataSet,
    refs: Vec<f64>,
    /// Per sample, the condition term of the value's bound: `CONDITION_FACTOR eps sum_k
    /// |lobe_k| kappa_k`.
    conds: Vec<f64>,
    jref: Vec<f64>,
    /// The floor of the Jacobian columns' scales.
    floor: f64,
}

impl Batch {
    /// Kernel `k`'s values and Jacobian at the batch's point.
    fn kernel(&self, k: Kernel) -> (bool, Vec<f64>, bool, Vec<f64>) {
        let (m, p) = (self.data.len(), self.layout.dim());
        let samples = self.layout.prepare(&self.data);
        let mut ev = Evaluator::with_kernel(&self.layout, k).expect("an available kernel");
        let (mut r, mut jac) = (vec![0.0; m], vec![0.0; m * p]);
        let ok_r = ev.residuals(&self.x, &samples, &mut r);
        let mut r2 = vec![0.0; m];
        let ok_j = ev.residuals_and_jacobian(&self.x, &samples, &mut r2, &mut jac);
        (ok_r, r, ok_j, jac)
    }

    /// The scale of sample `i`'s value error: its reference value (at least [`VALUE_FLOOR`]),
    /// or 1 where the reference is 0 (compared absolutely).
    fn value_scale(&self, i: usize) -> f64 {
        let rf = self.refs[i];
        if rf == 0.0 {
            1.0
        } else {
            rf.abs().max(VALUE_FLOOR)
        }
    }

    /// Sample `i`'s value error relative to its scale, and over its bound.
    fn value_error(&self, i: usize, v: f64) -> (f64, f64) {
        let scale = self.value_scale(i);
        let e = (v - self.refs[i]).abs();
        (e / scale, e / (VALUE_TOLERANCE * scale + self.conds[i]))
    }

    /// The scale of Jacobian column `j` (its largest finite reference entry, at least the
    /// floor), `None` where a reference entry is not finite.
    fn column_scale(&self, j: usize) -> Option<f64> {
        let m = self.data.len();
        let rc = &self.jref[j * m..(j + 1) * m];
        let scale = rc.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        scale.is_finite().then(|| scale.max(self.floor))
    }

    fn locate(&self, k: Kernel, w: Where, value: bool) -> TracedError {
        let m = self.data.len();
        let (_, r, _, jac) = self.kernel(k);
        let (i, column, got, want, scale, normalised, condition) = if value {
            let i = w.value_sample;
            let scale = self.value_scale(i);
            let (_, n) = self.value_error(i, r[i]);
            (i, None, r[i], self.refs[i], scale, n, self.conds[i] / scale)
        } else {
            let (j, i) = w.jacobian;
            let name = self.layout.free_names()[j].clone();
            let scale = self.column_scale(j).unwrap_or(f64::NAN);
            let (got, want) = (jac[j * m + i], self.jref[j * m + i]);
            let n = (got - want).abs() / (JACOBIAN_TOLERANCE * scale);
            (i, Some(name), got, want, scale, n, 0.0)
        };
        TracedError {
            error: (got - want).abs() / scale,
            normalised,
            condition,
            batch: usize::MAX,
            regime: self.regime,
            kinds: self.layout.kinds().to_vec(),
            x: self.x.clone(),
            params: serde_json::to_string(&self.layout.decode(&self.x))
                .expect("parameters serialise"),
            column,
            u: self.data.u(i),
            v: self.data.v(i),
            kernel: got,
            reference: want,
            scale,
        }
    }
}

fn batch(
    fam: &FamilyRef,
    reference: &FamilyReference,
    seed: u64,
    b: usize,
) -> (Vec<(FamilyKernelStats, Where)>, Batch) {
    let mut rng = Pcg64::seed_from_u64(seed);
    let regime = REGIMES[b % REGIMES.len()];
    let layout = layout_for(fam, b / REGIMES.len());
    let x = point(&layout, regime, &mut rng);
    let data = directions(regime, &mut rng);
    let (m, p) = (data.len(), layout.dim());
    let xdd: Vec<DD> = x.iter().map(|&v| DD::new(v)).collect();
    let (kd, lobes) = reference_fields(&layout, &xdd);
    let fields: Vec<Vec<f64>> = lobes
        .iter()
        .map(|l| l.iter().map(|f| f.to_f64()).collect())
        .collect();
    let (mut refs, mut conds) = (Vec::with_capacity(m), Vec::with_capacity(m));
    for i in 0..m {
        let (u, v) = (data.u(i), data.v(i));
        let (mut value, mut cond) = (kd, 0.0);
        for (l, f) in lobes.iter().zip(&fields) {
            let lobe = (reference.lobe)(l, u, v);
            value = value + lobe;
            let size = lobe.to_f64().abs();
            if size > 0.0 && size.is_finite() {
                cond += size * (reference.condition)(f, u, v);
            }
        }
        refs.push(value);
        conds.push(CONDITION_FACTOR * f64::EPSILON * cond);
    }
    let jref = reference_jacobian(&layout, &x, reference.lobe, &data);
    let finite_ref = refs.iter().all(|r| r.is_finite() && r.hi.abs() <= f64::MAX);
    // A column whose derivative vanishes (pan of a lobe with ax = ay) is compared absolutely,
    // against 1e-10 of the largest value: its analytic entries are rounding noise of that size.
    // A batch whose values all lie in a narrow lobe's far tails is compared against
    // VALUE_FLOOR.
    let largest = refs.iter().fold(0.0f64, |a, r| a.max(r.to_f64().abs()));
    let floor = (1e-10 * largest).max(VALUE_FLOOR);
    let this = Batch {
        regime,
        layout,
        x,
        data,
        refs: refs.iter().map(|r| r.to_f64()).collect(),
        conds,
        jref,
        floor,
    };
    let mut out = Vec::new();
    for k in Kernel::available() {
        let (ok_r, r, ok_j, jac) = this.kernel(k);
        let mut s = FamilyKernelStats {
            family: fam.name().to_string(),
            kernel: k.name().to_string(),
            values: m,
            ..FamilyKernelStats::default()
        };
        let mut w = Where::default();
        s.nans = r.iter().chain(&jac).filter(|v| v.is_nan()).count();
        s.mismatches = usize::from(ok_r != finite_ref) + usize::from(ok_j != ok_r);
        if ok_r {
            for (i, &v) in r.iter().enumerate() {
                let (e, n) = this.value_error(i, v);
                s.max_value_error = s.max_value_error.max(e);
                if n > s.max_value_normalised {
                    s.max_value_normalised = n;
                    w.value_sample = i;
                }
            }
        }
        if ok_j {
            for j in 0..p {
                let Some(scale) = this.column_scale(j) else {
                    continue;
                };
                let (col, rc) = (&jac[j * m..(j + 1) * m], &this.jref[j * m..(j + 1) * m]);
                for (i, (a, b)) in col.iter().zip(rc).enumerate() {
                    let e = (a - b).abs() / scale;
                    if e > s.max_jacobian_error {
                        s.max_jacobian_error = e;
                        w.jacobian = (j, i);
                    }
                }
            }
        }
        out.push((s, w));
    }
    (out, this)
}
