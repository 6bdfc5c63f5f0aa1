//! `overdraw:N:SEED`: many closed objects (cubes and coarse spheres) scattered
//! through a deep box in front of the camera, so that most pixels are covered
//! by several of them. Their triangles are large (tens to thousands of pixels
//! at 800x600), the case where a test of a whole triangle against the depth
//! buffer can save per-pixel work. The same seed gives the same scene on every
//! machine.

use super::random::SplitMix64;
use super::shapes::{cube, icosphere};
use crate::scene_desc::ObjectDesc;

/// Objects when none is given.
pub const DEFAULT_OVERDRAW_OBJECTS: u32 = 160;
/// Seed when none is given.
pub const DEFAULT_OVERDRAW_SEED: u64 = 7;
/// Most objects accepted.
pub const MAX_OVERDRAW_OBJECTS: u32 = 10_000;

/// Half extents of the box the object centers fill (x, y) and its depth range (z).
const HALF_WIDTH: f32 = 2.2;
const HALF_HEIGHT: f32 = 1.6;
const Z_RANGE: (f32, f32) = (-6.0, 0.0);
/// Range of object scales (cube half side, sphere radius).
const SCALE_RANGE: (f32, f32) = (0.25, 0.6);
/// Icosphere level of the spheres (80 triangles).
const SPHERE_LEVEL: u32 = 1;

/// The objects of `overdraw[:N[:SEED]]` (`params` are the parts after the
/// name), `None` for bad parameters.
pub(super) fn overdraw_objects(params: &[&str]) -> Option<Vec<ObjectDesc>> {
    if params.len() > 2 {
        return None;
    }
    let n = match params.first() {
        None => DEFAULT_OVERDRAW_OBJECTS,
        Some(p) => p.trim().parse().ok()?,
    };
    let seed = match params.get(1) {
        None => DEFAULT_OVERDRAW_SEED,
        Some(p) => p.trim().parse().ok()?,
    };
    if !(1..=MAX_OVERDRAW_OBJECTS).contains(&n) {
        return None;
    }
    let mut rng = SplitMix64(seed);
    let cube_mesh = cube();
    let sphere_mesh = icosphere(SPHERE_LEVEL);
    let objects = (0..n)
        .map(|_| {
            let is_cube = !rng.next_u64().is_multiple_of(3);
            let position = [
                rng.uniform(-HALF_WIDTH, HALF_WIDTH),
                rng.uniform(-HALF_HEIGHT, HALF_HEIGHT),
                rng.uniform(Z_RANGE.0, Z_RANGE.1),
            ];
            let rotation_deg = [
                rng.uniform(0.0, 360.0),
                rng.uniform(0.0, 360.0),
                rng.uniform(0.0, 360.0),
            ];
            let color = [
                rng.uniform(60.0, 250.0) as u8,
                rng.uniform(60.0, 250.0) as u8,
                rng.uniform(60.0, 250.0) as u8,
            ];
            let scale = rng.uniform(SCALE_RANGE.0, SCALE_RANGE.1);
            let (mesh_name, mesh) = if is_cube {
                ("builtin:cube".to_string(), cube_mesh.clone())
            } else {
                (
                    format!("builtin:sphere:{SPHERE_LEVEL}"),
                    sphere_mesh.clone(),
                )
            };
            ObjectDesc {
                mesh_name,
                mesh,
                color,
                position,
                rotation_deg,
                scale,
                // Closed shapes: faces turned away are hidden anyway.
                cull_backfaces: true,
                bounds_solids: false,
                shading: None,
            }
        })
        .collect();
    Some(objects)
}
