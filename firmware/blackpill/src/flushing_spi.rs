//! SPI1 of the Black Pill as a transmit-only master whose `flush` waits for
//! the wire, shared by the demo and the minimal example.

use embedded_hal::spi::SpiBus;
use stm32f4xx_hal::pac::SPI1;
use stm32f4xx_hal::spi::{self, Spi};

/// SPI1 in transmit-only (bidirectional output) mode, 8-bit frames.
pub type Spi1 = Spi<SPI1, true, u8>;

/// SPI1 whose `flush` waits until the last bit has left the shift register (the
/// HAL's returns at once), so chip select and data/command change only between
/// bytes. mipidsi's initialization runs through it.
pub struct FlushingSpi<'a>(pub &'a mut Spi1);

impl embedded_hal::spi::ErrorType for FlushingSpi<'_> {
    type Error = spi::Error;
}

impl SpiBus<u8> for FlushingSpi<'_> {
    fn read(&mut self, words: &mut [u8]) -> Result<(), spi::Error> {
        SpiBus::read(self.0, words)
    }
    fn write(&mut self, words: &[u8]) -> Result<(), spi::Error> {
        SpiBus::write(self.0, words)
    }
    fn transfer(&mut self, read: &mut [u8], write: &[u8]) -> Result<(), spi::Error> {
        SpiBus::transfer(self.0, read, write)
    }
    fn transfer_in_place(&mut self, words: &mut [u8]) -> Result<(), spi::Error> {
        SpiBus::transfer_in_place(self.0, words)
    }
    fn flush(&mut self) -> Result<(), spi::Error> {
        wait_idle(self.0);
        Ok(())
    }
}

/// Waits until SPI1 has sent its last bit.
pub fn wait_idle(spi: &Spi1) {
    while !spi.is_tx_empty() || spi.is_busy() {}
}
