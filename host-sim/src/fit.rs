//! `host-sim fit`: does a buffer configuration fit a board's SRAM?
//!
//! Three answers, from cheapest to most certain:
//! - analytic: the real packed sizes of the library's types and SPEC section 5's
//!   formulas, for the shared and the fixed allocation, with the frame workspace the
//!   scene needs, line buffers and a stack reserve;
//! - `--frames N`: renders the scene's turntable on the host and reports the worst
//!   pool peak, and so the smallest pool that never merges;
//! - `cargo xtask fit-link` (the project's tooling): builds the QEMU M4
//!   firmware with these parameters and reads the linker's answer from the ELF
//!   ([`read_link_report`], [`print_link_report`]).

use crate::convert::to_fixed;
use crate::memory::{band_memory, fragment_bytes};
use crate::render::{render, Grid, Method, RenderConfig};
use crate::scene_desc::SceneDesc;
use mcu_abuffer::memory::bytes::{self, FragmentParts, ADDRESS as ADDRESS_BYTES};
use mcu_abuffer::memory::defaults;
use std::path::Path;

/// Arguments of `host-sim fit`.
#[derive(clap::Args, Debug)]
pub struct FitArgs {
    /// Scene whose frame workspace counts too (built-in or scene file).
    #[arg(long, default_value = "teapot")]
    pub scene: String,
    /// Image width.
    #[arg(long, default_value_t = 240)]
    pub width: u32,
    /// Image height.
    #[arg(long, default_value_t = 240)]
    pub height: u32,
    /// Band height R.
    #[arg(long, default_value_t = defaults::BAND_ROWS)]
    pub band: u16,
    /// Coverage grid.
    #[arg(long, value_enum, default_value_t = Grid::G4x4)]
    pub grid: Grid,
    /// N_main.
    #[arg(long, default_value_t = defaults::MAIN_SLOTS)]
    pub main: u8,
    /// N_extra.
    #[arg(long, default_value_t = defaults::EXTRA_ADDRESSES)]
    pub extra: u8,
    /// N_pool.
    #[arg(long, default_value_t = defaults::POOL_SLOTS)]
    pub pool: usize,
    /// N_fixed of the fixed allocation compared against (default N_main + N_extra).
    #[arg(long)]
    pub fixed: Option<u8>,
    /// SRAM of the board, in bytes or with a K suffix (KiB).
    #[arg(long, default_value = "128K", value_parser = parse_bytes)]
    pub ram: usize,
    /// Bytes kept free for the stack (the firmware build scripts' default).
    #[arg(long, default_value_t = defaults::STACK_RESERVE_BYTES)]
    pub stack: usize,
    /// Entries of the carried-colors table in the frame workspace (color
    /// planes kept for the next band; 80 bytes each, 0 for none).
    #[arg(long, default_value_t = defaults::CARRIED_COLORS)]
    pub carried: usize,
    /// Also run a turntable of this many frames on the host: worst pool peak.
    #[arg(long)]
    pub frames: Option<u32>,
}

/// Parses `131072`, `128K` or `128k` (KiB).
pub fn parse_bytes(s: &str) -> Result<usize, String> {
    let t = s.trim();
    let (num, mult) = match t.strip_suffix(['K', 'k']) {
        Some(n) => (n, 1024),
        None => (t, 1),
    };
    num.trim()
        .parse::<usize>()
        .map(|n| n * mult)
        .map_err(|_| format!("'{s}' is not a byte count (like 131072 or 128K)"))
}

/// The byte budget of one configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryBudget {
    /// Per-pixel fragment counts, `W R` bytes.
    pub counts: usize,
    /// Main fragment slots, `W R N_main M_frag`.
    pub main_slots: usize,
    /// Pool addresses, `W R N_extra M_addr`.
    pub addresses: usize,
    /// Shared pool, `N_pool M_frag` (and the padding that aligns the fragment memory).
    pub pool: usize,
    /// The sink's line of RGB bytes.
    pub lines: usize,
    /// Frame workspace: transformed vertices, triangle order, row counts,
    /// objects, the resolved line.
    pub workspace: usize,
    /// Stack reserve.
    pub stack: usize,
}

impl MemoryBudget {
    /// Everything.
    pub fn total(&self) -> usize {
        self.counts
            + self.main_slots
            + self.addresses
            + self.pool
            + self.lines
            + self.workspace
            + self.stack
    }
}

/// The frame workspace a scene needs on a device (`mcu_abuffer::memory::WorkspaceMemory`,
/// the resolved line included), with `carried` entries of carried colors.
pub fn workspace_bytes(desc: &SceneDesc, carried: usize) -> usize {
    let vertices: usize = desc.objects.iter().map(|o| o.mesh.positions.len()).sum();
    let triangles: usize = desc.objects.iter().map(|o| o.mesh.triangles.len()).sum();
    bytes::workspace_memory(
        desc.height as usize,
        desc.objects.len(),
        vertices,
        triangles,
        carried,
    )
}

/// The analytic budget of `args` for `desc`, with `main`/`extra`/`pool` slots.
pub fn budget(
    args: &FitArgs,
    desc: &SceneDesc,
    main: usize,
    extra: usize,
    pool: usize,
) -> MemoryBudget {
    let mask_bytes = fragment_bytes(args.grid) - bytes::fragment(0);
    let parts = FragmentParts::new(
        mask_bytes,
        args.width as usize,
        args.band as usize,
        main,
        extra,
        pool,
    );
    MemoryBudget {
        counts: parts.counts,
        main_slots: parts.main_slots,
        addresses: parts.addresses,
        pool: parts.pool + parts.padding(),
        lines: args.width as usize * 3,
        workspace: workspace_bytes(desc, args.carried),
        stack: args.stack,
    }
}

fn verdict(total: usize, ram: usize) -> String {
    if total <= ram {
        format!("fits ({} bytes free)", ram - total)
    } else {
        format!("does not fit by {} bytes", total - ram)
    }
}

fn print_budget(name: &str, b: &MemoryBudget, ram: usize) {
    println!("{name}");
    println!("  counts            {:>8}", b.counts);
    println!("  main slots        {:>8}", b.main_slots);
    println!("  pool addresses    {:>8}", b.addresses);
    println!("  shared pool       {:>8}", b.pool);
    println!("  line buffers      {:>8}", b.lines);
    println!("  frame workspace   {:>8}", b.workspace);
    println!("  stack reserve     {:>8}", b.stack);
    println!(
        "  total             {:>8} of {ram}: {}",
        b.total(),
        verdict(b.total(), ram)
    );
}

/// Runs `host-sim fit` and returns the shared allocation's budget.
pub fn run_fit(args: &FitArgs, mut desc: SceneDesc) -> Result<MemoryBudget, String> {
    desc.width = args.width;
    desc.height = args.height;
    if args.main == 0 {
        return Err("--main must be at least 1".into());
    }
    if args.band == 0 || args.band as u32 > args.height {
        return Err(format!("--band must be 1..={}", args.height));
    }
    let frag = fragment_bytes(args.grid);
    let fixed = args
        .fixed
        .map(usize::from)
        .unwrap_or(args.main as usize + args.extra as usize);
    let shared = budget(
        args,
        &desc,
        args.main as usize,
        args.extra as usize,
        args.pool,
    );
    let fixed_budget = budget(args, &desc, fixed, 0, 0);
    let pixels = args.width as usize * args.band as usize;
    let shared_memory = band_memory(
        args.width as u16,
        args.band,
        args.grid,
        args.main,
        args.extra,
        args.pool,
    );
    let m_shared = shared_memory.total_bytes;
    let m_fixed =
        band_memory(args.width as u16, args.band, args.grid, fixed as u8, 0, 0).total_bytes;
    println!(
        "{}x{}, band {}, grid {:?} ({frag}-byte fragments, {ADDRESS_BYTES}-byte addresses), scene {}",
        args.width, args.height, args.band, args.grid, args.scene
    );
    println!("M_shared = W R (N_main M_frag + N_extra M_addr) + N_pool M_frag = {m_shared} bytes (N_main {}, N_extra {}, N_pool {})", args.main, args.extra, args.pool);
    println!("M_fixed  = W R N_fixed M_frag = {m_fixed} bytes (N_fixed {fixed})");
    println!(
        "M_fixed / M_shared = {:.3}",
        m_fixed as f64 / m_shared.max(1) as f64
    );
    print_budget("shared allocation", &shared, args.ram);
    print_budget("fixed allocation", &fixed_budget, args.ram);
    println!("verdict: {}", verdict(shared.total(), args.ram));

    if let Some(frames) = args.frames {
        let scene = to_fixed(&desc)?;
        // A pool too large to run out shows the demand: the worst peak.
        let unbounded = pixels * args.extra as usize;
        let config = RenderConfig {
            method: Method::Shared,
            grid: args.grid,
            main: args.main,
            extra: args.extra,
            pool: Some(unbounded),
            band: args.band,
            ..RenderConfig::default()
        };
        let mut worst = 0u32;
        for i in 0..frames.max(1) {
            let angle = 360.0 * i as f32 / frames.max(1) as f32;
            let out = render(&scene, &config, angle)?;
            worst = worst.max(out.stats.buffer.pool_peak);
        }
        println!("turntable of {frames} frames: worst pool peak {worst}; the smallest N_pool that never merges for want of pool slots is {worst}");
    }

    Ok(shared)
}

/// What the linker placed in RAM, read from an ELF.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LinkReport {
    /// `.data` bytes.
    pub data: u64,
    /// `.bss` bytes.
    pub bss: u64,
    /// `.uninit` bytes.
    pub uninit: u64,
    /// RAM from the memory layout (`_ram_end` minus the RAM origin; the linker
    /// script's `_stack_start` where an older cortex-m-rt has no `_ram_end`).
    pub ram: u64,
    /// Stack: `_stack_start - _stack_end`.
    pub stack: u64,
    /// Flash the image takes: vector table, code, read-only data and the
    /// initial values of `.data`.
    pub flash: u64,
    /// The renderer's statics as linked (0 where a firmware has none).
    pub renderer: RendererStatics,
}

/// Sizes of the `static`s that hold the renderer's memory in the firmwares
/// (`FRAGMENTS`, `DEPTHS`, `WORKSPACE`; each a `ConstStaticCell`, so the
/// memory plus a taken flag and padding).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RendererStatics {
    /// The fragment memory (`mcu_abuffer::memory::FragmentMemory`).
    pub fragments: u64,
    /// The z-buffer memory (`mcu_abuffer::memory::ZBufferMemory`).
    pub depths: u64,
    /// The frame workspace (`mcu_abuffer::memory::WorkspaceMemory`).
    pub workspace: u64,
}

/// Whether a `ConstStaticCell` of `linked` bytes holds `analytic` bytes of
/// memory: its size is the memory, one flag byte and at most 7 bytes of padding.
pub fn cell_holds(linked: u64, analytic: usize) -> bool {
    linked > analytic as u64 && linked <= analytic as u64 + 8
}

/// Reads a cortex-m-rt ELF's RAM use.
pub fn read_link_report(elf: &Path) -> Result<LinkReport, String> {
    use object::{Object, ObjectSection, ObjectSymbol};
    let bytes = std::fs::read(elf).map_err(|e| format!("{}: {e}", elf.display()))?;
    let file = object::File::parse(&*bytes).map_err(|e| format!("{}: {e}", elf.display()))?;
    let section = |name: &str| file.section_by_name(name).map(|s| s.size()).unwrap_or(0);
    let symbol = |name: &str| {
        file.symbols()
            .find(|s| s.name() == Ok(name))
            .map(|s| s.address())
    };
    let stack_start =
        symbol("_stack_start").ok_or("no _stack_start symbol (not a cortex-m-rt ELF?)")?;
    let stack_end = symbol("_stack_end").ok_or("no _stack_end symbol")?;
    // Rust statics are mangled `..<length><NAME>17h<hash>E`.
    let static_size = |name: &str| {
        let needle = format!("{}{name}17h", name.len());
        file.symbols()
            .find(|s| s.name().is_ok_and(|n| n.contains(&needle)))
            .map_or(0, |s| s.size())
    };
    let ram_origin = 0x2000_0000u64;
    Ok(LinkReport {
        data: section(".data"),
        bss: section(".bss"),
        uninit: section(".uninit"),
        // flip-link moves the stack to the bottom of RAM, so the stack's start is
        // not the end of RAM; cortex-m-rt's `_ram_end` is, either way.
        ram: symbol("_ram_end")
            .unwrap_or(stack_start)
            .saturating_sub(ram_origin),
        stack: stack_start.saturating_sub(stack_end),
        flash: [".vector_table", ".text", ".rodata", ".data"]
            .iter()
            .map(|name| section(name))
            .sum(),
        renderer: RendererStatics {
            fragments: static_size("FRAGMENTS"),
            depths: static_size("DEPTHS"),
            workspace: static_size("WORKSPACE"),
        },
    })
}

/// Prints what the linker placed in RAM in the firmware `elf` and whether the
/// renderer's statics are the `analytic` budget's bytes.
pub fn print_link_report(elf: &Path, analytic: &MemoryBudget) -> Result<(), String> {
    let r = read_link_report(elf)?;
    let statics = r.data + r.bss + r.uninit;
    println!("linker ({}):", elf.display());
    println!(
        "  .data {} + .bss {} + .uninit {} = {statics} bytes of {} RAM",
        r.data, r.bss, r.uninit, r.ram
    );
    println!("  stack (_stack_start - _stack_end): {} bytes", r.stack);
    let fragments = analytic.counts + analytic.main_slots + analytic.addresses + analytic.pool;
    let agree = |linked: u64, counted: usize| {
        if cell_holds(linked, counted) {
            "as counted above"
        } else {
            "NOT as counted above"
        }
    };
    println!(
        "  renderer statics: fragment memory {} bytes ({}), workspace {} bytes ({}); each with its cell's flag and padding",
        r.renderer.fragments,
        agree(r.renderer.fragments, fragments),
        r.renderer.workspace,
        agree(r.renderer.workspace, analytic.workspace)
    );
    Ok(())
}
