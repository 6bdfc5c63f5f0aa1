//! Depth complexity and memory of a scene (`host-sim stats`): fragments per pixel
//! before and after visibility, their histograms and heat maps, the memory of
//! the main and shared buffers and the pool's peak.

use crate::convert::FixedScene;
use crate::heat::{count_color, count_heat_map};
use crate::image_io::write_png;
use crate::memory::{band_memory, MemoryReport};
use crate::plot::{bar_panels_svg, BarPanel};
use crate::render::{render, Grid, Method, RenderConfig, RenderOutput};
use crate::scene_desc::SceneDesc;
use mcu_abuffer::memory::defaults;
use std::path::{Path, PathBuf};

/// Fragments per pixel at which the heat maps reach their brightest color (the
/// largest budget of the sweeps); more saturate.
pub const HEAT_SCALE_MAX: u32 = 8;

/// Bars of the histogram plot; the last one holds every larger count.
pub const HISTOGRAM_BARS: usize = 24;

/// Arguments of `host-sim stats`.
#[derive(clap::Args, Debug)]
pub struct StatsArgs {
    /// A built-in scene or a scene file (.toml).
    #[arg(long, default_value = "teapot")]
    pub scene: String,
    /// Image width.
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height.
    #[arg(long)]
    pub height: Option<u32>,
    /// Coverage mask grid.
    #[arg(long, value_enum, default_value_t = Grid::G4x4)]
    pub grid: Grid,
    /// Main fragment slots per pixel (N_main).
    #[arg(long, default_value_t = defaults::MAIN_SLOTS)]
    pub main: u8,
    /// Pool addresses per pixel (N_extra).
    #[arg(long, default_value_t = defaults::EXTRA_ADDRESSES)]
    pub extra: u8,
    /// Shared pool slots per band (N_pool); default: the library's
    /// (`memory::defaults::POOL_SLOTS`).
    #[arg(long)]
    pub pool: Option<usize>,
    /// Band height in rows (R).
    #[arg(long, default_value_t = defaults::BAND_ROWS)]
    pub band: u16,
    /// Turntable angle in degrees.
    #[arg(long, default_value_t = 0.0)]
    pub angle: f32,
    /// Write heat maps, the histogram plot and a JSON summary into this directory.
    #[arg(long)]
    pub out_dir: Option<PathBuf>,
    /// File name prefix for the outputs (default: the scene name).
    #[arg(long)]
    pub name: Option<String>,
}

/// Buffer parameters of a depth-complexity measurement.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StatsConfig {
    /// Mask grid.
    pub grid: Grid,
    /// `N_main`.
    pub main: u8,
    /// `N_extra`.
    pub extra: u8,
    /// `N_pool` (`None`: the library's default).
    pub pool: Option<usize>,
    /// Band height `R`.
    pub band: u16,
}

/// Everything `stats` measures.
#[derive(Clone, Debug, serde::Serialize)]
pub struct DepthComplexity {
    /// Triangles in the scene.
    pub triangles: usize,
    /// Image width.
    pub width: u16,
    /// Image height.
    pub height: u16,
    /// Pixels by fragments generated (index = fragments): before visibility.
    pub generated_histogram: Vec<u64>,
    /// Pixels by fragments left visible in the unlimited A-buffer: after visibility.
    pub visible_histogram: Vec<u64>,
    /// Pixels by fragments stored with the configured buffer (after merging).
    pub stored_histogram: Vec<u64>,
    /// Pixels with at least one fragment.
    pub covered_pixels: u64,
    /// Mean fragments generated per covered pixel.
    pub mean_generated: f64,
    /// Mean visible fragments per covered pixel.
    pub mean_visible: f64,
    /// Pool peak of the unlimited A-buffer (1 main slot, one address per other sample).
    pub unlimited_pool_peak: u32,
    /// Pool peak with the configured buffer.
    pub pool_peak: u32,
    /// Merges with the configured buffer.
    pub merges: u32,
    /// Pool peak of the configured `N_main`/`N_extra` with a pool that never runs
    /// out: the smallest `N_pool` that forces no merge.
    pub pool_demand: u32,
    /// Memory with the configured pool.
    pub memory: MemoryReport,
    /// Memory with `N_pool` = [`DepthComplexity::pool_demand`].
    pub memory_at_demand: MemoryReport,
}

/// Pixels by count: entry `n` is how many pixels hold `n`.
pub fn histogram(counts: impl Iterator<Item = u32>) -> Vec<u64> {
    let mut h: Vec<u64> = Vec::new();
    for n in counts {
        let n = n as usize;
        if h.len() <= n {
            h.resize(n + 1, 0);
        }
        h[n] += 1;
    }
    if h.is_empty() {
        h.push(0);
    }
    h
}

/// The mean depth complexity over the covered pixels of histogram `h` (pixels
/// by fragment count; the empty pixels of `h[0]` left out).
pub fn mean_over_covered(h: &[u64]) -> f64 {
    let covered: u64 = h.iter().skip(1).sum();
    let total: u64 = h.iter().enumerate().map(|(n, &c)| n as u64 * c).sum();
    total as f64 / covered.max(1) as f64
}

/// Measures depth complexity and memory of `scene` turned by `angle` degrees.
/// Returns the measurement and the unlimited rendering (for its per-pixel counts).
pub fn measure(
    scene: &FixedScene,
    config: &StatsConfig,
    angle: f32,
) -> Result<(DepthComplexity, RenderOutput), String> {
    let base = RenderConfig {
        grid: config.grid,
        band: config.band,
        main: config.main,
        extra: config.extra,
        ..Default::default()
    };
    let unlimited = render(
        scene,
        &RenderConfig {
            method: Method::Unlimited,
            rasterize_every_front_face: true,
            ..base
        },
        angle,
    )?;
    let band = config.band.clamp(1, scene.height);
    let pool = config.pool.unwrap_or(defaults::POOL_SLOTS);
    let shared = render(
        scene,
        &RenderConfig {
            method: Method::Shared,
            pool: Some(pool),
            ..base
        },
        angle,
    )?;
    let roomy_pool = scene.width as usize * band as usize * config.extra as usize;
    let roomy = render(
        scene,
        &RenderConfig {
            method: Method::Shared,
            pool: Some(roomy_pool),
            ..base
        },
        angle,
    )?;
    let generated_histogram = histogram(unlimited.generated_per_pixel.iter().map(|&n| n as u32));
    let visible_histogram = histogram(unlimited.stored_per_pixel.iter().map(|&n| n as u32));
    let stored_histogram = histogram(shared.stored_per_pixel.iter().map(|&n| n as u32));
    let pool_demand = roomy.stats.buffer.pool_peak;
    let memory = band_memory(
        scene.width,
        band,
        config.grid,
        config.main,
        config.extra,
        pool,
    );
    let memory_at_demand = band_memory(
        scene.width,
        band,
        config.grid,
        config.main,
        config.extra,
        pool_demand as usize,
    );
    Ok((
        DepthComplexity {
            triangles: scene.triangle_count(),
            width: scene.width,
            height: scene.height,
            covered_pixels: generated_histogram.iter().skip(1).sum(),
            mean_generated: mean_over_covered(&generated_histogram),
            mean_visible: mean_over_covered(&visible_histogram),
            generated_histogram,
            visible_histogram,
            stored_histogram,
            unlimited_pool_peak: unlimited.stats.buffer.pool_peak,
            pool_peak: shared.stats.buffer.pool_peak,
            merges: shared.stats.buffer.merges,
            pool_demand,
            memory,
            memory_at_demand,
        },
        unlimited,
    ))
}

/// A file-name-safe version of a scene name.
pub fn file_tag(scene: &str) -> String {
    let path = Path::new(scene);
    let name = match path.file_stem() {
        Some(stem) if scene.ends_with(".toml") => stem.to_string_lossy().into_owned(),
        _ => scene.to_string(),
    };
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '.' {
                c
            } else {
                '-'
            }
        })
        .collect()
}

fn percent(part: u64, whole: u64) -> f64 {
    100.0 * part as f64 / whole.max(1) as f64
}

/// The histogram plot: generated, visible and stored fragments per pixel, as a
/// share of the covered pixels, bars in the heat maps' colors.
pub fn histogram_svg(
    title: &str,
    d: &DepthComplexity,
    config: &StatsConfig,
    scale_max: u32,
) -> String {
    let longest = d
        .generated_histogram
        .len()
        .max(d.visible_histogram.len())
        .max(d.stored_histogram.len())
        .min(HISTOGRAM_BARS + 1);
    let panel = |name: String, h: &[u64]| {
        let covered: u64 = h.iter().skip(1).sum();
        // The last bar collects every larger count.
        let bar = |n: usize| -> u64 {
            if n + 1 == longest {
                h.iter().skip(n).sum()
            } else {
                h.get(n).copied().unwrap_or(0)
            }
        };
        BarPanel {
            title: name,
            y_label: "% of covered pixels".into(),
            categories: (1..longest)
                .map(|n| {
                    if n + 1 == longest && h.len() > longest {
                        format!("{n}+")
                    } else {
                        n.to_string()
                    }
                })
                .collect(),
            values: (1..longest).map(|n| percent(bar(n), covered)).collect(),
            colors: (1..longest)
                .map(|n| count_color(n as u32, scale_max))
                .collect(),
        }
    };
    bar_panels_svg(
        title,
        "fragments in the pixel",
        &[
            panel(
                format!(
                    "generated (before visibility): mean {:.2}",
                    d.mean_generated
                ),
                &d.generated_histogram,
            ),
            panel(
                format!(
                    "visible (unlimited A-buffer, after visibility): mean {:.2}",
                    d.mean_visible
                ),
                &d.visible_histogram,
            ),
            panel(
                format!(
                    "stored with N_main {} + N_extra {}, N_pool {} ({} merges)",
                    config.main, config.extra, d.memory.pool_slots, d.merges
                ),
                &d.stored_histogram,
            ),
        ],
        Some(&format!(
            "{} triangles, {}x{}, {} covered pixels; bar colors are the heat maps' colors ({} and more: brightest)",
            d.triangles, d.width, d.height, d.covered_pixels, scale_max
        )),
    )
}

/// Runs `host-sim stats` on the loaded scene description.
pub fn run_stats(args: &StatsArgs, desc: SceneDesc) -> Result<(), String> {
    if args.main == 0 {
        return Err("--main must be at least 1".into());
    }
    if args.band == 0 {
        return Err("--band must be at least 1".into());
    }
    let scene = crate::convert::to_fixed(&desc)?;
    let config = StatsConfig {
        grid: args.grid,
        main: args.main,
        extra: args.extra,
        pool: args.pool,
        band: args.band,
    };
    let (d, unlimited) = measure(&scene, &config, args.angle)?;
    let pixels = d.width as u64 * d.height as u64;
    println!(
        "scene            {} ({} triangles, {}x{}, angle {})",
        args.scene, d.triangles, d.width, d.height, args.angle
    );
    println!(
        "covered pixels   {} ({:.1} %)",
        d.covered_pixels,
        percent(d.covered_pixels, pixels)
    );
    println!(
        "mean per covered pixel: {:.3} generated, {:.3} visible",
        d.mean_generated, d.mean_visible
    );
    println!("fragments per pixel (pixels holding n):");
    println!(
        "  {:>3} {:>10} {:>10} {:>12}",
        "n",
        "generated",
        "visible",
        format!("stored {}+{}", args.main, args.extra)
    );
    let longest = d
        .generated_histogram
        .len()
        .max(d.visible_histogram.len())
        .max(d.stored_histogram.len());
    for n in 0..longest {
        let get = |h: &[u64]| h.get(n).copied().unwrap_or(0);
        println!(
            "  {:>3} {:>10} {:>10} {:>12}",
            n,
            get(&d.generated_histogram),
            get(&d.visible_histogram),
            get(&d.stored_histogram)
        );
    }
    let m = &d.memory;
    println!(
        "memory per band  {}x{} = {} pixels, {} masks: M_frag {} B, M_addr {} B",
        d.width,
        args.band.min(d.height),
        m.band_pixels,
        args.grid.samples(),
        m.fragment_bytes,
        m.address_bytes
    );
    println!(
        "  main buffer    N_main {} + N_extra {}: {} B",
        m.main_slots, m.extra_addresses, m.main_buffer_bytes
    );
    println!(
        "  shared pool    N_pool {}: {} B (peak {}{}, {} merges)",
        m.pool_slots,
        m.pool_bytes,
        d.pool_peak,
        if d.pool_peak as usize >= m.pool_slots {
            ": full"
        } else {
            ""
        },
        d.merges
    );
    println!(
        "  M_shared       {} B; M_fixed (N_fixed {}) {} B; M_fixed / M_shared {:.2}",
        m.total_bytes,
        m.main_slots as u32 + m.extra_addresses as u32,
        m.fixed_equivalent_bytes,
        m.fixed_to_shared_ratio()
    );
    let a = &d.memory_at_demand;
    println!(
        "  pool demand    {} slots (no merge forced by the pool): M_shared {} B, M_fixed / M_shared {:.2}",
        d.pool_demand,
        a.total_bytes,
        a.fixed_to_shared_ratio()
    );
    println!(
        "  unlimited      pool peak {} (N_main 1, N_extra {})",
        d.unlimited_pool_peak,
        args.grid.samples() - 1
    );
    if let Some(dir) = &args.out_dir {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let tag = args.name.clone().unwrap_or_else(|| file_tag(&args.scene));
        let scale_max = HEAT_SCALE_MAX;
        let (w, h) = (d.width as u32, d.height as u32);
        let generated = dir.join(format!("{tag}-generated.png"));
        write_png(
            &generated,
            w,
            h,
            &count_heat_map(&unlimited.generated_per_pixel, scale_max),
        )?;
        let visible: Vec<u16> = unlimited
            .stored_per_pixel
            .iter()
            .map(|&n| n as u16)
            .collect();
        let visible_path = dir.join(format!("{tag}-visible.png"));
        write_png(&visible_path, w, h, &count_heat_map(&visible, scale_max))?;
        let svg_path = dir.join(format!("{tag}-histogram.svg"));
        let title = format!("Fragments per pixel: {}", args.scene);
        std::fs::write(&svg_path, histogram_svg(&title, &d, &config, scale_max))
            .map_err(|e| format!("{}: {e}", svg_path.display()))?;
        let json_path = dir.join(format!("{tag}-stats.json"));
        std::fs::write(
            &json_path,
            serde_json::to_string_pretty(&d).unwrap_or_default(),
        )
        .map_err(|e| format!("{}: {e}", json_path.display()))?;
        for p in [&generated, &visible_path, &svg_path, &json_path] {
            println!("wrote            {}", p.display());
        }
    }
    Ok(())
}
