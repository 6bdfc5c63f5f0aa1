//! `host-sim tune`: the fastest bounded-memory configuration of the A-buffer
//! that fits an SRAM budget and keeps a scene's turntable within an NMSE
//! target against `unlimited` on every frame.
//!
//! The search covers the policy (`split-bands`, `shared`, `merge-closest`),
//! the band height, the main slots, the pool addresses and the pool size. A
//! configuration must fit `--ram` with the frame workspace, line buffers and
//! stack reserve counted as `host-sim fit` counts them; among those that meet
//! the target, the one with the shortest median host time per frame wins
//! (`cargo xtask tune` measures its instructions per frame on the Cortex-M4
//! too). The winner is printed with the `FIRMWARE_*` variables that build it.

use crate::bounded::frame_errors;
use crate::builtins::builtin_scene;
use crate::convert::to_fixed;
use crate::fit::{budget, parse_bytes, FitArgs};
use crate::render::{render, Grid, Method, RenderConfig};
use mcu_abuffer::memory::defaults;
use std::time::Duration;

/// Arguments of `host-sim tune`.
#[derive(clap::Args, Debug)]
pub struct TuneArgs {
    /// A built-in scene.
    #[arg(long, default_value = "teapot")]
    pub scene: String,
    /// Turntable frames (a full turn); every frame must meet the target.
    #[arg(long, default_value_t = 8)]
    pub frames: u32,
    /// SRAM available to the renderer and the stack, in bytes or with a K suffix.
    #[arg(long, default_value = "112K", value_parser = parse_bytes)]
    pub ram: usize,
    /// Bytes kept for the stack.
    #[arg(long, default_value_t = defaults::STACK_RESERVE_BYTES)]
    pub stack: usize,
    /// Largest NMSE against `unlimited` on any frame.
    #[arg(long, default_value_t = 1e-4)]
    pub nmse: f64,
    /// Image width and height.
    #[arg(long, default_value_t = 240)]
    pub size: u32,
    /// How many of the best configurations to list.
    #[arg(long, default_value_t = 5)]
    pub show: usize,
}

/// One configuration tried.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Candidate {
    /// Policy.
    pub method: Method,
    /// Band height.
    pub band: u16,
    /// Main slots per pixel.
    pub main: u8,
    /// Pool addresses per pixel.
    pub extra: u8,
    /// Pool slots.
    pub pool: usize,
    /// Bytes of SRAM with workspace, lines and stack.
    pub bytes: usize,
    /// Worst NMSE over the turntable.
    pub nmse: f64,
    /// Median host time per frame.
    pub time: Duration,
}

/// The policy's name on the command line and in `FIRMWARE_METHOD`.
pub fn method_name(method: Method) -> &'static str {
    match method {
        Method::SplitBands => "split-bands",
        Method::MergeClosest => "merge-closest",
        _ => "shared",
    }
}

/// What the search found.
#[derive(Clone, Debug, PartialEq)]
pub struct TuneResult {
    /// Configurations tried.
    pub tried: usize,
    /// Of those, the ones that fit the budget.
    pub fitting: usize,
    /// Bytes of the smallest configuration tried.
    pub smallest: usize,
    /// The configurations that fit and meet the target, fastest first.
    pub passing: Vec<Candidate>,
}

/// Searches the configurations (see the module documentation).
pub fn search(args: &TuneArgs) -> Result<TuneResult, String> {
    let desc = builtin_scene(&args.scene, args.size, args.size)
        .ok_or_else(|| format!("unknown built-in scene {}", args.scene))?;
    let scene = to_fixed(&desc)?;
    let frames = args.frames.max(1);
    let angles: Vec<f32> = (0..frames)
        .map(|i| 360.0 * i as f32 / frames as f32)
        .collect();
    // The unlimited image does not depend on the band height.
    let reference_config = RenderConfig {
        method: Method::Unlimited,
        band: 16.min(args.size as u16),
        ..RenderConfig::default()
    };
    let references = angles
        .iter()
        .map(|&a| render(&scene, &reference_config, a).map(|o| o.rgb))
        .collect::<Result<Vec<_>, _>>()?;
    let width = args.size as usize;
    let mut tried = 0usize;
    let mut fitting = 0usize;
    let mut passing: Vec<Candidate> = Vec::new();
    let bands = [1u16, 2, 4, 6, 8, 12, 16, 24, 32];
    let mut smallest = usize::MAX;
    for method in [Method::SplitBands, Method::Shared, Method::MergeClosest] {
        for &band in bands.iter().filter(|&&b| b as u32 <= args.size) {
            for main in 1u8..=3 {
                for extra in 0u8..=4 {
                    let pixels = width * band as usize;
                    let pools: Vec<usize> = if extra == 0 {
                        vec![0]
                    } else {
                        vec![pixels / 8, pixels / 4, pixels / 2]
                    };
                    for pool in pools {
                        tried += 1;
                        let fit = FitArgs {
                            scene: args.scene.clone(),
                            width: args.size,
                            height: args.size,
                            band,
                            grid: Grid::G4x4,
                            main,
                            extra,
                            pool,
                            fixed: None,
                            ram: args.ram,
                            stack: args.stack,
                            carried: defaults::CARRIED_COLORS,
                            frames: None,
                        };
                        let bytes =
                            budget(&fit, &desc, main as usize, extra as usize, pool).total();
                        smallest = smallest.min(bytes);
                        if bytes > args.ram {
                            continue;
                        }
                        fitting += 1;
                        let config = RenderConfig {
                            method,
                            band,
                            main,
                            extra,
                            pool: Some(pool),
                            ..RenderConfig::default()
                        };
                        let mut worst = 0.0f64;
                        let mut times = Vec::new();
                        for (&angle, reference) in angles.iter().zip(&references) {
                            let out = render(&scene, &config, angle)?;
                            worst = worst
                                .max(frame_errors(&out.rgb, reference, width, band as usize).nmse);
                            times.push(out.elapsed);
                            if worst > args.nmse {
                                break;
                            }
                        }
                        if worst <= args.nmse {
                            times.sort();
                            passing.push(Candidate {
                                method,
                                band,
                                main,
                                extra,
                                pool,
                                bytes,
                                nmse: worst,
                                time: times[times.len() / 2],
                            });
                        }
                    }
                }
            }
        }
    }
    passing.sort_by(|a, b| a.time.cmp(&b.time).then(a.bytes.cmp(&b.bytes)));
    Ok(TuneResult {
        tried,
        fitting,
        smallest,
        passing,
    })
}

/// Runs the search, prints the result and returns the winner (`None` when no
/// configuration fits and meets the target).
pub fn run_tune(args: &TuneArgs) -> Result<Option<Candidate>, String> {
    let TuneResult {
        tried,
        fitting,
        smallest,
        passing,
    } = search(args)?;
    let frames = args.frames.max(1);
    println!(
        "{}: {tried} configurations, {fitting} fit {} bytes, {} meet NMSE {:.1e} on all {frames} frames",
        args.scene,
        args.ram,
        passing.len(),
        args.nmse
    );
    let Some(best) = passing.first().copied() else {
        if fitting == 0 {
            println!(
                "none fits: the smallest (band 1, one slot per pixel) needs {smallest} bytes, {} over",
                smallest.saturating_sub(args.ram)
            );
        } else {
            println!("no configuration that fits meets the target");
        }
        return Ok(None);
    };
    println!("| policy | band | main | extra | pool | bytes | worst NMSE | host ms per frame |");
    println!("|---|---|---|---|---|---|---|---|");
    for c in passing.iter().take(args.show.max(1)) {
        println!(
            "| {} | {} | {} | {} | {} | {} | {:.2e} | {:.2} |",
            method_name(c.method),
            c.band,
            c.main,
            c.extra,
            c.pool,
            c.bytes,
            c.nmse,
            c.time.as_secs_f64() * 1000.0
        );
    }
    println!(
        "firmware: FIRMWARE_METHOD={} FIRMWARE_BAND={} FIRMWARE_MAIN={} FIRMWARE_EXTRA={} FIRMWARE_POOL={}",
        method_name(best.method),
        best.band,
        best.main,
        best.extra,
        best.pool
    );
    Ok(Some(best))
}
