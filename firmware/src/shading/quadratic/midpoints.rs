//! The lit edge midpoints: the three samples besides the vertices.

use super::QuadraticSamples;
use crate::fixed_point::wide_mul_add;
use crate::lighting::{color_q8, normalize_unit, rgb888_rounded, ColorQ8};
use crate::shading::TriangleLighting;

/// `2^30 / sqrt(1 + (k + 0.5) / 16)`, `k = 0..48`: where [`rsqrt_q28`] starts.
pub(super) const RSQRT_START: [u32; 48] = [
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
pub(super) fn rsqrt_q28(x: u64) -> u64 {
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
    let (x, extra) = scaled_into_one_to_four(len2);
    // Below 2^31 (see `rsqrt_q28`): with the sum's components (words) one
    // 32 x 32-bit product each.
    let y = rsqrt_q28(x) as i32;
    // Each component is `(c y + 2^(s - 1)) >> s` for `s = 30 - extra`,
    // rounded: the same quotient as the high word of `c 2^(32 - s) y + 2^31`
    // (numerator and divisor scaled by `2^(32 - s)`), one multiply-accumulate
    // and no 64-bit shift by a variable amount. The scaled component is a
    // word: `c² <= len2 < 2^31` puts `|c|` below 2^15.5, and `32 - s` is at
    // most 3.
    let up = (2 + extra) as u32;
    Some(sum.map(|c| (wide_mul_add(1 << 31, (c as i32) << up, y) >> 32) as i32))
}

/// A squared length `len2` of `[2^26, 2^31)` (Q28) scaled by a power of
/// four into `[1, 4)`, with that power's exponent negated: `(len2 4^extra,
/// extra)`.
#[inline]
pub(super) fn scaled_into_one_to_four(len2: u64) -> (u64, i32) {
    if len2 >= 1 << 30 {
        (len2 >> 2, -1)
    } else if len2 >= 1 << 28 {
        (len2, 0)
    } else {
        (len2 << 2, 1)
    }
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
    color_q8(rgb888_rounded(c))
}

/// Lights the three edge midpoints of a triangle whose vertex normals are
/// `lighting.normals` (rounded to 8 bits like the vertex colors); a midpoint
/// between opposite normals takes the mean of its two vertex colors
/// `vertex_colors`.
pub fn light_midpoints(lighting: &TriangleLighting, vertex_colors: &[ColorQ8; 3]) -> [ColorQ8; 3] {
    core::array::from_fn(|k| {
        let (i, j) = (k, (k + 1) % 3);
        match midpoint_normal(&lighting.normals[i], &lighting.normals[j]) {
            Some(n) => {
                // `round_to_8_bits` of the lit color.
                let [r, g, b] = lighting.light.shade_rounded(&n, lighting.base);
                [(r as i32) << 8, (g as i32) << 8, (b as i32) << 8]
            }
            None => core::array::from_fn(|ch| {
                ((vertex_colors[i][ch] as i64 + vertex_colors[j][ch] as i64) / 2) as i32
            }),
        }
    })
}
