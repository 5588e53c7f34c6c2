//! `brdf-sls polar`: measured data and fitted models in the plane of incidence (Figure 18).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use brdf_experiment::store::read_results;
use brdf_model::{DataSet, Params};

use super::shared::{load_data, load_non_empty, params_rmse};
use super::{bail_input, input_error, note, say};
use crate::cli::PolarArgs;
use crate::cli::values::{assignment, params};

/// Curve colours in order: red and black first, as the paper's Figure 18 (measured data is
/// blue), then colours that stay apart from those.
const CURVE_COLORS: [(u8, u8, u8); 6] = [
    (214, 39, 40),
    (0, 0, 0),
    (44, 160, 44),
    (255, 127, 14),
    (148, 103, 189),
    (140, 86, 75),
];

/// Parses one `--fit LABEL=PARAMS` (the label is optional; `index` numbers unlabelled JSON).
fn parse_fit(s: &str, index: usize) -> Result<(String, Params)> {
    // JSON holds no `=` before its `{`, a label no `{`: split at an `=` before any brace.
    let (label, p) = match assignment(s) {
        Ok((l, p)) if !l.contains('{') => (l, p),
        _ => (String::new(), s.trim().to_string()),
    };
    let parsed = params(&p).map_err(|e| input_error(format!("--fit {e}")))?;
    let label = if !label.is_empty() {
        label
    } else if brdf_model::named_params(&p).is_some() || p.starts_with('@') {
        p.trim_start_matches('@').to_string()
    } else {
        format!("fit {index}")
    };
    Ok((label, parsed))
}

/// The best trial (lowest final RMSE) of configuration `config` on `instance` in a results
/// directory (or trials.jsonl), decoded with the instance's model layout from the stored spec.
/// Returns a label for it and the parameters.
fn best_from_results(
    target: &Path,
    config: &str,
    instance: Option<&str>,
) -> Result<(String, Params)> {
    if !target.exists() {
        bail_input!(
            "--from-results {}: no such results directory or trials.jsonl file",
            target.display()
        );
    }
    let dir = if target.is_dir() {
        target.to_path_buf()
    } else {
        // A trials.jsonl file: its directory holds the results.
        match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        }
    };
    let contents = read_results(&dir)
        .with_context(|| format!("--from-results: reading results in {}", dir.display()))?;
    let spec = super::shared::stored_spec(
        &contents,
        &dir,
        &format!("--from-results {}", dir.display()),
        "the model layout is",
    )?;
    let names = || {
        spec.instances
            .iter()
            .map(|i| i.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let inst = match instance {
        Some(n) => spec
            .instances
            .iter()
            .find(|i| i.name == n)
            .with_context(|| format!("--instance `{n}`: not in the experiment ({})", names()))?,
        None if spec.instances.len() == 1 => &spec.instances[0],
        None => bail_input!(
            "--from-results: the experiment has {} instances; choose one with --instance ({})",
            spec.instances.len(),
            names()
        ),
    };
    if !spec.configurations.iter().any(|c| c.label == config) {
        let labels: Vec<&str> = spec
            .configurations
            .iter()
            .map(|c| c.label.as_str())
            .collect();
        bail_input!(
            "--config `{config}`: not in the experiment (configurations: {})",
            labels.join(", ")
        );
    }
    let best = contents
        .records
        .iter()
        .filter(|r| r.instance == inst.name && r.config == config)
        .filter(|r| r.result.best_rmse.is_finite() && !r.result.best_x.is_empty())
        .min_by(|a, b| a.result.best_rmse.total_cmp(&b.result.best_rmse))
        .with_context(|| {
            format!(
                "--from-results {}: no finished trial of `{config}` on `{}`",
                dir.display(),
                inst.name
            )
        })?;
    let layout = inst
        .model
        .layout()
        .with_context(|| format!("instance `{}`: model", inst.name))?;
    if best.result.best_x.len() != layout.dim() {
        bail_input!(
            "--from-results: trial {} stores {} parameters, the model of `{}` has {}",
            best.key,
            best.result.best_x.len(),
            inst.name,
            layout.dim()
        );
    }
    let label = format!(
        "{config} best of {} (trial {})",
        contents
            .records
            .iter()
            .filter(|r| r.instance == inst.name && r.config == config)
            .count(),
        best.trial
    );
    Ok((label, layout.decode(&best.result.best_x)))
}

/// `brdf-sls polar`.
pub fn polar(a: PolarArgs) -> Result<()> {
    use brdf_graphics::RGBColor;
    use brdf_graphics::polar::{
        PolarCurve, PolarMeasured, PolarPlot, SliceSelection, default_incident_angles, draw_polar,
        incident_angles, select_in_plane,
    };

    for (flag, v, hi) in [
        ("--incident-tol", a.incident_tol, 90.0),
        ("--plane-tol", a.plane_tol, 90.0),
        ("--phi-i", a.phi_i, 360.0),
    ] {
        if !(v.is_finite() && v.abs() <= hi && (flag == "--phi-i" || v >= 0.0)) {
            bail_input!(
                "{flag} {v}: expected degrees in {}",
                if flag == "--phi-i" {
                    "[-360, 360]"
                } else {
                    "[0, 90]"
                }
            );
        }
    }
    let radius = a.radius;
    let (data, _) = load_non_empty(&a.data)?;
    let sel = SliceSelection {
        phi_i_deg: a.phi_i,
        incident_tol_deg: a.incident_tol,
        plane_tol_deg: a.plane_tol,
    };
    let available = incident_angles(&data, &sel);
    let list = |v: &[(f64, usize)]| {
        const SHOWN: usize = 24;
        let mut s: Vec<String> = v.iter().take(SHOWN).map(|a| format!("{}", a.0)).collect();
        if v.len() > SHOWN {
            s.push(format!("... ({} in all)", v.len()));
        }
        if s.is_empty() {
            "none".into()
        } else {
            s.join(", ")
        }
    };
    let incident = if a.incident.is_empty() {
        let d = default_incident_angles(&available, 3);
        if d.is_empty() {
            bail_input!(
                "{}: no sample has both directions within {} degrees of the plane of incidence \
                 (azimuth {}); widen --plane-tol or give --incident",
                a.data.data.display(),
                sel.plane_tol_deg,
                sel.phi_i_deg
            );
        }
        d
    } else {
        a.incident.clone()
    };
    for &t in &incident {
        if !(t.is_finite() && (0.0..90.0).contains(&t)) {
            bail_input!("--incident {t}: incident angles must be in [0, 90) degrees");
        }
        if select_in_plane(&data, t, &sel).is_empty() {
            bail_input!(
                "--incident {t}: {} has no in-plane samples within {} degrees of that incident \
                 angle (and {} degrees of the plane); in-plane incident angles available: {} \
                 (or widen --incident-tol/--plane-tol)",
                a.data.data.display(),
                sel.incident_tol_deg,
                sel.plane_tol_deg,
                list(&available)
            );
        }
    }

    let mut fits = Vec::new();
    for (k, f) in a.fits.iter().enumerate() {
        fits.push(parse_fit(f, k + 1)?);
    }
    if let (Some(dir), Some(config)) = (&a.from_results, &a.config) {
        fits.push(best_from_results(dir, config, a.instance.as_deref())?);
    }
    if fits.len() > CURVE_COLORS.len() {
        bail_input!(
            "at most {} models per plot (--fit and --from-results), got {}",
            CURVE_COLORS.len(),
            fits.len()
        );
    }
    let mut curves = Vec::new();
    for (k, (label, params)) in fits.into_iter().enumerate() {
        let rmse = params_rmse(&params, &data)?;
        say!(
            "{label}: RMSE {rmse:.6} on {} samples; json: {}",
            data.len(),
            serde_json::to_string(&params)?
        );
        let (r, g, b) = CURVE_COLORS[k];
        curves.push(PolarCurve {
            label: format!("{label} (RMSE {rmse:.4})"),
            params,
            color: RGBColor(r, g, b),
            dashed: false,
        });
    }

    let file_name = a
        .data
        .data
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let wavelength = match a.data.file_spec().format_for(&a.data.data) {
        Ok(brdf_io::Format::Cornell { wavelength_nm }) => Some(wavelength_nm),
        _ => None,
    };
    let title = a.title.clone().unwrap_or_else(|| {
        let mut t = file_name.clone();
        if let Some(w) = wavelength {
            t.push_str(&format!(" at {w} nm"));
        }
        if let Some(m) = a.data.max_value {
            t.push_str(&format!(", values > {m} dropped"));
        }
        t.push_str(": BRDF in the plane of incidence");
        t
    });
    let data_label = a
        .data_label
        .clone()
        .unwrap_or_else(|| format!("measured ({file_name})"));
    // The samples the value cap removed: the same file read without the cap, kept above it.
    let dropped = match (a.show_dropped, a.data.max_value) {
        (true, Some(cap)) => {
            let mut uncapped = a.data.clone();
            uncapped.max_value = None;
            let (raw, _) = load_data(&uncapped)?;
            let mut d = DataSet::new();
            for i in (0..raw.len()).filter(|&i| raw.value(i) > cap) {
                d.push(raw.u(i), raw.v(i), raw.value(i));
            }
            Some((d, format!("dropped (values > {cap})")))
        }
        _ => None,
    };
    const MEASURED_COLOR: RGBColor = RGBColor(31, 119, 180);
    let mut plot = PolarPlot::new(title, incident.clone());
    plot.selection = sel;
    plot.measured = Some(PolarMeasured {
        label: &data_label,
        data: &data,
        color: MEASURED_COLOR,
    });
    plot.dropped = dropped.as_ref().map(|(d, label)| PolarMeasured {
        label,
        data: d,
        color: MEASURED_COLOR,
    });
    plot.curves = curves;
    plot.radius = radius;
    plot.shared_radius = a.shared_radius;
    let mut formats = Vec::new();
    for &f in &a.formats {
        if !formats.contains(&f) {
            formats.push(f);
        }
    }
    for p in brdf_graphics::polar::polar_panels(&plot) {
        note!(
            "incident {}: {} measured in-plane samples ({} dropped), radius {}",
            p.theta_i_deg,
            p.measured.len(),
            p.dropped.len(),
            brdf_graphics::chart::tick(p.r_max)
        );
    }
    let files = draw_polar(&plot, &a.out, &formats)?;
    for f in files {
        say!("wrote {}", f.display());
    }
    Ok(())
}
