//! Data-set commands: `gen` (synthetic data to CSV), `eval` (RMSE of given parameters) and
//! `info` (what a data file holds).

use anyhow::{Context, Result};

use super::shared::{load_data, load_non_empty, params_rmse};
use super::{flush_stdout, input_error, note, say};
use crate::cli::{EvalArgs, GenArgs, InfoArgs};

/// `brdf-sls gen`.
pub fn generate(a: GenArgs) -> Result<()> {
    let params = a.params.params().map_err(input_error)?;
    let data = brdf_model::try_synthetic(&params, a.samples, a.sigma, a.seed)?;
    match &a.out {
        Some(p) => {
            let mut buf = Vec::new();
            data.write_csv(&mut buf)?;
            brdf_experiment::store::write_atomic(p, &buf)
                .with_context(|| format!("writing {}", p.display()))?;
            note!("wrote {} samples to {}", data.len(), p.display());
        }
        None => {
            let stdout = std::io::stdout();
            data.write_csv(std::io::BufWriter::new(stdout.lock()))
                .map_err(|e| anyhow::Error::new(e).context("writing to standard output"))?;
            flush_stdout()?;
        }
    }
    Ok(())
}

/// `brdf-sls eval`.
pub fn eval(a: EvalArgs) -> Result<()> {
    let params = a.params.params().map_err(input_error)?;
    let (data, _) = load_non_empty(&a.data)?;
    let rmse = params_rmse(&params, &data)?;
    say!("RMSE {}", significant(rmse, a.digits));
    Ok(())
}

/// `x` with `digits` significant digits (17 tell any two f64 apart).
fn significant(x: f64, digits: u8) -> String {
    format!("{x:.*e}", usize::from(digits.saturating_sub(1)))
        .parse::<f64>()
        .map(|v| v.to_string())
        .unwrap_or_else(|_| x.to_string())
}

/// The 10-degree bin of a polar angle. Data files store angles rounded (Cornell: radians to 6
/// decimals, so 70 degrees reads as 69.99997); a tolerance of 1e-4 degrees, far below any
/// measurement's resolution, keeps such values in the bin they were meant for.
fn angle_bin(theta_deg: f64) -> usize {
    const TOLERANCE_DEG: f64 = 1e-4;
    (((theta_deg + TOLERANCE_DEG) / 10.0).floor().max(0.0) as usize).min(8)
}

/// `brdf-sls info`.
pub fn info(a: InfoArgs) -> Result<()> {
    let (data, rep) = load_data(&a.data)?;
    say!("{}", a.data.data.display());
    say!("samples: {}", data.len());
    say!("filters: {rep}");
    if data.is_empty() {
        return Ok(());
    }
    let n = data.len();
    let mut vals: Vec<f64> = data.values().to_vec();
    vals.sort_by(f64::total_cmp);
    let mean = vals.iter().sum::<f64>() / n as f64;
    say!(
        "value: min {}, median {}, mean {}, max {}",
        vals[0],
        vals[n / 2],
        mean,
        vals[n - 1]
    );
    let angles = |d: [f64; 3]| {
        let theta = d[2].clamp(-1.0, 1.0).acos().to_degrees();
        let phi = d[1].atan2(d[0]).to_degrees();
        (theta, phi)
    };
    for (name, which) in [("incident", 0), ("exitant", 1)] {
        let mut tmin = f64::INFINITY;
        let mut tmax = f64::NEG_INFINITY;
        let mut pmin = f64::INFINITY;
        let mut pmax = f64::NEG_INFINITY;
        let mut bins = [0usize; 9];
        for i in 0..n {
            let d = if which == 0 { data.u(i) } else { data.v(i) };
            let (t, p) = angles(d);
            tmin = tmin.min(t);
            tmax = tmax.max(t);
            pmin = pmin.min(p);
            pmax = pmax.max(p);
            bins[angle_bin(t)] += 1;
        }
        say!(
            "{name}: theta {tmin:.1}..{tmax:.1} deg, phi {pmin:.1}..{pmax:.1} deg; theta histogram (10-degree bins): {bins:?}"
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angle_bins_tolerate_stored_rounding() {
        assert_eq!(angle_bin(1.221730_f64.to_degrees()), 7);
        assert_eq!(angle_bin(69.9), 6);
        assert_eq!(angle_bin(0.0), 0);
        assert_eq!(angle_bin(90.0), 8);
        assert_eq!(angle_bin(95.0), 8);
    }

    #[test]
    fn significant_digits() {
        assert_eq!(significant(0.123456789, 3), "0.123");
        assert_eq!(significant(0.1 + 0.2, 17), "0.30000000000000004");
    }
}
