//! The lighting model in fixed point: ambient + Lambert diffuse + Blinn-Phong
//! specular from one white directional light, viewer at infinity.
//!
//! `I = base * (ambient + diffuse * max(0, n.l)) + 255 * specular * max(0, n.h)^shininess`
//! per channel (the specular term only where `n.l > 0`), computed in eye space with
//! unit vectors in Q2.14 and colors in Q8 (value x 256), clamped to `[0, 255]`.

use crate::fixed_point::{isqrt_u64, UNIT_BITS, UNIT_ONE};
use crate::geometry::ViewBasis;
use crate::scene::Light;
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};

/// A color with 8 fraction bits per channel (value x 256), as vertex colors are kept.
///
/// Range: `0 ..=` [`COLOR_Q8_MAX`] per channel ([`LightSetup::shade`] clamps, and
/// clipping interpolates between two such colors), so differences of two fit 17
/// bits and color planes stay within the bounds given at [`crate::setup::Plane`].
pub type ColorQ8 = [i32; 3];

/// The largest channel of a [`ColorQ8`]: 255 in Q8.
pub const COLOR_Q8_MAX: i32 = 255 << 8;

/// A color clamped to the range of [`ColorQ8`], `0 ..= 255` (Q8) per channel.
#[inline]
pub fn clamp_q8(c: ColorQ8) -> ColorQ8 {
    c.map(|v| v.clamp(0, COLOR_Q8_MAX))
}

/// A color in [`ColorQ8`] form.
#[inline]
pub fn color_q8(c: Rgb888) -> ColorQ8 {
    [
        (c.r() as i32) << 8,
        (c.g() as i32) << 8,
        (c.b() as i32) << 8,
    ]
}

/// Normalizes a vector to Q2.14; `None` for the zero vector.
pub fn normalize_unit(v: [i64; 3]) -> Option<[i32; 3]> {
    let len2: u64 = v.iter().map(|c| (c * c) as u64).sum();
    let len = isqrt_u64(len2) as i64;
    if len == 0 {
        return None;
    }
    Some(v.map(|c| ((c << UNIT_BITS) / len) as i32))
}

/// The light, prepared for one frame: eye-space direction and half vector.
///
/// Ranges: the directions are unit vectors (Q2.14); the coefficients are kept in
/// `0 .. 8` (Q2.14, below 2^17) and dot products with a unit normal are clamped
/// to `0 ..= 1` (2^14), so each coefficient times a dot product (or a power of
/// one) is below 2^31; ambient plus diffuse is below 16 and a channel below
/// `255 * 16 * 2^8 + 255 * 8 * 2^8 < 2^21` before the clamp to `255 * 256`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightSetup {
    to_light: [i32; 3],
    half: [i32; 3],
    ambient: i32,
    diffuse: i32,
    specular: i32,
    shininess: u32,
    /// The smallest `n.h` whose power is not zero: below it the specular
    /// term is skipped (the same result, without the powers).
    highlight_from: i32,
}

#[inline]
fn dot(a: &[i32; 3], b: &[i32; 3]) -> i32 {
    (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) >> UNIT_BITS
}

/// `x^e` for `x` in Q2.14 in `[0, 1]`, by repeated squaring.
fn pow_unit(mut x: i32, mut e: u32) -> i32 {
    let mut r = UNIT_ONE;
    while e > 0 {
        if e & 1 != 0 {
            r = (r * x + (1 << (UNIT_BITS - 1))) >> UNIT_BITS;
        }
        x = (x * x + (1 << (UNIT_BITS - 1))) >> UNIT_BITS;
        e >>= 1;
    }
    r
}

/// The smallest `x` in `0..=UNIT_ONE` with `pow_unit(x, e) > 0`. Each step of
/// [`pow_unit`] rounds a product of non-negative, non-decreasing values, so
/// the power does not decrease with `x`, and a bisection finds the boundary.
fn first_nonzero_power(e: u32) -> i32 {
    let (mut zero, mut nonzero) = (0, UNIT_ONE);
    if pow_unit(zero, e) > 0 {
        return 0;
    }
    while nonzero - zero > 1 {
        let mid = (zero + nonzero) / 2;
        if pow_unit(mid, e) > 0 {
            nonzero = mid;
        } else {
            zero = mid;
        }
    }
    nonzero
}

impl LightSetup {
    /// Prepares `light` for a camera with basis `view`.
    pub fn new(light: &Light, view: &ViewBasis) -> Self {
        let d = light.direction.map(|c| c.to_bits() as i64);
        let world = normalize_unit(d).unwrap_or([0, 0, UNIT_ONE]);
        let to_light = view.rotate_to_eye(&world);
        let half = normalize_unit([
            to_light[0] as i64,
            to_light[1] as i64,
            to_light[2] as i64 + UNIT_ONE as i64,
        ])
        .unwrap_or([0, 0, UNIT_ONE]);
        // Coefficients below 8, so products with a dot product of at most 1 (Q2.14)
        // stay below 2^31.
        let q14 =
            |c: fixed::types::I16F16| (c.to_bits() >> (16 - UNIT_BITS)).clamp(0, 8 * UNIT_ONE - 1);
        Self {
            to_light,
            half,
            ambient: q14(light.ambient),
            diffuse: q14(light.diffuse),
            specular: q14(light.specular),
            shininess: light.shininess.max(1) as u32,
            highlight_from: first_nonzero_power(light.shininess.max(1) as u32),
        }
    }

    /// The lit color of a surface with eye-space unit normal `n` (Q2.14) and color `base`.
    // Always inlined (vertex lighting, the midpoints of quadratic shading):
    // 0.03 M fewer instructions on the teapot's frame than out of line.
    #[inline(always)]
    pub fn shade(&self, n: &[i32; 3], base: Rgb888) -> ColorQ8 {
        // Unit vectors rounded to Q2.14 may give a dot product a step above 1.
        let ndl = dot(n, &self.to_light).clamp(0, UNIT_ONE);
        let diffuse = self.ambient + ((self.diffuse * ndl) >> UNIT_BITS);
        let spec = if ndl > 0 {
            let ndh = dot(n, &self.half).clamp(0, UNIT_ONE);
            if ndh < self.highlight_from {
                0
            } else {
                (self.specular * pow_unit(ndh, self.shininess)) >> UNIT_BITS
            }
        } else {
            0
        };
        // base (8 bit) * Q14 -> Q14, then to Q8: shift by 6.
        let highlight = (255 * spec) >> (UNIT_BITS - 8);
        let channel =
            |c: u8| (((c as i32 * diffuse) >> (UNIT_BITS - 8)) + highlight).clamp(0, COLOR_Q8_MAX);
        [channel(base.r()), channel(base.g()), channel(base.b())]
    }
}

impl ViewBasis {
    /// Rotates a world-space unit vector (Q2.14) into eye space (Q2.14).
    pub fn rotate_to_eye(&self, v: &[i32; 3]) -> [i32; 3] {
        let rows = self.rotation_rows();
        rows.map(|r| {
            ((r[0] * v[0] as i64 + r[1] * v[1] as i64 + r[2] * v[2] as i64 + (1 << 29)) >> 30)
                as i32
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn powers_below_the_highlight_bound_are_zero() {
        for e in 1..=255 {
            let from = first_nonzero_power(e);
            assert!(pow_unit(from, e) > 0, "{e}");
            for x in 0..from {
                assert_eq!(pow_unit(x, e), 0, "{x}^{e}");
            }
        }
    }

    #[test]
    fn pow_and_normalize() {
        assert_eq!(pow_unit(UNIT_ONE, 200), UNIT_ONE);
        assert_eq!(pow_unit(UNIT_ONE / 2, 2), UNIT_ONE / 4);
        let n = normalize_unit([3, 0, 4]).unwrap();
        assert_eq!(n, [UNIT_ONE * 3 / 5, 0, UNIT_ONE * 4 / 5]);
        assert!(normalize_unit([0, 0, 0]).is_none());
    }
}
