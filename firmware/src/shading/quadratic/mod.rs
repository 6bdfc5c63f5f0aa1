//! Quadratic shading by forward differences (SPEC section 8): the fit of
//! the intensity surface (`fit.rs`), the lit edge midpoints that it passes
//! through besides the vertices (`midpoints.rs`), and the walk that steps it
//! over the pixels (`walk.rs`).
//!
//! # The surface
//!
//! Six samples are lit per triangle: the three vertices (lit once per vertex, as
//! for Gouraud) and the three edge midpoints, whose normals are the renormalized
//! sums of the two vertex normals (the normal that per-pixel Phong with normals
//! interpolated linearly in screen space has there). All six are rounded to
//! whole 8-bit steps, as vertex colors are stored. The intensity surface
//! through them is the quadratic Lagrange interpolant on the barycentric
//! coordinates `s = λ1`, `t = λ2` (`λ0 = 1 - s - t`):
//!
//! ```text
//! I = φ + δ s + ε t + α s² + β t² + γ s t
//! α = 2 (c0 + c1 - 2 m01)      δ = 4 m01 - 3 c0 - c1      φ = c0
//! β = 2 (c0 + c2 - 2 m20)      ε = 4 m20 - 3 c0 - c2
//! γ = 4 (c0 + m12 - m01 - m20)
//! ```
//!
//! (`ck` the vertex samples, `mij` the midpoint samples, all Q8). These weights
//! are exact integer combinations; no system of equations is solved.
//!
//! The barycentric coordinates are affine in the pixel lattice. Pixel `(i, j)` of
//! the bounding box (center at `x0 + i + 1/2`, `y0 + j + 1/2`) is mapped to the
//! normalized box `u = i / 2^p`, `v = j / 2^q`, where `2^p > columns` and
//! `2^q > rows` are the smallest such powers of two. With one division each,
//! `s = s0 + su u + sv v` (and `t` alike) is found with [`BARYCENTRIC_BITS`]
//! fraction bits. Products of these give the six monomials `s²`, `t²`, `st`,
//! `s`, `t`, `1` as polynomials in `(u, v)`; per channel the six weights combine
//! them into the coefficients, and dividing the `u`, `v` powers by `2^p`, `2^q`
//! (a rounding shift) turns them into the lattice polynomial
//!
//! ```text
//! Q(i, j) = a i² + b j² + c i j + d i + e j + f
//! ```
//!
//! with integer coefficients in units of `2^-28` of an 8-bit step
//! ([`QUADRATIC_FRACTION_BITS`]). On a bounding box of at most 128 x 128
//! pixels ([`NARROW_QUADRATIC_BOX`], every triangle of a small mesh) the
//! coefficients are rounded to multiples of `2^8` instead: the same
//! polynomial in units of `2^-20`, which a walk in `i32` can step where its
//! values stay in range ([`walks_in_i32`]); `i32` halves the registers of
//! the per-pixel loop.
//!
//! # Why stepping is exact
//!
//! `Q` has integer coefficients, so its forward differences are integers:
//! `Q(i+1, j) - Q(i, j) = a (2i + 1) + c j + d`, whose own difference is `2a`;
//! in `y`, `b (2j + 1) + e` with difference `2b`, and the `x` difference at the
//! row start grows by `c` per row. The walker adds exactly these integers, so
//! after any number of steps it holds `Q(i, j)` itself: no drift, equal to direct
//! evaluation at every pixel (a test checks every pixel of random triangles up
//! to screen-spanning ones). Per pixel and channel: two additions, and a
//! rounding shift and clamp for covered pixels. The `i32` walk adds the same
//! integers modulo 2^32, so at a pixel where the polynomial is within
//! `i32` it holds exactly that value, however its differences wrap.
//!
//! # Ranges
//!
//! - Vertices lie within the guard band (±2^16 in 1/16 pixel), twice the area
//!   is below 2^35, numerators of the barycentric planes below 2^55: `i64`.
//! - The fit is used only when `|s0| + |su| + |sv| < 2^30` and the same for `t`
//!   (barycentric coordinates below 2^10 in value over the normalized box, which
//!   contains every pixel walked plus one step beyond). Otherwise the triangle is
//!   a sliver narrower than about a thousandth of its bounding box and it gets
//!   linear (Gouraud) planes instead.
//! - Under that bound every monomial mantissa is below 2^41 and the weights sum
//!   below 2^20 (Q8: `|α|, |β|, |δ|, |ε| < 2^18`, `|γ| < 2^19`), so each
//!   coefficient is below 2^61.1; the surface over the box is below 2^40 in Q8,
//!   i.e. `|Q| < 2^60.1`, first differences below 2^61.1 and second differences
//!   below 2^62.1: every value the walker holds fits `i64`.
//! - When both sums are below 2^25 instead (barycentric coordinates below 32,
//!   nearly every triangle), every monomial mantissa is below 2^30 + 1 and the
//!   fit multiplies it as an `i32`: the same products, one 32 x 32-bit
//!   multiplication each.
//!
//! # Accuracy (8-bit steps, inside the triangle)
//!
//! - coefficient rounding at 2^-28: at most `0.5 * 2^-28 * (i² + j² + ij + i + j + 1)`,
//!   0.024 at the far corner of a 2048 x 2048 box; on boxes of at most 128
//!   pixels, rounding at 2^-20: `0.5 * 2^-20 * (...)`, again at most 0.024;
//! - barycentric planes rounded at 2^-21 each, times the surface's slope in `s`
//!   and `t` (below 5,100 steps even for samples alternating 0 and 255): at
//!   most 0.015;
//! - monomial mantissas rounded at 2^-21, times the weights: at most 0.013.
//!
//! So the fitted surface is within 0.06 of an 8-bit step of the exact quadratic
//! through the six samples, anywhere in the triangle, for any triangle of a
//! 2048-pixel screen; the output adds one rounding to 8 bits and the clamp to
//! `[0, 255]`.

mod fit;
mod midpoints;
#[cfg(test)]
mod tests;
mod walk;

pub use fit::*;
pub use midpoints::*;
pub use walk::*;

/// Fraction bits of quadratic color values: one 8-bit step is `1 << 28`.
pub const QUADRATIC_FRACTION_BITS: u32 = 8 + BARYCENTRIC_BITS;

/// Fraction bits of barycentric coordinates over the normalized box, and of the
/// monomial mantissas.
pub const BARYCENTRIC_BITS: u32 = 20;

/// Low bits that are zero in every coefficient of a polynomial fitted on a
/// small box ([`NARROW_QUADRATIC_BOX`]): such polynomials are exact in
/// [`NARROW_QUADRATIC_FRACTION_BITS`] and may walk in `i32`.
pub const NARROW_QUADRATIC_DROPPED_BITS: u32 = 8;

/// Fraction bits of the `i32` quadratic walk ([`QuadraticWalk<i32>`]).
pub const NARROW_QUADRATIC_FRACTION_BITS: u32 =
    QUADRATIC_FRACTION_BITS - NARROW_QUADRATIC_DROPPED_BITS;

/// Widest and tallest bounding box (pixels) whose fit is rounded to
/// [`NARROW_QUADRATIC_FRACTION_BITS`]: that rounding adds at most
/// `0.5 * 2^-20 * (3 * 128² + 2 * 128 + 1)`, 0.024 of an 8-bit step.
pub const NARROW_QUADRATIC_BOX: i64 = 128;

/// Whether a bounding box of `size` pixels (columns, rows) is small enough
/// for the fit to round to [`NARROW_QUADRATIC_FRACTION_BITS`].
#[inline]
fn is_narrow_box(size: (i64, i64)) -> bool {
    size.0 <= NARROW_QUADRATIC_BOX && size.1 <= NARROW_QUADRATIC_BOX
}
