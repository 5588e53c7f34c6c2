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

mod eval;

use crate::{Options, Problem, Scaling};
use eval::eval;
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
