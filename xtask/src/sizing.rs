//! Choosing buffer parameters with the firmware in the loop: `cargo xtask
//! fit-link` (the analytic budget of `host-sim fit`, then what the linker
//! placed) and `cargo xtask tune` (the search of `host-sim tune`, then the
//! winner's instructions per frame on the Cortex-M4 under QEMU).

use crate::firmware::{build_m4, run_m4, FirmwareConfig};
use crate::run::scratch_dir;
use host_sim::fit::{print_link_report, run_fit, FitArgs};
use host_sim::tune::{method_name, run_tune, TuneArgs};
use mcu_abuffer::memory::defaults;
use std::time::Duration;

/// Runs `cargo xtask fit-link`.
pub fn fit_link(args: &FitArgs) -> Result<(), String> {
    let desc = host_sim::load_scene(&args.scene, Some(args.width), Some(args.height))?;
    let analytic = run_fit(args, desc)?;
    let config = FirmwareConfig {
        scene: args.scene.clone(),
        frames: 1,
        method: "shared".into(),
        grid: args.grid.name().into(),
        band: args.band,
        main: args.main,
        extra: args.extra,
        pool: args.pool,
        fixed: args.fixed.unwrap_or(args.main + args.extra),
    };
    if args.width != 240 || args.height != 240 || args.ram != 128 * 1024 {
        println!("note: the firmware is the default board (240x240 in 128 KiB); width, height and ram here do not change it");
    }
    let dir = scratch_dir("fit-link")?;
    let elf = dir.path().join("firmware.elf");
    match build_m4(&config, &[], &elf) {
        Ok(()) => print_link_report(&elf, &analytic),
        Err(e) => {
            println!("linker: the firmware build refused these parameters:\n{e}");
            Ok(())
        }
    }
}

/// Runs `cargo xtask tune`.
pub fn tune(args: &TuneArgs) -> Result<(), String> {
    let Some(best) = run_tune(args)? else {
        return Ok(());
    };
    let config = FirmwareConfig {
        scene: args.scene.clone(),
        frames: args.frames.max(1),
        method: method_name(best.method).into(),
        grid: "4x4".into(),
        band: best.band,
        main: best.main,
        extra: best.extra,
        pool: best.pool,
        fixed: defaults::FIXED_SLOTS,
    };
    let dir = scratch_dir("tune")?;
    let elf = dir.path().join("firmware.elf");
    build_m4(&config, &[], &elf)?;
    let run = run_m4(&elf, dir.path(), Duration::from_secs(600))?;
    let mut counts: Vec<u64> = run.stats.iter().map(|s| s.instructions).collect();
    counts.sort_unstable();
    println!(
        "Cortex-M4 under QEMU: median {:.2} M instructions per frame over {} frames",
        counts.get(counts.len() / 2).copied().unwrap_or(0) as f64 / 1e6,
        counts.len()
    );
    Ok(())
}
