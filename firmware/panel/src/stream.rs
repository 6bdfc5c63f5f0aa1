//! [`BandStream`]: the renderer's line sink for an ST7789, double-buffered.

use crate::link::PanelLink;
use crate::overlay::{BandCanvas, TextOverlay};
use crate::st7789::{address_range, CASET, RAMWR, RASET};
use mcu_abuffer::sink::{LineSink, Rgb565BigEndian};

/// What can go wrong while streaming.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum StreamError<E> {
    /// The link failed.
    Link(E),
    /// A band buffer does not hold one row (`width * 2` bytes), or the two differ
    /// in length.
    BufferSize {
        /// Bytes one row needs.
        row_bytes: usize,
        /// Length of the shorter buffer.
        shorter: usize,
    },
    /// A line's length differs from the image width.
    LineWidth {
        /// The row.
        y: u16,
        /// Pixels in the line.
        pixels: usize,
    },
    /// A row outside the image.
    Row {
        /// The row.
        y: u16,
    },
    /// The link kept a buffer or gave back none when one was expected.
    LostBuffer,
}

/// What [`BandStream::release`] gives back: the link and both band buffers.
pub type Released<'buf, L> = (L, [&'buf mut [u8]; 2]);

/// Counters of a stream.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StreamStats {
    /// Bands handed to the link.
    pub bands: u32,
    /// Pixel bytes handed to the link.
    pub bytes: u64,
}

/// Receives the renderer's lines and streams them band by band to the panel.
///
/// Two buffers of the same length (a whole number of rows in RGB565, 2 bytes per
/// pixel) alternate: one is filled while the link sends the other. A band goes out
/// when its buffer is full, when the image's last row arrives, or when a row does
/// not follow the previous one (a new frame); [`end_frame`](Self::end_frame) sends
/// whatever is left. Before a band goes out the overlay is drawn into it. Each band
/// is addressed on its own (`CASET`, `RASET`, `RAMWR`), so a band never depends on
/// where the previous transfer stopped.
///
/// For the overlap to cover a whole band's rendering, give each buffer room for
/// exactly one render band (`band_height * width * 2` bytes).
pub struct BandStream<'buf, L> {
    link: L,
    width: u16,
    height: u16,
    column_offset: u16,
    row_offset: u16,
    filling: Option<&'buf mut [u8]>,
    spare: Option<&'buf mut [u8]>,
    capacity_rows: u16,
    first_row: u16,
    rows: u16,
    in_flight: bool,
    overlay: TextOverlay,
    stats: StreamStats,
}

impl<'buf, L: PanelLink<'buf>> BandStream<'buf, L> {
    /// A stream of `width` x `height` images through `link`, alternating between
    /// `buffers`.
    pub fn new(
        link: L,
        width: u16,
        height: u16,
        buffers: [&'buf mut [u8]; 2],
    ) -> Result<Self, StreamError<L::Error>> {
        let row_bytes = 2 * width as usize;
        let [a, b] = buffers;
        let shorter = a.len().min(b.len());
        if width == 0 || shorter < row_bytes || a.len() != b.len() {
            return Err(StreamError::BufferSize { row_bytes, shorter });
        }
        let capacity_rows = (shorter / row_bytes).min(height.max(1) as usize) as u16;
        Ok(Self {
            link,
            width,
            height,
            column_offset: 0,
            row_offset: 0,
            filling: Some(a),
            spare: Some(b),
            capacity_rows,
            first_row: 0,
            rows: 0,
            in_flight: false,
            overlay: TextOverlay::default(),
            stats: StreamStats::default(),
        })
    }

    /// Places the image at column `columns` and row `rows` of the controller's
    /// memory (modules smaller than the controller's 240 x 320 may need it).
    pub fn with_offset(mut self, columns: u16, rows: u16) -> Self {
        self.column_offset = columns;
        self.row_offset = rows;
        self
    }

    /// Rows one buffer holds.
    pub fn band_rows(&self) -> u16 {
        self.capacity_rows
    }

    /// The overlay drawn into every band.
    pub fn overlay_mut(&mut self) -> &mut TextOverlay {
        &mut self.overlay
    }

    /// Bands and bytes sent so far.
    pub fn stats(&self) -> StreamStats {
        self.stats
    }

    /// The link (for example to read its own counters).
    pub fn link(&self) -> &L {
        &self.link
    }

    /// The link, mutably (for counters that reset when read).
    pub fn link_mut(&mut self) -> &mut L {
        &mut self.link
    }

    /// Sends the band being filled, if it has rows. The transfer may still be
    /// running when this returns; the next band waits for it.
    pub fn end_frame(&mut self) -> Result<(), StreamError<L::Error>> {
        if self.rows > 0 {
            self.send_band()?;
        }
        Ok(())
    }

    /// Sends what is left and waits until every transfer has finished.
    pub fn flush(&mut self) -> Result<(), StreamError<L::Error>> {
        self.end_frame()?;
        self.wait_in_flight()
    }

    /// Flushes and gives back the link and both buffers.
    pub fn release(mut self) -> Result<Released<'buf, L>, StreamError<L::Error>> {
        self.flush()?;
        match (self.filling.take(), self.spare.take()) {
            (Some(a), Some(b)) => Ok((self.link, [a, b])),
            _ => Err(StreamError::LostBuffer),
        }
    }

    fn wait_in_flight(&mut self) -> Result<(), StreamError<L::Error>> {
        if self.in_flight {
            let buffer = self.link.finish_pixels().map_err(StreamError::Link)?;
            self.in_flight = false;
            self.spare = Some(buffer.ok_or(StreamError::LostBuffer)?);
        }
        Ok(())
    }

    fn send_band(&mut self) -> Result<(), StreamError<L::Error>> {
        let buffer = self.filling.take().ok_or(StreamError::LostBuffer)?;
        let (first, rows) = (self.first_row, self.rows);
        self.rows = 0;
        let len = rows as usize * self.width as usize * 2;
        // The canvas only ever writes inside the band, so drawing cannot fail.
        let _ = self.overlay.draw(&mut BandCanvas::new(
            buffer,
            self.width,
            self.height,
            first,
            rows,
        ));
        // The bus is free once the previous band has left.
        if let Err(e) = self.wait_in_flight() {
            self.filling = Some(buffer);
            return Err(e);
        }
        let x0 = self.column_offset;
        let y0 = self.row_offset + first;
        let window = [
            (CASET, address_range(x0, x0 + self.width - 1)),
            (RASET, address_range(y0, y0 + rows - 1)),
        ];
        for (command, parameters) in window {
            if let Err(e) = self.link.command(command, &parameters) {
                self.filling = Some(buffer);
                return Err(StreamError::Link(e));
            }
        }
        if let Err(e) = self.link.command(RAMWR, &[]) {
            self.filling = Some(buffer);
            return Err(StreamError::Link(e));
        }
        self.link
            .start_pixels(buffer, len)
            .map_err(StreamError::Link)?;
        self.in_flight = true;
        self.stats.bands += 1;
        self.stats.bytes += len as u64;
        self.filling = self.spare.take();
        if self.filling.is_none() {
            return Err(StreamError::LostBuffer);
        }
        Ok(())
    }
}

impl<'buf, L: PanelLink<'buf>> LineSink for BandStream<'buf, L> {
    type Pixel = Rgb565BigEndian;
    type Error = StreamError<L::Error>;

    /// Hands out the next row of the band buffer being filled, as the panel
    /// takes it (RGB565, high byte first): the renderer resolves into the
    /// memory the DMA sends.
    fn fill_line<F: FnOnce(&mut [Rgb565BigEndian])>(
        &mut self,
        y: u16,
        width: u16,
        fill: F,
    ) -> Result<(), Self::Error> {
        if y >= self.height {
            return Err(StreamError::Row { y });
        }
        if width != self.width {
            return Err(StreamError::LineWidth {
                y,
                pixels: width as usize,
            });
        }
        if self.rows > 0 && y != self.first_row + self.rows {
            self.send_band()?;
        }
        if self.rows == 0 {
            self.first_row = y;
        }
        let row_bytes = Rgb565BigEndian::BYTES * self.width as usize;
        let start = self.rows as usize * row_bytes;
        let buffer = self.filling.as_deref_mut().ok_or(StreamError::LostBuffer)?;
        fill(Rgb565BigEndian::line_from_bytes_mut(
            &mut buffer[start..start + row_bytes],
        ));
        self.rows += 1;
        if self.rows == self.capacity_rows || y + 1 == self.height {
            self.send_band()?;
        }
        Ok(())
    }
}
