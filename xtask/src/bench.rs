//! `cargo xtask qemu-bench`: instructions per frame on the Cortex-M4 (QEMU
//! `mps2-an386`, `-icount shift=0`) for each method, from the firmware's own
//! SysTick counts.

use crate::firmware::{build_m4, build_m4_with_debug_info, decode_defmt, run_m4, FirmwareConfig};
use mcu_abuffer::memory::defaults;
use std::fmt::Write as _;
use std::time::Duration;

/// Arguments of `cargo xtask qemu-bench`.
#[derive(clap::Args, Debug)]
pub struct BenchArgs {
    /// Built-in scenes or scene files (comma-separated).
    #[arg(
        long,
        default_value = "teapot,spheres,starfighter",
        value_delimiter = ','
    )]
    pub scene: Vec<String>,
    /// Turntable frames per run.
    #[arg(long, default_value_t = 8)]
    pub frames: u32,
    /// Methods (comma-separated): zbuffer, shared, fixed-discard, fixed-merge, merge-closest, unlimited.
    #[arg(
        long,
        default_value = "zbuffer,shared,fixed-discard,unlimited",
        value_delimiter = ','
    )]
    pub methods: Vec<String>,
    /// `N_fixed` for the fixed methods.
    #[arg(long, default_value_t = defaults::FIXED_SLOTS)]
    pub fixed: u8,
    /// Rows per band (default: the method's, `memory::defaults::band_rows`).
    #[arg(long)]
    pub band: Option<u16>,
    /// Shared pool slots per band (shared and merge-closest).
    #[arg(long, default_value_t = defaults::POOL_SLOTS)]
    pub pool: usize,
    /// Also print the per-stage profile of each run (a separate, instrumented build).
    #[arg(long)]
    pub profile: bool,
    /// Write the table as Markdown to this file too.
    #[arg(long)]
    pub markdown: Option<std::path::PathBuf>,
}

fn median(mut v: Vec<u64>) -> u64 {
    v.sort_unstable();
    v.get(v.len() / 2).copied().unwrap_or(0)
}

/// Runs the benchmark and prints a table.
pub fn run_bench(args: &BenchArgs) -> Result<(), String> {
    let dir = crate::run::scratch_dir("bench")?;
    let mut table = String::new();
    writeln!(table, "| scene | method | median instructions/frame | min | max | of which output | fragments | merges | pool peak |").unwrap();
    writeln!(table, "|---|---|---|---|---|---|---|---|---|").unwrap();
    for scene in &args.scene {
        for method in &args.methods {
            let defaults = FirmwareConfig::for_method(method);
            let config = FirmwareConfig {
                scene: scene.clone(),
                frames: args.frames,
                fixed: args.fixed,
                band: args.band.unwrap_or(defaults.band),
                pool: args.pool,
                ..defaults
            };
            let work = dir.join(format!("{}-{method}", scene.replace(['/', ':', '.'], "_")));
            std::fs::create_dir_all(&work).map_err(|e| e.to_string())?;
            let elf = work.join("firmware.elf");
            if let Err(e) = build_m4(&config, &[], &elf) {
                // Memory that does not fit is a result of the table; any other
                // build failure (a missing tool, a compile error) stops the bench.
                let Some(reason) = e.lines().find(|l| l.contains("does not fit")) else {
                    return Err(format!(
                        "{scene} {method}: the firmware did not build:\n{e}"
                    ));
                };
                writeln!(table, "| {scene} | {method} | does not fit | | | | | | |").unwrap();
                eprintln!("{scene} {method}: {}", reason.trim());
                continue;
            }
            let run = run_m4(&elf, &work, Duration::from_secs(600))?;
            let instr: Vec<u64> = run.stats.iter().map(|s| s.instructions).collect();
            let out: Vec<u64> = run.stats.iter().map(|s| s.output_instructions).collect();
            let frags: Vec<u64> = run.stats.iter().map(|s| s.generated).collect();
            let merges: Vec<u64> = run.stats.iter().map(|s| s.merges).collect();
            let peak = run.stats.iter().map(|s| s.pool_peak).max().unwrap_or(0);
            writeln!(
                table,
                "| {scene} | {method} | {:.2} M | {:.2} M | {:.2} M | {:.2} M | {} | {} | {peak} |",
                median(instr.clone()) as f64 / 1e6,
                instr.iter().min().copied().unwrap_or(0) as f64 / 1e6,
                instr.iter().max().copied().unwrap_or(0) as f64 / 1e6,
                median(out) as f64 / 1e6,
                median(frags),
                median(merges),
            )
            .unwrap();
            if args.profile {
                let pelf = work.join("firmware-profile.elf");
                build_m4(&config, &["profile"], &pelf)?;
                let prun = run_m4(&pelf, &work.join("profile"), Duration::from_secs(600))?;
                if let Some(text) = decode_defmt(&pelf, &prun.defmt) {
                    for line in text.lines().filter(|l| l.contains("profile frame")) {
                        eprintln!("{scene} {method}: {}", line.trim());
                    }
                } else {
                    eprintln!(
                        "(install defmt-print to see the profile: cargo install defmt-print)"
                    );
                }
            }
        }
    }
    print!("{table}");
    if let Some(path) = &args.markdown {
        std::fs::write(path, &table).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}

/// `cargo xtask profile`: exact instructions per function and per source file
/// of one frame (frame 0 of the turntable) on the Cortex-M4 under QEMU, for
/// the teapot with `shared`, `zbuffer` and `split-bands` in the default M4
/// configuration: builds the QEMU firmware for one frame and runs
/// `scripts/qemu-profile.py` on it (by innermost inlined function, by source
/// file, by function symbol with its inlined callees, and by kind of
/// instruction, with the share of stack loads and stores per symbol). Writes
/// `docs/m4-profile/teapot-<method>.txt`. Needs qemu-system-arm, python3 and
/// llvm-symbolizer (Debian's llvm package); about a minute per method.
pub fn profile() -> Result<(), String> {
    use crate::run::{create_dir, output, program, repo_root, scratch_dir};
    let out_dir = repo_root().join("docs/m4-profile");
    create_dir(&out_dir)?;
    let scratch = scratch_dir("profile")?;
    for method in ["shared", "zbuffer", "split-bands"] {
        let config = FirmwareConfig {
            frames: 1,
            ..FirmwareConfig::for_method(method)
        };
        let elf = scratch.path().join(format!("{method}.elf"));
        build_m4_with_debug_info(&config, &elf)?;
        let listing = output(
            program("python3")
                .arg("scripts/qemu-profile.py")
                .arg(&elf)
                .args(["--top", "40", "--files", "--outer", "--mix"]),
        )?;
        let path = out_dir.join(format!("teapot-{method}.txt"));
        std::fs::write(&path, listing).map_err(|e| format!("{}: {e}", path.display()))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
