//! Firmware for QEMU `mps2-an386` (Cortex-M4F) standing in for an STM32F411-class
//! board: renders the baked scene as a turntable, band by band, from static
//! buffers, and for every frame counts instructions, logs statistics with defmt and
//! writes the picture to the host through semihosting (`frame-NNN.ppm`, plus
//! `stats.csv`). Exits through semihosting, non-zero on any failure.
//!
//! Instruction counts come from SysTick on the core clock: under
//! `qemu-system-arm -icount shift=0` one instruction takes 1 ns of virtual time, and
//! SysTick ticks at mps2's 25 MHz, so one tick is 40 instructions.
//!
//! The stack is painted at reset; after every frame the firmware reports the
//! stack's high-water mark so far (the last column of `stats.csv`, and the log).
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use cortex_m_semihosting::debug;
use defmt_semihosting as _;
use embedded_graphics_core::pixelcolor::Rgb888;
use mcu_abuffer::band_buffer::{BandBuffer, PoolUse};
use mcu_abuffer::coverage::CoverageMask;
use mcu_abuffer::draw_order::TriangleOrder;
use mcu_abuffer::fixed_point::Coord;
use mcu_abuffer::renderer::{render_frame, FrameOptions, FrameWorkspace};
use mcu_abuffer::sink::{LinePixel, LineSink, PackedRgb888};
use mcu_abuffer::stats::FrameStats;

#[path = "../common.rs"]
mod common;

use common::*;

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
        let fd =
            unsafe { cortex_m_semihosting::syscall!(OPEN, name.as_ptr(), mode, name.len() - 1) }
                as isize;
        (fd >= 0).then_some(Self { fd: fd as usize })
    }

    /// Writes all of `bytes`.
    fn write_all(&mut self, mut bytes: &[u8]) -> Result<(), ()> {
        while !bytes.is_empty() {
            // SAFETY: WRITE reads `bytes.len()` bytes from a valid slice; it returns
            // how many were not written.
            let left = unsafe {
                cortex_m_semihosting::syscall!(WRITE, self.fd, bytes.as_ptr(), bytes.len())
            };
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
/// The renderer resolves each line straight into the sink's line of PPM
/// pixels, so the ticks are the semihosting call's alone.
struct SemihostingFrameSink {
    file: Option<HostFile>,
    line: [PackedRgb888; WIDTH],
    ticks: u64,
}

impl LineSink for SemihostingFrameSink {
    type Pixel = PackedRgb888;
    type Error = ();

    fn fill_line<F: FnOnce(&mut [PackedRgb888])>(
        &mut self,
        _y: u16,
        width: u16,
        fill: F,
    ) -> Result<(), ()> {
        let line = self.line.get_mut(..width as usize).ok_or(())?;
        fill(line);
        let start = ticks();
        let result = match &mut self.file {
            Some(f) => f.write_all(PackedRgb888::line_bytes(line)),
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
    colors: u64,
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
    const ORDER: TriangleOrder = B::ORDER;
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
        params: &mcu_abuffer::band_buffer::DrawParams<'_>,
        band_y0: u16,
        band_rows: u16,
    ) -> Result<(), mcu_abuffer::setup::Rejection> {
        let t0 = ticks();
        let setup = mcu_abuffer::setup::TriangleSetup::new(
            vertices,
            params.cull_backfaces,
            params.width,
            params.height,
        );
        let t1 = ticks();
        self.ticks.setup += t1 - t0;
        let setup = setup?;
        // The whole-triangle test counts as setup, hidden or not; as in
        // `draw_in_band`, for faces turned away and where the frame driver
        // asks.
        let hidden = (setup.faces_away() || params.test_whole_band)
            && mcu_abuffer::raster::hidden_in_band(&setup, band_y0, band_rows, self);
        let t2 = ticks();
        self.ticks.setup += t2 - t1;
        if hidden {
            return Ok(());
        }
        let t1 = t2;
        let inserts_before = self.ticks.insert;
        let color_ticks = core::cell::Cell::new(0u64);
        let colors = || {
            let c0 = ticks();
            let planes = (params.colors)(&setup);
            color_ticks.set(color_ticks.get() + ticks() - c0);
            planes
        };
        mcu_abuffer::raster::rasterize(&setup, band_y0, band_rows, self, colors);
        self.ticks.colors += color_ticks.get();
        self.ticks.raster +=
            ticks() - t1 - (self.ticks.insert - inserts_before) - color_ticks.get();
        Ok(())
    }
    fn hides(&mut self, x: u16, row: u16, depth: i64) -> bool {
        self.inner.hides(x, row, depth)
    }
    fn hidden_run(&mut self, row: u16, x0: u16, x1: u16, depth: i64) -> u32 {
        self.inner.hidden_run(row, x0, x1, depth)
    }
    fn hides_columns(&mut self, x0: u16, x1: u16, depth: i64) -> bool {
        self.inner.hides_columns(x0, x1, depth)
    }
    fn count_triangle_test(&mut self, pixels: u32, hidden: bool) {
        self.inner.count_triangle_test(pixels, hidden)
    }
    fn survives(
        &mut self,
        x: u16,
        row: u16,
        fragment: &mcu_abuffer::fragment::Fragment<M>,
    ) -> bool {
        let t0 = ticks();
        let survives = self.inner.survives(x, row, fragment);
        self.ticks.insert += ticks() - t0;
        survives
    }
    fn insert(&mut self, x: u16, row: u16, fragment: &mcu_abuffer::fragment::Fragment<M>) {
        let t0 = ticks();
        self.inner.insert(x, row, fragment);
        self.ticks.insert += ticks() - t0;
    }
    fn insert_full_run<W: mcu_abuffer::shading::ColorWalk>(
        &mut self,
        x: u16,
        row: u16,
        run: &mcu_abuffer::band_buffer::FullRun<M>,
        walk: &W,
        color: &mut W::Row,
    ) {
        let t0 = ticks();
        self.inner.insert_full_run(x, row, run, walk, color);
        self.ticks.insert += ticks() - t0;
    }
    fn resolve_row<P: LinePixel>(&mut self, row: u16, background: Rgb888, out: &mut [P]) {
        let t0 = ticks();
        self.inner.resolve_row(row, background, out);
        self.ticks.resolve += ticks() - t0;
    }
    fn end_band(&mut self) {
        self.inner.end_band()
    }
    fn pool_use(&self) -> PoolUse {
        self.inner.pool_use()
    }
    fn pixel_fragment_count(&self, x: u16, row: u16) -> u32 {
        self.inner.pixel_fragment_count(x, row)
    }
    fn stats(&self) -> mcu_abuffer::stats::BufferStats {
        self.inner.stats()
    }
    fn hidden_count(&self) -> u32 {
        self.inner.hidden_count()
    }
    fn take_stats(&mut self) -> mcu_abuffer::stats::BufferStats {
        self.inner.take_stats()
    }
}

fn run_frames<M: CoverageMask, B: BandBuffer<M>>(
    buffer: &mut B,
    ws: &mut FrameWorkspace<'_>,
    stats_file: &mut HostFile,
) {
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
        let mut sink = SemihostingFrameSink {
            file,
            line: [PackedRgb888::default(); WIDTH],
            ticks: 0,
        };
        let options = FrameOptions {
            turntable_deg: Coord::from_bits(angle),
            ..FrameOptions::default()
        };
        let start = ticks();
        let mut profile = StageTicks {
            frame_start: start,
            ..StageTicks::default()
        };
        let result = if cfg!(feature = "profile") {
            let mut profiled = ProfiledBuffer {
                inner: buffer,
                ticks: profile,
            };
            let r = render_frame(
                &scene::SCENE,
                &options,
                ws,
                &mut profiled,
                &mut sink,
                |_, _, _| {},
            );
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
            let other = total.saturating_sub(
                geometry + p.setup + p.colors + p.raster + p.insert + p.resolve + sink.ticks,
            );
            defmt::info!(
                "profile frame {=usize} (instructions): transform+binning {=u64}, setup {=u64}, colors {=u64}, raster {=u64}, insert {=u64}, resolve {=u64}, output {=u64}, band loop {=u64}",
                i,
                geometry * k,
                p.setup * k,
                p.colors * k,
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
        let stack = mcu_abuffer::stack::painted_stack_use(cortex_m_rt::STACK_PAINT_VALUE);
        let (stack_peak, stack_reserved) = (stack.high_water, stack.reserved);
        defmt::info!(
            "frame {=usize}: stack high-water mark {=usize} of {=usize} bytes reserved",
            i,
            stack_peak,
            stack_reserved
        );
        defmt::info!(
            "frame {=usize}: {=u64} instructions ({=u64} rendering, {=u64} output), {=u32} fragments, {=u32} merges, pool peak {=u32}",
            i,
            instructions,
            instructions - output,
            output,
            b.fragments_generated,
            b.merges,
            b.pool_peak,
        );
        write_fields(
            stats_file,
            &[
                i as u64,
                instructions,
                output,
                b.fragments_generated as u64,
                b.fragments_stored as u64,
                b.fragments_hidden_on_arrival as u64,
                b.fragments_removed_hidden as u64,
                b.merges as u64,
                b.fragments_discarded as u64,
                b.pool_peak as u64,
                b.max_fragments_in_pixel as u64,
                stats.geometry.triangles_in as u64,
                stack_peak as u64,
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
    guard_below_stack(&mut core.MPU);
    start_tick_counter(&mut core.SYST);

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
        b"frame,instructions,output_instructions,generated,stored,hidden_on_arrival,removed_hidden,merges,discarded,pool_peak,max_in_pixel,triangles,stack_peak\n",
    );

    struct Frames<'f> {
        stats_file: &'f mut HostFile,
    }
    impl WithBuffers for Frames<'_> {
        fn run<M: CoverageMask, B: BandBuffer<M>>(
            self,
            buffer: &mut B,
            ws: &mut FrameWorkspace<'_>,
        ) {
            run_frames(buffer, ws, self.stats_file);
        }
    }
    with_buffers(Frames {
        stats_file: &mut stats_file,
    });
    debug::exit(debug::EXIT_SUCCESS);
    #[allow(clippy::empty_loop)]
    loop {}
}
