//! Quadratic colors stepped by forward differences.

use super::{
    is_narrow_box, QuadraticPolynomial, NARROW_QUADRATIC_BOX, NARROW_QUADRATIC_DROPPED_BITS,
    NARROW_QUADRATIC_FRACTION_BITS, QUADRATIC_FRACTION_BITS,
};
use crate::shading::{channel_i32, rounding_bias, ColorWalk, PlaneValue};
use embedded_graphics_core::pixelcolor::Rgb888;

/// A quadratic channel in [`QUADRATIC_FRACTION_BITS`], with its
/// [`rounding_bias`], to 8 bits, rounded and clamped.
#[inline]
fn channel_quadratic(v: i64) -> u8 {
    const _: () = assert!(QUADRATIC_FRACTION_BITS == 28);
    // The same as `channel(v, 28)`, decided on the high word: the value is
    // in `[0, 255]` exactly when that word is below 16.
    let high = (v >> 32) as i32;
    if (high as u32) < 16 {
        (v >> 28) as u8
    } else if high < 0 {
        0
    } else {
        255
    }
}

/// The number types a [`QuadraticWalk`] steps: `i64` any fitted
/// polynomial, `i32` one that [`walks_in_i32`] (half the registers).
pub trait QuadraticValue: PlaneValue {
    /// Low bits of the fitted coefficients ([`QUADRATIC_FRACTION_BITS`])
    /// that this type leaves out (all zero where it is used).
    const DROPPED_BITS: u32;
    /// The [`rounding_bias`] of this type's values, which the walk adds to
    /// them when it starts.
    const ROUNDING_BIAS: i64 = rounding_bias(QUADRATIC_FRACTION_BITS - Self::DROPPED_BITS);
    /// The 8-bit channel of a value that carries [`Self::ROUNDING_BIAS`],
    /// rounded and clamped.
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
    /// `Q(i, j)` per channel, plus [`QuadraticValue::ROUNDING_BIAS`].
    pub value: [V; 3],
    /// `Q(i + 1, j) - Q(i, j)` per channel.
    pub first_x: [V; 3],
}

/// Whether polynomials `p` over a bounding box of `size` pixels (columns,
/// rows) can be walked in `i32`: the box is at most
/// [`NARROW_QUADRATIC_BOX`] on each side, every coefficient is a multiple
/// of `2^8` (as the fit leaves them on such a box), and every value on the
/// box, in [`NARROW_QUADRATIC_FRACTION_BITS`], is below `2^31 - 2^20` in
/// magnitude (so below `2^31` with the walk's rounding bias, `2^19`) (bounded by the sum over the coefficients of `|k| m`, `m` the
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
            let f = f.plus(V::from_i64(V::ROUNDING_BIAS));
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
    const UNROLLED_RUNS: bool = core::mem::size_of::<V>() > 4;
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
        // `n^2 - n` in 32 bits: below 2^32 for a `u16` count and never
        // negative, so no 64-bit product or signed halving.
        let n_u32 = n as u32;
        let triangle = V::from_i64(((n_u32 * n_u32 - n_u32) / 2) as i64);
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
