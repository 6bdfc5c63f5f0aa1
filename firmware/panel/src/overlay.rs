//! Text drawn into a band before it is sent: the frame-rate overlay.
//!
//! The renderer never holds a whole frame, so the overlay is drawn band by band:
//! [`BandCanvas`] is an embedded-graphics [`DrawTarget`] over one band buffer that
//! takes frame coordinates and keeps only the pixels inside the band. Text crossing
//! a band boundary is drawn in pieces, one per band, and joins up on the panel.

use core::fmt;
use embedded_graphics::mono_font::ascii::FONT_6X10;
use embedded_graphics::mono_font::MonoTextStyleBuilder;
use embedded_graphics::pixelcolor::raw::RawU16;
use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use embedded_graphics::prelude::*;
use embedded_graphics::text::{Baseline, Text};

/// A band buffer (RGB565, big-endian, `width` pixels per row) seen as a drawing
/// surface in frame coordinates: rows `first_row..first_row + rows` are inside.
pub struct BandCanvas<'a> {
    pixels: &'a mut [u8],
    width: u16,
    frame_height: u16,
    first_row: u16,
    rows: u16,
}

impl<'a> BandCanvas<'a> {
    /// A canvas over `pixels`, which holds `rows` rows of `width` pixels starting
    /// at frame row `first_row`, in a frame `frame_height` rows high.
    ///
    /// Rows that `pixels` is too short for are treated as outside the band.
    pub fn new(
        pixels: &'a mut [u8],
        width: u16,
        frame_height: u16,
        first_row: u16,
        rows: u16,
    ) -> Self {
        let fit = if width == 0 {
            0
        } else {
            pixels.len() / (2 * width as usize)
        };
        let rows = rows.min(fit.min(u16::MAX as usize) as u16);
        Self {
            pixels,
            width,
            frame_height,
            first_row,
            rows,
        }
    }
}

impl OriginDimensions for BandCanvas<'_> {
    fn size(&self) -> Size {
        Size::new(self.width as u32, self.frame_height as u32)
    }
}

impl DrawTarget for BandCanvas<'_> {
    type Color = Rgb565;
    type Error = core::convert::Infallible;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Pixel<Self::Color>>,
    {
        let first = self.first_row as i32;
        let end = first + self.rows as i32;
        for Pixel(point, color) in pixels {
            if point.x < 0 || point.x >= self.width as i32 || point.y < first || point.y >= end {
                continue;
            }
            let index = 2 * ((point.y - first) as usize * self.width as usize + point.x as usize);
            let raw: u16 = RawU16::from(color).into_inner();
            self.pixels[index..index + 2].copy_from_slice(&raw.to_be_bytes());
        }
        Ok(())
    }
}

/// Capacity of the overlay text, in bytes.
pub const OVERLAY_TEXT_BYTES: usize = 40;

/// One line of text at a fixed place in the frame, white on black (6x10 font).
#[derive(Clone, Debug)]
pub struct TextOverlay {
    text: [u8; OVERLAY_TEXT_BYTES],
    len: usize,
    position: Point,
    enabled: bool,
}

impl Default for TextOverlay {
    fn default() -> Self {
        Self::new(Point::new(2, 2))
    }
}

impl TextOverlay {
    /// An empty overlay whose text has its top-left corner at `position`.
    pub const fn new(position: Point) -> Self {
        Self {
            text: [0; OVERLAY_TEXT_BYTES],
            len: 0,
            position,
            enabled: true,
        }
    }

    /// Turns drawing on or off (off: bands are sent exactly as rendered).
    pub fn set_enabled(&mut self, enabled: bool) {
        self.enabled = enabled;
    }

    /// Whether the overlay is drawn.
    pub fn enabled(&self) -> bool {
        self.enabled
    }

    /// The text shown now.
    pub fn text(&self) -> &str {
        // Only whole characters are ever stored (see `write_str`).
        core::str::from_utf8(&self.text[..self.len]).unwrap_or("")
    }

    /// Replaces the text with what `args` formats to (cut at
    /// [`OVERLAY_TEXT_BYTES`], on a character boundary).
    pub fn set_text(&mut self, args: fmt::Arguments<'_>) {
        self.len = 0;
        // Writing into the fixed buffer never fails; overflow is cut off.
        let _ = fmt::write(self, args);
    }

    /// The rectangle the text covers in the frame.
    pub fn bounding_box(&self) -> embedded_graphics::primitives::Rectangle {
        self.styled_text().bounding_box()
    }

    fn styled_text(
        &self,
    ) -> Text<'_, embedded_graphics::mono_font::MonoTextStyle<'static, Rgb565>> {
        let style = MonoTextStyleBuilder::new()
            .font(&FONT_6X10)
            .text_color(Rgb565::WHITE)
            .background_color(Rgb565::BLACK)
            .build();
        Text::with_baseline(self.text(), self.position, style, Baseline::Top)
    }

    /// Draws the text on `target` (the part inside it); does nothing when
    /// disabled or empty.
    pub fn draw<D: DrawTarget<Color = Rgb565>>(&self, target: &mut D) -> Result<(), D::Error> {
        if self.enabled && self.len > 0 {
            self.styled_text().draw(target)?;
        }
        Ok(())
    }
}

impl fmt::Write for TextOverlay {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        for c in s.chars() {
            let n = c.len_utf8();
            if self.len + n > OVERLAY_TEXT_BYTES {
                break;
            }
            c.encode_utf8(&mut self.text[self.len..self.len + n]);
            self.len += n;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_cut_at_capacity_on_a_character_boundary() {
        let mut overlay = TextOverlay::default();
        overlay.set_text(format_args!("{} {}.{} fps", "teapot", 1, 4));
        assert_eq!(overlay.text(), "teapot 1.4 fps");
        let long = "é".repeat(OVERLAY_TEXT_BYTES);
        overlay.set_text(format_args!("x{long}"));
        assert_eq!(overlay.text().len(), OVERLAY_TEXT_BYTES - 1);
        assert!(overlay.text().starts_with('x'));
    }

    #[test]
    fn the_canvas_keeps_only_its_band() {
        let (width, rows) = (4u16, 2u16);
        let mut pixels = [0u8; 4 * 2 * 2];
        let mut canvas = BandCanvas::new(&mut pixels, width, 10, 3, rows);
        let white = Rgb565::WHITE;
        let points = [(0, 2), (1, 3), (3, 4), (4, 3), (-1, 3), (0, 5)];
        canvas
            .draw_iter(points.iter().map(|&(x, y)| Pixel(Point::new(x, y), white)))
            .unwrap();
        let set: Vec<usize> = pixels
            .chunks_exact(2)
            .enumerate()
            .filter(|(_, p)| p != &[0, 0])
            .map(|(i, _)| i)
            .collect();
        // (1, 3) is index 1 of row 0; (3, 4) is index 3 of row 1.
        assert_eq!(set, [1, 7]);
    }
}
