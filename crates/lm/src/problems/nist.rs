//! The NIST StRD nonlinear regression problems (27 data sets, two starts each, certified
//! values), with analytic derivatives; the data files are embedded.
//!
//! ```
//! use bounded_lm::problems::nist;
//! let data = nist::load("Misra1a");
//! assert_eq!(data.certified.len(), 2);
//! ```

use crate::Problem;
use std::f64::consts::PI;

/// One NIST data set.
#[derive(Clone, Debug)]
pub struct NistData {
    /// NIST's name, e.g. `"Misra1a"`.
    pub name: String,
    /// NIST's two starting points.
    pub starts: [Vec<f64>; 2],
    /// Certified parameter values.
    pub certified: Vec<f64>,
    /// Certified residual sum of squares.
    pub certified_rss: f64,
    /// Response.
    pub y: Vec<f64>,
    /// Predictors (one or two per observation).
    pub x: Vec<[f64; 2]>,
}

/// The 27 problems in NIST's order of difficulty listing.
pub const NAMES: [&str; 27] = [
    "Misra1a", "Chwirut2", "Chwirut1", "Lanczos3", "Gauss1", "Gauss2", "DanWood", "Misra1b",
    "Kirby2", "Hahn1", "Nelson", "MGH17", "Lanczos1", "Lanczos2", "Gauss3", "Misra1c", "Misra1d",
    "Roszman1", "ENSO", "MGH09", "Thurber", "BoxBOD", "Rat42", "MGH10", "Eckerle4", "Rat43",
    "Bennett5",
];

fn line_range(text: &str, key: &str) -> (usize, usize) {
    let line = text
        .lines()
        .find(|l| l.contains(key))
        .unwrap_or_else(|| panic!("no '{key}' line"));
    let nums: Vec<usize> = line
        .split(|c: char| !c.is_ascii_digit())
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().unwrap())
        .collect();
    (nums[0], nums[1])
}

/// The text of NIST's `<name>.dat` file (embedded from `crates/lm/tests/data`), or `None` for
/// an unknown name.
pub fn data_file(name: &str) -> Option<&'static str> {
    Some(match name {
        "Misra1a" => include_str!("../../tests/data/Misra1a.dat"),
        "Chwirut2" => include_str!("../../tests/data/Chwirut2.dat"),
        "Chwirut1" => include_str!("../../tests/data/Chwirut1.dat"),
        "Lanczos3" => include_str!("../../tests/data/Lanczos3.dat"),
        "Gauss1" => include_str!("../../tests/data/Gauss1.dat"),
        "Gauss2" => include_str!("../../tests/data/Gauss2.dat"),
        "DanWood" => include_str!("../../tests/data/DanWood.dat"),
        "Misra1b" => include_str!("../../tests/data/Misra1b.dat"),
        "Kirby2" => include_str!("../../tests/data/Kirby2.dat"),
        "Hahn1" => include_str!("../../tests/data/Hahn1.dat"),
        "Nelson" => include_str!("../../tests/data/Nelson.dat"),
        "MGH17" => include_str!("../../tests/data/MGH17.dat"),
        "Lanczos1" => include_str!("../../tests/data/Lanczos1.dat"),
        "Lanczos2" => include_str!("../../tests/data/Lanczos2.dat"),
        "Gauss3" => include_str!("../../tests/data/Gauss3.dat"),
        "Misra1c" => include_str!("../../tests/data/Misra1c.dat"),
        "Misra1d" => include_str!("../../tests/data/Misra1d.dat"),
        "Roszman1" => include_str!("../../tests/data/Roszman1.dat"),
        "ENSO" => include_str!("../../tests/data/ENSO.dat"),
        "MGH09" => include_str!("../../tests/data/MGH09.dat"),
        "Thurber" => include_str!("../../tests/data/Thurber.dat"),
        "BoxBOD" => include_str!("../../tests/data/BoxBOD.dat"),
        "Rat42" => include_str!("../../tests/data/Rat42.dat"),
        "MGH10" => include_str!("../../tests/data/MGH10.dat"),
        "Eckerle4" => include_str!("../../tests/data/Eckerle4.dat"),
        "Rat43" => include_str!("../../tests/data/Rat43.dat"),
        "Bennett5" => include_str!("../../tests/data/Bennett5.dat"),
        _ => return None,
    })
}

/// Parses NIST's `<name>.dat` (one of [`NAMES`]).
///
/// # Panics
/// For a name not in [`NAMES`].
pub fn load(name: &str) -> NistData {
    let path = format!("{name}.dat");
    let text = data_file(name).unwrap_or_else(|| panic!("unknown NIST problem {name}"));
    let lines: Vec<&str> = text.lines().collect();
    let (s0, s1) = line_range(text, "Starting Values");
    let (d0, d1) = line_range(text, "Data     ");
    let mut starts = [Vec::new(), Vec::new()];
    let mut certified = Vec::new();
    for l in &lines[s0 - 1..s1] {
        let rhs = l
            .split('=')
            .nth(1)
            .unwrap_or_else(|| panic!("{path}: bad line {l}"));
        let v: Vec<f64> = rhs.split_whitespace().map(|t| t.parse().unwrap()).collect();
        starts[0].push(v[0]);
        starts[1].push(v[1]);
        certified.push(v[2]);
    }
    let rss_line = lines
        .iter()
        .find(|l| l.starts_with("Residual Sum of Squares"))
        .unwrap();
    let certified_rss: f64 = rss_line.split_whitespace().last().unwrap().parse().unwrap();
    let mut y = Vec::new();
    let mut x = Vec::new();
    for l in &lines[d0 - 1..d1] {
        let v: Vec<f64> = l.split_whitespace().map(|t| t.parse().unwrap()).collect();
        if v.is_empty() {
            continue;
        }
        y.push(v[0]);
        x.push([v[1], *v.get(2).unwrap_or(&0.0)]);
    }
    NistData {
        name: name.to_string(),
        starts,
        certified,
        certified_rss,
        y,
        x,
    }
}

/// Model value at one observation; fills `grad` (length p) with d model / d b.
pub fn model(name: &str, b: &[f64], xx: [f64; 2], grad: &mut [f64]) -> f64 {
    let x = xx[0];
    match name {
        "Misra1a" | "BoxBOD" => {
            let e = (-b[1] * x).exp();
            grad[0] = 1.0 - e;
            grad[1] = b[0] * x * e;
            b[0] * (1.0 - e)
        }
        "Chwirut1" | "Chwirut2" => {
            let e = (-b[0] * x).exp();
            let den = b[1] + b[2] * x;
            grad[0] = -x * e / den;
            grad[1] = -e / (den * den);
            grad[2] = -x * e / (den * den);
            e / den
        }
        "Lanczos1" | "Lanczos2" | "Lanczos3" => {
            let mut v = 0.0;
            for k in 0..3 {
                let e = (-b[2 * k + 1] * x).exp();
                grad[2 * k] = e;
                grad[2 * k + 1] = -b[2 * k] * x * e;
                v += b[2 * k] * e;
            }
            v
        }
        "Gauss1" | "Gauss2" | "Gauss3" => {
            let e0 = (-b[1] * x).exp();
            grad[0] = e0;
            grad[1] = -b[0] * x * e0;
            let mut v = b[0] * e0;
            for (a, c, w) in [(2, 3, 4), (5, 6, 7)] {
                let d = x - b[c];
                let e = (-d * d / (b[w] * b[w])).exp();
                grad[a] = e;
                grad[c] = b[a] * e * 2.0 * d / (b[w] * b[w]);
                grad[w] = b[a] * e * 2.0 * d * d / (b[w] * b[w] * b[w]);
                v += b[a] * e;
            }
            v
        }
        "DanWood" => {
            let v = b[0] * x.powf(b[1]);
            grad[0] = x.powf(b[1]);
            grad[1] = v * x.ln();
            v
        }
        "Misra1b" => {
            let t = 1.0 + b[1] * x / 2.0;
            grad[0] = 1.0 - t.powi(-2);
            grad[1] = b[0] * x * t.powi(-3);
            b[0] * (1.0 - t.powi(-2))
        }
        "Misra1c" => {
            let t = 1.0 + 2.0 * b[1] * x;
            grad[0] = 1.0 - t.powf(-0.5);
            grad[1] = b[0] * x * t.powf(-1.5);
            b[0] * (1.0 - t.powf(-0.5))
        }
        "Misra1d" => {
            let t = 1.0 + b[1] * x;
            grad[0] = b[1] * x / t;
            grad[1] = b[0] * x / (t * t);
            b[0] * b[1] * x / t
        }
        "Kirby2" => {
            let num = b[0] + b[1] * x + b[2] * x * x;
            let den = 1.0 + b[3] * x + b[4] * x * x;
            grad[0] = 1.0 / den;
            grad[1] = x / den;
            grad[2] = x * x / den;
            grad[3] = -num * x / (den * den);
            grad[4] = -num * x * x / (den * den);
            num / den
        }
        "Hahn1" | "Thurber" => {
            let num = b[0] + x * (b[1] + x * (b[2] + x * b[3]));
            let den = 1.0 + x * (b[4] + x * (b[5] + x * b[6]));
            let mut xp = 1.0;
            for k in 0..4 {
                grad[k] = xp / den;
                xp *= x;
            }
            let mut xp = x;
            for k in 4..7 {
                grad[k] = -num * xp / (den * den);
                xp *= x;
            }
            num / den
        }
        "Nelson" => {
            let x2 = xx[1];
            let e = (-b[2] * x2).exp();
            grad[0] = 1.0;
            grad[1] = -x * e;
            grad[2] = b[1] * x * x2 * e;
            b[0] - b[1] * x * e
        }
        "MGH17" => {
            let e4 = (-x * b[3]).exp();
            let e5 = (-x * b[4]).exp();
            grad[0] = 1.0;
            grad[1] = e4;
            grad[2] = e5;
            grad[3] = -x * b[1] * e4;
            grad[4] = -x * b[2] * e5;
            b[0] + b[1] * e4 + b[2] * e5
        }
        "Roszman1" => {
            let d = x - b[3];
            let t = b[2] / d;
            let c = 1.0 / (PI * (1.0 + t * t));
            grad[0] = 1.0;
            grad[1] = -x;
            grad[2] = -c / d;
            grad[3] = -c * b[2] / (d * d);
            b[0] - b[1] * x - t.atan() / PI
        }
        "ENSO" => {
            let w = 2.0 * PI * x / 12.0;
            let mut v = b[0] + b[1] * w.cos() + b[2] * w.sin();
            grad[0] = 1.0;
            grad[1] = w.cos();
            grad[2] = w.sin();
            for (per, cc, ss) in [(3, 4, 5), (6, 7, 8)] {
                let a = 2.0 * PI * x / b[per];
                let (sa, ca) = a.sin_cos();
                v += b[cc] * ca + b[ss] * sa;
                grad[cc] = ca;
                grad[ss] = sa;
                // d a / d period = -a / period
                grad[per] = (-b[cc] * sa + b[ss] * ca) * (-a / b[per]);
            }
            v
        }
        "MGH09" => {
            let num = x * x + x * b[1];
            let den = x * x + x * b[2] + b[3];
            grad[0] = num / den;
            grad[1] = b[0] * x / den;
            grad[2] = -b[0] * num * x / (den * den);
            grad[3] = -b[0] * num / (den * den);
            b[0] * num / den
        }
        "Rat42" => {
            let e = (b[1] - b[2] * x).exp();
            let den = 1.0 + e;
            grad[0] = 1.0 / den;
            grad[1] = -b[0] * e / (den * den);
            grad[2] = b[0] * x * e / (den * den);
            b[0] / den
        }
        "MGH10" => {
            let e = (b[1] / (x + b[2])).exp();
            grad[0] = e;
            grad[1] = b[0] * e / (x + b[2]);
            grad[2] = -b[0] * e * b[1] / ((x + b[2]) * (x + b[2]));
            b[0] * e
        }
        "Eckerle4" => {
            let d = (x - b[2]) / b[1];
            let e = (-0.5 * d * d).exp();
            let v = b[0] / b[1] * e;
            grad[0] = e / b[1];
            grad[1] = v * (d * d - 1.0) / b[1];
            grad[2] = v * d / b[1];
            v
        }
        "Rat43" => {
            let e = (b[1] - b[2] * x).exp();
            let base = 1.0 + e;
            let v = b[0] * base.powf(-1.0 / b[3]);
            grad[0] = v / b[0];
            grad[1] = -v / b[3] * e / base;
            grad[2] = v / b[3] * x * e / base;
            grad[3] = v * base.ln() / (b[3] * b[3]);
            v
        }
        "Bennett5" => {
            let base = b[1] + x;
            let v = b[0] * base.powf(-1.0 / b[2]);
            grad[0] = v / b[0];
            grad[1] = -v / (b[2] * base);
            grad[2] = v * base.ln() / (b[2] * b[2]);
            v
        }
        other => panic!("unknown NIST problem {other}"),
    }
}

/// A NIST problem as a [`Problem`] (residual = model - y; Nelson fits log y).
pub struct NistProblem<'a> {
    /// The data set.
    pub data: &'a NistData,
    grad: Vec<f64>,
}

impl<'a> NistProblem<'a> {
    /// The problem for `data` (allocates a gradient buffer; evaluations allocate nothing).
    pub fn new(data: &'a NistData) -> Self {
        Self {
            data,
            grad: vec![0.0; data.certified.len()],
        }
    }
    fn target(&self, i: usize) -> f64 {
        if self.data.name == "Nelson" {
            self.data.y[i].ln()
        } else {
            self.data.y[i]
        }
    }
}

impl Problem for NistProblem<'_> {
    fn residual_count(&self) -> usize {
        self.data.y.len()
    }
    fn parameter_count(&self) -> usize {
        self.data.certified.len()
    }
    fn residuals(&mut self, b: &[f64], r: &mut [f64]) -> bool {
        for i in 0..r.len() {
            r[i] = model(&self.data.name, b, self.data.x[i], &mut self.grad) - self.target(i);
        }
        r.iter().all(|v| v.is_finite())
    }
    fn jacobian(&mut self, b: &[f64], jac: &mut [f64]) -> bool {
        let m = self.data.y.len();
        for i in 0..m {
            model(&self.data.name, b, self.data.x[i], &mut self.grad);
            for (j, g) in self.grad.iter().enumerate() {
                jac[j * m + i] = *g;
            }
        }
        jac.iter().all(|v| v.is_finite())
    }
}

/// Log relative error of one estimate, capped at 11 digits (NIST certifies 11).
pub fn lre(est: f64, cert: f64) -> f64 {
    let rel = (est - cert).abs() / cert.abs();
    if rel == 0.0 {
        11.0
    } else {
        (-rel.log10()).clamp(0.0, 11.0)
    }
}

/// Parameter groups that can be exchanged without changing the model (sums of exponentials or
/// Gaussians, ENSO's two cycles): the same fit with the terms listed in another order is the
/// same answer.
fn exchangeable_groups(name: &str) -> &'static [&'static [usize]] {
    match name {
        "MGH17" => &[&[1, 3], &[2, 4]],
        "Lanczos1" | "Lanczos2" | "Lanczos3" => &[&[0, 1], &[2, 3], &[4, 5]],
        "Gauss1" | "Gauss2" | "Gauss3" => &[&[2, 3, 4], &[5, 6, 7]],
        "ENSO" => &[&[3, 4, 5], &[6, 7, 8]],
        _ => &[],
    }
}

/// Smallest LRE over the parameters, for the best ordering of exchangeable terms; Gaussian
/// widths enter squared, so their sign is irrelevant, and Eckerle4's model
/// `(b1/b2) exp(-0.5 ((x - b3)/b2)^2)` is the same at `(-b1, -b2, b3)`.
pub fn min_lre(name: &str, x: &[f64], cert: &[f64]) -> f64 {
    let mut y: Vec<f64> = x.to_vec();
    if name.starts_with("Gauss") {
        y[4] = y[4].abs();
        y[7] = y[7].abs();
    }
    if name == "Eckerle4" && y[1] < 0.0 {
        y[0] = -y[0];
        y[1] = -y[1];
    }
    let plain = |v: &[f64]| {
        v.iter()
            .zip(cert)
            .map(|(&e, &c)| lre(e, c))
            .fold(f64::INFINITY, f64::min)
    };
    let groups = exchangeable_groups(name);
    let mut best = plain(&y);
    // All orderings of the groups (at most 3! = 6).
    let k = groups.len();
    let perms: &[&[usize]] = match k {
        2 => &[&[1, 0]],
        3 => &[&[0, 2, 1], &[1, 0, 2], &[1, 2, 0], &[2, 0, 1], &[2, 1, 0]],
        _ => &[],
    };
    for perm in perms {
        let mut z = y.clone();
        for (dst, &src) in perm.iter().enumerate() {
            for (a, b) in groups[dst].iter().zip(groups[src]) {
                z[*a] = y[*b];
            }
        }
        best = best.max(plain(&z));
    }
    best
}
