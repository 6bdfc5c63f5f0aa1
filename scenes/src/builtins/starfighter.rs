//! A small X-winged starfighter made of closed, interpenetrating parts.

use super::geom::{length, Mat3, MeshBuilder, Placement};
use super::shapes::{cylinder, icosphere, rect_at, tapered_box};
use crate::scene_desc::MeshData;

/// Largest distance of any vertex from the origin.
const FIT_RADIUS: f32 = 1.5;

/// Wing tilt out of the horizontal plane, degrees.
const WING_TILT: f32 = 15.0;

/// The starfighter, nose towards -Z, +Y up, within radius 1.5 of the origin.
///
/// Parts: a fuselage (a box and a tapered nose), a canopy and a droid dome
/// (squashed spheres), four wings in an X (thin tapered boxes through the
/// fuselage, tilted by +-15 degrees), an engine at each wing root (intake,
/// body and nozzle cylinders, crossed by the wing) and a laser cannon at each
/// wing tip (housing, barrel and muzzle cylinders). Every part is closed and
/// has outward normals; the parts deliberately pass through each other.
pub(super) fn starfighter() -> MeshData {
    let mut b = MeshBuilder::new();
    let origin = Placement::at([0.0; 3]);

    // Fuselage: a slightly tapered box from the cockpit back, and a long
    // nose that tapers to a blunt tip and overlaps the box.
    b.append(
        &tapered_box(
            rect_at(0.0, 0.0, 0.15, 0.13, -0.4),
            rect_at(0.0, 0.0, 0.17, 0.15, 0.75),
        ),
        &origin,
    );
    b.append(
        &tapered_box(
            rect_at(0.0, -0.03, 0.035, 0.03, -1.45),
            rect_at(0.0, 0.0, 0.15, 0.13, -0.3),
        ),
        &origin,
    );
    // Canopy: an elongated dome sitting in the top of the fuselage.
    b.append(
        &icosphere(2),
        &Placement::at([0.0, 0.12, -0.3]).scaled([0.1, 0.08, 0.3]),
    );
    // Droid dome behind the canopy.
    b.append(
        &icosphere(1),
        &Placement::at([0.0, 0.14, 0.2]).scaled([0.075, 0.075, 0.075]),
    );

    // The wing shape, spanning +X from the fuselage axis, thin in Y, with
    // the chord along Z (leading edge towards -Z), tapering towards the tip.
    let wing = tapered_box(
        [
            [0.0, -0.02, -0.05],
            [0.0, -0.02, 0.55],
            [0.0, 0.02, 0.55],
            [0.0, 0.02, -0.05],
        ],
        [
            [1.05, -0.012, 0.15],
            [1.05, -0.012, 0.5],
            [1.05, 0.012, 0.5],
            [1.05, 0.012, 0.15],
        ],
    );
    // Engine: intake ring, body, nozzle; cannon: housing, barrel, muzzle.
    let engine = [
        cylinder(0.1, -0.42, -0.26, 16),
        cylinder(0.09, -0.3, 0.62, 16),
        cylinder(0.075, 0.6, 0.78, 16),
    ];
    let cannon = [
        cylinder(0.035, -0.1, 0.45, 12),
        cylinder(0.018, -0.95, 0.0, 12),
        cylinder(0.027, -1.05, -0.9, 12),
    ];

    for (side, up) in [(1.0f32, 1.0f32), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
        // Right wings point along +X, left ones along -X; a rotation by
        // 180 degrees (not a mirror) keeps the windings.
        let angle = if side > 0.0 {
            up * WING_TILT
        } else {
            180.0 - up * WING_TILT
        };
        let turn = Mat3::rot_z(angle);
        b.append(&wing, &origin.rotated(turn));

        // The engine sits at the wing root, pushed away from the other wing
        // of its side but still crossed by this one.
        let root = turn.apply([0.3, 0.0, 0.0]);
        let engine_at = [root[0], root[1] + up * 0.055, 0.0];
        for part in &engine {
            b.append(part, &Placement::at(engine_at));
        }
        // The cannon runs along the wing tip.
        let tip = turn.apply([1.06, 0.0, 0.0]);
        for part in &cannon {
            b.append(part, &Placement::at([tip[0], tip[1], 0.1]));
        }
    }

    let mut mesh = b.finish();
    let radius = mesh
        .positions
        .iter()
        .map(|&p| length(p))
        .fold(0.0f32, f32::max);
    if radius > FIT_RADIUS {
        let k = FIT_RADIUS / radius;
        for p in &mut mesh.positions {
            *p = p.map(|c| c * k);
        }
    }
    mesh
}
