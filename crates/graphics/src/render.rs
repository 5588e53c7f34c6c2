//! A small CPU renderer for the paper's Figures 8 and 12: a flat square surface (the `z = 0`
//! plane, normal `+z`) lit by a single point light and seen through a pinhole camera.
//!
//! Per pixel (and per supersample) the camera ray is intersected with the plane; at the hit
//! point `p` the renderer forms `u` = unit direction from `p` to the light and `v` = unit
//! direction from `p` to the camera (both pointing away from the surface, the model's
//! convention) and computes the reflected radiance
//! `L = f(u, v) * cos(theta_u) * intensity / r^2` (`r` = distance to the light).
//! The linear image is then exposed, tone mapped ([`ToneMap`]), tinted, sRGB encoded and
//! written as an 8-bit RGB PNG.
//!
//! Everything is deterministic: supersamples sit on a fixed regular grid inside each pixel and
//! rows are rendered in parallel into disjoint slices (the result does not depend on the
//! number of threads). Nothing is allocated per pixel.
//!
//! API: [`RenderOptions`] (scene, camera, exposure; defaults chosen to show the anisotropic
//! highlights of the paper's `tuning` and `cross` BRDFs), [`render_radiance`] (linear image),
//! [`tone_map`] (8-bit sRGB), [`write_png`] and the one-call [`render_png`].

use std::path::{Path, PathBuf};

use brdf_model::Params;
use rayon::prelude::*;

/// Rendering errors.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// An option is out of its domain (the message names the option and the expected range).
    #[error("invalid render option: {0}")]
    InvalidOption(String),
    /// Encoding or writing the image failed.
    #[error("{path}: writing the image failed: {message}")]
    Write {
        /// The output file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

/// How exposed linear radiance is mapped to display values in `[0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ToneMap {
    /// `x / (1 + x)`: never saturates, compresses highlights.
    Reinhard,
    /// `min(x, 1)`: linear up to white, brighter values clip (the default).
    Clamp,
}

/// Scene, camera and image settings.
///
/// Coordinates: the surface is the square `|x|, |y| <= plane_half_size` in the `z = 0` plane,
/// normal `+z`; the BRDF's `x`, `y` axes are the world `x`, `y` axes (so a lobe's pan angle is
/// measured from the world `x` axis).
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Image width in pixels (>= 1).
    pub width: u32,
    /// Image height in pixels (>= 1).
    pub height: u32,
    /// Supersamples per pixel along each axis (>= 1; `s * s` samples on a regular grid).
    pub supersampling: u32,
    /// Camera (pinhole) position; must be above the plane (`z > 0`).
    pub camera: [f64; 3],
    /// Point the camera looks at.
    pub look_at: [f64; 3],
    /// Vertical field of view in degrees, in `(0, 180)`.
    pub fov_deg: f64,
    /// Point light position; must be above the plane (`z > 0`).
    pub light: [f64; 3],
    /// Light intensity (radiant intensity; radiance scales linearly with it), >= 0.
    pub intensity: f64,
    /// Half the side of the square surface (> 0).
    pub plane_half_size: f64,
    /// Multiplier applied to the linear radiance before tone mapping (> 0).
    pub exposure: f64,
    /// Tone mapping operator.
    pub tone_map: ToneMap,
    /// Per-channel colour of the surface (linear, multiplies the radiance; each >= 0).
    pub tint: [f64; 3],
    /// Colour (8-bit sRGB) of pixels whose ray misses the surface.
    pub background: [u8; 3],
}

impl Default for RenderOptions {
    /// A 512x512 view of a 3.2x3.2 square from 2.2 above and slightly in front of its centre
    /// (66 degree field of view), the light 1.9 above the centre, clamp tone mapping.
    ///
    /// Why this scene: the paper's tuning lobe (`Cx = -1, Cy = 0.8, Cz = 0.96`, pan 45
    /// degrees) is forward-reflecting along its x' axis but retro-reflecting along y'. With
    /// the light close to the camera every surface point sees nearly retro-reflective
    /// geometry, so the lobe stays bright far out along y' and dies quickly along x': the
    /// `tuning` BRDF shows a diagonal streak and the `cross` BRDF (the same lobe also at -45
    /// degrees) an X. A light far to the side of the camera shows at most a faint, broad
    /// highlight for both. Intensity 3 keeps the centre of the X (`kd` plus two lobes) below
    /// white.
    fn default() -> Self {
        RenderOptions {
            width: 512,
            height: 512,
            supersampling: 2,
            camera: [0.0, -0.6, 2.2],
            look_at: [0.0, 0.0, 0.0],
            fov_deg: 66.0,
            light: [0.0, 0.0, 1.9],
            intensity: 3.0,
            plane_half_size: 1.6,
            exposure: 1.0,
            tone_map: ToneMap::Clamp,
            tint: [1.0, 1.0, 1.0],
            background: [24, 24, 30],
        }
    }
}

/// An orthonormal pinhole camera built from [`RenderOptions`].
#[derive(Clone, Copy, Debug)]
struct Camera {
    eye: [f64; 3],
    forward: [f64; 3],
    right: [f64; 3],
    up: [f64; 3],
    /// tan(fov / 2): half the image-plane height at unit distance.
    tan_half: f64,
    aspect: f64,
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

fn normalize(a: [f64; 3]) -> Option<[f64; 3]> {
    let l = dot(a, a).sqrt();
    (l > 0.0 && l.is_finite()).then(|| scale(a, 1.0 / l))
}

impl RenderOptions {
    /// Checks every option, naming the first one out of its domain.
    pub fn validate(&self) -> Result<(), RenderError> {
        let bad = |m: String| Err(RenderError::InvalidOption(m));
        if self.width == 0 || self.height == 0 {
            return bad(format!(
                "width and height must be >= 1 (got {}x{})",
                self.width, self.height
            ));
        }
        // Keeps the buffer (3 bytes per pixel) far below what a machine can hold.
        if u64::from(self.width) * u64::from(self.height) > 64_000_000 {
            return bad(format!(
                "width x height must be <= 64 megapixels (got {}x{})",
                self.width, self.height
            ));
        }
        if self.supersampling == 0 || self.supersampling > 16 {
            return bad(format!(
                "supersampling must be in 1..=16 (got {})",
                self.supersampling
            ));
        }
        let finite = |v: &[f64; 3]| v.iter().all(|c| c.is_finite());
        if !finite(&self.camera) || self.camera[2] <= 0.0 {
            return bad(format!(
                "camera must be finite and above the plane (z > 0), got {:?}",
                self.camera
            ));
        }
        if !finite(&self.light) || self.light[2] <= 0.0 {
            return bad(format!(
                "light must be finite and above the plane (z > 0), got {:?}",
                self.light
            ));
        }
        if !finite(&self.look_at) {
            return bad(format!("look_at must be finite, got {:?}", self.look_at));
        }
        if !(self.fov_deg > 0.0 && self.fov_deg < 180.0) {
            return bad(format!("fov_deg must be in (0, 180), got {}", self.fov_deg));
        }
        if !(self.intensity >= 0.0 && self.intensity.is_finite()) {
            return bad(format!(
                "intensity must be finite and >= 0, got {}",
                self.intensity
            ));
        }
        if !(self.plane_half_size > 0.0 && self.plane_half_size.is_finite()) {
            return bad(format!(
                "plane_half_size must be finite and > 0, got {}",
                self.plane_half_size
            ));
        }
        if !(self.exposure > 0.0 && self.exposure.is_finite()) {
            return bad(format!(
                "exposure must be finite and > 0, got {}",
                self.exposure
            ));
        }
        if !self.tint.iter().all(|t| *t >= 0.0 && t.is_finite()) {
            return bad(format!(
                "tint components must be finite and >= 0, got {:?}",
                self.tint
            ));
        }
        self.camera_frame().map(|_| ())
    }

    fn camera_frame(&self) -> Result<Camera, RenderError> {
        let forward = normalize(sub(self.look_at, self.camera))
            .ok_or_else(|| RenderError::InvalidOption("look_at must differ from camera".into()))?;
        // World z is "up"; a camera looking straight down uses world y as its up instead.
        let world_up = if forward[2].abs() > 0.999_999 {
            [0.0, 1.0, 0.0]
        } else {
            [0.0, 0.0, 1.0]
        };
        let right = normalize(cross(forward, world_up))
            .ok_or_else(|| RenderError::InvalidOption("degenerate camera orientation".into()))?;
        let up = cross(right, forward);
        Ok(Camera {
            eye: self.camera,
            forward,
            right,
            up,
            tan_half: (self.fov_deg.to_radians() * 0.5).tan(),
            aspect: f64::from(self.width) / f64::from(self.height),
        })
    }

    /// Pixel coordinates `[column, row]` (continuous; pixel `(i, j)` covers `[i, i+1) x [j, j+1)`,
    /// row 0 at the top) at which the world point `p` appears, or `None` when `p` is behind the
    /// camera or the options are invalid.
    pub fn project(&self, p: [f64; 3]) -> Option<[f64; 2]> {
        let cam = self.camera_frame().ok()?;
        let d = sub(p, cam.eye);
        let z = dot(d, cam.forward);
        if z <= 0.0 {
            return None;
        }
        let sx = dot(d, cam.right) / (z * cam.tan_half * cam.aspect);
        let sy = dot(d, cam.up) / (z * cam.tan_half);
        Some([
            (sx + 1.0) * 0.5 * f64::from(self.width),
            (1.0 - sy) * 0.5 * f64::from(self.height),
        ])
    }

    /// The point of the plane where a perfect mirror would reflect the light into the camera
    /// (where a sharp forward lobe puts its highlight), whether or not it lies on the square.
    pub fn mirror_point(&self) -> [f64; 3] {
        // The segment from the camera to the light mirrored below the plane crosses z = 0
        // at the fraction cz / (cz + lz) of its length.
        let c = self.camera;
        let l = [self.light[0], self.light[1], -self.light[2]];
        let t = c[2] / (c[2] + self.light[2]);
        [c[0] + (l[0] - c[0]) * t, c[1] + (l[1] - c[1]) * t, 0.0]
    }
}

/// A linear (scene-referred) radiance image, row-major, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct RadianceImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Mean radiance of each pixel's supersamples that hit the surface, weighted by the hit
    /// fraction (misses count as 0).
    pub radiance: Vec<f64>,
    /// Fraction of each pixel's supersamples that hit the surface (0 = background only).
    pub coverage: Vec<f64>,
}

impl RadianceImage {
    /// Radiance at column `x`, row `y` (panics if out of range, like slice indexing).
    pub fn at(&self, x: u32, y: u32) -> f64 {
        self.radiance[y as usize * self.width as usize + x as usize]
    }

    /// `(column, row, radiance)` of the brightest pixel (the first one on ties).
    pub fn brightest(&self) -> (u32, u32, f64) {
        let mut best = (0usize, f64::NEG_INFINITY);
        for (i, &l) in self.radiance.iter().enumerate() {
            if l > best.1 {
                best = (i, l);
            }
        }
        let w = self.width as usize;
        ((best.0 % w) as u32, (best.0 / w) as u32, best.1)
    }
}

/// Renders the linear radiance image of the surface with BRDF `params` (see the module docs
/// for the shading formula). Non-finite BRDF values (overflowing lobes) count as 0 so the
/// image stays finite.
pub fn render_radiance(
    params: &Params,
    opts: &RenderOptions,
) -> Result<RadianceImage, RenderError> {
    opts.validate()?;
    let cam = opts.camera_frame()?;
    let (w, h) = (opts.width as usize, opts.height as usize);
    let s = opts.supersampling as usize;
    let inv_samples = 1.0 / (s * s) as f64;
    let mut radiance = vec![0.0; w * h];
    let mut coverage = vec![0.0; w * h];
    radiance
        .par_chunks_mut(w)
        .zip(coverage.par_chunks_mut(w))
        .enumerate()
        .for_each(|(row, (rad_row, cov_row))| {
            for col in 0..w {
                let mut sum = 0.0;
                let mut hits = 0usize;
                for a in 0..s {
                    for b in 0..s {
                        // Regular grid, symmetric about the pixel centre, so mirrored scenes give
                        // mirrored images exactly.
                        let px = (col as f64 + (b as f64 + 0.5) / s as f64) / w as f64;
                        let py = (row as f64 + (a as f64 + 0.5) / s as f64) / h as f64;
                        if let Some(l) = shade(params, opts, &cam, px, py) {
                            sum += l;
                            hits += 1;
                        }
                    }
                }
                rad_row[col] = sum * inv_samples;
                cov_row[col] = hits as f64 * inv_samples;
            }
        });
    Ok(RadianceImage {
        width: opts.width,
        height: opts.height,
        radiance,
        coverage,
    })
}

/// Radiance seen along the ray through the normalised image point `(px, py)` (`[0, 1]^2`, `y`
/// down), or `None` when the ray misses the square.
fn shade(params: &Params, opts: &RenderOptions, cam: &Camera, px: f64, py: f64) -> Option<f64> {
    let sx = (2.0 * px - 1.0) * cam.tan_half * cam.aspect;
    let sy = (1.0 - 2.0 * py) * cam.tan_half;
    let d = [
        cam.forward[0] + sx * cam.right[0] + sy * cam.up[0],
        cam.forward[1] + sx * cam.right[1] + sy * cam.up[1],
        cam.forward[2] + sx * cam.right[2] + sy * cam.up[2],
    ];
    // The camera is above the plane, so only rays going down reach it.
    if d[2] >= 0.0 {
        return None;
    }
    let t = -cam.eye[2] / d[2];
    let p = [cam.eye[0] + t * d[0], cam.eye[1] + t * d[1], 0.0];
    if p[0].abs() > opts.plane_half_size || p[1].abs() > opts.plane_half_size {
        return None;
    }
    let to_light = sub(opts.light, p);
    let r2 = dot(to_light, to_light);
    let u = normalize(to_light)?;
    let v = normalize(sub(cam.eye, p))?;
    let cos_u = u[2];
    if cos_u <= 0.0 {
        return Some(0.0);
    }
    let f = params.value(u, v);
    let l = f * cos_u * opts.intensity / r2;
    Some(if l.is_finite() { l.max(0.0) } else { 0.0 })
}

/// sRGB transfer function (linear `[0, 1]` to encoded `[0, 1]`).
fn srgb_encode(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

fn srgb_decode(c: u8) -> f64 {
    let x = f64::from(c) / 255.0;
    if x <= 0.040_45 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

/// Maps a linear radiance image to 8-bit sRGB (`width * height * 3` bytes, row-major RGB):
/// exposure, tint, tone map, then sRGB encoding; partially covered pixels (the square's edges)
/// are blended with the background in linear space.
pub fn tone_map(img: &RadianceImage, opts: &RenderOptions) -> Vec<u8> {
    let bg = opts.background.map(srgb_decode);
    let mut out = vec![0u8; img.radiance.len() * 3];
    for (i, px) in out.chunks_exact_mut(3).enumerate() {
        let cov = img.coverage[i];
        let l = img.radiance[i] * opts.exposure;
        for c in 0..3 {
            let x = l * opts.tint[c];
            let t = match opts.tone_map {
                ToneMap::Reinhard => x / (1.0 + x),
                ToneMap::Clamp => x.min(1.0),
            };
            // radiance is already weighted by coverage; add the background's share.
            let lin = t + (1.0 - cov) * bg[c];
            px[c] = (srgb_encode(lin) * 255.0).round() as u8;
        }
    }
    out
}

/// Writes an 8-bit RGB buffer (`width * height * 3` bytes, row-major) as a PNG at `path`,
/// atomically (see [`crate::files::write_atomic`]). Parent directories are created.
pub fn write_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), RenderError> {
    let err = |message: String| RenderError::Write {
        path: path.to_path_buf(),
        message,
    };
    if rgb.len() != width as usize * height as usize * 3 {
        return Err(err(format!(
            "buffer holds {} bytes, {width}x{height} RGB needs {}",
            rgb.len(),
            width as usize * height as usize * 3
        )));
    }
    let png = crate::files::encode_png(rgb, width, height).map_err(err)?;
    crate::files::write_atomic(path, &png).map_err(|e| err(e.to_string()))
}

/// Renders `params` with `opts` and writes the PNG to `path` (see [`render_radiance`],
/// [`tone_map`], [`write_png`]). Returns the linear image (for statistics or tests).
pub fn render_png(
    params: &Params,
    opts: &RenderOptions,
    path: &Path,
) -> Result<RadianceImage, RenderError> {
    let img = render_radiance(params, opts)?;
    let rgb = tone_map(&img, opts);
    write_png(path, img.width, img.height, &rgb)?;
    Ok(img)
}

#[cfg(test)]
mod tests {
    use super::*;
    use brdf_model::{BrdfParams, Lobe, named_params};

    fn small(opts: RenderOptions) -> RenderOptions {
        RenderOptions {
            width: 96,
            height: 80,
            supersampling: 1,
            ..opts
        }
    }

    #[test]
    fn dimensions_and_not_black() {
        let opts = small(RenderOptions::default());
        let img = render_radiance(&named_params("tuning").unwrap().into(), &opts).unwrap();
        assert_eq!((img.width, img.height), (96, 80));
        assert_eq!(img.radiance.len(), 96 * 80);
        let rgb = tone_map(&img, &opts);
        assert_eq!(rgb.len(), 96 * 80 * 3);
        assert!(img.radiance.iter().all(|l| l.is_finite() && *l >= 0.0));
        // The square fills the middle of the default view.
        assert!(img.at(48, 40) > 0.0);
        let lit = rgb.iter().filter(|&&c| c > 60).count();
        assert!(lit > rgb.len() / 10, "only {lit} bright channels");
    }

    #[test]
    fn phong_highlight_at_mirror_point() {
        let phong: Params = BrdfParams {
            kd: 0.05,
            lobes: vec![Lobe::isotropic(-1.0, 1.0, 400.0)],
        }
        .into();
        let opts = RenderOptions {
            width: 128,
            height: 128,
            supersampling: 1,
            light: [0.4, 0.5, 1.6],
            ..RenderOptions::default()
        };
        let img = render_radiance(&phong, &opts).unwrap();
        let (x, y, l) = img.brightest();
        let m = opts.project(opts.mirror_point()).unwrap();
        let (dx, dy) = (f64::from(x) + 0.5 - m[0], f64::from(y) + 0.5 - m[1]);
        assert!(
            dx.hypot(dy) < 3.0,
            "brightest {x},{y} ({l}) vs mirror point {m:?}"
        );
        // And it is a highlight, not the diffuse floor.
        assert!(l > 20.0 * img.at(5, 120));
    }

    #[test]
    fn isotropic_brdf_mirrors_with_the_scene() {
        let iso: Params = BrdfParams {
            kd: 0.1,
            lobes: vec![
                Lobe::isotropic(-0.9, 0.9, 30.0),
                Lobe::isotropic(0.5, 0.3, 3.0),
            ],
        }
        .into();
        let a = RenderOptions {
            width: 64,
            height: 48,
            supersampling: 2,
            light: [0.6, 0.3, 1.2],
            ..RenderOptions::default()
        };
        let b = RenderOptions {
            light: [-0.6, 0.3, 1.2],
            ..a.clone()
        };
        let ia = render_radiance(&iso, &a).unwrap();
        let ib = render_radiance(&iso, &b).unwrap();
        let mut max_rel: f64 = 0.0;
        for y in 0..48 {
            for x in 0..64 {
                let (p, q) = (ia.at(x, y), ib.at(63 - x, y));
                max_rel = max_rel.max((p - q).abs() / (p.abs() + q.abs() + 1e-12));
            }
        }
        assert!(max_rel < 1e-9, "max relative difference {max_rel}");
        // The anisotropic tuning BRDF (pan 45 degrees) is not mirror symmetric.
        let tuning = Params::from(named_params("tuning").unwrap());
        let ta = render_radiance(&tuning, &a).unwrap();
        let tb = render_radiance(&tuning, &b).unwrap();
        let diff: f64 = (0..48)
            .flat_map(|y| (0..64).map(move |x| (x, y)))
            .map(|(x, y)| (ta.at(x, y) - tb.at(63 - x, y)).abs())
            .sum();
        assert!(diff > 1.0, "{diff}");
    }

    #[test]
    fn cross_differs_from_tuning() {
        let opts = small(RenderOptions::default());
        let t = render_radiance(&named_params("tuning").unwrap().into(), &opts).unwrap();
        let c = render_radiance(&named_params("cross").unwrap().into(), &opts).unwrap();
        let differ = t
            .radiance
            .iter()
            .zip(&c.radiance)
            .filter(|(a, b)| (*a - *b).abs() > 0.05 * (a.abs() + b.abs() + 1e-9))
            .count();
        assert!(differ > t.radiance.len() / 20, "{differ}");
    }

    #[test]
    fn bad_options_are_errors() {
        let p = named_params("tuning").unwrap();
        for o in [
            RenderOptions {
                width: 0,
                ..RenderOptions::default()
            },
            RenderOptions {
                camera: [0.0, -1.0, -1.0],
                ..RenderOptions::default()
            },
            RenderOptions {
                light: [0.0, 0.0, 0.0],
                ..RenderOptions::default()
            },
            RenderOptions {
                fov_deg: 180.0,
                ..RenderOptions::default()
            },
            RenderOptions {
                look_at: RenderOptions::default().camera,
                ..RenderOptions::default()
            },
            RenderOptions {
                exposure: f64::NAN,
                ..RenderOptions::default()
            },
        ] {
            assert!(matches!(
                render_radiance(&p.clone().into(), &o),
                Err(RenderError::InvalidOption(_))
            ));
        }
    }

    #[test]
    fn png_is_written() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sub/tuning.png");
        let opts = small(RenderOptions::default());
        render_png(&named_params("tuning").unwrap().into(), &opts, &path).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert!(bytes.len() > 100);
        assert_eq!(&bytes[1..4], b"PNG");
        assert!(write_png(&path, 2, 2, &[0; 5]).is_err());
    }
}
