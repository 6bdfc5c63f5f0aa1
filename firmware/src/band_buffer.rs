//! The interface between the rasterizer and the per-band pixel memory.

use crate::coverage::CoverageMask;
use crate::draw_order::TriangleOrder;
use crate::fragment::{rounded_depth, Fragment};
use crate::raster::{band_test_of_box, rasterize_rows, BandTest, RowRange};
use crate::setup::{DepthSetup, Rejection, SetupVertex, TriangleSetup};
use crate::shading::{ColorPlanes, ColorWalk};
use crate::sink::LinePixel;
use crate::stats::BufferStats;
use embedded_graphics_core::pixelcolor::Rgb888;

/// Pixel memory for one band of rows: receives fragments, then resolves rows to colors.
///
/// Implemented by the A-buffer ([`crate::fragment_buffer::FragmentBuffer`]) and the
/// plain z-buffer ([`crate::zbuffer::ZBuffer`]); tests implement it too (a
/// per-sample z-buffer is the A-buffer's oracle).
pub trait BandBuffer<M: CoverageMask> {
    /// The order in which each band's triangles arrive, within each facing
    /// group (those facing the viewer come first): nearest first unless a
    /// buffer says otherwise.
    const ORDER: TriangleOrder = TriangleOrder::NearestFirst;
    /// Pixels per row.
    fn width(&self) -> u16;
    /// Rows this buffer can hold (the band height `R`).
    fn band_height(&self) -> u16;
    /// Starts a band of `rows` rows (at most [`BandBuffer::band_height`]) at image row `y0`:
    /// every pixel becomes empty.
    fn begin_band(&mut self, y0: u16, rows: u16);
    /// Draws one window-space triangle into the band starting at image row `band_y0`
    /// with `band_rows` rows: sets it up, skips it when it faces away and the
    /// buffer already hides it there, and rasterizes it otherwise ([`draw_in_band`]).
    ///
    /// Buffers that decide about whole triangles before rasterizing them (culling
    /// against a z-buffer) override this; the others keep the default.
    fn draw_triangle(
        &mut self,
        vertices: &[SetupVertex; 3],
        params: &DrawParams<'_>,
        band_y0: u16,
        band_rows: u16,
    ) -> Result<(), Rejection>
    where
        Self: Sized,
    {
        draw_in_band(self, vertices, params, band_y0, band_rows)
    }
    /// Whether pixel `(x, row)` holds, at every sample, something strictly
    /// nearer than `depth` (a depth at a sample, times 16, as
    /// [`Fragment::depth_at`] gives it). Used to skip triangles that are hidden
    /// in the whole band; the default says `false` (nothing is skipped). Asking
    /// changes nothing in the buffer.
    #[inline]
    fn hides(&mut self, x: u16, row: u16, depth: i64) -> bool {
        let _ = (x, row, depth);
        false
    }
    /// How many pixels of band row `row`, from column `x0` on and at most
    /// through `x1`, [`BandBuffer::hides`] in a run: `x1 - x0 + 1` when it
    /// hides them all, otherwise the count before the first it does not
    /// hide. The default asks [`BandBuffer::hides`] pixel by pixel; a buffer
    /// that can scan a row faster gives the same answer its own way. Asking
    /// changes nothing in the buffer.
    #[inline]
    fn hidden_run(&mut self, row: u16, x0: u16, x1: u16, depth: i64) -> u32 {
        let mut x = x0 as u32;
        while x <= x1 as u32 && self.hides(x as u16, row, depth) {
            x += 1;
        }
        x - x0 as u32
    }
    /// Whether, in every pixel of columns `x0..=x1` in every row of the band,
    /// the buffer holds something strictly nearer at every sample than
    /// `depth` (the question of [`BandBuffer::hides`] for all those pixels at
    /// once), answered from a summary the buffer keeps; `false` when the
    /// summary cannot tell, and the caller then asks pixel by pixel. The
    /// default says `false`. Asking changes nothing in the buffer.
    #[inline]
    fn hides_columns(&mut self, x0: u16, x1: u16, depth: i64) -> bool {
        let _ = (x0, x1, depth);
        false
    }
    /// Counts one whole-triangle test against the band: `pixels` pixels asked
    /// with [`BandBuffer::hides`], and whether the triangle was skipped.
    #[inline]
    fn count_triangle_test(&mut self, pixels: u32, hidden: bool) {
        let _ = (pixels, hidden);
    }
    /// Whether `fragment` (its color not yet known) would keep at least one
    /// sample if it were inserted at column `x`, band row `row`. When it would
    /// not, the buffer counts it as inserted and hidden on arrival, exactly as
    /// [`BandBuffer::insert`] would have, and nothing else changes.
    ///
    /// The rasterizer asks this for a triangle's fragments until the first one
    /// that survives, and sets up the triangle's colors only then. The default
    /// answers `true` (every fragment gets inserted).
    #[inline]
    fn survives(&mut self, x: u16, row: u16, fragment: &Fragment<M>) -> bool {
        let _ = (x, row, fragment);
        true
    }
    /// How the band now being drawn uses the buffer's shared pool, for the
    /// frame driver's band heights ([`crate::fragment_buffer::OverflowPolicy::SplitBands`]):
    /// when [`PoolUse::ran_out`], the driver ends the band unresolved and draws
    /// its rows again as two bands of half the height; after a band that used
    /// little of the pool, the next one may be taller again. The default
    /// reports no pool.
    #[inline]
    fn pool_use(&self) -> PoolUse {
        PoolUse::default()
    }
    /// Adds the fragment of one triangle at column `x`, band row `row`.
    fn insert(&mut self, x: u16, row: u16, fragment: &Fragment<M>);
    /// Adds the fragments of one triangle in `run.len` pixels of band row
    /// `row` from column `x` on, each covering its whole pixel, their colors
    /// from `walk` (at `color`, which is left `run.len` steps on). The same
    /// as [`BandBuffer::insert`] pixel by pixel, which the default does; a
    /// buffer with a faster loop for whole pixels gives the same result its
    /// own way.
    #[inline(always)]
    fn insert_full_run<W: ColorWalk>(
        &mut self,
        x: u16,
        row: u16,
        run: &FullRun<M>,
        walk: &W,
        color: &mut W::Row,
    ) where
        Self: Sized,
    {
        insert_each(self, x, row, run, walk, color)
    }
    /// Resolves band row `row` into `out` in its pixel format (a sink's
    /// line), `background` where nothing covers.
    fn resolve_row<P: LinePixel>(&mut self, row: u16, background: Rgb888, out: &mut [P]);
    /// Ends the band after its rows are resolved: shared memory (the pool) is released.
    fn end_band(&mut self) {}
    /// Fragments held by pixel `(x, row)` now (for depth-complexity maps).
    fn pixel_fragment_count(&self, x: u16, row: u16) -> u32;
    /// Counters since the last [`BandBuffer::take_stats`].
    fn stats(&self) -> BufferStats;
    /// Fragments hidden on arrival plus triangles hidden in a whole band,
    /// since the last [`BandBuffer::take_stats`]: a count the frame driver
    /// reads around each triangle to tell whether the buffer hid it, without
    /// copying the statistics.
    #[inline]
    fn hidden_count(&self) -> u32 {
        let stats = self.stats();
        stats.fragments_hidden_on_arrival + stats.triangles_culled
    }
    /// Returns the counters and zeroes them.
    fn take_stats(&mut self) -> BufferStats;
}

/// A run of pixels along one row that a triangle covers wholly: what
/// [`BandBuffer::insert_full_run`] inserts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FullRun<M: CoverageMask> {
    /// Pixels in the run.
    pub len: u16,
    /// The triangle's depth plane at the first pixel's center, with
    /// [`crate::fragment::PLANE_EXTRA_BITS`] extra fraction bits
    /// ([`crate::setup::Plane`]) and [`crate::fragment::PLANE_HALF_UNIT`]
    /// added: the pixel's depth is [`crate::fragment::rounded_depth`].
    pub depth: i64,
    /// The plane's step per pixel, in the same units.
    pub depth_step: i64,
    /// The fragments' depth gradients, full mask and (unused) color: what
    /// every fragment of the run has besides its depth and color.
    pub template: Fragment<M>,
}

/// [`BandBuffer::insert_full_run`] pixel by pixel, as its default does;
/// buffers that override it fall back on this where their loop does not
/// apply.
#[inline(always)]
pub fn insert_each<M: CoverageMask, B: BandBuffer<M>, W: ColorWalk>(
    buffer: &mut B,
    x: u16,
    row: u16,
    run: &FullRun<M>,
    walk: &W,
    color: &mut W::Row,
) {
    let mut depth = run.depth;
    for k in 0..run.len {
        let fragment = Fragment {
            z: rounded_depth(depth),
            color: walk.color(color),
            ..run.template
        };
        buffer.insert(x + k, row, &fragment);
        walk.step(color);
        depth += run.depth_step;
    }
}

/// What [`BandBuffer::draw_triangle`] does by default: sets the triangle up,
/// skips it when none of its rows in the band can hold a sample, or when it
/// faces away (or the frame driver asks) and `buffer` already hides it in
/// the whole band, and otherwise rasterizes its rows that can hold samples,
/// setting up its colors only when a fragment survives.
/// Wrappers that override `draw_triangle` call this to draw the same way.
pub fn draw_in_band<M: CoverageMask, B: BandBuffer<M>>(
    buffer: &mut B,
    vertices: &[SetupVertex; 3],
    params: &DrawParams<'_>,
    band_y0: u16,
    band_rows: u16,
) -> Result<(), Rejection> {
    let screen = (params.width, params.height);
    let within = params.within_guard_band;
    let accepted = TriangleSetup::accept(vertices, params.cull_backfaces, screen, within)?;
    // Only rows whose samples reach into the triangle's height can hold its
    // fragments; a band without such a row costs nothing more (on the
    // z-buffer, whose one sample is the pixel center, that is half a row at
    // each end of the triangle on average).
    let in_band = |rows| RowRange::of_rows(rows, band_y0, band_rows);
    let Some(rows) = accepted.sample_rows::<M>().and_then(in_band) else {
        return Ok(());
    };
    let depth = DepthSetup::of(&accepted);
    // Faces turned away are drawn after the faces of the viewer and are mostly
    // behind them: for those a whole-triangle test pays. A face turned to the
    // viewer is rarely hidden and its probe finds a visible fragment as soon;
    // testing every one cost 1-3 % more instructions on every built-in scene
    // that fits the M4 (layers included), so it is tested only when the frame
    // driver asks (after a triangle the buffer hid: hidden ones come in
    // runs). The test asks what it can from the box and the depth plane
    // before the edges are set up.
    let mut ask_spans = None;
    if accepted.faces_away() || params.test_whole_band {
        let plane = (&depth.plane, depth.dzdx, depth.dzdy);
        match band_test_of_box(accepted.screen_box(), plane, rows, buffer) {
            BandTest::Hidden => return Ok(()),
            BandTest::Shown => {}
            BandTest::AskSpans(rows) => ask_spans = Some(rows),
        }
    }
    let setup = TriangleSetup::build_with(&accepted, depth);
    // With the pixel step still to ask, the probe starts where it stopped.
    let (rows, test_spans) = (ask_spans.unwrap_or(rows), ask_spans.is_some());
    rasterize_rows(&setup, rows, test_spans, buffer, || (params.colors)(&setup));
    Ok(())
}

/// How a band uses a buffer's shared pool ([`BandBuffer::pool_use`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PoolUse {
    /// An allocation failed in this band and the buffer asks for the band to
    /// be drawn again in halves.
    pub ran_out: bool,
    /// The most slots in use at once in this band.
    pub peak: usize,
    /// Slots in the pool.
    pub capacity: usize,
}

/// What [`BandBuffer::draw_triangle`] needs besides the vertices.
#[derive(Clone, Copy)]
pub struct DrawParams<'c> {
    /// Skip the triangle when it faces away.
    pub cull_backfaces: bool,
    /// The color planes of the triangle, given its setup; asked only when
    /// the triangle leaves a visible fragment (lighting and the quadratic fit
    /// cost work). The frame driver's answer may come from an earlier band
    /// ([`crate::color_carry`]).
    pub colors: &'c dyn Fn(&TriangleSetup) -> ColorPlanes,
    /// Image width.
    pub width: u16,
    /// Image height.
    pub height: u16,
    /// Whether a face of the viewer meets the whole-band test too (faces
    /// turned away always do): the frame driver asks for it after a
    /// triangle the buffer hid, since triangles drawn nearest first come
    /// hidden in runs, behind whatever hid the first of them.
    pub test_whole_band: bool,
    /// Whether every vertex is known to lie within the guard band (`±2^16`
    /// in 1/16 pixel), as the frame driver's do (window positions are
    /// clamped to it): setup then neither tests nor clamps them, and its
    /// 32-bit differences of corners assume they fit (for a vertex beyond
    /// the band they overflow: wrong edges, or a panic where overflow is
    /// checked).
    /// With `false`, setup tests them and clamps any that lie beyond.
    pub within_guard_band: bool,
}
