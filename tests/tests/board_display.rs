//! The board's display path on the host: the ST7789 initialization (through
//! mipidsi) and the double-buffered band stream, driven by the same functions the
//! STM32F411 firmware calls, into an emulated ST7789 behind the embedded-hal
//! `SpiDevice` and `OutputPin` traits. What the controller's memory holds afterwards
//! must be host-sim's frame, pixel for pixel (in RGB565).

use abuffer_panel::demo::{defaults, render_turntable_frame};
use abuffer_panel::emulator::{St7789Emulator, MEMORY_COLUMNS};
use abuffer_panel::link::{PanelLink, SpiPanelLink};
use abuffer_panel::overlay::BandCanvas;
use abuffer_panel::st7789::{self, CASET, RAMWR, RASET};
use abuffer_panel::stream::{BandStream, StreamError};
use abuffer_test_support::OwnedWorkspace;
use embedded_graphics_core::pixelcolor::raw::{RawData, RawU16};
use embedded_graphics_core::pixelcolor::{Rgb565, Rgb888};
use embedded_hal::delay::DelayNs;
use host_sim::builtins::builtin_scene;
use host_sim::convert::{to_fixed, FixedScene};
use host_sim::render::{abuffer, render, Method, RenderConfig};
use mcu_abuffer::fixed_point::Coord;
use mcu_abuffer::{BufferConfig, LineSink, Mask4x4, OverflowPolicy};

const W: u16 = defaults::WIDTH;
const H: u16 = defaults::HEIGHT;
const BAND: u16 = defaults::BAND_ROWS;

struct NoWait;

impl DelayNs for NoWait {
    fn delay_ns(&mut self, _ns: u32) {}
}

/// Resets and initializes the emulated module as the board does.
fn initialized_panel(
    emulator: &St7789Emulator,
) -> (
    abuffer_panel::emulator::EmulatedSpi,
    abuffer_panel::emulator::EmulatedDataCommandPin,
) {
    st7789::initialize(
        emulator.spi(),
        emulator.data_command_pin(),
        emulator.reset_pin(),
        &mut NoWait,
        W,
        H,
        true,
    )
    .unwrap_or_else(|e| panic!("initialization failed: {e:?}"))
}

fn scene(name: &str) -> FixedScene {
    to_fixed(&builtin_scene(name, W as u32, H as u32).unwrap()).unwrap()
}

/// host-sim's rendering of `name` at `angle` with the board's buffer parameters, in RGB565.
fn host_frame(name: &str, angle: f32) -> Vec<u16> {
    let config = RenderConfig {
        method: Method::Shared,
        main: defaults::MAIN_SLOTS,
        extra: defaults::EXTRA_ADDRESSES,
        pool: Some(defaults::POOL_SLOTS),
        band: BAND,
        ..RenderConfig::default()
    };
    let out = render(&scene(name), &config, angle).unwrap();
    out.rgb
        .chunks_exact(3)
        .map(|p| RawU16::from(Rgb565::from(Rgb888::new(p[0], p[1], p[2]))).into_inner())
        .collect()
}

/// Renders `name` at `angle` through the board's buffers and `stream`.
fn panel_frame<'buf, L: PanelLink<'buf>>(name: &str, angle: f32, stream: &mut BandStream<'buf, L>)
where
    L::Error: core::fmt::Debug,
{
    let fixed = scene(name);
    let objects = fixed.objects();
    let lib_scene = fixed.scene(&objects);
    let mut workspace = OwnedWorkspace::for_scene(&lib_scene);
    let config = BufferConfig {
        width: W,
        band_height: BAND,
        main_slots: defaults::MAIN_SLOTS,
        extra_addresses: defaults::EXTRA_ADDRESSES,
        policy: OverflowPolicy::MergeFarthest,
    };
    let mut storage = abuffer::<Mask4x4, u16>(config, defaults::POOL_SLOTS).unwrap();
    let mut buffer = storage.buffer();
    render_turntable_frame(
        &lib_scene,
        Coord::from_num(angle),
        &mut workspace.borrow(),
        &mut buffer,
        stream,
    )
    .unwrap_or_else(|e| panic!("{name} at {angle}: {e:?}"));
}

fn band_buffers() -> [&'static mut [u8]; 2] {
    let bytes = BAND as usize * W as usize * 2;
    [Vec::leak(vec![0u8; bytes]), Vec::leak(vec![0u8; bytes])]
}

fn count_differences(a: &[u16], b: &[u16]) -> usize {
    a.iter().zip(b).filter(|(x, y)| x != y).count() + a.len().abs_diff(b.len())
}

#[test]
fn initialization_leaves_the_controller_ready_for_rgb565() {
    let emulator = St7789Emulator::new();
    initialized_panel(&emulator);
    let state = emulator.state();
    assert!(state.errors.is_empty(), "{:?}", state.errors);
    assert!(!state.sleeping, "still asleep");
    assert!(state.display_on, "display off");
    assert!(state.inverted, "inversion off");
    assert_eq!(state.colmod, st7789::COLMOD_RGB565);
    assert_eq!(state.madctl, 0, "not the default orientation");
}

#[test]
fn every_demo_scene_arrives_exactly_as_host_sim_renders_it() {
    let emulator = St7789Emulator::new();
    let (spi, dc) = initialized_panel(&emulator);
    let mut stream = BandStream::new(SpiPanelLink::new(spi, dc), W, H, band_buffers()).unwrap();
    stream.overlay_mut().set_enabled(false);
    for (i, name) in defaults::SCENES.iter().enumerate() {
        for angle in [0.0, 30.0 + 90.0 * i as f32] {
            // A color the renderer never produces shows any pixel left unwritten.
            emulator.fill_memory(0x1234);
            emulator.clear_log();
            panel_frame(name, angle, &mut stream);
            stream.flush().unwrap();
            let state = emulator.state();
            assert!(state.errors.is_empty(), "{name}: {:?}", state.errors);
            assert_eq!(state.pixels_written, W as u64 * H as u64);
            let bands = H.div_ceil(BAND) as usize;
            assert_eq!(
                state.commands.len(),
                3 * bands,
                "CASET, RASET, RAMWR per band"
            );
            let shown = emulator.region(0, 0, W, H);
            let expected = host_frame(name, angle);
            let differing = count_differences(&shown, &expected);
            assert_eq!(
                differing, 0,
                "{name} at {angle} degrees: {differing} pixels differ"
            );
            // Not an empty picture.
            let background = expected[0];
            let covered = shown.iter().filter(|&&p| p != background).count();
            assert!(
                covered > 2_000,
                "{name} at {angle}: only {covered} pixels drawn"
            );
        }
    }
    // Nothing was written outside the image's columns below it either.
    let below = emulator.region(0, H, MEMORY_COLUMNS, 320 - H);
    assert!(below.iter().all(|&p| p == 0x1234));
}

/// A link that behaves like DMA: `start_pixels` only records the buffer; the bytes
/// go out at `finish_pixels`. It checks the stream never sends a command while a
/// transfer is in flight and that the two buffers alternate.
struct DeferredLink<'buf, L> {
    inner: L,
    pending: Option<(&'buf mut [u8], usize)>,
    started: Vec<*const u8>,
    commands_in_flight: usize,
}

impl<'buf, L: PanelLink<'buf>> PanelLink<'buf> for DeferredLink<'buf, L> {
    type Error = L::Error;

    fn command(&mut self, command: u8, parameters: &[u8]) -> Result<(), L::Error> {
        if self.pending.is_some() {
            self.commands_in_flight += 1;
        }
        self.inner.command(command, parameters)
    }

    fn start_pixels(&mut self, buffer: &'buf mut [u8], len: usize) -> Result<(), L::Error> {
        assert!(
            self.pending.is_none(),
            "a second transfer started before the first finished"
        );
        self.started.push(buffer.as_ptr());
        self.pending = Some((buffer, len));
        Ok(())
    }

    fn finish_pixels(&mut self) -> Result<Option<&'buf mut [u8]>, L::Error> {
        let Some((buffer, len)) = self.pending.take() else {
            return Ok(None);
        };
        self.inner.start_pixels(buffer, len)?;
        self.inner.finish_pixels()
    }
}

#[test]
fn overlapped_transfers_give_the_same_frame_and_alternate_buffers() {
    let emulator = St7789Emulator::new();
    let (spi, dc) = initialized_panel(&emulator);
    let link = DeferredLink {
        inner: SpiPanelLink::new(spi, dc),
        pending: None,
        started: Vec::new(),
        commands_in_flight: 0,
    };
    let mut stream = BandStream::new(link, W, H, band_buffers()).unwrap();
    stream.overlay_mut().set_enabled(false);
    panel_frame("teapot", 60.0, &mut stream);
    // The last band is still "in flight" until the stream is flushed.
    assert!(stream.link().pending.is_some());
    stream.flush().unwrap();
    let link = stream.link();
    assert_eq!(link.commands_in_flight, 0);
    assert_eq!(link.started.len(), H.div_ceil(BAND) as usize);
    for pair in link.started.windows(2) {
        assert_ne!(pair[0], pair[1], "consecutive bands share a buffer");
    }
    for triple in link.started.windows(3) {
        assert_eq!(triple[0], triple[2], "more than two buffers in use");
    }
    let state = emulator.state();
    assert!(state.errors.is_empty(), "{:?}", state.errors);
    let differing = count_differences(&emulator.region(0, 0, W, H), &host_frame("teapot", 60.0));
    assert_eq!(differing, 0);
}

#[test]
fn the_overlay_crosses_bands_and_joins_up() {
    let emulator = St7789Emulator::new();
    let (spi, dc) = initialized_panel(&emulator);
    let mut stream = BandStream::new(SpiPanelLink::new(spi, dc), W, H, band_buffers()).unwrap();
    stream
        .overlay_mut()
        .set_text(format_args!("{} {}.{} fps", "teapot", 3, 4));
    let text_box = stream.overlay_mut().bounding_box();
    // The 10-pixel font at row 2 crosses a band boundary.
    assert!(text_box.top_left.y < BAND as i32 && text_box.bottom_right().unwrap().y >= BAND as i32);
    panel_frame("teapot", 0.0, &mut stream);
    stream.flush().unwrap();

    // The same text drawn in one piece over host-sim's whole frame.
    let plain = host_frame("teapot", 0.0);
    let mut expected_bytes: Vec<u8> = plain.iter().flat_map(|p| p.to_be_bytes()).collect();
    let overlay = stream.overlay_mut().clone();
    overlay
        .draw(&mut BandCanvas::new(&mut expected_bytes, W, H, 0, H))
        .unwrap();
    let expected: Vec<u16> = expected_bytes
        .chunks_exact(2)
        .map(|b| u16::from_be_bytes([b[0], b[1]]))
        .collect();
    let shown = emulator.region(0, 0, W, H);
    assert_eq!(count_differences(&shown, &expected), 0);
    // And the text is really there: white pixels inside its box.
    let changed = count_differences(&shown, &plain);
    assert!(changed > 100, "overlay changed only {changed} pixels");
}

#[test]
fn a_stream_refuses_wrong_buffers_and_lines() {
    let emulator = St7789Emulator::new();
    let short: [&mut [u8]; 2] = [Vec::leak(vec![0u8; 100]), Vec::leak(vec![0u8; 100])];
    let refused = BandStream::new(
        SpiPanelLink::new(emulator.spi(), emulator.data_command_pin()),
        W,
        H,
        short,
    );
    assert!(matches!(
        refused.err(),
        Some(StreamError::BufferSize {
            row_bytes: 480,
            shorter: 100
        })
    ));
    let mut stream = BandStream::new(
        SpiPanelLink::new(emulator.spi(), emulator.data_command_pin()),
        W,
        H,
        band_buffers(),
    )
    .unwrap();
    let line = vec![Rgb888::new(1, 2, 3); W as usize - 1];
    assert_eq!(
        stream.write_line(0, &line),
        Err(StreamError::LineWidth { y: 0, pixels: 239 })
    );
    let line = vec![Rgb888::new(1, 2, 3); W as usize];
    assert_eq!(stream.write_line(H, &line), Err(StreamError::Row { y: H }));
    // Nothing reached the controller.
    assert!(emulator.state().commands.is_empty());
}

#[test]
fn a_partial_band_is_addressed_on_its_own() {
    // Rows 10 and 11 only, then a new frame from row 0: each piece gets its own window.
    let emulator = St7789Emulator::new();
    let (spi, dc) = initialized_panel(&emulator);
    emulator.fill_memory(0);
    emulator.clear_log();
    let mut stream = BandStream::new(SpiPanelLink::new(spi, dc), W, H, band_buffers()).unwrap();
    stream.overlay_mut().set_enabled(false);
    let red = vec![Rgb888::new(255, 0, 0); W as usize];
    let blue = vec![Rgb888::new(0, 0, 255); W as usize];
    stream.write_line(10, &red).unwrap();
    stream.write_line(11, &red).unwrap();
    stream.write_line(0, &blue).unwrap();
    stream.flush().unwrap();
    let state = emulator.state();
    assert!(state.errors.is_empty(), "{:?}", state.errors);
    assert_eq!(state.commands, [CASET, RASET, RAMWR, CASET, RASET, RAMWR]);
    assert_eq!(state.pixels_written, 3 * W as u64);
    let rows = emulator.region(0, 0, W, 12);
    let row = |y: usize| &rows[y * W as usize..(y + 1) * W as usize];
    assert!(row(0).iter().all(|&p| p == 0x001F));
    assert!(row(1).iter().all(|&p| p == 0));
    assert!(row(10).iter().all(|&p| p == 0xF800) && row(11).iter().all(|&p| p == 0xF800));
    assert_eq!(stream.stats().bands, 2);
}

mod any_line_sequence {
    use super::*;
    use proptest::prelude::*;

    /// A line of one color whose RGB565 value is distinct per (row, write).
    fn line(width: u16, seed: u32) -> (Vec<Rgb888>, u16) {
        let c = Rgb888::new(
            (seed * 37) as u8,
            (seed * 91 + 7) as u8,
            (seed * 13 + 100) as u8,
        );
        let raw = RawU16::from(Rgb565::from(c)).into_inner();
        (vec![c; width as usize], raw)
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

        /// Whatever rows arrive in whatever order, through buffers of any size, the
        /// controller ends up with the last line written to each row, never sees a
        /// protocol error, and rows outside the image or lines of the wrong width
        /// are refused without reaching it.
        #[test]
        fn the_controller_holds_the_last_line_of_every_row(
            width in 1u16..=240,
            height in 1u16..=40,
            capacity_rows in 1usize..=12,
            extra_bytes in 0usize..4,
            writes in proptest::collection::vec((0u16..48, 0u8..8), 0..120),
        ) {
            let emulator = St7789Emulator::new();
            let (spi, dc) = initialized_panel(&emulator);
            emulator.fill_memory(0xDEAD);
            let bytes = capacity_rows * width as usize * 2 + extra_bytes;
            let buffers: [&'static mut [u8]; 2] =
                [Vec::leak(vec![0u8; bytes]), Vec::leak(vec![0u8; bytes])];
            let mut stream = BandStream::new(SpiPanelLink::new(spi, dc), width, height, buffers).unwrap();
            stream.overlay_mut().set_enabled(false);
            let mut expected = vec![None; height as usize];
            for (i, &(y, kind)) in writes.iter().enumerate() {
                let (pixels, raw) = line(width, i as u32);
                if kind == 0 {
                    // A line one pixel short (or long, for a 1-pixel image).
                    let wrong = if width > 1 { width - 1 } else { 2 };
                    let short = vec![pixels[0]; wrong as usize];
                    prop_assert_eq!(
                        stream.write_line(y.min(height - 1), &short),
                        Err(StreamError::LineWidth { y: y.min(height - 1), pixels: wrong as usize })
                    );
                } else if y >= height {
                    prop_assert_eq!(stream.write_line(y, &pixels), Err(StreamError::Row { y }));
                } else {
                    prop_assert_eq!(stream.write_line(y, &pixels), Ok(()));
                    expected[y as usize] = Some(raw);
                }
            }
            stream.flush().unwrap();
            let state = emulator.state();
            prop_assert!(state.errors.is_empty(), "{:?}", state.errors);
            let shown = emulator.region(0, 0, width, height);
            for (y, want) in expected.iter().enumerate() {
                let row = &shown[y * width as usize..(y + 1) * width as usize];
                let want = want.unwrap_or(0xDEAD);
                prop_assert!(row.iter().all(|&p| p == want), "row {} holds {:?}, not {:#06x}", y, &row[..1], want);
            }
            // Columns right of the image are untouched.
            if width < MEMORY_COLUMNS {
                let right = emulator.region(width, 0, MEMORY_COLUMNS - width, height);
                prop_assert!(right.iter().all(|&p| p == 0xDEAD));
            }
            // Buffers come back whole.
            let (_, [a, b]) = stream.release().unwrap();
            prop_assert_eq!((a.len(), b.len()), (bytes, bytes));
        }
    }
}
