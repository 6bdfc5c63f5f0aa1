//! Gouraud shading: the lit vertex colors interpolated linearly over the
//! triangle, one addition per channel and pixel ([`LinearWalk`]).

use super::{rounding_bias, ColorWalk, PlaneValue};
use crate::fixed_point::{Reciprocal, SUBPIXEL_BITS};
use crate::lighting::ColorQ8;
use crate::setup::Plane;
use core::num::Wrapping;
use core::ops::{Mul, Sub};
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
    /// for `V = i32` the planes must [`LinearWalk::fits`]. The values carry
    /// the [`rounding_bias`] from here on.
    #[inline]
    pub fn start(p: &[Plane; 3], j: i64) -> Self {
        Self {
            row_start: p.map(|p| V::from_i64(p.origin + j * p.dy + rounding_bias(16))),
            dx: p.map(|p| V::from_i64(p.dx)),
            dy: p.map(|p| V::from_i64(p.dy)),
        }
    }
}

impl LinearWalk<i64> {
    /// The planes' own values in a row's state (the walk's values less the
    /// [`rounding_bias`] they carry): for planes that are not colors, such
    /// as Phong's normals.
    #[inline]
    pub fn plane_values(row: &[i64; 3]) -> [i64; 3] {
        row.map(|v| v - rounding_bias(16))
    }
}

impl LinearWalk<i32> {
    /// Whether every value of planes `p` over the bounding box of `setup`
    /// (and one step beyond it) is below 2^30 in magnitude, so the walk can
    /// run in `i32` (with the [`rounding_bias`] added, below 2^31).
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

/// Bound (1/16 pixel, exclusive) on the coordinate steps of a triangle whose
/// color gradients [`color_planes`] finds in words: 1,024 pixels.
const SHORT_EDGE_LIMIT: i32 = 1 << 14;

/// The numerators of the x and y gradients of the three channels (channel
/// after channel, x before y): the colors' steps along the edges from vertex
/// 0 crossed with the coordinate steps `[dx1, dy1, dx2, dy2]`. Wrapping:
/// colors outside [`ColorSource::Linear`](super::ColorSource::Linear)'s
/// range give meaningless planes, never a panic.
#[inline(always)]
fn gradient_numerators<T>(colors: &[ColorQ8; 3], steps: [T; 4]) -> [T; 6]
where
    T: Copy + From<i32>,
    Wrapping<T>: Mul<Output = Wrapping<T>> + Sub<Output = Wrapping<T>>,
{
    let [dx1, dy1, dx2, dy2] = steps.map(Wrapping);
    core::array::from_fn(|k| {
        let color = |v: usize| Wrapping(T::from(colors[v][k / 2]));
        let (dc1, dc2) = (color(1) - color(0), color(2) - color(0));
        let Wrapping(n) = if k % 2 == 0 {
            dc1 * dy2 - dc2 * dy1
        } else {
            dx1 * dc2 - dx2 * dc1
        };
        n
    })
}

/// Extra bits of the color gradients' quotients: Q8 colors over 1/16 pixel
/// to 16 fraction bits per pixel.
const GRADIENT_SHIFT: u32 = 8 + SUBPIXEL_BITS;

/// The corners' steps from vertex 0, `[dx1, dy1, dx2, dy2]` (1/16 pixel).
#[inline(always)]
fn corner_steps(xs: &[i32; 3], ys: &[i32; 3]) -> [i32; 4] {
    [xs[1] - xs[0], ys[1] - ys[0], xs[2] - xs[0], ys[2] - ys[0]]
}

/// The gradients of the three channels (x then y, channel after channel) by
/// one reciprocal, with every product in `i64`.
#[inline(always)]
fn gradients_in_i64(colors: &[ColorQ8; 3], steps: [i32; 4], area2: Reciprocal) -> [i64; 6] {
    area2.mul_div_each(
        gradient_numerators(colors, steps.map(i64::from)),
        GRADIENT_SHIFT,
    )
}

/// Planes through the vertex colors (Q8), values with 16 fraction bits, over
/// pixel centers from `center` (1/16 pixel); `area2 > 0` for vertices `xs`, `ys`
/// (1/16 pixel, within the guard band).
#[inline(always)]
pub(super) fn color_planes(
    colors: &[ColorQ8; 3],
    xs: &[i32; 3],
    ys: &[i32; 3],
    center: (i32, i32),
    area2: Reciprocal,
) -> [Plane; 3] {
    let steps = corner_steps(xs, ys);
    let gradients = if steps.iter().fold(0, |m, d| m | d.abs()) < SHORT_EDGE_LIMIT {
        // In words: color steps below 2^16 times coordinate steps below
        // 2^14, so each product is below 2^30 and their difference fits
        // `i32`. The same quotients as in `i64`.
        area2.mul_div_each_word(gradient_numerators(colors, steps), GRADIENT_SHIFT)
    } else {
        gradients_in_i64(colors, steps, area2)
    };
    planes_of(colors, xs, ys, center, &gradients)
}

/// The planes with `gradients` ([`color_planes`]'s) through vertex 0's
/// colors, their origins at `center`.
#[inline(always)]
fn planes_of(
    colors: &[ColorQ8; 3],
    xs: &[i32; 3],
    ys: &[i32; 3],
    center: (i32, i32),
    gradients: &[i64; 6],
) -> [Plane; 3] {
    let (u0, v0) = ((center.0 - xs[0]) as i64, (center.1 - ys[0]) as i64);
    core::array::from_fn(|ch| {
        let (gx, gy) = (gradients[2 * ch], gradients[2 * ch + 1]);
        Plane {
            origin: (((colors[0][ch] as i64) << GRADIENT_SHIFT) + gx * u0 + gy * v0)
                >> SUBPIXEL_BITS,
            dx: gx,
            dy: gy,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::xorshift;

    /// The planes with every product in `i64`, as for long edges.
    fn planes_in_i64(
        colors: &[ColorQ8; 3],
        xs: &[i32; 3],
        ys: &[i32; 3],
        center: (i32, i32),
        area2: Reciprocal,
    ) -> [Plane; 3] {
        let gradients = gradients_in_i64(colors, corner_steps(xs, ys), area2);
        planes_of(colors, xs, ys, center, &gradients)
    }

    #[test]
    fn short_edges_give_the_planes_of_64_bit_products() {
        let mut next = xorshift(0x51_7cc1_b727_220a);
        let mut checked = 0;
        for i in 0..200_000 {
            // Edges up to the word path's bound, and some beyond it.
            let reach = if i % 8 == 0 {
                1 << 15
            } else {
                SHORT_EDGE_LIMIT
            };
            let mut corner = || (next() % (2 * reach as u64)) as i32 - reach;
            let (xs, ys) = ([0, corner(), corner()], [0, corner(), corner()]);
            let area2 = (xs[1] as i64 * ys[2] as i64) - (xs[2] as i64 * ys[1] as i64);
            if area2 <= 0 {
                continue;
            }
            let colors: [ColorQ8; 3] =
                core::array::from_fn(|_| core::array::from_fn(|_| (next() % 65281) as i32));
            let x0 = xs.iter().min().unwrap() >> SUBPIXEL_BITS;
            let y0 = ys.iter().min().unwrap() >> SUBPIXEL_BITS;
            let center = ((x0 << SUBPIXEL_BITS) + 8, (y0 << SUBPIXEL_BITS) + 8);
            let area2 = Reciprocal::new(area2 as u64);
            assert_eq!(
                color_planes(&colors, &xs, &ys, center, area2),
                planes_in_i64(&colors, &xs, &ys, center, area2),
                "{xs:?} {ys:?} {colors:?}"
            );
            checked += 1;
        }
        assert!(checked > 50_000, "{checked}");
    }
}
