//! Rasterization: walks a set-up triangle's pixels within a band, builds each
//! pixel's coverage mask from the signs of the edge functions at the samples, and
//! hands one fragment per covered pixel to a [`BandBuffer`].
//!
//! Per pixel, the three edge values at the center decide cheaply: when every edge
//! clears the center by more than the farthest sample offset, the mask is full
//! (interior pixel); when one edge is below minus that margin, it is empty. Only
//! the remaining pixels evaluate samples, stepping each edge function across the
//! grid with additions (SPEC section 2).

use crate::band_buffer::BandBuffer;
use crate::coverage::CoverageMask;
use crate::fixed_point::DEPTH_MAX;
use crate::fragment::Fragment;
use crate::setup::{ColorPlanes, Edge, TriangleSetup};
use crate::shading::{ColorWalk, ConstantWalk, LinearWalk, PhongWalk, QuadraticWalk};

/// Samples where one edge function (value `e` at the pixel center, already biased)
/// is non-negative.
#[inline]
pub fn edge_mask<M: CoverageMask>(e: i64, edge: &Edge) -> M {
    // Near an edge |e| is below the margin (< 2^22), so 32 bits suffice.
    edge_mask_near::<M>(e as i32, edge.a as i32, edge.b as i32)
}

/// [`edge_mask`] for an edge value `e` within the pixel's margin, with the edge's
/// steps `a` (x) and `b` (y) per 1/16 pixel.
#[inline]
fn edge_mask_near<M: CoverageMask>(e: i32, a: i32, b: i32) -> M {
    let mut row_value = e + a * M::offset_x(0) + b * M::offset_y(0);
    let step_x = a * (16 / M::COLS as i32);
    let step_y = b * (16 / M::ROWS as i32);
    if M::SAMPLES <= 32 {
        // One 32-bit word: the common grids (4x4, 8x4) on 32-bit cores.
        let mut bits = 0u32;
        let mut bit = 0;
        for _ in 0..M::ROWS {
            let mut value = row_value;
            for _ in 0..M::COLS {
                bits |= ((value >= 0) as u32) << bit;
                bit += 1;
                value += step_x;
            }
            row_value += step_y;
        }
        M::from_u64(bits as u64)
    } else {
        let mut bits = 0u64;
        let mut bit = 0;
        for _ in 0..M::ROWS {
            let mut value = row_value;
            for _ in 0..M::COLS {
                bits |= ((value >= 0) as u64) << bit;
                bit += 1;
                value += step_x;
            }
            row_value += step_y;
        }
        M::from_u64(bits)
    }
}

/// An integer type edge functions are stepped in: `i32` when a triangle's edge
/// values fit (nearly always), `i64` otherwise.
trait EdgeValue:
    Copy + PartialOrd + core::ops::Add<Output = Self> + core::ops::Neg<Output = Self>
{
    fn from_i64(v: i64) -> Self;
    fn near(self) -> i32;
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
}

/// Coverage of the pixel whose center has edge values `e`, given each edge's
/// margin (the largest change of that edge from the center to a sample).
#[inline]
fn pixel_coverage<M: CoverageMask, E: EdgeValue>(
    e: &[E; 3],
    edges: &[Edge; 3],
    margin: &[E; 3],
) -> M {
    let mut mask = M::FULL;
    for i in 0..3 {
        if e[i] >= margin[i] {
            continue;
        }
        if e[i] < -margin[i] {
            return M::EMPTY;
        }
        mask = mask & edge_mask_near::<M>(e[i].near(), edges[i].a as i32, edges[i].b as i32);
    }
    mask
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
pub fn rasterize<M: CoverageMask, B: BandBuffer<M>>(
    setup: &TriangleSetup,
    band_y0: u16,
    band_rows: u16,
    buffer: &mut B,
) {
    if band_rows == 0 {
        return;
    }
    let band_last = band_y0 as u32 + band_rows as u32 - 1;
    let y_first = setup.y0.max(band_y0);
    let y_last = (setup.y1 as u32).min(band_last) as u16;
    if y_first > y_last || setup.x0 > setup.x1 {
        return;
    }
    // One loop per kind of color, so the per-pixel work has no branch on it.
    let first_row = (y_first - setup.y0) as i64;
    let rows = (y_first, y_last, band_y0);
    if edges_fit_i32(setup, y_first, y_last) {
        rasterize_with::<M, B, i32>(setup, rows, first_row, buffer)
    } else {
        rasterize_with::<M, B, i64>(setup, rows, first_row, buffer)
    }
}

/// Picks the color walk of `setup` and rasterizes with edges in `E`.
#[inline]
fn rasterize_with<M: CoverageMask, B: BandBuffer<M>, E: EdgeValue>(
    setup: &TriangleSetup,
    rows: (u16, u16, u16),
    first_row: i64,
    buffer: &mut B,
) {
    match &setup.colors {
        ColorPlanes::Constant(c) => {
            rasterize_rows::<M, B, ConstantWalk, E>(setup, rows, ConstantWalk(*c), buffer)
        }
        ColorPlanes::Linear(p) => {
            rasterize_rows::<M, B, _, E>(setup, rows, LinearWalk::start(p, first_row), buffer)
        }
        ColorPlanes::Quadratic(p) => {
            rasterize_rows::<M, B, _, E>(setup, rows, QuadraticWalk::start(p, first_row), buffer)
        }
        ColorPlanes::Phong(p) => {
            rasterize_rows::<M, B, _, E>(setup, rows, PhongWalk::start(p, first_row), buffer)
        }
    }
}

/// Rasterizes image rows `rows.0 ..= rows.1` of `setup` into the band starting
/// at image row `rows.2`, colors from `colors` (positioned at row `rows.0`).
// Kept out of line: one copy per kind of color, each with its own registers.
#[inline(never)]
fn rasterize_rows<M: CoverageMask, B: BandBuffer<M>, W: ColorWalk, E: EdgeValue>(
    setup: &TriangleSetup,
    rows: (u16, u16, u16),
    mut colors: W,
    buffer: &mut B,
) {
    let (y_first, y_last, band_y0) = rows;
    let margin: [E; 3] = setup.edges.map(|e| {
        E::from_i64(e.a.abs() * M::max_offset_x() as i64 + e.b.abs() * M::max_offset_y() as i64)
    });
    let step_x: [E; 3] = setup.edges.map(|e| E::from_i64(e.a << 4));
    let step_y = setup.edges.map(|e| e.b << 4);
    // Half-open ranges: inclusive ones cost an extra test per step.
    for y in y_first..y_last + 1 {
        let dy = (y - setup.y0) as i64;
        let mut e: [E; 3] = [E::from_i64(0); 3];
        for i in 0..3 {
            e[i] = E::from_i64(setup.edges[i].origin + dy * step_y[i]);
        }
        let mut z = setup.depth.origin + dy * setup.depth.dy;
        let mut pixel_colors = colors.row();
        let row = y - band_y0;
        for x in setup.x0..setup.x1 + 1 {
            let mask = pixel_coverage::<M, E>(&e, &setup.edges, &margin);
            if !mask.is_empty() {
                let color = colors.color(&pixel_colors);
                let fragment = Fragment {
                    mask,
                    z: ((z + (1 << 15)) >> 16).clamp(0, DEPTH_MAX as i64) as u32,
                    dzdx: setup.dzdx,
                    dzdy: setup.dzdy,
                    color,
                };
                buffer.insert(x, row, &fragment);
            }
            for i in 0..3 {
                e[i] = e[i] + step_x[i];
            }
            z += setup.depth.dx;
            colors.step(&mut pixel_colors);
        }
        colors.next_row();
    }
}
