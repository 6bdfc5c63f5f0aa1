//! How bytes reach the panel.
//!
//! A [`PanelLink`] sends commands (blocking) and pixel data (possibly in the
//! background). The stream calls it in a fixed order: commands only while no pixel
//! transfer is in flight, then [`PanelLink::start_pixels`], which may return at once;
//! the buffer stays with the link until [`PanelLink::finish_pixels`] hands it back.
//! Passing the buffer by value makes the overlap safe: nothing can write into a band
//! while it is being sent.
//!
//! [`SpiPanelLink`] is the portable implementation over embedded-hal 1.0: any
//! `SpiDevice` plus the data/command pin. It sends the pixels before
//! `start_pixels` returns, so it has no overlap; a board with DMA implements the
//! trait itself (the STM32F411 firmware in `firmware/blackpill` does).

use embedded_hal::digital::OutputPin;
use embedded_hal::spi::SpiDevice;

/// A way to send commands and pixel data to the display controller.
///
/// `'buf` is the lifetime of the band buffers; a link that keeps sending after
/// `start_pixels` returns (DMA) needs `'static` buffers.
pub trait PanelLink<'buf> {
    /// Error of the bus or pins.
    type Error;

    /// Sends a command byte and its parameter bytes. Never called while a pixel
    /// transfer is in flight.
    fn command(&mut self, command: u8, parameters: &[u8]) -> Result<(), Self::Error>;

    /// Starts sending the first `len` bytes of `buffer` as pixel data (after a
    /// memory-write command). The link keeps `buffer` until
    /// [`finish_pixels`](Self::finish_pixels).
    fn start_pixels(&mut self, buffer: &'buf mut [u8], len: usize) -> Result<(), Self::Error>;

    /// Waits until the transfer started last has left, and returns its buffer;
    /// `None` when no transfer was started since the last call.
    fn finish_pixels(&mut self) -> Result<Option<&'buf mut [u8]>, Self::Error>;
}

/// Error of [`SpiPanelLink`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SpiLinkError<S, P> {
    /// The SPI device failed.
    Spi(S),
    /// The data/command pin failed.
    DataCommand(P),
    /// `start_pixels` was given more bytes than its buffer holds.
    Length,
}

/// A blocking [`PanelLink`] over an embedded-hal 1.0 [`SpiDevice`] and the
/// data/command [`OutputPin`] (low: command, high: data).
pub struct SpiPanelLink<'buf, SPI, DC> {
    spi: SPI,
    dc: DC,
    sent: Option<&'buf mut [u8]>,
}

impl<'buf, SPI, DC> SpiPanelLink<'buf, SPI, DC>
where
    SPI: SpiDevice,
    DC: OutputPin,
{
    /// A link over `spi` with the data/command pin `dc`.
    pub fn new(spi: SPI, dc: DC) -> Self {
        Self {
            spi,
            dc,
            sent: None,
        }
    }

    /// Gives back the SPI device and the pin (and a band buffer still held, if any).
    pub fn release(self) -> (SPI, DC, Option<&'buf mut [u8]>) {
        (self.spi, self.dc, self.sent)
    }
}

impl<'buf, SPI, DC> PanelLink<'buf> for SpiPanelLink<'buf, SPI, DC>
where
    SPI: SpiDevice,
    DC: OutputPin,
{
    type Error = SpiLinkError<SPI::Error, DC::Error>;

    fn command(&mut self, command: u8, parameters: &[u8]) -> Result<(), Self::Error> {
        self.dc.set_low().map_err(SpiLinkError::DataCommand)?;
        self.spi.write(&[command]).map_err(SpiLinkError::Spi)?;
        if !parameters.is_empty() {
            self.dc.set_high().map_err(SpiLinkError::DataCommand)?;
            self.spi.write(parameters).map_err(SpiLinkError::Spi)?;
        }
        Ok(())
    }

    fn start_pixels(&mut self, buffer: &'buf mut [u8], len: usize) -> Result<(), Self::Error> {
        let data = buffer.get(..len).ok_or(SpiLinkError::Length)?;
        self.dc.set_high().map_err(SpiLinkError::DataCommand)?;
        self.spi.write(data).map_err(SpiLinkError::Spi)?;
        self.sent = Some(buffer);
        Ok(())
    }

    fn finish_pixels(&mut self) -> Result<Option<&'buf mut [u8]>, Self::Error> {
        Ok(self.sent.take())
    }
}
