//! The z-buffer modes of SPEC section 7: the hierarchical z-buffer is exact,
//! midpoint subdivision is exact where its test cannot be fooled, counters are
//! deterministic, and the command line takes the subdivision options.

use host_sim::builtins::{builtin_mesh, builtin_scene, BUILTIN_LIGHT, BUILTIN_SCENES};
use host_sim::convert::{to_fixed, FixedScene};
use host_sim::render::{
    render, render_frames, Method, MidpointSettings, RenderConfig, RenderOutput,
};
use host_sim::scene_desc::{CameraDesc, MeshData, ObjectDesc, SceneDesc, ShadingDesc};
use host_sim::zbuffer_table::{differing_pixels, markdown_table, measure_table};

fn run(scene: &FixedScene, method: Method, band: u16, midpoint: MidpointSettings) -> RenderOutput {
    render(
        scene,
        &RenderConfig {
            method,
            band,
            midpoint,
            ..RenderConfig::default()
        },
        0.0,
    )
    .expect("renders")
}

fn differing(a: &RenderOutput, b: &RenderOutput) -> u64 {
    differing_pixels(&a.rgb, &b.rgb).unwrap()
}

#[test]
fn hierarchical_zbuffer_equals_zbuffer_on_every_builtin_scene() {
    for name in BUILTIN_SCENES {
        let scene = to_fixed(&builtin_scene(name, 160, 120).unwrap()).unwrap();
        for band in [16, 120, 7] {
            let plain = run(&scene, Method::Zbuffer, band, MidpointSettings::default());
            let hiz = run(
                &scene,
                Method::ZbufferHiz,
                band,
                MidpointSettings::default(),
            );
            assert_eq!(differing(&hiz, &plain), 0, "{name}, band {band}");
            assert!(hiz.rgb == plain.rgb, "{name}, band {band}");
            let (p, h) = (&plain.stats.buffer, &hiz.stats.buffer);
            assert_eq!(
                h.fragments_stored, p.fragments_stored,
                "{name}, band {band}"
            );
            // Both decide about whole triangles before their pixels (per
            // band in the plain one, for the faces turned away of two-sided
            // objects; per tile in the hierarchical one) and count those
            // comparisons apart.
            assert!(p.depth_tests > 0 && h.depth_tests > 0);
            assert!(h.culling_depth_tests > 0);
            if *name == "teapot" {
                assert!(p.culling_depth_tests > 0, "band {band}");
            }
        }
    }
}

/// A mesh of one triangle with its own normals (not all parallel, so lit
/// shading is not a plane).
fn triangle(corners: [[f32; 3]; 3], normals: [[f32; 3]; 3]) -> MeshData {
    MeshData {
        positions: corners.to_vec(),
        normals: normals.to_vec(),
        triangles: vec![[0, 1, 2]],
    }
}

fn object(mesh: MeshData, position: [f32; 3], scale: f32, shading: ShadingDesc) -> ObjectDesc {
    ObjectDesc {
        mesh_name: "test".into(),
        mesh,
        color: [200, 150, 90],
        position,
        rotation_deg: [0.0; 3],
        scale,
        cull_backfaces: false,
        bounds_solids: false,
        shading: Some(shading),
    }
}

/// A full-screen occluder drawn first; then objects entirely behind it (cubes
/// and spheres in any order) and camera-facing triangles in front of it, each
/// nearer than everything drawn before it: they start lower on the screen
/// (triangles are visited by first row) and come closer to the camera. Some
/// reach past the screen's edge, so their pieces there are drawn with tests.
fn occluder_scene(width: u32, height: u32) -> SceneDesc {
    let tilted = [[0.3, 0.2, 1.0], [-0.4, 0.1, 1.0], [0.1, -0.5, 1.0]];
    let flat = [[0.0, 0.0, 1.0]; 3];
    let quad = MeshData {
        positions: vec![
            [-20.0, -20.0, 0.0],
            [20.0, -20.0, 0.0],
            [20.0, 20.0, 0.0],
            [-20.0, 20.0, 0.0],
        ],
        normals: vec![[0.0, 0.0, 1.0]; 4],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    };
    let mut objects = vec![object(quad, [0.0, 0.0, -1.0], 1.0, ShadingDesc::Flat)];
    // Behind the occluder.
    let cube = builtin_mesh("cube").unwrap();
    let sphere = builtin_mesh("sphere:2").unwrap();
    for i in 0..12 {
        let f = i as f32;
        let mesh = if i % 2 == 0 {
            cube.clone()
        } else {
            sphere.clone()
        };
        objects.push(ObjectDesc {
            rotation_deg: [20.0 * f, 35.0 * f, 0.0],
            ..object(
                mesh,
                [-2.0 + 0.4 * f, 1.2 - 0.25 * f, -2.5 - 0.3 * (i % 3) as f32],
                0.6,
                ShadingDesc::Quadratic,
            )
        });
    }
    // In front: a staircase down and to the right, each step nearer.
    for i in 0..7 {
        let f = i as f32;
        let corners = [[-0.6, 0.5, 0.0], [0.7, 0.4, 0.0], [-0.2, -0.6, 0.0]];
        let shading = match i % 3 {
            0 => ShadingDesc::Quadratic,
            1 => ShadingDesc::Phong,
            _ => ShadingDesc::Gouraud,
        };
        objects.push(object(
            triangle(corners, if i == 3 { flat } else { tilted }),
            [-2.1 + 0.6 * f, 1.6 - 0.45 * f, -0.5 + 0.25 * f],
            1.0,
            shading,
        ));
    }
    SceneDesc {
        width,
        height,
        background: [1, 2, 3],
        camera: CameraDesc {
            eye: [0.0, 0.0, 5.0],
            target: [0.0; 3],
            up: [0.0, 1.0, 0.0],
            fov_y_deg: 40.0,
            near: 0.5,
            far: 20.0,
        },
        light: Some(BUILTIN_LIGHT),
        objects,
    }
}

#[test]
fn midpoint_subdivision_is_exact_behind_a_full_screen_occluder() {
    let scene = to_fixed(&occluder_scene(200, 150)).unwrap();
    for band in [150, 16] {
        let plain = run(&scene, Method::Zbuffer, band, MidpointSettings::default());
        for k in 0..=3 {
            for d in [k, k + 2] {
                for safe in [false, true] {
                    let settings = MidpointSettings {
                        initial: k,
                        max: d,
                        safe,
                    };
                    let out = run(&scene, Method::ZbufferMidpoint, band, settings);
                    let b = &out.stats.buffer;
                    assert_eq!(
                        differing(&out, &plain),
                        0,
                        "band {band}, K {k}, D {d}, safe {safe}"
                    );
                    assert!(b.triangles_culled > 0 && b.pieces_culled > 0);
                    // Pieces judged visible went in untested (in a band of 16
                    // rows, only pieces within it can be judged).
                    if !safe && (band == 150 || d > k) {
                        assert!(b.untested_writes > 0, "band {band}, K {k}, D {d}");
                    }
                }
            }
        }
    }
}

#[test]
fn midpoint_subdivision_errs_only_where_its_test_is_fooled() {
    // On an ordinary scene the test can be fooled; the errors stay a small
    // fraction of the image, and keeping per-pixel tests in visible pieces
    // can only remove the errors of untested writes.
    let scene = to_fixed(&builtin_scene("overdraw", 200, 150).unwrap()).unwrap();
    let plain = run(&scene, Method::Zbuffer, 150, MidpointSettings::default());
    let fast = run(
        &scene,
        Method::ZbufferMidpoint,
        150,
        MidpointSettings::default(),
    );
    let safe = run(
        &scene,
        Method::ZbufferMidpoint,
        150,
        MidpointSettings {
            safe: true,
            ..MidpointSettings::default()
        },
    );
    let pixels = 200 * 150;
    assert!(differing(&fast, &plain) < pixels / 20);
    assert!(differing(&safe, &plain) <= differing(&fast, &plain));
    assert_eq!(safe.stats.buffer.untested_writes, 0);
    assert!(fast.stats.buffer.untested_writes > 0);
    // Fewer per-pixel tests than the plain z-buffer.
    assert!(fast.stats.buffer.depth_tests < plain.stats.buffer.depth_tests / 2);
}

#[test]
fn counters_are_deterministic() {
    let scene = to_fixed(&builtin_scene("overdraw:40:3", 160, 120).unwrap()).unwrap();
    for method in [Method::Zbuffer, Method::ZbufferHiz, Method::ZbufferMidpoint] {
        for band in [120, 16] {
            // Both frames through the same band buffer and frame workspace.
            let config = RenderConfig {
                method,
                band,
                ..RenderConfig::default()
            };
            let frames = render_frames(&scene, &config, &[0.0, 0.0]).expect("renders");
            let (a, b) = (&frames[0], &frames[1]);
            assert_eq!(a.stats, b.stats, "{method:?}, band {band}");
            assert!(a.rgb == b.rgb);
        }
    }
    let rows = measure_table(&scene, 120, 4, 2, 0.0).unwrap();
    assert_eq!(rows.len(), 10);
    assert_eq!(rows[0].differing, 0);
    assert_eq!(rows[1].differing, 0);
    let again = measure_table(&scene, 120, 4, 1, 0.0).unwrap();
    for (a, b) in rows.iter().zip(&again) {
        assert_eq!(
            (a.counts, a.differing),
            (b.counts, b.differing),
            "{}",
            a.label
        );
    }
    let table = markdown_table(&rows);
    assert!(table.contains("| zbuffer-midpoint K=2 D=4 |"));
}

#[test]
fn command_line_takes_the_subdivision_options() {
    let dir = abuffer_test_support::ScratchDir::new("zbuffer-modes");
    let host_sim = env!("CARGO_BIN_EXE_host-sim");
    let png = dir.join("m.png");
    let json = dir.join("m.json");
    let out = std::process::Command::new(host_sim)
        .args([
            "render",
            "--scene",
            "overdraw:30",
            "--width",
            "96",
            "--height",
            "72",
        ])
        .args(["--method", "zbuffer-midpoint", "--subdiv-initial", "1"])
        .args(["--subdiv-max", "3", "--midpoint-safe", "--out"])
        .arg(&png)
        .arg("--stats-json")
        .arg(&json)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(text.contains("depth compares"), "{text}");
    assert!(text.contains("differ from zbuffer"), "{text}");
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(stats["config"]["method"], "zbuffer-midpoint");
    assert_eq!(stats["config"]["midpoint"]["initial"], 1);
    assert_eq!(stats["depth"]["untested_writes"], 0);
    let bad = std::process::Command::new(host_sim)
        .args([
            "render",
            "--scene",
            "teapot:2",
            "--method",
            "zbuffer-midpoint",
        ])
        .args(["--subdiv-initial", "3", "--subdiv-max", "2", "--out"])
        .arg(dir.join("bad.png"))
        .output()
        .unwrap();
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("K <= D"));
    let table = std::process::Command::new(host_sim)
        .args(["zbuffer-table", "--scene", "overdraw:20", "--width", "80"])
        .args(["--height", "60", "--repeat", "1"])
        .output()
        .unwrap();
    assert!(table.status.success());
    assert!(String::from_utf8_lossy(&table.stdout).contains("| zbuffer-hiz |"));
    std::fs::remove_dir_all(&dir).ok();
}
