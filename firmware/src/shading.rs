//! Shading across a triangle: quadratic shading by forward differences (SPEC
//! section 8), the per-pixel Phong reference, and the color walkers that the
//! rasterizer steps over a triangle's pixels (rows top to bottom, pixels left to
//! right).
//!
//! # Quadratic shading
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
//! ## Why stepping is exact
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
//! ## Ranges
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
//! ## Accuracy (8-bit steps, inside the triangle)
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

use crate::fixed_point::{Reciprocal, GUARD_BAND_PX, SUBPIXEL_BITS, UNIT_BITS};
use crate::lighting::{clamp_q8, normalize_unit, ColorQ8, LightSetup, COLOR_Q8_MAX};
use crate::setup::{ColorSource, Plane};
use embedded_graphics_core::pixelcolor::Rgb888;

/// Fraction bits of quadratic color values: one 8-bit step is `1 << 28`.
pub const QUADRATIC_FRACTION_BITS: u32 = 8 + BARYCENTRIC_BITS;

/// Fraction bits of barycentric coordinates over the normalized box, and of the
/// monomial mantissas.
pub const BARYCENTRIC_BITS: u32 = 20;

/// Bound on `|s0| + |su| + |sv|` (and `t`) for the quadratic fit (2^10 in value).
const BARYCENTRIC_LIMIT: i64 = 1 << 30;

/// Bound on `|s0| + |su| + |sv|` (and `t`) under which the fit's monomials
/// fit `i32` (2^5 in value).
const SMALL_BARYCENTRIC_LIMIT: i64 = 1 << 25;

/// Fraction bits of the normal planes of Phong shading (Q2.14 plus 16).
pub const NORMAL_PLANE_BITS: u32 = UNIT_BITS + 16;

/// Normal-plane gradients are kept within this (2^10 units per pixel).
const NORMAL_STEP_LIMIT: i64 = 1 << 40;

/// Normal-plane values at the lattice origin are kept within this.
const NORMAL_ORIGIN_LIMIT: i64 = 1 << 50;

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

/// The six samples of a quadratic fit, Q8 colors.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QuadraticSamples {
    /// At vertices 0, 1, 2.
    pub vertices: [ColorQ8; 3],
    /// At the midpoints of edges 0-1, 1-2 and 2-0.
    pub midpoints: [ColorQ8; 3],
}

impl QuadraticSamples {
    /// The samples clamped to `[0, 255]` (Q8).
    pub fn clamped(&self) -> Self {
        let clamp = |c: &[ColorQ8; 3]| c.map(clamp_q8);
        Self {
            vertices: clamp(&self.vertices),
            midpoints: clamp(&self.midpoints),
        }
    }

    /// Whether every sample is within `[0, 255]` (Q8), as [`ColorQ8`]
    /// promises.
    pub fn in_range(&self) -> bool {
        self.vertices
            .iter()
            .chain(&self.midpoints)
            .flatten()
            .all(|&c| (0..=COLOR_Q8_MAX).contains(&c))
    }
}

/// One channel over the pixel lattice of a bounding box:
/// `Q(i, j) = a i² + b j² + c i j + d i + e j + f`, in units of
/// `2^-QUADRATIC_FRACTION_BITS` of an 8-bit step, `(i, j)` the pixel offset from
/// the box's first pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QuadraticPolynomial {
    /// Coefficient of `i²`.
    pub a: i64,
    /// Coefficient of `j²`.
    pub b: i64,
    /// Coefficient of `i j`.
    pub c: i64,
    /// Coefficient of `i`.
    pub d: i64,
    /// Coefficient of `j`.
    pub e: i64,
    /// Value at the first pixel.
    pub f: i64,
}

impl QuadraticPolynomial {
    /// The zero polynomial.
    pub const ZERO: Self = Self {
        a: 0,
        b: 0,
        c: 0,
        d: 0,
        e: 0,
        f: 0,
    };

    /// The coefficients `[a, b, c, d, e, f]`.
    #[inline(always)]
    pub fn coefficients(&self) -> [i64; 6] {
        [self.a, self.b, self.c, self.d, self.e, self.f]
    }

    /// The polynomial with coefficients `[a, b, c, d, e, f]`.
    #[inline(always)]
    pub fn from_coefficients([a, b, c, d, e, f]: [i64; 6]) -> Self {
        Self { a, b, c, d, e, f }
    }

    /// The polynomial evaluated directly at lattice point `(i, j)` (128-bit
    /// products; the result fits `i64` within the walked box).
    pub fn eval(&self, i: i64, j: i64) -> i64 {
        let (i, j) = (i as i128, j as i128);
        let v = self.a as i128 * i * i
            + self.b as i128 * j * j
            + self.c as i128 * i * j
            + self.d as i128 * i
            + self.e as i128 * j
            + self.f as i128;
        v as i64
    }
}

/// `x y + z w` from Q20 factors, rounded back to Q20. Every factor is below
/// 2^31 in magnitude (the fit checks `|s0| + |su| + |sv| < 2^30` first), so each
/// product is one 32 x 32-bit multiplication.
#[inline]
fn mul2_q20(x: i64, y: i64, z: i64, w: i64) -> i64 {
    let wide = |a: i64| a as i32 as i64;
    (wide(x) * wide(y) + wide(z) * wide(w) + (1 << (BARYCENTRIC_BITS - 1))) >> BARYCENTRIC_BITS
}

/// Bits needed for `n >= 1`: the smallest `p` with `2^p > n`.
#[inline]
fn bits_above(n: i64) -> u32 {
    64 - (n as u64).leading_zeros()
}

/// Fits the quadratic through `samples` on a triangle with vertices `xs`, `ys`
/// (1/16 pixel, within the guard band) over the lattice of the bounding box
/// whose first pixel is `origin` (pixels) and which is `size` pixels
/// (columns, rows) large, one polynomial per channel.
///
/// `None` for a zero-area triangle, an empty box, or a sliver whose barycentric
/// coordinates over the box exceed the range above (use linear planes then);
/// also for input outside the ranges above (vertices beyond the guard band, a
/// box beyond 4096 pixels). Samples are clamped to `[0, 255]` (Q8) first.
pub fn fit_quadratic(
    xs: &[i64; 3],
    ys: &[i64; 3],
    origin: (i64, i64),
    size: (i64, i64),
    samples: &QuadraticSamples,
) -> Option<[QuadraticPolynomial; 3]> {
    fit_quadratic_over(xs, ys, origin, size, &samples.clamped(), None)
}

/// [`fit_quadratic`], with the reciprocal of twice the triangle's area when
/// the caller has it already: `Reciprocal::new` of twice the area of the
/// corners before they were clamped to the guard band (setup's), used
/// where no corner lies on the guard band's edge (where none was clamped).
/// The samples must be within `[0, 255]` (Q8) already
/// ([`QuadraticSamples::in_range`]): color setup clamps the vertex colors
/// it is given, and the midpoints' lighting and means stay within them.
#[inline(always)]
pub(crate) fn fit_quadratic_over(
    xs: &[i64; 3],
    ys: &[i64; 3],
    origin: (i64, i64),
    size: (i64, i64),
    samples: &QuadraticSamples,
    area2: Option<Reciprocal>,
) -> Option<[QuadraticPolynomial; 3]> {
    debug_assert!(samples.in_range(), "samples out of range: {samples:?}");
    let basis = FitBasis::new(xs, ys, origin, size, area2)?;
    Some(if basis.monomials_fit_i32() {
        fit_channels::<i32>(&basis, samples)
    } else {
        fit_channels::<i64>(&basis, samples)
    })
}

/// What [`fit_quadratic`] shares between channels besides the monomials: the
/// barycentric planes over the normalized box (`[value at the origin, change
/// over u, change over v]`, Q20), the shift that takes each coefficient from
/// the normalized box to pixel steps, and the low bits dropped on small boxes.
struct FitBasis {
    s: [i64; 3],
    t: [i64; 3],
    /// The larger of `|s0| + |su| + |sv|` and the same sum for `t`.
    extent: i64,
    shifts: [u32; 6],
    drop: u32,
}

impl FitBasis {
    /// The barycentric planes of the triangle `xs`, `ys` over the box at
    /// `origin` of `size` pixels, as [`fit_quadratic`] takes them; `None`
    /// where it returns `None`.
    #[inline(always)]
    fn new(
        xs: &[i64; 3],
        ys: &[i64; 3],
        origin: (i64, i64),
        size: (i64, i64),
        reciprocal: Option<Reciprocal>,
    ) -> Option<Self> {
        let guard = (GUARD_BAND_PX as i64) << SUBPIXEL_BITS;
        let box_limit = 4096;
        let farthest = xs.iter().chain(ys).fold(0, |m, c| m.max(c.abs()));
        if farthest > guard
            || !(0..=box_limit).contains(&origin.0)
            || !(0..=box_limit).contains(&origin.1)
            || size.0 > box_limit
            || size.1 > box_limit
        {
            return None;
        }
        let (dx1, dy1) = (xs[1] - xs[0], ys[1] - ys[0]);
        let (dx2, dy2) = (xs[2] - xs[0], ys[2] - ys[0]);
        let area2 = dx1 * dy2 - dx2 * dy1;
        if area2 == 0 || size.0 < 1 || size.1 < 1 {
            return None;
        }
        let sign = area2.signum();
        let area2 = area2.abs();
        let half = 1i64 << (SUBPIXEL_BITS - 1);
        let u0 = (origin.0 << SUBPIXEL_BITS) + half - xs[0];
        let v0 = (origin.1 << SUBPIXEL_BITS) + half - ys[0];
        let p = bits_above(size.0);
        let q = bits_above(size.1);
        // s * area2 = (x - x0) dy2 - (y - y0) dx2 with x = 16 (x0 + u 2^p) + 8 ...;
        // [value at the origin, change over u in [0, 1], change over v in [0, 1]].
        // One reciprocal of the area for the six plane coefficients.
        // The caller's reciprocal is of the area of the corners before
        // setup clamped them to the guard band: this area whenever no
        // corner lies on the guard band's edge.
        let reciprocal = match reciprocal {
            Some(r) if farthest < guard => r,
            _ => Reciprocal::new(area2 as u64),
        };
        let scale = SUBPIXEL_BITS + BARYCENTRIC_BITS;
        let at = |n: i64, extra: u32| reciprocal.mul_div_round(sign * n, extra);
        let (s0, su, sv) = (
            at(u0 * dy2 - v0 * dx2, BARYCENTRIC_BITS),
            at(dy2, scale + p),
            at(-dx2, scale + q),
        );
        let (t0, tu, tv) = (
            at(dx1 * v0 - dy1 * u0, BARYCENTRIC_BITS),
            at(-dy1, scale + p),
            at(dx1, scale + q),
        );
        let extent = (s0.abs() + su.abs() + sv.abs()).max(t0.abs() + tu.abs() + tv.abs());
        if extent >= BARYCENTRIC_LIMIT {
            return None;
        }
        Some(FitBasis {
            s: [s0, su, sv],
            t: [t0, tu, tv],
            extent,
            shifts: [2 * p, 2 * q, p + q, p, q, 0],
            // Boxes up to NARROW_QUADRATIC_BOX get coefficients in multiples of
            // 2^8, which an `i32` walk can hold (`walks_in_i32`).
            drop: if is_narrow_box(size) {
                NARROW_QUADRATIC_DROPPED_BITS
            } else {
                0
            },
        })
    }

    /// Whether every monomial mantissa fits `i32`: with both planes below
    /// 2^25 over the box (barycentric coordinates below 32, nearly every
    /// triangle) each is below 2^30 + 1, since `(|x| + |y|)^2 < 2^50` bounds
    /// every product of two plane values and the mantissas drop 20 bits. The
    /// weights then multiply them as 32 x 32-bit products, the same values
    /// as the 32 x 64-bit ones.
    #[inline(always)]
    fn monomials_fit_i32(&self) -> bool {
        self.extent < SMALL_BARYCENTRIC_LIMIT
    }
}

/// A monomial mantissa of the fit: `i64`, or `i32` when the planes are small
/// enough for every mantissa to fit (then each product is one 32 x 32-bit
/// multiplication).
trait Monomial: Copy {
    /// The mantissa `v` (within this type's range).
    fn from_mantissa(v: i64) -> Self;
    /// `w m` for a weight `w` below 2^20.
    fn weighted(self, w: i64) -> i64;
}

impl Monomial for i64 {
    #[inline(always)]
    fn from_mantissa(v: i64) -> Self {
        v
    }
    #[inline(always)]
    fn weighted(self, w: i64) -> i64 {
        w as i32 as i64 * self
    }
}

impl Monomial for i32 {
    #[inline(always)]
    fn from_mantissa(v: i64) -> Self {
        v as i32
    }
    #[inline(always)]
    fn weighted(self, w: i64) -> i64 {
        w as i32 as i64 * self as i64
    }
}

/// The three channels' polynomials over `basis`: the monomials of `s²`, `t²`
/// and `s t` (coefficients of `[u², v², uv, u, v, 1]`), then each channel's
/// six coefficients. Straight-line code with no branch between the channels,
/// so the compiler keeps each `i32` monomial's products 32 x 32-bit; out of
/// line, one copy per monomial type, so neither copy's registers burden the
/// caller's (0.2 M fewer instructions a teapot frame than inline).
#[inline(never)]
fn fit_channels<T: Monomial>(
    basis: &FitBasis,
    samples: &QuadraticSamples,
) -> [QuadraticPolynomial; 3] {
    let [s0, su, sv] = basis.s;
    let [t0, tu, tv] = basis.t;
    // Monomials over the normalized box, coefficients of [u², v², uv, u, v, 1], Q20.
    let m = |x: i64, y: i64| T::from_mantissa(mul2_q20(x, y, 0, 0));
    let m2 = |x: i64, y: i64, z: i64, w: i64| T::from_mantissa(mul2_q20(x, y, z, w));
    let ss = [
        m(su, su),
        m(sv, sv),
        m(2 * su, sv),
        m(2 * s0, su),
        m(2 * s0, sv),
        m(s0, s0),
    ];
    let tt = [
        m(tu, tu),
        m(tv, tv),
        m(2 * tu, tv),
        m(2 * t0, tu),
        m(2 * t0, tv),
        m(t0, t0),
    ];
    let st = [
        m(su, tu),
        m(sv, tv),
        m2(su, tv, sv, tu),
        m2(s0, tu, t0, su),
        m2(s0, tv, t0, sv),
        m(s0, t0),
    ];
    let monomials = &[ss, tt, st];
    // Q8 weights times Q20 mantissas: Q28 over the normalized box; the powers
    // of u = i / 2^p and v = j / 2^q become shifts by `n` (below 32). On a
    // small box the coefficients are rounded to multiples of 2^8 (see
    // `drop`): the value over 2^(n + drop) rounded to nearest (halves up),
    // times 2^drop, with one shift (the quotient by 2^n, floored, then its
    // low `drop` bits cleared).
    // `n + drop` is at most 26 (boxes up to 4096 pixels, 2^8 dropped only
    // up to 128): the halves fit 32 bits.
    let half = |k: usize| ((1u32 << (basis.shifts[k] + basis.drop)) >> 1) as i64;
    let halves = [half(0), half(1), half(2), half(3), half(4), half(5)];
    let kept = !((1i64 << basis.drop) - 1);
    let round = |v: i64, k: usize| ((v + halves[k]) >> (basis.shifts[k] & 31)) & kept;
    let channel =
        |ch: usize| fit_channel(&ChannelWeights::of(samples, ch), basis, monomials, &round);
    [channel(0), channel(1), channel(2)]
}

/// One channel's polynomial from its weights and the shared monomials,
/// coefficients rounded by `round` (the value and the coefficient's index).
#[inline(always)]
fn fit_channel<T: Monomial>(
    w: &ChannelWeights,
    basis: &FitBasis,
    [ss, tt, st]: &[[T; 6]; 3],
    round: &impl Fn(i64, usize) -> i64,
) -> QuadraticPolynomial {
    let [s0, su, sv] = basis.s;
    let [t0, tu, tv] = basis.t;
    // The weights fit 20 bits: 32 x 64-bit (or 32 x 32-bit) products with
    // the monomials, 32 x 32-bit ones with the barycentric planes (below
    // 2^30, checked in `FitBasis::new`).
    #[inline(always)]
    fn linear(w: i64, s: i64) -> i64 {
        w as i32 as i64 * s as i32 as i64
    }
    #[inline(always)]
    fn quadratic<T: Monomial>(w: &ChannelWeights, s: T, t: T, st: T) -> i64 {
        s.weighted(w.alpha) + t.weighted(w.beta) + st.weighted(w.gamma)
    }
    QuadraticPolynomial {
        a: round(quadratic(w, ss[0], tt[0], st[0]), 0),
        b: round(quadratic(w, ss[1], tt[1], st[1]), 1),
        c: round(quadratic(w, ss[2], tt[2], st[2]), 2),
        d: round(
            quadratic(w, ss[3], tt[3], st[3]) + linear(w.delta, su) + linear(w.epsilon, tu),
            3,
        ),
        e: round(
            quadratic(w, ss[4], tt[4], st[4]) + linear(w.delta, sv) + linear(w.epsilon, tv),
            4,
        ),
        f: round(
            quadratic(w, ss[5], tt[5], st[5])
                + linear(w.delta, s0)
                + linear(w.epsilon, t0)
                + (w.c0 << BARYCENTRIC_BITS),
            5,
        ),
    }
}

/// One channel's weights of the fit, from its six samples (Q8, within
/// `[0, 255]`): `|α|, |β|, |δ|, |ε| < 2^18`, `|γ| < 2^19`.
struct ChannelWeights {
    alpha: i64,
    beta: i64,
    gamma: i64,
    delta: i64,
    epsilon: i64,
    c0: i64,
}

impl ChannelWeights {
    #[inline(always)]
    fn of(samples: &QuadraticSamples, ch: usize) -> Self {
        let sample = |v: &ColorQ8| v[ch] as i64;
        let [v0, v1, v2] = &samples.vertices;
        let [v01, v12, v20] = &samples.midpoints;
        let (c0, c1, c2) = (sample(v0), sample(v1), sample(v2));
        let (m01, m12, m20) = (sample(v01), sample(v12), sample(v20));
        Self {
            alpha: 2 * (c0 + c1 - 2 * m01),
            beta: 2 * (c0 + c2 - 2 * m20),
            gamma: 4 * (c0 + m12 - m01 - m20),
            delta: 4 * m01 - 3 * c0 - c1,
            epsilon: 4 * m20 - 3 * c0 - c2,
            c0,
        }
    }
}

/// `2^30 / sqrt(1 + (k + 0.5) / 16)`, `k = 0..48`: where [`rsqrt_q28`] starts.
const RSQRT_START: [u32; 48] = [
    1057347856, 1026693558, 998559613, 972618566, 948599586, 926276469, 905458609, 885984104,
    867714429, 850530263, 834328203, 819018128, 804521086, 790767575, 777696137, 765252196,
    753387102, 742057327, 731223792, 720851298, 710908045, 701365222, 692196655, 683378504,
    674889000, 666708225, 658817909, 651201261, 643842818, 636728315, 629844563, 623179354,
    616721362, 610460069, 604385689, 598489102, 592761802, 587195840, 581783781, 576518662,
    571393950, 566403514, 561541591, 556802759, 552181909, 547674226, 543275165, 538980433,
];

/// `1 / sqrt(x)` for `x` in `[1, 4)` (Q28), Q30: a table at the centers of 48
/// intervals of width 1/16 (within 1.6 %), then two Newton steps (relative
/// error below 2^-21).
fn rsqrt_q28(x: u64) -> u64 {
    let k = ((x >> 24) - 16).min(47) as usize;
    // Every factor below is a word (x below 2^30, y within 3.2 % of its
    // value in (2^29, 2^30], so x y² / 2^58 within 7 % of 2^30): each
    // product is one 32 x 32 -> 64-bit multiplication.
    let x = x as u32;
    let wide = |a: u32, b: u32| a as u64 * b as u64;
    let mut y = RSQRT_START[k];
    for _ in 0..2 {
        // y (3 - x y²) / 2, all Q30 (x Q28).
        let h = (wide((wide(y, y) >> 30) as u32, x) >> 28) as u32;
        y = (wide(y, (3 << 30) - h) >> 31) as u32;
    }
    y as u64
}

/// The unit vector (Q2.14) along `a + b` for unit vectors `a`, `b` (Q2.14): the
/// normal halfway between two vertex normals. A fast reciprocal square root for
/// angles below about 150 degrees, [`normalize_unit`] beyond; `None` for
/// opposite vectors.
pub fn midpoint_normal(a: &[i32; 3], b: &[i32; 3]) -> Option<[i32; 3]> {
    // Wrapping: for inputs far from unit length the result is meaningless but
    // every step below stays in range (components below 2^31, squares in u64).
    let sum = [0, 1, 2].map(|k| a[k].wrapping_add(b[k]) as i64);
    let len2 = sum.iter().map(|c| (c * c) as u64).sum::<u64>();
    // |a + b|² in Q28 is at most 4 (plus rounding); bring it into [1, 4).
    if len2 < 1 << 26 {
        // Short: scale up first so the integer square root keeps 16 more bits.
        return normalize_unit(sum.map(|c| c << 16));
    }
    if len2 >= 1 << 31 {
        return normalize_unit(sum);
    }
    let (x, extra) = if len2 >= 1 << 30 {
        (len2 >> 2, -1)
    } else if len2 >= 1 << 28 {
        (len2, 0)
    } else {
        (len2 << 2, 1)
    };
    // Below 2^31 (see `rsqrt_q28`): with the sum's components (words) one
    // 32 x 32-bit product each.
    let y = rsqrt_q28(x) as i32 as i64;
    let shift = (30 - extra) as u32;
    Some(sum.map(|c| ((c as i32 as i64 * y + (1 << (shift - 1))) >> shift) as i32))
}

/// Largest deviation of a midpoint sample from the mean of its edge's vertex
/// samples (Q8) for which a triangle is drawn with linear planes: half an
/// 8-bit step, the samples' own rounding.
pub const PLANAR_TOLERANCE: i32 = 128;

/// Whether the six samples lie on the plane through the vertex samples within
/// [`PLANAR_TOLERANCE`] in every channel.
///
/// The quadratic through the samples is the linear interpolant of the vertices
/// plus `4 Σ λi λj (mij - (ci + cj) / 2)`, and `Σ 4 λi λj <= 4/3` inside the
/// triangle, so such a triangle's quadratic differs from its linear planes by
/// at most 2/3 of an 8-bit step, and by nothing when the deviations are zero.
/// Those triangles skip the fit and step linear planes (Gouraud's cost).
pub fn samples_are_planar(samples: &QuadraticSamples) -> bool {
    let v = &samples.vertices;
    (0..3).all(|k| {
        let (i, j) = (k, (k + 1) % 3);
        (0..3).all(|ch| {
            // Wrapping: out-of-range samples give an arbitrary answer, never a panic.
            let deviation = samples.midpoints[k][ch]
                .wrapping_mul(2)
                .wrapping_sub(v[i][ch])
                .wrapping_sub(v[j][ch]);
            deviation.wrapping_abs() <= 2 * PLANAR_TOLERANCE
        })
    })
}

/// A lit color rounded to whole 8-bit steps (still Q8), as vertex colors are
/// kept: samples of one precision, so a triangle whose six normals are equal
/// gets six equal samples and shades constant.
#[inline]
pub fn round_to_8_bits(c: ColorQ8) -> ColorQ8 {
    c.map(|v| ((v + 128) >> 8).clamp(0, 255) << 8)
}

/// Lights the three edge midpoints of a triangle whose vertex normals are
/// `lighting.normals` (rounded to 8 bits like the vertex colors); a midpoint
/// between opposite normals takes the mean of its two vertex colors
/// `vertex_colors`.
pub fn light_midpoints(lighting: &TriangleLighting, vertex_colors: &[ColorQ8; 3]) -> [ColorQ8; 3] {
    core::array::from_fn(|k| {
        let (i, j) = (k, (k + 1) % 3);
        match midpoint_normal(&lighting.normals[i], &lighting.normals[j]) {
            Some(n) => round_to_8_bits(lighting.light.shade(&n, lighting.base)),
            None => core::array::from_fn(|ch| {
                ((vertex_colors[i][ch] as i64 + vertex_colors[j][ch] as i64) / 2) as i32
            }),
        }
    })
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
    /// Eye-space normal components, [`NORMAL_PLANE_BITS`] fraction bits.
    pub normal: [Plane; 3],
    /// The light.
    pub light: LightSetup,
    /// The surface's color.
    pub base: Rgb888,
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

/// The integer a [`LinearWalk`] steps in: `i64` for any plane, `i32` for
/// planes whose values over the bounding box fit ([`LinearWalk::fits`]). Both
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

/// A quadratic channel in [`QUADRATIC_FRACTION_BITS`] to 8 bits, rounded and clamped.
#[inline]
fn channel_quadratic(v: i64) -> u8 {
    const _: () = assert!(QUADRATIC_FRACTION_BITS == 28);
    // The same as `channel(v, 28)`, decided on the high word: the rounded
    // value is in `[0, 255]` exactly when that word is below 16.
    let rounded = v + (1 << 27);
    let high = (rounded >> 32) as i32;
    if (high as u32) < 16 {
        (rounded >> 28) as u8
    } else if high < 0 {
        0
    } else {
        255
    }
}

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

/// The number types a [`QuadraticWalk`] steps: `i64` any fitted
/// polynomial, `i32` one that [`walks_in_i32`] (half the registers).
pub trait QuadraticValue: PlaneValue {
    /// Low bits of the fitted coefficients ([`QUADRATIC_FRACTION_BITS`])
    /// that this type leaves out (all zero where it is used).
    const DROPPED_BITS: u32;
    /// The 8-bit channel of a value, rounded and clamped.
    fn channel(self) -> u8;
    /// `self + other`, wrapping.
    fn plus(self, other: Self) -> Self;
    /// `self * other`, wrapping.
    fn times(self, other: Self) -> Self;
}

/// [`QuadraticValue`]'s wrapping addition and multiplication, the same
/// for every integer type.
macro_rules! wrapping_arithmetic {
    () => {
        #[inline]
        fn plus(self, other: Self) -> Self {
            self.wrapping_add(other)
        }
        #[inline]
        fn times(self, other: Self) -> Self {
            self.wrapping_mul(other)
        }
    };
}

impl QuadraticValue for i64 {
    const DROPPED_BITS: u32 = 0;
    #[inline]
    fn channel(self) -> u8 {
        channel_quadratic(self)
    }
    wrapping_arithmetic!();
}

impl QuadraticValue for i32 {
    const DROPPED_BITS: u32 = NARROW_QUADRATIC_DROPPED_BITS;
    #[inline(always)]
    fn channel(self) -> u8 {
        channel_i32(self, NARROW_QUADRATIC_FRACTION_BITS)
    }
    wrapping_arithmetic!();
}

/// Quadratic colors by forward differences: per pixel and channel the value
/// grows by its `x` difference and the difference by `2a`; per row the row
/// start grows by its `y` difference, that by `2b`, and the row's first `x`
/// difference by `c`. In `i64` (any fitted polynomial) or, where
/// [`walks_in_i32`], in `i32`.
#[derive(Clone, Copy, Debug)]
pub struct QuadraticWalk<V: QuadraticValue = i64> {
    value: [V; 3],
    first_x: [V; 3],
    first_y: [V; 3],
    second_x: [V; 3],
    second_y: [V; 3],
    cross: [V; 3],
}

/// The state of a [`QuadraticWalk`] within a row: value and `x` difference per channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct QuadraticRow<V = i64> {
    /// `Q(i, j)` per channel.
    pub value: [V; 3],
    /// `Q(i + 1, j) - Q(i, j)` per channel.
    pub first_x: [V; 3],
}

/// Whether polynomials `p` over a bounding box of `size` pixels (columns,
/// rows) can be walked in `i32`: the box is at most
/// [`NARROW_QUADRATIC_BOX`] on each side, every coefficient is a multiple
/// of `2^8` (as the fit leaves them on such a box), and every value on the
/// box, in [`NARROW_QUADRATIC_FRACTION_BITS`], is below `2^31 - 2^20` in
/// magnitude (bounded by the sum over the coefficients of `|k| m`, `m` the
/// largest value of `k`'s monomial on the box). The walk's arithmetic wraps:
/// it is exact modulo 2^32, so each value it reaches at a pixel is the
/// polynomial's, whatever its differences and products do on the way.
// Always inlined into color setup: the compiler's choice, out of line, cost
// the teapot's frames 0.15 to 0.25 M instructions more (with
// `Reciprocal::mul_div`, which it then moved out too).
#[inline(always)]
pub fn walks_in_i32(p: &[QuadraticPolynomial; 3], size: (i64, i64)) -> bool {
    if !is_narrow_box(size) || size.0 < 1 || size.1 < 1 {
        return false;
    }
    // In 32-bit words: a coefficient's term alone is at least |k| (every
    // monomial's largest value is at least 1), so the bound fails for any
    // |k| above 2^39 and every one that passes has its high word within
    // [-2^7, 2^7) and `k >> 8` within `i32`. The bound itself is then a
    // sum of 32 x 32-bit products over 2^8 (the dropped bits are zero).
    const _: () = assert!(NARROW_QUADRATIC_DROPPED_BITS == 8 && NARROW_QUADRATIC_BOX <= 1 << 15);
    const DROPPED: u32 = (1 << NARROW_QUADRATIC_DROPPED_BITS) - 1;
    let (w, h) = (size.0 as u32, size.1 as u32);
    let monomials = [w * w, h * h, w * h, w, h, 1];
    p.iter().all(|p| {
        let ks = p.coefficients();
        let low_bits = ks.iter().fold(0, |or, &k| or | k as u32);
        // `hi ^ (hi >> 31)` is `hi` or `-hi - 1`: below 2^7 exactly when
        // the high word is within [-2^7, 2^7).
        let high = ks.iter().fold(0, |or, &k| {
            let hi = (k >> 32) as i32;
            or | (hi ^ (hi >> 31))
        });
        if low_bits & DROPPED != 0 || high >= 1 << 7 {
            return false;
        }
        let bound: u64 = ks
            .iter()
            .zip(monomials)
            .map(|(&k, m)| {
                ((k >> NARROW_QUADRATIC_DROPPED_BITS) as i32).unsigned_abs() as u64 * m as u64
            })
            .sum();
        bound < (1 << 31) - (1 << 20)
    })
}

impl<V: QuadraticValue> QuadraticWalk<V> {
    /// Starts at row `j` of the bounding box by direct evaluation (once per
    /// band; additions from there on); for `V = i32` the polynomials must
    /// pass [`walks_in_i32`].
    pub fn start(p: &[QuadraticPolynomial; 3], j: i64) -> Self {
        let mut walk = Self {
            value: [V::from_i64(0); 3],
            first_x: [V::from_i64(0); 3],
            first_y: [V::from_i64(0); 3],
            second_x: [V::from_i64(0); 3],
            second_y: [V::from_i64(0); 3],
            cross: [V::from_i64(0); 3],
        };
        // Each result fits `i64` (see the module's ranges), so wrapping
        // arithmetic gives it exactly even where a partial product does not;
        // in `i32` the walk is exact modulo 2^32, and the dropped bits of
        // every coefficient are zero, so the coefficients are narrowed first
        // and the start computed in the walk's own type (the same integers
        // as narrowing the `i64` results).
        let j = V::from_i64(j);
        let two_j_plus_one = j.plus(j).plus(V::from_i64(1));
        for (c, p) in p.iter().enumerate() {
            let [a, b, cross, d, e, f] =
                p.coefficients().map(|k| V::from_i64(k >> V::DROPPED_BITS));
            walk.value[c] = b.times(j).plus(e).times(j).plus(f);
            walk.first_x[c] = a.plus(cross.times(j)).plus(d);
            walk.first_y[c] = b.times(two_j_plus_one).plus(e);
            walk.second_x[c] = a.plus(a);
            walk.second_y[c] = b.plus(b);
            walk.cross[c] = cross;
        }
        walk
    }

    /// The 8-bit color of a row state.
    #[inline]
    pub fn rgb(row: &QuadraticRow<V>) -> Rgb888 {
        Rgb888::new(
            row.value[0].channel(),
            row.value[1].channel(),
            row.value[2].channel(),
        )
    }
}

impl<V: QuadraticValue> ColorWalk for QuadraticWalk<V> {
    type Row = QuadraticRow<V>;
    #[inline]
    fn row(&self) -> QuadraticRow<V> {
        QuadraticRow {
            value: self.value,
            first_x: self.first_x,
        }
    }
    #[inline]
    fn next_row(&mut self) {
        for c in 0..3 {
            self.value[c] = self.value[c].plus(self.first_y[c]);
            self.first_y[c] = self.first_y[c].plus(self.second_y[c]);
            self.first_x[c] = self.first_x[c].plus(self.cross[c]);
        }
    }
    #[inline]
    fn color(&self, row: &QuadraticRow<V>) -> Rgb888 {
        Self::rgb(row)
    }
    #[inline]
    fn step(&self, row: &mut QuadraticRow<V>) {
        for c in 0..3 {
            row.value[c] = row.value[c].plus(row.first_x[c]);
            row.first_x[c] = row.first_x[c].plus(self.second_x[c]);
        }
    }
    #[inline]
    fn skip(&self, row: &mut QuadraticRow<V>, n: u16) {
        // n steps at once: the value grows by n D + s n (n - 1) / 2, the
        // difference D by n s (s the second difference); the same integers.
        let triangle = V::from_i64(n as i64 * (n as i64 - 1) / 2);
        let n = V::from_count(n);
        for c in 0..3 {
            let grown = n
                .times(row.first_x[c])
                .plus(triangle.times(self.second_x[c]));
            row.value[c] = row.value[c].plus(grown);
            row.first_x[c] = row.first_x[c].plus(n.times(self.second_x[c]));
        }
    }
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
        let lit = shade_interpolated(row, &self.light, self.base);
        let c = lit.map(|v| ((v + 128) >> 8).clamp(0, 255) as u8);
        Rgb888::new(c[0], c[1], c[2])
    }
    #[inline]
    fn step(&self, row: &mut [i64; 3]) {
        self.normal.step(row)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed_point::UNIT_ONE;

    /// A small deterministic generator (xorshift64*).
    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
        }
        fn range(&mut self, lo: i64, hi: i64) -> i64 {
            lo + (self.next() % (hi - lo + 1) as u64) as i64
        }
        fn unit(&mut self) -> f64 {
            (self.next() >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// A bounding box on a `w x h` screen as setup computes it.
    fn bounding_box(
        xs: &[i64; 3],
        ys: &[i64; 3],
        w: i64,
        h: i64,
    ) -> Option<((i64, i64), (i64, i64))> {
        let x0 = (xs.iter().min()? >> 4).max(0);
        let y0 = (ys.iter().min()? >> 4).max(0);
        let x1 = (xs.iter().max()? >> 4).min(w - 1);
        let y1 = (ys.iter().max()? >> 4).min(h - 1);
        (x0 <= x1 && y0 <= y1).then_some(((x0, y0), (x1 - x0 + 1, y1 - y0 + 1)))
    }

    fn random_samples(rng: &mut Rng) -> QuadraticSamples {
        let mut color = || core::array::from_fn(|_| rng.range(0, 255 << 8) as i32);
        QuadraticSamples {
            vertices: [color(), color(), color()],
            midpoints: [color(), color(), color()],
        }
    }

    /// A random triangle: small, medium, or reaching over the whole screen
    /// (vertices up to the guard band).
    fn random_triangle(rng: &mut Rng, w: i64, h: i64) -> ([i64; 3], [i64; 3]) {
        let kind = rng.range(0, 3);
        let (cx, cy) = (rng.range(0, w * 16), rng.range(0, h * 16));
        let r = match kind {
            0 => 64,
            1 => 1024,
            2 => w.max(h) * 16,
            _ => 4096 * 16,
        };
        let lim = 4096 * 16;
        let xs = [0; 3].map(|_| (cx + rng.range(-r, r)).clamp(-lim, lim));
        let ys = [0; 3].map(|_| (cy + rng.range(-r, r)).clamp(-lim, lim));
        (xs, ys)
    }

    /// The fitted channel at a point given in 1/16 pixel, as a real number of 8-bit steps.
    fn at_point(p: &QuadraticPolynomial, origin: (i64, i64), x: f64, y: f64) -> f64 {
        let i = (x - (origin.0 * 16 + 8) as f64) / 16.0;
        let j = (y - (origin.1 * 16 + 8) as f64) / 16.0;
        let v = p.a as f64 * i * i
            + p.b as f64 * j * j
            + p.c as f64 * i * j
            + p.d as f64 * i
            + p.e as f64 * j
            + p.f as f64;
        v / (1u64 << QUADRATIC_FRACTION_BITS) as f64
    }

    #[test]
    fn fit_reproduces_the_six_samples() {
        let mut rng = Rng(0x1234_5678_9abc_def1);
        let (w, h) = (2048, 2048);
        let mut worst = 0.0f64;
        let mut fitted = 0;
        for _ in 0..20_000 {
            // On-screen triangles: the samples lie in the box.
            let xs = [0; 3].map(|_| rng.range(0, w * 16 - 1));
            let ys = [0; 3].map(|_| rng.range(0, h * 16 - 1));
            let Some((origin, size)) = bounding_box(&xs, &ys, w, h) else {
                continue;
            };
            let samples = random_samples(&mut rng);
            let Some(poly) = fit_quadratic(&xs, &ys, origin, size, &samples) else {
                continue;
            };
            fitted += 1;
            for ch in 0..3 {
                for k in 0..3 {
                    let l = (k + 1) % 3;
                    let vertex = at_point(&poly[ch], origin, xs[k] as f64, ys[k] as f64);
                    let mid = at_point(
                        &poly[ch],
                        origin,
                        (xs[k] + xs[l]) as f64 / 2.0,
                        (ys[k] + ys[l]) as f64 / 2.0,
                    );
                    worst = worst.max((vertex - samples.vertices[k][ch] as f64 / 256.0).abs());
                    worst = worst.max((mid - samples.midpoints[k][ch] as f64 / 256.0).abs());
                }
            }
        }
        assert!(fitted > 19_000, "only {fitted} triangles fitted");
        // The stated bound: within 1/16 of an 8-bit step (analysis: below 0.06).
        assert!(worst < 1.0 / 16.0, "worst deviation {worst} steps");
    }

    #[test]
    fn samples_out_of_range_are_clamped_before_the_fit() {
        // The public fit clamps its samples; the fit itself takes them in
        // range (color setup clamps the vertex colors it is given).
        let mut rng = Rng(0x5a3c_0ff5_e7c1_a3b9);
        let mut outside = 0;
        for _ in 0..2_000 {
            let (xs, ys) = random_triangle(&mut rng, 128, 128);
            let Some((origin, size)) = bounding_box(&xs, &ys, 128, 128) else {
                continue;
            };
            let mut wide =
                || core::array::from_fn(|_| rng.range(0, 3 * 256 * 256) as i32 - 256 * 256);
            let samples = QuadraticSamples {
                vertices: [wide(), wide(), wide()],
                midpoints: [wide(), wide(), wide()],
            };
            outside += !samples.in_range() as u32;
            let clamped = samples.clamped();
            assert!(clamped.in_range());
            assert_eq!(
                fit_quadratic(&xs, &ys, origin, size, &samples),
                fit_quadratic_over(&xs, &ys, origin, size, &clamped, None)
            );
        }
        assert!(outside > 1_000, "only {outside} sample sets out of range");
    }

    #[test]
    fn a_reciprocal_handed_over_gives_the_same_fit() {
        // Setup hands over the reciprocal of its own area: the same bits
        // as the fit's own where no corner lies on the guard band's edge;
        // there a wrong one is not used.
        let mut rng = Rng(0x7ec1_9e0c_a1ea_2024);
        let guard = (GUARD_BAND_PX as i64) << SUBPIXEL_BITS;
        let (mut handed, mut refused) = (0, 0);
        for n in 0..5_000 {
            let (w, h) = if n % 2 == 0 { (128, 128) } else { (2048, 2048) };
            let (mut xs, ys) = random_triangle(&mut rng, w, h);
            let on_edge = n % 5 == 0;
            if on_edge {
                xs[0] = -guard;
            }
            let Some((origin, size)) = bounding_box(&xs, &ys, w, h) else {
                continue;
            };
            let samples = random_samples(&mut rng);
            let area2 =
                ((xs[1] - xs[0]) * (ys[2] - ys[0]) - (xs[2] - xs[0]) * (ys[1] - ys[0])).abs();
            // On the edge, a reciprocal of another area.
            let given = if on_edge { area2 + 1 } else { area2 };
            let reciprocal = Reciprocal::new(given.max(1) as u64);
            let own = fit_quadratic(&xs, &ys, origin, size, &samples);
            let over = fit_quadratic_over(&xs, &ys, origin, size, &samples, Some(reciprocal));
            assert_eq!(own, over, "{xs:?} {ys:?}");
            handed += (own.is_some() && !on_edge) as u32;
            refused += (own.is_some() && on_edge) as u32;
        }
        assert!(handed > 2_000, "{handed}");
        assert!(refused > 100, "{refused}");
    }

    #[test]
    fn i32_monomials_give_the_i64_fit() {
        // Any triangle whose planes pass `monomials_fit_i32`, slivers up to
        // the bound included, fits to the same bits with 32-bit monomials.
        let mut rng = Rng(0x5eed_0f17_32b1_7500);
        let (mut compared, mut near_bound) = (0, 0);
        for n in 0..40_000 {
            let (w, h) = if n % 2 == 0 { (128, 128) } else { (2048, 2048) };
            let mut xs = [0; 3].map(|_| rng.range(0, w * 16 - 1));
            let mut ys = [0; 3].map(|_| rng.range(0, h * 16 - 1));
            if n % 4 < 2 {
                // A sliver: the third corner close to the line of the others.
                let t = rng.range(0, 256);
                xs[2] = xs[0] + (xs[1] - xs[0]) * t / 256 + rng.range(-2, 2);
                ys[2] = ys[0] + (ys[1] - ys[0]) * t / 256 + rng.range(-2, 2);
            }
            let Some((origin, size)) = bounding_box(&xs, &ys, w, h) else {
                continue;
            };
            let Some(basis) = FitBasis::new(&xs, &ys, origin, size, None) else {
                continue;
            };
            if !basis.monomials_fit_i32() {
                continue;
            }
            near_bound += (basis.extent >= SMALL_BARYCENTRIC_LIMIT / 4) as u32;
            let samples = random_samples(&mut rng);
            assert_eq!(
                fit_channels::<i32>(&basis, &samples),
                fit_channels::<i64>(&basis, &samples),
                "{xs:?} {ys:?}"
            );
            compared += 1;
        }
        assert!(compared > 15_000, "{compared}");
        assert!(near_bound > 20, "{near_bound}");
    }

    #[test]
    fn walks_in_i32_in_words_equals_the_64_bit_bound() {
        // The test as first written: every coefficient and product in 64 bits.
        fn in_64_bits(p: &[QuadraticPolynomial; 3], size: (i64, i64)) -> bool {
            if !is_narrow_box(size) || size.0 < 1 || size.1 < 1 {
                return false;
            }
            let (w, h) = (size.0 as u64, size.1 as u64);
            const DROPPED: i64 = (1 << NARROW_QUADRATIC_DROPPED_BITS) - 1;
            p.iter().all(|p| {
                let ks = p.coefficients();
                let low_bits = ks.iter().fold(0, |or, k| or | k);
                let high = ks.iter().fold(0, |or, k| or | k.unsigned_abs());
                if low_bits & DROPPED != 0 || high >= 1 << 40 {
                    return false;
                }
                let monomials = [w * w, h * h, w * h, w, h, 1];
                let bound: u64 = ks
                    .iter()
                    .zip(monomials)
                    .map(|(k, m)| k.unsigned_abs() * m)
                    .sum();
                bound < ((1 << 31) - (1 << 20)) << NARROW_QUADRATIC_DROPPED_BITS
            })
        }
        let mut rng = Rng(0x0005_eed0_fb0d);
        let (mut narrow, mut wide) = (0, 0);
        for n in 0..200_000 {
            // One magnitude per set, from small (the bound passes) to far
            // beyond it; mostly multiples of 2^8; the edges of the high
            // word's range, and any word, now and then.
            let bits = rng.range(4, 41) as u32;
            let coefficient = |rng: &mut Rng| -> i64 {
                let k = match rng.range(0, 40) {
                    0 => (1i64 << 39) - rng.range(0, 1 << 10),
                    1 => -(1i64 << 39) + rng.range(-(1 << 10), 1 << 10),
                    2 => rng.next() as i64,
                    // Below 2^40, where a wider test of the high word
                    // would let `k >> 8` wrap in `i32`.
                    3 => (1i64 << 40) - rng.range(1, 1 << 12),
                    _ => rng.range(-(1i64 << bits), 1i64 << bits),
                };
                if n % 7 == 0 {
                    k
                } else {
                    k & !0xff
                }
            };
            let poly: [QuadraticPolynomial; 3] = core::array::from_fn(|_| {
                QuadraticPolynomial::from_coefficients(core::array::from_fn(|_| {
                    coefficient(&mut rng)
                }))
            });
            let side = |rng: &mut Rng| {
                if rng.range(0, 1) == 0 {
                    rng.range(0, 12)
                } else {
                    rng.range(0, 130)
                }
            };
            let size = (side(&mut rng), side(&mut rng));
            let expected = in_64_bits(&poly, size);
            assert_eq!(walks_in_i32(&poly, size), expected, "{poly:?} {size:?}");
            if expected {
                narrow += 1;
            } else {
                wide += 1;
            }
        }
        assert!(narrow > 5_000 && wide > 5_000, "{narrow} {wide}");
    }

    #[test]
    fn narrow_coefficients_are_words_above_the_dropped_bits() {
        // What the carried-colors table relies on to keep a polynomial that
        // walks in `i32` in one word per coefficient.
        let mut rng = Rng(0x00c0_ffee_1234_8765);
        let mut narrow = 0;
        for n in 0..20_000 {
            let (w, h) = if n % 2 == 0 { (128, 128) } else { (40, 24) };
            let (xs, ys) = random_triangle(&mut rng, w, h);
            let Some((origin, size)) = bounding_box(&xs, &ys, w, h) else {
                continue;
            };
            let samples = random_samples(&mut rng);
            let Some(p) = fit_quadratic(&xs, &ys, origin, size, &samples) else {
                continue;
            };
            if !walks_in_i32(&p, size) {
                continue;
            }
            narrow += 1;
            for q in &p {
                for k in q.coefficients() {
                    let word = k >> NARROW_QUADRATIC_DROPPED_BITS;
                    assert_eq!(word << NARROW_QUADRATIC_DROPPED_BITS, k, "{q:?}");
                    assert_eq!(word as i32 as i64, word, "{q:?}");
                }
            }
        }
        assert!(narrow > 5_000, "{narrow}");
        // At the bound: a value coefficient as large as the walk takes.
        let big = (((1i64 << 31) - (1 << 20)) << NARROW_QUADRATIC_DROPPED_BITS) - 256;
        let p = QuadraticPolynomial {
            f: big,
            ..QuadraticPolynomial::ZERO
        };
        assert!(walks_in_i32(&[p; 3], (1, 1)));
        assert_eq!(
            (big >> NARROW_QUADRATIC_DROPPED_BITS) as i32 as i64,
            big >> 8
        );
    }

    #[test]
    fn stepping_equals_direct_evaluation_exactly() {
        let mut rng = Rng(0x0fed_cba9_8765_4321);
        let mut checked_pixels = 0u64;
        let (mut boxes, mut fitted, mut narrow_boxes) = (0, 0, 0u32);
        for round in 0..1_500 {
            // Every third screen is small: boxes the `i32` walk may take.
            let (w, h) = match round % 3 {
                0 => (2048, 2048),
                1 => (320, 240),
                _ => (100, 100),
            };
            let (xs, ys) = random_triangle(&mut rng, w, h);
            let Some((origin, size)) = bounding_box(&xs, &ys, w, h) else {
                continue;
            };
            boxes += 1;
            let samples = random_samples(&mut rng);
            let Some(poly) = fit_quadratic(&xs, &ys, origin, size, &samples) else {
                continue;
            };
            fitted += 1;
            // Large boxes: a band of rows starting anywhere, plus the first rows.
            let first = if size.1 > 64 {
                rng.range(0, size.1 - 1)
            } else {
                0
            };
            let last = (first + 40).min(size.1);
            let mut walk = QuadraticWalk::<i64>::start(&poly, first);
            // Where the fit allows it, the `i32` walk alongside: at every pixel
            // of the box, the same polynomial without its zero low bits.
            let narrow = walks_in_i32(&poly, size);
            narrow_boxes += narrow as u32;
            let mut walk32 = QuadraticWalk::<i32>::start(&poly, first);
            for j in first..=last {
                let mut row = walk.row();
                let mut row32 = walk32.row();
                for i in 0..=size.0 {
                    for ch in 0..3 {
                        let exact = poly[ch].eval(i, j);
                        assert_eq!(row.value[ch], exact, "({i}, {j})");
                        assert_eq!(
                            row.first_x[ch],
                            poly[ch].eval(i + 1, j) - poly[ch].eval(i, j)
                        );
                        if narrow && i < size.0 && j < size.1 {
                            assert_eq!(exact & 0xff, 0);
                            assert_eq!(row32.value[ch] as i64, exact >> 8, "({i}, {j})");
                        }
                    }
                    if narrow && i < size.0 && j < size.1 {
                        let walks = QuadraticWalk::<i64>::rgb(&row);
                        assert_eq!(QuadraticWalk::<i32>::rgb(&row32), walks);
                    }
                    walk.step(&mut row);
                    walk32.step(&mut row32);
                    checked_pixels += 1;
                }
                walk.next_row();
                walk32.next_row();
            }
        }
        // Random samples curve steeply, so a third of the small boxes pass.
        assert!(narrow_boxes > 100, "{narrow_boxes} boxes walked in i32");
        // Random triangles are rarely slivers: nearly all take the quadratic.
        assert!(
            fitted * 100 >= boxes * 99,
            "{fitted} of {boxes} triangles fitted"
        );
        assert!(fitted > 1_000, "only {fitted} triangles fitted");
        assert!(checked_pixels > 10_000_000, "{checked_pixels}");
    }

    #[test]
    fn screen_spanning_triangle_steps_exactly_over_every_pixel() {
        // Corners far outside a 2048 x 2048 screen: the box is the whole screen.
        let lim = 4096 * 16;
        let xs = [-lim, lim, -lim / 2];
        let ys = [-lim, -lim / 3, lim];
        let (origin, size) = ((0, 0), (2048, 2048));
        let mut rng = Rng(99);
        for _ in 0..3 {
            let samples = random_samples(&mut rng);
            let poly = fit_quadratic(&xs, &ys, origin, size, &samples).expect("fits");
            let mut walk = QuadraticWalk::<i64>::start(&poly, 0);
            for j in 0..=size.1 {
                let mut row = walk.row();
                for i in 0..=size.0 {
                    for ch in 0..3 {
                        assert_eq!(row.value[ch], poly[ch].eval(i, j));
                    }
                    walk.step(&mut row);
                }
                walk.next_row();
            }
        }
    }

    #[test]
    fn equal_samples_shade_constant() {
        let mut rng = Rng(7);
        for _ in 0..2_000 {
            let (xs, ys) = random_triangle(&mut rng, 640, 480);
            let Some((origin, size)) = bounding_box(&xs, &ys, 640, 480) else {
                continue;
            };
            let color = [rng.range(0, 255) as i32 * 256, 77 * 256 + 13, 0];
            let samples = QuadraticSamples {
                vertices: [color; 3],
                midpoints: [color; 3],
            };
            let Some(poly) = fit_quadratic(&xs, &ys, origin, size, &samples) else {
                continue;
            };
            for ch in 0..3 {
                let expected = (color[ch] as i64) << BARYCENTRIC_BITS;
                assert_eq!(
                    poly[ch],
                    QuadraticPolynomial {
                        f: expected,
                        ..Default::default()
                    }
                );
            }
        }
    }

    #[test]
    fn degenerate_triangles_fit_nothing() {
        let samples = QuadraticSamples::default();
        // Collinear and coincident vertices.
        assert!(
            fit_quadratic(&[0, 160, 320], &[0, 160, 320], (0, 0), (21, 21), &samples).is_none()
        );
        assert!(fit_quadratic(&[5, 5, 5], &[9, 9, 9], (0, 0), (1, 1), &samples).is_none());
        // A sliver far thinner than its box falls back to linear planes.
        let xs = [0, 2047 * 16, 2047 * 16];
        let ys = [0, 2047 * 16, 2047 * 16 + 1];
        assert!(fit_quadratic(&xs, &ys, (0, 0), (2048, 2048), &samples).is_none());
    }

    #[test]
    fn fitted_surface_matches_the_quadratic_inside() {
        // A smooth surface given by a known quadratic in barycentric coordinates
        // is reproduced at every pixel center inside the triangle.
        let xs = [10 * 16 + 3, 200 * 16, 90 * 16 + 7];
        let ys = [5 * 16, 60 * 16 + 9, 230 * 16 + 1];
        let (origin, size) = bounding_box(&xs, &ys, 240, 240).unwrap();
        let value = |s: f64, t: f64| 40.0 + 120.0 * s + 60.0 * t - 90.0 * s * s + 30.0 * s * t;
        let q8 = |v: f64| [(v * 256.0).round() as i32; 3];
        let samples = QuadraticSamples {
            vertices: [
                q8(value(0.0, 0.0)),
                q8(value(1.0, 0.0)),
                q8(value(0.0, 1.0)),
            ],
            midpoints: [
                q8(value(0.5, 0.0)),
                q8(value(0.5, 0.5)),
                q8(value(0.0, 0.5)),
            ],
        };
        let poly = fit_quadratic(&xs, &ys, origin, size, &samples).unwrap();
        let (x0, y0) = (xs[0] as f64, ys[0] as f64);
        let (dx1, dy1) = (xs[1] as f64 - x0, ys[1] as f64 - y0);
        let (dx2, dy2) = (xs[2] as f64 - x0, ys[2] as f64 - y0);
        let area = dx1 * dy2 - dx2 * dy1;
        for j in 0..size.1 {
            for i in 0..size.0 {
                let (x, y) = (
                    ((origin.0 + i) * 16 + 8) as f64,
                    ((origin.1 + j) * 16 + 8) as f64,
                );
                let s = ((x - x0) * dy2 - (y - y0) * dx2) / area;
                let t = (dx1 * (y - y0) - dy1 * (x - x0)) / area;
                if s < 0.0 || t < 0.0 || s + t > 1.0 {
                    continue;
                }
                let got = poly[0].eval(i, j) as f64 / (1u64 << QUADRATIC_FRACTION_BITS) as f64;
                // Samples rounded to Q8: within 1/256 plus the fit's rounding.
                assert!(
                    (got - value(s, t)).abs() < 0.02,
                    "({i}, {j}): {got} vs {}",
                    value(s, t)
                );
            }
        }
    }

    #[test]
    fn midpoint_normal_matches_float_normalization() {
        let mut rng = Rng(3);
        let unit = |rng: &mut Rng| loop {
            let v = [0; 3].map(|_| rng.unit() * 2.0 - 1.0);
            let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if l > 0.1 && l <= 1.0 {
                break v.map(|c| ((c / l) * UNIT_ONE as f64).round() as i32);
            }
        };
        let mut worst = 0.0f64;
        for _ in 0..200_000 {
            let a = unit(&mut rng);
            // Mostly nearby normals (meshes), some far apart.
            let b = if rng.range(0, 3) > 0 {
                let d = [0; 3].map(|_| rng.range(-3000, 3000) as i32);
                let v = [a[0] + d[0], a[1] + d[1], a[2] + d[2]];
                let l = v.iter().map(|c| (*c as f64).powi(2)).sum::<f64>().sqrt();
                v.map(|c| (c as f64 / l * UNIT_ONE as f64).round() as i32)
            } else {
                unit(&mut rng)
            };
            let s = [a[0] + b[0], a[1] + b[1], a[2] + b[2]].map(|c| c as f64);
            let l = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
            match midpoint_normal(&a, &b) {
                Some(n) => {
                    for k in 0..3 {
                        worst = worst.max((n[k] as f64 - s[k] / l * UNIT_ONE as f64).abs());
                    }
                }
                None => assert_eq!(l, 0.0),
            }
        }
        assert!(worst <= 1.0, "worst component error {worst} units of 2^-14");
        assert_eq!(midpoint_normal(&[UNIT_ONE, 0, 0], &[-UNIT_ONE, 0, 0]), None);
    }

    #[test]
    fn rsqrt_in_words_equals_the_64_bit_steps() {
        // The steps as first written, every value in 64 bits.
        fn in_64_bits(x: u64) -> u64 {
            let k = ((x >> 24) - 16).min(47) as usize;
            let mut y = RSQRT_START[k] as u64;
            for _ in 0..2 {
                let h = (((y * y) >> 30) * x) >> 28;
                y = (y * ((3 << 30) - h)) >> 31;
            }
            y
        }
        // Both ends of every table interval and a stride through all.
        let mut xs: std::vec::Vec<u64> = (16..64u64)
            .flat_map(|k| [k << 24, ((k + 1) << 24) - 1])
            .collect();
        xs.extend(((1u64 << 28)..(4 << 28)).step_by(997));
        for x in xs {
            assert_eq!(rsqrt_q28(x), in_64_bits(x), "x {x}");
            assert!(rsqrt_q28(x) < 1 << 31);
        }
    }

    #[test]
    fn rsqrt_table_and_newton_steps() {
        let mut x = 1u64 << 28;
        while x < 4 << 28 {
            let y = rsqrt_q28(x) as f64 / (1u64 << 30) as f64;
            let exact = 1.0 / (x as f64 / (1u64 << 28) as f64).sqrt();
            assert!((y / exact - 1.0).abs() < 1.0 / (1 << 21) as f64, "x {x}");
            x += 12_345;
        }
    }
}
