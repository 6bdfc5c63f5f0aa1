//! Fixed-point formats of the pipeline and the integer math they need.
//!
//! Every quantity after scene loading is an integer with a stated format:
//!
//! | quantity | type | format | range |
//! |---|---|---|---|
//! | model and world coordinates | [`Coord`] (`I16F16`) | Q16.16 | ±32768 |
//! | matrix entries | `i32` | Q16.16 | ±32768 |
//! | clip-space coordinates `X, Y, Zs, w` | `i64` | Q32.32 | ±2^30 before clipping |
//! | window coordinates | [`SubPixel`] (`i32`) | Q27.4, 1/16 pixel | ±[`GUARD_BAND_PX`] px after clipping |
//! | window depth | `u32` | 24 fraction bits, 0 = near | `0 ..= DEPTH_MAX` |
//! | unit vectors (normals, light) | `i32` | Q2.14 | ±1 |
//!
//! Window coordinates are snapped to 1/16 pixel. Sample offsets of every supported
//! coverage grid (4x4, 8x4, 8x8) are odd multiples of 1/16 or 1/8 pixel, so every
//! sample position is exact and edge functions at samples are exact integers.

/// Model and world coordinates: Q16.16.
pub type Coord = fixed::types::I16F16;

/// Window coordinates in 1/16 pixel (Q27.4).
pub type SubPixel = i32;

/// Fraction bits of [`SubPixel`].
pub const SUBPIXEL_BITS: u32 = 4;
/// One pixel in [`SubPixel`] units.
pub const SUBPIXEL_ONE: i32 = 1 << SUBPIXEL_BITS;

/// Window coordinates are kept within `±GUARD_BAND_PX` pixels by clipping, which
/// bounds edge functions (below 2^36) and depth-plane numerators (below 2^43).
pub const GUARD_BAND_PX: i32 = 4096;

/// Fraction bits of window depth.
pub const DEPTH_BITS: u32 = 24;
/// The largest window depth (the far plane).
pub const DEPTH_MAX: u32 = (1 << DEPTH_BITS) - 1;

/// Fraction bits of unit vectors (normals, light direction).
pub const UNIT_BITS: u32 = 14;
/// 1.0 in unit-vector format.
pub const UNIT_ONE: i32 = 1 << UNIT_BITS;

/// Integer square root: the largest `r` with `r * r <= n`.
pub const fn isqrt_u64(n: u64) -> u64 {
    if n < 2 {
        return n;
    }
    // Bit-by-bit method: deterministic, no division, at most 32 iterations.
    let mut rem = n;
    let mut root: u64 = 0;
    let mut bit: u64 = 1 << 62;
    while bit > rem {
        bit >>= 2;
    }
    while bit != 0 {
        if rem >= root + bit {
            rem -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    root
}

/// Q30 fixed-point one.
const Q30: i64 = 1 << 30;

/// Sine and cosine of `x` radians in Q30, for `0 <= x <= pi/4` (x in Q30).
fn sin_cos_octant(x: i64) -> (i64, i64) {
    // Taylor series to the x^11 / x^12 terms: error below 1e-10 on [0, pi/4].
    let x2 = (x * x) >> 30;
    // sin = x (1 - x2/6 (1 - x2/20 (1 - x2/42 (1 - x2/72 (1 - x2/110)))))
    let mut s = Q30 - x2 / 110;
    s = Q30 - ((x2 * s) >> 30) / 72;
    s = Q30 - ((x2 * s) >> 30) / 42;
    s = Q30 - ((x2 * s) >> 30) / 20;
    s = Q30 - ((x2 * s) >> 30) / 6;
    let sin = (x * s) >> 30;
    // cos = 1 - x2/2 (1 - x2/12 (1 - x2/30 (1 - x2/56 (1 - x2/90 (1 - x2/132)))))
    let mut c = Q30 - x2 / 132;
    c = Q30 - ((x2 * c) >> 30) / 90;
    c = Q30 - ((x2 * c) >> 30) / 56;
    c = Q30 - ((x2 * c) >> 30) / 30;
    c = Q30 - ((x2 * c) >> 30) / 12;
    let cos = Q30 - ((x2 * c) >> 30) / 2;
    (sin, cos)
}

/// Sine and cosine of an angle in degrees, as Q30 (`1 << 30` is 1.0).
///
/// Integer-only and deterministic: the same bits on every target.
pub fn sin_cos_deg(deg: Coord) -> (i32, i32) {
    // Reduce to [0, 360) degrees in Q16, then to an octant and an offset within it.
    let full = 360i64 << 16;
    let d = (deg.to_bits() as i64).rem_euclid(full);
    let eighth = 45i64 << 16;
    let octant = d / eighth;
    let rem = d - octant * eighth;
    // Offset in radians, Q30: rem (Q16 degrees) * pi/180.
    // pi/180 in Q46, rounded.
    const PI_OVER_180_Q46: i64 = 1_228_166_276_394;
    // deg_q16 < 45 * 2^16, so the product stays below 2^62.
    let to_rad = |deg_q16: i64| (deg_q16 * PI_OVER_180_Q46 + (1 << 31)) >> 32;
    let (s, c) = match octant {
        0 => sin_cos_octant(to_rad(rem)),
        1 => {
            let (s, c) = sin_cos_octant(to_rad(eighth - rem));
            (c, s)
        }
        2 => {
            let (s, c) = sin_cos_octant(to_rad(rem));
            (c, -s)
        }
        3 => {
            let (s, c) = sin_cos_octant(to_rad(eighth - rem));
            (s, -c)
        }
        4 => {
            let (s, c) = sin_cos_octant(to_rad(rem));
            (-s, -c)
        }
        5 => {
            let (s, c) = sin_cos_octant(to_rad(eighth - rem));
            (-c, -s)
        }
        6 => {
            let (s, c) = sin_cos_octant(to_rad(rem));
            (-c, s)
        }
        _ => {
            let (s, c) = sin_cos_octant(to_rad(eighth - rem));
            (-s, c)
        }
    };
    (s.clamp(-Q30, Q30) as i32, c.clamp(-Q30, Q30) as i32)
}

/// `a * b >> shift` with rounding to nearest, in 64 bits.
#[inline]
pub const fn mul_shift_round(a: i64, b: i64, shift: u32) -> i64 {
    (a * b + (1 << (shift - 1))) >> shift
}

/// Saturates an `i64` into `[-limit, limit]`.
#[inline]
pub const fn saturate(v: i64, limit: i64) -> i64 {
    if v > limit {
        limit
    } else if v < -limit {
        -limit
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isqrt_exact_and_floor() {
        for n in 0u64..10_000 {
            let r = isqrt_u64(n);
            assert!(r * r <= n && (r + 1) * (r + 1) > n, "n={n}");
        }
        assert_eq!(isqrt_u64(u64::MAX), u32::MAX as u64);
        assert_eq!(isqrt_u64(1 << 62), 1 << 31);
    }

    #[test]
    fn sin_cos_matches_float() {
        let mut d = -720.0f64;
        while d <= 720.0 {
            let (s, c) = sin_cos_deg(Coord::from_num(d));
            let r = Coord::from_num(d).to_num::<f64>().to_radians();
            assert!(
                (s as f64 / Q30 as f64 - r.sin()).abs() < 2e-8,
                "sin {d} {} {}",
                s as f64 / Q30 as f64,
                r.sin()
            );
            assert!((c as f64 / Q30 as f64 - r.cos()).abs() < 2e-8, "cos {d}");
            d += 0.37;
        }
    }
}
