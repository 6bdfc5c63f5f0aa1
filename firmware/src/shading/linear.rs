//! Gouraud shading: the lit vertex colors interpolated linearly over the
//! triangle, one addition per channel and pixel ([`LinearWalk`]).

use super::{ColorWalk, PlaneValue};
use crate::fixed_point::{Reciprocal, SUBPIXEL_BITS};
use crate::lighting::ColorQ8;
use crate::setup::Plane;
use embedded_graphics_core::pixelcolor::Rgb888;

/// Linear color planes (Gouraud): one addition per channel and pixel, in
/// `i64` or, when [`LinearWalk::fits`], in `i32` (half the registers).
#[derive(Clone, Copy, Debug)]
pub struct LinearWalk<V: PlaneValue = i64> {
    row_start: [V; 3],
    dx: [V; 3],
    dy: [V; 3],
}

impl<V: PlaneValue> LinearWalk<V> {
    /// Starts at row `j` of the bounding box of planes `p` (16 fraction bits);
    /// for `V = i32` the planes must [`LinearWalk::fits`].
    #[inline]
    pub fn start(p: &[Plane; 3], j: i64) -> Self {
        Self {
            row_start: p.map(|p| V::from_i64(p.origin + j * p.dy)),
            dx: p.map(|p| V::from_i64(p.dx)),
            dy: p.map(|p| V::from_i64(p.dy)),
        }
    }
}

impl LinearWalk<i32> {
    /// Whether every value of planes `p` over the bounding box of `setup`
    /// (and one step beyond it) is below 2^30 in magnitude, so the walk can
    /// run in `i32`.
    pub fn fits(p: &[Plane; 3], setup: &crate::setup::TriangleSetup) -> bool {
        let columns = (setup.x1 - setup.x0) as i64 + 1;
        let rows = (setup.y1 - setup.y0) as i64 + 1;
        p.iter().all(|p| {
            p.origin.unsigned_abs() as i64
                + p.dx.unsigned_abs() as i64 * columns
                + p.dy.unsigned_abs() as i64 * rows
                < 1 << 30
        })
    }
}

impl<V: PlaneValue> ColorWalk for LinearWalk<V> {
    type Row = [V; 3];
    #[inline]
    fn row(&self) -> [V; 3] {
        self.row_start
    }
    #[inline]
    fn next_row(&mut self) {
        for c in 0..3 {
            self.row_start[c] += self.dy[c];
        }
    }
    #[inline]
    fn color(&self, row: &[V; 3]) -> Rgb888 {
        Rgb888::new(row[0].channel16(), row[1].channel16(), row[2].channel16())
    }
    #[inline]
    fn step(&self, row: &mut [V; 3]) {
        for c in 0..3 {
            row[c] += self.dx[c];
        }
    }
    #[inline]
    fn skip(&self, row: &mut [V; 3], n: u16) {
        for c in 0..3 {
            row[c] += self.dx[c] * V::from_count(n);
        }
    }
}

/// Planes through the vertex colors (Q8), values with 16 fraction bits, over
/// pixel centers from `center` (1/16 pixel); `area2 > 0` for vertices `xs`, `ys`.
#[inline(always)]
pub(super) fn color_planes(
    colors: &[ColorQ8; 3],
    xs: &[i64; 3],
    ys: &[i64; 3],
    center: (i64, i64),
    area2: Reciprocal,
) -> [Plane; 3] {
    let (dx1, dy1) = (xs[1] - xs[0], ys[1] - ys[0]);
    let (dx2, dy2) = (xs[2] - xs[0], ys[2] - ys[0]);
    let shift = 8 + SUBPIXEL_BITS;
    let steps = |ch: usize| {
        let c0 = colors[0][ch] as i64;
        (colors[1][ch] as i64 - c0, colors[2][ch] as i64 - c0)
    };
    // The x and y gradients of the three channels, by one reciprocal.
    let gradients = area2.mul_div_each(
        core::array::from_fn::<_, 6, _>(|k| {
            let (dc1, dc2) = steps(k / 2);
            if k % 2 == 0 {
                dc1 * dy2 - dc2 * dy1
            } else {
                dx1 * dc2 - dx2 * dc1
            }
        }),
        shift,
    );
    core::array::from_fn(|ch| {
        let (gx, gy) = (gradients[2 * ch], gradients[2 * ch + 1]);
        Plane {
            origin: (((colors[0][ch] as i64) << shift)
                + gx * (center.0 - xs[0])
                + gy * (center.1 - ys[0]))
                >> SUBPIXEL_BITS,
            dx: gx,
            dy: gy,
        }
    })
}
