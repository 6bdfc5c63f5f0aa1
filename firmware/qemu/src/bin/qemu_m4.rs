//! Firmware for QEMU `mps2-an386` (Cortex-M4F) standing in for an STM32F411-class
//! board: renders the baked scene as a turntable, band by band, from static
//! buffers, and for every frame counts instructions, logs statistics with defmt and
//! writes the picture to the host through semihosting (`frame-NNN.ppm`, plus
//! `stats.csv`). Exits through semihosting, non-zero on any failure.
//!
//! Instruction counts come from SysTick on the core clock: under
//! `qemu-system-arm -icount shift=0` one instruction takes 1 ns of virtual time, and
//! SysTick ticks at mps2's 25 MHz, so one tick is 40 instructions.
#![no_std]
#![no_main]

use core::sync::atomic::{AtomicU32, Ordering};
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_rt::{entry, exception};
use cortex_m_semihosting::{debug, hio};
use defmt_semihosting as _;
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};
use mcu_abuffer::band_buffer::BandBuffer;
use mcu_abuffer::coverage::{CoverageMask, Mask1x1};
use mcu_abuffer::fixed_point::Coord;
use mcu_abuffer::fragment::PackedFragment;
use mcu_abuffer::fragment_buffer::{BufferConfig, BufferStorage, FragmentBuffer, OverflowPolicy};
use mcu_abuffer::geometry::{ClipTransform, ObjectTransform};
use mcu_abuffer::renderer::{render_frame, FrameOptions, FrameWorkspace, ObjectFrame, ScreenVertex};
use mcu_abuffer::sink::LineSink;
use mcu_abuffer::stats::FrameStats;
use mcu_abuffer::zbuffer::ZBuffer;

/// Which kind of pixel memory a build uses.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Method {
    ABuffer,
    ZBuffer,
}

mod config {
    use super::{Method, OverflowPolicy};
    include!(concat!(env!("OUT_DIR"), "/config.rs"));
}

mod scene {
    use embedded_graphics_core::pixelcolor::Rgb888;
    use fixed::types::I2F14;
    use mcu_abuffer::fixed_point::Coord;
    use mcu_abuffer::scene::{Camera, Light, Mesh, Normal, Scene, SceneObject, Shading, Transform};
    include!(concat!(env!("OUT_DIR"), "/scene_data.rs"));
}

use config::*;

// The build script's memory arithmetic must use the real sizes.
const _: () = assert!(core::mem::size_of::<ScreenVertex>() == SCREEN_VERTEX_BYTES);
const _: () = assert!(core::mem::size_of::<ObjectFrame>() <= OBJECT_FRAME_BYTES);
const _: () = assert!(core::mem::size_of::<Rgb888>() == COLOR_BYTES);
const _: () = assert!(PackedFragment::<Mask>::SIZE == FRAGMENT_BYTES);

const SYSTICK_RELOAD: u32 = 0x00FF_FFFF;
/// Instructions per SysTick tick under `-icount shift=0` at 25 MHz.
const INSTRUCTIONS_PER_TICK: u64 = 40;

static SYSTICK_WRAPS: AtomicU32 = AtomicU32::new(0);

#[exception]
fn SysTick() {
    SYSTICK_WRAPS.fetch_add(1, Ordering::Relaxed);
}

/// SysTick ticks since start (64-bit, counting wraps).
fn ticks() -> u64 {
    loop {
        let before = SYSTICK_WRAPS.load(Ordering::Relaxed);
        let current = cortex_m::peripheral::SYST::get_current();
        let after = SYSTICK_WRAPS.load(Ordering::Relaxed);
        if before == after {
            return before as u64 * (SYSTICK_RELOAD as u64 + 1) + (SYSTICK_RELOAD - current) as u64;
        }
    }
}

const ABUF_PIXELS: usize = if matches!(METHOD, Method::ABuffer) { WIDTH * BAND } else { 0 };
const ZBUF_PIXELS: usize = if matches!(METHOD, Method::ZBuffer) { WIDTH * BAND } else { 0 };

static mut COUNTS: [u8; ABUF_PIXELS] = [0; ABUF_PIXELS];
static mut MAIN_SLOTS: [PackedFragment<Mask>; ABUF_PIXELS * MAIN] = [PackedFragment::EMPTY; ABUF_PIXELS * MAIN];
static mut ADDRESSES: [u16; ABUF_PIXELS * EXTRA] = [0; ABUF_PIXELS * EXTRA];
static mut POOL_SLOTS: [PackedFragment<Mask>; POOL] = [PackedFragment::EMPTY; POOL];
static mut DEPTHS: [u32; ZBUF_PIXELS] = [0; ZBUF_PIXELS];
static mut COLORS: [Rgb888; ZBUF_PIXELS] = [Rgb888::BLACK; ZBUF_PIXELS];

const EMPTY_OBJECT: ObjectFrame = ObjectFrame {
    transform: ObjectTransform { clip: ClipTransform { rows: [[0; 3]; 4], offsets: [0; 4] }, normal: [[0; 3]; 3] },
    vertex_base: 0,
    triangle_base: 0,
};
const EMPTY_VERTEX: ScreenVertex = ScreenVertex { x: 0, y: 0, z: 0, color: [0; 3], outcode: 0 };
static mut WS_OBJECTS: [ObjectFrame; OBJECTS_LEN] = [EMPTY_OBJECT; OBJECTS_LEN];
static mut WS_VERTICES: [ScreenVertex; VERTICES] = [EMPTY_VERTEX; VERTICES];
static mut WS_ROWS: [u16; TRIANGLES] = [0; TRIANGLES];
static mut WS_ORDER: [u32; TRIANGLES] = [0; TRIANGLES];
static mut WS_ROW_STARTS: [u32; HEIGHT + 1] = [0; HEIGHT + 1];
static mut WS_LINE: [Rgb888; WIDTH] = [Rgb888::BLACK; WIDTH];

/// A file on the host, through semihosting.
struct HostFile {
    fd: usize,
}

impl HostFile {
    /// Opens `name` (NUL-terminated) for writing, truncated, in binary mode.
    fn create(name: &[u8]) -> Option<Self> {
        if name.last() != Some(&0) {
            return None;
        }
        let mode = cortex_m_semihosting::nr::open::W_TRUNC_BINARY;
        // SAFETY: OPEN reads `name.len() - 1` bytes from a valid, NUL-terminated buffer.
        let fd = unsafe { cortex_m_semihosting::syscall!(OPEN, name.as_ptr(), mode, name.len() - 1) } as isize;
        (fd >= 0).then_some(Self { fd: fd as usize })
    }

    /// Writes all of `bytes`.
    fn write_all(&mut self, mut bytes: &[u8]) -> Result<(), ()> {
        while !bytes.is_empty() {
            // SAFETY: WRITE reads `bytes.len()` bytes from a valid slice; it returns
            // how many were not written.
            let left = unsafe { cortex_m_semihosting::syscall!(WRITE, self.fd, bytes.as_ptr(), bytes.len()) };
            if left > bytes.len() {
                return Err(());
            }
            bytes = &bytes[bytes.len() - left..];
            if left == 0 {
                break;
            }
        }
        Ok(())
    }
}

impl Drop for HostFile {
    fn drop(&mut self) {
        // SAFETY: closes a descriptor this value owns.
        unsafe {
            cortex_m_semihosting::syscall!(CLOSE, self.fd);
        }
    }
}

/// Writes lines to a semihosting file as binary PPM, counting the ticks spent.
struct SemihostingFrameSink {
    file: Option<HostFile>,
    bytes: [u8; WIDTH * 3],
    checksum: u32,
    ticks: u64,
}

impl LineSink for SemihostingFrameSink {
    type Error = ();

    fn write_line(&mut self, _y: u16, pixels: &[Rgb888]) -> Result<(), ()> {
        let start = ticks();
        for (dst, c) in self.bytes.chunks_exact_mut(3).zip(pixels) {
            dst[0] = c.r();
            dst[1] = c.g();
            dst[2] = c.b();
        }
        // FNV-1a over the line, so a log shows whether two runs drew the same frame.
        for &b in &self.bytes[..pixels.len() * 3] {
            self.checksum = (self.checksum ^ b as u32).wrapping_mul(0x0100_0193);
        }
        let result = match &mut self.file {
            Some(f) => f.write_all(&self.bytes[..pixels.len() * 3]).map_err(|_| ()),
            None => Ok(()),
        };
        self.ticks += ticks() - start;
        result
    }
}

/// Formats `n` in decimal into `buf`, returns the digits.
fn decimal(mut n: u64, buf: &mut [u8; 20]) -> &[u8] {
    let mut i = buf.len();
    loop {
        i -= 1;
        buf[i] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            return &buf[i..];
        }
    }
}

fn write_fields(file: &mut HostFile, fields: &[u64]) {
    let mut buf = [0u8; 20];
    for (i, &v) in fields.iter().enumerate() {
        if i > 0 {
            let _ = file.write_all(b",");
        }
        let _ = file.write_all(decimal(v, &mut buf));
    }
    let _ = file.write_all(b"\n");
}

fn fail(message: &str) -> ! {
    if let Ok(mut err) = hio::hstderr() {
        let _ = err.write_all(message.as_bytes());
        let _ = err.write_all(b"\n");
    }
    defmt::error!("{=str}", message);
    debug::exit(debug::EXIT_FAILURE);
    #[allow(clippy::empty_loop)]
    loop {}
}

#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    fail("panic");
}

fn frame_file(index: usize) -> Option<HostFile> {
    let mut name = *b"frame-000.ppm\0";
    name[6] = b'0' + (index / 100 % 10) as u8;
    name[7] = b'0' + (index / 10 % 10) as u8;
    name[8] = b'0' + (index % 10) as u8;
    HostFile::create(&name)
}

/// Ticks spent per stage of a frame (the `profile` feature).
#[derive(Clone, Copy, Default)]
struct StageTicks {
    frame_start: u64,
    first_band: u64,
    setup: u64,
    raster: u64,
    insert: u64,
    resolve: u64,
}

/// Forwards to a band buffer and times setup, rasterization, insertion and resolve.
struct ProfiledBuffer<'b, B> {
    inner: &'b mut B,
    ticks: StageTicks,
}

impl<M: CoverageMask, B: BandBuffer<M>> BandBuffer<M> for ProfiledBuffer<'_, B> {
    fn width(&self) -> u16 {
        self.inner.width()
    }
    fn band_height(&self) -> u16 {
        self.inner.band_height()
    }
    fn begin_band(&mut self, y0: u16, rows: u16) {
        if self.ticks.first_band == 0 {
            self.ticks.first_band = ticks();
        }
        self.inner.begin_band(y0, rows)
    }
    fn draw_triangle(
        &mut self,
        vertices: &[mcu_abuffer::setup::SetupVertex; 3],
        params: &mcu_abuffer::band_buffer::DrawParams,
        band_y0: u16,
        band_rows: u16,
    ) -> Result<(), mcu_abuffer::setup::Rejection> {
        let t0 = ticks();
        let setup = mcu_abuffer::setup::TriangleSetup::new(vertices, params.cull_backfaces, params.colors, params.width, params.height);
        let t1 = ticks();
        self.ticks.setup += t1 - t0;
        let setup = setup?;
        let inserts_before = self.ticks.insert;
        mcu_abuffer::raster::rasterize(&setup, band_y0, band_rows, self);
        self.ticks.raster += ticks() - t1 - (self.ticks.insert - inserts_before);
        Ok(())
    }
    fn insert(&mut self, x: u16, row: u16, fragment: &mcu_abuffer::fragment::Fragment<M>) {
        let t0 = ticks();
        self.inner.insert(x, row, fragment);
        self.ticks.insert += ticks() - t0;
    }
    fn resolve_row(&mut self, row: u16, background: Rgb888, out: &mut [Rgb888]) {
        let t0 = ticks();
        self.inner.resolve_row(row, background, out);
        self.ticks.resolve += ticks() - t0;
    }
    fn end_band(&mut self) {
        self.inner.end_band()
    }
    fn pixel_fragment_count(&self, x: u16, row: u16) -> u32 {
        self.inner.pixel_fragment_count(x, row)
    }
    fn stats(&self) -> mcu_abuffer::stats::BufferStats {
        self.inner.stats()
    }
    fn take_stats(&mut self) -> mcu_abuffer::stats::BufferStats {
        self.inner.take_stats()
    }
}

fn run_frames<M: CoverageMask, B: BandBuffer<M>>(buffer: &mut B, ws: &mut FrameWorkspace<'_>, stats_file: &mut HostFile) {
    let mut header_buf = [0u8; 20];
    for (i, &angle) in scene::FRAME_ANGLES.iter().enumerate() {
        let mut file = frame_file(i);
        if file.is_none() {
            fail("cannot open the frame file on the host");
        }
        if let Some(f) = &mut file {
            let _ = f.write_all(b"P6\n");
            let _ = f.write_all(decimal(WIDTH as u64, &mut header_buf));
            let _ = f.write_all(b" ");
            let _ = f.write_all(decimal(HEIGHT as u64, &mut header_buf));
            let _ = f.write_all(b"\n255\n");
        }
        let mut sink = SemihostingFrameSink { file, bytes: [0; WIDTH * 3], checksum: 0x811C_9DC5, ticks: 0 };
        let options = FrameOptions { turntable_deg: Coord::from_bits(angle) };
        let start = ticks();
        let mut profile = StageTicks { frame_start: start, ..StageTicks::default() };
        let result = if cfg!(feature = "profile") {
            let mut profiled = ProfiledBuffer { inner: buffer, ticks: profile };
            let r = render_frame(&scene::SCENE, &options, ws, &mut profiled, &mut sink, |_, _, _| {});
            profile = profiled.ticks;
            r
        } else {
            render_frame(&scene::SCENE, &options, ws, buffer, &mut sink, |_, _, _| {})
        };
        let total = ticks() - start;
        if cfg!(feature = "profile") {
            let k = INSTRUCTIONS_PER_TICK;
            let p = &profile;
            let geometry = p.first_band.saturating_sub(p.frame_start);
            let other = total.saturating_sub(geometry + p.setup + p.raster + p.insert + p.resolve + sink.ticks);
            defmt::info!(
                "profile frame {=usize} (instructions): transform+binning {=u64}, setup {=u64}, raster {=u64}, insert {=u64}, resolve {=u64}, output {=u64}, band loop {=u64}",
                i,
                geometry * k,
                p.setup * k,
                p.raster * k,
                p.insert * k,
                p.resolve * k,
                sink.ticks * k,
                other * k
            );
        }
        let stats: FrameStats = match result {
            Ok(s) => s,
            Err(_) => fail("render_frame failed"),
        };
        let instructions = total * INSTRUCTIONS_PER_TICK;
        let output = sink.ticks * INSTRUCTIONS_PER_TICK;
        let b = &stats.buffer;
        defmt::info!(
            "frame {=usize}: {=u64} instructions ({=u64} rendering, {=u64} output), {=u64} fragments, {=u64} merges, pool peak {=u32}, checksum {=u32:#x}",
            i,
            instructions,
            instructions - output,
            output,
            b.fragments_generated,
            b.merges,
            b.pool_peak,
            sink.checksum
        );
        write_fields(
            stats_file,
            &[
                i as u64,
                instructions,
                output,
                b.fragments_generated,
                b.fragments_stored,
                b.fragments_hidden_on_arrival,
                b.fragments_removed_hidden,
                b.merges,
                b.fragments_discarded,
                b.pool_peak as u64,
                b.max_fragments_in_pixel as u64,
                stats.geometry.triangles_in as u64,
                sink.checksum as u64,
            ],
        );
    }
}

#[entry]
fn main() -> ! {
    let mut core = match cortex_m::Peripherals::take() {
        Some(p) => p,
        None => fail("peripherals taken twice"),
    };
    core.SYST.set_clock_source(SystClkSource::Core);
    core.SYST.set_reload(SYSTICK_RELOAD);
    core.SYST.clear_current();
    core.SYST.enable_interrupt();
    core.SYST.enable_counter();

    defmt::info!(
        "scene {=str}: {=usize} triangles, {=usize}x{=usize}, {=str} {=str}, band {=usize}, main {=usize}, extra {=usize}, pool {=usize}",
        SCENE_NAME,
        TRIANGLES,
        WIDTH,
        HEIGHT,
        METHOD_NAME,
        GRID_NAME,
        BAND,
        MAIN,
        EXTRA,
        POOL
    );
    let mut stats_file = match HostFile::create(b"stats.csv\0") {
        Some(f) => f,
        None => fail("cannot open stats.csv on the host"),
    };
    let _ = stats_file.write_all(
        b"frame,instructions,output_instructions,generated,stored,hidden_on_arrival,removed_hidden,merges,discarded,pool_peak,max_in_pixel,triangles,checksum\n",
    );

    // SAFETY: `main` runs once and is the only code touching these statics; each is
    // borrowed exactly once here for the rest of the program.
    let mut ws = unsafe {
        FrameWorkspace {
            objects: &mut *core::ptr::addr_of_mut!(WS_OBJECTS),
            vertices: &mut *core::ptr::addr_of_mut!(WS_VERTICES),
            triangle_rows: &mut *core::ptr::addr_of_mut!(WS_ROWS),
            triangle_order: &mut *core::ptr::addr_of_mut!(WS_ORDER),
            row_starts: &mut *core::ptr::addr_of_mut!(WS_ROW_STARTS),
            line: &mut *core::ptr::addr_of_mut!(WS_LINE),
        }
    };
    match METHOD {
        Method::ABuffer => {
            let config = BufferConfig {
                width: WIDTH as u16,
                band_height: BAND as u16,
                main_slots: MAIN as u8,
                extra_addresses: EXTRA as u8,
                policy: POLICY,
            };
            // SAFETY: as above, borrowed once.
            let storage = unsafe {
                BufferStorage {
                    counts: &mut *core::ptr::addr_of_mut!(COUNTS),
                    main: &mut *core::ptr::addr_of_mut!(MAIN_SLOTS),
                    addresses: &mut *core::ptr::addr_of_mut!(ADDRESSES),
                    pool: &mut *core::ptr::addr_of_mut!(POOL_SLOTS),
                }
            };
            let mut buffer: FragmentBuffer<'_, Mask, u16> = match FragmentBuffer::new(config, storage) {
                Ok(b) => b,
                Err(_) => fail("fragment buffer configuration rejected"),
            };
            run_frames(&mut buffer, &mut ws, &mut stats_file);
        }
        Method::ZBuffer => {
            // SAFETY: as above, borrowed once.
            let (depth, color) = unsafe { (&mut *core::ptr::addr_of_mut!(DEPTHS), &mut *core::ptr::addr_of_mut!(COLORS)) };
            let mut buffer = match ZBuffer::new(WIDTH as u16, BAND as u16, depth, color) {
                Some(b) => b,
                None => fail("z-buffer configuration rejected"),
            };
            run_frames::<Mask1x1, _>(&mut buffer, &mut ws, &mut stats_file);
        }
    }
    debug::exit(debug::EXIT_SUCCESS);
    #[allow(clippy::empty_loop)]
    loop {}
}
