//! The SPI display path end to end: the Cortex-M3 firmware streams its frame line by
//! line over QEMU's PL022 to the emulated SSD0323 OLED, and what the display shows
//! (a QMP screendump) is exactly host-sim's rendering of the same scene, quantized
//! to 4-bit gray the same way.
//!
//! Needs `qemu-system-arm` and the `thumbv7m-none-eabi` target (the README's test
//! command installs both).

use embedded_graphics_core::pixelcolor::Rgb888;
use host_sim::builtins::builtin_scene;
use host_sim::convert::to_fixed;
use host_sim::render::{render, Method, RenderConfig};
use mcu_abuffer::sink::gray4;
use std::time::Duration;
use xtask::firmware::{build_firmware, run_oled_screendump, FirmwareConfig, FirmwareTarget};

#[test]
fn oled_shows_the_host_rendering_in_4_bit_gray() {
    if !system_tests::firmware_tools_present(
        "oled_shows_the_host_rendering_in_4_bit_gray",
        "thumbv7m-none-eabi",
        true,
    ) {
        return;
    }
    let dir = system_tests::scratch_dir("oled");
    let config = FirmwareConfig {
        scene: "teapot:4".into(),
        frames: 1,
        ..FirmwareConfig::for_method("shared")
    };
    let elf = dir.join("oled.elf");
    build_firmware(FirmwareTarget::Oled, &config, &[], &elf)
        .unwrap_or_else(|e| panic!("OLED firmware build failed: {e}"));
    let shown = run_oled_screendump(&elf, &dir, Duration::from_secs(300))
        .unwrap_or_else(|e| panic!("OLED run failed: {e}"));
    assert_eq!(shown.len(), 128 * 64);

    let scene = to_fixed(&builtin_scene("teapot:4", 128, 64).unwrap()).unwrap();
    let host_config = RenderConfig {
        method: Method::Shared,
        main: config.main,
        extra: config.extra,
        pool: Some(config.pool),
        band: config.band,
        ..RenderConfig::default()
    };
    let host = render(&scene, &host_config, 0.0).unwrap();
    let expected: Vec<u8> = host
        .rgb
        .chunks_exact(3)
        .map(|p| gray4(Rgb888::new(p[0], p[1], p[2])))
        .collect();
    let differing = expected.iter().zip(&shown).filter(|(a, b)| a != b).count();
    assert_eq!(
        differing, 0,
        "{differing} of 8192 OLED pixels differ from host-sim"
    );
    // Not a blank screen: the teapot covers a good part of it, in several gray levels.
    let background = expected[0];
    assert!(shown.iter().filter(|&&l| l != background).count() > 1500);
    let mut levels = shown.clone();
    levels.sort_unstable();
    levels.dedup();
    assert!(levels.len() >= 8, "only {} gray levels shown", levels.len());
}
