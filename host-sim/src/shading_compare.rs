//! Shading modes side by side (`host-sim shading`): a scene rendered with every
//! object in `gouraud`, `quadratic` and `phong`, the error of the first two
//! against `phong` per channel (over the object's pixels, and over the highlight
//! region separately), and one image: gouraud | quadratic | phong | error of
//! gouraud | error of quadratic.
//!
//! The highlight region is where the specular term alone (the scene rendered with
//! `phong`, ambient and diffuse set to zero, on black) reaches a threshold.

use crate::convert::FixedScene;
use crate::heat::heat_color;
use crate::image_io::write_png;
use crate::render::{render, Grid, Method, RenderConfig, RenderOutput};
use crate::scene_desc::SceneDesc;
use embedded_graphics_core::pixelcolor::Rgb888;
use fixed::types::I16F16;
use mcu_abuffer::memory::defaults;
use mcu_abuffer::scene::Shading;
use std::path::PathBuf;

/// A shading mode forced on every object.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShadingMode {
    /// The objects' colors, no lighting.
    Unlit,
    /// One lit color per triangle.
    Flat,
    /// Lit at the vertices, interpolated linearly.
    Gouraud,
    /// Quadratic through vertices and edge midpoints, by forward differences.
    Quadratic,
    /// Normal interpolated and lit per pixel (the reference).
    Phong,
}

impl ShadingMode {
    /// The renderer's shading mode.
    pub fn shading(self) -> Shading {
        match self {
            ShadingMode::Unlit => Shading::Unlit,
            ShadingMode::Flat => Shading::Flat,
            ShadingMode::Gouraud => Shading::Gouraud,
            ShadingMode::Quadratic => Shading::Quadratic,
            ShadingMode::Phong => Shading::Phong,
        }
    }
}

/// Arguments of `host-sim shading`.
#[derive(clap::Args, Debug)]
pub struct ShadingArgs {
    /// A built-in scene or a scene file (.toml); it needs a light.
    #[arg(long, default_value = "teapot")]
    pub scene: String,
    /// Output PNG: the side-by-side image (with `--only`, that one rendering).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Image width.
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height.
    #[arg(long)]
    pub height: Option<u32>,
    /// Pixel memory method of the renderings.
    #[arg(long, value_enum, default_value_t = Method::Unlimited)]
    pub method: Method,
    /// Coverage mask grid.
    #[arg(long, value_enum, default_value_t = Grid::G4x4)]
    pub grid: Grid,
    /// Band height in rows.
    #[arg(long, default_value_t = defaults::BAND_ROWS)]
    pub band: u16,
    /// Turntable angle in degrees.
    #[arg(long, default_value_t = 0.0)]
    pub angle: f32,
    /// Highlight region: specular term alone at least this (0..255).
    #[arg(long, default_value_t = 10)]
    pub highlight: u8,
    /// Error (8-bit steps) shown at the top of the error maps' color ramp.
    #[arg(long, default_value_t = 24)]
    pub error_scale: u8,
    /// Render only this mode (no comparison), e.g. to count instructions.
    #[arg(long, value_enum)]
    pub only: Option<ShadingMode>,
    /// Write the numbers as JSON to this file.
    #[arg(long)]
    pub stats_json: Option<PathBuf>,
}

/// Absolute error against the reference over a set of pixels, per channel.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct ErrorStats {
    /// Pixels in the set.
    pub pixels: usize,
    /// Mean absolute error, 8-bit steps, per channel (R, G, B).
    pub mean: [f64; 3],
    /// Largest absolute error per channel.
    pub max: [u8; 3],
}

/// One mode's error against `phong`.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct ModeError {
    /// Over every pixel an object touches.
    pub object: ErrorStats,
    /// Over the highlight region.
    pub highlight: ErrorStats,
}

/// The three renderings and their errors.
#[derive(Clone, Debug)]
pub struct ShadingComparison {
    /// Image width.
    pub width: u16,
    /// Image height.
    pub height: u16,
    /// Gouraud rendering.
    pub gouraud: RenderOutput,
    /// Quadratic rendering.
    pub quadratic: RenderOutput,
    /// Phong rendering (the reference).
    pub phong: RenderOutput,
    /// Pixels some object touches.
    pub object_pixels: Vec<bool>,
    /// Pixels of the highlight region.
    pub highlight_pixels: Vec<bool>,
    /// Gouraud against phong.
    pub gouraud_error: ModeError,
    /// Quadratic against phong.
    pub quadratic_error: ModeError,
}

/// `scene` with every object shaded `mode`.
pub fn with_shading(scene: &FixedScene, mode: ShadingMode) -> FixedScene {
    let mut s = scene.clone();
    for o in &mut s.objects {
        o.shading = mode.shading();
    }
    s
}

/// The specular term alone: `phong`, ambient and diffuse zero, black background.
pub fn specular_only(scene: &FixedScene) -> FixedScene {
    let mut s = with_shading(scene, ShadingMode::Phong);
    if let Some(light) = &mut s.light {
        light.ambient = I16F16::ZERO;
        light.diffuse = I16F16::ZERO;
    }
    s.background = Rgb888::new(0, 0, 0);
    s
}

/// Absolute error of `image` against `reference` over the pixels where `mask` is set.
pub fn error_stats(image: &[u8], reference: &[u8], mask: &[bool]) -> ErrorStats {
    let mut sum = [0u64; 3];
    let mut max = [0u8; 3];
    let mut pixels = 0;
    for (p, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
        pixels += 1;
        for c in 0..3 {
            let d = image[3 * p + c].abs_diff(reference[3 * p + c]);
            sum[c] += d as u64;
            max[c] = max[c].max(d);
        }
    }
    ErrorStats {
        pixels,
        mean: sum.map(|s| {
            if pixels == 0 {
                0.0
            } else {
                s as f64 / pixels as f64
            }
        }),
        max,
    }
}

/// Renders `scene` in the three modes and measures the errors against `phong`.
pub fn compare_shading(
    scene: &FixedScene,
    config: &RenderConfig,
    angle: f32,
    highlight_threshold: u8,
) -> Result<ShadingComparison, String> {
    if scene.light.is_none() {
        return Err("the scene has no light: every mode would draw unlit".into());
    }
    let run = |mode| render(&with_shading(scene, mode), config, angle);
    let gouraud = run(ShadingMode::Gouraud)?;
    let quadratic = run(ShadingMode::Quadratic)?;
    let phong = run(ShadingMode::Phong)?;
    let specular = render(&specular_only(scene), config, angle)?;
    let object_pixels: Vec<bool> = phong.generated_per_pixel.iter().map(|&n| n > 0).collect();
    let highlight_pixels: Vec<bool> = specular
        .rgb
        .chunks_exact(3)
        .zip(&object_pixels)
        .map(|(p, &o)| o && p.iter().copied().max().unwrap_or(0) >= highlight_threshold)
        .collect();
    let errors = |image: &RenderOutput| ModeError {
        object: error_stats(&image.rgb, &phong.rgb, &object_pixels),
        highlight: error_stats(&image.rgb, &phong.rgb, &highlight_pixels),
    };
    Ok(ShadingComparison {
        width: phong.width,
        height: phong.height,
        gouraud_error: errors(&gouraud),
        quadratic_error: errors(&quadratic),
        gouraud,
        quadratic,
        phong,
        object_pixels,
        highlight_pixels,
    })
}

/// Gap between panels, pixels.
const GAP: usize = 4;

/// The side-by-side image: gouraud | quadratic | phong | |gouraud - phong| |
/// |quadratic - phong|, errors as the largest channel difference on the heat
/// ramp (black 0, pale yellow `error_scale` steps and above). Returns width,
/// height and RGB888 pixels.
pub fn side_by_side(cmp: &ShadingComparison, error_scale: u8) -> (u32, u32, Vec<u8>) {
    let (w, h) = (cmp.width as usize, cmp.height as usize);
    let error_map = |image: &[u8]| -> Vec<u8> {
        image
            .chunks_exact(3)
            .zip(cmp.phong.rgb.chunks_exact(3))
            .flat_map(|(a, b)| {
                let d = (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0);
                if d == 0 {
                    [0, 0, 0]
                } else {
                    heat_color(0.1 + 0.9 * d as f64 / error_scale.max(1) as f64)
                }
            })
            .collect()
    };
    let panels = [
        cmp.gouraud.rgb.clone(),
        cmp.quadratic.rgb.clone(),
        cmp.phong.rgb.clone(),
        error_map(&cmp.gouraud.rgb),
        error_map(&cmp.quadratic.rgb),
    ];
    let total_w = panels.len() * w + (panels.len() - 1) * GAP;
    let mut out = vec![255u8; total_w * h * 3];
    for (k, panel) in panels.iter().enumerate() {
        let x0 = k * (w + GAP);
        for y in 0..h {
            let dst = (y * total_w + x0) * 3;
            out[dst..dst + 3 * w].copy_from_slice(&panel[y * w * 3..(y + 1) * w * 3]);
        }
    }
    (total_w as u32, h as u32, out)
}

fn format_stats(s: &ErrorStats) -> String {
    format!(
        "{:6.3} {:6.3} {:6.3} | {:3} {:3} {:3}",
        s.mean[0], s.mean[1], s.mean[2], s.max[0], s.max[1], s.max[2]
    )
}

/// `host-sim shading` on a loaded scene description.
pub fn run_shading(args: &ShadingArgs, desc: SceneDesc) -> Result<(), String> {
    let scene = crate::convert::to_fixed(&desc)?;
    let config = RenderConfig {
        method: args.method,
        grid: args.grid,
        band: args.band.max(1),
        ..Default::default()
    };
    if let Some(mode) = args.only {
        let out = render(&with_shading(&scene, mode), &config, args.angle)?;
        if let Some(path) = &args.out {
            write_png(path, out.width as u32, out.height as u32, &out.rgb)?;
        }
        println!(
            "{} {:?}: {} triangle setups, {} fragments generated",
            args.scene,
            mode,
            out.stats.geometry.triangle_setups,
            out.stats.buffer.fragments_generated
        );
        return Ok(());
    }
    let cmp = compare_shading(&scene, &config, args.angle, args.highlight)?;
    let objects = cmp.object_pixels.iter().filter(|&&o| o).count();
    let highlight = cmp.highlight_pixels.iter().filter(|&&o| o).count();
    println!(
        "scene {} ({} triangles, {}x{}), method {:?}, grid {:?}",
        args.scene,
        scene.triangle_count(),
        cmp.width,
        cmp.height,
        args.method,
        args.grid
    );
    println!(
        "error against phong, 8-bit steps: mean R G B | max R G B; {objects} object pixels, \
         {highlight} in the highlight region (specular >= {})",
        args.highlight
    );
    println!(
        "{:10} {:>40} {:>40}",
        "", "object pixels", "highlight region"
    );
    for (name, e) in [
        ("gouraud", &cmp.gouraud_error),
        ("quadratic", &cmp.quadratic_error),
    ] {
        println!(
            "{name:10} {:>40} {:>40}",
            format_stats(&e.object),
            format_stats(&e.highlight)
        );
    }
    if let Some(path) = &args.out {
        let (w, h, rgb) = side_by_side(&cmp, args.error_scale);
        write_png(path, w, h, &rgb)?;
        println!(
            "wrote {} (gouraud | quadratic | phong | error gouraud | error quadratic)",
            path.display()
        );
    }
    if let Some(path) = &args.stats_json {
        let json = serde_json::json!({
            "scene": args.scene,
            "triangles": scene.triangle_count(),
            "width": cmp.width,
            "height": cmp.height,
            "method": args.method,
            "grid": args.grid,
            "highlight_threshold": args.highlight,
            "object_pixels": objects,
            "highlight_pixels": highlight,
            "gouraud": cmp.gouraud_error,
            "quadratic": cmp.quadratic_error,
        });
        std::fs::write(
            path,
            serde_json::to_string_pretty(&json).unwrap_or_default(),
        )
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
    }
    Ok(())
}
