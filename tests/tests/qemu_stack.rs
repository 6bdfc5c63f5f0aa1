//! The M4 firmware under QEMU on the extreme scene (`tests/data/extreme.toml`: the
//! camera inside a closed box, depth complexity 1,000, triangles a million pixels
//! wide, slivers and degenerate triangles, a plane through the near plane, every
//! shading mode), at 64 x 64 pixels so a frame takes seconds:
//!
//! - the frames equal host-sim's, bit for bit, and so do the statistics;
//! - the stack's high-water mark (the firmware paints the stack at reset and
//!   reports the mark after every frame) is below the stack the linker reserved
//!   (`_stack_end` up to `_stack_start`, read from the ELF) with a quarter of the
//!   mark to spare, and at least 1 KiB below the reserve the build script keeps
//!   free in any configuration it accepts (`FIRMWARE_STACK_RESERVE`, 10 KiB by
//!   default). The mark was 6,684 bytes here (6,924 at 240 pixels, where the
//!   output line on the stack is longer); docs/robustness.md has the figures.
//!
//! Needs `qemu-system-arm` and the `thumbv7em-none-eabihf` target (the test
//! command installs both).

use host_sim::convert::to_fixed;
use host_sim::render::{render, RenderConfig};
use host_sim::scene_file::load_scene_file;
use std::time::Duration;
use xtask::firmware::{
    build_firmware_bin, build_m4, repo_root, run_m4, FirmwareConfig, FirmwareTarget,
};

/// The stack the build script keeps free by default (`FIRMWARE_STACK_RESERVE`).
const BUILD_STACK_RESERVE: u64 = mcu_abuffer::memory::defaults::STACK_RESERVE_BYTES as u64;

/// The value of symbol `name` in a 32-bit little-endian ELF file.
fn elf_symbol(elf: &[u8], name: &str) -> Option<u32> {
    let u16_at = |o: usize| u16::from_le_bytes([elf[o], elf[o + 1]]) as usize;
    let u32_at = |o: usize| u32::from_le_bytes([elf[o], elf[o + 1], elf[o + 2], elf[o + 3]]);
    if elf.get(..6)? != b"\x7fELF\x01\x01" {
        return None;
    }
    let (shoff, shentsize, shnum) = (u32_at(0x20) as usize, u16_at(0x2E), u16_at(0x30));
    let section = |i: usize| shoff + i * shentsize;
    for i in 0..shnum {
        let sh = section(i);
        if u32_at(sh + 4) != 2 {
            continue; // not SHT_SYMTAB
        }
        let (offset, size, entsize) = (
            u32_at(sh + 16) as usize,
            u32_at(sh + 20) as usize,
            u32_at(sh + 36) as usize,
        );
        let strtab = u32_at(section(u32_at(sh + 24) as usize) + 16) as usize;
        for sym in (offset..offset + size).step_by(entsize.max(16)) {
            let start = strtab + u32_at(sym) as usize;
            let end = start + elf[start..].iter().position(|&b| b == 0)?;
            if &elf[start..end] == name.as_bytes() {
                return Some(u32_at(sym + 4));
            }
        }
    }
    None
}

#[test]
fn extreme_scene_on_the_m4_matches_the_host_and_its_stack_fits() {
    if !system_tests::firmware_tools_present(
        "extreme_scene_on_the_m4_matches_the_host_and_its_stack_fits",
        "thumbv7em-none-eabihf",
        true,
    ) {
        return;
    }
    // The scene file asks for 64 x 64; the build script takes the size from these.
    std::env::set_var("FIRMWARE_WIDTH", "64");
    std::env::set_var("FIRMWARE_HEIGHT", "64");
    let config = FirmwareConfig {
        scene: "tests/data/extreme.toml".into(),
        frames: 2,
        ..FirmwareConfig::for_method("shared")
    };
    let dir = system_tests::scratch_dir("qemu-extreme");
    let elf = dir.join("firmware.elf");
    build_m4(&config, &[], &elf).unwrap_or_else(|e| panic!("firmware build failed: {e}"));
    let run = run_m4(&elf, &dir, Duration::from_secs(900))
        .unwrap_or_else(|e| panic!("QEMU run failed: {e}"));
    assert_eq!(run.frames.len(), 2);

    // Parity with the host.
    let desc = load_scene_file(&repo_root().join(&config.scene)).unwrap();
    let scene = to_fixed(&desc).unwrap();
    assert_eq!((scene.width, scene.height), (64, 64));
    let host_config = RenderConfig {
        main: config.main,
        extra: config.extra,
        pool: Some(config.pool),
        band: config.band,
        ..RenderConfig::default()
    };
    for (i, frame) in run.frames.iter().enumerate() {
        let host = render(&scene, &host_config, config.frame_angle(i as u32)).unwrap();
        assert!(host.rgb == *frame, "frame {i}: QEMU and host-sim differ");
        let (s, b) = (&run.stats[i], &host.stats.buffer);
        assert_eq!(
            (s.generated, s.stored, s.merges, s.pool_peak),
            (
                u64::from(b.fragments_generated),
                u64::from(b.fragments_stored),
                u64::from(b.merges),
                u64::from(b.pool_peak)
            ),
            "frame {i}: statistics differ"
        );
    }
    // Depth complexity 1,000: the first frame's A-buffer takes fragments from
    // far more layers than one (it skips triangles it already hides in a band).
    assert!(
        run.stats[0].generated > 10 * 64 * 64,
        "depth complexity 1,000"
    );

    // The stack.
    let bytes = std::fs::read(&elf).unwrap();
    let start = elf_symbol(&bytes, "_stack_start").expect("_stack_start") as u64;
    let end = elf_symbol(&bytes, "_stack_end").expect("_stack_end") as u64;
    let reserved = start - end;
    let peaks: Vec<u64> = run.stats.iter().map(|s| s.stack_peak).collect();
    assert!(peaks.windows(2).all(|w| w[0] <= w[1]), "{peaks:?}");
    let peak = *peaks.last().unwrap();
    println!("stack: high-water mark {peak} bytes, {reserved} reserved by the linker, {BUILD_STACK_RESERVE} kept free by the build");
    assert!(peak > 0 && peak < reserved, "{peak} of {reserved}");
    assert!(
        peak + peak / 4 <= reserved,
        "stack high-water mark {peak} bytes leaves less than a quarter spare in the {reserved} bytes the linker reserved"
    );
    assert!(
        peak + 1024 <= BUILD_STACK_RESERVE,
        "stack high-water mark {peak} bytes is within 1 KiB of the {BUILD_STACK_RESERVE}-byte reserve the build keeps free"
    );
}

/// flip-link places the stack below the statics, so a stack overflow faults
/// instead of overwriting the fragment pool: the M4 firmware's layout has the
/// stack at the start of RAM with the lowest static (`STATICS_CANARY`) right
/// above it, and a firmware that recurses without end (`qemu-stack-overflow`,
/// with the renderer's static buffers lent out) ends in the hard-fault handler,
/// which finds the stack pointer below the stack and the canary unchanged.
#[test]
fn a_stack_overflow_faults_and_leaves_the_statics_intact() {
    if !system_tests::firmware_tools_present(
        "a_stack_overflow_faults_and_leaves_the_statics_intact",
        "thumbv7em-none-eabihf",
        true,
    ) {
        return;
    }
    let dir = system_tests::scratch_dir("qemu-overflow");
    let elf = dir.join("firmware.elf");
    build_firmware_bin(
        FirmwareTarget::M4,
        "qemu-stack-overflow",
        &FirmwareConfig::default(),
        &[],
        &elf,
    )
    .unwrap_or_else(|e| panic!("firmware build failed: {e}"));

    // The layout: RAM starts at 0x2000_0000 (firmware/qemu/memory/mps2-an386.x).
    let bytes = std::fs::read(&elf).unwrap();
    let start = elf_symbol(&bytes, "_stack_start").expect("_stack_start");
    let end = elf_symbol(&bytes, "_stack_end").expect("_stack_end");
    let canary = elf_symbol(&bytes, "STATICS_CANARY").expect("STATICS_CANARY");
    assert_eq!(
        end, 0x2000_0000,
        "the stack does not start at the RAM's start"
    );
    assert!(start > end, "empty stack");
    assert_eq!(
        canary, start,
        "the lowest static is not right above the stack"
    );

    let error = match run_m4(&elf, &dir, Duration::from_secs(120)) {
        Ok(_) => panic!("the runaway recursion ended without a fault"),
        Err(e) => e,
    };
    assert!(
        error.contains("hard fault: stack overflow") && error.contains("statics intact"),
        "{error}"
    );
}
