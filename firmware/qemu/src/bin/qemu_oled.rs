//! Firmware for QEMU `lm3s6965evb` (Cortex-M3, 64 KiB SRAM, no FPU): renders the
//! baked scene once at 128x64 and streams every finished line over the PL022 SPI
//! controller to the board's SSD0323 OLED as 4-bit gray, the way a real display is
//! driven: a column and row window command, then the line's pixel data.
//!
//! Wiring (as on the LM3S6965 evaluation board and in QEMU's model): SSI0 at
//! `0x4000_8000`, data/command on GPIO PC7 (high = data), the OLED selected while
//! GPIO PD0 is high. When the frame is out the firmware prints `frame done` on the
//! semihosting console and waits, so the host can take a screendump.
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use cortex_m_semihosting::hio;
use defmt_semihosting as _;
use embedded_graphics_core::pixelcolor::{Gray4, GrayColor};
use mcu_abuffer::band_buffer::BandBuffer;
use mcu_abuffer::coverage::CoverageMask;
use mcu_abuffer::renderer::{render_frame, FrameOptions, FrameWorkspace};
use mcu_abuffer::sink::LineSink;

#[path = "../common.rs"]
mod common;

use common::*;

const SYSCTL_RCGC1: usize = 0x400F_E104;
const SYSCTL_RCGC2: usize = 0x400F_E108;
const GPIO_C: usize = 0x4000_6000;
const GPIO_D: usize = 0x4000_7000;
const GPIO_DIR: usize = 0x400;
const GPIO_DEN: usize = 0x51C;
const SSI0: usize = 0x4000_8000;
const SSI_CR0: usize = 0x00;
const SSI_CR1: usize = 0x04;
const SSI_DR: usize = 0x08;
const SSI_SR: usize = 0x0C;
const SSI_CPSR: usize = 0x10;
const SR_RNE: u32 = 1 << 2;

/// SSD0323 commands used here.
const CMD_SET_COLUMNS: u8 = 0x15;
const CMD_SET_ROWS: u8 = 0x75;
const CMD_DISPLAY_ON: u8 = 0xAF;

fn write_reg(addr: usize, value: u32) {
    // SAFETY: `addr` is one of this board's memory-mapped peripheral registers.
    unsafe { core::ptr::write_volatile(addr as *mut u32, value) }
}

fn read_reg(addr: usize) -> u32 {
    // SAFETY: as for `write_reg`.
    unsafe { core::ptr::read_volatile(addr as *const u32) }
}

/// Sets the pins in `mask` of a GPIO port to `high` (masked data register: the
/// address carries the mask, so other pins are untouched).
fn gpio_write(port: usize, mask: u32, high: bool) {
    write_reg(port + ((mask as usize) << 2), if high { mask } else { 0 });
}

/// The SSD0323 on SSI0 with its data/command line.
struct Oled;

impl Oled {
    fn init() -> Self {
        // Clocks for SSI0 and GPIO ports C and D.
        write_reg(SYSCTL_RCGC1, read_reg(SYSCTL_RCGC1) | (1 << 4));
        write_reg(SYSCTL_RCGC2, read_reg(SYSCTL_RCGC2) | (1 << 2) | (1 << 3));
        // PC7 (data/command) and PD0 (chip select) as outputs.
        write_reg(GPIO_C + GPIO_DIR, read_reg(GPIO_C + GPIO_DIR) | 0x80);
        write_reg(GPIO_C + GPIO_DEN, read_reg(GPIO_C + GPIO_DEN) | 0x80);
        write_reg(GPIO_D + GPIO_DIR, read_reg(GPIO_D + GPIO_DIR) | 0x01);
        write_reg(GPIO_D + GPIO_DEN, read_reg(GPIO_D + GPIO_DEN) | 0x01);
        gpio_write(GPIO_D, 0x01, true);
        // SSI0: master, 8-bit frames, SPI mode 3, enabled.
        write_reg(SSI0 + SSI_CR1, 0);
        write_reg(SSI0 + SSI_CR0, 0x07 | (1 << 6) | (1 << 7));
        write_reg(SSI0 + SSI_CPSR, 2);
        write_reg(SSI0 + SSI_CR1, 1 << 1);
        let mut oled = Oled;
        oled.command(&[CMD_DISPLAY_ON]);
        oled
    }

    /// Sends bytes; reads the data register back after each one, because the
    /// controller's receive FIFO must not fill (QEMU's PL022 stalls when it does).
    fn transfer(&mut self, bytes: &[u8]) {
        for &b in bytes {
            write_reg(SSI0 + SSI_DR, b as u32);
            while read_reg(SSI0 + SSI_SR) & SR_RNE == 0 {}
            let _ = read_reg(SSI0 + SSI_DR);
        }
    }

    fn command(&mut self, bytes: &[u8]) {
        gpio_write(GPIO_C, 0x80, false);
        self.transfer(bytes);
    }

    fn data(&mut self, bytes: &[u8]) {
        gpio_write(GPIO_C, 0x80, true);
        self.transfer(bytes);
    }
}

/// Streams each finished line to the OLED: a one-row window, then 64 bytes of
/// 4-bit gray (two pixels per byte, the left one in the high nibble). The
/// renderer resolves into `levels`, one gray level per pixel.
struct OledSink {
    oled: Oled,
    levels: [Gray4; WIDTH],
    bytes: [u8; WIDTH / 2],
}

impl LineSink for OledSink {
    type Pixel = Gray4;
    type Error = ();

    fn fill_line<F: FnOnce(&mut [Gray4])>(
        &mut self,
        y: u16,
        width: u16,
        fill: F,
    ) -> Result<(), ()> {
        let levels = self.levels.get_mut(..width as usize).ok_or(())?;
        fill(levels);
        for (byte, pair) in self.bytes.iter_mut().zip(levels.chunks(2)) {
            let left = pair[0].luma();
            let right = pair.get(1).map_or(0, |c| c.luma());
            *byte = (left << 4) | right;
        }
        let last_column = (WIDTH / 2 - 1) as u8;
        self.oled.command(&[
            CMD_SET_COLUMNS,
            0,
            last_column,
            CMD_SET_ROWS,
            y as u8,
            y as u8,
        ]);
        self.oled.data(&self.bytes);
        Ok(())
    }
}

struct Frame {
    sink: OledSink,
}

impl WithBuffers for Frame {
    fn run<M: CoverageMask, B: BandBuffer<M>>(
        mut self,
        buffer: &mut B,
        ws: &mut FrameWorkspace<'_>,
    ) {
        let options = FrameOptions::default();
        let start = ticks();
        match render_frame(&scene::SCENE, &options, ws, buffer, &mut self.sink, |_, _, _| {}) {
            Ok(stats) => defmt::info!(
                "frame out in {=u64} SysTick ticks: {=u32} fragments, {=u32} merges, pool peak {=u32}",
                ticks() - start,
                stats.buffer.fragments_generated,
                stats.buffer.merges,
                stats.buffer.pool_peak
            ),
            Err(_) => fail("render_frame failed"),
        }
    }
}

#[entry]
fn main() -> ! {
    const _: () = assert!(
        WIDTH == 128 && HEIGHT <= 80,
        "the SSD0323 shows 128 columns and up to 80 rows"
    );
    let mut core = match cortex_m::Peripherals::take() {
        Some(p) => p,
        None => fail("peripherals taken twice"),
    };
    guard_below_stack(&mut core.MPU);
    start_tick_counter(&mut core.SYST);
    let oled = Oled::init();
    with_buffers(Frame {
        sink: OledSink {
            oled,
            levels: [Gray4::BLACK; WIDTH],
            bytes: [0; WIDTH / 2],
        },
    });
    if let Ok(mut out) = hio::hstdout() {
        let _ = out.write_all(b"frame done\n");
    }
    loop {
        cortex_m::asm::wfi();
    }
}
