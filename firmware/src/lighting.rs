//! The lighting model in fixed point: ambient + Lambert diffuse + Blinn-Phong
//! specular from one white directional light, viewer at infinity.
//!
//! `I = base * (ambient + diffuse * max(0, n.l)) + 255 * specular * max(0, n.h)^shininess`
//! per channel (the specular term only where `n.l > 0`), with unit vectors in
//! Q2.14 and colors in Q8 (value x 256), clamped to `[0, 255]`. The light is
//! prepared in eye space for the frame ([`LightSetup::new`]), then turned into
//! each object's model space ([`LightSetup::in_model_space`]), where the
//! mesh's normals are lit as they are stored.

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

/// A [`ColorQ8`] rounded to the nearest 8-bit channels, each clamped to
/// `0 ..= 255`: how lit colors become the 8-bit colors of vertices,
/// fragments and flat triangles.
#[inline]
pub fn channels_rounded(c: ColorQ8) -> [u8; 3] {
    c.map(|v| ((v + 128) >> 8).clamp(0, 255) as u8)
}

/// [`channels_rounded`] as an [`Rgb888`].
#[inline]
pub fn rgb888_rounded(c: ColorQ8) -> Rgb888 {
    let [r, g, b] = channels_rounded(c);
    Rgb888::new(r, g, b)
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

/// The light, prepared for one frame: direction and half vector, in eye
/// space or in one object's model space.
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
    /// No light: all zero (so that workspace memory holding it stays in
    /// `.bss`); it lights nothing, and the renderer uses it only as the
    /// value of objects in scenes without a light.
    pub const NONE: Self = Self {
        to_light: [0; 3],
        half: [0; 3],
        ambient: 0,
        diffuse: 0,
        specular: 0,
        shininess: 0,
        highlight_from: 0,
    };

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

    /// The same light for normals in the model space of an object whose
    /// normals turn into eye space by the rotation `normal` (rows, Q2.14,
    /// [`crate::geometry::ObjectTransform::normal`]): its directions turned
    /// back by the transposed rotation. A rotation keeps dot products, so
    /// shading a model-space normal with it gives what shading the normal
    /// turned into eye space gives with `self`, but for the rounding of the
    /// two directions (a unit of Q2.14 in a component): the normals need no
    /// turning, per vertex or per triangle.
    pub fn in_model_space(&self, normal: &[[i32; 3]; 3]) -> Self {
        let back = |v: &[i32; 3]| {
            let turned: [i64; 3] = core::array::from_fn(|j| {
                (0..3)
                    .map(|i| normal[i][j] as i64 * v[i] as i64)
                    .sum::<i64>()
            });
            normalize_unit(turned).unwrap_or(*v)
        };
        Self {
            to_light: back(&self.to_light),
            half: back(&self.half),
            ..*self
        }
    }

    /// The lit color of a surface with unit normal `n` (Q2.14, in the space
    /// of the light's directions: eye space, or an object's model space for
    /// [`LightSetup::in_model_space`]) and color `base`.
    // Always inlined (vertex lighting, the midpoints of quadratic shading):
    // 0.03 M fewer instructions on the teapot's frame than out of line.
    #[inline(always)]
    pub fn shade(&self, n: &[i32; 3], base: Rgb888) -> ColorQ8 {
        let [r, g, b] = self.lit(n, base);
        let clamp = |v: i32| v.clamp(0, COLOR_Q8_MAX);
        [clamp(r), clamp(g), clamp(b)]
    }

    /// [`channels_rounded`] of [`LightSetup::shade`]: the lit color
    /// rounded to 8 bits per channel, with one clamp instead of two. The
    /// same bits: below 0 both give 0 (the rounding of a value from -128
    /// on is 0, of one below that negative); above `255 * 256` both give
    /// 255 (the rounding of `255 * 256` is 255, and of a larger value at
    /// least that).
    #[inline(always)]
    pub fn shade_rounded(&self, n: &[i32; 3], base: Rgb888) -> [u8; 3] {
        channels_rounded(self.lit(n, base))
    }

    /// The channels of [`LightSetup::shade`] before their clamp (Q8,
    /// below 2^21 in magnitude).
    #[inline(always)]
    fn lit(&self, n: &[i32; 3], base: Rgb888) -> [i32; 3] {
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
        let channel = |c: u8| ((c as i32 * diffuse) >> (UNIT_BITS - 8)) + highlight;
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
    fn a_light_turned_into_model_space_shades_model_normals_alike() {
        use crate::fixed_point::{sin_cos_deg, Coord};
        // A rotation (Q2.14 rows) about x, then about y, as an object's
        // normal matrix holds it.
        let q14 = |v: i32| (v + (1 << 15)) >> 16;
        let (sa, ca) = sin_cos_deg(Coord::from_num(37));
        let (sb, cb) = sin_cos_deg(Coord::from_num(-112));
        let (sa, ca, sb, cb) = (q14(sa), q14(ca), q14(sb), q14(cb));
        let one = UNIT_ONE;
        let rx = [[one, 0, 0], [0, ca, -sa], [0, sa, ca]];
        let ry = [[cb, 0, sb], [0, one, 0], [-sb, 0, cb]];
        let turn = |m: &[[i32; 3]; 3], v: &[i32; 3]| -> [i32; 3] {
            core::array::from_fn(|i| {
                (m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2] + (1 << (UNIT_BITS - 1)))
                    >> UNIT_BITS
            })
        };
        let normal: [[i32; 3]; 3] = core::array::from_fn(|i| {
            core::array::from_fn(|j| turn(&ry, &[rx[0][j], rx[1][j], rx[2][j]])[i])
        });
        // Unit vectors from long ones, as `LightSetup::new` makes them.
        let to_light = normalize_unit([3 << 16, 5 << 16, 7 << 16]).unwrap();
        let half = normalize_unit([
            (to_light[0] as i64) << 8,
            (to_light[1] as i64) << 8,
            (to_light[2] as i64 + UNIT_ONE as i64) << 8,
        ])
        .unwrap();
        let eye = LightSetup {
            to_light,
            half,
            ambient: UNIT_ONE / 5,
            diffuse: UNIT_ONE * 7 / 10,
            specular: UNIT_ONE / 2,
            shininess: 20,
            highlight_from: first_nonzero_power(20),
        };
        let model = eye.in_model_space(&normal);
        let base = Rgb888::new(200, 150, 90);
        let mut rng = crate::test_rng::xorshift(0x05EE_D0F1_16E7);
        let (mut largest, mut sum, mut count) = (0, 0i64, 0i64);
        for _ in 0..20_000 {
            let mut c = || (rng() % 2001) as i64 - 1000;
            let Some(n) = normalize_unit([c(), c(), c()]) else {
                continue;
            };
            let lit_eye = eye.shade(&turn(&normal, &n), base);
            let lit_model = model.shade(&n, base);
            for (a, b) in lit_eye.iter().zip(lit_model) {
                largest = largest.max((a - b).abs());
                sum += (a - b).abs() as i64;
                count += 1;
            }
        }
        // Q8: apart by the rounding of the turned directions and of the
        // normals turned into eye space, steepest in the highlight (78 at
        // most, 0.95 on average here): within half an 8-bit step, and
        // within 1/64 of a step on average.
        assert!(largest <= 128, "largest difference {largest}");
        assert!(sum <= 4 * count, "mean difference {}", sum / count);
    }

    #[test]
    fn shade_rounded_is_the_rounded_shade() {
        // Lights from dark to far beyond white (and, past what `new`
        // makes, below black), in every direction.
        let mut rng = crate::test_rng::xorshift(0x005a_de0f_ba5e_c010);
        for i in 0..50_000 {
            let r: [u64; 16] = core::array::from_fn(|_| rng());
            let vector = |k: usize| {
                normalize_unit(core::array::from_fn(|j| (r[k + j] % 2001) as i64 - 1000))
            };
            let (Some(n), Some(to_light), Some(half)) = (vector(0), vector(3), vector(6)) else {
                continue;
            };
            let coefficient = |k: usize| (r[k] % (8 * UNIT_ONE as u64)) as i32;
            let shininess = 1 + (r[12] % 64) as u32;
            let light = LightSetup {
                to_light,
                half,
                ambient: coefficient(9) - if i % 4 == 0 { 4 * UNIT_ONE } else { 0 },
                diffuse: coefficient(10),
                specular: coefficient(11),
                shininess,
                highlight_from: first_nonzero_power(shininess),
            };
            let base = Rgb888::new(r[13] as u8, r[14] as u8, r[15] as u8);
            assert_eq!(
                light.shade_rounded(&n, base),
                channels_rounded(light.shade(&n, base)),
                "{light:?} {n:?} {base:?}"
            );
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
