//! The dynamic mode: a turntable animation (every object turned about the world's
//! vertical axis), written as an animated GIF or numbered PNGs, with per-frame
//! statistics and the worst frame's pool peak.

use crate::convert::FixedScene;
use crate::image_io::write_png;
use crate::render::{render, RenderConfig, RenderOutput};
use crate::sweep::turntable_angles;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// One rendered frame of a turntable.
#[derive(Clone, Debug)]
pub struct TurntableFrame {
    /// Turntable angle, degrees.
    pub angle: f32,
    /// The rendering.
    pub output: RenderOutput,
}

/// Renders `frames` frames evenly spaced over a full turn from `start_deg`, in
/// parallel.
pub fn render_turntable(
    scene: &FixedScene,
    config: &RenderConfig,
    frames: u32,
    start_deg: f32,
) -> Result<Vec<TurntableFrame>, String> {
    turntable_angles(frames, start_deg)
        .into_par_iter()
        .map(|angle| {
            Ok(TurntableFrame {
                angle,
                output: render(scene, config, angle)?,
            })
        })
        .collect()
}

/// Writes RGB888 frames as a looping animated GIF (each frame quantized to its
/// own 256-color palette), `delay_ms` per frame.
pub fn write_gif(
    path: &Path,
    width: u16,
    height: u16,
    frames: &[&[u8]],
    delay_ms: u32,
) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let file = std::fs::File::create(path).map_err(|e| err(&e))?;
    let mut encoder = gif::Encoder::new(std::io::BufWriter::new(file), width, height, &[])
        .map_err(|e| err(&e))?;
    encoder
        .set_repeat(gif::Repeat::Infinite)
        .map_err(|e| err(&e))?;
    let delay = (delay_ms / 10).clamp(1, u16::MAX as u32) as u16;
    for rgb in frames {
        let mut frame = gif::Frame::from_rgb_speed(width, height, rgb, 10);
        frame.delay = delay;
        encoder.write_frame(&frame).map_err(|e| err(&e))?;
    }
    Ok(())
}

/// The file of frame `i` when frames are written as PNGs: `stem-007.png`.
pub fn numbered_png(out: &Path, i: usize) -> PathBuf {
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "frame".into());
    out.with_file_name(format!("{stem}-{i:03}.png"))
}

/// Renders a turntable, prints a line of statistics per frame and the worst pool
/// peak, and writes `out` (an animated GIF for `.gif`, else numbered PNGs next to
/// it). Returns the frames.
pub fn run_turntable(
    scene: &FixedScene,
    config: &RenderConfig,
    frames: u32,
    start_deg: f32,
    delay_ms: u32,
    out: &Path,
) -> Result<Vec<TurntableFrame>, String> {
    if frames == 0 {
        return Err("--frames must be at least 1".into());
    }
    let rendered = render_turntable(scene, config, frames, start_deg)?;
    println!(
        "{:>5} {:>8} {:>10} {:>9} {:>8} {:>9} {:>9} {:>7} {:>8}",
        "frame", "angle", "generated", "stored", "merges", "discarded", "pool peak", "max/px", "ms"
    );
    for (i, f) in rendered.iter().enumerate() {
        let b = &f.output.stats.buffer;
        println!(
            "{:>5} {:>8.2} {:>10} {:>9} {:>8} {:>9} {:>9} {:>7} {:>8.2}",
            i,
            f.angle,
            b.fragments_generated,
            b.fragments_stored,
            b.merges,
            b.fragments_discarded,
            b.pool_peak,
            b.max_fragments_in_pixel,
            f.output.elapsed.as_secs_f64() * 1e3
        );
    }
    if let Some((i, worst)) = rendered
        .iter()
        .enumerate()
        .max_by_key(|(_, f)| f.output.stats.buffer.pool_peak)
    {
        println!(
            "worst pool peak  {} (frame {i}, angle {:.2}) of {} slots",
            worst.output.stats.buffer.pool_peak, worst.angle, worst.output.pool_slots
        );
    }
    let is_gif = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gif"));
    if is_gif {
        let images: Vec<&[u8]> = rendered.iter().map(|f| f.output.rgb.as_slice()).collect();
        write_gif(out, scene.width, scene.height, &images, delay_ms)?;
        println!(
            "wrote            {} ({} frames)",
            out.display(),
            rendered.len()
        );
    } else {
        for (i, f) in rendered.iter().enumerate() {
            write_png(
                &numbered_png(out, i),
                scene.width as u32,
                scene.height as u32,
                &f.output.rgb,
            )?;
        }
        println!(
            "wrote            {} .. {}",
            numbered_png(out, 0).display(),
            numbered_png(out, rendered.len() - 1).display()
        );
    }
    Ok(rendered)
}

/// Writes per-frame statistics of a turntable as JSON.
pub fn write_frames_json(
    path: &Path,
    scene_name: &str,
    config: &RenderConfig,
    frames: &[TurntableFrame],
) -> Result<(), String> {
    let list: Vec<serde_json::Value> = frames
        .iter()
        .map(|f| {
            let b = &f.output.stats.buffer;
            serde_json::json!({
                "angle": f.angle,
                "generated": b.fragments_generated,
                "stored": b.fragments_stored,
                "merges": b.merges,
                "discarded": b.fragments_discarded,
                "pool_peak": b.pool_peak,
                "max_in_pixel": b.max_fragments_in_pixel,
                "milliseconds": f.output.elapsed.as_secs_f64() * 1e3,
            })
        })
        .collect();
    let worst = frames
        .iter()
        .map(|f| f.output.stats.buffer.pool_peak)
        .max()
        .unwrap_or(0);
    let json = serde_json::json!({
        "scene": scene_name,
        "config": config,
        "frames": list,
        "worst_pool_peak": worst,
    });
    std::fs::write(
        path,
        serde_json::to_string_pretty(&json).unwrap_or_default(),
    )
    .map_err(|e| format!("{}: cannot write: {e}", path.display()))
}
