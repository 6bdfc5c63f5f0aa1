//! `host-sim bounded`: how far each bounded-memory method is from `unlimited`
//! over a turntable, per scene, as a Markdown table: the largest NMSE of any
//! frame, the most speckled pixels of any frame (a channel off by more than
//! [`SPECKLE_LEVELS`]), the worst row position within a band (the mean error
//! of the rows at that position over the image's mean row error: streaks
//! along band boundaries show as a high ratio), the memory and the time.

use crate::builtins::builtin_scene;
use crate::compare::nmse;
use crate::convert::to_fixed;
use crate::plot::{LineChart, Point, Scale, Series, PALETTE};
use crate::render::{render, Method, RenderConfig};
use mcu_abuffer::memory::defaults;
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
    #[arg(long, default_value_t = defaults::BAND_ROWS)]
    pub band: u16,
    /// Main slots per pixel.
    #[arg(long, default_value_t = defaults::MAIN_SLOTS)]
    pub main: u8,
    /// Pool addresses per pixel.
    #[arg(long, default_value_t = defaults::EXTRA_ADDRESSES)]
    pub extra: u8,
    /// Shared pool slots.
    #[arg(long, default_value_t = defaults::POOL_SLOTS)]
    pub pool: usize,
    /// Image width and height.
    #[arg(long, default_value_t = 240)]
    pub size: u32,
    /// Also plot the mean squared error of every image row of the first
    /// scene, per method, over the turntable (SVG): streaks along band
    /// boundaries show as peaks every `band` rows.
    #[arg(long)]
    pub row_plot: Option<std::path::PathBuf>,
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

/// The mean squared difference per channel of every row of `image` against
/// `reference` (RGB, `width` pixels per row).
pub fn row_errors(image: &[u8], reference: &[u8], width: usize) -> Vec<f64> {
    image
        .chunks_exact(3 * width.max(1))
        .zip(reference.chunks_exact(3 * width.max(1)))
        .map(|(a, b)| {
            let sum: u64 = a
                .iter()
                .zip(b)
                .map(|(x, y)| (*x as i64 - *y as i64).pow(2) as u64)
                .sum();
            sum as f64 / a.len().max(1) as f64
        })
        .collect()
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
    let mut series = Vec::new();
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
        let plotted = args.row_plot.is_some() && name == &args.scene[0];
        for (m, &method) in args.methods.iter().enumerate() {
            let (mut worst, mut splits, mut time) = (FrameErrors::default(), 0u64, Duration::ZERO);
            let mut rows = vec![0.0f64; args.size as usize];
            for (&angle, reference) in angles.iter().zip(&references) {
                let out = render(&scene, &config(method), angle)?;
                if plotted {
                    let errors = row_errors(&out.rgb, &reference.rgb, out.width as usize);
                    for (sum, e) in rows.iter_mut().zip(errors) {
                        *sum += e / angles.len() as f64;
                    }
                }
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
            if plotted {
                series.push(Series {
                    name: method_name(method),
                    color: PALETTE[m % PALETTE.len()],
                    dashed: false,
                    points: rows
                        .iter()
                        .enumerate()
                        .map(|(y, &e)| Point {
                            x: y as f64,
                            y: e,
                            label: None,
                        })
                        .collect(),
                });
            }
        }
    }
    print!("{table}");
    if let Some(path) = &args.row_plot {
        let chart = LineChart {
            title: format!(
                "{}: error per image row against unlimited, mean of {} frames",
                args.scene[0], args.frames
            ),
            x_label: format!("image row (bands of {} rows)", args.band),
            y_label: "mean squared difference per channel".into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Log10,
            series,
            note: Some(format!(
                "main {}, extra {}, pool {}; markers on the bottom edge: no error",
                args.main, args.extra, args.pool
            )),
        };
        std::fs::write(path, chart.to_svg()).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}

fn method_name(method: Method) -> String {
    use clap::ValueEnum;
    method
        .to_possible_value()
        .map(|v| v.get_name().to_string())
        .unwrap_or_else(|| format!("{method:?}"))
}
