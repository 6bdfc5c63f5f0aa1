//! Shading across a triangle (SPEC section 8): how each shading mode turns a
//! triangle's lit samples into the colors that the rasterizer steps over its
//! pixels, rows top to bottom and pixels left to right, by additions.
//!
//! One file per mode:
//! - this file: what the modes share: the [`ColorWalk`] that the rasterizer
//!   steps, the one color of unlit and flat triangles ([`ConstantWalk`]), the
//!   integers of linear walks ([`PlaneValue`]), and the color source of the
//!   pieces of a clipped triangle ([`clipped_piece_source`]);
//! - [`linear`]: Gouraud, the lit vertex colors interpolated linearly;
//! - [`quadratic`]: the intensity surface through the lit vertices and edge
//!   midpoints, stepped by forward differences (the default of lit scenes);
//! - [`phong`]: the normal interpolated and lit at every pixel, the reference
//!   the others are measured against.
//!
//! Each triangle's planes or polynomials are set up by
//! [`TriangleSetup::color_planes`](crate::setup::TriangleSetup::color_planes),
//! only for a triangle that leaves a visible fragment.

pub mod linear;
pub mod phong;
pub mod quadratic;

use crate::lighting::{normalize_unit, ColorQ8, LightSetup};
use crate::setup::ColorSource;
use embedded_graphics_core::pixelcolor::Rgb888;
use quadratic::round_to_8_bits;

/// What quadratic and Phong shading need about a triangle besides its vertices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TriangleLighting<'l> {
    /// Eye-space unit normals (Q2.14) at the three vertices, in the order of the
    /// vertices handed to setup.
    pub normals: [[i32; 3]; 3],
    /// The light, prepared for the frame (borrowed: a color request copies
    /// no more than it must).
    pub light: &'l LightSetup,
    /// The surface's color.
    pub base: Rgb888,
}

/// The color source for one piece of a clipped triangle whose corners carry
/// the interpolated normals `normals` (no longer unit length) and colors
/// `corner_colors` (which clipping interpolated linearly): linear sources
/// take the corner colors; quadratic ones take the normals renormalized and
/// the corners relit with them; Phong sources take the normals
/// renormalized. Other sources are returned unchanged.
pub fn clipped_piece_source<'l>(
    source: ColorSource<'l>,
    normals: &[[i32; 3]; 3],
    corner_colors: [ColorQ8; 3],
) -> ColorSource<'l> {
    let renormalized = |lighting: TriangleLighting<'l>| TriangleLighting {
        normals: normals.map(|n| normalize_unit(n.map(|c| c as i64)).unwrap_or([0; 3])),
        ..lighting
    };
    match source {
        ColorSource::Linear(_) => ColorSource::Linear(corner_colors),
        ColorSource::Quadratic(lighting, _) => {
            let lighting = renormalized(lighting);
            let relit = core::array::from_fn(|k| {
                round_to_8_bits(lighting.light.shade(&lighting.normals[k], lighting.base))
            });
            ColorSource::Quadratic(lighting, relit)
        }
        ColorSource::Phong(lighting) => ColorSource::Phong(renormalized(lighting)),
        other => other,
    }
}

/// Colors of a triangle visited row by row (top to bottom) and, within a row,
/// pixel by pixel to the right, by additions.
pub trait ColorWalk {
    /// The state while walking one row.
    type Row;
    /// The state at the first pixel of the current row.
    fn row(&self) -> Self::Row;
    /// Moves to the next row.
    fn next_row(&mut self);
    /// The color at the current pixel of `row`.
    fn color(&self, row: &Self::Row) -> Rgb888;
    /// Moves `row` one pixel to the right.
    fn step(&self, row: &mut Self::Row);
    /// Moves `row` `n` pixels to the right: the same state as `n` steps.
    #[inline]
    fn skip(&self, row: &mut Self::Row, n: u16) {
        for _ in 0..n {
            self.step(row);
        }
    }
}

/// An 8-bit channel from a value with `bits` fraction bits: rounded, then
/// clamped to `[0, 255]` with one comparison in the common case.
#[inline(always)]
fn channel(v: i64, bits: u32) -> u8 {
    let c = (v + (1 << (bits - 1))) >> bits;
    if (c as u64) <= 255 {
        c as u8
    } else if c < 0 {
        0
    } else {
        255
    }
}

/// One color everywhere.
#[derive(Clone, Copy, Debug)]
pub struct ConstantWalk(pub Rgb888);

impl ColorWalk for ConstantWalk {
    type Row = ();
    #[inline]
    fn row(&self) {}
    #[inline]
    fn next_row(&mut self) {}
    #[inline]
    fn color(&self, _: &()) -> Rgb888 {
        self.0
    }
    #[inline]
    fn step(&self, _: &mut ()) {}
}

/// The integer a [`LinearWalk`](linear::LinearWalk) steps in: `i64` for any plane, `i32` for
/// planes whose values over the bounding box fit ([`LinearWalk::fits`](linear::LinearWalk::fits)). Both
/// hold the same integers, so they give the same colors.
pub trait PlaneValue:
    Copy + core::ops::Add<Output = Self> + core::ops::AddAssign + core::ops::Mul<Output = Self>
{
    /// A plane value (the caller knows it fits).
    fn from_i64(v: i64) -> Self;
    /// `n` as a value.
    fn from_count(n: u16) -> Self;
    /// The 8-bit channel of a value with 16 fraction bits, rounded and clamped
    /// to `[0, 255]` with one comparison in the common case.
    fn channel16(self) -> u8;
}

impl PlaneValue for i64 {
    #[inline]
    fn from_i64(v: i64) -> Self {
        v
    }
    #[inline]
    fn from_count(n: u16) -> Self {
        n as i64
    }
    #[inline]
    fn channel16(self) -> u8 {
        channel(self, 16)
    }
}

impl PlaneValue for i32 {
    #[inline]
    fn from_i64(v: i64) -> Self {
        v as i32
    }
    #[inline]
    fn from_count(n: u16) -> Self {
        n as i32
    }
    #[inline(always)]
    fn channel16(self) -> u8 {
        channel_i32(self, 16)
    }
}

/// The 8-bit channel of an `i32` value with `bits` fraction bits, rounded
/// and clamped: a shift and a clamp, one saturating instruction on Cortex-M.
/// The value must be below `2^31 - 2^(bits - 1)`.
#[inline(always)]
fn channel_i32(v: i32, bits: u32) -> u8 {
    ((v + (1 << (bits - 1))) >> bits).clamp(0, 255) as u8
}
