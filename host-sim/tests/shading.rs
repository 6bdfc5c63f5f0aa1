//! Shading modes through the whole renderer: quadratic against Gouraud with
//! per-pixel Phong as the reference, band independence, degenerate input.

use host_sim::builtins::{builtin_mesh, builtin_scene, BUILTIN_LIGHT};
use host_sim::convert::to_fixed;
use host_sim::render::{render, Method, RenderConfig, RenderOutput};
use host_sim::scene_desc::{CameraDesc, MeshData, ObjectDesc, SceneDesc, ShadingDesc};
use host_sim::scene_file::load_scene_file;
use host_sim::shading_compare::{compare_shading, ModeError};
use std::path::Path;

fn sphere_scene() -> SceneDesc {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/scenes/sphere.toml");
    load_scene_file(&path).expect("the sphere scene loads")
}

fn scene(objects: Vec<ObjectDesc>, eye: [f32; 3]) -> SceneDesc {
    SceneDesc {
        width: 96,
        height: 72,
        background: [1, 2, 3],
        camera: CameraDesc {
            eye,
            target: [0.0; 3],
            up: [0.0, 1.0, 0.0],
            fov_y_deg: 50.0,
            near: 0.5,
            far: 20.0,
        },
        light: Some(BUILTIN_LIGHT),
        objects,
    }
}

fn object(mesh: MeshData, shading: ShadingDesc) -> ObjectDesc {
    ObjectDesc {
        mesh_name: "test".into(),
        mesh,
        color: [200, 150, 90],
        position: [0.0; 3],
        rotation_deg: [0.0; 3],
        scale: 1.0,
        cull_backfaces: false,
        bounds_solids: false,
        shading: Some(shading),
    }
}

fn run(desc: &SceneDesc, method: Method, band: u16) -> RenderOutput {
    let scene = to_fixed(desc).expect("scene converts");
    let config = RenderConfig {
        method,
        band,
        ..Default::default()
    };
    render(&scene, &config, 0.0).expect("renders")
}

fn with_shading(mut desc: SceneDesc, shading: ShadingDesc) -> SceneDesc {
    for o in &mut desc.objects {
        o.shading = Some(shading);
    }
    desc
}

/// Quadratic must beat Gouraud in mean and largest error, per channel, over the
/// object and over the highlight region.
fn assert_quadratic_closer(name: &str, gouraud: &ModeError, quadratic: &ModeError) {
    for (region, g, q) in [
        ("object", &gouraud.object, &quadratic.object),
        ("highlight", &gouraud.highlight, &quadratic.highlight),
    ] {
        println!(
            "{name} {region} ({} pixels): gouraud mean {:.3?} max {:?}; quadratic mean {:.3?} max {:?}",
            g.pixels, g.mean, g.max, q.mean, q.max
        );
        assert!(g.pixels > 100, "{name}: {region} region too small");
        for c in 0..3 {
            assert!(q.mean[c] < g.mean[c], "{name} {region} channel {c}: mean");
            assert!(q.max[c] < g.max[c], "{name} {region} channel {c}: max");
        }
    }
}

#[test]
fn quadratic_is_closer_to_phong_than_gouraud_on_a_sphere() {
    let scene = to_fixed(&sphere_scene()).unwrap();
    let cmp = compare_shading(&scene, &RenderConfig::default(), 0.0, 10).unwrap();
    assert_quadratic_closer("sphere", &cmp.gouraud_error, &cmp.quadratic_error);
    // Most of Gouraud's error is gone.
    for c in 0..3 {
        assert!(cmp.quadratic_error.highlight.mean[c] * 3.0 < cmp.gouraud_error.highlight.mean[c]);
    }
}

#[test]
fn quadratic_is_closer_to_phong_than_gouraud_on_the_teapot() {
    let scene = to_fixed(&builtin_scene("teapot", 240, 240).unwrap()).unwrap();
    let config = RenderConfig {
        method: Method::Unlimited,
        ..Default::default()
    };
    let cmp = compare_shading(&scene, &config, 0.0, 10).unwrap();
    assert_quadratic_closer("teapot", &cmp.gouraud_error, &cmp.quadratic_error);
}

#[test]
fn quadratic_and_phong_do_not_depend_on_the_band_height() {
    let desc = builtin_scene("teapot", 96, 80).unwrap();
    for shading in [ShadingDesc::Quadratic, ShadingDesc::Phong] {
        let desc = with_shading(desc.clone(), shading);
        for method in [Method::Unlimited, Method::Zbuffer] {
            let reference = run(&desc, method, 80);
            for band in [1, 3, 16, 33] {
                assert_eq!(
                    run(&desc, method, band).rgb,
                    reference.rgb,
                    "{shading:?} {method:?} band {band}"
                );
            }
        }
    }
}

#[test]
fn quadratic_is_the_default_with_a_light() {
    let mut desc = builtin_scene("spheres", 64, 64).unwrap();
    let default = run(&desc, Method::Unlimited, 16).rgb;
    desc = with_shading(desc, ShadingDesc::Quadratic);
    assert_eq!(run(&desc, Method::Unlimited, 16).rgb, default);
}

#[test]
fn equal_normals_shade_constant() {
    // A square facing the camera, every normal the same: six equal samples per
    // triangle, one color inside, and the same as Gouraud's.
    let mesh = MeshData {
        positions: vec![
            [-1.0, -1.0, 0.0],
            [1.0, -1.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 1.0, 0.0],
        ],
        normals: vec![[0.2, 0.3, 0.9]; 4],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    };
    let quadratic = run(
        &scene(
            vec![object(mesh.clone(), ShadingDesc::Quadratic)],
            [0.0, 0.0, 3.0],
        ),
        Method::Zbuffer,
        16,
    );
    let gouraud = run(
        &scene(vec![object(mesh, ShadingDesc::Gouraud)], [0.0, 0.0, 3.0]),
        Method::Zbuffer,
        16,
    );
    assert_eq!(quadratic.rgb, gouraud.rgb);
    let colors: std::collections::HashSet<&[u8]> = quadratic
        .rgb
        .chunks_exact(3)
        .filter(|p| *p != [1, 2, 3])
        .collect();
    assert_eq!(colors.len(), 1, "{colors:?}");
}

#[test]
fn degenerate_triangles_shade_nothing() {
    let mesh = MeshData {
        // Collinear, coincident, and a needle thinner than a sample.
        positions: vec![
            [-1.0, -1.0, 0.0],
            [0.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.3, 0.3, 0.0],
            [-1.0, 0.5, 0.0],
            [1.0, 0.5, 0.0],
            [1.0, 0.504, 0.0],
        ],
        normals: vec![
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 0.2],
            [-1.0, 0.0, 0.2],
        ],
        triangles: vec![[0, 1, 2], [3, 3, 3], [4, 5, 6]],
    };
    for shading in [ShadingDesc::Quadratic, ShadingDesc::Phong] {
        let out = run(
            &scene(vec![object(mesh.clone(), shading)], [0.0, 0.0, 3.0]),
            Method::Unlimited,
            16,
        );
        assert_eq!(out.stats.geometry.triangles_degenerate, 2, "{shading:?}");
        assert!(out.stats.buffer.fragments_generated <= 96, "{shading:?}");
    }
}

#[test]
fn clipped_triangles_shade_like_the_reference() {
    // The camera sits inside a sphere and close to a large sphere's surface:
    // triangles cross the near plane and are clipped into pieces, whose
    // corners carry interpolated normals.
    let sphere = builtin_mesh("sphere:2").unwrap();
    let mut outside = object(sphere, ShadingDesc::Phong);
    outside.scale = 1.6;
    outside.cull_backfaces = false;
    let desc = scene(vec![outside], [0.3, 0.2, 1.8]);
    let scene_fixed = to_fixed(&desc).unwrap();
    let config = RenderConfig {
        method: Method::Unlimited,
        ..Default::default()
    };
    let cmp = compare_shading(&scene_fixed, &config, 0.0, 10).unwrap();
    let clipped = cmp.phong.stats.geometry.triangles_clipped;
    assert!(clipped > 0, "no triangle was clipped");
    println!(
        "{clipped} clipped; gouraud {:?}, quadratic {:?}",
        cmp.gouraud_error.object, cmp.quadratic_error.object
    );
    for c in 0..3 {
        assert!(cmp.quadratic_error.object.mean[c] < cmp.gouraud_error.object.mean[c]);
    }
}
