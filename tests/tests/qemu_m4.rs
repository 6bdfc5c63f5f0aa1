//! The firmware under QEMU (`mps2-an386`, Cortex-M4F): the frames it draws are the
//! host simulator's, bit for bit; instruction counts are deterministic and within
//! bounds; parameters that do not fit the board stop the build with a clear message.
//!
//! Needs `qemu-system-arm` and the `thumbv7em-none-eabihf` target (the README's test
//! command installs both).

use host_sim::builtins::builtin_scene;
use host_sim::convert::to_fixed;
use host_sim::render::{render, Grid, Method, RenderConfig};
use std::time::Duration;
use system_tests::ScratchDir;
use xtask::firmware::{build_m4, run_m4, FirmwareConfig, FirmwareRun};

/// Upper bounds on instructions per frame (teapot, default M4 configuration),
/// set from the largest frame these tests draw, 20.12 M (`shared`, 3-frame
/// turntable), 9.80 M (`zbuffer`, 3 frames) and 20.09 M (`split-bands`, 2
/// frames), plus 2.0 to 2.4 % (`docs/m4-benchmark.md`, "Now"): a change that makes
/// frames slower fails here. Counts are deterministic (`-icount shift=0`), so
/// the margin is for intended changes and code placement only. The builds leave
/// out the debug information, which changes the code slightly
/// (`xtask::firmware::DebugInfo`).
const TEAPOT_SHARED_MAX_INSTRUCTIONS: u64 = 20_600_000;
const TEAPOT_ZBUFFER_MAX_INSTRUCTIONS: u64 = 10_000_000;
/// See [`TEAPOT_SHARED_MAX_INSTRUCTIONS`].
const TEAPOT_SPLIT_BANDS_MAX_INSTRUCTIONS: u64 = 20_500_000;

fn workdir(name: &str) -> ScratchDir {
    system_tests::scratch_dir(&format!("qemu-{name}"))
}

/// A firmware built into a scratch folder of its own.
struct BuiltFirmware {
    name: String,
    dir: ScratchDir,
    elf: std::path::PathBuf,
}

impl BuiltFirmware {
    fn build(name: &str, config: &FirmwareConfig) -> Self {
        let dir = workdir(name);
        let elf = dir.join("firmware.elf");
        build_m4(config, &[], &elf)
            .unwrap_or_else(|e| panic!("firmware build for {name} failed: {e}"));
        Self {
            name: name.into(),
            dir,
            elf,
        }
    }

    fn run(&self) -> FirmwareRun {
        run_m4(&self.elf, &self.dir, Duration::from_secs(300))
            .unwrap_or_else(|e| panic!("QEMU run for {} failed: {e}", self.name))
    }
}

fn host_config(config: &FirmwareConfig) -> RenderConfig {
    let method = match config.method.as_str() {
        "shared" => Method::Shared,
        "zbuffer" => Method::Zbuffer,
        "fixed-discard" => Method::FixedDiscard,
        "fixed-merge" => Method::FixedMerge,
        "merge-closest" => Method::MergeClosest,
        "split-bands" => Method::SplitBands,
        "unlimited" => Method::Unlimited,
        other => panic!("unknown method {other}"),
    };
    let grid = match config.grid.as_str() {
        "8x4" => Grid::G8x4,
        "8x8" => Grid::G8x8,
        _ => Grid::G4x4,
    };
    RenderConfig {
        method,
        grid,
        main: config.main,
        extra: config.extra,
        pool: Some(config.pool),
        fixed: config.fixed,
        band: config.band,
        ..RenderConfig::default()
    }
}

/// Builds and runs the firmware for `config`, renders every frame on the host
/// and compares with the firmware's.
fn assert_parity(name: &str, config: &FirmwareConfig) -> (BuiltFirmware, FirmwareRun) {
    let firmware = BuiltFirmware::build(name, config);
    let run = firmware.run();
    assert_eq!(
        run.frames.len(),
        config.frames as usize,
        "{name}: frame count"
    );
    let scene = to_fixed(&builtin_scene(&config.scene, 240, 240).unwrap()).unwrap();
    for (i, frame) in run.frames.iter().enumerate() {
        let host = render(&scene, &host_config(config), config.frame_angle(i as u32)).unwrap();
        let differing = host
            .rgb
            .chunks_exact(3)
            .zip(frame.chunks_exact(3))
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(
            differing, 0,
            "{name} frame {i}: {differing} pixels differ between QEMU and host-sim"
        );
        let s = &run.stats[i];
        let b = &host.stats.buffer;
        assert_eq!(
            (s.generated, s.stored, s.merges, s.discarded, s.pool_peak),
            (
                u64::from(b.fragments_generated),
                u64::from(b.fragments_stored),
                u64::from(b.merges),
                u64::from(b.fragments_discarded),
                u64::from(b.pool_peak)
            ),
            "{name} frame {i}: statistics differ"
        );
    }
    (firmware, run)
}

#[test]
fn firmware_frames_equal_host_frames_and_counts_are_deterministic() {
    if !system_tests::firmware_tools_present(
        "firmware_frames_equal_host_frames_and_counts_are_deterministic",
        "thumbv7em-none-eabihf",
        true,
    ) {
        return;
    }
    for scene in ["teapot", "spheres", "starfighter"] {
        let config = FirmwareConfig {
            scene: scene.into(),
            frames: 3,
            ..FirmwareConfig::for_method("shared")
        };
        let (firmware, run) = assert_parity(scene, &config);
        for s in &run.stats {
            assert!(s.instructions > 0 && s.output_instructions < s.instructions);
        }
        if scene == "teapot" {
            for s in &run.stats {
                assert!(
                    s.instructions <= TEAPOT_SHARED_MAX_INSTRUCTIONS,
                    "teapot frame {}: {} instructions, bound {TEAPOT_SHARED_MAX_INSTRUCTIONS}",
                    s.frame,
                    s.instructions
                );
            }
            // The same binary twice: the same instruction counts, to the tick.
            let again = firmware.run();
            let counts =
                |r: &FirmwareRun| r.stats.iter().map(|s| s.instructions).collect::<Vec<_>>();
            assert_eq!(counts(&run), counts(&again));
        }
    }
    let zbuffer = FirmwareConfig {
        frames: 3,
        ..FirmwareConfig::for_method("zbuffer")
    };
    let (_, run) = assert_parity("teapot-zbuffer", &zbuffer);
    for s in &run.stats {
        assert!(
            s.instructions <= TEAPOT_ZBUFFER_MAX_INSTRUCTIONS,
            "teapot z-buffer frame {}: {} instructions, bound {TEAPOT_ZBUFFER_MAX_INSTRUCTIONS}",
            s.frame,
            s.instructions
        );
    }
}

#[test]
fn split_bands_on_the_device_looks_like_unlimited() {
    if !system_tests::firmware_tools_present(
        "split_bands_on_the_device_looks_like_unlimited",
        "thumbv7em-none-eabihf",
        true,
    ) {
        return;
    }
    // The two-sided teapot in the default M4 memory: the device's frames are
    // the host's, and within the bounded-memory thresholds of `unlimited`
    // (NMSE 1e-4, at most 0.02 % of pixels off by more than 24 levels).
    let config = FirmwareConfig {
        method: "split-bands".into(),
        frames: 2,
        ..FirmwareConfig::default()
    };
    let (_, run) = assert_parity("teapot-split-bands", &config);
    let scene = to_fixed(&builtin_scene(&config.scene, 240, 240).unwrap()).unwrap();
    let unlimited = RenderConfig {
        method: Method::Unlimited,
        band: config.band,
        ..RenderConfig::default()
    };
    for (i, frame) in run.frames.iter().enumerate() {
        let reference = render(&scene, &unlimited, config.frame_angle(i as u32)).unwrap();
        let error = host_sim::compare::nmse(frame, &reference.rgb);
        assert!(
            error <= 1e-4,
            "frame {i}: NMSE {error:.2e} against unlimited"
        );
        let speckles = frame
            .chunks_exact(3)
            .zip(reference.rgb.chunks_exact(3))
            .filter(|(a, b)| (0..3).any(|c| (a[c] as i32 - b[c] as i32).abs() > 24))
            .count();
        assert!(
            speckles * 5000 <= 240 * 240,
            "frame {i}: {speckles} pixels off by more than 24 levels"
        );
        let s = &run.stats[i];
        assert!(
            s.instructions <= TEAPOT_SPLIT_BANDS_MAX_INSTRUCTIONS,
            "teapot split-bands frame {}: {} instructions, bound {TEAPOT_SPLIT_BANDS_MAX_INSTRUCTIONS}",
            s.frame,
            s.instructions
        );
    }
}

#[test]
fn parameters_that_do_not_fit_stop_the_build_with_the_overshoot() {
    if !system_tests::firmware_tools_present(
        "parameters_that_do_not_fit_stop_the_build_with_the_overshoot",
        "thumbv7em-none-eabihf",
        true,
    ) {
        return;
    }
    let config = FirmwareConfig {
        pool: 9000,
        frames: 1,
        ..FirmwareConfig::default()
    };
    let dir = workdir("too-big");
    let err = build_m4(&config, &[], &dir.join("firmware.elf")).unwrap_err();
    assert!(
        err.contains("does not fit") && err.contains("by ") && err.contains("pool 9000"),
        "{err}"
    );
}

/// `host-sim fit`'s count of the renderer's memory is what the firmware links:
/// the fragment memory and the workspace statics of the default M4 build
/// (teapot) hold exactly the bytes the library's run-time byte counts give.
#[test]
fn the_linked_renderer_memory_is_the_counted_one() {
    if !system_tests::firmware_tools_present(
        "the_linked_renderer_memory_is_the_counted_one",
        "thumbv7em-none-eabihf",
        false,
    ) {
        return;
    }
    use host_sim::fit::{budget, cell_holds, read_link_report, workspace_bytes, FitArgs};
    use mcu_abuffer::memory::{bytes, defaults};
    let config = FirmwareConfig {
        frames: 1,
        ..FirmwareConfig::default()
    };
    let dir = workdir("linked-memory");
    let elf = dir.join("firmware.elf");
    build_m4(&config, &[], &elf).unwrap_or_else(|e| panic!("firmware build failed: {e}"));
    let linked = read_link_report(&elf).unwrap().renderer;
    let mut desc = builtin_scene(&config.scene, 240, 240).unwrap();
    desc.width = 240;
    desc.height = 240;
    let fragments = bytes::fragment_memory(
        2,
        240,
        config.band as usize,
        config.main as usize,
        config.extra as usize,
        config.pool,
    );
    let workspace = workspace_bytes(&desc, defaults::CARRIED_COLORS);
    assert!(
        cell_holds(linked.fragments, fragments),
        "fragment memory linked {} bytes, counted {fragments}",
        linked.fragments
    );
    assert!(
        cell_holds(linked.workspace, workspace),
        "workspace linked {} bytes, counted {workspace}",
        linked.workspace
    );
    // `fit`'s budget is made of the same counts.
    let args = FitArgs {
        scene: config.scene.clone(),
        width: 240,
        height: 240,
        band: config.band,
        grid: Grid::G4x4,
        main: config.main,
        extra: config.extra,
        pool: config.pool,
        fixed: None,
        ram: 128 * 1024,
        stack: defaults::STACK_RESERVE_BYTES,
        carried: defaults::CARRIED_COLORS,
        frames: None,
    };
    let b = budget(&args, &desc, 1, 2, config.pool);
    assert_eq!(b.counts + b.main_slots + b.addresses + b.pool, fragments);
    assert_eq!(b.workspace, workspace);
}
