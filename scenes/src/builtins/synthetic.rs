//! Synthetic scenes of controlled complexity, for measuring the A-buffer.
//!
//! - `layers:N:DEPTH:SEED`: `N` random triangles, tilted and interpenetrating,
//!   their centroids spread uniformly over the square `[-1, 1]^2` and their areas
//!   adding up to `DEPTH` times the square's area, so the expected depth
//!   complexity is `DEPTH` everywhere in the square except within a triangle's
//!   size of its border (where triangles stick out). The same seed gives the
//!   same scene on every machine.
//! - `grid:N`: a wavy height field cut into `N x N` quads, seen at a slant, so
//!   that many triangles of one surface fall into each pixel.
//! - `knot:SEGMENTS:SIDES`: a (2, 3) torus knot, a tube that passes in front of
//!   itself three times; `2 * SEGMENTS * SIDES` triangles (131,072 by default).
//!
//! Every parameter after the name is optional; missing ones take the defaults
//! below.

use super::geom::{add, cross, dot, mul, normalize, sub, tri_normal, MeshBuilder, V3};
use super::random::SplitMix64;
use crate::scene_desc::{MeshData, ObjectDesc};

/// Triangles of `layers` when none is given.
pub const DEFAULT_LAYER_TRIANGLES: u32 = 400;
/// Target depth complexity of `layers` when none is given.
pub const DEFAULT_LAYER_DEPTH: f32 = 4.0;
/// Seed of `layers` when none is given.
pub const DEFAULT_LAYER_SEED: u64 = 1;
/// Most triangles `layers` accepts.
pub const MAX_LAYER_TRIANGLES: u32 = 1_000_000;
/// Largest target depth complexity `layers` accepts.
pub const MAX_LAYER_DEPTH: f32 = 256.0;
/// Quads per side of `grid` when none is given (131,072 triangles).
pub const DEFAULT_GRID_QUADS: u32 = 256;
/// Most quads per side `grid` accepts.
pub const MAX_GRID_QUADS: u32 = 1024;
/// Segments along `knot` when none is given.
pub const DEFAULT_KNOT_SEGMENTS: u32 = 1024;
/// Segments around the tube of `knot` when none is given.
pub const DEFAULT_KNOT_SIDES: u32 = 64;
/// Most segments along `knot`.
pub const MAX_KNOT_SEGMENTS: u32 = 8192;
/// Most segments around the tube of `knot`.
pub const MAX_KNOT_SIDES: u32 = 256;
/// Colors (and objects) of a `layers` scene: triangle `i` belongs to object
/// `i % LAYER_COLORS`.
pub const LAYER_COLORS: u32 = 12;

/// A synthetic scene's objects and the direction (objects to eye) it is seen from.
pub(super) struct SyntheticScene {
    pub(super) objects: Vec<ObjectDesc>,
    pub(super) toward_eye: V3,
}

/// Splits `name:a:b:c` into the name and its parameters.
fn split_params(name: &str) -> (&str, Vec<&str>) {
    let mut parts = name.split(':');
    let base = parts.next().unwrap_or("");
    (base, parts.collect())
}

/// Parameter `i` of `params` as a `T` within `range`, or `default` when absent.
fn param<T: std::str::FromStr + PartialOrd>(
    params: &[&str],
    i: usize,
    default: T,
    range: std::ops::RangeInclusive<T>,
) -> Option<T> {
    match params.get(i) {
        None => Some(default),
        Some(text) => {
            let v: T = text.trim().parse().ok()?;
            range.contains(&v).then_some(v)
        }
    }
}

/// The synthetic scene called `name`, `None` when the name is not one, has more
/// parameters than it takes, or a parameter is out of range.
pub(super) fn synthetic_scene(name: &str) -> Option<SyntheticScene> {
    let (base, params) = split_params(name);
    match base {
        "layers" if params.len() <= 3 => {
            let n = param(&params, 0, DEFAULT_LAYER_TRIANGLES, 1..=MAX_LAYER_TRIANGLES)?;
            let depth = param(&params, 1, DEFAULT_LAYER_DEPTH, 0.001..=MAX_LAYER_DEPTH)?;
            let seed = param(&params, 2, DEFAULT_LAYER_SEED, 0..=u64::MAX)?;
            Some(SyntheticScene {
                objects: layers(n, depth, seed),
                toward_eye: [0.0, 0.0, 1.0],
            })
        }
        "grid" | "knot" => Some(SyntheticScene {
            objects: vec![ObjectDesc {
                mesh_name: format!("builtin:{name}"),
                mesh: synthetic_mesh(name)?,
                color: if base == "grid" {
                    [110, 190, 150]
                } else {
                    [205, 140, 90]
                },
                position: [0.0; 3],
                rotation_deg: [0.0; 3],
                scale: 1.0,
                // The grid is an open surface; the knot is closed.
                cull_backfaces: base == "knot",
                bounds_solids: false,
                shading: None,
            }],
            toward_eye: if base == "grid" {
                [0.0, 0.8, 1.0]
            } else {
                [0.25, 0.35, 1.0]
            },
        }),
        _ => None,
    }
}

/// The single-mesh synthetic shapes by name: `grid[:N]` and `knot[:SEGMENTS[:SIDES]]`.
pub(super) fn synthetic_mesh(name: &str) -> Option<MeshData> {
    let (base, params) = split_params(name);
    match base {
        "grid" if params.len() <= 1 => {
            let n = param(&params, 0, DEFAULT_GRID_QUADS, 1..=MAX_GRID_QUADS)?;
            Some(wavy_grid(n))
        }
        "knot" if params.len() <= 2 => {
            let segments = param(&params, 0, DEFAULT_KNOT_SEGMENTS, 3..=MAX_KNOT_SEGMENTS)?;
            let sides = param(&params, 1, DEFAULT_KNOT_SIDES, 3..=MAX_KNOT_SIDES)?;
            Some(torus_knot(segments, sides))
        }
        _ => None,
    }
}

/// Half the side of the square the layers cover.
const LAYER_HALF_SIDE: f32 = 1.0;
/// Layer planes sit at depths within this distance of `z = 0`.
const LAYER_DEPTH_SPREAD: f32 = 0.25;
/// Largest slope of a layer plane (dz/dx and dz/dy), so planes cross each other.
const LAYER_MAX_SLOPE: f32 = 0.2;

/// `n` random triangles with centroids uniform over the square `[-1, 1]^2` and
/// areas adding up to `depth` times its area, grouped by color into up to
/// [`LAYER_COLORS`] objects.
fn layers(n: u32, depth: f32, seed: u64) -> Vec<ObjectDesc> {
    let mut rng = SplitMix64(seed);
    let side = 2.0 * LAYER_HALF_SIDE;
    let target_area = depth * side * side / n as f32;
    let groups = n.min(LAYER_COLORS);
    let mut builders: Vec<MeshBuilder> = (0..groups).map(|_| MeshBuilder::new()).collect();
    let colors: Vec<[u8; 3]> = (0..groups)
        .map(|_| {
            [
                rng.uniform(50.0, 250.0) as u8,
                rng.uniform(50.0, 250.0) as u8,
                rng.uniform(50.0, 250.0) as u8,
            ]
        })
        .collect();
    for i in 0..n {
        // A random shape: three points near a circle, stretched along a random axis.
        let spin = rng.uniform(0.0, std::f32::consts::TAU);
        let stretch = rng.uniform(1.0, 3.0);
        let axis = rng.uniform(0.0, std::f32::consts::PI);
        let (sa, ca) = axis.sin_cos();
        let mut shape = [[0.0f32; 2]; 3];
        for (k, p) in shape.iter_mut().enumerate() {
            let angle = spin + k as f32 * std::f32::consts::TAU / 3.0 + rng.uniform(-0.5, 0.5);
            let (s, c) = angle.sin_cos();
            // Stretch along `axis`: rotate into the axis frame, scale, rotate back.
            let (u, v) = (c * ca + s * sa, -c * sa + s * ca);
            let u = u * stretch;
            *p = [u * ca - v * sa, u * sa + v * ca];
        }
        let area = 0.5
            * ((shape[1][0] - shape[0][0]) * (shape[2][1] - shape[0][1])
                - (shape[2][0] - shape[0][0]) * (shape[1][1] - shape[0][1]))
                .abs();
        let scale = (target_area / area.max(1e-6)).sqrt();
        let centroid = [
            (shape[0][0] + shape[1][0] + shape[2][0]) / 3.0,
            (shape[0][1] + shape[1][1] + shape[2][1]) / 3.0,
        ];
        let local: [[f32; 2]; 3] =
            shape.map(|p| [(p[0] - centroid[0]) * scale, (p[1] - centroid[1]) * scale]);
        // Uniform centroids give a uniform expected coverage inside the square.
        let center = [
            rng.uniform(-LAYER_HALF_SIDE, LAYER_HALF_SIDE),
            rng.uniform(-LAYER_HALF_SIDE, LAYER_HALF_SIDE),
        ];
        let z0 = rng.uniform(-LAYER_DEPTH_SPREAD, LAYER_DEPTH_SPREAD);
        let slope = [
            rng.uniform(-LAYER_MAX_SLOPE, LAYER_MAX_SLOPE),
            rng.uniform(-LAYER_MAX_SLOPE, LAYER_MAX_SLOPE),
        ];
        let corners: [V3; 3] = local.map(|p| {
            [
                center[0] + p[0],
                center[1] + p[1],
                z0 + slope[0] * p[0] + slope[1] * p[1],
            ]
        });
        let mut normal = tri_normal(corners[0], corners[1], corners[2]);
        if normal[2] < 0.0 {
            normal = mul(normal, -1.0);
        }
        let b = &mut builders[(i % groups) as usize];
        let first = b.next_index();
        for c in corners {
            b.vertex(c, normal);
        }
        b.tri_facing(first, first + 1, first + 2, normal);
    }
    builders
        .into_iter()
        .zip(colors)
        .enumerate()
        .map(|(g, (b, color))| ObjectDesc {
            mesh_name: format!("builtin:layers:{n}:{depth}:{seed}/{g}"),
            mesh: b.finish(),
            color,
            position: [0.0; 3],
            rotation_deg: [0.0; 3],
            scale: 1.0,
            cull_backfaces: false,
            bounds_solids: false,
            shading: None,
        })
        .collect()
}

/// Height of the wavy grid at `(x, z)` and its gradient.
fn wave(x: f32, z: f32) -> (f32, f32, f32) {
    use std::f32::consts::PI;
    let (fx, fz, amp) = (2.5 * PI, 2.0 * PI, 0.08);
    let h = amp * (fx * x).sin() * (fz * z).cos();
    let dx = amp * fx * (fx * x).cos() * (fz * z).cos();
    let dz = -amp * fz * (fx * x).sin() * (fz * z).sin();
    (h, dx, dz)
}

/// The square `[-1, 1]^2` of the XZ plane as a height field cut into `n x n`
/// quads (two triangles each), normals from the analytic gradient, facing +Y.
fn wavy_grid(n: u32) -> MeshData {
    let mut b = MeshBuilder::new();
    let side = n + 1;
    for j in 0..side {
        let z = -1.0 + 2.0 * j as f32 / n as f32;
        for i in 0..side {
            let x = -1.0 + 2.0 * i as f32 / n as f32;
            let (h, dx, dz) = wave(x, z);
            b.vertex([x, h, z], [-dx, 1.0, -dz]);
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * side + i;
            let (right, below) = (a + 1, a + side);
            // Counter-clockwise seen from +Y (x right, z towards the viewer).
            b.tri(a, below, right);
            b.tri(right, below, below + 1);
        }
    }
    b.finish()
}

/// A point of the (2, 3) torus knot at parameter `t`, scaled to lie within radius 1
/// together with its tube.
fn knot_point(t: f32) -> V3 {
    let (p, q) = (2.0f32, 3.0f32);
    let r = 2.0 + (q * t).cos();
    mul(
        [r * (p * t).cos(), r * (p * t).sin(), -(q * t).sin()],
        KNOT_SCALE,
    )
}

/// Tube radius of the knot before scaling.
const KNOT_TUBE: f32 = 0.4;
/// Scale that brings the knot and its tube within radius 1.
const KNOT_SCALE: f32 = 1.0 / (3.0 + KNOT_TUBE);

/// A tube of `sides` segments around the (2, 3) torus knot cut into `segments`
/// rings; normals point away from the tube's center line.
fn torus_knot(segments: u32, sides: u32) -> MeshData {
    let mut b = MeshBuilder::new();
    let mut normals: Vec<V3> = Vec::with_capacity((segments * sides) as usize);
    let tau = std::f32::consts::TAU;
    let h = tau / segments as f32 * 0.25;
    for s in 0..segments {
        let t = tau * s as f32 / segments as f32;
        let center = knot_point(t);
        let ahead = knot_point(t + h);
        let behind = knot_point(t - h);
        let tangent = normalize(sub(ahead, behind)).unwrap_or([1.0, 0.0, 0.0]);
        // The curvature direction (towards the center of the osculating circle),
        // made exactly perpendicular to the tangent.
        let bend = sub(add(ahead, behind), mul(center, 2.0));
        let normal =
            normalize(sub(bend, mul(tangent, dot(bend, tangent)))).unwrap_or([0.0, 0.0, 1.0]);
        let binormal = cross(tangent, normal);
        for k in 0..sides {
            let phi = tau * k as f32 / sides as f32;
            let (sp, cp) = phi.sin_cos();
            let out = add(mul(normal, cp), mul(binormal, sp));
            b.vertex(add(center, mul(out, KNOT_TUBE * KNOT_SCALE)), out);
            normals.push(out);
        }
    }
    let ring = |s: u32, k: u32| (s % segments) * sides + (k % sides);
    for s in 0..segments {
        for k in 0..sides {
            let (a, c) = (ring(s, k), ring(s + 1, k));
            let (a2, c2) = (ring(s, k + 1), ring(s + 1, k + 1));
            b.tri_facing(a, c, c2, outward(&normals, [a, c, c2]));
            b.tri_facing(a, c2, a2, outward(&normals, [a, c2, a2]));
        }
    }
    b.finish()
}

/// The sum of a triangle's vertex normals (its outside).
fn outward(normals: &[V3], triangle: [u32; 3]) -> V3 {
    triangle
        .iter()
        .fold([0.0; 3], |acc, &i| add(acc, normals[i as usize]))
}

#[cfg(test)]
mod tests {
    use super::super::geom::length;
    use super::*;
    use crate::builtins::builtin_scene;

    /// Sum of the triangle areas of `mesh`.
    fn mesh_area(mesh: &MeshData) -> f64 {
        mesh.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
                0.5 * length(cross(sub(b, a), sub(c, a))) as f64
            })
            .sum()
    }

    #[test]
    fn layers_are_deterministic_for_a_seed() {
        let a = builtin_scene("layers:300:3:7", 120, 100).unwrap();
        let b = builtin_scene("layers:300:3:7", 120, 100).unwrap();
        assert_eq!(a, b);
        let c = builtin_scene("layers:300:3:8", 120, 100).unwrap();
        assert_ne!(a.objects, c.objects);
        // Defaults fill in missing parameters.
        assert_eq!(
            builtin_scene("layers", 64, 64).unwrap(),
            builtin_scene(
                &format!(
                    "layers:{DEFAULT_LAYER_TRIANGLES}:{DEFAULT_LAYER_DEPTH}:{DEFAULT_LAYER_SEED}"
                ),
                64,
                64
            )
            .unwrap()
        );
    }

    #[test]
    fn layers_have_the_requested_count_and_depth_complexity() {
        for (n, depth) in [(20u32, 1.0f32), (50, 2.0), (400, 4.0), (2000, 8.0)] {
            let scene = builtin_scene(&format!("layers:{n}:{depth}:3"), 64, 64).unwrap();
            assert_eq!(scene.objects.len() as u32, n.min(LAYER_COLORS));
            let triangles: usize = scene.objects.iter().map(|o| o.mesh.triangles.len()).sum();
            assert_eq!(triangles as u32, n);
            // Projected onto the XY plane, areas add up to depth x the square's area.
            let mut area = 0.0f64;
            for o in &scene.objects {
                for t in &o.mesh.triangles {
                    let [a, b, c] = t.map(|i| o.mesh.positions[i as usize]);
                    let cross_z = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
                    // Counter-clockwise seen from the camera (+Z).
                    assert!(cross_z > 0.0);
                    area += 0.5 * cross_z as f64;
                    let centroid = [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0];
                    assert!(centroid[0].abs() <= 1.0 + 1e-5 && centroid[1].abs() <= 1.0 + 1e-5);
                }
            }
            let mean_depth = area / 4.0;
            assert!(
                (mean_depth - depth as f64).abs() < 1e-3 * depth as f64,
                "{n} triangles: depth {mean_depth}, wanted {depth}"
            );
        }
    }

    #[test]
    fn bad_parameters_are_rejected() {
        for bad in [
            "layers:0",
            "layers:x",
            "layers:10:0",
            "layers:10:2:-1",
            "layers:1:2:3:4",
            "grid:0",
            "grid:2000",
            "grid:4:4",
            "knot:2",
            "knot:16:2",
            "knot:16:16:16",
        ] {
            assert!(builtin_scene(bad, 32, 32).is_none(), "{bad}");
        }
    }

    #[test]
    fn grid_and_knot_sizes_and_orientation() {
        let grid = synthetic_mesh("grid:10").unwrap();
        assert_eq!(grid.triangles.len(), 200);
        assert_eq!(grid.positions.len(), 121);
        for t in &grid.triangles {
            let [a, b, c] = t.map(|i| grid.positions[i as usize]);
            assert!(tri_normal(a, b, c)[1] > 0.0, "grid triangle faces down");
        }
        let dense = synthetic_mesh("grid").unwrap();
        assert_eq!(dense.triangles.len() as u32, 2 * DEFAULT_GRID_QUADS.pow(2));
        let knot = synthetic_mesh("knot").unwrap();
        assert_eq!(
            knot.triangles.len() as u32,
            2 * DEFAULT_KNOT_SEGMENTS * DEFAULT_KNOT_SIDES
        );
        assert!(knot.triangles.len() > 100_000);
        let small = synthetic_mesh("knot:96:12").unwrap();
        assert_eq!(small.triangles.len(), 2 * 96 * 12);
        for mesh in [&small, &knot] {
            for p in &mesh.positions {
                assert!(length(*p) <= 1.0 + 1e-5);
            }
            // Every triangle faces the way its vertex normals point (outward).
            for t in &mesh.triangles {
                let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
                let n = t
                    .iter()
                    .fold([0.0; 3], |acc, &i| add(acc, mesh.normals[i as usize]));
                assert!(dot(tri_normal(a, b, c), n) > 0.0);
            }
        }
        // A closed tube: its area is close to that of a straight tube of the knot's length.
        let length_of_curve: f64 = (0..4096)
            .map(|i| {
                let t0 = std::f32::consts::TAU * i as f32 / 4096.0;
                let t1 = std::f32::consts::TAU * (i + 1) as f32 / 4096.0;
                length(sub(knot_point(t1), knot_point(t0))) as f64
            })
            .sum();
        let tube = std::f64::consts::TAU * (KNOT_TUBE * KNOT_SCALE) as f64 * length_of_curve;
        let area = mesh_area(&knot);
        assert!((area / tube - 1.0).abs() < 0.05, "{area} vs {tube}");
    }
}
