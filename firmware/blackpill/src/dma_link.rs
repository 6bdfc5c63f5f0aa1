//! The ST7789 link of the Black Pill: SPI1 as a transmit-only master, commands by
//! polling, pixel data by DMA2 stream 3 (channel 3 is SPI1_TX on the F411).

use crate::flushing_spi::{wait_idle, Spi1};
use abuffer_panel::link::PanelLink;
use core::sync::atomic::{compiler_fence, Ordering};
use embedded_hal::digital::OutputPin;
use embedded_hal::spi::SpiBus;
use stm32f4xx_hal::dma::traits::{Stream, StreamISR};
use stm32f4xx_hal::dma::{DmaChannel, DmaDataSize, DmaDirection, Stream3};
use stm32f4xx_hal::pac::{DMA2, SPI1};
use stm32f4xx_hal::spi;

/// Error of [`DmaPanelLink`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, defmt::Format)]
pub enum DmaLinkError {
    /// The SPI peripheral reported an error.
    Spi(spi::Error),
    /// More bytes than the buffer holds, or than one transfer can move (65535).
    Length,
}

/// Commands by polling, pixels by DMA; chip select low from a command's first byte
/// to the end of its parameters, and from the start of a pixel transfer to its end.
pub struct DmaPanelLink<CS, DC> {
    spi: Spi1,
    cs: CS,
    dc: DC,
    stream: Stream3<DMA2>,
    in_flight: Option<&'static mut [u8]>,
    wait_cycles: u64,
    transfer_errors: u32,
}

impl<CS: OutputPin, DC: OutputPin> DmaPanelLink<CS, DC> {
    /// A link over `spi` (configured), the pins, and DMA2 stream 3.
    pub fn new(spi: Spi1, cs: CS, dc: DC, mut stream: Stream3<DMA2>) -> Self {
        stream.set_channel(DmaChannel::Channel3);
        stream.set_direction(DmaDirection::MemoryToPeripheral);
        stream.set_memory_increment(true);
        stream.set_peripheral_increment(false);
        // SAFETY: byte transfers to the 8-bit data register from byte buffers.
        unsafe {
            stream.set_memory_size(DmaDataSize::Byte);
            stream.set_peripheral_size(DmaDataSize::Byte);
        }
        stream.set_peripheral_address(spi_data_register());
        Self {
            spi,
            cs,
            dc,
            stream,
            in_flight: None,
            wait_cycles: 0,
            transfer_errors: 0,
        }
    }

    /// Core cycles spent waiting for pixel transfers to finish since the last call
    /// (zero when rendering a band takes longer than sending one).
    pub fn take_wait_cycles(&mut self) -> u64 {
        core::mem::take(&mut self.wait_cycles)
    }

    /// Transfers the DMA reported as failed since reset.
    pub fn transfer_errors(&self) -> u32 {
        self.transfer_errors
    }

    fn write(&mut self, bytes: &[u8]) -> Result<(), DmaLinkError> {
        SpiBus::write(&mut self.spi, bytes).map_err(DmaLinkError::Spi)?;
        wait_idle(&self.spi);
        Ok(())
    }
}

fn spi_data_register() -> u32 {
    // SAFETY: only the register's address is taken.
    unsafe { (*SPI1::ptr()).dr().as_ptr() as u32 }
}

fn set_tx_dma(enabled: bool) {
    // SAFETY: one bit of SPI1's CR2 that the HAL driver does not use; only this
    // link touches it, never during a HAL transfer.
    unsafe { (*SPI1::ptr()).cr2().modify(|_, w| w.txdmaen().bit(enabled)) };
}

// Pin errors are infallible on this chip; they are dropped.
impl<CS: OutputPin, DC: OutputPin> PanelLink<'static> for DmaPanelLink<CS, DC> {
    type Error = DmaLinkError;

    fn command(&mut self, command: u8, parameters: &[u8]) -> Result<(), DmaLinkError> {
        let _ = self.cs.set_low();
        let _ = self.dc.set_low();
        let mut result = self.write(&[command]);
        if result.is_ok() && !parameters.is_empty() {
            let _ = self.dc.set_high();
            result = self.write(parameters);
        }
        let _ = self.cs.set_high();
        result
    }

    fn start_pixels(&mut self, buffer: &'static mut [u8], len: usize) -> Result<(), DmaLinkError> {
        if len > buffer.len() || len > u16::MAX as usize || len == 0 {
            return Err(DmaLinkError::Length);
        }
        let _ = self.cs.set_low();
        let _ = self.dc.set_high();
        self.stream.set_memory_address(buffer.as_ptr() as u32);
        self.stream.set_number_of_transfers(len as u16);
        self.stream.clear_transfer_complete();
        self.stream.clear_transfer_error();
        self.stream.clear_fifo_error();
        self.stream.clear_direct_mode_error();
        // The band's bytes are in memory before the DMA reads them.
        compiler_fence(Ordering::Release);
        // Stream first, then the SPI's request (the reference manual's order).
        // SAFETY: the stream is configured above and in `new`; the buffer is
        // 'static and held by the link until the transfer completes.
        unsafe { self.stream.enable() };
        set_tx_dma(true);
        self.in_flight = Some(buffer);
        Ok(())
    }

    fn finish_pixels(&mut self) -> Result<Option<&'static mut [u8]>, DmaLinkError> {
        let Some(buffer) = self.in_flight.take() else {
            return Ok(None);
        };
        let start = cortex_m::peripheral::DWT::cycle_count();
        while !self.stream.is_transfer_complete() {
            if self.stream.is_transfer_error() {
                // The band is lost on the screen (the next frame redraws it); the
                // buffer comes back so streaming goes on.
                self.transfer_errors += 1;
                defmt::warn!("DMA transfer error; band dropped");
                break;
            }
        }
        // The DMA has filled the data register for the last time; wait for the
        // last byte to leave before chip select rises.
        wait_idle(&self.spi);
        set_tx_dma(false);
        // SAFETY: the transfer is complete (or failed); stopping the stream is safe.
        unsafe { self.stream.disable() };
        while self.stream.is_enabled() {}
        self.stream.clear_transfer_complete();
        self.stream.clear_transfer_error();
        compiler_fence(Ordering::Acquire);
        let _ = self.cs.set_high();
        self.wait_cycles += cortex_m::peripheral::DWT::cycle_count().wrapping_sub(start) as u64;
        Ok(Some(buffer))
    }
}
