//! The interface between the rasterizer and the per-band pixel memory.

use crate::coverage::CoverageMask;
use crate::fragment::Fragment;
use crate::stats::BufferStats;
use embedded_graphics_core::pixelcolor::Rgb888;

/// Pixel memory for one band of rows: receives fragments, then resolves rows to colors.
///
/// Implemented by the A-buffer ([`crate::fragment_buffer::FragmentBuffer`]) and the
/// plain z-buffer ([`crate::zbuffer::ZBuffer`]); tests implement it too (a
/// per-sample z-buffer is the A-buffer's oracle).
pub trait BandBuffer<M: CoverageMask> {
    /// Pixels per row.
    fn width(&self) -> u16;
    /// Rows this buffer can hold (the band height `R`).
    fn band_height(&self) -> u16;
    /// Starts a band of `rows` rows (at most [`BandBuffer::band_height`]) at image row `y0`:
    /// every pixel becomes empty.
    fn begin_band(&mut self, y0: u16, rows: u16);
    /// Adds the fragment of one triangle at column `x`, band row `row`.
    fn insert(&mut self, x: u16, row: u16, fragment: &Fragment<M>);
    /// Resolves band row `row` into colors, `background` where nothing covers.
    fn resolve_row(&mut self, row: u16, background: Rgb888, out: &mut [Rgb888]);
    /// Ends the band after its rows are resolved: shared memory (the pool) is released.
    fn end_band(&mut self) {}
    /// Fragments held by pixel `(x, row)` now (for depth-complexity maps).
    fn pixel_fragment_count(&self, x: u16, row: u16) -> u32;
    /// Counters since the last [`BandBuffer::take_stats`].
    fn stats(&self) -> BufferStats;
    /// Returns the counters and zeroes them.
    fn take_stats(&mut self) -> BufferStats;
}
