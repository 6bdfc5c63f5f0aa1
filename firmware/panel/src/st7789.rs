//! ST7789 commands used by the stream, and the encoding of a drawing window.
//!
//! The controller takes a command byte with the data/command line low, then its
//! parameters with the line high. A window is set by `CASET` (first and last
//! column) and `RASET` (first and last row), each as two big-endian 16-bit
//! values; `RAMWR` then writes pixels into the window row by row. In the 16-bit
//! color mode (`COLMOD` 0x55) a pixel is two bytes, RGB565 big-endian.

/// Software reset.
pub const SWRESET: u8 = 0x01;
/// Leave sleep mode.
pub const SLPOUT: u8 = 0x11;
/// Normal display mode on.
pub const NORON: u8 = 0x13;
/// Display inversion off.
pub const INVOFF: u8 = 0x20;
/// Display inversion on (most 240x240 IPS modules need it for true colors).
pub const INVON: u8 = 0x21;
/// Display off.
pub const DISPOFF: u8 = 0x28;
/// Display on.
pub const DISPON: u8 = 0x29;
/// Column address set: first and last column of the window.
pub const CASET: u8 = 0x2A;
/// Row address set: first and last row of the window.
pub const RASET: u8 = 0x2B;
/// Memory write: pixel data for the window follows.
pub const RAMWR: u8 = 0x2C;
/// Memory data access control (row/column order and exchange, RGB/BGR).
pub const MADCTL: u8 = 0x36;
/// Interface pixel format.
pub const COLMOD: u8 = 0x3A;

/// `COLMOD` parameter for 16 bits per pixel (RGB565) on the interface and panel.
pub const COLMOD_RGB565: u8 = 0x55;

/// Parameters of `CASET` or `RASET` for the inclusive range `first..=last`.
pub fn address_range(first: u16, last: u16) -> [u8; 4] {
    let [f0, f1] = first.to_be_bytes();
    let [l0, l1] = last.to_be_bytes();
    [f0, f1, l0, l1]
}

/// The two bytes of an RGB565 pixel in the order the controller takes them.
pub fn pixel_bytes(rgb565: u16) -> [u8; 2] {
    rgb565.to_be_bytes()
}

/// Error of [`initialize`].
pub type InitError<SPI, DC, RST> = mipidsi::InitError<
    mipidsi::interface::SpiError<
        <SPI as embedded_hal::spi::ErrorType>::Error,
        <DC as embedded_hal::digital::ErrorType>::Error,
    >,
    <RST as embedded_hal::digital::ErrorType>::Error,
>;

/// Brings an ST7789 module out of reset into the state the stream expects, through
/// the mipidsi driver: hardware reset, sleep out, 16-bit RGB565 color, default
/// orientation (`MADCTL` 0), inversion on when `inverted` (most 240 x 240 IPS
/// modules show true colors only with it), normal mode, display on.
///
/// `width` x `height` is the visible area (at most 240 x 320). The SPI device and
/// the data/command pin come back for the stream; mipidsi keeps nothing.
pub fn initialize<SPI, DC, RST, D>(
    spi: SPI,
    data_command: DC,
    reset: RST,
    delay: &mut D,
    width: u16,
    height: u16,
    inverted: bool,
) -> Result<(SPI, DC), InitError<SPI, DC, RST>>
where
    SPI: embedded_hal::spi::SpiDevice,
    DC: embedded_hal::digital::OutputPin,
    RST: embedded_hal::digital::OutputPin,
    D: embedded_hal::delay::DelayNs,
{
    use mipidsi::options::ColorInversion;
    // mipidsi stages pixel data here; initialization sends no pixels.
    let mut staging = [0u8; 16];
    let interface = mipidsi::interface::SpiInterface::new(spi, data_command, &mut staging);
    let display = mipidsi::Builder::new(mipidsi::models::ST7789, interface)
        .display_size(width, height)
        .invert_colors(if inverted {
            ColorInversion::Inverted
        } else {
            ColorInversion::Normal
        })
        .reset_pin(reset)
        .init(delay)?;
    let (interface, _model, _reset) = display.release();
    Ok(interface.release())
}
