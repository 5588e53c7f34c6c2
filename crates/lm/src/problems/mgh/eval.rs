//! The residuals and Jacobians of the 35 problems, one arm per problem (the formulas of
//! Moré, Garbow and Hillstrom 1981, section 3).

use super::*;

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
pub(super) fn eval(p: &Mgh, x: &[f64], r: &mut [f64], jac: Option<&mut [f64]>) {
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
