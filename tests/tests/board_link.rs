//! The STM32F411 board firmware (`firmware/blackpill`) builds for
//! `thumbv7em-none-eabihf` and links within the F411CE's 512 KiB of flash and
//! 128 KiB of RAM, with the stack the build reserves; a configuration that does not
//! fit stops the build with the overshoot. (Running it needs the board; the display
//! path it uses is tested in `board_display.rs`.)

use host_sim::fit::read_link_report;
use mcu_abuffer::memory::defaults::STACK_RESERVE_BYTES;
use xtask::firmware::build_board;

const FLASH: u64 = 512 * 1024;
const RAM: u64 = 128 * 1024;
const STACK_RESERVE: u64 = STACK_RESERVE_BYTES as u64;

fn scratch(name: &str) -> system_tests::ScratchDir {
    system_tests::scratch_dir(&format!("board-{name}"))
}

#[test]
fn board_firmware_links_within_the_f411() {
    if !system_tests::firmware_tools_present(
        "board_firmware_links_within_the_f411",
        "thumbv7em-none-eabihf",
        false,
    ) {
        return;
    }
    let dir = scratch("default");
    let elf = dir.join("blackpill-st7789.elf");
    build_board(&[], &elf).unwrap_or_else(|e| panic!("board build failed: {e}"));
    let link = read_link_report(&elf).unwrap();
    let statics = link.data + link.bss + link.uninit;
    println!(
        "flash {} of {FLASH}; RAM statics {statics} (.data {} .bss {} .uninit {}), stack {} of {}",
        link.flash, link.data, link.bss, link.uninit, link.stack, link.ram
    );
    // The layout is the top-level memory.x: 128 KiB of RAM from 0x2000_0000.
    assert_eq!(link.ram, RAM, "not linked with the F411's memory.x");
    assert!(link.flash > 100 * 1024, "the scenes are missing from flash");
    assert!(link.flash <= FLASH, "flash {} exceeds {FLASH}", link.flash);
    assert!(
        statics + STACK_RESERVE <= RAM,
        "statics {statics} leave less than 10 KiB of stack"
    );
    assert!(link.stack >= STACK_RESERVE);
    // The renderer's memory starts as zeros (`.bss`): a non-zero initial value
    // in one of its types would move the whole static to `.data`, whose image
    // takes as much flash again.
    assert!(
        link.data < 4096,
        ".data {} bytes: a renderer static has a non-zero initial value",
        link.data
    );

    // The renderer's statics hold what the library's byte counts (and so the
    // build script's RAM check) say: the board's default sizes, the largest of
    // its scenes.
    use abuffer_panel::demo::defaults;
    use mcu_abuffer::memory::bytes;
    let (width, height) = (defaults::WIDTH as usize, defaults::HEIGHT as usize);
    let fragments = bytes::fragment_memory(
        2,
        width,
        defaults::BAND_ROWS as usize,
        defaults::MAIN_SLOTS as usize,
        defaults::EXTRA_ADDRESSES as usize,
        defaults::POOL_SLOTS,
    );
    let scenes: Vec<_> = defaults::SCENES
        .iter()
        .map(|name| host_sim::builtins::builtin_scene(name, width as u32, height as u32).unwrap())
        .collect();
    let most = |count: fn(&host_sim::scene_desc::SceneDesc) -> usize| {
        scenes.iter().map(count).max().unwrap()
    };
    let workspace = bytes::workspace_memory(
        height,
        most(|d| d.objects.len()),
        most(|d| d.objects.iter().map(|o| o.mesh.positions.len()).sum()),
        most(|d| d.objects.iter().map(|o| o.mesh.triangles.len()).sum()),
        defaults::CARRIED_COLORS,
    );
    let r = link.renderer;
    println!("renderer statics: fragment memory {fragments}, workspace {workspace} bytes");
    assert!(
        host_sim::fit::cell_holds(r.fragments, fragments),
        "fragment memory linked {} bytes, counted {fragments}",
        r.fragments
    );
    assert!(
        host_sim::fit::cell_holds(r.workspace, workspace),
        "workspace linked {} bytes, counted {workspace}",
        r.workspace
    );
}

#[test]
fn an_oversized_board_configuration_names_the_overshoot() {
    if !system_tests::firmware_tools_present(
        "an_oversized_board_configuration_names_the_overshoot",
        "thumbv7em-none-eabihf",
        false,
    ) {
        return;
    }
    let dir = scratch("oversized");
    let elf = dir.join("blackpill-st7789.elf");
    let err = build_board(&[("BOARD_POOL", "4000".to_string())], &elf).unwrap_err();
    assert!(
        err.contains("does not fit 131072 bytes by"),
        "unexpected error: {err}"
    );
}
