//! Rasterization: walks a set-up triangle's pixels within a band, builds each
//! pixel's coverage mask from the signs of the edge functions at the samples, and
//! hands one fragment per covered pixel to a [`BandBuffer`].
//!
//! Per pixel, the three edge values at the center decide cheaply: when every edge
//! clears the center by more than the farthest sample offset, the mask is full
//! (interior pixel); when one edge is below minus that margin, the pixel is ruled
//! out, and the pixels no edge rules out form one run per row. Only the remaining
//! pixels look at samples, through [`CoverageMask::edge_coverage`] (sorted sample
//! thresholds for 4x4, the edge function stepped across the grid with additions
//! otherwise; SPEC section 2).
//!
//! Fragments are first offered to the buffer without a color; a triangle's
//! colors are set up when its first fragment survives, and a triangle the
//! buffer already hides in the whole band is skipped before any fragment
//! ([`hidden_in_band`]).

use crate::band_buffer::BandBuffer;
use crate::coverage::CoverageMask;
use crate::fixed_point::DEPTH_MAX;
use crate::fragment::Fragment;
use crate::setup::{ColorPlanes, Edge, TriangleSetup};
use crate::shading::{ColorWalk, ConstantWalk, LinearWalk, PhongWalk, QuadraticWalk};
use embedded_graphics_core::pixelcolor::Rgb888;

/// Samples where one edge function (value `e` at the pixel center, already biased)
/// is non-negative.
#[inline]
pub fn edge_mask<M: CoverageMask>(e: i64, edge: &Edge) -> M {
    // Near an edge |e| is below the margin (< 2^22), so 32 bits suffice.
    M::edge_coverage(&M::edge_samples(edge.a as i32, edge.b as i32), e as i32)
}

/// An integer type edge functions are stepped in: `i32` when a triangle's edge
/// values fit (nearly always), `i64` otherwise.
trait EdgeValue:
    Copy + PartialOrd + core::ops::Add<Output = Self> + core::ops::Neg<Output = Self>
{
    fn from_i64(v: i64) -> Self;
    fn near(self) -> i32;
    /// `self * n` (the result is an edge value the walk reaches, so it fits).
    fn times(self, n: i64) -> Self;
    /// The fewest steps of `step > 0` that take `value < target` to `target` or beyond.
    fn steps_to_reach(value: Self, target: Self, step: Self) -> i64;
}

impl EdgeValue for i32 {
    #[inline]
    fn from_i64(v: i64) -> Self {
        v as i32
    }
    #[inline]
    fn near(self) -> i32 {
        self
    }
    #[inline]
    fn times(self, n: i64) -> Self {
        self * n as i32
    }
    #[inline]
    fn steps_to_reach(value: Self, target: Self, step: Self) -> i64 {
        // Both differences are below 2^31 in magnitude and positive here.
        let gap = (target - value) as u32;
        gap.div_ceil(step as u32) as i64
    }
}

impl EdgeValue for i64 {
    #[inline]
    fn from_i64(v: i64) -> Self {
        v
    }
    #[inline]
    fn near(self) -> i32 {
        self as i32
    }
    #[inline]
    fn times(self, n: i64) -> Self {
        self * n
    }
    #[inline]
    fn steps_to_reach(value: Self, target: Self, step: Self) -> i64 {
        ((target - value) as u64).div_ceil(step as u64) as i64
    }
}

/// Coverage of the pixel whose center has edge values `e`, given each edge's
/// margin (the largest change of that edge from the center to a sample).
/// `None` when an edge has every sample outside (the pixel is ruled out).
#[inline(always)]
fn pixel_coverage<M: CoverageMask, E: EdgeValue>(
    e: &[E; 3],
    edges: &[M::EdgeSamples; 3],
    margin: &[E; 3],
) -> Option<M> {
    if e[0] < -margin[0] || e[1] < -margin[1] || e[2] < -margin[2] {
        return None;
    }
    let mut mask = M::FULL;
    for i in 0..3 {
        if e[i] < margin[i] {
            mask = mask & M::edge_coverage(&edges[i], e[i].near());
        }
    }
    Some(mask)
}

/// Whether every edge value over the rows `y_first..=y_last` of the bounding box
/// (and one step beyond) stays within `±2^30`, so the pixel loop can run in `i32`.
fn edges_fit_i32(setup: &TriangleSetup, y_first: u16, y_last: u16) -> bool {
    let columns = (setup.x1 - setup.x0) as i64 + 1;
    let rows = (y_last - setup.y0) as i64 + 1;
    let _ = y_first;
    setup.edges.iter().all(|e| {
        let bound = e.origin.abs() + (e.a.abs() << 4) * columns + (e.b.abs() << 4) * rows;
        bound < 1 << 30
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
    if band_rows == 0 {
        return;
    }
    let band_last = band_y0 as u32 + band_rows as u32 - 1;
    let y_first = setup.y0.max(band_y0);
    let y_last = (setup.y1 as u32).min(band_last) as u16;
    if y_first > y_last || setup.x0 > setup.x1 {
        return;
    }
    let rows = RowRange {
        first: y_first,
        last: y_last,
        band_y0,
    };
    if edges_fit_i32(setup, y_first, y_last) {
        rasterize_with::<M, B, i32, F>(setup, rows, buffer, colors)
    } else {
        rasterize_with::<M, B, i64, F>(setup, rows, buffer, colors)
    }
}

/// Whether `buffer` hides every fragment `setup` could leave in the band
/// starting at image row `band_y0` with `band_rows` rows: every pixel of the
/// triangle's bounding box there holds something strictly nearer, at every
/// sample, than the nearest sample depth any of its fragments can have. Then
/// rasterizing it would change nothing (each fragment would be hidden on
/// arrival), so it is counted and skipped.
///
/// The bound is exact for the fragments the rasterizer makes: their depth at a
/// pixel center is the walked plane, whose smallest value over the box is at
/// one of its corners, rounded as fragments are; a sample lies at most the
/// grid's largest offsets from the center.
pub fn hidden_in_band<M: CoverageMask, B: BandBuffer<M>>(
    setup: &TriangleSetup,
    band_y0: u16,
    band_rows: u16,
    buffer: &mut B,
) -> bool {
    if band_rows == 0 {
        return false;
    }
    let band_last = band_y0 as u32 + band_rows as u32 - 1;
    let y_first = setup.y0.max(band_y0);
    let y_last = (setup.y1 as u32).min(band_last) as u16;
    if y_first > y_last || setup.x0 > setup.x1 {
        return false;
    }
    let d = &setup.depth;
    let (i1, j0, j1) = (
        (setup.x1 - setup.x0) as i64,
        (y_first - setup.y0) as i64,
        (y_last - setup.y0) as i64,
    );
    let corner = |i: i64, j: i64| d.origin + i * d.dx + j * d.dy;
    let nearest = corner(0, j0)
        .min(corner(i1, j0))
        .min(corner(0, j1))
        .min(corner(i1, j1));
    let z = ((nearest + (1 << 15)) >> 16).clamp(0, DEPTH_MAX as i64);
    let bound = 16 * z
        - setup.dzdx.unsigned_abs() as i64 * M::max_offset_x() as i64
        - setup.dzdy.unsigned_abs() as i64 * M::max_offset_y() as i64;
    let mut asked = 0u32;
    for row in y_first - band_y0..y_last - band_y0 + 1 {
        for x in setup.x0..setup.x1 + 1 {
            asked += 1;
            if !buffer.hides(x, row, bound) {
                buffer.count_triangle_test(asked, false);
                return false;
            }
        }
    }
    buffer.count_triangle_test(asked, true);
    true
}

/// The image rows of a triangle within one band.
#[derive(Clone, Copy)]
struct RowRange {
    first: u16,
    last: u16,
    band_y0: u16,
}

/// A fragment of `setup` without its color yet.
#[inline(always)]
fn fragment_at<M: CoverageMask>(
    setup: &TriangleSetup,
    mask: M,
    z: i64,
    color: Rgb888,
) -> Fragment<M> {
    let z = (z + (1 << 15)) >> 16;
    Fragment {
        mask,
        // One comparison in the common case.
        z: if (z as u64) <= DEPTH_MAX as u64 {
            z as u32
        } else if z < 0 {
            0
        } else {
            DEPTH_MAX
        },
        dzdx: setup.dzdx,
        dzdy: setup.dzdy,
        color,
    }
}

/// Finds the first surviving fragment, then sets up colors and inserts from there.
#[inline]
fn rasterize_with<M, B, E, F>(setup: &TriangleSetup, rows: RowRange, buffer: &mut B, colors: F)
where
    M: CoverageMask,
    B: BandBuffer<M>,
    E: EdgeValue,
    F: FnOnce() -> ColorPlanes,
{
    let samples = setup.edges.map(|e| M::edge_samples(e.a as i32, e.b as i32));
    let mut first = None;
    walk_pixels::<M, E, _>(
        setup,
        &samples,
        rows.last,
        (setup.x0, rows.first),
        |x, y, mask, z| {
            let probe = fragment_at(setup, mask, z, Rgb888::new(0, 0, 0));
            if buffer.survives(x, y - rows.band_y0, &probe) {
                first = Some((x, y));
                true
            } else {
                false
            }
        },
    );
    let Some(start) = first else {
        return;
    };
    // One loop per kind of color, so the per-pixel work has no branch on it.
    let j = (start.1 - setup.y0) as i64;
    macro_rules! insert_with {
        ($walk:expr) => {
            insert_from::<M, B, E, _>(setup, &samples, rows, start, $walk, buffer)
        };
    }
    match colors() {
        ColorPlanes::Constant(c) => insert_with!(ConstantWalk(c)),
        ColorPlanes::Linear(p) => insert_with!(LinearWalk::start(&p, j)),
        ColorPlanes::Quadratic(p) => insert_with!(QuadraticWalk::start(&p, j)),
        ColorPlanes::Phong(p) => insert_with!(PhongWalk::start(&p, j)),
    }
}

/// Inserts the fragments of `setup` from pixel `start` (image coordinates) on,
/// colors from `walk` (positioned at the first column of `start`'s row).
// Kept out of line: one copy per kind of color, each with its own registers.
#[inline(never)]
fn insert_from<M, B, E, W>(
    setup: &TriangleSetup,
    samples: &[M::EdgeSamples; 3],
    rows: RowRange,
    start: (u16, u16),
    walk: W,
    buffer: &mut B,
) where
    M: CoverageMask,
    B: BandBuffer<M>,
    E: EdgeValue,
    W: ColorWalk,
{
    let mut colors = PositionedWalk::new(walk, start.1);
    walk_pixels::<M, E, _>(setup, samples, rows.last, start, |x, y, mask, z| {
        let color = colors.color_at(x - setup.x0, y);
        buffer.insert(x, y - rows.band_y0, &fragment_at(setup, mask, z, color));
        false
    });
}

/// A color walk that follows the rasterizer: rows top to bottom, columns left
/// to right within a row, stepping by additions from the row's first column.
struct PositionedWalk<W: ColorWalk> {
    walk: W,
    row: W::Row,
    column: u16,
    y: u16,
}

impl<W: ColorWalk> PositionedWalk<W> {
    /// `walk` positioned at the first column of image row `y`.
    #[inline]
    fn new(walk: W, y: u16) -> Self {
        Self {
            row: walk.row(),
            walk,
            column: 0,
            y,
        }
    }

    /// The color at column `column` (from the bounding box's first) of image row
    /// `y`; rows and, within a row, columns never go back.
    #[inline(always)]
    fn color_at(&mut self, column: u16, y: u16) -> Rgb888 {
        if y != self.y {
            while self.y < y {
                self.walk.next_row();
                self.y += 1;
            }
            self.row = self.walk.row();
            self.column = 0;
        }
        match column - self.column {
            0 => {}
            1 => self.walk.step(&mut self.row),
            n => self.walk.skip(&mut self.row, n),
        }
        self.column = column;
        self.walk.color(&self.row)
    }
}

/// Visits the pixels of `setup` with a non-empty mask, from pixel `start`
/// (image coordinates) to the end of image row `y_last`, rows top to bottom and
/// left to right, calling `visit(x, y, mask, depth)` (depth with 16 extra
/// fraction bits); stops early when `visit` returns `true`.
///
/// Per row, the walk starts at the first column not ruled out by an edge that
/// rises to the right (one division per such edge) and ends at the first
/// column ruled out after that: the pixels no edge rules out (every edge value
/// at the center at least minus its margin) form a convex set, so they are one
/// run per row. Pixels in the run still get their exact masks.
#[inline(always)]
fn walk_pixels<M, E, V>(
    setup: &TriangleSetup,
    samples: &[M::EdgeSamples; 3],
    y_last: u16,
    start: (u16, u16),
    mut visit: V,
) where
    M: CoverageMask,
    E: EdgeValue,
    V: FnMut(u16, u16, M, i64) -> bool,
{
    let margin: [E; 3] = setup.edges.map(|e| {
        E::from_i64(e.a.abs() * M::max_offset_x() as i64 + e.b.abs() * M::max_offset_y() as i64)
    });
    let step_x: [E; 3] = setup.edges.map(|e| E::from_i64(e.a << 4));
    let step_y = setup.edges.map(|e| e.b << 4);
    let (start_x, start_y) = start;
    // Half-open ranges: inclusive ones cost an extra test per step.
    for y in start_y..y_last + 1 {
        let dy = (y - setup.y0) as i64;
        let mut e: [E; 3] = [E::from_i64(0); 3];
        for i in 0..3 {
            e[i] = E::from_i64(setup.edges[i].origin + dy * step_y[i]);
        }
        // Columns to skip: up to the resume column on the first row, and past
        // every edge that rises to the right but is still below its margin.
        let mut skip = if y == start_y {
            (start_x - setup.x0) as i64
        } else {
            0
        };
        for i in 0..3 {
            if step_x[i] > E::from_i64(0) && e[i] < -margin[i] {
                skip = skip.max(E::steps_to_reach(e[i], -margin[i], step_x[i]));
            }
        }
        let columns = (setup.x1 - setup.x0) as i64 + 1;
        if skip >= columns {
            continue;
        }
        let mut x = setup.x0 + skip as u16;
        for i in 0..3 {
            e[i] = e[i] + E::times(step_x[i], skip);
        }
        let mut z = setup.depth.origin + dy * setup.depth.dy + skip * setup.depth.dx;
        while x <= setup.x1 {
            let Some(mask) = pixel_coverage::<M, E>(&e, samples, &margin) else {
                break;
            };
            if !mask.is_empty() && visit(x, y, mask, z) {
                return;
            }
            for i in 0..3 {
                e[i] = e[i] + step_x[i];
            }
            z += setup.depth.dx;
            x += 1;
        }
    }
}
