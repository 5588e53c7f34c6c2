//! `brdf-sls render`: a BRDF on a lit square, to PNG (the paper's Figures 8 and 12).

use anyhow::Result;

use super::{input_error, say};
use crate::cli::RenderArgs;

/// Turns a renderer error into one naming the command-line flag: the library's messages name
/// the `RenderOptions` field they are about, first.
fn render_error(e: brdf_graphics::render::RenderError) -> anyhow::Error {
    use brdf_graphics::render::RenderError;
    const FLAGS: [(&str, &str); 11] = [
        ("width", "--width/--height"),
        ("supersampling", "--supersampling"),
        ("camera", "--camera"),
        ("light", "--light"),
        ("look_at", "--look-at"),
        ("fov_deg", "--fov"),
        ("intensity", "--intensity"),
        ("plane_half_size", "--half-size"),
        ("exposure", "--exposure"),
        ("tint", "--tint"),
        ("degenerate camera", "--camera/--look-at"),
    ];
    match e {
        RenderError::InvalidOption(m) => match FLAGS.iter().find(|(k, _)| m.starts_with(k)) {
            Some((_, flag)) => input_error(format!("{flag}: {m}")),
            None => input_error(format!("invalid render option: {m}")),
        },
        other => other.into(),
    }
}

/// `brdf-sls render`.
pub fn render(a: RenderArgs) -> Result<()> {
    let params = a.params.params().map_err(input_error)?;
    if !a
        .out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        return Err(input_error(format!(
            "--out {}: the renderer writes PNG; give a file name ending in .png",
            a.out.display()
        )));
    }
    // render_png validates the options (render_radiance does) before drawing anything.
    let opts = a.options();
    let img = brdf_graphics::render::render_png(&params, &opts, &a.out).map_err(render_error)?;
    // Exposure diagnostics: how much of the surface is burnt out (clamp) helps choose
    // --exposure/--intensity without guessing.
    let gain = opts.exposure * opts.tint.iter().copied().fold(0.0, f64::max);
    let on_surface = || (0..img.radiance.len()).filter(|&i| img.coverage[i] > 0.0);
    let covered = on_surface().count();
    let clipped = on_surface()
        .filter(|&i| img.radiance[i] * gain >= 1.0)
        .count();
    let (_, _, peak) = img.brightest();
    let clip_note = match opts.tone_map {
        brdf_graphics::render::ToneMap::Clamp if covered > 0 => format!(
            "; {:.1}% of the surface clipped at white",
            100.0 * clipped as f64 / covered as f64
        ),
        _ => String::new(),
    };
    say!(
        "wrote {} ({}x{}): peak radiance {peak:.4}, x exposure {} = {:.4}{clip_note}",
        a.out.display(),
        img.width,
        img.height,
        opts.exposure,
        peak * opts.exposure,
    );
    Ok(())
}
