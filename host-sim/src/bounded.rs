//! `host-sim bounded`: how far each bounded-memory method is from `unlimited`
//! over a turntable, per scene, as a Markdown table: the largest NMSE of any
//! frame, the most speckled pixels of any frame (a channel off by more than
//! [`SPECKLE_LEVELS`]), the worst row position within a band (the mean error
//! of the rows at that position over the image's mean row error: streaks
//! along band boundaries show as a high ratio), the memory and the time.

use crate::builtins::builtin_scene;
use crate::compare::nmse;
use crate::convert::to_fixed;
use crate::render::{render, Method, RenderConfig};
use std::fmt::Write as _;
use std::time::Duration;

/// A channel off by more than this many levels is a visible speckle.
pub const SPECKLE_LEVELS: i32 = 24;

/// Arguments of `host-sim bounded`.
#[derive(clap::Args, Debug)]
pub struct BoundedArgs {
    /// Built-in scenes (comma-separated).
    #[arg(
        long,
        default_value = "teapot,teapot:24,spheres,starfighter,layers,grid,knot,overdraw,blob",
        value_delimiter = ','
    )]
    pub scene: Vec<String>,
    /// Bounded-memory methods to compare with `unlimited` (comma-separated).
    #[arg(
        long,
        default_value = "split-bands,shared,merge-closest",
        value_enum,
        value_delimiter = ','
    )]
    pub methods: Vec<Method>,
    /// Turntable frames (a full turn).
    #[arg(long, default_value_t = 8)]
    pub frames: u32,
    /// Rows per band.
    #[arg(long, default_value_t = 8)]
    pub band: u16,
    /// Main slots per pixel.
    #[arg(long, default_value_t = 1)]
    pub main: u8,
    /// Pool addresses per pixel.
    #[arg(long, default_value_t = 2)]
    pub extra: u8,
    /// Shared pool slots.
    #[arg(long, default_value_t = 512)]
    pub pool: usize,
    /// Image width and height.
    #[arg(long, default_value_t = 240)]
    pub size: u32,
}

/// The errors of one frame against its reference.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameErrors {
    /// Normalized mean squared error.
    pub nmse: f64,
    /// Pixels with a channel off by more than [`SPECKLE_LEVELS`].
    pub speckles: usize,
    /// The largest mean squared error of the rows at one position within a
    /// band, over the mean of all rows (0 when the images are equal).
    pub worst_band_row: f64,
}

/// The errors of `image` against `reference` (RGB, `width` pixels per row)
/// for bands of `band` rows.
pub fn frame_errors(image: &[u8], reference: &[u8], width: usize, band: usize) -> FrameErrors {
    let rows = image.len() / (3 * width).max(1);
    let band = band.max(1);
    let mut per_position = vec![(0u64, 0u64); band];
    let (mut total, mut speckles) = (0u64, 0usize);
    for y in 0..rows {
        let line = 3 * width * y..3 * width * (y + 1);
        let mut row_error = 0u64;
        for (a, b) in image[line.clone()]
            .chunks_exact(3)
            .zip(reference[line].chunks_exact(3))
        {
            let d = [0, 1, 2].map(|c| a[c] as i32 - b[c] as i32);
            row_error += d.iter().map(|v| (v * v) as u64).sum::<u64>();
            speckles += d.iter().any(|v| v.abs() > SPECKLE_LEVELS) as usize;
        }
        total += row_error;
        let slot = &mut per_position[y % band];
        slot.0 += row_error;
        slot.1 += 1;
    }
    let mean = total as f64 / rows.max(1) as f64;
    let worst = per_position
        .iter()
        .filter(|(_, n)| *n > 0)
        .map(|(e, n)| *e as f64 / *n as f64)
        .fold(0.0, f64::max);
    FrameErrors {
        nmse: nmse(image, reference),
        speckles,
        worst_band_row: if mean > 0.0 { worst / mean } else { 0.0 },
    }
}

/// Runs the comparison and prints the table.
pub fn run_bounded(args: &BoundedArgs) -> Result<(), String> {
    let mut table = String::new();
    writeln!(
        table,
        "| scene | method | worst NMSE | most speckles (pixels, %) | worst band row / mean | band splits per frame | host time per frame |"
    )
    .unwrap();
    writeln!(table, "|---|---|---|---|---|---|---|").unwrap();
    for name in &args.scene {
        let desc = builtin_scene(name, args.size, args.size)
            .ok_or_else(|| format!("unknown built-in scene {name}"))?;
        let scene = to_fixed(&desc).map_err(|e| format!("{name}: {e}"))?;
        let config = |method| RenderConfig {
            method,
            band: args.band,
            main: args.main,
            extra: args.extra,
            pool: Some(args.pool),
            ..RenderConfig::default()
        };
        let angles: Vec<f32> = (0..args.frames.max(1))
            .map(|i| 360.0 * i as f32 / args.frames.max(1) as f32)
            .collect();
        let references = angles
            .iter()
            .map(|&a| render(&scene, &config(Method::Unlimited), a))
            .collect::<Result<Vec<_>, _>>()?;
        for &method in &args.methods {
            let (mut worst, mut splits, mut time) = (FrameErrors::default(), 0u64, Duration::ZERO);
            for (&angle, reference) in angles.iter().zip(&references) {
                let out = render(&scene, &config(method), angle)?;
                let e = frame_errors(
                    &out.rgb,
                    &reference.rgb,
                    out.width as usize,
                    args.band as usize,
                );
                worst.nmse = worst.nmse.max(e.nmse);
                worst.speckles = worst.speckles.max(e.speckles);
                worst.worst_band_row = worst.worst_band_row.max(e.worst_band_row);
                splits += out.stats.band_splits as u64;
                time += out.elapsed;
            }
            let pixels = (args.size * args.size) as f64;
            writeln!(
                table,
                "| {name} | {} | {:.2e} | {} ({:.3} %) | {:.1} | {:.1} | {:.2} ms |",
                method_name(method),
                worst.nmse,
                worst.speckles,
                100.0 * worst.speckles as f64 / pixels,
                worst.worst_band_row,
                splits as f64 / angles.len() as f64,
                time.as_secs_f64() * 1000.0 / angles.len() as f64,
            )
            .unwrap();
        }
    }
    print!("{table}");
    Ok(())
}

fn method_name(method: Method) -> String {
    use clap::ValueEnum;
    method
        .to_possible_value()
        .map(|v| v.get_name().to_string())
        .unwrap_or_else(|| format!("{method:?}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_streak_along_band_boundaries_shows_in_the_band_row_ratio() {
        // 4 x 8 image, bands of 4 rows: every band's last row is off.
        let reference = vec![100u8; 4 * 8 * 3];
        let mut image = reference.clone();
        for y in [3usize, 7] {
            for x in 0..4 {
                image[3 * (4 * y + x)] = 140;
            }
        }
        let e = frame_errors(&image, &reference, 4, 4);
        assert_eq!(e.speckles, 8);
        // All the error sits in one of four row positions.
        assert!((e.worst_band_row - 4.0).abs() < 1e-9);
        let same = frame_errors(&reference, &reference, 4, 4);
        assert_eq!(
            (same.nmse, same.speckles, same.worst_band_row),
            (0.0, 0, 0.0)
        );
    }
}
