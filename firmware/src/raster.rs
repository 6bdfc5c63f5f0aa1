//! Rasterization: walks a set-up triangle's pixels within a band, builds each
//! pixel's coverage mask from the signs of the edge functions at the samples, and
//! hands one fragment per covered pixel to a [`BandBuffer`].
//!
//! Per row, one division per edge finds the run of pixels no edge rules out
//! (an edge rules a pixel out when its value at the center is below minus the
//! farthest sample offset) and, within a run longer than 8 pixels, the
//! interior run where every edge clears the center by that margin: interior
//! pixels take the full mask with no per-sample work. Only the other pixels
//! look at samples, and only for the edges they do not clear,
//! through [`CoverageMask::edge_coverage`] (sorted sample thresholds for 4x4,
//! the edge function stepped across the grid with additions otherwise; SPEC
//! section 2). Edge values and Gouraud colors are walked in 32 bits when the
//! triangle's ranges allow it (the same integers as in 64 bits); within a
//! row, a pixel's edge values and depth are the row's values plus its
//! column's steps, one multiply-accumulate each.
//!
//! Fragments are first offered to the buffer without a color; a triangle's
//! colors are set up when its first fragment survives, and a triangle facing
//! away that the buffer already hides in the whole band is skipped before any
//! fragment ([`hidden_in_band`]), as is a face of the viewer the frame
//! driver asks about (`DrawParams::test_whole_band`, after a triangle the
//! buffer hid); where the test finds a pixel the buffer does not hide, the
//! search for the first surviving fragment starts there.

use crate::band_buffer::{BandBuffer, FullRun};
use crate::coverage::{CoverageMask, SHORT_STEP_LIMIT};
use crate::fixed_point::{count_mul_add, word_mul_add};
use crate::fragment::{
    fragment_depth, rounded_depth, rounded_depth_saturated, Fragment, PLANE_HALF_UNIT,
};
use crate::setup::{Edge, Plane, ScreenBox, TriangleSetup};
use crate::shading::linear::LinearWalk;
use crate::shading::phong::PhongWalk;
use crate::shading::quadratic::QuadraticWalk;
use crate::shading::{ColorPlanes, ColorWalk, ConstantWalk};
use core::marker::PhantomData;
use embedded_graphics_core::pixelcolor::Rgb888;

/// Samples where one edge function (value `e` at the pixel center, already biased)
/// is non-negative.
#[inline]
pub fn edge_mask<M: CoverageMask>(e: i64, edge: &Edge) -> M {
    // Near an edge |e| is below the margin (< 2^22), so 32 bits suffice.
    M::edge_coverage(&M::edge_samples(edge.a, edge.b), e as i32)
}

/// An integer type edge functions are stepped in: `i32` when a triangle's edge
/// values fit (nearly always), `i64` otherwise.
trait EdgeValue:
    Copy
    + PartialOrd
    + core::ops::Add<Output = Self>
    + core::ops::Sub<Output = Self>
    + core::ops::Neg<Output = Self>
{
    const ZERO: Self;
    /// Whether every triangle walked in this type has edge steps within
    /// `±SHORT_STEP_LIMIT` (its masks may take
    /// [`CoverageMask::edge_coverage_short`]).
    const SHORT_STEPS: bool;
    fn from_i64(v: i64) -> Self;
    fn near(self) -> i32;
    /// `self + k step`, the value `k` pixels on (an edge value the walk
    /// reaches, so it fits).
    fn at_column(self, step: Self, k: u32) -> Self;
    /// The fewest steps of `step > 0` that take `value < target` to `target`
    /// or beyond (at most `2^30`: beyond any bounding box is as good as
    /// further).
    fn steps_to_reach(value: Self, target: Self, step: Self) -> i32;
    /// How many steps `k >= 0` of `step < 0` keep `value + k step >= limit`,
    /// for `value >= limit` (at most `2^30 + 1`, as above).
    fn steps_above(value: Self, limit: Self, step: Self) -> i32;
}

impl EdgeValue for i32 {
    const ZERO: Self = 0;
    // `edges_fit_i32` says so.
    const SHORT_STEPS: bool = true;
    #[inline]
    fn from_i64(v: i64) -> Self {
        v as i32
    }
    #[inline]
    fn near(self) -> i32 {
        self
    }
    #[inline(always)]
    fn at_column(self, step: Self, k: u32) -> Self {
        word_mul_add(self, k, step)
    }
    #[inline]
    fn steps_to_reach(value: Self, target: Self, step: Self) -> i32 {
        // Positive here and below 2^30 + 2^22 (edge values within ±2^30,
        // margins below 2^22), and so are the quotients: they fit `i32`.
        let gap = (target - value) as u32;
        gap.div_ceil(step as u32) as i32
    }
    #[inline]
    fn steps_above(value: Self, limit: Self, step: Self) -> i32 {
        // As above: the quotient plus one stays below 2^31.
        ((value - limit) as u32 / step.unsigned_abs()) as i32 + 1
    }
}

impl EdgeValue for i64 {
    const ZERO: Self = 0;
    const SHORT_STEPS: bool = false;
    #[inline]
    fn from_i64(v: i64) -> Self {
        v
    }
    #[inline]
    fn near(self) -> i32 {
        self as i32
    }
    #[inline(always)]
    fn at_column(self, step: Self, k: u32) -> Self {
        self + step * k as i64
    }
    #[inline]
    fn steps_to_reach(value: Self, target: Self, step: Self) -> i32 {
        // Beyond any bounding box (2^16 columns at most) is as good as
        // further.
        ((target - value) as u64).div_ceil(step as u64).min(1 << 30) as i32
    }
    #[inline]
    fn steps_above(value: Self, limit: Self, step: Self) -> i32 {
        ((value - limit) as u64 / step.unsigned_abs()).min(1 << 30) as i32 + 1
    }
}

/// Coverage of the pixel whose center has edge values `e`, given each edge's
/// margin (the largest change of that edge from the center to a sample):
/// an edge that clears the center by its margin covers every sample. Asked
/// only within a row's span, where no edge is below minus its margin (an
/// edge that were would give an empty mask all the same).
#[inline(always)]
fn pixel_coverage<M: CoverageMask, E: EdgeValue>(
    e: &[E; 3],
    edges: &[M::EdgeSamples; 3],
    margin: &[E; 3],
) -> M {
    let mut mask = M::FULL;
    for i in 0..3 {
        if e[i] < margin[i] {
            let e = e[i].near();
            let edge = if E::SHORT_STEPS {
                // Below the margin: some sample is left out.
                M::edge_coverage_short_partial(&edges[i], e)
            } else {
                M::edge_coverage(&edges[i], e)
            };
            mask = mask & edge;
        }
    }
    mask
}

/// Whether every edge value over the rows `y_first..=y_last` of the bounding box
/// (and one step beyond) stays within `±2^30`, so the pixel loop can run in `i32`,
/// and every edge step within `±SHORT_STEP_LIMIT` (`EdgeValue::SHORT_STEPS`).
/// A triangle under 1,024 pixels across (nearly every one) needs no more
/// than its corners to say so: its steps are below 2^14.
// The corners' test inline, the bound out of line: 0.18 M fewer
// instructions on the teapot's frame than the compiler's choice (the whole
// test out of line), 0.19 M fewer than all of it inline.
#[inline(always)]
fn edges_fit_i32(setup: &TriangleSetup, y_first: u16, y_last: u16) -> bool {
    setup.corners_within_1024_px() || edges_fit_i32_bound(setup, y_first, y_last)
}

/// [`edges_fit_i32`] for a triangle 1,024 pixels across or more: the bound
/// over the box, out of line.
#[inline(never)]
fn edges_fit_i32_bound(setup: &TriangleSetup, y_first: u16, y_last: u16) -> bool {
    let columns = (setup.x1 - setup.x0) as i64 + 1;
    let rows = (y_last - setup.y0) as i64 + 1;
    let _ = y_first;
    setup.edges.iter().all(|e| {
        let bound = e.origin.abs()
            + ((e.a.unsigned_abs() as i64) << 4) * columns
            + ((e.b.unsigned_abs() as i64) << 4) * rows;
        let limit = SHORT_STEP_LIMIT as u32;
        let short = e.a.unsigned_abs() < limit && e.b.unsigned_abs() < limit;
        bound < 1 << 30 && short
    })
}

/// Rasterizes the rows of `setup` that fall in the band starting at image row
/// `band_y0` with `band_rows` rows, inserting fragments into `buffer`.
///
/// Colors are set up lazily: fragments are first offered to
/// [`BandBuffer::survives`] without a color, and only when one survives does
/// `colors` run (lighting, quadratic fit); from that fragment on, each is
/// inserted with its color. A triangle hidden everywhere in the band costs its
/// edges and depth only. The result is the same as inserting every fragment.
pub fn rasterize<M, B, F>(
    setup: &TriangleSetup,
    band_y0: u16,
    band_rows: u16,
    buffer: &mut B,
    colors: F,
) where
    M: CoverageMask,
    B: BandBuffer<M>,
    F: FnOnce() -> ColorPlanes,
{
    if let Some(rows) = RowRange::of_samples::<M>(setup, band_y0, band_rows) {
        rasterize_rows(setup, rows, false, buffer, colors)
    }
}

/// [`rasterize`] over `rows` (the triangle's rows in the band). With
/// `test_spans`, first [`hidden_in_band`]'s pixel step: nothing is drawn
/// when it finds the triangle hidden, and otherwise the probe for a
/// surviving fragment starts at the first pixel that step could not rule
/// out (the pixels before it are hidden at every sample).
#[inline(always)]
pub(crate) fn rasterize_rows<M, B, F>(
    setup: &TriangleSetup,
    rows: RowRange,
    test_spans: bool,
    buffer: &mut B,
    colors: F,
) where
    M: CoverageMask,
    B: BandBuffer<M>,
    F: FnOnce() -> ColorPlanes,
{
    if edges_fit_i32(setup, rows.first, rows.last) {
        rasterize_with::<M, B, i32, F>(setup, rows, test_spans, buffer, colors)
    } else {
        rasterize_with::<M, B, i64, F>(setup, rows, test_spans, buffer, colors)
    }
}

/// Whether `buffer` hides every fragment `setup` could leave in the band
/// starting at image row `band_y0` with `band_rows` rows: at every pixel the
/// triangle can touch there, the buffer holds something strictly nearer, at
/// every sample, than the nearest sample depth any fragment of it can have.
/// Then rasterizing it would change nothing (each fragment would be hidden
/// on arrival), so it is counted and skipped.
///
/// Asked in two steps. First whole strips of the bounding box's columns,
/// against the nearest sample depth over the whole box: one comparison a
/// strip where the buffer keeps a summary ([`BandBuffer::hides_columns`]).
/// Then pixel by pixel: a single-sample buffer (the z-buffer) scans the
/// box's rows against that same bound ([`BandBuffer::hidden_run`], a few
/// instructions a pixel); a multi-sample buffer is asked only about the
/// pixels of the triangle's row spans, each against the nearest sample depth
/// at that pixel: fewer and tighter questions, each dearer (on the two-sided
/// teapot, 0.53 M fewer instructions a frame than asking about the box).
///
/// The bounds are exact for the fragments the rasterizer makes: their depth
/// at a pixel center is the walked plane, rounded as fragments are, whose
/// smallest value over the box is at one of its corners; a sample lies at
/// most the grid's largest offsets from the center.
pub fn hidden_in_band<M: CoverageMask, B: BandBuffer<M>>(
    setup: &TriangleSetup,
    band_y0: u16,
    band_rows: u16,
    buffer: &mut B,
) -> bool {
    let depth = (&setup.depth, setup.dzdx, setup.dzdy);
    let Some(rows) = RowRange::of_samples::<M>(setup, band_y0, band_rows) else {
        return false;
    };
    match band_test_of_box(setup.screen_box(), depth, rows, buffer) {
        BandTest::Hidden => true,
        BandTest::Shown => false,
        BandTest::AskSpans(rows) => {
            if edges_fit_i32(setup, rows.first, rows.last) {
                let edges = EdgeWalk::<M, i32>::new(setup);
                spans_hidden(setup, &edges, rows, buffer).is_none()
            } else {
                let edges = EdgeWalk::<M, i64>::new(setup);
                spans_hidden(setup, &edges, rows, buffer).is_none()
            }
        }
    }
}

/// What the first steps of [`hidden_in_band`] say, from the box and the
/// depth plane alone.
pub(crate) enum BandTest {
    /// The buffer hides the triangle in the band (the test is counted).
    Hidden,
    /// It does not, or the triangle has no pixel in the band (counted too
    /// where pixels were asked).
    Shown,
    /// Only the pixels of the triangle's row spans in these rows can tell
    /// ([`spans_hidden`], which needs the edges).
    AskSpans(RowRange),
}

/// [`hidden_in_band`] up to its pixel step over the row spans: everything
/// it asks from the bounding box `screen_box` and the depth plane `plane`
/// with the fragments' gradients `dzdx`, `dzdy`.
#[inline(always)]
pub(crate) fn band_test_of_box<M: CoverageMask, B: BandBuffer<M>>(
    screen_box: ScreenBox,
    (d, dzdx, dzdy): (&Plane, i32, i32),
    rows: RowRange,
    buffer: &mut B,
) -> BandTest {
    let ScreenBox { x0, y0, x1, .. } = screen_box;
    let (i1, j0, j1) = (
        (x1 - x0) as i64,
        (rows.first - y0) as i64,
        (rows.last - y0) as i64,
    );
    // The plane's smallest value over the box's corners: its steps in x and
    // in y are independent, so the smaller end in each.
    let nearest = d.origin + (i1 * d.dx).min(0) + (j0 * d.dy).min(j1 * d.dy);
    let bound = 16 * fragment_depth(nearest) as i64 - sample_reach::<M>(dzdx, dzdy);
    if buffer.hides_columns(x0, x1, bound) {
        buffer.count_triangle_test(0, true);
        return BandTest::Hidden;
    }
    if M::SAMPLES == 1 {
        if box_hidden((x0, x1), rows, bound, buffer) {
            BandTest::Hidden
        } else {
            BandTest::Shown
        }
    } else {
        BandTest::AskSpans(rows)
    }
}

/// How much nearer than its depth at the pixel center (times 16) a fragment
/// of `setup` can be at a sample: its gradients times the grid's largest
/// sample offsets.
#[inline]
fn sample_reach<M: CoverageMask>(dzdx: i32, dzdy: i32) -> i64 {
    dzdx.unsigned_abs() as i64 * M::max_offset_x() as i64
        + dzdy.unsigned_abs() as i64 * M::max_offset_y() as i64
}

/// [`hidden_in_band`]'s pixel step over the rows of the bounding box, every
/// pixel against `bound`; counts the test.
fn box_hidden<M: CoverageMask, B: BandBuffer<M>>(
    (x0, x1): (u16, u16),
    rows: RowRange,
    bound: i64,
    buffer: &mut B,
) -> bool {
    let columns = (x1 - x0) as u32 + 1;
    let mut asked = 0u32;
    for row in rows.first - rows.band_y0..rows.last - rows.band_y0 + 1 {
        let run = buffer.hidden_run(row, x0, x1, bound);
        if run < columns {
            // The pixels of the run and the first one not hidden.
            buffer.count_triangle_test(asked + run + 1, false);
            return false;
        }
        asked += columns;
    }
    buffer.count_triangle_test(asked, true);
    true
}

/// [`hidden_in_band`]'s pixel step over the triangle's row spans (the pixels
/// the rasterizer would look at), each pixel against the nearest sample
/// depth a fragment of it can have there; counts the test. `None` when
/// every pixel is hidden; otherwise where the walk found the first that is
/// not (a start for [`walk_pixels`]).
fn spans_hidden<M, B, E>(
    setup: &TriangleSetup,
    edges: &EdgeWalk<M, E>,
    rows: RowRange,
    buffer: &mut B,
) -> Option<WalkStart<E>>
where
    M: CoverageMask,
    B: BandBuffer<M>,
    E: EdgeValue,
{
    let reach = sample_reach::<M>(setup.dzdx, setup.dzdy);
    let dz = setup.depth.dx;
    let start = edges.first_row(setup, rows.first);
    let (mut e_row, mut z_row, mut span) = (start.e_row, start.z_row, start.span);
    let mut asked = 0u32;
    let mut y = rows.first;
    loop {
        let row = y - rows.band_y0;
        for k in span.start..span.end {
            asked += 1;
            let z = count_mul_add(z_row, k as u32, dz);
            let bound = 16 * rounded_depth_saturated(z) as i64 - reach;
            if !buffer.hides(setup.x0 + k as u16, row, bound) {
                buffer.count_triangle_test(asked, false);
                return Some(WalkStart {
                    y,
                    e_row,
                    z_row,
                    span: span.from(k),
                });
            }
        }
        if y >= rows.last {
            break;
        }
        y += 1;
        span = edges.next_row(setup, &mut e_row, &mut z_row);
    }
    buffer.count_triangle_test(asked, true);
    None
}

/// What [`walk_pixels`] does with each pixel of a triangle: offer its
/// fragment to the buffer (probing for the first survivor) or insert it.
/// A trait rather than a closure so the per-pixel work is always inlined
/// into the walk's loops.
trait PixelVisitor<M: CoverageMask> {
    /// Handles the fragment at image pixel `(x, y)` with coverage `mask`,
    /// depth plane `z` (with [`PLANE_HALF_UNIT`], as the walks carry it)
    /// and `color`; `true` stops the walk.
    fn visit(&mut self, x: u16, y: u16, mask: M, z: i64, color: Rgb888) -> bool;
}

/// The fragments of one triangle handed to the buffer: with `PROBE`, offered
/// without a color to [`BandBuffer::survives`] until one survives; without,
/// all inserted.
struct TriangleFragments<'a, B, const PROBE: bool> {
    setup: &'a TriangleSetup,
    band_y0: u16,
    buffer: &'a mut B,
}

/// Looks for a triangle's first fragment that survives.
type Probe<'a, B> = TriangleFragments<'a, B, true>;
/// Inserts every fragment of a triangle.
type Insert<'a, B> = TriangleFragments<'a, B, false>;

impl<M: CoverageMask, B: BandBuffer<M>, const PROBE: bool> PixelVisitor<M>
    for TriangleFragments<'_, B, PROBE>
{
    #[inline(always)]
    fn visit(&mut self, x: u16, y: u16, mask: M, z: i64, color: Rgb888) -> bool {
        let fragment = fragment_at(self.setup, mask, z, color);
        let row = y - self.band_y0;
        if PROBE {
            self.buffer.survives(x, row, &fragment)
        } else {
            self.buffer.insert(x, row, &fragment);
            false
        }
    }
}

/// The image rows of a triangle within one band.
#[derive(Clone, Copy)]
pub(crate) struct RowRange {
    first: u16,
    last: u16,
    band_y0: u16,
}

impl RowRange {
    /// The rows of `setup` that can hold samples of grid `M`
    /// ([`TriangleSetup::sample_rows`]) within the band of `band_rows` rows
    /// from image row `band_y0`; `None` when none is there.
    #[inline(always)]
    pub(crate) fn of_samples<M: CoverageMask>(
        setup: &TriangleSetup,
        band_y0: u16,
        band_rows: u16,
    ) -> Option<Self> {
        Self::of_rows(setup.sample_rows::<M>()?, band_y0, band_rows)
    }

    /// Image rows `first..=last` within the band of `band_rows` rows from
    /// image row `band_y0`; `None` when none is there.
    #[inline(always)]
    pub(crate) fn of_rows((first, last): (u16, u16), band_y0: u16, band_rows: u16) -> Option<Self> {
        if band_rows == 0 {
            return None;
        }
        let band_last = band_y0 as u32 + band_rows as u32 - 1;
        let first = first.max(band_y0);
        let last = (last as u32).min(band_last) as u16;
        (first <= last).then_some(Self {
            first,
            last,
            band_y0,
        })
    }
}

/// The fragment of `setup` with coverage `mask`, depth plane `z` (with
/// [`PLANE_HALF_UNIT`], as the walks carry it) and `color`.
#[inline(always)]
fn fragment_at<M: CoverageMask>(
    setup: &TriangleSetup,
    mask: M,
    z: i64,
    color: Rgb888,
) -> Fragment<M> {
    Fragment {
        mask,
        z: if M::SAMPLES == 1 {
            rounded_depth(z)
        } else {
            rounded_depth_saturated(z)
        },
        dzdx: setup.dzdx,
        dzdy: setup.dzdy,
        color,
    }
}

/// Finds the first surviving fragment, then sets up colors and inserts from there.
// Always inlined: with the compiler's choice the caller (`draw_in_band`)
// came out 2.5 KB larger on the M4 and 0.01 to 0.1 M instructions a frame
// slower on the built-in scenes.
#[inline(always)]
fn rasterize_with<M, B, E, F>(
    setup: &TriangleSetup,
    rows: RowRange,
    test_spans: bool,
    buffer: &mut B,
    colors: F,
) where
    M: CoverageMask,
    B: BandBuffer<M>,
    E: EdgeValue,
    F: FnOnce() -> ColorPlanes,
{
    let edges = EdgeWalk::<M, E>::new(setup);
    let first = if test_spans {
        match spans_hidden(setup, &edges, rows, buffer) {
            Some(start) => start,
            None => return,
        }
    } else {
        edges.first_row(setup, rows.first)
    };
    let tables = edge_tables::<M>(setup);
    // Probing needs no color: the walk of a constant costs nothing.
    let mut no_color = ConstantWalk(Rgb888::new(0, 0, 0));
    let mut probe = Probe {
        setup,
        band_y0: rows.band_y0,
        buffer: &mut *buffer,
    };
    let Some(start) = walk_pixels(
        setup,
        &edges,
        &tables,
        rows.last,
        first,
        &mut no_color,
        &mut probe,
    ) else {
        return;
    };
    // One loop per kind of color, so the per-pixel work has no branch on it.
    let j = (start.y - setup.y0) as i64;
    macro_rules! insert_with {
        ($walk:expr) => {
            insert_from::<M, B, E, _>(setup, &edges, &tables, rows, start, $walk, buffer)
        };
    }
    match colors() {
        ColorPlanes::Constant(c) => insert_with!(ConstantWalk(c)),
        ColorPlanes::Linear(p) => {
            if LinearWalk::<i32>::fits(&p, setup) {
                insert_with!(LinearWalk::<i32>::start(&p, j))
            } else {
                insert_with!(LinearWalk::<i64>::start(&p, j))
            }
        }
        ColorPlanes::Quadratic(p) => insert_with!(QuadraticWalk::<i64>::start(&p, j)),
        ColorPlanes::NarrowQuadratic(p) => insert_with!(QuadraticWalk::<i32>::start(&p, j)),
        ColorPlanes::Phong(p) => insert_with!(PhongWalk::start(&p, j)),
    }
}

/// Inserts the fragments of `setup` from `start` (where the probe stopped) on,
/// colors from `walk` (positioned at the first column of `start`'s row).
// Kept out of line: one copy per kind of color, each with its own registers.
#[inline(never)]
fn insert_from<M, B, E, W>(
    setup: &TriangleSetup,
    edges: &EdgeWalk<M, E>,
    tables: &EdgeTables<M>,
    rows: RowRange,
    start: WalkStart<E>,
    mut walk: W,
    buffer: &mut B,
) where
    M: CoverageMask,
    B: BandBuffer<M>,
    E: EdgeValue,
    W: ColorWalk,
{
    if M::SAMPLES == 1 {
        // One sample at the center: every pixel a row touches is covered
        // whole, and each row is one run for the buffer.
        return insert_full_rows(setup, edges, rows, start, walk, buffer);
    }
    let mut insert = Insert {
        setup,
        band_y0: rows.band_y0,
        buffer,
    };
    walk_pixels(
        setup,
        edges,
        tables,
        rows.last,
        start,
        &mut walk,
        &mut insert,
    );
}

/// [`insert_from`] for one sample per pixel: each row's pixels from `start`
/// on go to the buffer as one run ([`BandBuffer::insert_full_run`]).
#[inline(always)]
fn insert_full_rows<M, B, E, W>(
    setup: &TriangleSetup,
    edges: &EdgeWalk<M, E>,
    rows: RowRange,
    start: WalkStart<E>,
    mut walk: W,
    buffer: &mut B,
) where
    M: CoverageMask,
    B: BandBuffer<M>,
    E: EdgeValue,
    W: ColorWalk,
{
    let template = fragment_at(setup, M::FULL, 0, Rgb888::new(0, 0, 0));
    let WalkStart {
        mut e_row,
        mut z_row,
        mut span,
        y,
    } = start;
    let mut row = y - rows.band_y0;
    let last = rows.last - rows.band_y0;
    loop {
        if span.start < span.end {
            let mut color = walk.row();
            walk.skip(&mut color, span.start as u16);
            let run = FullRun {
                len: (span.end - span.start) as u16,
                depth: z_row + span.start as u32 as i64 * setup.depth.dx,
                depth_step: setup.depth.dx,
                template,
            };
            let x = setup.x0 + span.start as u16;
            buffer.insert_full_run(x, row, &run, &walk, &mut color);
        }
        if row >= last {
            return;
        }
        row += 1;
        walk.next_row();
        span = edges.next_row(setup, &mut e_row, &mut z_row);
    }
}

/// What the row walks of one triangle in one band share: per edge its
/// steps per pixel in x and y and the margin beyond which a pixel needs no
/// look at its samples (the edge's largest change from the center to a
/// sample). The masks' tables ([`EdgeTables`]) come apart: the whole-band
/// test walks the rows without them.
struct EdgeWalk<M: CoverageMask, E> {
    margin: [E; 3],
    step_x: [E; 3],
    step_y: [E; 3],
    /// Columns of the bounding box.
    columns: i32,
    grid: PhantomData<M>,
}

/// The mask grid's tables of a triangle's three edges.
type EdgeTables<M> = [<M as CoverageMask>::EdgeSamples; 3];

/// The mask grid's tables of `setup`'s edges.
#[inline(always)]
fn edge_tables<M: CoverageMask>(setup: &TriangleSetup) -> EdgeTables<M> {
    setup.edges.map(|e| M::edge_samples(e.a, e.b))
}

impl<M: CoverageMask, E: EdgeValue> EdgeWalk<M, E> {
    #[inline(always)]
    fn new(setup: &TriangleSetup) -> Self {
        Self {
            margin: setup.edges.map(|e| {
                E::from_i64(
                    e.a.unsigned_abs() as i64 * M::max_offset_x() as i64
                        + e.b.unsigned_abs() as i64 * M::max_offset_y() as i64,
                )
            }),
            step_x: setup.edges.map(|e| E::from_i64((e.a as i64) << 4)),
            step_y: setup.edges.map(|e| E::from_i64((e.b as i64) << 4)),
            columns: (setup.x1 - setup.x0) as i32 + 1,
            grid: PhantomData,
        }
    }

    /// The span of the row whose first pixel has edge values `e`.
    #[inline(always)]
    fn span(&self, e: &[E; 3]) -> RowSpan {
        // With one sample, at the center, every margin is zero: said here,
        // the loops of the z-buffer's rows neither load nor negate them.
        let margin = if M::SAMPLES == 1 {
            [E::ZERO; 3]
        } else {
            self.margin
        };
        row_span(e, &self.step_x, &margin, self.columns, M::SAMPLES == 1)
    }

    /// Steps the edge values `e_row` and the depth `z_row` at the bounding
    /// box's first column down one row; returns the new row's span.
    #[inline(always)]
    fn next_row(&self, setup: &TriangleSetup, e_row: &mut [E; 3], z_row: &mut i64) -> RowSpan {
        for i in 0..3 {
            e_row[i] = e_row[i] + self.step_y[i];
        }
        *z_row += setup.depth.dy;
        self.span(e_row)
    }

    /// A walk from the start of image row `y` (within the bounding box).
    #[inline(always)]
    fn first_row(&self, setup: &TriangleSetup, y: u16) -> WalkStart<E> {
        let j = (y - setup.y0) as i64;
        let e_row: [E; 3] = core::array::from_fn(|i| {
            E::from_i64(setup.edges[i].origin + j * ((setup.edges[i].b as i64) << 4))
        });
        WalkStart {
            y,
            e_row,
            z_row: setup.depth.origin + j * setup.depth.dy + PLANE_HALF_UNIT,
            span: self.span(&e_row),
        }
    }
}

/// Where a pixel walk starts: image row `y`, the edge values and depth at
/// the bounding box's first column there (the depth plane's value with
/// [`PLANE_HALF_UNIT`] added, so that each pixel's depth rounds by a shift),
/// and the row's pixels from the start on.
#[derive(Clone, Copy)]
struct WalkStart<E> {
    y: u16,
    e_row: [E; 3],
    z_row: i64,
    span: RowSpan,
}

/// The columns of one row of a triangle's bounding box (counted from its first
/// column) that the triangle touches: `start..end` are the pixels no edge
/// rules out, and within them `full_start..full_end` the pixels every edge
/// clears by its margin (full masks, no per-sample work).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct RowSpan {
    start: i32,
    full_start: i32,
    full_end: i32,
    end: i32,
}

impl RowSpan {
    /// The same span from column `k` (within it) on.
    #[inline(always)]
    fn from(self, k: i32) -> Self {
        let full_start = self.full_start.max(k);
        RowSpan {
            start: k,
            full_start,
            full_end: self.full_end.max(full_start),
            end: self.end,
        }
    }
}

/// Runs of at most this many pixels are walked without looking for their
/// interior: [`pixel_coverage`] tells a full pixel from its three edge
/// values, which costs less than the interior's divisions until runs are
/// longer. Measured on the M4 (frame 0, instructions, `split-bands`):
/// against runs of at most 2 pixels, 8 takes 0.36 M off the teapot, 0.39 M
/// off the spheres, 0.35 M off `blob` and 0.22 M off the starfighter; 6
/// and 12 give the same within 0.02 M, 16 and more lose on the
/// starfighter's large triangles.
const LONGEST_RUN_WITHOUT_INTERIOR: i32 = 8;

/// The span of the row whose first pixel has edge values `e`, for a bounding
/// box `columns` pixels wide: one division per edge that is not vertical.
///
/// An edge value grows by `step_x` per pixel, so the pixels where it is at
/// least `-margin` (not ruled out by this edge) and those where it is at least
/// `margin` (this edge covers every sample) are each one run from the left
/// (`step_x < 0`) or to the right (`step_x > 0`); the span is their
/// intersection over the three edges.
#[inline(always)]
fn row_span<E: EdgeValue>(
    e: &[E; 3],
    step_x: &[E; 3],
    margin: &[E; 3],
    columns: i32,
    one_sample: bool,
) -> RowSpan {
    let (mut start, mut end) = (0i32, columns);
    for i in 0..3 {
        let (v, s, m) = (e[i], step_x[i], margin[i]);
        if s > E::ZERO {
            if v < -m {
                start = start.max(E::steps_to_reach(v, -m, s));
            }
        } else if v < -m {
            end = 0;
        } else if s < E::ZERO {
            end = end.min(E::steps_above(v, -m, s));
        }
    }
    if one_sample {
        // One sample at the center: every pixel not ruled out is covered.
        return RowSpan {
            start,
            full_start: start,
            full_end: end.max(start),
            end,
        };
    }
    // Short runs (small triangles, and most rows of them) have few interior
    // pixels: finding them costs more than looking at their edge values.
    if end - start <= LONGEST_RUN_WITHOUT_INTERIOR {
        return RowSpan {
            start,
            full_start: start,
            full_end: start,
            end,
        };
    }
    let (mut full_start, mut full_end) = (start, end);
    for i in 0..3 {
        let (v, s, m) = (e[i], step_x[i], margin[i]);
        if s > E::ZERO {
            if v < m {
                full_start = full_start.max(E::steps_to_reach(v, m, s));
            }
        } else if v < m {
            full_end = 0;
        } else if s < E::ZERO {
            full_end = full_end.min(E::steps_above(v, m, s));
        }
    }
    let full_start = full_start.min(end);
    RowSpan {
        start,
        full_start,
        full_end: full_end.clamp(full_start, end),
        end,
    }
}

/// Visits the pixels of `setup` with a non-empty mask (from the edges'
/// `tables`) from `start` to the end of image row `y_last`, rows top to
/// bottom and left to right, calling `visitor.visit(x, y, mask, depth,
/// color)` (depth with 16 extra fraction bits, color from `walk`, which
/// starts positioned at the first column of `start`'s row). When it returns
/// `true` the walk stops and returns where, so that another walk can go on
/// from that pixel (included).
///
/// Per row, [`row_span`] finds the pixels no edge rules out (every edge value
/// at the center at least minus its margin: a convex set, so one run per row)
/// and, within them, the interior run where every mask is full. Only the
/// pixels between the two look at samples; the result is the same as testing
/// every pixel of the bounding box.
#[inline(always)]
fn walk_pixels<M, E, W, V>(
    setup: &TriangleSetup,
    edges: &EdgeWalk<M, E>,
    tables: &EdgeTables<M>,
    y_last: u16,
    start: WalkStart<E>,
    walk: &mut W,
    visitor: &mut V,
) -> Option<WalkStart<E>>
where
    M: CoverageMask,
    E: EdgeValue,
    W: ColorWalk,
    V: PixelVisitor<M>,
{
    let dz = setup.depth.dx;
    let x0 = setup.x0 as i32;
    // Edge values and depth at the first pixel of the current row, stepped
    // down one row at a time (the same integers as evaluating each row);
    // plain integer counters: the pixel loops below keep few values live.
    let WalkStart {
        mut e_row,
        mut z_row,
        mut span,
        ..
    } = start;
    let mut y = start.y as i32;
    loop {
        if span.start < span.end {
            let row = y as u16;
            let e = e_row;
            let mut color = walk.row();
            walk.skip(&mut color, span.start as u16);
            // The depth at column `k`: with one sample per pixel, stepped
            // along with the colors; with a grid, whose masks leave the
            // loops few registers, the row's value plus `k` steps, one
            // multiply-accumulate where a pixel is visited
            // (`count_mul_add`; the same integers; measured in
            // `docs/m4-benchmark-history.md`).
            // Columns are counted from the box's first, never negative: as
            // `u32`, one multiplication fewer than a signed column.
            let stepped = M::SAMPLES == 1;
            let mut z = z_row + span.start as u32 as i64 * dz;
            let depth_at = |k: i32, z: i64| {
                if stepped {
                    z
                } else {
                    count_mul_add(z_row, k as u32, dz)
                }
            };
            // Where to go on from column `k` (counted from the box's first).
            let stop = |k: i32| {
                Some(WalkStart {
                    y: row,
                    e_row: e,
                    z_row,
                    span: span.from(k),
                })
            };
            // Pixels near an edge: their exact masks from the samples. A
            // pixel's edge values are the row's plus its column's steps, by
            // `EdgeValue::at_column` (one `mla` each in `i32`): stepped, the
            // three values stayed live through the loop and were spilled
            // (measured in `docs/m4-benchmark-history.md`).
            macro_rules! edge_pixels {
                ($from:expr, $to:expr) => {
                    let (mut k, to) = ($from, $to);
                    while k < to {
                        let at: [E; 3] =
                            core::array::from_fn(|i| e[i].at_column(edges.step_x[i], k as u32));
                        let mask = pixel_coverage::<M, E>(&at, tables, &edges.margin);
                        if !mask.is_empty()
                            && visitor.visit(
                                (x0 + k) as u16,
                                row,
                                mask,
                                depth_at(k, z),
                                walk.color(&color),
                            )
                        {
                            return stop(k);
                        }
                        walk.step(&mut color);
                        if stepped {
                            z += dz;
                        }
                        k += 1;
                    }
                };
            }
            edge_pixels!(span.start, span.full_start);
            // The interior: full masks.
            let (mut k, to) = (span.full_start, span.full_end);
            while k < to {
                let depth = depth_at(k, z);
                if visitor.visit((x0 + k) as u16, row, M::FULL, depth, walk.color(&color)) {
                    return stop(k);
                }
                walk.step(&mut color);
                if stepped {
                    z += dz;
                }
                k += 1;
            }
            edge_pixels!(span.full_end, span.end);
        }
        if y >= y_last as i32 {
            return None;
        }
        y += 1;
        walk.next_row();
        span = edges.next_row(setup, &mut e_row, &mut z_row);
    }
}
