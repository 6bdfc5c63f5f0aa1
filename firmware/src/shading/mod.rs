//! Shading across a triangle (SPEC section 8): how each shading mode turns a
//! triangle's lit samples into the colors that the rasterizer steps over its
//! pixels, rows top to bottom and pixels left to right, by additions.
//!
//! One file per mode:
//! - this file: what the modes share: a triangle's [`ColorSource`] (what
//!   the renderer knows of its colors) and its [`ColorPlanes`] (what the
//!   rasterizer steps), the color setup between the two
//!   ([`TriangleSetup::color_planes`]), the [`ColorWalk`] that steps them,
//!   the one color of unlit and flat triangles ([`ConstantWalk`]), the
//!   integers of linear walks ([`PlaneValue`]), and the color source of the
//!   pieces of a clipped triangle ([`clipped_piece_source`]);
//! - [`linear`]: Gouraud, the lit vertex colors interpolated linearly;
//! - [`quadratic`]: the intensity surface through the lit vertices and edge
//!   midpoints, stepped by forward differences (the default of lit scenes);
//! - [`phong`]: the normal interpolated and lit at every pixel, the reference
//!   the others are measured against.
//!
//! Color setup runs only for a triangle that leaves a visible fragment, after
//! its edges and depth plane ([`crate::setup`]): a hidden triangle never pays
//! for its lighting or its quadratic fit.

pub mod linear;
pub mod phong;
pub mod quadratic;

use crate::fixed_point::SUBPIXEL_BITS;
use crate::lighting::{color_q8, normalize_unit, rgb888_rounded, ColorQ8, LightSetup};
use crate::setup::{Corners, Plane, TriangleSetup};
use embedded_graphics_core::pixelcolor::Rgb888;
use phong::{normal_planes, PhongPlanes};
use quadratic::{
    fit_quadratic_over, light_midpoints, samples_are_planar, walks_in_i32, QuadraticPolynomial,
    QuadraticSamples,
};

/// How fragment colors are produced across a triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorSource<'l> {
    /// One color for the whole triangle.
    Constant(Rgb888),
    /// The vertex colors (Q8, `0 ..= 255 * 256`, in the order of the
    /// vertices given to setup) interpolated linearly in screen space
    /// (Gouraud).
    Linear([ColorQ8; 3]),
    /// A quadratic through the vertex colors (the second field: the lit
    /// vertices rounded to 8 bits per channel, in the order of the vertices
    /// given to setup) and the lit edge midpoints, stepped by forward
    /// differences (SPEC section 8, [`quadratic`]).
    Quadratic(TriangleLighting<'l>, [Rgb888; 3]),
    /// The normal interpolated linearly in screen space and lit at every pixel
    /// (Phong; the reference).
    Phong(TriangleLighting<'l>),
}

/// Colors of a set-up triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorPlanes {
    /// A constant color.
    Constant(Rgb888),
    /// One plane per channel, values with 16 fraction bits.
    Linear([Plane; 3]),
    /// One lattice polynomial per channel ([`quadratic::QUADRATIC_FRACTION_BITS`]).
    Quadratic([QuadraticPolynomial; 3]),
    /// Quadratic polynomials that [`walks_in_i32`]: the same colors as
    /// [`ColorPlanes::Quadratic`] with these polynomials, stepped in half the
    /// registers.
    NarrowQuadratic([QuadraticPolynomial; 3]),
    /// Normal planes and the light, lit per pixel.
    Phong(PhongPlanes),
}

impl TriangleSetup {
    /// The color planes of this triangle for `source`: the color setup of its
    /// shading mode (the lighting of the midpoints and the quadratic fit
    /// happen here).
    pub fn color_planes<'l>(&self, source: ColorSource<'l>) -> ColorPlanes {
        let swapped = self.corners.swapped;
        // The corners and the box as the fit and Phong's planes take them
        // (not loaded for the other modes).
        let corners = || {
            let Corners { xs, ys, .. } = self.corners;
            let origin = (self.x0 as i64, self.y0 as i64);
            (xs.map(i64::from), ys.map(i64::from), origin)
        };
        // Colors and normals follow the vertices' order.
        let ordered_colors = |mut colors: [ColorQ8; 3]| {
            if swapped {
                colors.swap(1, 2);
            }
            colors
        };
        let ordered = |mut lighting: TriangleLighting<'l>| {
            if swapped {
                lighting.normals.swap(1, 2);
            }
            lighting
        };
        match source {
            ColorSource::Constant(c) => ColorPlanes::Constant(c),
            ColorSource::Linear(colors) => {
                ColorPlanes::Linear(self.linear_planes(&ordered_colors(colors)))
            }
            ColorSource::Quadratic(lighting, colors) => {
                // The fit takes samples within [0, 255] (Q8): the vertex
                // colors are 8-bit by their type (no clamp to pay), and the
                // midpoints' lighting and means stay within that range.
                let colors = ordered_colors(colors.map(color_q8));
                let samples = QuadraticSamples {
                    vertices: colors,
                    midpoints: light_midpoints(&ordered(lighting), &colors),
                };
                let (xs, ys, (x0, y0)) = corners();
                let size = (self.x1 as i64 - x0 + 1, self.y1 as i64 - y0 + 1);
                let fitted = if samples_are_planar(&samples) {
                    None
                } else {
                    let area2 = Some(self.corners.area2);
                    fit_quadratic_over(&xs, &ys, (x0, y0), size, &samples, area2)
                };
                match fitted {
                    Some(channels) if walks_in_i32(&channels, size) => {
                        ColorPlanes::NarrowQuadratic(channels)
                    }
                    Some(channels) => ColorPlanes::Quadratic(channels),
                    // Samples on a plane, or a sliver far thinner than its box.
                    None => ColorPlanes::Linear(self.linear_planes(&colors)),
                }
            }
            ColorSource::Phong(lighting) => {
                let lighting = ordered(lighting);
                let (xs, ys, origin) = corners();
                match normal_planes(&xs, &ys, origin, &lighting.normals) {
                    Some(normal) => ColorPlanes::Phong(PhongPlanes {
                        normal,
                        light: *lighting.light,
                        base: lighting.base,
                    }),
                    // Zero area once clamped to the guard band.
                    None => ColorPlanes::Constant(lighting.base),
                }
            }
        }
    }

    /// The linear (Gouraud) planes of this triangle through the vertex
    /// colors `colors` (Q8, in the vertices' order), from the center of
    /// the first pixel of its bounding box. Out of line, with the setup
    /// and the colors as its only arguments: the color setup builds no
    /// closure's environment for it.
    #[inline(never)]
    fn linear_planes(&self, colors: &[ColorQ8; 3]) -> [Plane; 3] {
        let half = 1 << (SUBPIXEL_BITS - 1);
        let center = (
            ((self.x0 as i32) << SUBPIXEL_BITS) + half,
            ((self.y0 as i32) << SUBPIXEL_BITS) + half,
        );
        let Corners { xs, ys, area2, .. } = &self.corners;
        linear::color_planes(colors, xs, ys, center, *area2)
    }
}

/// What quadratic and Phong shading need about a triangle besides its vertices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TriangleLighting<'l> {
    /// Unit normals (Q2.14) at the three vertices, in the object's model space
    /// (where `light` is), in the order of the vertices handed to setup.
    pub normals: [[i32; 3]; 3],
    /// The light, prepared for the frame in the object's model space
    /// (borrowed: a color request copies no more than it must).
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
                rgb888_rounded(lighting.light.shade(&lighting.normals[k], lighting.base))
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
    /// Whether a z-buffer's run of pixels ([`crate::band_buffer::BandBuffer::insert_full_run`])
    /// may be stepped by a loop the compiler unrolls. Off by default: on
    /// the short runs of dense meshes the unrolled loop's set-up per row
    /// costs more than it saves (3.5 % of `blob`'s z-buffer frame). On for
    /// the 64-bit quadratic walk, whose twelve words of state per pixel
    /// the unrolled loop handles better.
    const UNROLLED_RUNS: bool = false;
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

/// Half a unit of a value with `bits` fraction bits: the color walks add it
/// to their values once, when they start, so that the channel of every
/// pixel is rounded by a shift ([`PlaneValue::channel16`],
/// [`quadratic::QuadraticValue::channel`]) instead of an addition per pixel
/// and channel.
pub const fn rounding_bias(bits: u32) -> i64 {
    1 << (bits - 1)
}

/// The 8-bit channel of a value with `bits` fraction bits that carries the
/// [`rounding_bias`]: shifted (so rounded), then clamped to `[0, 255]` with
/// one comparison in the common case.
#[inline(always)]
fn channel(v: i64, bits: u32) -> u8 {
    let c = v >> bits;
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
    /// The 8-bit channel of a value with 16 fraction bits that carries the
    /// [`rounding_bias`] (so rounded), clamped to `[0, 255]` with one
    /// comparison in the common case.
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

/// The 8-bit channel of an `i32` value with `bits` fraction bits that
/// carries the [`rounding_bias`]: a shift and a clamp, one saturating
/// instruction on Cortex-M.
#[inline(always)]
fn channel_i32(v: i32, bits: u32) -> u8 {
    (v >> bits).clamp(0, 255) as u8
}
