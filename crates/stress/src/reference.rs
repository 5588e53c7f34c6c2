//! The model and its analytic Jacobian in double-double arithmetic, mirroring
//! `brdf_model::BrdfParams::value` and the layout's internal coordinates exactly, plus the
//! forward-error bound each `f64` kernel must meet at every sample.
//!
//! The reference rotates the directions by pan (`u'x = cos p ux + sin p uy`,
//! `u'y = -sin p ux + cos p uy`), as `BrdfParams::value` does, rather than folding the rotation
//! into coefficients as the kernels do, so the two computations share no formula: the pan
//! derivative here is `pi/180 (Cx - Cy)(u'y v'x + u'x v'y)` from `du'x/dp = u'y`,
//! `du'y/dp = -u'x`. The exponent is `n = x` ([`ExponentCoord::Raw`]) or `n = expm1(x)`
//! ([`ExponentCoord::Log1p`], whose Jacobian column is `f ln d * e^x`), both in double-double.
//! Magnitudes are computed as logarithms first (`ln f = n ln d`, `ln g = ln n + ln f - ln d`),
//! so overflow of `f64` is decided in double-double and never produces NaN.
//!
//! # Error bounds (why each constant)
//! A kernel computes `d` in `f64` from at most four rounded products, three additions and a
//! rotation with rounded `cos`/`sin` (each term bounded by `A = (|Cx| + |Cy|) |u_xy| |v_xy| +
//! |Cz uz vz|`): absolute error at most [`K_D`]` eps A`. The relative error of `d^n` is then
//! `n K_D eps A / d` from `d`, plus the rounding of `n ln d` (and of `n` itself in the `Log1p`
//! coordinate), at most [`K_L`]` eps |n ln d|`, plus the kernel's own `exp`/`ln` error,
//! bounded by [`K_EXP`]` eps` (the degree-11 Taylor `exp` of brdf-model truncates at about
//! 7e-15 = 32 eps; `ln` is below 1 ulp). Within `K_D eps A` of `d = 0` the clamp may go
//! either way, so `(K_D eps A)^n` is allowed there. Values below [`FLOOR`] are not resolved:
//! no fit can see them next to data of 1e-6 or more.

use crate::dd::{DD, DEG, LN_MAX};
use brdf_model::{BrdfParams, ExponentCoord, Layout, LobeKind};

/// Allowed kernel `exp`/`ln` error in units of `eps` (exp truncation ~32 eps, ln < 1 ulp, sums).
pub const K_EXP: f64 = 64.0;
/// Allowed error of `d` in units of `eps A` (four products, three sums, rotation).
pub const K_D: f64 = 8.0;
/// Allowed error of `n ln d` in units of `eps |n ln d|` (rounding of the product and of `n`).
pub const K_L: f64 = 4.0;
/// Absolute floor of every bound: values below 1e-300 cannot influence a fit.
pub const FLOOR: f64 = 1e-300;
/// The vector kernels give `d^n = 0` below about `2^-1010` (brdf-model's `EXP_FLUSH_K`: no
/// subnormal arithmetic), and with it every derivative computed from it: `n d^n / d` and
/// `d^n ln d` may then be 0 however large `1/d` makes them. Below this reference `d^n` (a
/// margin of one binade for the kernel's own error) a zero entry is allowed.
pub const FLUSHED_BELOW: f64 = 1.4e-304;
const EPS: f64 = f64::EPSILON;

/// What a Jacobian column differentiates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// The constant term.
    Kd,
    /// Cx of lobe k.
    Cx(usize),
    /// Cy of lobe k.
    Cy(usize),
    /// Cxy (isotropic) of lobe k.
    Cxy(usize),
    /// Cz of lobe k.
    Cz(usize),
    /// Exponent (internal coordinate) of lobe k.
    N(usize),
    /// Pan (degrees) of lobe k.
    Pan(usize),
}

impl Role {
    /// Short name of the role without the lobe number (`"cx"`, `"n"`, ...).
    pub fn kind(self) -> &'static str {
        match self {
            Role::Kd => "kd",
            Role::Cx(_) => "cx",
            Role::Cy(_) => "cy",
            Role::Cxy(_) => "cxy",
            Role::Cz(_) => "cz",
            Role::N(_) => "n",
            Role::Pan(_) => "pan",
        }
    }
}

#[derive(Clone, Copy, Debug)]
struct RefLobe {
    aniso: bool,
    cx: f64,
    cy: f64,
    cz: f64,
    n: DD,
    ln_n: DD,
    /// `dn/dx` of the internal coordinate, and its logarithm.
    ln_scale: DD,
    scale: f64,
    sin: DD,
    cos: DD,
}

/// One lobe's quantities at one sample (per-sample scratch, no allocation).
#[derive(Clone, Copy, Debug, Default)]
struct LobeAt {
    d: f64,
    a: f64,
    f: f64,
    f_dd: DD,
    /// `n d^n / d` (0 when `d <= 0` or `n = 0`).
    g: f64,
    /// `d^n ln d dn/dx`.
    h: f64,
    ln_d: f64,
    l: f64,
    /// `d(d)/d theta` weights: P', Q', S and the pan factor.
    p: f64,
    q: f64,
    s: f64,
    pan: f64,
    hu_hv: f64,
    near_clamp: bool,
    overflow: bool,
    ambiguous: bool,
}

/// The reference value of one sample and the facts needed to judge a kernel there.
#[derive(Clone, Copy, Debug)]
pub struct SampleRef {
    /// `f` in double-double ([`DD::INF`] on overflow).
    pub value: DD,
    /// Allowed absolute error of a kernel's value.
    pub allowed: f64,
    /// The value or a derivative overflows `f64`.
    pub overflow_value: bool,
    /// A derivative (`n d^n / d` or `d^n ln d`) overflows `f64`.
    pub overflow_deriv: bool,
    /// A log-magnitude lies within rounding of `ln(f64::MAX)`: either outcome is right.
    pub ambiguous: bool,
}

/// The reference model at one internal parameter vector.
#[derive(Clone, Debug)]
pub struct Reference {
    kd: DD,
    lobes: Vec<RefLobe>,
    roles: Vec<Role>,
    /// Whether each lobe's exponent is free (the kernel checks `d^n ln d` only then).
    n_free: Vec<bool>,
    at: Vec<LobeAt>,
}

impl Reference {
    /// Builds the reference for `layout` at internal vector `x` (fixed parameters filled in).
    pub fn new(layout: &Layout, x: &[f64]) -> Reference {
        let p = BrdfParams::try_from(&layout.decode(x)).expect("a Lafortune layout");
        let coord = layout.exponent_coord();
        let lobes = layout
            .kinds()
            .iter()
            .enumerate()
            .map(|(k, kind)| {
                let l = p.lobes[k];
                let (n, scale) = match layout.free_index(&format!("lobe{}.n", k + 1)) {
                    Some(j) => match coord {
                        ExponentCoord::Raw => (DD::new(x[j]), DD::ONE),
                        ExponentCoord::Log1p => (DD::new(x[j]).exp_m1(), DD::new(x[j]).exp()),
                    },
                    None => (DD::new(l.n), DD::ONE),
                };
                let aniso = *kind == LobeKind::Anisotropic;
                let (sin, cos) = if aniso {
                    (DEG * l.pan_deg).sin_cos()
                } else {
                    (DD::ZERO, DD::ONE)
                };
                RefLobe {
                    aniso,
                    cx: l.cx,
                    cy: l.cy,
                    cz: l.cz,
                    n,
                    ln_n: if n.hi > 0.0 { n.ln() } else { DD::ZERO },
                    ln_scale: scale.ln(),
                    scale: scale.to_f64(),
                    sin,
                    cos,
                }
            })
            .collect::<Vec<_>>();
        let roles = layout
            .free_names()
            .iter()
            .map(|name| role_of(name))
            .collect::<Vec<_>>();
        let n_free = (0..lobes.len())
            .map(|k| roles.contains(&Role::N(k)))
            .collect();
        Reference {
            n_free,
            kd: DD::new(p.kd),
            at: vec![LobeAt::default(); lobes.len()],
            lobes,
            roles,
        }
    }

    /// The roles of the free parameters, in free-vector order.
    pub fn roles(&self) -> &[Role] {
        &self.roles
    }

    /// Evaluates sample `(u, v)`: returns the value, writes the reference Jacobian row into
    /// `jac` and the allowed absolute error of each entry into `allowed` (`+inf`: not judged,
    /// the sample is within rounding of the clamp `d = 0` where the derivative jumps).
    pub fn sample(
        &mut self,
        u: [f64; 3],
        v: [f64; 3],
        jac: &mut [f64],
        allowed: &mut [f64],
    ) -> SampleRef {
        let hu = u[0].hypot(u[1]);
        let hv = v[0].hypot(v[1]);
        let mut allowed_v = 2.0 * EPS * self.kd.hi.abs() + FLOOR;
        let mut out = SampleRef {
            value: DD::ZERO,
            allowed: 0.0,
            overflow_value: false,
            overflow_deriv: false,
            ambiguous: false,
        };
        for (k, (lb, at)) in self.lobes.iter().zip(self.at.iter_mut()).enumerate() {
            *at = lobe_at(lb, u, v, hu, hv);
            let a = at.a;
            if at.near_clamp {
                allowed_v += if lb.n.hi == 0.0 {
                    1.0
                } else {
                    (K_D * EPS * a).powf(lb.n.hi).min(1.0)
                };
            }
            if at.d > 0.0 && !at.overflow {
                allowed_v += EPS * at.f * rel_factor(lb.n.hi, at);
            }
            out.overflow_deriv |= at.g.is_infinite() || (self.n_free[k] && at.h.is_infinite());
            out.overflow_value |= at.overflow;
            out.ambiguous |= at.ambiguous;
        }
        // The sum in double-double (the f64 `f` kept per lobe is rounded).
        let mut sum = self.kd;
        let mut inf = false;
        for at in &self.at {
            if at.d > 0.0 {
                if at.overflow {
                    inf = true;
                } else {
                    sum = sum + at.f_dd;
                }
            }
        }
        out.value = if inf { DD::INF } else { sum };
        // Finite lobes can still overflow when summed.
        out.overflow_value |= !out.value.hi.is_finite();
        out.ambiguous |= out.value.hi.is_finite() && out.value.hi > f64::MAX * (1.0 - 1e-9);
        out.allowed = allowed_v;
        for (j, role) in self.roles.iter().enumerate() {
            let (val, allow) = match *role {
                Role::Kd => (1.0, FLOOR),
                Role::N(k) => {
                    let (lb, at) = (&self.lobes[k], &self.at[k]);
                    if at.near_clamp {
                        (at.h, f64::INFINITY)
                    } else if at.d <= 0.0 {
                        (0.0, FLOOR)
                    } else {
                        let f_rel = EPS * rel_factor(lb.n.hi, at);
                        let ld = at.ln_d.abs();
                        let allow =
                            at.f * lb.scale * (f_rel * ld + EPS * (2.0 * ld + K_D * at.a / at.d))
                                + FLOOR * lb.scale;
                        (at.h, flushed_allowance(at.f, at.h, allow))
                    }
                }
                Role::Cx(k) | Role::Cy(k) | Role::Cxy(k) | Role::Cz(k) | Role::Pan(k) => {
                    let (lb, at) = (&self.lobes[k], &self.at[k]);
                    let (w, aw) = match *role {
                        Role::Cx(_) => (at.p, 2.0 * at.hu_hv),
                        Role::Cy(_) => (at.q, 2.0 * at.hu_hv),
                        Role::Cxy(_) => (at.p + at.q, 2.0 * at.hu_hv),
                        Role::Cz(_) => (at.s, at.s.abs()),
                        _ => (at.pan, DEG.hi * (lb.cx - lb.cy).abs() * 2.0 * at.hu_hv),
                    };
                    if at.near_clamp {
                        (at.g * w, f64::INFINITY)
                    } else if at.d <= 0.0 {
                        (0.0, FLOOR)
                    } else if at.g.is_infinite() {
                        (f64::INFINITY, f64::INFINITY)
                    } else {
                        let n = lb.n.hi;
                        let g_rel =
                            EPS * (K_EXP + K_D * (n + 1.0) * at.a / at.d + K_L * at.l.abs());
                        let allow = at.g.abs() * (g_rel * w.abs() + K_D * EPS * aw) + FLOOR;
                        (at.g * w, flushed_allowance(at.f, at.g * w, allow))
                    }
                }
            };
            jac[j] = val;
            allowed[j] = allow;
        }
        out
    }
}

/// `allow`, or at least `2 |val|` (so that 0 passes with a margin) where the kernels flush
/// `f = d^n` to 0 ([`FLUSHED_BELOW`]).
fn flushed_allowance(f: f64, val: f64, allow: f64) -> f64 {
    if f < FLUSHED_BELOW {
        allow.max(2.0 * val.abs() + FLOOR)
    } else {
        allow
    }
}

/// `K_EXP + K_D n A / d + K_L |n ln d|`: the relative error allowed for `d^n`, in eps.
fn rel_factor(n: f64, at: &LobeAt) -> f64 {
    K_EXP + K_D * n * at.a / at.d.abs() + K_L * at.l.abs()
}

/// `d` of a lobe in double-double and the derivative weights `P'`, `Q'`, `S`, pan factor.
fn lobe_d(lb: &RefLobe, u: [f64; 3], v: [f64; 3]) -> (DD, DD, DD, DD, DD) {
    let s = DD::prod(u[2], v[2]);
    if lb.aniso {
        let ux = lb.cos * u[0] + lb.sin * u[1];
        let uy = -(lb.sin * u[0]) + lb.cos * u[1];
        let vx = lb.cos * v[0] + lb.sin * v[1];
        let vy = -(lb.sin * v[0]) + lb.cos * v[1];
        let p = ux * vx;
        let q = uy * vy;
        let d = p * lb.cx + q * lb.cy + s * lb.cz;
        let pan = DEG * (DD::new(lb.cx) - DD::new(lb.cy)) * (uy * vx + ux * vy);
        (d, p, q, s, pan)
    } else {
        let p = DD::prod(u[0], v[0]);
        let q = DD::prod(u[1], v[1]);
        let d = (p + q) * lb.cx + s * lb.cz;
        (d, p, q, s, DD::ZERO)
    }
}

/// True when `l` is within rounding of the `f64` overflow threshold in log space.
fn near_overflow(l: DD) -> bool {
    (l - LN_MAX).to_f64().abs() < 1e-9 * (1.0 + l.hi.abs())
}

fn lobe_at(lb: &RefLobe, u: [f64; 3], v: [f64; 3], hu: f64, hv: f64) -> LobeAt {
    let (d, p, q, s, pan) = lobe_d(lb, u, v);
    let a = (lb.cx.abs() + lb.cy.abs()) * hu * hv + (lb.cz * u[2] * v[2]).abs();
    let mut at = LobeAt {
        d: d.to_f64(),
        a,
        p: p.to_f64(),
        q: q.to_f64(),
        s: s.to_f64(),
        pan: pan.to_f64(),
        hu_hv: hu * hv,
        near_clamp: d.hi.abs() <= K_D * EPS * a,
        ..LobeAt::default()
    };
    if d.hi.is_nan() || d.hi <= 0.0 {
        return at;
    }
    let ln_d = d.ln();
    let l = lb.n * ln_d;
    at.ln_d = ln_d.to_f64();
    at.l = l.to_f64();
    let f = l.exp();
    at.f = f.to_f64();
    at.f_dd = f;
    at.overflow = !f.hi.is_finite();
    at.ambiguous |= near_overflow(l);
    if lb.n.hi > 0.0 {
        let lg = lb.ln_n + l - ln_d;
        at.ambiguous |= near_overflow(lg);
        at.g = lg.exp().to_f64();
    }
    if ln_d.hi != 0.0 {
        let lh = l + ln_d.abs().ln() + lb.ln_scale;
        at.ambiguous |= near_overflow(lh);
        at.h = lh.exp().to_f64().copysign(ln_d.hi);
    }
    at
}

/// Parses a free-parameter name of brdf-model (`kd`, `lobeK.cx`, ...).
fn role_of(name: &str) -> Role {
    if name == "kd" {
        return Role::Kd;
    }
    let rest = name.strip_prefix("lobe").unwrap_or(name);
    let (k, field) = rest.split_once('.').unwrap_or(("1", "kd"));
    let k: usize = k.parse::<usize>().unwrap_or(1) - 1;
    match field {
        "cx" => Role::Cx(k),
        "cy" => Role::Cy(k),
        "cxy" => Role::Cxy(k),
        "cz" => Role::Cz(k),
        "n" => Role::N(k),
        "pan" => Role::Pan(k),
        _ => Role::Kd,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use brdf_model::named_params;

    /// On benign points the double-double reference agrees with the f64 libm scalar model
    /// (`BrdfParams::value`, `powf`) to 1e-14 relative: the reference mirrors the model.
    #[test]
    fn agrees_with_libm_on_benign_points() {
        let layout = Layout::builder(&[LobeKind::Anisotropic, LobeKind::Isotropic])
            .build()
            .unwrap();
        let mut p = named_params("tuning").unwrap();
        p.lobes.push(brdf_model::Lobe::isotropic(0.5, 0.7, 3.0));
        let x = layout.encode(&p);
        let mut r = Reference::new(&layout, &x);
        let mut jac = vec![0.0; layout.dim()];
        let mut allowed = vec![0.0; layout.dim()];
        let q = layout.decode(&x);
        let mut worst: f64 = 0.0;
        for i in 0..200 {
            let t = i as f64 * 0.0071;
            let u = [t.sin() * 0.6, t.cos() * 0.3, 0.0];
            let u = [u[0], u[1], (1.0 - u[0] * u[0] - u[1] * u[1]).sqrt()];
            let v = [-u[1] * 0.8, u[0] * 0.9, 0.0];
            let v = [v[0], v[1], (1.0 - v[0] * v[0] - v[1] * v[1]).sqrt()];
            let s = r.sample(u, v, &mut jac, &mut allowed);
            let libm = q.value(u, v);
            worst = worst.max(((s.value - DD::new(libm)).to_f64() / libm).abs());
        }
        assert!(worst < 1e-14, "worst {worst:e}");
    }
}
