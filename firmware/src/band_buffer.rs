//! The interface between the rasterizer and the per-band pixel memory.

use crate::coverage::CoverageMask;
use crate::fragment::Fragment;
use crate::raster::rasterize;
use crate::setup::{ColorSource, Rejection, SetupVertex, TriangleSetup};
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
    /// Draws one window-space triangle into the band starting at image row `band_y0`
    /// with `band_rows` rows: sets it up and rasterizes it.
    ///
    /// Buffers that decide about whole triangles before rasterizing them (culling
    /// against a z-buffer) override this; the others keep the default.
    fn draw_triangle(
        &mut self,
        vertices: &[SetupVertex; 3],
        params: &DrawParams,
        band_y0: u16,
        band_rows: u16,
    ) -> Result<(), Rejection>
    where
        Self: Sized,
    {
        let setup = TriangleSetup::new(
            vertices,
            params.cull_backfaces,
            params.colors,
            params.width,
            params.height,
        )?;
        rasterize(&setup, band_y0, band_rows, self);
        Ok(())
    }
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

/// What [`BandBuffer::draw_triangle`] needs besides the vertices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DrawParams {
    /// Skip the triangle when it faces away.
    pub cull_backfaces: bool,
    /// How fragment colors are produced.
    pub colors: ColorSource,
    /// Image width.
    pub width: u16,
    /// Image height.
    pub height: u16,
}
