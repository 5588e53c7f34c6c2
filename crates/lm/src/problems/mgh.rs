//! The Moré, Garbow and Hillstrom test collection.
//!
//! J. J. Moré, B. S. Garbow and K. E. Hillstrom, *Testing Unconstrained Optimization
//! Software*, ACM Transactions on Mathematical Software 7(1), 17-41, 1981: 35 problems given as
//! residuals `f_i(x)`, `i = 1..m`, with a standard start `x0` and the known minima of
//! `sum f_i^2`. All 35 are here, with analytic Jacobians (`tests/mgh.rs` checks each against
//! forward differences at `x0` and at a perturbed point). The variable-dimension problems use
//! the sizes listed in [`all`].
//!
//! **Convention.** MGH (and [`Mgh::minima`]) report `F = sum f_i^2`; the solver minimises
//! `f = 0.5 F`, so [`Mgh::f_minima`] halves them. Where MGH lists more than one value (local
//! minima that Gauss-Newton methods are known to reach, such as Freudenstein and Roth's 48.9842),
//! all are listed, the global one first; a run that ends at any of them has found a minimum.
//!
//! ```
//! use bounded_lm::problems::mgh;
//! use bounded_lm::{Options, Solver};
//! let mut prob = mgh::Mgh::new(mgh::Kind::Rosenbrock, 2, 2);
//! let mut x = prob.start(1.0);
//! let inf = [f64::INFINITY; 2];
//! let rep = Solver::new().solve(&mut prob, &mut x, &[-inf[0]; 2], &inf, &Default::default()).unwrap();
//! assert!(prob.reaches_minimum(rep.f));
//! ```

use crate::{Options, Problem, Scaling};
use std::f64::consts::PI;

/// The 35 problems, numbered as in MGH's paper.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[allow(missing_docs)]
pub enum Kind {
    Rosenbrock = 1,
    FreudensteinRoth,
    PowellBadlyScaled,
    BrownBadlyScaled,
    Beale,
    JennrichSampson,
    HelicalValley,
    Bard,
    Gaussian,
    Meyer,
    GulfResearch,
    Box3d,
    PowellSingular,
    Wood,
    KowalikOsborne,
    BrownDennis,
    Osborne1,
    BiggsExp6,
    Osborne2,
    Watson,
    ExtendedRosenbrock,
    ExtendedPowellSingular,
    PenaltyI,
    PenaltyII,
    VariablyDimensioned,
    Trigonometric,
    BrownAlmostLinear,
    DiscreteBoundaryValue,
    DiscreteIntegralEquation,
    BroydenTridiagonal,
    BroydenBanded,
    LinearFullRank,
    LinearRankOne,
    LinearRankOneZero,
    Chebyquad,
}

const BARD_Y: [f64; 15] = [
    0.14, 0.18, 0.22, 0.25, 0.29, 0.32, 0.35, 0.39, 0.37, 0.58, 0.73, 0.96, 1.34, 2.10, 4.39,
];
const GAUSSIAN_Y: [f64; 15] = [
    0.0009, 0.0044, 0.0175, 0.0540, 0.1295, 0.2420, 0.3521, 0.3989, 0.3521, 0.2420, 0.1295, 0.0540,
    0.0175, 0.0044, 0.0009,
];
const MEYER_Y: [f64; 16] = [
    34780.0, 28610.0, 23650.0, 19630.0, 16370.0, 13720.0, 11540.0, 9744.0, 8261.0, 7030.0, 6005.0,
    5147.0, 4427.0, 3820.0, 3307.0, 2872.0,
];
const KOWALIK_Y: [f64; 11] = [
    0.1957, 0.1947, 0.1735, 0.1600, 0.0844, 0.0627, 0.0456, 0.0342, 0.0323, 0.0235, 0.0246,
];
const KOWALIK_U: [f64; 11] = [
    4.0, 2.0, 1.0, 0.5, 0.25, 0.167, 0.125, 0.1, 0.0833, 0.0714, 0.0625,
];
const OSBORNE1_Y: [f64; 33] = [
    0.844, 0.908, 0.932, 0.936, 0.925, 0.908, 0.881, 0.850, 0.818, 0.784, 0.751, 0.718, 0.685,
    0.658, 0.628, 0.603, 0.580, 0.558, 0.538, 0.522, 0.506, 0.490, 0.478, 0.467, 0.457, 0.448,
    0.438, 0.431, 0.424, 0.420, 0.414, 0.411, 0.406,
];
const OSBORNE2_Y: [f64; 65] = [
    1.366, 1.191, 1.112, 1.013, 0.991, 0.885, 0.831, 0.847, 0.786, 0.725, 0.746, 0.679, 0.608,
    0.655, 0.616, 0.606, 0.602, 0.626, 0.651, 0.724, 0.649, 0.649, 0.694, 0.644, 0.624, 0.661,
    0.612, 0.558, 0.533, 0.495, 0.500, 0.423, 0.395, 0.375, 0.372, 0.391, 0.396, 0.405, 0.428,
    0.429, 0.523, 0.562, 0.607, 0.653, 0.672, 0.708, 0.633, 0.668, 0.645, 0.632, 0.591, 0.559,
    0.597, 0.625, 0.739, 0.710, 0.729, 0.720, 0.636, 0.581, 0.428, 0.292, 0.162, 0.098, 0.054,
];

/// One MGH problem of a given size.
#[derive(Clone, Debug)]
pub struct Mgh {
    kind: Kind,
    n: usize,
    m: usize,
    /// Gulf research: y_i.
    aux: Vec<f64>,
}

/// The collection with the sizes used here: MGH's own sizes where fixed; for the variable ones
/// the sizes of MGH's tables (Watson n = 6 and 9, Penalty I and II n = 4 and 10, Chebyquad n = 8)
/// or n = 10, the linear problems with n = 5, m = 10, Gulf research with m = 10, Extended Powell
/// with n = 12.
pub fn all() -> Vec<Mgh> {
    use Kind::*;
    let list: [(Kind, usize, usize); 39] = [
        (Rosenbrock, 2, 2),
        (FreudensteinRoth, 2, 2),
        (PowellBadlyScaled, 2, 2),
        (BrownBadlyScaled, 2, 3),
        (Beale, 2, 3),
        (JennrichSampson, 2, 10),
        (HelicalValley, 3, 3),
        (Bard, 3, 15),
        (Gaussian, 3, 15),
        (Meyer, 3, 16),
        (GulfResearch, 3, 10),
        (Box3d, 3, 10),
        (PowellSingular, 4, 4),
        (Wood, 4, 6),
        (KowalikOsborne, 4, 11),
        (BrownDennis, 4, 20),
        (Osborne1, 5, 33),
        (BiggsExp6, 6, 13),
        (Osborne2, 11, 65),
        (Watson, 6, 31),
        (Watson, 9, 31),
        (ExtendedRosenbrock, 10, 10),
        (ExtendedPowellSingular, 12, 12),
        (PenaltyI, 4, 5),
        (PenaltyI, 10, 11),
        (PenaltyII, 4, 8),
        (PenaltyII, 10, 20),
        (VariablyDimensioned, 10, 12),
        (Trigonometric, 10, 10),
        (BrownAlmostLinear, 10, 10),
        (DiscreteBoundaryValue, 10, 10),
        (DiscreteIntegralEquation, 10, 10),
        (BroydenTridiagonal, 10, 10),
        (BroydenBanded, 10, 10),
        (LinearFullRank, 5, 10),
        (LinearRankOne, 5, 10),
        (LinearRankOneZero, 5, 10),
        (Chebyquad, 8, 8),
        (Chebyquad, 7, 7),
    ];
    list.iter().map(|&(k, n, m)| Mgh::new(k, n, m)).collect()
}

impl Mgh {
    /// Problem `kind` with `n` parameters and `m` residuals.
    ///
    /// # Panics
    /// When the sizes are not valid for the problem (fixed sizes must match MGH's; Extended
    /// Rosenbrock needs even n, Extended Powell a multiple of 4, and so on).
    pub fn new(kind: Kind, n: usize, m: usize) -> Self {
        use Kind::*;
        let fixed: Option<(usize, usize)> = match kind {
            Rosenbrock | FreudensteinRoth | PowellBadlyScaled => Some((2, 2)),
            BrownBadlyScaled | Beale => Some((2, 3)),
            HelicalValley => Some((3, 3)),
            Bard | Gaussian => Some((3, 15)),
            Meyer => Some((3, 16)),
            PowellSingular => Some((4, 4)),
            Wood => Some((4, 6)),
            KowalikOsborne => Some((4, 11)),
            Osborne1 => Some((5, 33)),
            Osborne2 => Some((11, 65)),
            _ => None,
        };
        let ok = match kind {
            _ if fixed.is_some() => fixed == Some((n, m)),
            JennrichSampson => n == 2 && m >= 2,
            GulfResearch => n == 3 && (3..=100).contains(&m),
            Box3d => n == 3 && m >= 3,
            BrownDennis => n == 4 && m >= 4,
            BiggsExp6 => n == 6 && m >= 6,
            Watson => (2..=31).contains(&n) && m == 31,
            ExtendedRosenbrock => n >= 2 && n.is_multiple_of(2) && m == n,
            ExtendedPowellSingular => n >= 4 && n.is_multiple_of(4) && m == n,
            PenaltyI => n >= 1 && m == n + 1,
            PenaltyII => n >= 1 && m == 2 * n,
            VariablyDimensioned => n >= 1 && m == n + 2,
            LinearFullRank | LinearRankOne => n >= 1 && m >= n,
            LinearRankOneZero => n >= 3 && m >= n,
            Chebyquad => n >= 1 && m >= n,
            _ => n >= 1 && m == n,
        };
        assert!(ok, "MGH {kind:?}: invalid size n = {n}, m = {m}");
        let aux = if kind == GulfResearch {
            (1..=m)
                .map(|i| 25.0 + (-50.0 * (i as f64 / 100.0).ln()).powf(2.0 / 3.0))
                .collect()
        } else {
            Vec::new()
        };
        Self { kind, n, m, aux }
    }

    /// Which problem.
    pub fn kind(&self) -> Kind {
        self.kind
    }

    /// MGH's number (1..=35).
    pub fn number(&self) -> u8 {
        self.kind as u8
    }

    /// A label such as `"24 Penalty II (n=10)"`.
    pub fn label(&self) -> String {
        let name = format!("{:?}", self.kind);
        let variable = !matches!(
            self.kind,
            Kind::Rosenbrock
                | Kind::FreudensteinRoth
                | Kind::PowellBadlyScaled
                | Kind::BrownBadlyScaled
                | Kind::Beale
                | Kind::HelicalValley
                | Kind::Bard
                | Kind::Gaussian
                | Kind::Meyer
                | Kind::PowellSingular
                | Kind::Wood
                | Kind::KowalikOsborne
                | Kind::Osborne1
                | Kind::Osborne2
        );
        if variable {
            format!("{} {name} (n={}, m={})", self.number(), self.n, self.m)
        } else {
            format!("{} {name}", self.number())
        }
    }

    /// The standard start `x0` times `factor` (MGH also use 10 and 100).
    pub fn start(&self, factor: f64) -> Vec<f64> {
        use Kind::*;
        let n = self.n;
        let x0: Vec<f64> = match self.kind {
            Rosenbrock => vec![-1.2, 1.0],
            FreudensteinRoth => vec![0.5, -2.0],
            PowellBadlyScaled => vec![0.0, 1.0],
            BrownBadlyScaled => vec![1.0, 1.0],
            Beale => vec![1.0, 1.0],
            JennrichSampson => vec![0.3, 0.4],
            HelicalValley => vec![-1.0, 0.0, 0.0],
            Bard => vec![1.0, 1.0, 1.0],
            Gaussian => vec![0.4, 1.0, 0.0],
            Meyer => vec![0.02, 4000.0, 250.0],
            GulfResearch => vec![5.0, 2.5, 0.15],
            Box3d => vec![0.0, 10.0, 20.0],
            PowellSingular => vec![3.0, -1.0, 0.0, 1.0],
            Wood => vec![-3.0, -1.0, -3.0, -1.0],
            KowalikOsborne => vec![0.25, 0.39, 0.415, 0.39],
            BrownDennis => vec![25.0, 5.0, -5.0, -1.0],
            Osborne1 => vec![0.5, 1.5, -1.0, 0.01, 0.02],
            BiggsExp6 => vec![1.0, 2.0, 1.0, 1.0, 1.0, 1.0],
            Osborne2 => vec![1.3, 0.65, 0.65, 0.7, 0.6, 3.0, 5.0, 7.0, 2.0, 4.5, 5.5],
            Watson => vec![0.0; n],
            ExtendedRosenbrock => (0..n)
                .map(|j| if j % 2 == 0 { -1.2 } else { 1.0 })
                .collect(),
            ExtendedPowellSingular => (0..n).map(|j| [3.0, -1.0, 0.0, 1.0][j % 4]).collect(),
            PenaltyI => (1..=n).map(|j| j as f64).collect(),
            PenaltyII => vec![0.5; n],
            VariablyDimensioned => (1..=n).map(|j| 1.0 - j as f64 / n as f64).collect(),
            Trigonometric => vec![1.0 / n as f64; n],
            BrownAlmostLinear => vec![0.5; n],
            DiscreteBoundaryValue | DiscreteIntegralEquation => {
                let h = 1.0 / (n as f64 + 1.0);
                (1..=n)
                    .map(|j| j as f64 * h * (j as f64 * h - 1.0))
                    .collect()
            }
            BroydenTridiagonal | BroydenBanded => vec![-1.0; n],
            LinearFullRank | LinearRankOne | LinearRankOneZero => vec![1.0; n],
            Chebyquad => (1..=n).map(|j| j as f64 / (n as f64 + 1.0)).collect(),
        };
        x0.into_iter().map(|v| v * factor).collect()
    }

    /// The minima of `F = sum f_i^2` listed by MGH for this size (global first), or computed
    /// from their closed forms (the linear problems). Empty when MGH list none for this size.
    pub fn minima(&self) -> Vec<f64> {
        use Kind::*;
        let (n, m) = (self.n, self.m as f64);
        match self.kind {
            Rosenbrock
            | PowellBadlyScaled
            | BrownBadlyScaled
            | Beale
            | HelicalValley
            | GulfResearch
            | Box3d
            | PowellSingular
            | Wood
            | ExtendedRosenbrock
            | ExtendedPowellSingular
            | VariablyDimensioned
            | DiscreteBoundaryValue
            | DiscreteIntegralEquation
            | BroydenTridiagonal
            | BroydenBanded => vec![0.0],
            FreudensteinRoth => vec![0.0, 48.9842],
            JennrichSampson if self.m == 10 => vec![124.362],
            Bard => vec![8.21487e-3, 17.4286],
            Gaussian => vec![1.12793e-8],
            Meyer => vec![87.9458],
            KowalikOsborne => vec![3.07505e-4, 1.02734e-3],
            BrownDennis if self.m == 20 => vec![85822.2],
            Osborne1 => vec![5.46489e-5],
            BiggsExp6 if self.m == 13 => vec![0.0, 5.65565e-3],
            Osborne2 => vec![4.01377e-2],
            Watson if n == 6 => vec![2.28767e-3],
            Watson if n == 9 => vec![1.39976e-6],
            Watson if n == 12 => vec![4.72238e-10],
            PenaltyI if n == 4 => vec![2.24997e-5],
            PenaltyI if n == 10 => vec![7.08765e-5],
            PenaltyII if n == 4 => vec![9.37629e-6],
            PenaltyII if n == 10 => vec![2.93660e-4],
            Trigonometric if n == 10 => vec![0.0, 2.79506e-5],
            Trigonometric => vec![0.0],
            BrownAlmostLinear => vec![0.0, 1.0],
            LinearFullRank => vec![m - n as f64],
            LinearRankOne => vec![m * (m - 1.0) / (2.0 * (2.0 * m + 1.0))],
            LinearRankOneZero => vec![(m * m + 3.0 * m - 6.0) / (2.0 * (2.0 * m - 3.0))],
            Chebyquad if n <= 7 || n == 9 => vec![0.0],
            Chebyquad if n == 8 => vec![3.51687e-3],
            Chebyquad if n == 10 => vec![6.50395e-3],
            _ => Vec::new(),
        }
    }

    /// [`Mgh::minima`] in the solver's convention `f = 0.5 F`.
    pub fn f_minima(&self) -> Vec<f64> {
        self.minima().into_iter().map(|v| 0.5 * v).collect()
    }

    /// Whether `f` (the solver's `0.5 F`) is at one of the listed minima: within `1e-5`
    /// relative (MGH print 6 digits) or `1e-12` absolute (for the zero minima).
    pub fn reaches_minimum(&self, f: f64) -> bool {
        self.f_minima()
            .iter()
            .any(|&fs| f.is_finite() && (f - fs).abs() <= 1e-5 * fs + 1e-12)
    }

    /// Index into the listed minima that `f` reaches (0 = global), if any.
    pub fn which_minimum(&self, f: f64) -> Option<usize> {
        self.f_minima()
            .iter()
            .position(|&fs| f.is_finite() && (f - fs).abs() <= 1e-5 * fs + 1e-12)
    }
}

/// A box and what it does, from [`Mgh::cutting_box`].
#[derive(Clone, Debug, PartialEq)]
pub struct Bounds {
    /// Lower bounds.
    pub lower: Vec<f64>,
    /// Upper bounds.
    pub upper: Vec<f64>,
    /// The bounded parameter (0-based).
    pub index: usize,
    /// True for an upper bound.
    pub is_upper: bool,
    /// The bound's value.
    pub value: f64,
}

impl Bounds {
    /// `"x3 <= 0.52"` (1-based index, as in MGH).
    pub fn describe(&self) -> String {
        let op = if self.is_upper { "<=" } else { ">=" };
        format!("x{} {op} {:.4e}", self.index + 1, self.value)
    }
}

/// The solver configuration whose unbounded minimiser from `x0` defines [`Mgh::cutting_box`]
/// in the tests, tables and stress suite: the Gauss-Newton model with the other defaults and
/// budgets of 5000. It is pinned, not [`Options::default`], so the boxes (and every boxed
/// result measured in them) do not move when the defaults change.
pub fn box_reference_options() -> Options {
    let mut options = Options::gauss_newton().with_limits(5000, 5000);
    options.scaling.decay = Scaling::NL2SOL_DECAY;
    options.safeguards.second_order_correction = false;
    options
}

impl Mgh {
    /// A box that cuts off the minimiser `x_star` (reached without bounds from `x0`): the
    /// parameter `j` with the largest `|x*_j - x0_j| / max(1, |x*_j|)` gets a bound halfway
    /// between `x0_j` and `x*_j` (an upper bound when `x*_j > x0_j`), the others stay free. The
    /// bounded minimum then has that bound active (unless the box holds another minimiser),
    /// and the start `x0` is feasible.
    pub fn cutting_box(&self, x_star: &[f64]) -> Bounds {
        let x0 = self.start(1.0);
        let mut best = (0usize, -1.0f64);
        for j in 0..self.n {
            let d = (x_star[j] - x0[j]).abs() / x_star[j].abs().max(1.0);
            if d > best.1 {
                best = (j, d);
            }
        }
        let j = best.0;
        let value = 0.5 * (x0[j] + x_star[j]);
        let mut lower = vec![f64::NEG_INFINITY; self.n];
        let mut upper = vec![f64::INFINITY; self.n];
        let is_upper = x_star[j] > x0[j];
        if is_upper {
            upper[j] = value;
        } else {
            lower[j] = value;
        }
        Bounds {
            lower,
            upper,
            index: j,
            is_upper,
            value,
        }
    }
}

impl Problem for Mgh {
    fn residual_count(&self) -> usize {
        self.m
    }

    fn parameter_count(&self) -> usize {
        self.n
    }

    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        eval(self, x, r, None);
        r.iter().all(|v| v.is_finite())
    }

    fn jacobian(&mut self, x: &[f64], jac: &mut [f64]) -> bool {
        jac.fill(0.0);
        let mut dummy = [0.0f64; 0];
        eval(self, x, &mut dummy, Some(jac));
        jac.iter().all(|v| v.is_finite())
    }
}

/// Helical valley's angle: `atan(x2/x1) / 2pi`, plus 1/2 for `x1 < 0`.
fn helical_theta(a: f64, b: f64) -> f64 {
    if a > 0.0 {
        (b / a).atan() / (2.0 * PI)
    } else if a < 0.0 {
        (b / a).atan() / (2.0 * PI) + 0.5
    } else {
        0.25 * b.signum()
    }
}

/// Residuals into `r` (when `jac` is `None`) or the Jacobian into `jac` (zeroed on entry).
fn eval(p: &Mgh, x: &[f64], r: &mut [f64], jac: Option<&mut [f64]>) {
    use Kind::*;
    let (n, m) = (p.n, p.m);
    let want_j = jac.is_some();
    let mut dummy = [0.0f64; 0];
    let j: &mut [f64] = match jac {
        Some(j) => j,
        None => &mut dummy,
    };
    // Jacobian entry d r_i / d x_k (column-major).
    macro_rules! jset {
        ($i:expr, $k:expr, $v:expr) => {
            j[($k) * m + ($i)] = $v
        };
    }
    macro_rules! out {
        ($i:expr, $v:expr) => {
            if !want_j {
                r[$i] = $v;
            }
        };
    }
    match p.kind {
        Rosenbrock => {
            out!(0, 10.0 * (x[1] - x[0] * x[0]));
            out!(1, 1.0 - x[0]);
            if want_j {
                jset!(0, 0, -20.0 * x[0]);
                jset!(0, 1, 10.0);
                jset!(1, 0, -1.0);
            }
        }
        FreudensteinRoth => {
            out!(0, -13.0 + x[0] + ((5.0 - x[1]) * x[1] - 2.0) * x[1]);
            out!(1, -29.0 + x[0] + ((x[1] + 1.0) * x[1] - 14.0) * x[1]);
            if want_j {
                jset!(0, 0, 1.0);
                jset!(1, 0, 1.0);
                jset!(0, 1, 10.0 * x[1] - 3.0 * x[1] * x[1] - 2.0);
                jset!(1, 1, 3.0 * x[1] * x[1] + 2.0 * x[1] - 14.0);
            }
        }
        PowellBadlyScaled => {
            out!(0, 1e4 * x[0] * x[1] - 1.0);
            out!(1, (-x[0]).exp() + (-x[1]).exp() - 1.0001);
            if want_j {
                jset!(0, 0, 1e4 * x[1]);
                jset!(0, 1, 1e4 * x[0]);
                jset!(1, 0, -(-x[0]).exp());
                jset!(1, 1, -(-x[1]).exp());
            }
        }
        BrownBadlyScaled => {
            out!(0, x[0] - 1e6);
            out!(1, x[1] - 2e-6);
            out!(2, x[0] * x[1] - 2.0);
            if want_j {
                jset!(0, 0, 1.0);
                jset!(1, 1, 1.0);
                jset!(2, 0, x[1]);
                jset!(2, 1, x[0]);
            }
        }
        Beale => {
            for i in 0..3 {
                let k = i as i32 + 1;
                out!(i, [1.5, 2.25, 2.625][i] - x[0] * (1.0 - x[1].powi(k)));
                if want_j {
                    jset!(i, 0, -(1.0 - x[1].powi(k)));
                    jset!(i, 1, x[0] * k as f64 * x[1].powi(k - 1));
                }
            }
        }
        JennrichSampson => {
            for i in 0..m {
                let k = (i + 1) as f64;
                let (e0, e1) = ((k * x[0]).exp(), (k * x[1]).exp());
                out!(i, 2.0 + 2.0 * k - (e0 + e1));
                if want_j {
                    jset!(i, 0, -k * e0);
                    jset!(i, 1, -k * e1);
                }
            }
        }
        HelicalValley => {
            let rho2 = x[0] * x[0] + x[1] * x[1];
            let rho = rho2.sqrt();
            out!(0, 10.0 * (x[2] - 10.0 * helical_theta(x[0], x[1])));
            out!(1, 10.0 * (rho - 1.0));
            out!(2, x[2]);
            if want_j {
                let c = 1.0 / (2.0 * PI * rho2);
                jset!(0, 0, 100.0 * x[1] * c);
                jset!(0, 1, -100.0 * x[0] * c);
                jset!(0, 2, 10.0);
                jset!(1, 0, 10.0 * x[0] / rho);
                jset!(1, 1, 10.0 * x[1] / rho);
                jset!(2, 2, 1.0);
            }
        }
        Bard => {
            for i in 0..15 {
                let u = (i + 1) as f64;
                let v = 16.0 - u;
                let w = u.min(v);
                let d = v * x[1] + w * x[2];
                out!(i, BARD_Y[i] - (x[0] + u / d));
                if want_j {
                    jset!(i, 0, -1.0);
                    jset!(i, 1, u * v / (d * d));
                    jset!(i, 2, u * w / (d * d));
                }
            }
        }
        Gaussian => {
            for i in 0..15 {
                let t = (7.0 - i as f64) / 2.0;
                let d = t - x[2];
                let e = (-0.5 * x[1] * d * d).exp();
                out!(i, x[0] * e - GAUSSIAN_Y[i]);
                if want_j {
                    jset!(i, 0, e);
                    jset!(i, 1, -0.5 * x[0] * e * d * d);
                    jset!(i, 2, x[0] * e * x[1] * d);
                }
            }
        }
        Meyer => {
            for i in 0..16 {
                let t = 45.0 + 5.0 * (i + 1) as f64;
                let d = t + x[2];
                let e = (x[1] / d).exp();
                out!(i, x[0] * e - MEYER_Y[i]);
                if want_j {
                    jset!(i, 0, e);
                    jset!(i, 1, x[0] * e / d);
                    jset!(i, 2, -x[0] * e * x[1] / (d * d));
                }
            }
        }
        GulfResearch => {
            for i in 0..m {
                let t = (i + 1) as f64 / 100.0;
                let dy = p.aux[i] - x[1];
                let a = dy.abs();
                let pw = a.powf(x[2]);
                let e = (-pw / x[0]).exp();
                out!(i, e - t);
                if want_j {
                    jset!(i, 0, e * pw / (x[0] * x[0]));
                    let da = if a > 0.0 {
                        e * x[2] * a.powf(x[2] - 1.0) * dy.signum() / x[0]
                    } else {
                        0.0
                    };
                    jset!(i, 1, da);
                    jset!(
                        i,
                        2,
                        if a > 0.0 {
                            -e * pw * a.ln() / x[0]
                        } else {
                            0.0
                        }
                    );
                }
            }
        }
        Box3d => {
            for i in 0..m {
                let t = 0.1 * (i + 1) as f64;
                let (e0, e1) = ((-t * x[0]).exp(), (-t * x[1]).exp());
                let c = (-t).exp() - (-10.0 * t).exp();
                out!(i, e0 - e1 - x[2] * c);
                if want_j {
                    jset!(i, 0, -t * e0);
                    jset!(i, 1, t * e1);
                    jset!(i, 2, -c);
                }
            }
        }
        PowellSingular | ExtendedPowellSingular => {
            let (s5, s10) = (5f64.sqrt(), 10f64.sqrt());
            for b in 0..n / 4 {
                let o = 4 * b;
                let (a, c) = (x[o + 1] - 2.0 * x[o + 2], x[o] - x[o + 3]);
                out!(o, x[o] + 10.0 * x[o + 1]);
                out!(o + 1, s5 * (x[o + 2] - x[o + 3]));
                out!(o + 2, a * a);
                out!(o + 3, s10 * c * c);
                if want_j {
                    jset!(o, o, 1.0);
                    jset!(o, o + 1, 10.0);
                    jset!(o + 1, o + 2, s5);
                    jset!(o + 1, o + 3, -s5);
                    jset!(o + 2, o + 1, 2.0 * a);
                    jset!(o + 2, o + 2, -4.0 * a);
                    jset!(o + 3, o, 2.0 * s10 * c);
                    jset!(o + 3, o + 3, -2.0 * s10 * c);
                }
            }
        }
        Wood => {
            let (s90, s10) = (90f64.sqrt(), 10f64.sqrt());
            out!(0, 10.0 * (x[1] - x[0] * x[0]));
            out!(1, 1.0 - x[0]);
            out!(2, s90 * (x[3] - x[2] * x[2]));
            out!(3, 1.0 - x[2]);
            out!(4, s10 * (x[1] + x[3] - 2.0));
            out!(5, (x[1] - x[3]) / s10);
            if want_j {
                jset!(0, 0, -20.0 * x[0]);
                jset!(0, 1, 10.0);
                jset!(1, 0, -1.0);
                jset!(2, 2, -2.0 * s90 * x[2]);
                jset!(2, 3, s90);
                jset!(3, 2, -1.0);
                jset!(4, 1, s10);
                jset!(4, 3, s10);
                jset!(5, 1, 1.0 / s10);
                jset!(5, 3, -1.0 / s10);
            }
        }
        KowalikOsborne => {
            for i in 0..11 {
                let u = KOWALIK_U[i];
                let num = u * u + u * x[1];
                let den = u * u + u * x[2] + x[3];
                out!(i, KOWALIK_Y[i] - x[0] * num / den);
                if want_j {
                    jset!(i, 0, -num / den);
                    jset!(i, 1, -x[0] * u / den);
                    jset!(i, 2, x[0] * num * u / (den * den));
                    jset!(i, 3, x[0] * num / (den * den));
                }
            }
        }
        BrownDennis => {
            for i in 0..m {
                let t = (i + 1) as f64 / 5.0;
                let (s, c) = t.sin_cos();
                let a = x[0] + t * x[1] - t.exp();
                let b = x[2] + x[3] * s - c;
                out!(i, a * a + b * b);
                if want_j {
                    jset!(i, 0, 2.0 * a);
                    jset!(i, 1, 2.0 * a * t);
                    jset!(i, 2, 2.0 * b);
                    jset!(i, 3, 2.0 * b * s);
                }
            }
        }
        Osborne1 => {
            for i in 0..33 {
                let t = 10.0 * i as f64;
                let (e3, e4) = ((-t * x[3]).exp(), (-t * x[4]).exp());
                out!(i, OSBORNE1_Y[i] - (x[0] + x[1] * e3 + x[2] * e4));
                if want_j {
                    jset!(i, 0, -1.0);
                    jset!(i, 1, -e3);
                    jset!(i, 2, -e4);
                    jset!(i, 3, x[1] * t * e3);
                    jset!(i, 4, x[2] * t * e4);
                }
            }
        }
        BiggsExp6 => {
            for i in 0..m {
                let t = 0.1 * (i + 1) as f64;
                let y = (-t).exp() - 5.0 * (-10.0 * t).exp() + 3.0 * (-4.0 * t).exp();
                let (e0, e1, e4) = ((-t * x[0]).exp(), (-t * x[1]).exp(), (-t * x[4]).exp());
                out!(i, x[2] * e0 - x[3] * e1 + x[5] * e4 - y);
                if want_j {
                    jset!(i, 0, -t * x[2] * e0);
                    jset!(i, 1, t * x[3] * e1);
                    jset!(i, 2, e0);
                    jset!(i, 3, -e1);
                    jset!(i, 4, -t * x[5] * e4);
                    jset!(i, 5, e4);
                }
            }
        }
        Osborne2 => {
            for i in 0..65 {
                let t = i as f64 / 10.0;
                let e0 = (-t * x[4]).exp();
                let mut v = x[0] * e0;
                if want_j {
                    jset!(i, 0, -e0);
                    jset!(i, 4, x[0] * t * e0);
                }
                for k in 1..4 {
                    let d = t - x[7 + k];
                    let ek = (-d * d * x[4 + k]).exp();
                    v += x[k] * ek;
                    if want_j {
                        jset!(i, k, -ek);
                        jset!(i, 4 + k, x[k] * d * d * ek);
                        jset!(i, 7 + k, -2.0 * x[k] * x[4 + k] * d * ek);
                    }
                }
                out!(i, OSBORNE2_Y[i] - v);
            }
        }
        Watson => {
            for i in 0..29 {
                let t = (i + 1) as f64 / 29.0;
                let (mut s1, mut s2) = (0.0, 0.0);
                let mut tp = 1.0; // t^(j-1) for 1-based j
                for k in 0..n {
                    if k >= 1 {
                        s1 += k as f64 * x[k] * tp / t;
                    }
                    s2 += x[k] * tp;
                    tp *= t;
                }
                out!(i, s1 - s2 * s2 - 1.0);
                if want_j {
                    let mut tp = 1.0;
                    for k in 0..n {
                        let d1 = if k >= 1 { k as f64 * tp / t } else { 0.0 };
                        jset!(i, k, d1 - 2.0 * s2 * tp);
                        tp *= t;
                    }
                }
            }
            out!(29, x[0]);
            out!(30, x[1] - x[0] * x[0] - 1.0);
            if want_j {
                jset!(29, 0, 1.0);
                jset!(30, 0, -2.0 * x[0]);
                jset!(30, 1, 1.0);
            }
        }
        ExtendedRosenbrock => {
            for b in 0..n / 2 {
                let o = 2 * b;
                out!(o, 10.0 * (x[o + 1] - x[o] * x[o]));
                out!(o + 1, 1.0 - x[o]);
                if want_j {
                    jset!(o, o, -20.0 * x[o]);
                    jset!(o, o + 1, 10.0);
                    jset!(o + 1, o, -1.0);
                }
            }
        }
        PenaltyI => {
            let sa = 1e-5f64.sqrt();
            let mut s = 0.0;
            for k in 0..n {
                out!(k, sa * (x[k] - 1.0));
                s += x[k] * x[k];
                if want_j {
                    jset!(k, k, sa);
                    jset!(n, k, 2.0 * x[k]);
                }
            }
            out!(n, s - 0.25);
        }
        PenaltyII => {
            let sa = 1e-5f64.sqrt();
            let e = |v: f64| (v / 10.0).exp();
            out!(0, x[0] - 0.2);
            if want_j {
                jset!(0, 0, 1.0);
            }
            for i in 1..n {
                let y = e((i + 1) as f64) + e(i as f64);
                out!(i, sa * (e(x[i]) + e(x[i - 1]) - y));
                if want_j {
                    jset!(i, i, sa * e(x[i]) / 10.0);
                    jset!(i, i - 1, sa * e(x[i - 1]) / 10.0);
                }
            }
            for i in n..2 * n - 1 {
                let k = i - n + 1;
                out!(i, sa * (e(x[k]) - (-0.1f64).exp()));
                if want_j {
                    jset!(i, k, sa * e(x[k]) / 10.0);
                }
            }
            let mut s = 0.0;
            for k in 0..n {
                s += (n - k) as f64 * x[k] * x[k];
                if want_j {
                    jset!(2 * n - 1, k, 2.0 * (n - k) as f64 * x[k]);
                }
            }
            out!(2 * n - 1, s - 1.0);
        }
        VariablyDimensioned => {
            let s: f64 = (0..n).map(|k| (k + 1) as f64 * (x[k] - 1.0)).sum();
            for k in 0..n {
                out!(k, x[k] - 1.0);
                if want_j {
                    jset!(k, k, 1.0);
                    jset!(n, k, (k + 1) as f64);
                    jset!(n + 1, k, 2.0 * s * (k + 1) as f64);
                }
            }
            out!(n, s);
            out!(n + 1, s * s);
        }
        Trigonometric => {
            let sc: f64 = x.iter().map(|v| v.cos()).sum();
            for i in 0..n {
                let (s, c) = x[i].sin_cos();
                out!(i, n as f64 - sc + (i + 1) as f64 * (1.0 - c) - s);
                if want_j {
                    for k in 0..n {
                        jset!(i, k, x[k].sin());
                    }
                    jset!(i, i, s + (i + 1) as f64 * s - c);
                }
            }
        }
        BrownAlmostLinear => {
            let s: f64 = x.iter().sum();
            for i in 0..n - 1 {
                out!(i, x[i] + s - (n + 1) as f64);
                if want_j {
                    for k in 0..n {
                        jset!(i, k, if k == i { 2.0 } else { 1.0 });
                    }
                }
            }
            out!(n - 1, x.iter().product::<f64>() - 1.0);
            if want_j {
                for k in 0..n {
                    let prod: f64 = (0..n).filter(|&q| q != k).map(|q| x[q]).product();
                    jset!(n - 1, k, prod);
                }
            }
        }
        DiscreteBoundaryValue => {
            let h = 1.0 / (n as f64 + 1.0);
            for i in 0..n {
                let t = (i + 1) as f64 * h;
                let xl = if i > 0 { x[i - 1] } else { 0.0 };
                let xr = if i + 1 < n { x[i + 1] } else { 0.0 };
                let c = x[i] + t + 1.0;
                out!(i, 2.0 * x[i] - xl - xr + 0.5 * h * h * c * c * c);
                if want_j {
                    jset!(i, i, 2.0 + 1.5 * h * h * c * c);
                    if i > 0 {
                        jset!(i, i - 1, -1.0);
                    }
                    if i + 1 < n {
                        jset!(i, i + 1, -1.0);
                    }
                }
            }
        }
        DiscreteIntegralEquation => {
            let h = 1.0 / (n as f64 + 1.0);
            let t = |k: usize| (k + 1) as f64 * h;
            for i in 0..n {
                let ti = t(i);
                let (mut s1, mut s2) = (0.0, 0.0);
                for k in 0..n {
                    let c = x[k] + t(k) + 1.0;
                    if k <= i {
                        s1 += t(k) * c * c * c;
                    } else {
                        s2 += (1.0 - t(k)) * c * c * c;
                    }
                    if want_j {
                        let d = if k <= i {
                            (1.0 - ti) * t(k)
                        } else {
                            ti * (1.0 - t(k))
                        };
                        let v = 0.5 * h * d * 3.0 * c * c + if k == i { 1.0 } else { 0.0 };
                        jset!(i, k, v);
                    }
                }
                out!(i, x[i] + 0.5 * h * ((1.0 - ti) * s1 + ti * s2));
            }
        }
        BroydenTridiagonal => {
            for i in 0..n {
                let xl = if i > 0 { x[i - 1] } else { 0.0 };
                let xr = if i + 1 < n { x[i + 1] } else { 0.0 };
                out!(i, (3.0 - 2.0 * x[i]) * x[i] - xl - 2.0 * xr + 1.0);
                if want_j {
                    jset!(i, i, 3.0 - 4.0 * x[i]);
                    if i > 0 {
                        jset!(i, i - 1, -1.0);
                    }
                    if i + 1 < n {
                        jset!(i, i + 1, -2.0);
                    }
                }
            }
        }
        BroydenBanded => {
            for i in 0..n {
                let lo = i.saturating_sub(5);
                let hi = (i + 1).min(n - 1);
                let mut s = 0.0;
                for k in lo..=hi {
                    if k != i {
                        s += x[k] * (1.0 + x[k]);
                        if want_j {
                            jset!(i, k, -(1.0 + 2.0 * x[k]));
                        }
                    }
                }
                out!(i, x[i] * (2.0 + 5.0 * x[i] * x[i]) + 1.0 - s);
                if want_j {
                    jset!(i, i, 2.0 + 15.0 * x[i] * x[i]);
                }
            }
        }
        LinearFullRank => {
            let s: f64 = x.iter().sum();
            let mf = m as f64;
            for i in 0..m {
                let xi = if i < n { x[i] } else { 0.0 };
                out!(i, xi - 2.0 * s / mf - 1.0);
                if want_j {
                    for k in 0..n {
                        jset!(i, k, if k == i { 1.0 } else { 0.0 } - 2.0 / mf);
                    }
                }
            }
        }
        LinearRankOne => {
            let s: f64 = (0..n).map(|k| (k + 1) as f64 * x[k]).sum();
            for i in 0..m {
                out!(i, (i + 1) as f64 * s - 1.0);
                if want_j {
                    for k in 0..n {
                        jset!(i, k, ((i + 1) * (k + 1)) as f64);
                    }
                }
            }
        }
        LinearRankOneZero => {
            let s: f64 = (1..n - 1).map(|k| (k + 1) as f64 * x[k]).sum();
            out!(0, -1.0);
            out!(m - 1, -1.0);
            for i in 1..m - 1 {
                out!(i, i as f64 * s - 1.0);
                if want_j {
                    for k in 1..n - 1 {
                        jset!(i, k, (i * (k + 1)) as f64);
                    }
                }
            }
        }
        Chebyquad => {
            let nf = n as f64;
            if !want_j {
                r[..m].fill(0.0);
            }
            for k in 0..n {
                // Shifted Chebyshev polynomials T_i(x) on [0, 1] and their derivatives.
                let z = 2.0 * x[k] - 1.0;
                let (mut t0, mut t1) = (1.0, z);
                let (mut d0, mut d1) = (0.0, 2.0);
                for i in 0..m {
                    if !want_j {
                        r[i] += t1 / nf;
                    } else {
                        jset!(i, k, d1 / nf);
                    }
                    let t2 = 2.0 * z * t1 - t0;
                    let d2 = 4.0 * t1 + 2.0 * z * d1 - d0;
                    (t0, t1, d0, d1) = (t1, t2, d1, d2);
                }
            }
            if !want_j {
                for i in 0..m {
                    let q = (i + 1) as f64;
                    if (i + 1) % 2 == 0 {
                        r[i] += 1.0 / (q * q - 1.0);
                    }
                }
            }
        }
    }
}
