//! The quadratic through six samples, as a lattice polynomial.

use super::{is_narrow_box, BARYCENTRIC_BITS, NARROW_QUADRATIC_DROPPED_BITS};
use crate::fixed_point::{wide_mul, wide_mul_add, Reciprocal, GUARD_BAND_PX, SUBPIXEL_BITS};
use crate::lighting::{clamp_q8, ColorQ8, COLOR_Q8_MAX};

/// Bound on `|s0| + |su| + |sv|` (and `t`) for the quadratic fit (2^10 in value).
const BARYCENTRIC_LIMIT: i64 = 1 << 30;

/// Bound on `|s0| + |su| + |sv|` (and `t`) under which the fit's monomials
/// fit `i32` (2^5 in value).
pub(super) const SMALL_BARYCENTRIC_LIMIT: i64 = 1 << 25;

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

/// A product of two Q20 plane values (a [`wide_mul`], or a sum of them)
/// rounded back to Q20: a monomial's mantissa.
#[inline(always)]
fn round_q20(v: i64) -> i64 {
    (v + (1 << (BARYCENTRIC_BITS - 1))) >> BARYCENTRIC_BITS
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
pub(super) struct FitBasis {
    s: [i32; 3],
    t: [i32; 3],
    /// The larger of `|s0| + |su| + |sv|` and the same sum for `t`.
    pub(super) extent: i64,
    shifts: [u32; 6],
    drop: u32,
}

impl FitBasis {
    /// The barycentric planes of the triangle `xs`, `ys` over the box at
    /// `origin` of `size` pixels, as [`fit_quadratic`] takes them; `None`
    /// where it returns `None`.
    #[inline(always)]
    pub(super) fn new(
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
        // Within the guard band the corners are words (±2^16), their
        // differences too (±2^17), and so are the offsets of the box's first
        // pixel center from vertex 0 (its origin below 4096 pixels: below
        // 2^17 + 8): each product below is one 32 x 32-bit multiplication.
        let (xs, ys) = (xs.map(|c| c as i32), ys.map(|c| c as i32));
        let wide = |a: i32, b: i32| a as i64 * b as i64;
        let (mut dx1, mut dy1) = (xs[1] - xs[0], ys[1] - ys[0]);
        let (mut dx2, mut dy2) = (xs[2] - xs[0], ys[2] - ys[0]);
        let area2 = wide(dx1, dy2) - wide(dx2, dy1);
        if area2 == 0 || size.0 < 1 || size.1 < 1 {
            return None;
        }
        // Each numerator below is linear in the steps to vertex 2 (`s`) or
        // to vertex 1 (`t`): with every step negated where the area is
        // negative, they are the numerators times the area's sign (the
        // same integers as that product).
        if area2 < 0 {
            (dx1, dy1, dx2, dy2) = (-dx1, -dy1, -dx2, -dy2);
        }
        let area2 = area2.abs();
        let half = 1 << (SUBPIXEL_BITS - 1);
        let u0 = ((origin.0 as i32) << SUBPIXEL_BITS) + half - xs[0];
        let v0 = ((origin.1 as i32) << SUBPIXEL_BITS) + half - ys[0];
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
        let at = |n: i64, extra: u32| reciprocal.mul_div_round(n, extra);
        let (s0, su, sv) = (
            at(wide(u0, dy2) - wide(v0, dx2), BARYCENTRIC_BITS),
            at(dy2 as i64, scale + p),
            at(-dx2 as i64, scale + q),
        );
        let (t0, tu, tv) = (
            at(wide(dx1, v0) - wide(dy1, u0), BARYCENTRIC_BITS),
            at(-dy1 as i64, scale + p),
            at(dx1 as i64, scale + q),
        );
        let extent = (s0.abs() + su.abs() + sv.abs()).max(t0.abs() + tu.abs() + tv.abs());
        if extent >= BARYCENTRIC_LIMIT {
            return None;
        }
        // Below 2^30 in magnitude (`extent`): words.
        Some(FitBasis {
            s: [s0, su, sv].map(|v| v as i32),
            t: [t0, tu, tv].map(|v| v as i32),
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
    pub(super) fn monomials_fit_i32(&self) -> bool {
        self.extent < SMALL_BARYCENTRIC_LIMIT
    }
}

/// A monomial mantissa of the fit: `i64`, or `i32` when the planes are small
/// enough for every mantissa to fit (then each product with a weight is one
/// 32 x 32-bit multiply-accumulate).
pub(super) trait Monomial: Copy {
    /// The mantissa `v` (within this type's range).
    fn from_mantissa(v: i64) -> Self;
    /// `acc + w m` for a weight `w` below 2^20 (the sum fits `i64`).
    fn weighted_add(self, acc: i64, w: i32) -> i64;
}

impl Monomial for i64 {
    #[inline(always)]
    fn from_mantissa(v: i64) -> Self {
        v
    }
    #[inline(always)]
    fn weighted_add(self, acc: i64, w: i32) -> i64 {
        acc + w as i64 * self
    }
}

impl Monomial for i32 {
    #[inline(always)]
    fn from_mantissa(v: i64) -> Self {
        v as i32
    }
    #[inline(always)]
    fn weighted_add(self, acc: i64, w: i32) -> i64 {
        wide_mul_add(acc, w, self)
    }
}

/// The monomial `x y` of two Q20 plane values (words: below 2^30, or twice
/// such a value, which `FitBasis::new` checks), Q20.
#[inline(always)]
fn monomial<T: Monomial>(x: i32, y: i32) -> T {
    T::from_mantissa(round_q20(wide_mul(x, y)))
}

/// The monomial `x y + z w` of Q20 plane values, Q20.
#[inline(always)]
fn monomial2<T: Monomial>(x: i32, y: i32, z: i32, w: i32) -> T {
    T::from_mantissa(round_q20(wide_mul_add(wide_mul(x, y), z, w)))
}

/// The three channels' polynomials over `basis`, coefficient by coefficient:
/// for each of `[a, b, c, d, e, f]` the three monomials of `s²`, `t²` and
/// `s t` that belong to it (coefficients of `[u², v², uv, u, v, 1]` over the
/// normalized box), then the coefficient of each channel. Each product is
/// used soon after it is made, so few values are live at once (with the
/// products in source order, [`wide_mul`]: 742 instructions for the `i32`
/// case on a Cortex-M4, against 910 when every monomial was made first).
/// Out of line, one copy per monomial type, so neither copy's registers
/// burden the caller's.
#[inline(never)]
pub(super) fn fit_channels<T: Monomial>(
    basis: &FitBasis,
    samples: &QuadraticSamples,
) -> [QuadraticPolynomial; 3] {
    let [s0, su, sv] = basis.s;
    let [t0, tu, tv] = basis.t;
    let weights = [0, 1, 2].map(|ch| ChannelWeights::of(samples, ch));
    let m = monomial::<T>;
    let m2 = monomial2::<T>;
    let w = &weights;
    let a = coefficient(w, basis, 0, [m(su, su), m(tu, tu), m(su, tu)], [0, 0]);
    let b = coefficient(w, basis, 1, [m(sv, sv), m(tv, tv), m(sv, tv)], [0, 0]);
    let c = coefficient(
        w,
        basis,
        2,
        [m(2 * su, sv), m(2 * tu, tv), m2(su, tv, sv, tu)],
        [0, 0],
    );
    let d = coefficient(
        w,
        basis,
        3,
        [m(2 * s0, su), m(2 * t0, tu), m2(s0, tu, t0, su)],
        [su, tu],
    );
    let e = coefficient(
        w,
        basis,
        4,
        [m(2 * s0, sv), m(2 * t0, tv), m2(s0, tv, t0, sv)],
        [sv, tv],
    );
    let f = coefficient(w, basis, 5, [m(s0, s0), m(t0, t0), m(s0, t0)], [s0, t0]);
    core::array::from_fn(|ch| QuadraticPolynomial {
        a: a[ch],
        b: b[ch],
        c: c[ch],
        d: d[ch],
        e: e[ch],
        f: f[ch],
    })
}

/// How coefficient `k` goes from the normalized box to pixel steps.
///
/// Q8 weights times Q20 mantissas: Q28 over the normalized box; the powers
/// of u = i / 2^p and v = j / 2^q become shifts by `shift` (below 32). On a
/// small box the coefficients are rounded to multiples of 2^8 (see
/// `FitBasis::drop`): the value over 2^(shift + drop) rounded to nearest
/// (halves up), times 2^drop, with one shift (the quotient by 2^shift,
/// floored, then its low `drop` bits cleared). `shift + drop` is at most 26
/// (boxes up to 4096 pixels, 2^8 dropped only up to 128): the half fits 32
/// bits.
#[derive(Clone, Copy)]
struct CoefficientStep {
    /// Added before the shift, to round.
    half: i64,
    /// The power of two to divide by.
    shift: u32,
    /// The bits kept after the shift (a word: the high word passes
    /// unchanged).
    kept: i64,
}

impl CoefficientStep {
    #[inline(always)]
    fn of(basis: &FitBasis, k: usize) -> Self {
        Self {
            half: ((1u32 << (basis.shifts[k] + basis.drop)) >> 1) as i64,
            shift: basis.shifts[k] & 31,
            kept: !(((1u32 << basis.drop) - 1) as i64),
        }
    }
}

/// Coefficient `k` (of `[a, b, c, d, e, f]`) of the three channels: each
/// channel's weights times `monomials` (of `s²`, `t²`, `s t`), plus its
/// linear weights times `linear` (the `s` and `t` planes' terms, for `d`,
/// `e` and `f`) and its first sample (for `f`), stepped to pixels.
#[inline(always)]
fn coefficient<T: Monomial>(
    weights: &[ChannelWeights; 3],
    basis: &FitBasis,
    k: usize,
    [ss, tt, st]: [T; 3],
    [s, t]: [i32; 2],
) -> [i64; 3] {
    let step = CoefficientStep::of(basis, k);
    let channel = |w: &ChannelWeights| {
        let mut v = ss.weighted_add(step.half, w.alpha);
        v = tt.weighted_add(v, w.beta);
        v = st.weighted_add(v, w.gamma);
        if k >= 3 {
            v = wide_mul_add(v, w.delta, s);
            v = wide_mul_add(v, w.epsilon, t);
        }
        if k == 5 {
            v += (w.c0 as i64) << BARYCENTRIC_BITS;
        }
        (v >> step.shift) & step.kept
    };
    [
        channel(&weights[0]),
        channel(&weights[1]),
        channel(&weights[2]),
    ]
}

/// One channel's weights of the fit, from its six samples (Q8, within
/// `[0, 255]`): `|α|, |β|, |δ|, |ε| < 2^18`, `|γ| < 2^19`.
struct ChannelWeights {
    alpha: i32,
    beta: i32,
    gamma: i32,
    delta: i32,
    epsilon: i32,
    c0: i32,
}

impl ChannelWeights {
    #[inline(always)]
    fn of(samples: &QuadraticSamples, ch: usize) -> Self {
        let sample = |v: &ColorQ8| v[ch];
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::xorshift;

    /// The barycentric planes of `FitBasis::new` from 64-bit differences
    /// and products, each numerator times the area's sign.
    fn planes_in_i64(
        xs: &[i64; 3],
        ys: &[i64; 3],
        origin: (i64, i64),
        size: (i64, i64),
    ) -> Option<([i32; 3], [i32; 3])> {
        let (dx1, dy1) = (xs[1] - xs[0], ys[1] - ys[0]);
        let (dx2, dy2) = (xs[2] - xs[0], ys[2] - ys[0]);
        let area2 = dx1 * dy2 - dx2 * dy1;
        if area2 == 0 {
            return None;
        }
        let sign = area2.signum();
        let reciprocal = Reciprocal::new(area2.unsigned_abs());
        let half = 1i64 << (SUBPIXEL_BITS - 1);
        let u0 = (origin.0 << SUBPIXEL_BITS) + half - xs[0];
        let v0 = (origin.1 << SUBPIXEL_BITS) + half - ys[0];
        let (p, q) = (bits_above(size.0), bits_above(size.1));
        let scale = SUBPIXEL_BITS + BARYCENTRIC_BITS;
        let at = |n: i64, extra: u32| reciprocal.mul_div_round(sign * n, extra);
        let s = [
            at(u0 * dy2 - v0 * dx2, BARYCENTRIC_BITS),
            at(dy2, scale + p),
            at(-dx2, scale + q),
        ];
        let t = [
            at(dx1 * v0 - dy1 * u0, BARYCENTRIC_BITS),
            at(-dy1, scale + p),
            at(dx1, scale + q),
        ];
        let sum = |v: &[i64; 3]| v.iter().map(|c| c.abs()).sum::<i64>();
        if sum(&s).max(sum(&t)) >= BARYCENTRIC_LIMIT {
            return None;
        }
        Some((s.map(|v| v as i32), t.map(|v| v as i32)))
    }

    #[test]
    fn planes_in_words_equal_the_64_bit_planes() {
        // Corners anywhere in the guard band (its edges included), both
        // orientations, boxes anywhere up to 4096 pixels.
        let mut next = xorshift(0x0f17_ba5e_5eed_2024);
        let guard = (GUARD_BAND_PX as i64) << SUBPIXEL_BITS;
        let mut fitted = 0;
        for i in 0..200_000 {
            let reach = [guard, 4096, 256][i % 3];
            let mut corner = || {
                let c = (next() % (2 * reach as u64 + 1)) as i64 - reach;
                if next().is_multiple_of(16) {
                    c.signum() * guard
                } else {
                    c
                }
            };
            let (xs, ys) = (
                [corner(), corner(), corner()],
                [corner(), corner(), corner()],
            );
            let mut count = |n: u64| (next() % n) as i64;
            let origin = (count(4097), count(4097));
            let size = (1 + count(4096), 1 + count(4096));
            let basis = FitBasis::new(&xs, &ys, origin, size, None);
            assert_eq!(
                basis.as_ref().map(|b| (b.s, b.t)),
                planes_in_i64(&xs, &ys, origin, size),
                "{xs:?} {ys:?} {origin:?} {size:?}"
            );
            fitted += basis.is_some() as u32;
        }
        assert!(fitted > 10_000, "{fitted}");
    }
}
