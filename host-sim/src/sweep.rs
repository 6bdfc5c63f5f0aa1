//! The quality-against-memory sweep (`host-sim sweep`): every overflow policy at
//! every fragment budget, NMSE against the unlimited A-buffer, memory from the
//! real packed sizes (SPEC sections 4 to 6).
//!
//! Budget `k` is the most fragments a pixel may hold:
//! - `fixed-discard`, `fixed-merge`: `k` slots per pixel, no pool;
//! - `shared`, `merge-closest`: for each requested split `m`, `N_main = min(m, k)`
//!   slots and `N_extra = k - N_main` pool addresses per pixel (a split that
//!   repeats an earlier one at the same budget is left out).
//!
//! The pool of `shared` and `merge-closest` is either a fixed number of slots per
//! band, or, by default, sized to the worst peak: each frame is rendered with a
//! pool that cannot run out, and the memory is counted with `N_pool` equal to the
//! largest number of pool slots in use at once over all frames. A pool of exactly
//! that many slots hands out the same slots in the same order, so it renders the
//! same images; with it the pool never forces a merge, and `shared` at budget `k`
//! renders what `fixed-merge` renders with `k` slots.
//!
//! Frames turn the scene about the vertical axis (`frames` evenly spaced angles
//! over a full turn); NMSE is taken over all frames together
//! (`sum (I - R)^2 / sum R^2` over every frame's pixels and channels).

use crate::compare::ErrorSums;
use crate::convert::FixedScene;
use crate::memory::{band_memory, MemoryReport};
use crate::plot::{LineChart, Point, Scale, Series, PALETTE};
use crate::render::{render, Grid, Method, RenderConfig};
use indicatif::{ProgressBar, ProgressStyle};
use mcu_abuffer::memory::defaults;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// How a pixel's memory overflows, as the sweep names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, clap::ValueEnum)]
pub enum Policy {
    /// Fixed slots; of the two farthest, the smaller coverage is dropped.
    FixedDiscard,
    /// Fixed slots; the two farthest merge.
    FixedMerge,
    /// Main slots + pool addresses + shared pool; the two farthest merge (the paper).
    Shared,
    /// As `shared`, but the pair closest in depth merges (as Z3 does).
    MergeClosest,
}

impl Policy {
    /// Every policy, in table order.
    pub const ALL: [Policy; 4] = [
        Policy::FixedDiscard,
        Policy::FixedMerge,
        Policy::Shared,
        Policy::MergeClosest,
    ];

    /// The name used on the command line and in the CSV.
    pub fn name(self) -> &'static str {
        match self {
            Policy::FixedDiscard => "fixed-discard",
            Policy::FixedMerge => "fixed-merge",
            Policy::Shared => "shared",
            Policy::MergeClosest => "merge-closest",
        }
    }

    /// Whether the policy uses the shared pool.
    pub fn uses_pool(self) -> bool {
        matches!(self, Policy::Shared | Policy::MergeClosest)
    }
}

/// One configuration of the sweep.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SweepConfig {
    /// Overflow policy.
    pub policy: Policy,
    /// Most fragments per pixel, `N_main + N_extra`.
    pub budget: u8,
    /// The requested split (`N_main` before capping at the budget); the budget
    /// itself for the fixed policies.
    pub split: u8,
    /// `N_main` (or `N_fixed`).
    pub main: u8,
    /// `N_extra` (0 for the fixed policies).
    pub extra: u8,
}

/// The configurations for `budgets`, `policies` and `splits` (see the module docs).
pub fn sweep_configs(budgets: &[u8], policies: &[Policy], splits: &[u8]) -> Vec<SweepConfig> {
    let mut configs = Vec::new();
    for &policy in policies {
        for &k in budgets {
            if policy.uses_pool() {
                let mut seen = Vec::new();
                for &m in splits {
                    let main = m.clamp(1, k);
                    if seen.contains(&main) {
                        continue;
                    }
                    seen.push(main);
                    configs.push(SweepConfig {
                        policy,
                        budget: k,
                        split: m,
                        main,
                        extra: k - main,
                    });
                }
            } else {
                configs.push(SweepConfig {
                    policy,
                    budget: k,
                    split: k,
                    main: k,
                    extra: 0,
                });
            }
        }
    }
    configs
}

/// How the pool of `shared` and `merge-closest` is sized.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PoolSizing {
    /// To the worst peak over the frames (no merge is forced by the pool).
    Peak,
    /// A fixed number of slots per band.
    Slots(usize),
}

/// What to sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepParams {
    /// Mask grid.
    pub grid: Grid,
    /// Band height `R`.
    pub band: u16,
    /// Turntable angle of each frame, degrees.
    pub angles: Vec<f32>,
    /// Pool sizing.
    pub pool: PoolSizing,
    /// The configurations.
    pub configs: Vec<SweepConfig>,
}

/// `frames` angles evenly spaced over a full turn, starting at `start_deg`.
pub fn turntable_angles(frames: u32, start_deg: f32) -> Vec<f32> {
    (0..frames.max(1))
        .map(|i| start_deg + 360.0 * i as f32 / frames.max(1) as f32)
        .collect()
}

/// The measurements of one configuration over all frames.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepRow {
    /// The configuration.
    pub config: SweepConfig,
    /// Largest pool occupancy over the frames (0 without a pool).
    pub pool_peak: u32,
    /// Memory of the band buffer (`N_pool` per the sizing).
    pub memory: MemoryReport,
    /// NMSE against the unlimited A-buffer over all frames.
    pub nmse: f64,
    /// PSNR against the unlimited A-buffer over all frames, dB.
    pub psnr_db: f64,
    /// Largest channel difference in any frame.
    pub max_abs_diff: u8,
    /// Pixels that differ, summed over frames.
    pub differing_pixels: u64,
    /// Merges, summed over frames.
    pub merges: u64,
    /// Discarded fragments, summed over frames.
    pub discarded: u64,
}

/// A finished sweep.
#[derive(Clone, Debug)]
pub struct SweepResult {
    /// One row per configuration, in the order of [`SweepParams::configs`].
    pub rows: Vec<SweepRow>,
    /// The unlimited A-buffer's worst pool peak over the frames.
    pub unlimited_pool_peak: u32,
    /// Renderings made (references included).
    pub renders: usize,
    /// Wall time.
    pub elapsed: Duration,
}

/// What one rendering of one configuration contributed.
struct FrameMeasure {
    sums: ErrorSums,
    pool_peak: u32,
    merges: u64,
    discarded: u64,
    max_abs_diff: u8,
    differing_pixels: u64,
}

fn render_config(
    config: &SweepConfig,
    params: &SweepParams,
    width: u16,
    height: u16,
) -> RenderConfig {
    let band = params.band.clamp(1, height);
    let pool = match params.pool {
        PoolSizing::Slots(n) => n,
        // Enough for every pixel to fill all its addresses: never runs out.
        PoolSizing::Peak => width as usize * band as usize * config.extra as usize,
    };
    let method = match config.policy {
        Policy::FixedDiscard => Method::FixedDiscard,
        Policy::FixedMerge => Method::FixedMerge,
        Policy::Shared => Method::Shared,
        Policy::MergeClosest => Method::MergeClosest,
    };
    RenderConfig {
        method,
        grid: params.grid,
        main: config.main,
        extra: config.extra,
        pool: Some(pool),
        fixed: config.budget,
        band,
        ..Default::default()
    }
}

/// Runs the sweep on both cores; `progress` advances once per rendering.
pub fn run_sweep(
    scene: &FixedScene,
    params: &SweepParams,
    progress: &ProgressBar,
) -> Result<SweepResult, String> {
    let start = Instant::now();
    if params.angles.is_empty() {
        return Err("a sweep needs at least one frame".into());
    }
    if let Some(bad) = params.configs.iter().find(|c| c.main == 0 || c.budget == 0) {
        return Err(format!("budget and N_main must be at least 1: {bad:?}"));
    }
    let (w, h) = (scene.width, scene.height);
    let band = params.band.clamp(1, h);
    let reference_config = RenderConfig {
        method: Method::Unlimited,
        grid: params.grid,
        band,
        ..Default::default()
    };
    let references = params
        .angles
        .par_iter()
        .map(|&a| {
            let r = render(scene, &reference_config, a);
            progress.inc(1);
            r
        })
        .collect::<Result<Vec<_>, String>>()?;
    let jobs: Vec<(usize, usize)> = (0..params.configs.len())
        .flat_map(|c| (0..params.angles.len()).map(move |f| (c, f)))
        .collect();
    let measures = jobs
        .par_iter()
        .map(|&(c, f)| {
            let cfg = render_config(&params.configs[c], params, w, h);
            let out = render(scene, &cfg, params.angles[f])?;
            let reference = &references[f].rgb;
            let mut sums = ErrorSums::default();
            sums.add(&out.rgb, reference);
            let mut max_abs_diff = 0u8;
            let mut differing_pixels = 0u64;
            for (p, q) in out.rgb.chunks_exact(3).zip(reference.chunks_exact(3)) {
                let d = p
                    .iter()
                    .zip(q)
                    .map(|(a, b)| a.abs_diff(*b))
                    .max()
                    .unwrap_or(0);
                max_abs_diff = max_abs_diff.max(d);
                differing_pixels += (d > 0) as u64;
            }
            progress.inc(1);
            Ok(FrameMeasure {
                sums,
                pool_peak: out.stats.buffer.pool_peak,
                merges: out.stats.buffer.merges.into(),
                discarded: out.stats.buffer.fragments_discarded.into(),
                max_abs_diff,
                differing_pixels,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    let frames = params.angles.len();
    let rows = params
        .configs
        .iter()
        .enumerate()
        .map(|(c, config)| {
            let ms = &measures[c * frames..(c + 1) * frames];
            let mut sums = ErrorSums::default();
            for m in ms {
                sums.squared_error += m.sums.squared_error;
                sums.reference_energy += m.sums.reference_energy;
                sums.values += m.sums.values;
            }
            let pool_peak = ms.iter().map(|m| m.pool_peak).max().unwrap_or(0);
            let pool_slots = if config.policy.uses_pool() {
                match params.pool {
                    PoolSizing::Peak => pool_peak as usize,
                    PoolSizing::Slots(n) => n,
                }
            } else {
                0
            };
            SweepRow {
                config: *config,
                pool_peak,
                memory: band_memory(w, band, params.grid, config.main, config.extra, pool_slots),
                nmse: sums.nmse(),
                psnr_db: sums.psnr_db(),
                max_abs_diff: ms.iter().map(|m| m.max_abs_diff).max().unwrap_or(0),
                differing_pixels: ms.iter().map(|m| m.differing_pixels).sum(),
                merges: ms.iter().map(|m| m.merges).sum(),
                discarded: ms.iter().map(|m| m.discarded).sum(),
            }
        })
        .collect();
    Ok(SweepResult {
        rows,
        unlimited_pool_peak: references
            .iter()
            .map(|r| r.stats.buffer.pool_peak)
            .max()
            .unwrap_or(0),
        renders: references.len() + jobs.len(),
        elapsed: start.elapsed(),
    })
}

/// The CSV header, one column per [`SweepRow`] field plus the scene's.
pub const CSV_HEADER: &str = "scene,width,height,frames,grid,band,policy,fragments_per_pixel,split,n_main,n_extra,pool_slots,pool_peak,fragment_bytes,address_bytes,main_buffer_bytes,pool_bytes,total_bytes,bytes_per_pixel,fixed_equivalent_bytes,nmse,psnr_db,max_abs_diff,differing_pixels,merges,discarded";

/// The sweep as CSV (header line included). Scene names are quoted.
pub fn to_csv(
    scene_name: &str,
    scene: &FixedScene,
    params: &SweepParams,
    result: &SweepResult,
) -> String {
    let mut out = String::new();
    out.push_str(CSV_HEADER);
    out.push('\n');
    let band = params.band.clamp(1, scene.height);
    for r in &result.rows {
        let m = &r.memory;
        let _ = writeln!(
            out,
            "\"{}\",{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.4},{},{:e},{:.4},{},{},{},{}",
            scene_name.replace('"', "\"\""),
            scene.width,
            scene.height,
            params.angles.len(),
            params.grid.name(),
            band,
            r.config.policy.name(),
            r.config.budget,
            r.config.split,
            r.config.main,
            r.config.extra,
            m.pool_slots,
            r.pool_peak,
            m.fragment_bytes,
            m.address_bytes,
            m.main_buffer_bytes,
            m.pool_bytes,
            m.total_bytes,
            m.bytes_per_pixel(),
            m.fixed_equivalent_bytes,
            r.nmse,
            r.psnr_db,
            r.max_abs_diff,
            r.differing_pixels,
            r.merges,
            r.discarded
        );
    }
    out
}

/// A series of the plots: one policy, one split.
fn series_key(c: &SweepConfig) -> (Policy, u8) {
    (c.policy, if c.policy.uses_pool() { c.split } else { 0 })
}

fn series_name(key: (Policy, u8)) -> String {
    if key.0.uses_pool() {
        format!("{} N_main={}", key.0.name(), key.1)
    } else {
        key.0.name().to_string()
    }
}

/// The plot series: one per policy and split, points in budget order.
fn plot_series(result: &SweepResult, x: impl Fn(&SweepRow) -> f64) -> Vec<Series> {
    let mut keys: Vec<(Policy, u8)> = Vec::new();
    for r in &result.rows {
        let k = series_key(&r.config);
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    keys.iter()
        .enumerate()
        .map(|(i, &key)| {
            let mut rows: Vec<&SweepRow> = result
                .rows
                .iter()
                .filter(|r| series_key(&r.config) == key)
                .collect();
            rows.sort_by_key(|r| r.config.budget);
            Series {
                name: series_name(key),
                color: PALETTE[i % PALETTE.len()],
                dashed: key.0 == Policy::MergeClosest,
                points: rows
                    .iter()
                    .map(|r| Point {
                        x: x(r),
                        y: r.nmse,
                        label: Some(r.config.budget.to_string()),
                    })
                    .collect(),
            }
        })
        .collect()
}

/// NMSE against bytes of fragment memory per pixel.
pub fn nmse_memory_chart(title: &str, result: &SweepResult) -> LineChart {
    LineChart {
        title: title.to_string(),
        x_label: "fragment memory per pixel of the band, bytes (M / (W R))".into(),
        y_label: "NMSE against unlimited".into(),
        x_scale: Scale::Linear,
        y_scale: Scale::Log10,
        series: plot_series(result, |r| r.memory.bytes_per_pixel()),
        note: Some("labels: fragments per pixel; hollow markers on the bottom edge: NMSE 0".into()),
    }
}

/// NMSE against the budget (fragments per pixel).
pub fn nmse_budget_chart(title: &str, result: &SweepResult) -> LineChart {
    LineChart {
        title: title.to_string(),
        x_label: "fragments per pixel (N_main + N_extra, or N_fixed)".into(),
        y_label: "NMSE against unlimited".into(),
        x_scale: Scale::Linear,
        y_scale: Scale::Log10,
        series: plot_series(result, |r| r.config.budget as f64),
        note: Some("hollow markers on the bottom edge: NMSE 0".into()),
    }
}

/// Relative NMSE tolerance of "equal quality" in the summary.
pub const EQUAL_QUALITY_TOLERANCE: f64 = 0.05;

/// The cheapest row of `policy` whose NMSE is at most `nmse (1 + tolerance)`.
pub fn cheapest_within(result: &SweepResult, policy: Policy, nmse: f64) -> Option<&SweepRow> {
    result
        .rows
        .iter()
        .filter(|r| r.config.policy == policy && r.nmse <= nmse * (1.0 + EQUAL_QUALITY_TOLERANCE))
        .min_by_key(|r| r.memory.total_bytes)
}

fn fmt_nmse(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v:.2e}")
    }
}

/// A Markdown summary: NMSE by budget and policy, and memory at equal quality.
pub fn summary_markdown(
    scene_name: &str,
    scene: &FixedScene,
    params: &SweepParams,
    result: &SweepResult,
) -> String {
    let mut out = String::new();
    let band = params.band.clamp(1, scene.height);
    let _ = writeln!(
        out,
        "Scene `{scene_name}`: {} triangles, {}x{}, {} frame(s), {} masks, band {} rows; pool {}.\n",
        scene.triangle_count(),
        scene.width,
        scene.height,
        params.angles.len(),
        params.grid.name(),
        band,
        match params.pool {
            PoolSizing::Peak => "sized to the worst peak over the frames".to_string(),
            PoolSizing::Slots(n) => format!("{n} slots per band"),
        }
    );
    let mut keys: Vec<(Policy, u8)> = Vec::new();
    for r in &result.rows {
        let k = series_key(&r.config);
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    let mut budgets: Vec<u8> = result.rows.iter().map(|r| r.config.budget).collect();
    budgets.sort_unstable();
    budgets.dedup();
    out.push_str("NMSE against unlimited:\n\n| fragments per pixel |");
    for &k in &keys {
        let _ = write!(out, " {} |", series_name(k));
    }
    out.push_str("\n|---|");
    for _ in &keys {
        out.push_str("---|");
    }
    out.push('\n');
    for &b in &budgets {
        let _ = write!(out, "| {b} |");
        for &k in &keys {
            let cell = result
                .rows
                .iter()
                .find(|r| series_key(&r.config) == k && r.config.budget == b)
                .map(|r| fmt_nmse(r.nmse))
                .unwrap_or_else(|| "-".into());
            let _ = write!(out, " {cell} |");
        }
        out.push('\n');
    }
    let _ = writeln!(
        out,
        "\nMemory of `shared` (bytes per band) against fixed slots at equal quality \
         (NMSE within {} %); `fixed-merge` at the same budget renders the same image when \
         the pool is sized to the peak:\n",
        EQUAL_QUALITY_TOLERANCE * 100.0
    );
    out.push_str("| fragments per pixel | N_main + N_extra | pool peak | M_shared | NMSE | cheapest fixed-merge within tolerance | M_fixed / M_shared | cheapest fixed-discard within tolerance | M_fixed / M_shared |\n|---|---|---|---|---|---|---|---|---|\n");
    for r in result
        .rows
        .iter()
        .filter(|r| r.config.policy == Policy::Shared)
    {
        let against = |p: Policy| match cheapest_within(result, p, r.nmse) {
            Some(f) => (
                format!("{} slots, {} B", f.config.budget, f.memory.total_bytes),
                format!(
                    "{:.2}",
                    f.memory.total_bytes as f64 / r.memory.total_bytes as f64
                ),
            ),
            None => ("none in the sweep".into(), "-".into()),
        };
        let (merge, merge_ratio) = against(Policy::FixedMerge);
        let (discard, discard_ratio) = against(Policy::FixedDiscard);
        let _ = writeln!(
            out,
            "| {} | {} + {} | {} | {} | {} | {merge} | {merge_ratio} | {discard} | {discard_ratio} |",
            r.config.budget,
            r.config.main,
            r.config.extra,
            r.pool_peak,
            r.memory.total_bytes,
            fmt_nmse(r.nmse)
        );
    }
    let _ = writeln!(
        out,
        "\nUnlimited A-buffer: worst pool peak {} (1 main slot per pixel). {} renderings in {:.1} s.",
        result.unlimited_pool_peak,
        result.renders,
        result.elapsed.as_secs_f64()
    );
    out
}

/// Arguments of `host-sim sweep`.
#[derive(clap::Args, Debug)]
pub struct SweepArgs {
    /// A built-in scene or a scene file (.toml).
    #[arg(long, default_value = "teapot")]
    pub scene: String,
    /// Image width.
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height.
    #[arg(long)]
    pub height: Option<u32>,
    /// Frames of a turntable animation (a full turn); NMSE and pool peak over all.
    #[arg(long, default_value_t = 1)]
    pub frames: u32,
    /// Angle of the first frame, degrees.
    #[arg(long, default_value_t = 0.0)]
    pub angle: f32,
    /// Largest budget: fragments per pixel 1..=N.
    #[arg(long, default_value_t = 8)]
    pub max_fragments: u8,
    /// N_main values for shared and merge-closest (N_extra = budget - N_main).
    #[arg(long, value_delimiter = ',', default_value = "1,2")]
    pub splits: Vec<u8>,
    /// Policies to sweep.
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = Policy::ALL.to_vec())]
    pub policies: Vec<Policy>,
    /// Coverage mask grid.
    #[arg(long, value_enum, default_value_t = Grid::G4x4)]
    pub grid: Grid,
    /// Band height in rows (R).
    #[arg(long, default_value_t = defaults::BAND_ROWS)]
    pub band: u16,
    /// Pool slots per band for shared and merge-closest; default: the worst peak.
    #[arg(long)]
    pub pool: Option<usize>,
    /// Directory for the CSV, the plots and the summary.
    #[arg(long, default_value = ".")]
    pub out_dir: PathBuf,
    /// File name prefix (default: the scene name).
    #[arg(long)]
    pub name: Option<String>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// Runs `host-sim sweep` on the loaded scene description.
pub fn run_sweep_command(
    args: &SweepArgs,
    desc: crate::scene_desc::SceneDesc,
) -> Result<(), String> {
    if args.max_fragments == 0 || args.max_fragments > 64 {
        return Err("--max-fragments must be 1..=64".into());
    }
    if args.splits.is_empty() || args.splits.contains(&0) {
        return Err("--splits needs N_main values of at least 1".into());
    }
    if args.frames == 0 || args.band == 0 {
        return Err("--frames and --band must be at least 1".into());
    }
    let scene = crate::convert::to_fixed(&desc)?;
    let budgets: Vec<u8> = (1..=args.max_fragments).collect();
    let params = SweepParams {
        grid: args.grid,
        band: args.band,
        angles: if args.frames == 1 {
            vec![args.angle]
        } else {
            turntable_angles(args.frames, args.angle)
        },
        pool: args.pool.map_or(PoolSizing::Peak, PoolSizing::Slots),
        configs: sweep_configs(&budgets, &args.policies, &args.splits),
    };
    let total = (params.configs.len() + 1) * params.angles.len();
    let progress = if args.quiet {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::new(total as u64);
        if let Ok(style) = ProgressStyle::with_template(
            "{bar:40.cyan/blue} {pos}/{len} renderings {elapsed} (eta {eta})",
        ) {
            bar.set_style(style);
        }
        bar
    };
    let result = run_sweep(&scene, &params, &progress)?;
    progress.finish_and_clear();
    std::fs::create_dir_all(&args.out_dir)
        .map_err(|e| format!("{}: {e}", args.out_dir.display()))?;
    let tag = args
        .name
        .clone()
        .unwrap_or_else(|| crate::complexity::file_tag(&args.scene));
    let write = |suffix: &str, text: String| -> Result<PathBuf, String> {
        let path = args.out_dir.join(format!("{tag}-{suffix}"));
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(path)
    };
    let title = format!(
        "{} ({} triangles, {}x{}, {} frame{}, {} masks)",
        args.scene,
        scene.triangle_count(),
        scene.width,
        scene.height,
        params.angles.len(),
        if params.angles.len() == 1 { "" } else { "s" },
        args.grid.name()
    );
    let summary = summary_markdown(&args.scene, &scene, &params, &result);
    let paths = [
        write("sweep.csv", to_csv(&args.scene, &scene, &params, &result))?,
        write(
            "nmse-memory.svg",
            nmse_memory_chart(&title, &result).to_svg(),
        )?,
        write(
            "nmse-budget.svg",
            nmse_budget_chart(&title, &result).to_svg(),
        )?,
        write("sweep.md", summary.clone())?,
    ];
    println!("{summary}");
    for p in &paths {
        println!("wrote {}", p.display());
    }
    eprintln!(
        "sweep: {} renderings of {}x{} in {:.2} s on {} threads",
        result.renders,
        scene.width,
        scene.height,
        result.elapsed.as_secs_f64(),
        rayon::current_num_threads()
    );
    Ok(())
}
