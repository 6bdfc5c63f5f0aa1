//! Depth comparisons of the z-buffer modes: the plain z-buffer, the
//! hierarchical one (8x8 tiles) and midpoint subdivision (SPEC section 7),
//! with the pixels where each differs from the plain z-buffer.
//!
//! What counts as a depth comparison: one read of the depth buffer compared
//! with a new depth. Per-pixel tests (`BufferStats::depth_tests`: one per
//! fragment tested) and tests made before rasterizing
//! (`BufferStats::culling_depth_tests`: one per tile of a triangle's bounding
//! box in the hierarchical z-buffer, one per test point read in midpoint
//! subdivision) are counted apart and added up. Reads that only keep the
//! tiles' farthest depths exact are reported on their own.

use crate::compare::compare_rgb;
use crate::convert::{to_fixed, FixedScene};
use crate::render::{render, Method, MidpointSettings, RenderConfig, RenderOutput};
use crate::scene_desc::SceneDesc;
use mcu_abuffer::stats::BufferStats;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Duration;

/// Arguments of `host-sim zbuffer-table`.
#[derive(clap::Args, Debug)]
pub struct ZbufferTableArgs {
    /// A built-in scene or a scene file (.toml).
    #[arg(long, default_value = "overdraw")]
    pub scene: String,
    /// Image width.
    #[arg(long, default_value_t = 800)]
    pub width: u32,
    /// Image height.
    #[arg(long, default_value_t = 600)]
    pub height: u32,
    /// Band height in rows; default: the whole image in one band, as a
    /// frame-sized z-buffer.
    #[arg(long)]
    pub band: Option<u16>,
    /// Deepest subdivision level of zbuffer-midpoint (D).
    #[arg(long, default_value_t = MidpointSettings::default().max)]
    pub subdiv_max: u8,
    /// Timings per configuration, each over 5 renders; the time is the fastest
    /// (processor time of the rendering thread on Linux, wall time elsewhere).
    #[arg(long, default_value_t = 5)]
    pub repeat: u32,
    /// Turntable angle in degrees.
    #[arg(long, default_value_t = 0.0)]
    pub angle: f32,
    /// Also write the table (Markdown) to this file.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// The depth counters of one z-buffer rendering.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DepthCounts {
    /// Per-pixel depth tests.
    pub per_pixel: u64,
    /// Depth comparisons before rasterizing (tiles or test points).
    pub culling: u64,
    /// Reads that keep the tiles' farthest depths exact.
    pub tile_refresh_reads: u64,
    /// Triangles (per band) culled whole.
    pub triangles_culled: u64,
    /// Tiles or sub-triangles judged hidden.
    pub pieces_culled: u64,
    /// Pixels written (depth and color).
    pub pixels_written: u64,
    /// Of those, written without a depth test.
    pub untested_writes: u64,
}

impl DepthCounts {
    /// The counters of a frame.
    pub fn of(b: &BufferStats) -> Self {
        Self {
            per_pixel: b.depth_tests.into(),
            culling: b.culling_depth_tests.into(),
            tile_refresh_reads: b.tile_refresh_reads.into(),
            triangles_culled: b.triangles_culled.into(),
            pieces_culled: b.pieces_culled.into(),
            pixels_written: b.fragments_stored.into(),
            untested_writes: b.untested_writes.into(),
        }
    }

    /// All depth comparisons: per pixel and before rasterizing.
    pub fn comparisons(&self) -> u64 {
        self.per_pixel + self.culling
    }
}

/// Pixels whose color differs between two RGB888 images of the same size.
pub fn differing_pixels(image: &[u8], reference: &[u8]) -> Result<u64, String> {
    Ok(compare_rgb(image, reference)?.differing_pixels)
}

/// Whether a method is one of the z-buffers.
pub fn is_zbuffer(method: Method) -> bool {
    matches!(
        method,
        Method::Zbuffer | Method::ZbufferHiz | Method::ZbufferMidpoint
    )
}

/// What `host-sim render` reports for a z-buffer method: the depth counters
/// and, for the culling ones, the pixels that differ from the plain z-buffer
/// (rendered once more for that). `None` for other methods.
pub fn depth_report(
    scene: &FixedScene,
    config: &RenderConfig,
    angle: f32,
    out: &RenderOutput,
) -> Result<Option<(DepthCounts, Option<u64>)>, String> {
    if !is_zbuffer(config.method) {
        return Ok(None);
    }
    let counts = DepthCounts::of(&out.stats.buffer);
    let differing = if config.method == Method::Zbuffer {
        None
    } else {
        let plain = render(
            scene,
            &RenderConfig {
                method: Method::Zbuffer,
                ..*config
            },
            angle,
        )?;
        Some(differing_pixels(&out.rgb, &plain.rgb)?)
    };
    Ok(Some((counts, differing)))
}

/// Printable lines of a [`depth_report`].
pub fn report_lines(counts: &DepthCounts, differing: Option<u64>) -> Vec<String> {
    let mut lines = vec![
        format!(
            "depth compares   {} ({} per pixel, {} before rasterizing)",
            counts.comparisons(),
            counts.per_pixel,
            counts.culling
        ),
        format!(
            "culled           {} triangles, {} pieces; {} tile refresh reads",
            counts.triangles_culled, counts.pieces_culled, counts.tile_refresh_reads
        ),
        format!(
            "pixels written   {} ({} without a depth test)",
            counts.pixels_written, counts.untested_writes
        ),
    ];
    if let Some(d) = differing {
        lines.push(format!("differ from zbuffer {d} pixels"));
    }
    lines
}

/// The report as JSON.
pub fn report_json(counts: &DepthCounts, differing: Option<u64>) -> serde_json::Value {
    serde_json::json!({
        "comparisons": counts.comparisons(),
        "per_pixel_tests": counts.per_pixel,
        "culling_tests": counts.culling,
        "tile_refresh_reads": counts.tile_refresh_reads,
        "triangles_culled": counts.triangles_culled,
        "pieces_culled": counts.pieces_culled,
        "pixels_written": counts.pixels_written,
        "untested_writes": counts.untested_writes,
        "differing_pixels_from_zbuffer": differing,
    })
}

/// One row of the table.
#[derive(Clone, Debug)]
pub struct TableRow {
    /// Method name as on the command line, with its settings.
    pub label: String,
    /// Counters.
    pub counts: DepthCounts,
    /// Fastest time per frame (processor time where available).
    pub time: Duration,
    /// Pixels differing from the plain z-buffer.
    pub differing: u64,
}

/// The configurations of the table: zbuffer, zbuffer-hiz, then
/// zbuffer-midpoint with K = 0..=3 as published (visible pieces untested)
/// and with per-pixel tests kept.
pub fn table_configs(band: u16, subdiv_max: u8) -> Vec<(String, RenderConfig)> {
    let base = RenderConfig {
        method: Method::Zbuffer,
        band,
        ..RenderConfig::default()
    };
    let mut configs = vec![
        ("zbuffer".to_string(), base),
        (
            "zbuffer-hiz".to_string(),
            RenderConfig {
                method: Method::ZbufferHiz,
                ..base
            },
        ),
    ];
    for safe in [false, true] {
        for k in 0..=3u8 {
            let label = format!(
                "zbuffer-midpoint K={k} D={}{}",
                subdiv_max.max(k),
                if safe { " safe" } else { "" }
            );
            configs.push((
                label,
                RenderConfig {
                    method: Method::ZbufferMidpoint,
                    midpoint: MidpointSettings {
                        initial: k,
                        max: subdiv_max.max(k),
                        safe,
                    },
                    ..base
                },
            ));
        }
    }
    configs
}

/// Fewest renders timed together in one measurement of [`measure_table`].
const RENDERS_PER_TIMING: u32 = 5;

/// Least wall time one measurement of [`measure_table`] renders for: the
/// system's processor-time clock may advance in steps of several
/// milliseconds (4 ms on the 2-core test machine), so one measurement
/// spans many steps and a frame's time is read to a few percent.
const LEAST_TIME_PER_TIMING: Duration = Duration::from_millis(100);

/// Processor time the calling thread has used, where the system reports it
/// (Linux: `/proc/thread-self/schedstat`).
fn thread_cpu_time() -> Option<Duration> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let nanos: u64 = text.split_whitespace().next()?.parse().ok()?;
    Some(Duration::from_nanos(nanos))
}

/// Times every configuration of [`table_configs`] `repeat` times (each time
/// over at least [`RENDERS_PER_TIMING`] renders and [`LEAST_TIME_PER_TIMING`]),
/// taking turns so that a busy machine slows all of them alike, and keeps the
/// fastest time per frame of each: the processor time of the rendering thread
/// where the system reports it (less disturbed by other work), else the wall
/// time.
pub fn measure_table(
    scene: &FixedScene,
    band: u16,
    subdiv_max: u8,
    repeat: u32,
    angle: f32,
) -> Result<Vec<TableRow>, String> {
    let configs = table_configs(band, subdiv_max);
    let mut outputs: Vec<Option<RenderOutput>> = vec![None; configs.len()];
    let mut fastest = vec![Duration::MAX; configs.len()];
    for _ in 0..repeat.max(1) {
        for (i, (label, config)) in configs.iter().enumerate() {
            // Several renders per measurement, for at least
            // LEAST_TIME_PER_TIMING: the system's processor-time clock may
            // advance in steps of a few milliseconds.
            let cpu_before = thread_cpu_time();
            let mut wall = Duration::ZERO;
            let mut renders = 0u32;
            while renders < RENDERS_PER_TIMING || wall < LEAST_TIME_PER_TIMING {
                renders += 1;
                let out = render(scene, config, angle)?;
                wall += out.elapsed;
                if let Some(prev) = &outputs[i] {
                    if prev.rgb != out.rgb || prev.stats != out.stats {
                        return Err(format!("{label}: two renders of one frame differ"));
                    }
                }
                outputs[i] = Some(out);
            }
            let total = match (cpu_before, thread_cpu_time()) {
                (Some(a), Some(b)) => b.saturating_sub(a),
                _ => wall,
            };
            fastest[i] = fastest[i].min(total / renders);
        }
    }
    let reference = outputs[0].as_ref().ok_or("no render")?.rgb.clone();
    let mut rows = Vec::new();
    for (((label, _), out), time) in configs.into_iter().zip(outputs).zip(fastest) {
        let out = out.ok_or("no render")?;
        rows.push(TableRow {
            label,
            counts: DepthCounts::of(&out.stats.buffer),
            time,
            differing: differing_pixels(&out.rgb, &reference)?,
        });
    }
    Ok(rows)
}

/// `n` with thousands separated by commas.
fn grouped(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// `value` against `base` as a signed percentage, `-` without either.
fn percent(value: f64, base: f64) -> String {
    if base == 0.0 || value == 0.0 {
        "-".to_string()
    } else {
        format!("{:+.0} %", 100.0 * (value - base) / base)
    }
}

/// The rows as a Markdown table; percentages are against the `zbuffer-hiz`
/// row (the publication's baseline), or the first row without one.
pub fn markdown_table(rows: &[TableRow]) -> String {
    let mut s = String::new();
    s.push_str(
        "| method | per-pixel tests | tests before rasterizing | all comparisons \
         | tile refresh reads | triangles culled | pieces culled | pixels written (untested) \
         | ms/frame (CPU) | pixels differing |\n",
    );
    s.push_str("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    let Some(base) = rows
        .iter()
        .find(|r| r.label == "zbuffer-hiz")
        .or(rows.first())
    else {
        return s;
    };
    let (base_culling, base_all) = (base.counts.culling as f64, base.counts.comparisons() as f64);
    let base_ms = base.time.as_secs_f64() * 1e3;
    for r in rows {
        let c = &r.counts;
        let ms = r.time.as_secs_f64() * 1e3;
        let _ = writeln!(
            s,
            "| {} | {} | {} ({}) | {} ({}) | {} | {} | {} | {} ({}) | {:.1} ({}) | {} |",
            r.label,
            grouped(c.per_pixel),
            grouped(c.culling),
            percent(c.culling as f64, base_culling),
            grouped(c.comparisons()),
            percent(c.comparisons() as f64, base_all),
            grouped(c.tile_refresh_reads),
            grouped(c.triangles_culled),
            grouped(c.pieces_culled),
            grouped(c.pixels_written),
            grouped(c.untested_writes),
            ms,
            percent(ms, base_ms),
            grouped(r.differing),
        );
    }
    s
}

/// `host-sim zbuffer-table`.
pub fn run_zbuffer_table(args: &ZbufferTableArgs, desc: SceneDesc) -> Result<(), String> {
    let scene = to_fixed(&desc)?;
    let band = args.band.unwrap_or(scene.height).clamp(1, scene.height);
    let rows = measure_table(&scene, band, args.subdiv_max, args.repeat, args.angle)?;
    let mut text = format!(
        "Scene `{}`, {} triangles, {}x{}, bands of {} rows; time: processor time per frame, \
         the fastest of {} timings of at least {RENDERS_PER_TIMING} renders and {} ms each; \
         percentages against `zbuffer-hiz`.\n\n",
        args.scene,
        scene.triangle_count(),
        scene.width,
        scene.height,
        band,
        args.repeat.max(1),
        LEAST_TIME_PER_TIMING.as_millis()
    );
    text.push_str(&markdown_table(&rows));
    print!("{text}");
    if let Some(path) = &args.out {
        std::fs::write(path, &text)
            .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
    }
    Ok(())
}
