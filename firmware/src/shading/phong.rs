//! Phong shading, the reference the other modes are measured against: the
//! vertex normals interpolated linearly over the triangle ([`normal_planes`]),
//! then renormalized and lit at every covered pixel ([`PhongWalk`]). An
//! integer square root and divisions per pixel: for comparison, not a fast path.

use super::linear::LinearWalk;
use super::ColorWalk;
use crate::fixed_point::{SUBPIXEL_BITS, UNIT_BITS};
use crate::lighting::{normalize_unit, rgb888_rounded, ColorQ8, LightSetup};
use crate::setup::Plane;
use embedded_graphics_core::pixelcolor::Rgb888;

/// Fraction bits of the normal planes of Phong shading (Q2.14 plus 16).
pub const NORMAL_PLANE_BITS: u32 = UNIT_BITS + 16;

/// Normal-plane gradients are kept within this (2^10 units per pixel).
const NORMAL_STEP_LIMIT: i64 = 1 << 40;

/// Normal-plane values at the lattice origin are kept within this.
const NORMAL_ORIGIN_LIMIT: i64 = 1 << 50;

/// Planes of the three normal components for Phong shading over the lattice of
/// the bounding box whose first pixel is `origin`: values with
/// [`NORMAL_PLANE_BITS`] fraction bits, gradients per pixel. 128-bit setup,
/// gradients saturated to ±2^40 (edge-on slivers).
pub fn normal_planes(
    xs: &[i64; 3],
    ys: &[i64; 3],
    origin: (i64, i64),
    normals: &[[i32; 3]; 3],
) -> Option<[Plane; 3]> {
    let (dx1, dy1) = ((xs[1] - xs[0]) as i128, (ys[1] - ys[0]) as i128);
    let (dx2, dy2) = ((xs[2] - xs[0]) as i128, (ys[2] - ys[0]) as i128);
    let area2 = dx1 * dy2 - dx2 * dy1;
    if area2 == 0 {
        return None;
    }
    let half = 1i128 << (SUBPIXEL_BITS - 1);
    let u0 = ((origin.0 as i128) << SUBPIXEL_BITS) + half - xs[0] as i128;
    let v0 = ((origin.1 as i128) << SUBPIXEL_BITS) + half - ys[0] as i128;
    let extra = NORMAL_PLANE_BITS - UNIT_BITS;
    let clamp = |v: i128, limit: i64| v.clamp(-(limit as i128), limit as i128) as i64;
    Some(core::array::from_fn(|k| {
        let n0 = normals[0][k] as i128;
        let dn1 = normals[1][k] as i128 - n0;
        let dn2 = normals[2][k] as i128 - n0;
        // Change per 1/16 pixel, times 2^extra, over area2.
        let gx = (dn1 * dy2 - dn2 * dy1) << extra;
        let gy = (dx1 * dn2 - dx2 * dn1) << extra;
        let origin_value = (n0 << extra) + (gx * u0 + gy * v0) / area2;
        Plane {
            origin: clamp(origin_value, NORMAL_ORIGIN_LIMIT),
            dx: clamp((gx << SUBPIXEL_BITS) / area2, NORMAL_STEP_LIMIT),
            dy: clamp((gy << SUBPIXEL_BITS) / area2, NORMAL_STEP_LIMIT),
        }
    }))
}

/// Per-pixel Phong shading of a triangle: normal planes and the light.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PhongPlanes {
    /// Normal components (in the space of `light`: the object's model
    /// space), [`NORMAL_PLANE_BITS`] fraction bits.
    pub normal: [Plane; 3],
    /// The light.
    pub light: LightSetup,
    /// The surface's color.
    pub base: Rgb888,
}

/// Phong shading: normal planes stepped by additions, then per covered pixel
/// renormalized (integer square root and divisions) and lit. The reference,
/// not a fast path.
#[derive(Clone, Copy, Debug)]
pub struct PhongWalk {
    normal: LinearWalk,
    light: LightSetup,
    base: Rgb888,
}

impl PhongWalk {
    /// Starts at row `j` of the bounding box.
    pub fn start(p: &PhongPlanes, j: i64) -> Self {
        Self {
            // Its values carry the colors' rounding bias; `color` reads
            // the normals themselves (`LinearWalk::plane_values`).
            normal: LinearWalk::start(&p.normal, j),
            light: p.light,
            base: p.base,
        }
    }
}

/// The lit color for an interpolated normal of any length (components below 2^52).
pub fn shade_interpolated(n: &[i64; 3], light: &LightSetup, base: Rgb888) -> ColorQ8 {
    let largest = n.iter().map(|c| c.unsigned_abs()).max().unwrap_or(0);
    let excess = (64 - largest.leading_zeros()).saturating_sub(30);
    let unit = normalize_unit(n.map(|c| c >> excess)).unwrap_or([0; 3]);
    light.shade(&unit, base)
}

impl ColorWalk for PhongWalk {
    type Row = [i64; 3];
    #[inline]
    fn row(&self) -> [i64; 3] {
        self.normal.row()
    }
    #[inline]
    fn next_row(&mut self) {
        self.normal.next_row()
    }
    fn color(&self, row: &[i64; 3]) -> Rgb888 {
        let normal = LinearWalk::plane_values(row);
        rgb888_rounded(shade_interpolated(&normal, &self.light, self.base))
    }
    #[inline]
    fn step(&self, row: &mut [i64; 3]) {
        self.normal.step(row)
    }
    #[inline]
    fn skip(&self, row: &mut [i64; 3], n: u16) {
        // The normals' walk skips in one multiplication, not `n` steps.
        self.normal.skip(row, n)
    }
}
