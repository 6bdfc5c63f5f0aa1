//! Two-sided objects whose meshes bound solids skip the faces they turn away
//! that no opening can show (`bounds_solids`), and draw the same image.

use host_sim::builtins::{builtin_mesh, builtin_scene};
use host_sim::compare::nmse;
use host_sim::convert::to_fixed;
use host_sim::render::{render, Method, RenderConfig, RenderOutput};
use host_sim::scene_desc::{MeshData, SceneDesc};

const METHODS: [Method; 4] = [
    Method::Unlimited,
    Method::SplitBands,
    Method::Shared,
    Method::Zbuffer,
];

fn run(desc: &SceneDesc, method: Method, angle: f32) -> RenderOutput {
    let scene = to_fixed(desc).expect("scene converts");
    let config = RenderConfig {
        method,
        ..Default::default()
    };
    render(&scene, &config, angle).expect("renders")
}

/// `desc` rendered with and without what its objects say about their shape.
fn both(desc: &SceneDesc, method: Method, angle: f32) -> (RenderOutput, RenderOutput) {
    let mut plain = desc.clone();
    for o in &mut plain.objects {
        o.bounds_solids = false;
    }
    (run(desc, method, angle), run(&plain, method, angle))
}

/// The cube without its top face, seen from `eye` (the built-in scenes'
/// light and background): its inside shows through the opening.
fn open_box(eye: [f32; 3]) -> SceneDesc {
    let mut mesh: MeshData = builtin_mesh("cube").unwrap();
    let positions = mesh.positions.clone();
    mesh.triangles
        .retain(|t| !t.iter().all(|&v| positions[v as usize][1] == 1.0));
    assert_eq!(mesh.triangles.len(), 10);
    let mut desc = builtin_scene("teapot", 96, 80).unwrap();
    desc.camera.eye = eye;
    desc.camera.target = [0.0; 3];
    let object = &mut desc.objects[0];
    object.mesh_name = "open box".into();
    object.mesh = mesh;
    object.rotation_deg = [0.0; 3];
    object.cull_backfaces = false;
    object.bounds_solids = true;
    desc
}

#[test]
fn an_open_box_looks_the_same_and_skips_faces_no_opening_shows() {
    let mut skipped = 0;
    for eye in [[1.5, 4.0, 5.0], [-3.0, 3.0, 3.0], [0.5, -4.0, 4.0]] {
        let desc = open_box(eye);
        for angle in [0.0, 35.0, 110.0, 250.0] {
            for method in METHODS {
                let (with, without) = both(&desc, method, angle);
                assert_eq!(with.rgb, without.rgb, "{method:?} from {eye:?} at {angle}");
                let setups = |o: &RenderOutput| o.stats.geometry.triangle_setups;
                assert!(setups(&with) <= setups(&without));
                skipped += with.stats.geometry.triangles_backfacing;
            }
        }
    }
    // From above, the bottom's outside faces away and lies beside the opening
    // on screen in some of the views; from below the opening is hidden.
    assert!(skipped > 0);
}

#[test]
fn a_camera_inside_draws_every_face() {
    // The eye inside a closed cube that says it bounds a solid: a vertex lies
    // behind the near plane, so nothing is skipped and the inside shows.
    let mut desc = open_box([0.2, 0.1, 0.3]);
    desc.objects[0].mesh = builtin_mesh("cube").unwrap();
    desc.objects[0].scale = 3.0;
    desc.camera.target = [0.0, 0.0, -1.0];
    for method in METHODS {
        let (with, without) = both(&desc, method, 0.0);
        assert_eq!(with.rgb, without.rgb, "{method:?}");
        assert_eq!(with.stats.geometry.triangles_backfacing, 0);
        assert!(!with.rgb.chunks_exact(3).any(|p| p == desc.background));
    }
}

#[test]
fn the_teapot_changes_only_where_rounding_let_a_face_turned_away_win() {
    // The built-in teapot says it bounds solids. Its z-buffer images are the
    // same; the antialiased ones lose a few pixels where a face turned away
    // won a sample beside a silhouette by the depth planes' rounding, and
    // `shared` merges otherwise.
    let desc = builtin_scene("teapot", 240, 240).unwrap();
    assert!(desc.objects[0].bounds_solids);
    for angle in [0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0] {
        for method in METHODS {
            let (with, without) = both(&desc, method, angle);
            let differing = with
                .rgb
                .chunks_exact(3)
                .zip(without.rgb.chunks_exact(3))
                .filter(|(a, b)| a != b)
                .count();
            if method == Method::Zbuffer {
                assert_eq!(differing, 0, "at {angle}");
            }
            let error = nmse(&with.rgb, &without.rgb);
            if method == Method::Shared {
                // The pool's merges follow the fragments that arrive: fewer
                // of them (faces turned away probed in vain) move some merges.
                let merges = |o: &RenderOutput| o.stats.buffer.merges;
                assert!(merges(&with) <= merges(&without), "at {angle}");
                assert!(error < 2e-4, "at {angle}: NMSE {error:e}");
            } else {
                assert!(differing <= 8, "{method:?} at {angle}: {differing} pixels");
                assert!(error < 3e-6, "{method:?} at {angle}: NMSE {error:e}");
            }
            // Most faces turned away are skipped before setup.
            let g = |o: &RenderOutput| o.stats.geometry;
            assert!(
                g(&with).triangles_backfacing > 1000,
                "{method:?} at {angle}"
            );
            assert!(g(&with).triangle_setups * 4 < g(&without).triangle_setups * 3);
        }
    }
}

#[test]
fn a_mesh_that_does_not_bound_solids_is_an_error_naming_the_object() {
    let mut desc = open_box([1.5, 4.0, 5.0]);
    for t in &mut desc.objects[0].mesh.triangles {
        t.swap(1, 2);
    }
    let err = to_fixed(&desc).unwrap_err();
    assert!(
        err.contains("object 0 (mesh 'open box')") && err.contains("turned inwards"),
        "{err}"
    );
    // Culled, the object never asks which faces an opening shows.
    desc.objects[0].cull_backfaces = true;
    assert!(to_fixed(&desc).is_ok());
}
