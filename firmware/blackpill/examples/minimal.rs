//! The smallest firmware that uses mcu-abuffer: one antialiased frame of an
//! octahedron on an ST7789 240x240 display driven by mipidsi, on an STM32F411
//! "Black Pill" (the wiring of the README's "Running on a board").
//!
//! Everything the renderer needs is in the four lines under "The renderer";
//! the rest is the board and the display. Build and flash:
//!
//!     cargo run --release --example minimal    # in firmware/blackpill
#![no_std]
#![no_main]

#[path = "../src/flushing_spi.rs"]
mod flushing_spi;

use cortex_m_rt::entry;
use defmt_rtt as _;
use embedded_graphics_core::pixelcolor::Rgb888;
use embedded_hal_bus::spi::ExclusiveDevice;
use flushing_spi::FlushingSpi;
use mcu_abuffer::memory::{FragmentMemory, WorkspaceMemory};
use mcu_abuffer::scene::OCTAHEDRON;
use mcu_abuffer::{Camera, Coord, DrawTargetSink, FrameOptions, Light, Mask4x4, OverflowPolicy};
use mcu_abuffer::{Renderer, Scene, SceneObject, Shading, Transform};
use mipidsi::options::ColorInversion;
use panic_probe as _;
use static_cell::ConstStaticCell;
use stm32f4xx_hal::pac;
use stm32f4xx_hal::prelude::*;
use stm32f4xx_hal::rcc::Config;
use stm32f4xx_hal::spi::{Mode, Phase, Polarity, Spi};

// The renderer: 240x240 in 6-row bands (1 fragment slot and 2 pool addresses
// per pixel, 1,152 pool slots: 43,488 bytes; the library's `memory::defaults`),
// scenes of up to 1 object with 64 vertices and 128 triangles.
static FRAGMENTS: ConstStaticCell<FragmentMemory<Mask4x4, 240, 6, 1, 2, 1152>> =
    ConstStaticCell::new(FragmentMemory::new());
static WORKSPACE: ConstStaticCell<WorkspaceMemory<240, 1, 64, 128>> =
    ConstStaticCell::new(WorkspaceMemory::new());

/// The octahedron, lit from the upper left, seen from slightly above.
static OBJECTS: [SceneObject<'static>; 1] = [SceneObject {
    mesh: OCTAHEDRON,
    color: Rgb888::new(220, 170, 120),
    transform: Transform {
        position: [Coord::ZERO; 3],
        rotation_deg: [Coord::ZERO, Coord::lit("30"), Coord::ZERO],
        scale: Coord::ONE,
    },
    cull_backfaces: true,
    shading: Shading::Quadratic,
}];

#[entry]
fn main() -> ! {
    let dp = pac::Peripherals::take().expect("device peripherals taken at reset");
    let cp = cortex_m::Peripherals::take().expect("core peripherals taken at reset");
    let mut rcc = dp
        .RCC
        .freeze(Config::hse(25.MHz()).sysclk(100.MHz()).pclk2(100.MHz()));
    let gpioa = dp.GPIOA.split(&mut rcc);
    let (sck, mosi) = (gpioa.pa5.into_alternate(), gpioa.pa7.into_alternate());
    let cs = gpioa.pa4.into_push_pull_output();
    let dc = gpioa.pa3.into_push_pull_output();
    let reset = gpioa.pa2.into_push_pull_output();
    let mut backlight = gpioa.pa1.into_push_pull_output();
    let mode = Mode {
        polarity: Polarity::IdleHigh,
        phase: Phase::CaptureOnSecondTransition,
    };
    let mut spi = Spi::new_bidi(dp.SPI1, (Some(sck), Some(mosi)), mode, 50.MHz(), &mut rcc);
    let mut delay = cp.SYST.delay(&rcc.clocks);
    let Ok(device) = ExclusiveDevice::new_no_delay(FlushingSpi(&mut spi), cs);
    let mut staging = [0u8; 512];
    let interface = mipidsi::interface::SpiInterface::new(device, dc, &mut staging);
    let mut display = mipidsi::Builder::new(mipidsi::models::ST7789, interface)
        .display_size(240, 240)
        .invert_colors(ColorInversion::Inverted)
        .reset_pin(reset)
        .init(&mut delay)
        .expect("display initialization");
    backlight.set_high();

    let scene = Scene {
        width: 240,
        height: 240,
        background: Rgb888::new(16, 18, 28),
        camera: Camera {
            eye: [Coord::ZERO, Coord::lit("1.2"), Coord::lit("3.5")],
            target: [Coord::ZERO; 3],
            up: [Coord::ZERO, Coord::ONE, Coord::ZERO],
            fov_y_deg: Coord::lit("40"),
            near: Coord::ONE,
            far: Coord::lit("10"),
        },
        light: Some(Light {
            direction: [Coord::lit("-0.4"), Coord::lit("0.7"), Coord::ONE],
            ambient: Coord::lit("0.15"),
            diffuse: Coord::lit("0.75"),
            specular: Coord::lit("0.4"),
            shininess: 24,
        }),
        objects: &OBJECTS,
    };

    // The renderer.
    let buffer = FRAGMENTS.take().buffer(OverflowPolicy::SplitBands);
    let mut renderer = Renderer::new(WORKSPACE.take().workspace(), buffer);
    let mut sink = DrawTargetSink::<_, 240>::new(&mut display);
    match renderer.render(&scene, &FrameOptions::default(), &mut sink) {
        Ok(stats) => defmt::info!(
            "frame drawn: {=u32} fragments, {=u32} merges",
            stats.buffer.fragments_generated,
            stats.buffer.merges
        ),
        Err(e) => defmt::error!("frame failed: {}", defmt::Debug2Format(&e)),
    }
    loop {
        cortex_m::asm::wfi();
    }
}
