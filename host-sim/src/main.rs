//! `host-sim`: renders scenes with the `mcu_abuffer` library on the desktop.

use clap::{Parser, Subcommand};
use host_sim::convert::to_fixed;
use host_sim::image_io::write_png;
use host_sim::load_scene;
use host_sim::render::{render, Grid, Method, MidpointSettings, RenderConfig};
use mcu_abuffer::memory::defaults;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "host-sim",
    version,
    about = "Desktop simulator and test program for the mcu-abuffer renderer"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Renders a scene to a PNG image (or a turntable animation) and prints the frame statistics.
    Render(RenderArgs),
    /// Compares an image with a reference: NMSE, PSNR, largest difference, differing pixels.
    Compare(host_sim::compare::CompareArgs),
    /// Depth complexity, fragments per pixel, buffer memory and pool peak of a scene.
    Stats(host_sim::complexity::StatsArgs),
    /// NMSE against unlimited and memory for every policy at 1..8 fragments per pixel.
    Sweep(host_sim::sweep::SweepArgs),
    /// Gouraud, quadratic and phong side by side, with their errors against phong.
    Shading(host_sim::shading_compare::ShadingArgs),
    /// Whether buffer parameters fit a board's SRAM (analytic, or over a turntable; `cargo xtask fit-link` adds the linker's answer).
    Fit(host_sim::fit::FitArgs),
    /// Bounded-memory methods against unlimited over a turntable: worst NMSE,
    /// speckles, band-row error ratio, band splits, time (a Markdown table).
    Bounded(host_sim::bounded::BoundedArgs),
    /// The fastest bounded-memory configuration that fits an SRAM budget and
    /// keeps a turntable within an NMSE target against unlimited.
    Tune(host_sim::tune::TuneArgs),
    /// Depth comparisons, time and image errors of zbuffer, zbuffer-hiz and
    /// zbuffer-midpoint (K = 0..3), as a Markdown table.
    ZbufferTable(host_sim::zbuffer_table::ZbufferTableArgs),
}

#[derive(clap::Args)]
struct RenderArgs {
    /// A built-in scene (teapot, teapot:N, spheres, starfighter) or a scene file (.toml).
    #[arg(long, default_value = "teapot")]
    scene: String,
    /// Output PNG file.
    #[arg(long)]
    out: PathBuf,
    /// Image width (built-in scenes; a scene file sets its own unless given here).
    #[arg(long)]
    width: Option<u32>,
    /// Image height.
    #[arg(long)]
    height: Option<u32>,
    /// Pixel memory method.
    #[arg(long, value_enum, default_value_t = Method::SplitBands)]
    method: Method,
    /// Coverage mask grid (columns x rows).
    #[arg(long, value_enum, default_value_t = Grid::G4x4)]
    grid: Grid,
    /// Main fragment slots per pixel (N_main), for shared and merge-closest.
    #[arg(long, default_value_t = defaults::MAIN_SLOTS)]
    main: u8,
    /// Pool addresses per pixel (N_extra), for shared and merge-closest.
    #[arg(long, default_value_t = defaults::EXTRA_ADDRESSES)]
    extra: u8,
    /// Shared pool slots per band (N_pool).
    #[arg(long, default_value_t = defaults::POOL_SLOTS)]
    pool: usize,
    /// Fragment slots per pixel (N_fixed), for fixed-discard and fixed-merge.
    #[arg(long, default_value_t = defaults::FIXED_SLOTS)]
    fixed: u8,
    /// Band height in rows (R); default: the method's (6, the z-buffers 24).
    #[arg(long)]
    band: Option<u16>,
    /// Turntable angle in degrees (rotation of every object about the world Y axis).
    #[arg(long, default_value_t = 0.0)]
    angle: f32,
    /// Also write the statistics as JSON to this file.
    #[arg(long)]
    stats_json: Option<PathBuf>,
    /// Samples per pixel side for --method ssaa (N x N samples per pixel).
    #[arg(long, default_value_t = 4)]
    ssaa: u8,
    /// Render a turntable animation: every object turns about the vertical axis.
    #[arg(long)]
    turntable: bool,
    /// Frames of the turntable (a full turn; default 36). Output: a .gif, or numbered PNGs.
    #[arg(long)]
    frames: Option<u32>,
    /// Display time of one animation frame, milliseconds.
    #[arg(long, default_value_t = 80)]
    frame_ms: u32,
    /// Subdivisions before the first test, for --method zbuffer-midpoint (K).
    #[arg(long, default_value_t = MidpointSettings::default().initial)]
    subdiv_initial: u8,
    /// Deepest subdivision level, for --method zbuffer-midpoint (D, K..=6).
    #[arg(long, default_value_t = MidpointSettings::default().max)]
    subdiv_max: u8,
    /// zbuffer-midpoint: keep per-pixel depth tests in pieces judged visible,
    /// so that only the "hidden" verdict can be wrong.
    #[arg(long)]
    midpoint_safe: bool,
    /// Rasterize every face of the viewer in full, so that the fragments
    /// generated in the statistics measure depth complexity (the image is
    /// the same; by default a face drawn right after a hidden triangle is
    /// skipped when the whole band hides it).
    #[arg(long)]
    every_front_face: bool,
}

fn run_render(args: &RenderArgs) -> Result<(), String> {
    if args.main == 0
        && matches!(
            args.method,
            Method::Shared | Method::MergeClosest | Method::SplitBands
        )
    {
        return Err("--main must be at least 1".into());
    }
    if args.fixed == 0 && matches!(args.method, Method::FixedDiscard | Method::FixedMerge) {
        return Err("--fixed must be at least 1".into());
    }
    let zbuffer = matches!(
        args.method,
        Method::Zbuffer | Method::ZbufferHiz | Method::ZbufferMidpoint
    );
    let band = args.band.unwrap_or(defaults::band_rows(zbuffer));
    if band == 0 {
        return Err("--band must be at least 1".into());
    }
    let desc = load_scene(&args.scene, args.width, args.height)?;
    let scene = to_fixed(&desc)?;
    let config = RenderConfig {
        method: args.method,
        grid: args.grid,
        main: args.main,
        extra: args.extra,
        pool: Some(args.pool),
        fixed: args.fixed,
        band,
        ssaa: args.ssaa,
        midpoint: MidpointSettings {
            initial: args.subdiv_initial,
            max: args.subdiv_max,
            safe: args.midpoint_safe,
        },
        rasterize_every_front_face: args.every_front_face,
    };
    if args.turntable || args.frames.is_some() {
        if !args.turntable {
            return Err("--frames needs --turntable (nothing else moves)".into());
        }
        let frames = host_sim::animate::run_turntable(
            &scene,
            &config,
            args.frames.unwrap_or(36),
            args.angle,
            args.frame_ms,
            &args.out,
        )?;
        if let Some(path) = &args.stats_json {
            host_sim::animate::write_frames_json(path, &args.scene, &config, &frames)?;
        }
        return Ok(());
    }
    let out = render(&scene, &config, args.angle)?;
    write_png(&args.out, out.width as u32, out.height as u32, &out.rgb)?;
    let s = &out.stats;
    let b = &s.buffer;
    let g = &s.geometry;
    println!(
        "scene            {} ({} triangles, {}x{})",
        args.scene,
        scene.triangle_count(),
        out.width,
        out.height
    );
    println!(
        "method           {:?} grid {:?} band {} pool {}",
        args.method,
        args.grid,
        band.min(out.height),
        out.pool_slots
    );
    println!(
        "triangles        {} in, {} clipped, {} outside, {} back-facing, {} degenerate",
        g.triangles_in,
        g.triangles_clipped,
        g.triangles_outside,
        g.triangles_backfacing,
        g.triangles_degenerate
    );
    println!(
        "setups           {} triangle, {} color, {} colors carried from the band above",
        g.triangle_setups, g.color_setups, g.colors_carried
    );
    println!(
        "fragments        {} generated, {} stored, {} hidden on arrival, {} removed as hidden",
        b.fragments_generated,
        b.fragments_stored,
        b.fragments_hidden_on_arrival,
        b.fragments_removed_hidden
    );
    println!(
        "overflow         {} merges, {} discarded",
        b.merges, b.fragments_discarded
    );
    println!("pool peak        {}", b.pool_peak);
    println!("max per pixel    {}", b.max_fragments_in_pixel);
    let depth = host_sim::zbuffer_table::depth_report(&scene, &config, args.angle, &out)?;
    if let Some((counts, differing)) = &depth {
        for line in host_sim::zbuffer_table::report_lines(counts, *differing) {
            println!("{line}");
        }
    } else if b.culling_depth_tests > 0 {
        // The A-buffer's whole-band test of triangles facing away.
        println!(
            "hidden whole     {} triangles skipped in a band, {} pixels tested",
            b.triangles_culled, b.culling_depth_tests
        );
    }
    println!("time             {:.2} ms", out.elapsed.as_secs_f64() * 1e3);
    println!("wrote            {}", args.out.display());
    if let Some(path) = &args.stats_json {
        let json = serde_json::json!({
            "scene": args.scene,
            "triangles": scene.triangle_count(),
            "width": out.width,
            "height": out.height,
            "config": config,
            "pool_slots": out.pool_slots,
            "milliseconds": out.elapsed.as_secs_f64() * 1e3,
            "geometry": {
                "triangles_in": g.triangles_in,
                "triangles_clipped": g.triangles_clipped,
                "triangles_outside": g.triangles_outside,
                "triangles_backfacing": g.triangles_backfacing,
                "triangles_degenerate": g.triangles_degenerate,
                "triangle_setups": g.triangle_setups,
                "color_setups": g.color_setups,
                "colors_carried": g.colors_carried,
            },
            "fragments": {
                "generated": b.fragments_generated,
                "stored": b.fragments_stored,
                "hidden_on_arrival": b.fragments_hidden_on_arrival,
                "removed_hidden": b.fragments_removed_hidden,
                "merges": b.merges,
                "discarded": b.fragments_discarded,
                "pool_peak": b.pool_peak,
                "max_in_pixel": b.max_fragments_in_pixel,
            },
            "bands": s.bands,
            "depth": depth.map(|(c, d)| host_sim::zbuffer_table::report_json(&c, d)),
        });
        std::fs::write(
            path,
            serde_json::to_string_pretty(&json).unwrap_or_default(),
        )
        .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
    }
    Ok(())
}

/// Exit status of a program whose output pipe was closed (128 + SIGPIPE),
/// as a shell reports it.
const BROKEN_PIPE_STATUS: i32 = 141;

/// Ends the program quietly when the reader of its standard output goes
/// away (`host-sim compare a.png b.png | head -1`), as a shell tool does,
/// instead of with a panic: Rust ignores SIGPIPE, so `print!` to a closed
/// pipe panics with "failed printing to stdout: Broken pipe".
fn exit_quietly_on_closed_stdout() {
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let payload = info.payload();
        let message = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied())
            .unwrap_or("");
        if message.starts_with("failed printing to stdout") && message.contains("Broken pipe") {
            std::process::exit(BROKEN_PIPE_STATUS);
        }
        default_hook(info);
    }));
}

fn main() -> ExitCode {
    exit_quietly_on_closed_stdout();
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Render(args) => run_render(args),
        Command::Compare(args) => host_sim::compare::run_compare(args),
        Command::Stats(args) => load_scene(&args.scene, args.width, args.height)
            .and_then(|desc| host_sim::complexity::run_stats(args, desc)),
        Command::Sweep(args) => load_scene(&args.scene, args.width, args.height)
            .and_then(|desc| host_sim::sweep::run_sweep_command(args, desc)),
        Command::Shading(args) => load_scene(&args.scene, args.width, args.height)
            .and_then(|desc| host_sim::shading_compare::run_shading(args, desc)),
        Command::Fit(args) => load_scene(&args.scene, Some(args.width), Some(args.height))
            .and_then(|desc| host_sim::fit::run_fit(args, desc).map(|_| ())),
        Command::Bounded(args) => host_sim::bounded::run_bounded(args),
        Command::Tune(args) => host_sim::tune::run_tune(args).map(|_| ()),
        Command::ZbufferTable(args) => load_scene(&args.scene, Some(args.width), Some(args.height))
            .and_then(|desc| host_sim::zbuffer_table::run_zbuffer_table(args, desc)),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
