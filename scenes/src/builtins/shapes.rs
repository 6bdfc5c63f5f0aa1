//! Simple closed shapes: cube, icosphere, tapered boxes and cylinders.

use std::collections::HashMap;

use super::geom::{add, dot, mul, normalize, tri_normal, MeshBuilder, V3};
use crate::scene_desc::MeshData;

/// The cube [-1, 1]^3: six faces of four vertices each, face normals.
pub(super) fn cube() -> MeshData {
    let mut b = MeshBuilder::new();
    for axis in 0..3 {
        for sign in [1.0f32, -1.0] {
            let mut n = [0.0; 3];
            n[axis] = sign;
            // Two tangents with u x v = n, so the corner order below runs
            // counter-clockwise around n.
            let mut u = [0.0; 3];
            u[(axis + 1) % 3] = 1.0;
            let mut v = [0.0; 3];
            v[(axis + 2) % 3] = sign;
            let corner = |su: f32, sv: f32| add(n, add(mul(u, su), mul(v, sv)));
            let first = b.vertex(corner(-1.0, -1.0), n);
            b.vertex(corner(1.0, -1.0), n);
            b.vertex(corner(1.0, 1.0), n);
            b.vertex(corner(-1.0, 1.0), n);
            b.tri(first, first + 1, first + 2);
            b.tri(first, first + 2, first + 3);
        }
    }
    b.finish()
}

/// A unit icosphere: an icosahedron whose triangles are split in four
/// `level` times, every new vertex pushed out to the sphere. Normals are the
/// positions; `20 * 4^level` triangles.
pub(super) fn icosphere(level: u32) -> MeshData {
    let g = (1.0 + 5.0f32.sqrt()) / 2.0;
    let corners: [V3; 12] = [
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ];
    const FACES: [[u32; 3]; 20] = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let mut points: Vec<V3> = corners
        .iter()
        .map(|&c| normalize(c).expect("icosahedron corner"))
        .collect();
    // Wind every face outward (a face of a convex solid around the origin
    // faces outward when its normal agrees with its centroid).
    let mut faces: Vec<[u32; 3]> = FACES
        .iter()
        .map(|&[a, b, c]| {
            let (pa, pb, pc) = (points[a as usize], points[b as usize], points[c as usize]);
            if dot(tri_normal(pa, pb, pc), add(add(pa, pb), pc)) < 0.0 {
                [a, c, b]
            } else {
                [a, b, c]
            }
        })
        .collect();
    for _ in 0..level {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, points: &mut Vec<V3>| -> u32 {
            let key = (a.min(b), a.max(b));
            *midpoints.entry(key).or_insert_with(|| {
                let m = add(points[a as usize], points[b as usize]);
                points.push(normalize(m).expect("midpoint of a sphere edge"));
                points.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for &[a, b, c] in &faces {
            let ab = midpoint(a, b, &mut points);
            let bc = midpoint(b, c, &mut points);
            let ca = midpoint(c, a, &mut points);
            next.push([a, ab, ca]);
            next.push([b, bc, ab]);
            next.push([c, ca, bc]);
            next.push([ab, bc, ca]);
        }
        faces = next;
    }
    MeshData {
        normals: points.clone(),
        positions: points,
        triangles: faces,
    }
}

/// A closed six-faced solid between two quadrilateral cross-sections (a box,
/// or a box tapered towards one end). `near` and `far` list their corners in
/// the same order around the solid; every face gets its own four vertices
/// with the face normal.
pub(super) fn tapered_box(near: [V3; 4], far: [V3; 4]) -> MeshData {
    let inside = mul(
        near.iter()
            .chain(&far)
            .fold([0.0; 3], |acc, &p| add(acc, p)),
        1.0 / 8.0,
    );
    let mut b = MeshBuilder::new();
    b.flat_face(&near, inside);
    b.flat_face(&far, inside);
    for k in 0..4 {
        let l = (k + 1) % 4;
        b.flat_face(&[near[k], near[l], far[l], far[k]], inside);
    }
    b.finish()
}

/// A box-shaped section for [`tapered_box`]: the rectangle of half-width
/// `hw` and half-height `hh` around `(cx, cy)` at depth `z`.
pub(super) fn rect_at(cx: f32, cy: f32, hw: f32, hh: f32, z: f32) -> [V3; 4] {
    [
        [cx - hw, cy - hh, z],
        [cx + hw, cy - hh, z],
        [cx + hw, cy + hh, z],
        [cx - hw, cy + hh, z],
    ]
}

/// A closed cylinder of `radius` around the Z axis from `z0` to `z1`
/// (`z0 < z1`), with `segments` sides: smooth side normals, flat caps (a fan
/// around a center vertex). `4 * segments` triangles.
pub(super) fn cylinder(radius: f32, z0: f32, z1: f32, segments: u32) -> MeshData {
    let mut b = MeshBuilder::new();
    let ring: Vec<(f32, f32)> = (0..segments)
        .map(|k| {
            let a = std::f32::consts::TAU * k as f32 / segments as f32;
            (a.cos(), a.sin())
        })
        .collect();
    // Side: two vertices per direction, normal pointing away from the axis.
    let side = b.next_index();
    for &(c, s) in &ring {
        b.vertex([radius * c, radius * s, z0], [c, s, 0.0]);
        b.vertex([radius * c, radius * s, z1], [c, s, 0.0]);
    }
    // Vertex order so far: (0, z0), (0, z1), (1, z0), (1, z1), ...
    for k in 0..segments {
        let l = (k + 1) % segments;
        let (k0, k1) = (side + 2 * k, side + 2 * k + 1);
        let (l0, l1) = (side + 2 * l, side + 2 * l + 1);
        let (c, s) = ring[k as usize];
        let out = [c, s, 0.0];
        b.tri_facing(k0, l0, l1, out);
        b.tri_facing(k0, l1, k1, out);
    }
    // Caps.
    for (z, n) in [(z0, [0.0, 0.0, -1.0]), (z1, [0.0, 0.0, 1.0])] {
        let center = b.vertex([0.0, 0.0, z], n);
        let first = center + 1;
        for &(c, s) in &ring {
            b.vertex([radius * c, radius * s, z], n);
        }
        for k in 0..segments {
            let l = (k + 1) % segments;
            b.tri_facing(center, first + k, first + l, n);
        }
    }
    b.finish()
}
