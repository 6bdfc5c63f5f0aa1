//! Rendering through host-sim: extreme geometry, sinks and the command line.

use host_sim::builtins::{builtin_mesh, builtin_scene};
use host_sim::convert::to_fixed;
use host_sim::render::{render, render_frames, Grid, Method, RenderConfig};
use host_sim::scene_desc::{CameraDesc, MeshData, ObjectDesc, SceneDesc};

fn camera() -> CameraDesc {
    CameraDesc {
        eye: [0.0, 0.0, 4.0],
        target: [0.0; 3],
        up: [0.0, 1.0, 0.0],
        fov_y_deg: 40.0,
        near: 0.5,
        far: 20.0,
    }
}

fn object(mesh: MeshData, position: [f32; 3], scale: f32) -> ObjectDesc {
    ObjectDesc {
        mesh_name: "test".into(),
        mesh,
        color: [200, 100, 50],
        position,
        rotation_deg: [0.0; 3],
        scale,
        cull_backfaces: false,
        bounds_solids: false,
        shading: None,
    }
}

fn scene(objects: Vec<ObjectDesc>) -> SceneDesc {
    SceneDesc {
        width: 64,
        height: 48,
        background: [1, 2, 3],
        camera: camera(),
        light: None,
        objects,
    }
}

fn triangle(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> MeshData {
    MeshData {
        positions: vec![a, b, c],
        normals: vec![[0.0, 0.0, 1.0]; 3],
        triangles: vec![[0, 1, 2]],
    }
}

fn background_pixels(rgb: &[u8]) -> usize {
    rgb.chunks_exact(3).filter(|p| *p == [1, 2, 3]).count()
}

fn run(desc: &SceneDesc, method: Method) -> host_sim::render::RenderOutput {
    let scene = to_fixed(desc).expect("scene converts");
    render(
        &scene,
        &RenderConfig {
            method,
            ..Default::default()
        },
        0.0,
    )
    .expect("renders")
}

#[test]
fn object_behind_the_camera_draws_nothing() {
    let desc = scene(vec![object(
        builtin_mesh("cube").unwrap(),
        [0.0, 0.0, 8.0],
        1.0,
    )]);
    for method in [Method::Shared, Method::Unlimited, Method::Zbuffer] {
        let out = run(&desc, method);
        assert_eq!(background_pixels(&out.rgb), 64 * 48);
        assert_eq!(out.stats.buffer.fragments_generated, 0);
    }
}

#[test]
fn huge_triangles_far_outside_the_view_are_clipped_without_overflow() {
    // A triangle thousands of units wide, crossing the near plane and the guard band,
    // covers the whole screen exactly once.
    // Its plane is at z = 3 on the view axis (1 unit ahead of the eye); the third
    // vertex is behind the eye.
    let big = triangle(
        [-9000.0, -9000.0, 0.0],
        [9000.0, -9000.0, 0.0],
        [0.0, 9000.0, 6.0],
    );
    let desc = scene(vec![object(big, [0.0; 3], 1.0)]);
    for method in [Method::Shared, Method::Unlimited, Method::Zbuffer] {
        let out = run(&desc, method);
        assert_eq!(background_pixels(&out.rgb), 0, "{method:?}");
        assert!(out.stats.geometry.triangles_clipped == 1);
        assert!(
            out.rgb.chunks_exact(3).all(|p| p == [200, 100, 50]),
            "{method:?}"
        );
    }
    // Entirely off to the side: nothing drawn.
    let away = triangle([5000.0, 0.0, 0.0], [5001.0, 0.0, 0.0], [5000.0, 1.0, 0.0]);
    let out = run(&scene(vec![object(away, [0.0; 3], 1.0)]), Method::Shared);
    assert_eq!(background_pixels(&out.rgb), 64 * 48);
}

#[test]
fn near_plane_crossing_is_clipped_not_dropped() {
    // A floor running from behind the camera to far in front: the visible part is drawn.
    let floor = MeshData {
        positions: vec![
            [-5.0, -1.0, 10.0],
            [5.0, -1.0, 10.0],
            [5.0, -1.0, -15.0],
            [-5.0, -1.0, -15.0],
        ],
        normals: vec![[0.0, 1.0, 0.0]; 4],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    };
    let out = run(&scene(vec![object(floor, [0.0; 3], 1.0)]), Method::Shared);
    assert_eq!(out.stats.geometry.triangles_clipped, 2);
    // The lower half of the image shows the floor.
    let w = 64;
    let bottom_row = &out.rgb[(47 * w) * 3..(48 * w) * 3];
    assert!(bottom_row.chunks_exact(3).all(|p| p == [200, 100, 50]));
    let top_row = &out.rgb[..w * 3];
    assert!(top_row.chunks_exact(3).all(|p| p == [1, 2, 3]));
}

#[test]
fn camera_inside_a_mesh_sees_its_inside() {
    let sphere = builtin_mesh("sphere").unwrap();
    let desc = scene(vec![object(sphere, [0.0, 0.0, 4.0], 3.0)]);
    let out = run(&desc, Method::Shared);
    assert_eq!(background_pixels(&out.rgb), 0);
}

#[test]
fn zero_area_triangles_are_ignored() {
    let flat = triangle([0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [2.0, 2.0, 0.0]);
    let out = run(&scene(vec![object(flat, [0.0; 3], 1.0)]), Method::Shared);
    assert_eq!(out.stats.geometry.triangles_degenerate, 1);
    assert_eq!(background_pixels(&out.rgb), 64 * 48);
}

#[test]
fn coordinates_beyond_the_fixed_point_range_are_an_error() {
    let far = triangle([1e9, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
    let err = to_fixed(&scene(vec![object(far, [0.0; 3], 1.0)])).unwrap_err();
    assert!(
        err.contains("object 0") && err.contains("coordinate"),
        "{err}"
    );
}

#[test]
fn unlimited_is_the_same_for_every_band_height_and_grid_runs() {
    let desc = builtin_scene("spheres", 96, 80).unwrap();
    let fixed = to_fixed(&desc).unwrap();
    for grid in [Grid::G4x4, Grid::G8x4, Grid::G8x8] {
        let base = RenderConfig {
            method: Method::Unlimited,
            grid,
            band: 80,
            ..Default::default()
        };
        let full = render(&fixed, &base, 10.0).unwrap();
        assert_eq!(full.stats.buffer.merges, 0);
        for band in [1, 7, 16] {
            let banded = render(&fixed, &RenderConfig { band, ..base }, 10.0).unwrap();
            assert!(banded.rgb == full.rgb, "{grid:?} band {band}");
        }
    }
}

#[test]
fn shared_with_room_for_every_sample_equals_unlimited() {
    let desc = builtin_scene("starfighter", 96, 96).unwrap();
    let fixed = to_fixed(&desc).unwrap();
    let unlimited = render(
        &fixed,
        &RenderConfig {
            method: Method::Unlimited,
            ..Default::default()
        },
        0.0,
    )
    .unwrap();
    let roomy = RenderConfig {
        method: Method::Shared,
        main: 2,
        extra: 14,
        pool: Some(96 * 16 * 14),
        ..Default::default()
    };
    let shared = render(&fixed, &roomy, 0.0).unwrap();
    assert_eq!(shared.stats.buffer.merges, 0);
    assert!(shared.rgb == unlimited.rgb);
}

#[test]
fn the_same_input_gives_the_same_image_twice() {
    // The teapot is two-sided and its first band holds back faces: the
    // buffer's per-frame state (the strip summary) is exercised from row 0.
    for scene in host_sim::builtins::BUILTIN_SCENES {
        same_image_twice(scene, 33.0);
    }
}

fn same_image_twice(scene: &str, turn: f32) {
    let fixed = to_fixed(&builtin_scene(scene, 48, 48).unwrap()).unwrap();
    for (method, band) in [
        (Method::Shared, 16),
        (Method::Shared, 4),
        (Method::SplitBands, 4),
        (Method::FixedDiscard, 16),
        (Method::MergeClosest, 4),
        (Method::Zbuffer, 16),
    ] {
        let cfg = RenderConfig {
            method,
            band,
            ..Default::default()
        };
        // Both frames through the same band buffer and frame workspace: what
        // the first leaves there must not change the second.
        let frames = render_frames(&fixed, &cfg, &[turn, turn]).unwrap();
        let (a, b) = (&frames[0], &frames[1]);
        let what = format!("{scene} at {turn} degrees, {method:?} in bands of {band}");
        assert!(a.rgb == b.rgb, "{what}: images differ");
        assert_eq!(a.stats, b.stats, "{what}");
        assert!(a.stored_per_pixel == b.stored_per_pixel, "{what}");
        assert!(a.generated_per_pixel == b.generated_per_pixel, "{what}");
    }
}

#[test]
fn skipping_faces_after_a_hidden_triangle_changes_no_image() {
    // After a triangle the buffer hid, the renderer tests the next face of
    // the viewer against the whole band and skips it when hidden. The test
    // is exact: the image must be the one every face rasterized in full
    // gives, with no more fragments generated; on the spheres, whose
    // surfaces hide one another, it must skip some.
    for scene in host_sim::builtins::BUILTIN_SCENES {
        let fixed = to_fixed(&builtin_scene(scene, 96, 96).unwrap()).unwrap();
        for (method, band) in [
            (Method::Unlimited, 16),
            (Method::Shared, 16),
            (Method::SplitBands, 4),
            (Method::FixedDiscard, 6),
            (Method::MergeClosest, 4),
            (Method::Zbuffer, 24),
        ] {
            let cfg = RenderConfig {
                method,
                band,
                ..Default::default()
            };
            let every = RenderConfig {
                rasterize_every_front_face: true,
                ..cfg
            };
            let turns = [0.0, 100.0];
            let skipping = render_frames(&fixed, &cfg, &turns).unwrap();
            let full = render_frames(&fixed, &every, &turns).unwrap();
            for (i, (a, b)) in skipping.iter().zip(&full).enumerate() {
                let what = format!("{scene} frame {i}, {method:?} in bands of {band}");
                assert!(a.rgb == b.rgb, "{what}: images differ");
                let (made, all) = (
                    a.stats.buffer.fragments_generated,
                    b.stats.buffer.fragments_generated,
                );
                assert!(made <= all, "{what}: {made} fragments, {all} in full");
                if *scene == "spheres" {
                    assert!(made < all, "{what}: nothing skipped ({made} fragments)");
                }
            }
        }
    }
}

#[test]
fn command_line_renders_a_builtin_scene() {
    let dir = abuffer_test_support::ScratchDir::new("host-sim-cli");
    let png = dir.join("teapot.png");
    let json = dir.join("stats.json");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .args([
            "render", "--scene", "teapot", "--width", "64", "--height", "64", "--out",
        ])
        .arg(&png)
        .arg("--stats-json")
        .arg(&json)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let stdout = String::from_utf8_lossy(&status.stdout);
    assert!(
        stdout.contains("pool peak") && stdout.contains("merges"),
        "{stdout}"
    );
    let image = host_sim::image_io::read_png(&png).unwrap();
    assert_eq!((image.width, image.height), (64, 64));
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(stats["triangles"], 4096);
    // A bad scene name is a clear error.
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .args(["render", "--scene", "nosuch", "--out"])
        .arg(dir.join("x.png"))
        .output()
        .unwrap();
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("built-in"));
}

/// A reader that closes the pipe before reading (`host-sim ... | head -1`)
/// ends the program with the shell's status for a closed pipe, not a panic.
#[test]
fn a_closed_output_pipe_ends_the_program_quietly() {
    let dir = abuffer_test_support::ScratchDir::new("host-sim-pipe");
    let png = dir.join("a.png");
    let made = std::process::Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .args([
            "render", "--scene", "spheres", "--width", "16", "--height", "16",
        ])
        .arg("--out")
        .arg(&png)
        .output()
        .unwrap();
    assert!(made.status.success());
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let compare = std::process::Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .arg("compare")
        .args([&png, &png])
        .stdout(writer)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&compare.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(compare.status.code(), Some(141), "{stderr}");
}
