//! Gouraud shading: the lit vertex colors interpolated linearly over the
//! triangle, one addition per channel and pixel ([`LinearWalk`]).

use super::{ColorWalk, PlaneValue};
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
