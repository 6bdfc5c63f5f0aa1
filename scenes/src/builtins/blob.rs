//! A smooth, lumpy, closed surface like a pebble or a potato: a dense closed
//! mesh for timing the renderers on ordinary solid geometry.
//!
//! The surface is a sphere pushed in and out along each direction `u` from the
//! origin: the point at `r(u) u`, with
//!
//! ```text
//! r(u) = 1 + STRETCH x^2 - FLATTEN y^2 + sum over lumps of h_i ((1 + u . c_i) / 2)^k_i
//! ```
//!
//! for `u = (x, y, z)` of unit length: a slight stretch along X and
//! flattening along Y, and ten lumps. Each lump is a smooth bump (`h_i > 0`)
//! or dent (`h_i < 0`) centered on the direction `c_i`, the narrower the
//! higher its power `k_i` (from the center to half height: about 30 degrees
//! for power 10, 22 degrees for power 18). Since `r` stays positive, the
//! surface is the graph of a function over the sphere of directions and never
//! passes through itself.
//!
//! It is tessellated as a latitude-longitude grid from pole to pole (the
//! poles on the Y axis), each ring of latitude turned by half a segment from
//! the one above it so that the triangles between rings are isosceles rather
//! than right-angled, and closed by a fan at each pole. Neighbouring
//! triangles share their vertices, so the mesh is watertight. Normals are
//! those of the smooth surface, computed from the gradient of `r`.
//!
//! Only additions, multiplications, divisions and square roots are used,
//! evaluated in the order written and each rounded correctly (IEEE 754), so
//! the mesh is the same bit for bit on every machine. The platform's `sin`
//! and `cos` may differ in the last place, so the grid's angles come from
//! [`sin_cos_turns`] instead.

use super::geom::{add, dot, mul, normalize, sub, MeshBuilder, V3};
use crate::scene_desc::MeshData;

/// Vertices on each ring of latitude.
const SEGMENTS: u32 = 50;

/// Bands of latitude from pole to pole; there are `BANDS - 1` rings.
const BANDS: u32 = 38;

/// Vertices: the rings and the two poles.
const VERTICES: u32 = SEGMENTS * (BANDS - 1) + 2;

/// Triangles: two per segment between neighbouring rings, one per segment in
/// each polar fan (3,700).
const TRIANGLES: u32 = 2 * SEGMENTS * (BANDS - 1);

/// Stretch along X: the radius grows by this much towards +-X.
const STRETCH: f32 = 0.08;

/// Flattening along Y: the radius shrinks by this much towards +-Y.
const FLATTEN: f32 = 0.12;

/// A bump or dent: its height (negative for a dent), the direction of its
/// center (any length) and its power (higher is narrower).
struct Lump {
    height: f32,
    toward: V3,
    power: u32,
}

/// The lumps, spread around so that every side has some.
const LUMPS: [Lump; 10] = [
    Lump {
        height: 0.15,
        toward: [0.6, 0.7, 0.4],
        power: 12,
    },
    Lump {
        height: -0.2,
        toward: [-0.2, 0.35, 0.9],
        power: 14,
    },
    Lump {
        height: 0.09,
        toward: [-0.8, -0.3, 0.5],
        power: 10,
    },
    Lump {
        height: -0.16,
        toward: [0.3, -0.8, -0.5],
        power: 12,
    },
    Lump {
        height: 0.15,
        toward: [-0.3, 0.45, -0.85],
        power: 12,
    },
    Lump {
        height: -0.18,
        toward: [0.95, 0.1, -0.3],
        power: 16,
    },
    Lump {
        height: 0.12,
        toward: [0.5, -0.4, 0.75],
        power: 16,
    },
    Lump {
        height: -0.16,
        toward: [-0.7, 0.6, 0.1],
        power: 18,
    },
    Lump {
        height: 0.12,
        toward: [0.1, -0.95, 0.2],
        power: 14,
    },
    Lump {
        height: -0.14,
        toward: [-0.6, -0.5, -0.6],
        power: 14,
    },
];

/// The blob: [`VERTICES`] vertices, [`TRIANGLES`] triangles, centered on the
/// origin with every vertex at a distance between 0.75 and 1.15 from it.
pub(super) fn blob() -> MeshData {
    let lumps: Vec<(f32, V3, u32)> = LUMPS
        .iter()
        .map(|l| {
            let center = normalize(l.toward).expect("lump direction");
            (l.height, center, l.power)
        })
        .collect();
    let mut b = MeshBuilder::new();
    let north = surface_vertex(&mut b, &lumps, [0.0, 1.0, 0.0]);
    for ring in 1..BANDS {
        let (sin_t, cos_t) = sin_cos_turns(ring, 2 * BANDS);
        for j in 0..SEGMENTS {
            // In half segments, so that each ring is turned by half a segment
            // from the one above it.
            let (sin_p, cos_p) = sin_cos_turns(2 * j + ring, 2 * SEGMENTS);
            // Increasing longitude turns counter-clockwise seen from +Y.
            let u = [sin_t * cos_p, cos_t, -sin_t * sin_p];
            surface_vertex(&mut b, &lumps, u);
        }
    }
    let south = surface_vertex(&mut b, &lumps, [0.0, -1.0, 0.0]);
    debug_assert_eq!(b.next_index(), VERTICES);

    // Vertex `j` (taken around) of ring `ring` (1..BANDS).
    let at = |ring: u32, j: u32| 1 + (ring - 1) * SEGMENTS + j % SEGMENTS;
    for j in 0..SEGMENTS {
        b.tri(north, at(1, j), at(1, j + 1));
    }
    for ring in 1..BANDS - 1 {
        // Vertex j of the lower ring lies halfway between vertices j and
        // j + 1 of the upper one.
        for j in 0..SEGMENTS {
            let (a0, a1) = (at(ring, j), at(ring, j + 1));
            let (b0, b1) = (at(ring + 1, j), at(ring + 1, j + 1));
            b.tri(a0, b0, a1);
            b.tri(b0, b1, a1);
        }
    }
    for j in 0..SEGMENTS {
        b.tri(south, at(BANDS - 1, j + 1), at(BANDS - 1, j));
    }
    let mesh = b.finish();
    debug_assert_eq!(mesh.triangles.len(), TRIANGLES as usize);
    mesh
}

/// Adds the surface point in direction `u` (about unit length) with its
/// normal, and returns its index.
fn surface_vertex(b: &mut MeshBuilder, lumps: &[(f32, V3, u32)], u: V3) -> u32 {
    let u = normalize(u).expect("direction");
    let (r, gradient) = radius(lumps, u);
    // The surface p(u) = r(u) u has a normal along u - g / r, where g is the
    // part of the gradient of r along the sphere (perpendicular to u).
    let along_sphere = sub(gradient, mul(u, dot(gradient, u)));
    let normal = sub(u, mul(along_sphere, 1.0 / r));
    b.vertex(mul(u, r), normal)
}

/// `r(u)` and the gradient of the same polynomial in `(x, y, z)`.
fn radius(lumps: &[(f32, V3, u32)], u: V3) -> (f32, V3) {
    let [x, y, _] = u;
    let mut r = 1.0 + STRETCH * x * x - FLATTEN * y * y;
    let mut gradient = [2.0 * STRETCH * x, -2.0 * FLATTEN * y, 0.0];
    for &(height, center, power) in lumps {
        let w = (1.0 + dot(u, center)) * 0.5;
        // w^(power - 1) by repeated multiplication (powi may round
        // differently from one build to another).
        let mut w_less = 1.0f32;
        for _ in 1..power {
            w_less *= w;
        }
        r += height * w_less * w;
        gradient = add(gradient, mul(center, height * power as f32 * w_less * 0.5));
    }
    (r, gradient)
}

/// Sine and cosine of the angle `turns / parts` of a full turn, rounded to
/// `f32`, the same on every machine: the nearest quarter turn is taken off
/// with integers, the rest (within 45 degrees) goes through the Taylor series
/// in `f64`. Multiples of a quarter turn come out exact.
fn sin_cos_turns(turns: u32, parts: u32) -> (f32, f32) {
    let parts = i64::from(parts.max(1));
    let k = i64::from(turns) % parts;
    // The nearest quarter turn, and what is left: rest / (4 parts) of a
    // turn, within an eighth of a turn.
    let quarter = (8 * k + parts).div_euclid(2 * parts);
    let rest = 4 * k - quarter * parts;
    let x = std::f64::consts::TAU * rest as f64 / (4 * parts) as f64;
    // Terms x^n / n!: odd n for the sine, even n for the cosine. For
    // |x| <= pi / 4 the last ones are far below f64 precision.
    let (mut sin, mut cos) = (0.0f64, 0.0f64);
    let mut term = 1.0f64;
    for n in 0..24u32 {
        match n % 4 {
            0 => cos += term,
            1 => sin += term,
            2 => cos -= term,
            _ => sin -= term,
        }
        term *= x / f64::from(n + 1);
    }
    let (sin, cos) = (sin as f32, cos as f32);
    match quarter % 4 {
        0 => (sin, cos),
        1 => (cos, -sin),
        2 => (-sin, -cos),
        _ => (-cos, sin),
    }
}

#[cfg(test)]
mod tests {
    use crate::openings::mesh_openings;

    use super::super::geom::{length, tri_normal};
    use super::*;

    #[test]
    fn blob_counts() {
        let mesh = blob();
        let count = mesh.triangles.len();
        assert!((3600..=3800).contains(&count), "{count} triangles");
        assert_eq!(count, TRIANGLES as usize);
        assert_eq!(count, 3700);
        assert_eq!(mesh.positions.len(), VERTICES as usize);
        assert_eq!(mesh.positions.len(), 1852);
        assert_eq!(mesh.normals.len(), mesh.positions.len());
    }

    #[test]
    fn blob_is_closed_and_consistently_wound() {
        let mesh = blob();
        // No openings: each edge is shared by exactly two triangles that run
        // along it in opposite directions, and the surface encloses a
        // positive volume.
        assert_eq!(mesh_openings(&mesh), Ok(vec![]));
        // A closed surface of genus 0 that uses every vertex: V - E + F = 2.
        let mut used = vec![false; mesh.positions.len()];
        for t in &mesh.triangles {
            for &i in t {
                used[i as usize] = true;
            }
        }
        assert!(used.iter().all(|&u| u), "unused vertex");
        let edges = mesh.triangles.len() * 3 / 2;
        let euler = mesh.positions.len() as i64 - edges as i64 + mesh.triangles.len() as i64;
        assert_eq!(euler, 2);
    }

    #[test]
    fn blob_triangles_are_proper_and_face_outward() {
        let mesh = blob();
        let count = mesh.positions.len() as u32;
        let mut smallest = f32::MAX;
        for t in &mesh.triangles {
            assert!(t.iter().all(|&i| i < count), "{t:?} out of range");
            assert!(t[0] != t[1] && t[1] != t[2] && t[2] != t[0], "{t:?}");
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            let n = tri_normal(a, b, c);
            smallest = smallest.min(length(n) * 0.5);
            // Counter-clockwise seen from outside, and seen from the center
            // every triangle shows its back: the mesh projects one to one
            // onto the sphere of directions, so it cannot pass through
            // itself.
            let centroid = mul(add(add(a, b), c), 1.0 / 3.0);
            let n = normalize(n).expect("triangle normal");
            let centroid_dir = normalize(centroid).expect("centroid direction");
            assert!(dot(n, centroid_dir) > 0.7, "{t:?} tilted too far");
        }
        // The slivers at the poles are the smallest: still far from zero.
        assert!(smallest > 2e-4, "smallest triangle area {smallest}");
    }

    #[test]
    fn blob_normals_are_unit_and_outward() {
        let mesh = blob();
        // Area-weighted face normals at each vertex, to compare with the
        // analytic ones.
        let mut faces = vec![[0.0f32; 3]; mesh.positions.len()];
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            let n = tri_normal(a, b, c);
            for &i in t {
                faces[i as usize] = add(faces[i as usize], n);
            }
        }
        let center = [0.0; 3];
        let mut worst = 1.0f32;
        for ((&p, &n), &f) in mesh.positions.iter().zip(&mesh.normals).zip(&faces) {
            assert!(n.iter().all(|c| c.is_finite()), "normal {n:?}");
            assert!((length(n) - 1.0).abs() < 1e-5, "normal {n:?} not unit");
            assert!(dot(n, sub(p, center)) > 0.0, "normal {n:?} at {p:?}");
            worst = worst.min(dot(n, normalize(f).expect("face normal sum")));
        }
        assert!(worst > 0.998, "analytic and face normals differ: {worst}");
    }

    #[test]
    fn blob_stays_between_radii() {
        let mesh = blob();
        for p in &mesh.positions {
            let r = length(*p);
            assert!((0.75..=1.15).contains(&r), "{p:?} at radius {r}");
        }
        // Lumpy, not a sphere: the radius spans most of that range.
        let radii: Vec<f32> = mesh.positions.iter().map(|&p| length(p)).collect();
        let lo = radii.iter().copied().fold(f32::MAX, f32::min);
        let hi = radii.iter().copied().fold(f32::MIN, f32::max);
        assert!(hi - lo > 0.3, "radii {lo}..{hi}");
    }

    #[test]
    fn blob_is_deterministic() {
        let a = blob();
        let b = blob();
        let bits = |m: &MeshData| -> Vec<u32> {
            m.positions
                .iter()
                .chain(&m.normals)
                .flatten()
                .map(|c| c.to_bits())
                .collect()
        };
        assert_eq!(a, b);
        assert_eq!(bits(&a), bits(&b));
    }

    #[test]
    fn sin_cos_turns_matches_the_library() {
        assert_eq!(sin_cos_turns(0, 8), (0.0, 1.0));
        assert_eq!(sin_cos_turns(2, 8), (1.0, 0.0));
        assert_eq!(sin_cos_turns(4, 8).1, -1.0);
        assert_eq!(sin_cos_turns(6, 8), (-1.0, 0.0));
        assert_eq!(sin_cos_turns(9, 8), sin_cos_turns(1, 8));
        for parts in [7u32, 76, 100, 360] {
            for turns in 0..=parts {
                let angle = std::f64::consts::TAU * f64::from(turns) / f64::from(parts);
                let (s, c) = sin_cos_turns(turns, parts);
                assert!((f64::from(s) - angle.sin()).abs() < 1e-7, "{turns}/{parts}");
                assert!((f64::from(c) - angle.cos()).abs() < 1e-7, "{turns}/{parts}");
            }
        }
    }
}
