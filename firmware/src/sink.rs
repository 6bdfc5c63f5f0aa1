//! Where resolved lines go: a small trait, an adapter for any embedded-graphics
//! display, and an in-memory image.

use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Point, Size};
use embedded_graphics_core::pixelcolor::{Rgb565, Rgb888, RgbColor};
use embedded_graphics_core::primitives::Rectangle;

/// Receives the picture one finished line at a time, top to bottom within a band.
pub trait LineSink {
    /// Error of the underlying device.
    type Error;
    /// Takes image row `y`.
    fn write_line(&mut self, y: u16, pixels: &[Rgb888]) -> Result<(), Self::Error>;
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
/// (an SPI display driver, a simulator window, a framebuffer).
pub struct DrawTargetSink<'a, D> {
    target: &'a mut D,
}

impl<'a, D> DrawTargetSink<'a, D>
where
    D: DrawTarget<Color = Rgb565>,
{
    /// Wraps a draw target.
    pub fn new(target: &'a mut D) -> Self {
        Self { target }
    }
}

impl<D> LineSink for DrawTargetSink<'_, D>
where
    D: DrawTarget<Color = Rgb565>,
{
    type Error = D::Error;

    fn write_line(&mut self, y: u16, pixels: &[Rgb888]) -> Result<(), Self::Error> {
        let area = Rectangle::new(Point::new(0, y as i32), Size::new(pixels.len() as u32, 1));
        self.target
            .fill_contiguous(&area, pixels.iter().map(|&c| Rgb565::from(c)))
    }
}

/// Writes lines into a caller-owned RGB888 image (3 bytes per pixel, rows top to bottom).
pub struct ImageSink<'a> {
    width: u16,
    pixels: &'a mut [u8],
}

/// A line did not fit the image.
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
    type Error = OutOfImage;

    fn write_line(&mut self, y: u16, line: &[Rgb888]) -> Result<(), OutOfImage> {
        let w = self.width as usize;
        let start = y as usize * w * 3;
        let row = self
            .pixels
            .get_mut(start..start + w * 3)
            .ok_or(OutOfImage { y })?;
        for (dst, c) in row.chunks_exact_mut(3).zip(line) {
            dst.copy_from_slice(&[c.r(), c.g(), c.b()]);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use embedded_graphics_core::geometry::{Dimensions, OriginDimensions};
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
        DrawTargetSink::new(&mut screen)
            .write_line(1, &line)
            .unwrap();
        assert_eq!(screen.pixels[0], [Rgb565::BLACK; 4]);
        assert_eq!(
            screen.pixels[1],
            [Rgb565::RED, Rgb565::GREEN, Rgb565::BLUE, Rgb565::WHITE]
        );
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
        assert_eq!(bytes, [0, 0, 0, 0, 0, 0, 1, 2, 3, 4, 5, 6]);
    }
}
