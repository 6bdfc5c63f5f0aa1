//! Clipping a triangle against the view volume: the near and far planes and a
//! guard band around the screen (SPEC section 1, DESIGN "Fixed point and integers").
//!
//! Only triangles that cross a plane come here (the others are accepted or rejected
//! by outcodes). The triangle becomes a convex polygon of at most 9 vertices, cut by
//! each plane in turn with 128-bit intermediate products, so any vertex that a
//! [`crate::geometry::ClipTransform`] can produce is handled without overflow.
//! A triangle crossing the near plane is cut there, never dropped whole.

use crate::fixed_point::GUARD_BAND_PX;
use crate::lighting::ColorQ8;

/// Most vertices a clipped triangle can have (3 + one per plane).
pub const MAX_CLIPPED_VERTICES: usize = 9;

/// A vertex in scaled clip space with the attributes interpolated along with it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClipVertex {
    /// `[X, Y, Zs, w]`: below 2^61 in magnitude from the transform; at most 2^38
    /// once [`clip_triangle`] has shifted the triangle, and so in its output.
    pub clip: [i64; 4],
    /// Color, Q8, `0 ..= 255 * 256` (interpolation stays between two such).
    pub color: ColorQ8,
    /// Normal in the object's model space, Q2.14 (zero when the shading
    /// does not use it); no longer unit length after interpolation.
    pub normal: [i32; 3],
}

/// A clipped polygon.
#[derive(Clone, Copy, Debug)]
pub struct ClippedPolygon {
    /// Vertices; the first `len` are valid.
    pub vertices: [ClipVertex; MAX_CLIPPED_VERTICES],
    /// Number of vertices (0, or 3 and more).
    pub len: usize,
}

/// Signed distance-like value of `c` to plane `plane` (non-negative inside).
#[inline]
fn distance(c: &[i64; 4], plane: usize) -> i128 {
    let [x, y, z, w] = c.map(|v| v as i128);
    let g = GUARD_BAND_PX as i128 * w;
    match plane {
        0 => z,     // near: Zs >= 0
        1 => w - z, // far: Zs <= w
        2 => x + g, // left
        3 => g - x, // right
        4 => y + g, // top
        _ => g - y, // bottom
    }
}

fn lerp(a: i64, b: i64, num: i128, den: i128) -> i64 {
    (a as i128 + (b as i128 - a as i128) * num / den) as i64
}

fn intersect(a: &ClipVertex, b: &ClipVertex, da: i128, db: i128) -> ClipVertex {
    // t = da / (da - db), with da >= 0 > db, so 0 <= t < 1.
    let den = da - db;
    let mut v = ClipVertex::default();
    for i in 0..4 {
        v.clip[i] = lerp(a.clip[i], b.clip[i], da, den);
    }
    for i in 0..3 {
        v.color[i] = lerp(a.color[i] as i64, b.color[i] as i64, da, den) as i32;
        v.normal[i] = lerp(a.normal[i] as i64, b.normal[i] as i64, da, den) as i32;
    }
    v
}

/// Clips triangle `tri` against the planes in `outcode_union` (bits of
/// [`crate::geometry::outcode`]); returns the polygon that remains (possibly empty).
pub fn clip_triangle(tri: &[ClipVertex; 3], outcode_union: u8) -> ClippedPolygon {
    let mut poly = ClippedPolygon {
        vertices: [ClipVertex::default(); MAX_CLIPPED_VERTICES],
        len: 3,
    };
    poly.vertices[..3].copy_from_slice(tri);
    // Clip-space components reach 2^61 (see `ClipTransform`): a guard-band
    // distance (`4096 w + x`) would then need 74 bits, and an interpolation
    // product `(b - a) * distance` more than 128. One right shift common to the
    // three vertices brings every component to at most 2^38, so distances stay below
    // 2^51 and products below 2^91. Scaling all vertices alike moves nothing:
    // clip space is homogeneous, and the interpolation weights are ratios of
    // distances.
    let largest = tri
        .iter()
        .flat_map(|v| v.clip.iter())
        .fold(0u64, |m, c| m | c.unsigned_abs());
    let excess = (64 - largest.leading_zeros()).saturating_sub(38);
    for v in &mut poly.vertices[..3] {
        v.clip = v.clip.map(|c| c >> excess);
    }
    let mut scratch = [ClipVertex::default(); MAX_CLIPPED_VERTICES];
    for plane in 0..6 {
        if outcode_union & (1 << plane) == 0 {
            continue;
        }
        let n = poly.len;
        let mut out = 0;
        for i in 0..n {
            let a = &poly.vertices[i];
            let b = &poly.vertices[(i + 1) % n];
            let da = distance(&a.clip, plane);
            let db = distance(&b.clip, plane);
            if da >= 0 {
                scratch[out] = *a;
                out += 1;
            }
            if (da >= 0) != (db >= 0) && out < MAX_CLIPPED_VERTICES {
                scratch[out] = if da >= 0 {
                    intersect(a, b, da, db)
                } else {
                    intersect(b, a, db, da)
                };
                out += 1;
            }
        }
        poly.vertices[..out].copy_from_slice(&scratch[..out]);
        poly.len = out;
        if out < 3 {
            poly.len = 0;
            break;
        }
    }
    poly
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: i64, y: i64, z: i64, w: i64) -> ClipVertex {
        ClipVertex {
            clip: [x, y, z, w],
            color: [0; 3],
            normal: [0; 3],
        }
    }

    #[test]
    fn near_plane_cut_keeps_the_front_part() {
        // One vertex behind the near plane (Zs < 0): the triangle becomes a quad.
        let tri = [
            v(0, 0, 100, 1000),
            v(500, 0, 100, 1000),
            v(0, 500, -100, 900),
        ];
        let p = clip_triangle(&tri, 1);
        assert_eq!(p.len, 4);
        for vert in &p.vertices[..p.len] {
            assert!(vert.clip[2] >= 0);
        }
    }

    #[test]
    fn all_behind_is_empty_and_inside_is_unchanged() {
        let behind = [v(0, 0, -1, 10), v(1, 0, -1, 10), v(0, 1, -1, 10)];
        assert_eq!(clip_triangle(&behind, 1).len, 0);
        let inside = [v(0, 0, 1, 10), v(1, 0, 1, 10), v(0, 1, 1, 10)];
        let p = clip_triangle(&inside, 63);
        assert_eq!(p.len, 3);
        assert_eq!(&p.vertices[..3], &inside);
    }
}
