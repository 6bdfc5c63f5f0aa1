//! Where resolved lines go: the [`LineSink`] trait, whose sinks hand the
//! renderer their own memory to resolve each line into, in their own pixel
//! format ([`LinePixel`]: the big-endian RGB565 of SPI displays, the packed
//! RGB888 of image files, embedded-graphics' colors); an adapter for any
//! embedded-graphics display; and an in-memory image.

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Point, Size};
use embedded_graphics_core::pixelcolor::raw::{RawData, RawU16};
use embedded_graphics_core::pixelcolor::{Gray4, GrayColor, Rgb565, Rgb888, RgbColor};
use embedded_graphics_core::primitives::Rectangle;

/// A pixel format a sink's lines are written in (a display's, an image
/// file's): the renderer converts each resolved color once, as it writes it
/// into the sink's line, so a line goes out with no pass of its own. A
/// z-buffer can keep its colors in the format too
/// ([`crate::ZBuffer`]), so that its rows go out as a copy.
pub trait LinePixel: Copy + 'static {
    /// The pixel of black (named apart from the color traits' `BLACK`,
    /// which the same types have).
    const BLACK_PIXEL: Self;

    /// The pixel of 8-bit channels `r`, `g`, `b`.
    fn from_channels(r: u8, g: u8, b: u8) -> Self;

    /// The color the pixel shows, in 8-bit channels (what a format with
    /// fewer bits keeps of a color, scaled up).
    fn to_rgb888(self) -> Rgb888;

    /// The pixel showing `c`.
    #[inline(always)]
    fn from_rgb888(c: Rgb888) -> Self {
        Self::from_channels(c.r(), c.g(), c.b())
    }

    /// Sets the pixel to the one showing `c` (a format may store its parts
    /// one by one).
    #[inline(always)]
    fn set_rgb888(&mut self, c: Rgb888) {
        *self = Self::from_rgb888(c);
    }

    /// Sets every pixel of `line` to `value` (a format may write several
    /// pixels at once).
    #[inline(always)]
    fn fill(line: &mut [Self], value: Self) {
        line.fill(value);
    }

    /// Copies `src` into `dst` (of the same length; a format may copy
    /// several pixels at once).
    #[inline(always)]
    fn copy_line(dst: &mut [Self], src: &[Self]) {
        dst.copy_from_slice(src);
    }
}

impl LinePixel for Rgb888 {
    const BLACK_PIXEL: Self = <Rgb888 as RgbColor>::BLACK;

    #[inline(always)]
    fn from_channels(r: u8, g: u8, b: u8) -> Self {
        Rgb888::new(r, g, b)
    }

    #[inline(always)]
    fn to_rgb888(self) -> Rgb888 {
        self
    }

    #[inline(always)]
    fn from_rgb888(c: Rgb888) -> Self {
        c
    }
}

impl LinePixel for Rgb565 {
    const BLACK_PIXEL: Self = <Rgb565 as RgbColor>::BLACK;

    #[inline(always)]
    fn from_channels(r: u8, g: u8, b: u8) -> Self {
        Rgb565::from(Rgb888::new(r, g, b))
    }

    #[inline(always)]
    fn to_rgb888(self) -> Rgb888 {
        Rgb888::from(self)
    }
}

impl LinePixel for Gray4 {
    const BLACK_PIXEL: Self = <Gray4 as GrayColor>::BLACK;

    #[inline(always)]
    fn from_channels(r: u8, g: u8, b: u8) -> Self {
        Gray4::new(gray4(Rgb888::new(r, g, b)))
    }

    #[inline(always)]
    fn to_rgb888(self) -> Rgb888 {
        Rgb888::from(self)
    }
}

/// Pixel formats that are plain bytes (`#[repr(transparent)]` over a byte
/// array), so that a line of them is a byte slice and back.
macro_rules! byte_pixel {
    ($name:ident, $bytes:expr) => {
        impl $name {
            /// Bytes of one pixel.
            pub const BYTES: usize = $bytes;

            /// The bytes of `line`, pixel after pixel.
            #[inline]
            pub fn line_bytes(line: &[Self]) -> &[u8] {
                // SAFETY: `Self` is `#[repr(transparent)]` over `[u8; BYTES]`:
                // size `BYTES`, alignment 1, every byte initialized.
                unsafe {
                    core::slice::from_raw_parts(line.as_ptr().cast::<u8>(), line.len() * $bytes)
                }
            }

            /// The bytes of `line`, mutably.
            #[inline]
            pub fn line_bytes_mut(line: &mut [Self]) -> &mut [u8] {
                // SAFETY: as in `line_bytes`; the bytes borrow `line`
                // mutably for their life.
                unsafe {
                    core::slice::from_raw_parts_mut(
                        line.as_mut_ptr().cast::<u8>(),
                        line.len() * $bytes,
                    )
                }
            }

            /// `bytes` as pixels (whole pixels from the start; a partial
            /// last pixel is left out).
            #[inline]
            pub fn line_from_bytes_mut(bytes: &mut [u8]) -> &mut [Self] {
                let n = bytes.len() / $bytes;
                // SAFETY: as in `line_bytes`, and every byte pattern is a
                // pixel; the slice borrows `bytes` mutably for its life.
                unsafe { core::slice::from_raw_parts_mut(bytes.as_mut_ptr().cast::<Self>(), n) }
            }
        }
    };
}

/// An RGB888 pixel as three bytes, red, green, blue: how binary PPM and PNG
/// files store a line ([`Rgb888`] itself takes a 32-bit word).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(transparent)]
pub struct PackedRgb888(pub [u8; 3]);

byte_pixel!(PackedRgb888, 3);

impl LinePixel for PackedRgb888 {
    const BLACK_PIXEL: Self = Self([0; 3]);

    #[inline(always)]
    fn from_channels(r: u8, g: u8, b: u8) -> Self {
        Self([r, g, b])
    }

    /// Three byte stores: stored as one value, the three bytes are first
    /// packed into a word and stored as a half-word and a byte.
    #[inline(always)]
    fn set_rgb888(&mut self, c: Rgb888) {
        self.0[0] = c.r();
        self.0[1] = c.g();
        self.0[2] = c.b();
    }

    #[inline(always)]
    fn to_rgb888(self) -> Rgb888 {
        let [r, g, b] = self.0;
        Rgb888::new(r, g, b)
    }

    /// Whole words where the line allows it ([`crate::words::fill_repeating`]).
    #[inline(always)]
    fn fill(line: &mut [Self], value: Self) {
        crate::words::fill_repeating(Self::line_bytes_mut(line), value.0);
    }

    /// Whole words where both lines allow it ([`crate::words::copy_bytes`]).
    #[inline(always)]
    fn copy_line(dst: &mut [Self], src: &[Self]) {
        crate::words::copy_bytes(Self::line_bytes_mut(dst), Self::line_bytes(src));
    }
}

/// An RGB565 pixel as two bytes, the high byte first: how SPI displays
/// (ST7789, ILI9341, ...) take a line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(transparent)]
pub struct Rgb565BigEndian(pub [u8; 2]);

byte_pixel!(Rgb565BigEndian, 2);

impl LinePixel for Rgb565BigEndian {
    const BLACK_PIXEL: Self = Self([0; 2]);

    #[inline(always)]
    fn to_rgb888(self) -> Rgb888 {
        Rgb888::from(Rgb565::from(RawU16::new(u16::from_be_bytes(self.0))))
    }

    #[inline(always)]
    fn from_channels(r: u8, g: u8, b: u8) -> Self {
        Self(
            RawU16::from(Rgb565::from_channels(r, g, b))
                .into_inner()
                .to_be_bytes(),
        )
    }

    /// Whole words where both lines allow it ([`crate::words::copy_bytes`]).
    #[inline(always)]
    fn copy_line(dst: &mut [Self], src: &[Self]) {
        crate::words::copy_bytes(Self::line_bytes_mut(dst), Self::line_bytes(src));
    }

    /// Whole words where the line allows it ([`crate::words::fill_repeating`]).
    #[inline(always)]
    fn fill(line: &mut [Self], value: Self) {
        crate::words::fill_repeating(Self::line_bytes_mut(line), value.0);
    }
}

/// Receives the picture one finished line at a time, top to bottom within a
/// band, in its own pixel format and in its own memory: the renderer writes
/// each line straight into the buffer the sink hands it (a DMA buffer, a row
/// of an image), with no line of its own and no copy.
pub trait LineSink {
    /// The pixel format of the lines.
    type Pixel: LinePixel;
    /// Error of the underlying device.
    type Error;

    /// Hands `fill` a line of `width` pixels for image row `y` to write every
    /// pixel of, then takes the line. A sink that cannot take such a line
    /// (a row beyond its image, another width) returns an error without
    /// calling `fill`.
    fn fill_line<F: FnOnce(&mut [Self::Pixel])>(
        &mut self,
        y: u16,
        width: u16,
        fill: F,
    ) -> Result<(), Self::Error>;

    /// Takes image row `y` from colors: [`LineSink::fill_line`] with each
    /// color converted (for lines that exist as colors already).
    fn write_line(&mut self, y: u16, pixels: &[Rgb888]) -> Result<(), Self::Error> {
        let width = u16::try_from(pixels.len()).unwrap_or(u16::MAX);
        self.fill_line(y, width, |line| convert_line(pixels, line))
    }
}

/// Writes `colors` into `line` in its pixel format (as far as both reach).
#[inline]
pub fn convert_line<P: LinePixel>(colors: &[Rgb888], line: &mut [P]) {
    for (dst, &c) in line.iter_mut().zip(colors) {
        *dst = P::from_rgb888(c);
    }
}

/// The 4-bit gray level (0 to 15) of a color, as 4-bit gray displays show it:
/// luma `(77 R + 150 G + 29 B) / 256` (ITU-R BT.601 weights), rounded, then scaled
/// to 15 levels with rounding.
#[inline]
pub fn gray4(c: Rgb888) -> u8 {
    let luma = (77 * c.r() as u32 + 150 * c.g() as u32 + 29 * c.b() as u32 + 128) >> 8;
    ((luma * 15 + 127) / 255) as u8
}

/// Streams lines to any embedded-graphics [`DrawTarget`] with RGB565 pixels
/// (an SPI display driver, a simulator window, a framebuffer), through a
/// line of at most `WIDTH` pixels that the sink keeps.
pub struct DrawTargetSink<'a, D, const WIDTH: usize> {
    target: &'a mut D,
    line: [Rgb565; WIDTH],
}

impl<'a, D, const WIDTH: usize> DrawTargetSink<'a, D, WIDTH>
where
    D: DrawTarget<Color = Rgb565>,
{
    /// Wraps a draw target, for lines of at most `WIDTH` pixels.
    pub fn new(target: &'a mut D) -> Self {
        Self {
            target,
            line: [<Rgb565 as RgbColor>::BLACK; WIDTH],
        }
    }
}

/// Why a [`DrawTargetSink`] did not take a line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrawTargetSinkError<E> {
    /// The draw target failed.
    Target(E),
    /// The line is wider than the sink's line.
    TooWide {
        /// Pixels asked for.
        width: u16,
        /// Pixels the sink's line holds.
        line: usize,
    },
}

impl<D, const WIDTH: usize> LineSink for DrawTargetSink<'_, D, WIDTH>
where
    D: DrawTarget<Color = Rgb565>,
{
    type Pixel = Rgb565;
    type Error = DrawTargetSinkError<D::Error>;

    fn fill_line<F: FnOnce(&mut [Rgb565])>(
        &mut self,
        y: u16,
        width: u16,
        fill: F,
    ) -> Result<(), Self::Error> {
        let line = self
            .line
            .get_mut(..width as usize)
            .ok_or(DrawTargetSinkError::TooWide { width, line: WIDTH })?;
        fill(line);
        let area = Rectangle::new(Point::new(0, y as i32), Size::new(width as u32, 1));
        self.target
            .fill_contiguous(&area, line.iter().copied())
            .map_err(DrawTargetSinkError::Target)
    }
}

/// Writes lines into a caller-owned RGB888 image (3 bytes per pixel, rows top
/// to bottom): the renderer resolves each line into the image's row itself.
pub struct ImageSink<'a> {
    width: u16,
    pixels: &'a mut [u8],
}

/// A line did not fit the image: a row beyond it, or another width.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OutOfImage {
    /// The row that was written.
    pub y: u16,
}

impl<'a> ImageSink<'a> {
    /// An image `width` pixels wide over `pixels` (length a multiple of `3 * width`).
    pub fn new(width: u16, pixels: &'a mut [u8]) -> Self {
        Self { width, pixels }
    }
}

impl LineSink for ImageSink<'_> {
    type Pixel = PackedRgb888;
    type Error = OutOfImage;

    fn fill_line<F: FnOnce(&mut [PackedRgb888])>(
        &mut self,
        y: u16,
        width: u16,
        fill: F,
    ) -> Result<(), OutOfImage> {
        if width != self.width {
            return Err(OutOfImage { y });
        }
        let row_bytes = width as usize * PackedRgb888::BYTES;
        let start = y as usize * row_bytes;
        let row = self
            .pixels
            .get_mut(start..start + row_bytes)
            .ok_or(OutOfImage { y })?;
        fill(PackedRgb888::line_from_bytes_mut(row));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use embedded_graphics_core::geometry::{Dimensions, OriginDimensions};
    use embedded_graphics_core::pixelcolor::GrayColor;
    use embedded_graphics_core::Pixel;

    struct Screen {
        pixels: [[Rgb565; 4]; 2],
    }

    impl OriginDimensions for Screen {
        fn size(&self) -> Size {
            Size::new(4, 2)
        }
    }

    impl DrawTarget for Screen {
        type Color = Rgb565;
        type Error = core::convert::Infallible;
        fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(
            &mut self,
            pixels: I,
        ) -> Result<(), Self::Error> {
            for Pixel(p, c) in pixels {
                if self.bounding_box().contains(p) {
                    self.pixels[p.y as usize][p.x as usize] = c;
                }
            }
            Ok(())
        }
    }

    #[test]
    fn draw_target_receives_lines_in_rgb565() {
        let mut screen = Screen {
            pixels: [[Rgb565::BLACK; 4]; 2],
        };
        let line = [
            Rgb888::new(255, 0, 0),
            Rgb888::new(0, 255, 0),
            Rgb888::new(0, 0, 255),
            Rgb888::WHITE,
        ];
        DrawTargetSink::<_, 4>::new(&mut screen)
            .write_line(1, &line)
            .unwrap();
        assert_eq!(screen.pixels[0], [Rgb565::BLACK; 4]);
        assert_eq!(
            screen.pixels[1],
            [Rgb565::RED, Rgb565::GREEN, Rgb565::BLUE, Rgb565::WHITE]
        );
    }

    #[test]
    fn draw_target_sink_refuses_lines_wider_than_its_own() {
        let mut screen = Screen {
            pixels: [[Rgb565::BLACK; 4]; 2],
        };
        let mut sink = DrawTargetSink::<_, 3>::new(&mut screen);
        let mut filled = false;
        assert_eq!(
            sink.fill_line(0, 4, |_| filled = true),
            Err(DrawTargetSinkError::TooWide { width: 4, line: 3 })
        );
        assert!(!filled);
        sink.write_line(0, &[Rgb888::WHITE; 3]).unwrap();
        assert_eq!(
            screen.pixels[0],
            [Rgb565::WHITE, Rgb565::WHITE, Rgb565::WHITE, Rgb565::BLACK]
        );
    }

    #[test]
    fn byte_pixels_are_their_bytes() {
        let c = Rgb888::new(0xF8, 0xFC, 0x08);
        assert_eq!(PackedRgb888::from_rgb888(c).0, [0xF8, 0xFC, 0x08]);
        // RGB565, red in the high bits, high byte first.
        let be = |r, g, b| Rgb565BigEndian::from_channels(r, g, b).0;
        assert_eq!(be(255, 0, 0), [0xF8, 0x00]);
        assert_eq!(be(0, 255, 0), [0x07, 0xE0]);
        assert_eq!(be(0, 0, 255), [0x00, 0x1F]);
        assert_eq!(be(255, 255, 255), [0xFF, 0xFF]);
        // Four pixels at a time, and the rest one by one.
        let mut line = [PackedRgb888::default(); 6];
        PackedRgb888::fill(&mut line, PackedRgb888([9, 8, 7]));
        assert_eq!(line, [PackedRgb888([9, 8, 7]); 6]);
        let line = [PackedRgb888([1, 2, 3]), PackedRgb888([4, 5, 6])];
        assert_eq!(PackedRgb888::line_bytes(&line), &[1, 2, 3, 4, 5, 6]);
        let mut bytes = [0u8; 5];
        let pixels = Rgb565BigEndian::line_from_bytes_mut(&mut bytes);
        assert_eq!(pixels.len(), 2);
        pixels[1] = Rgb565BigEndian([7, 8]);
        assert_eq!(bytes, [0, 0, 7, 8, 0]);
        assert_eq!(Gray4::from_rgb888(Rgb888::WHITE).luma(), 15);
    }

    #[test]
    fn gray4_levels() {
        assert_eq!(gray4(Rgb888::BLACK), 0);
        assert_eq!(gray4(Rgb888::WHITE), 15);
        assert_eq!(gray4(Rgb888::new(128, 128, 128)), 8);
        assert_eq!(gray4(Rgb888::new(0, 255, 0)), 9);
    }

    #[test]
    fn image_sink_writes_rows_and_refuses_rows_beyond() {
        let mut bytes = [0u8; 2 * 2 * 3];
        let mut sink = ImageSink::new(2, &mut bytes);
        sink.write_line(1, &[Rgb888::new(1, 2, 3), Rgb888::new(4, 5, 6)])
            .unwrap();
        assert_eq!(
            sink.write_line(2, &[Rgb888::BLACK; 2]),
            Err(OutOfImage { y: 2 })
        );
        assert_eq!(
            sink.write_line(0, &[Rgb888::BLACK; 3]),
            Err(OutOfImage { y: 0 })
        );
        assert_eq!(bytes, [0, 0, 0, 0, 0, 0, 1, 2, 3, 4, 5, 6]);
    }

    /// Byte pixels copy as their bytes, word-aligned or not.
    #[test]
    fn byte_pixel_lines_copy_whole() {
        let pixels: [PackedRgb888; 9] = core::array::from_fn(|i| PackedRgb888([i as u8, 1, 2]));
        let mut line = [PackedRgb888::BLACK_PIXEL; 9];
        PackedRgb888::copy_line(&mut line, &pixels);
        assert_eq!(line, pixels);
        let pixels: [Rgb565BigEndian; 21] = core::array::from_fn(|i| Rgb565BigEndian([i as u8, 9]));
        let mut line = [Rgb565BigEndian::BLACK_PIXEL; 21];
        Rgb565BigEndian::copy_line(&mut line, &pixels);
        assert_eq!(line, pixels);
    }

    /// Byte pixels fill as the slice's own fill would.
    #[test]
    fn byte_pixel_lines_fill_whole() {
        for len in 0..30 {
            let value = PackedRgb888([9, 8, 7]);
            let mut line = [PackedRgb888::BLACK_PIXEL; 30];
            PackedRgb888::fill(&mut line[1..1 + len], value);
            let mut expected = [PackedRgb888::BLACK_PIXEL; 30];
            expected[1..1 + len].fill(value);
            assert_eq!(line, expected);
            let value = Rgb565BigEndian([0xF8, 0x1F]);
            let mut line = [Rgb565BigEndian::BLACK_PIXEL; 30];
            Rgb565BigEndian::fill(&mut line[1..1 + len], value);
            let mut expected = [Rgb565BigEndian::BLACK_PIXEL; 30];
            expected[1..1 + len].fill(value);
            assert_eq!(line, expected);
        }
    }
}
