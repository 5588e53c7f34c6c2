//! End-to-end checks of the renderer (Figures 8 and 12) and the polar plots (Figure 18) on the
//! paper's named BRDFs and the Cornell data shipped in experiments/data.
//!
//! Set `BRDF_SLS_SAMPLE_DIR` to keep the images (they go to a temporary directory otherwise).

use std::path::{Path, PathBuf};

use brdf_graphics::ImageFormat as PlotFormat;
use brdf_graphics::polar::{
    PolarCurve, PolarMeasured, PolarPlot, SliceSelection, draw_polar, incident_angles,
    polar_panels, select_in_plane,
};
use brdf_graphics::render::{RenderOptions, render_png, tone_map};
use brdf_io::read_cornell;
use brdf_model::{Filters, named_params};
use plotters::style::RGBColor;

fn out_dir(tmp: &tempfile::TempDir) -> PathBuf {
    std::env::var_os("BRDF_SLS_SAMPLE_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| tmp.path().to_path_buf())
}

fn cornell(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../experiments/data/{name}.brdf"))
}

#[test]
fn figures_8_and_12_render_differently() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = out_dir(&tmp);
    let opts = RenderOptions::default();
    let tuning = render_png(
        &named_params("tuning").unwrap().into(),
        &opts,
        &dir.join("fig08-tuning.png"),
    )
    .unwrap();
    let cross = render_png(
        &named_params("cross").unwrap().into(),
        &opts,
        &dir.join("fig12-cross.png"),
    )
    .unwrap();
    assert_eq!((tuning.width, tuning.height), (512, 512));
    for f in ["fig08-tuning.png", "fig12-cross.png"] {
        assert!(std::fs::metadata(dir.join(f)).unwrap().len() > 10_000);
    }
    // The cross BRDF adds a second lobe: never darker, and clearly brighter somewhere the
    // tuning BRDF is dim (the second arm of the cross).
    let (t8, c8) = (tone_map(&tuning, &opts), tone_map(&cross, &opts));
    assert!(
        tuning
            .radiance
            .iter()
            .zip(&cross.radiance)
            .all(|(t, c)| c >= t)
    );
    let new_bright = t8
        .chunks(3)
        .zip(c8.chunks(3))
        .filter(|(t, c)| c[0] > 150 && t[0] < 110)
        .count();
    assert!(new_bright > 2000, "{new_bright} pixels");
}

#[test]
fn figure_18_from_cornell_data() {
    let (data, _) = read_cornell(cornell("krylon_blue"), 550.0, &Filters::paper()).unwrap();
    let sel = SliceSelection::default();
    let angles = incident_angles(&data, &sel);
    let listed: Vec<f64> = angles.iter().map(|a| a.0).collect();
    assert_eq!(
        listed,
        vec![10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0],
        "{angles:?}"
    );
    assert!(angles.iter().all(|a| a.1 >= 10), "{angles:?}");
    let mut plot = PolarPlot::new(
        "krylon_blue at 550 nm in the plane of incidence",
        vec![10.0, 40.0, 70.0],
    );
    plot.measured = Some(PolarMeasured {
        label: "measured (Cornell krylon_blue)",
        data: &data,
        color: RGBColor(31, 119, 180),
    });
    plot.curves.push(PolarCurve {
        label: "pbrt-v1 3-lobe fit (Lafortune)".into(),
        params: named_params("pbrt-bluepaint").unwrap().into(),
        color: RGBColor(0, 0, 0),
        dashed: false,
    });
    plot.curves.push(PolarCurve {
        label: "paper Table 6".into(),
        params: named_params("paper-bluepaint").unwrap().into(),
        color: RGBColor(214, 39, 40),
        dashed: false,
    });
    let panels = polar_panels(&plot);
    for p in &panels {
        // Every measured in-plane sample at this angle, on both sides of the normal.
        assert!(
            p.measured.len() >= 10,
            "{}: {}",
            p.theta_i_deg,
            p.measured.len()
        );
        assert!(p.measured.iter().any(|s| s.theta_o_deg < 0.0));
        assert!(p.measured.iter().any(|s| s.theta_o_deg > 0.0));
    }
    // Unfiltered, the measured peak is on the forward side near the mirror direction (the
    // paper's filter drops values above 1, which removes the glossy peak at 70 degrees).
    let (raw, _) = read_cornell(cornell("krylon_blue"), 550.0, &Filters::default()).unwrap();
    for ti in [10.0, 40.0, 70.0] {
        let slice = select_in_plane(&raw, ti, &sel);
        let peak = slice
            .iter()
            .max_by(|a, b| a.value.total_cmp(&b.value))
            .unwrap();
        assert!(
            (peak.theta_o_deg - ti).abs() < 12.0,
            "{ti}: peak at {}",
            peak.theta_o_deg
        );
    }
    let tmp = tempfile::tempdir().unwrap();
    let files = draw_polar(
        &plot,
        &out_dir(&tmp).join("fig18-polar"),
        &[PlotFormat::Png, PlotFormat::Svg],
    )
    .unwrap();
    for f in files {
        assert!(std::fs::metadata(&f).unwrap().len() > 5_000, "{f:?}");
    }
}
