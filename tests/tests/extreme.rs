//! Extreme scenes: what a device with no one watching must survive, each checked
//! against a per-sample z-buffer (the oracle of SPEC section 3) or against exact
//! geometry.
//!
//! - depth complexity 1,000: a thousand intersecting full-screen triangles;
//! - triangles a million pixels wide, whole and with an edge across the screen;
//! - triangles crossing the near plane: the camera inside a closed box, and a
//!   ground plane running from behind the camera to the distance;
//! - slivers, needle fans and degenerate triangles;
//! - 5,000 triangles in one band of one row: more than any per-band bin would
//!   hold. The renderer keeps no per-band bin: the active list of a band lives in
//!   the frame workspace's `triangle_order`, which has one entry per triangle of
//!   the scene, so every triangle of the scene can be active in one band and none
//!   is lost. A workspace too small for the scene is an error before any drawing.
//!
//! Every rendering also goes through the buffer's invariant checks of
//! [`checked_render`] (`abuffer_test_support::Checked`, after every insertion
//! and at the end of every band): stored masks pairwise disjoint, no pixel over
//! its budget, every pool slot accounted for.

use abuffer_test_support::{
    first_difference, Checked, FragmentStorage, OwnedObject, OwnedScene, OwnedWorkspace,
    PerSampleZBuffer,
};
use mcu_abuffer::band_buffer::BandBuffer;
use mcu_abuffer::coverage::{CoverageMask, Mask4x4, Mask8x8};
use mcu_abuffer::fixed_point::Coord;
use mcu_abuffer::fragment_buffer::{BufferConfig, OverflowPolicy};
use mcu_abuffer::renderer::{render_frame, RenderError, WorkspacePart};
use mcu_abuffer::scene::{Camera, Scene, Shading, Transform};
use mcu_abuffer::sink::ImageSink;
use mcu_abuffer::stats::FrameStats;
use system_tests::{render, rgb888, Rng, Unit};

// ---------------------------------------------------------------------------------
// Oracle and checks
// ---------------------------------------------------------------------------------

/// The masks stored in every pixel of a finished band, image row by row:
/// `masks[y][x]` lists the pixel's fragments' masks, nearest first.
type Masks<M> = Vec<Vec<Vec<M>>>;

/// Renders through `storage`'s buffer wrapped in [`Checked`], which asserts
/// after every insertion and at the end of every band that stored masks are
/// non-empty and pairwise disjoint, lists are sorted by depth, no pixel holds
/// more than it may, and the pool holds exactly the slots the lists use.
/// Returns the image, the statistics and every pixel's masks.
fn checked_render<M: CoverageMask>(
    scene: &Scene<'_>,
    storage: &mut FragmentStorage<M>,
) -> (Vec<u8>, FrameStats, Masks<M>) {
    let mut masks: Masks<M> = vec![vec![Vec::new(); scene.width as usize]; scene.height as usize];
    let mut buffer = Checked::new(storage.buffer());
    let (image, stats) = render(
        scene,
        &Default::default(),
        &mut buffer,
        |y0, rows, b: &Checked<_>| {
            for row in 0..rows {
                for x in 0..b.width() {
                    masks[(y0 + row) as usize][x as usize] =
                        b.inner().fragments(x, row).map(|f| f.mask).collect();
                }
            }
        },
    );
    (image, stats, masks)
}

/// Renders `scene` through an unlimited A-buffer and a per-sample z-buffer with
/// band height `band` and asserts equal images. Returns the unlimited rendering
/// and the per-sample coverage counts.
fn assert_oracle<M: CoverageMask>(
    scene: &Scene<'_>,
    band: u16,
) -> ((Vec<u8>, FrameStats, Masks<M>), PerSampleZBuffer<M>) {
    let mut storage = FragmentStorage::<M>::unlimited(scene.width, band);
    let unlimited = checked_render(scene, &mut storage);
    let mut reference = PerSampleZBuffer::<M>::new(scene.width, band).counting_hits(scene.height);
    let (expected, _) = render(scene, &Default::default(), &mut reference, |_, _, _| {});
    if let Some((x, y, a, b)) = first_difference(scene.width, &unlimited.0, &expected) {
        panic!("unlimited A-buffer and per-sample z-buffer differ at ({x}, {y}): {a:?} vs {b:?}");
    }
    assert_eq!(unlimited.1.buffer.merges, 0);
    (unlimited, reference)
}

/// A shared buffer with `main`, `extra`, `pool` and band `band`, merging the two farthest.
fn shared<M: CoverageMask>(
    width: u16,
    band: u16,
    main: u8,
    extra: u8,
    pool: usize,
) -> FragmentStorage<M> {
    FragmentStorage::new(
        BufferConfig {
            width,
            band_height: band,
            main_slots: main,
            extra_addresses: extra,
            policy: OverflowPolicy::MergeFarthest,
        },
        pool,
    )
}

// ---------------------------------------------------------------------------------
// Scenes
// ---------------------------------------------------------------------------------

fn c(v: f64) -> Coord {
    Coord::from_num(v)
}

const UP: [Unit; 3] = [Unit::ZERO, Unit::ZERO, Unit::ONE];

/// A camera at `(0, 0, distance)` looking at the origin, y up.
fn camera(distance: f64, fov: f64, near: f64, far: f64) -> Camera {
    Camera {
        eye: [c(0.0), c(0.0), c(distance)],
        target: [Coord::ZERO; 3],
        up: [c(0.0), c(1.0), c(0.0)],
        fov_y_deg: c(fov),
        near: c(near),
        far: c(far),
    }
}

/// An unlit object of independent triangles.
fn triangles(tris: &[[[f64; 3]; 3]], color: [u8; 3]) -> OwnedObject {
    OwnedObject {
        positions: tris.iter().flatten().map(|p| p.map(c)).collect(),
        normals: vec![UP; tris.len() * 3],
        triangles: (0..tris.len() as u32)
            .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
            .collect(),
        color: rgb888(color),
        transform: Transform::default(),
        cull: false,
        openings: None,
        shading: Shading::Unlit,
    }
}

fn scene(width: u16, height: u16, camera: Camera, objects: Vec<OwnedObject>) -> OwnedScene {
    OwnedScene {
        width,
        height,
        background: rgb888([255, 0, 255]),
        camera,
        light: None,
        objects,
        turntable_deg: Coord::ZERO,
    }
}

/// Window position (pixels) of world point `p` for a camera of [`camera`] at
/// `distance` with field `fov` on a `width x height` image (gluPerspective).
fn window(p: [f64; 3], distance: f64, fov: f64, width: u16, height: u16) -> (f64, f64) {
    let f = 1.0 / (fov.to_radians() / 2.0).tan();
    let depth = distance - p[2];
    let aspect = width as f64 / height as f64;
    let x_ndc = f / aspect * p[0] / depth;
    let y_ndc = f * p[1] / depth;
    (
        (x_ndc + 1.0) / 2.0 * width as f64,
        (1.0 - y_ndc) / 2.0 * height as f64,
    )
}

/// Position of sample `s` of pixel `(x, y)` in window pixels.
fn sample_position<M: CoverageMask>(x: u16, y: u16, s: u32) -> (f64, f64) {
    (
        x as f64 + 0.5 + M::offset_x(s % M::COLS) as f64 / 16.0,
        y as f64 + 0.5 + M::offset_y(s / M::COLS) as f64 / 16.0,
    )
}

// ---------------------------------------------------------------------------------
// Tests
// ---------------------------------------------------------------------------------

/// A thousand full-screen triangles through every pixel, tilted at random so that
/// they cut through each other: depth complexity 1,000 everywhere.
#[test]
fn depth_complexity_one_thousand() {
    let (w, h) = (40u16, 30u16);
    let mut rng = Rng::new(1000);
    let mut objects = Vec::new();
    for object in 0..4 {
        // Two objects wound one way, two the other: the buffer tests the
        // triangles that face away against the whole band.
        let corners = if object % 2 == 0 {
            [[-40.0, -40.0], [40.0, -40.0], [0.0, 40.0]]
        } else {
            [[-40.0, -40.0], [0.0, 40.0], [40.0, -40.0]]
        };
        let tris: Vec<[[f64; 3]; 3]> = (0..250)
            .map(|_| {
                let z = rng.float(-4.0, 4.0);
                let (tx, ty) = (rng.float(-0.2, 0.2), rng.float(-0.2, 0.2));
                corners.map(|[x, y]| [x, y, z + tx * x + ty * y])
            })
            .collect();
        objects.push(triangles(&tris, rng.color()));
        // Distinct colors per triangle would need 1,000 objects; four objects of
        // 250 and a per-object color keep the scene small and still show merges.
    }
    let s = scene(w, h, camera(20.0, 30.0, 1.0, 100.0), objects);
    let objects = s.objects();
    let lib = s.scene(&objects);
    let ((_, stats, _), reference) = assert_oracle::<Mask4x4>(&lib, 5);
    let pixels = w as u64 * h as u64;
    // The per-sample reference takes every fragment; the A-buffer skips the
    // triangles that it already hides in a whole band.
    let covered = (0..h).all(|y| (0..w).all(|x| reference.hits(x, y, 0) == 1000));
    assert!(covered, "every triangle covers every pixel");
    assert!(u64::from(stats.buffer.fragments_generated) >= pixels);
    assert!(stats.buffer.triangles_culled > 0);
    // The smallest memory and a typical one: budgets kept, every triangle set up.
    for (main, extra, pool, band) in [(1, 0, 0, 1), (1, 2, 64, 4), (3, 0, 1, 30)] {
        let mut storage = shared::<Mask4x4>(w, band, main, extra, pool);
        let (_, stats, _) = checked_render(&lib, &mut storage);
        assert!(u64::from(stats.buffer.fragments_generated) >= pixels);
        assert!(stats.geometry.triangle_setups as u64 >= 1000 * h.div_ceil(band) as u64);
        assert!(stats.buffer.max_fragments_in_pixel <= (main + extra) as u32);
        assert!(stats.buffer.merges > 0);
    }
}

/// A triangle two million pixels wide that contains the whole view renders like a
/// modest one in the same plane; one whose edge crosses the screen puts that edge
/// where the exact geometry says, to within a sixteenth of a pixel.
#[test]
fn triangles_a_million_pixels_wide() {
    let (w, h) = (64u16, 48u16);
    let (distance, fov) = (10.0, 1.0);
    // At 10 units with a 1-degree field, a pixel is 0.0036 units: 12,000 units
    // are 3.3 million pixels.
    let (x0, _) = window([-12_000.0, 0.0, 0.0], distance, fov, w, h);
    let (x1, _) = window([12_000.0, 0.0, 0.0], distance, fov, w, h);
    assert!(x1 - x0 > 1.0e6, "{}", x1 - x0);
    let cam = camera(distance, fov, 1.0, 100.0);
    let huge = [
        [-12_000.0, -12_000.0, 0.0],
        [12_000.0, -12_000.0, 0.0],
        [0.0, 12_000.0, 0.0],
    ];
    let modest = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]];
    let mut images = Vec::new();
    for tri in [huge, modest] {
        let s = scene(w, h, cam, vec![triangles(&[tri], [10, 200, 30])]);
        let objects = s.objects();
        let lib = s.scene(&objects);
        let ((image, _, masks), _) = assert_oracle::<Mask8x8>(&lib, 7);
        // The huge one is clipped to the guard band and drawn as several pieces;
        // together they cover every sample.
        for m in masks.iter().flatten() {
            assert_eq!(m.iter().fold(Mask8x8::EMPTY, |a, &b| a | b), Mask8x8::FULL);
        }
        assert!(image.chunks_exact(3).all(|p| p == [10, 200, 30]));
        images.push(image);
    }
    assert_eq!(images[0], images[1]);

    // The hypotenuse x + y = 0 runs through the screen's center, corner to corner.
    let edge = [
        [-12_000.0, -12_000.0, 0.0],
        [12_000.0, -12_000.0, 0.0],
        [-12_000.0, 12_000.0, 0.0],
    ];
    let s = scene(w, h, cam, vec![triangles(&[edge], [200, 200, 200])]);
    let objects = s.objects();
    let lib = s.scene(&objects);
    let ((_, stats, masks), _) = assert_oracle::<Mask8x8>(&lib, 48);
    assert!(stats.geometry.triangles_clipped == 1);
    let a = window([-1.0, 1.0, 0.0], distance, fov, w, h);
    let b = window([1.0, -1.0, 0.0], distance, fov, w, h);
    let (nx, ny) = (b.1 - a.1, a.0 - b.0);
    let len = (nx * nx + ny * ny).sqrt();
    let inside_sign = {
        let p = window([-2.0, -2.0, 0.0], distance, fov, w, h);
        ((p.0 - a.0) * nx + (p.1 - a.1) * ny).signum()
    };
    let mut checked = 0;
    for y in 0..h {
        for x in 0..w {
            let mask = masks[y as usize][x as usize]
                .iter()
                .fold(Mask8x8::EMPTY, |a, &b| a | b);
            for s in 0..Mask8x8::SAMPLES {
                let (sx, sy) = sample_position::<Mask8x8>(x, y, s);
                let d = ((sx - a.0) * nx + (sy - a.1) * ny) / len * inside_sign;
                if d.abs() > 1.0 / 16.0 {
                    assert_eq!(
                        mask.get(s),
                        d > 0.0,
                        "sample {s} of ({x}, {y}), {d} px from the edge"
                    );
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > (w as usize * h as usize * 64) * 9 / 10);
}

/// Twelve triangles of a closed box around the camera: every one crosses the near
/// plane or lies behind it, and in every direction every sample is covered
/// exactly once (no crack along a clipped edge, nothing covered twice).
#[test]
fn camera_inside_a_closed_box() {
    let (w, h) = (48u16, 36u16);
    let corners: Vec<[f64; 3]> = (0..8)
        .map(|i| [i & 1, i >> 1 & 1, i >> 2 & 1].map(|b| if b == 1 { 3.0 } else { -3.0 }))
        .collect();
    let faces = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let mut rng = Rng::new(7);
    let objects: Vec<OwnedObject> = faces
        .iter()
        .map(|f| {
            let q = f.map(|i| corners[i]);
            triangles(&[[q[0], q[1], q[2]], [q[0], q[2], q[3]]], rng.color())
        })
        .collect();
    let eye = [0.4, -0.3, 0.2];
    let directions = [
        [1.0, 0.0, 0.0],
        [-1.0, 0.2, 0.0],
        [0.0, 0.0, -1.0],
        [0.1, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [-1.0, -1.0, 0.5],
        [0.3, -1.0, 0.1],
        [0.0, 1.0, 0.01],
    ];
    for dir in directions {
        for fov in [40.0, 120.0, 179.0] {
            let cam = Camera {
                eye: eye.map(c),
                target: [0, 1, 2].map(|i| c(eye[i] + dir[i])),
                up: if dir[1].abs() > 0.9 {
                    [c(1.0), c(0.0), c(0.0)]
                } else {
                    [c(0.0), c(1.0), c(0.0)]
                },
                fov_y_deg: c(fov),
                near: c(0.01),
                far: c(50.0),
            };
            let s = scene(w, h, cam, objects.clone());
            let objs = s.objects();
            let lib = s.scene(&objs);
            let ((_, stats, _), reference) = assert_oracle::<Mask4x4>(&lib, 9);
            assert!(stats.geometry.triangles_clipped > 0);
            for y in 0..h {
                for x in 0..w {
                    for smp in 0..Mask4x4::SAMPLES {
                        let n = reference.hits(x, y, smp);
                        assert_eq!(n, 1, "direction {dir:?}, fov {fov}: sample {smp} of ({x}, {y}) covered {n} times");
                    }
                }
            }
        }
    }
}

/// A ground plane from behind the camera to 500 units ahead: below its far edge
/// every sample is covered once, above it none.
#[test]
fn ground_plane_through_the_near_plane() {
    let (w, h) = (64u16, 48u16);
    let (distance, fov) = (0.0, 60.0);
    let ground = [
        [-400.0, -1.0, 50.0],
        [400.0, -1.0, 50.0],
        [400.0, -1.0, -500.0],
        [-400.0, -1.0, -500.0],
    ];
    let obj = triangles(
        &[
            [ground[0], ground[1], ground[2]],
            [ground[0], ground[2], ground[3]],
        ],
        [90, 160, 60],
    );
    let cam = Camera {
        eye: [c(0.0), c(0.0), c(distance)],
        target: [c(0.0), c(0.0), c(-1.0)],
        up: [c(0.0), c(1.0), c(0.0)],
        fov_y_deg: c(fov),
        near: c(0.05),
        far: c(1000.0),
    };
    let s = scene(w, h, cam, vec![obj]);
    let objs = s.objects();
    let lib = s.scene(&objs);
    let ((_, stats, _), reference) = assert_oracle::<Mask4x4>(&lib, 1);
    assert_eq!(stats.geometry.triangles_clipped, 2);
    // The far edge at z = -500 is seen at depth 500.
    let (_, horizon) = window([0.0, -1.0, -500.0], distance, fov, w, h);
    for y in 0..h {
        for x in 0..w {
            for smp in 0..Mask4x4::SAMPLES {
                let (_, sy) = sample_position::<Mask4x4>(x, y, smp);
                let n = reference.hits(x, y, smp);
                if sy > horizon + 0.1 {
                    assert_eq!(n, 1, "sample {smp} of ({x}, {y}) below the far edge");
                } else if sy < horizon - 0.1 {
                    assert_eq!(n, 0, "sample {smp} of ({x}, {y}) above the far edge");
                }
            }
        }
    }
}

/// Slivers a sixteenth of a pixel wide, a fan of 720 needles around one point,
/// sub-pixel triangles and degenerate ones: no sample is ever covered twice, the
/// fan covers its inside once, degenerate triangles are counted and draw nothing.
#[test]
fn slivers_needles_and_degenerate_triangles() {
    let (w, h) = (48u16, 48u16);
    let (distance, fov) = (10.0, 60.0);
    // One pixel at the origin's depth: 2 * 10 * tan(30) / 48 units.
    let px = 2.0 * distance * (30f64).to_radians().tan() / h as f64;
    let mut tris = Vec::new();
    // Needle fan: 720 triangles around (-4 px, 2 px), radius 18 px.
    let center = [-4.0 * px, 2.0 * px, 0.0];
    let n = 720;
    for i in 0..n {
        let a0 = i as f64 / n as f64 * std::f64::consts::TAU;
        let a1 = (i + 1) as f64 / n as f64 * std::f64::consts::TAU;
        let r = 18.0 * px;
        tris.push([
            center,
            [center[0] + r * a0.cos(), center[1] + r * a0.sin(), 0.0],
            [center[0] + r * a1.cos(), center[1] + r * a1.sin(), 0.0],
        ]);
    }
    let fan = triangles(&tris, [250, 250, 250]);
    // Slivers across the whole screen, 1/16 px wide, and sub-pixel triangles, in front.
    let mut rng = Rng::new(3);
    let mut thin = Vec::new();
    for _ in 0..40 {
        let y = rng.float(-20.0, 20.0) * px;
        let x = rng.float(-20.0, 20.0) * px;
        thin.push([
            [-30.0 * px, y, 1.0],
            [30.0 * px, y + rng.float(-5.0, 5.0) * px, 1.0],
            [-30.0 * px, y + px / 16.0, 1.0],
        ]);
        thin.push([
            [x, -30.0 * px, 1.5],
            [x + px / 16.0, -30.0 * px, 1.5],
            [x + rng.float(-3.0, 3.0) * px, 30.0 * px, 1.5],
        ]);
        let p = [
            rng.float(-20.0, 20.0) * px,
            rng.float(-20.0, 20.0) * px,
            2.0,
        ];
        thin.push([
            p,
            [p[0] + 0.2 * px, p[1], 2.0],
            [p[0], p[1] + 0.3 * px, 2.0],
        ]);
    }
    let slivers = triangles(&thin, [20, 40, 220]);
    // Degenerate: a point, a repeated vertex, three collinear points.
    let degenerate = triangles(
        &[
            [[0.1, 0.1, 0.0]; 3],
            [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
            [[-1.0, -1.0, 0.5], [0.0, 0.0, 0.5], [2.0, 2.0, 0.5]],
        ],
        [255, 0, 0],
    );
    for objects in [vec![fan.clone()], vec![fan, slivers, degenerate]] {
        let s = scene(w, h, camera(distance, fov, 1.0, 100.0), objects.clone());
        let objs = s.objects();
        let lib = s.scene(&objs);
        let ((_, stats, _), reference) = assert_oracle::<Mask4x4>(&lib, 16);
        let (cx, cy) = window(center, distance, fov, w, h);
        for y in 0..h {
            for x in 0..w {
                for smp in 0..Mask4x4::SAMPLES {
                    let hits = reference.hits(x, y, smp);
                    if objects.len() == 1 {
                        assert!(hits <= 1, "sample {smp} of ({x}, {y}) covered {hits} times");
                        let (sx, sy) = sample_position::<Mask4x4>(x, y, smp);
                        // Inside the 720-gon's inscribed circle, with a margin.
                        if ((sx - cx).powi(2) + (sy - cy).powi(2)).sqrt() < 17.9 {
                            assert_eq!(hits, 1, "fan sample {smp} of ({x}, {y})");
                        }
                    }
                }
            }
        }
        if objects.len() == 3 {
            assert_eq!(stats.geometry.triangles_degenerate, 3);
        }
        // The smallest memory copes too.
        let mut storage = shared::<Mask4x4>(w, 1, 1, 0, 0);
        checked_render(&lib, &mut storage);
    }
}

/// 5,000 triangles crossing the single row of a 1-row image, so all are active in
/// one band of one row: the image equals the per-sample z-buffer's, every
/// triangle is set up once, and a workspace one entry short is refused.
#[test]
fn five_thousand_triangles_in_one_row() {
    let (w, h) = (64u16, 1u16);
    let (distance, fov) = (10.0, 60.0);
    // Image height 1: a pixel is the whole 2 * 10 * tan(30) = 11.5 units tall.
    let mut rng = Rng::new(5000);
    let tris: Vec<[[f64; 3]; 3]> = (0..5000)
        .map(|_| {
            let x = rng.float(-55.0, 55.0);
            let z = rng.float(-3.0, 3.0);
            let dx = rng.float(0.05, 6.0);
            [
                [x, -8.0, z + rng.float(-1.0, 1.0)],
                [x + dx, rng.float(-2.0, 2.0), z],
                [x - dx * rng.float(0.0, 1.0), 8.0, z + rng.float(-1.0, 1.0)],
            ]
        })
        .collect();
    let mut objects = Vec::new();
    for chunk in tris.chunks(1250) {
        objects.push(triangles(chunk, rng.color()));
    }
    let s = scene(w, h, camera(distance, fov, 1.0, 100.0), objects);
    let objs = s.objects();
    let lib = s.scene(&objs);
    let ((_, stats, _), _) = assert_oracle::<Mask8x8>(&lib, 1);
    assert_eq!(stats.bands, 1);
    let drawn = stats.geometry.triangles_in
        - stats.geometry.triangles_outside
        - stats.geometry.triangles_degenerate;
    assert!(drawn > 4500, "{drawn}");
    assert_eq!(stats.geometry.triangle_setups, drawn);
    // The smallest memory sets up every triangle too (none is dropped for room).
    let mut storage = shared::<Mask8x8>(w, 1, 1, 0, 0);
    let (_, small, _) = checked_render(&lib, &mut storage);
    assert_eq!(small.geometry.triangle_setups, drawn);

    // The active list is the workspace's triangle order: one entry short is an error.
    let n = lib.triangle_count();
    let mut ws = OwnedWorkspace::for_scene(&lib);
    ws.triangle_order.pop();
    let mut image = vec![0u8; w as usize * 3];
    let mut sink = ImageSink::new(w, &mut image);
    let mut storage = shared::<Mask8x8>(w, 1, 1, 0, 0);
    let err = render_frame(
        &lib,
        &Default::default(),
        &mut ws.borrow(),
        &mut storage.buffer(),
        &mut sink,
        |_, _, _| {},
    )
    .unwrap_err();
    assert_eq!(
        err,
        RenderError::Workspace {
            part: WorkspacePart::Triangles,
            needed: n,
            available: n - 1
        }
    );
    assert_eq!(image, vec![0u8; w as usize * 3], "nothing drawn");
}
