//! Regression tests for the failures fuzzing found (`fuzz/`, see
//! docs/robustness.md), each reduced to a scene written out by hand. The system
//! tests build with overflow checks, so an arithmetic overflow fails them the way
//! it failed the fuzzer.

use abuffer_test_support::{FragmentStorage, OwnedObject, OwnedScene};
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};
use host_sim::convert::to_fixed;
use host_sim::render::{render, RenderConfig};
use host_sim::scene_desc::{CameraDesc, LightDesc, MeshData, ObjectDesc, SceneDesc};
use host_sim::scene_file::parse_scene;
use mcu_abuffer::coverage::Mask4x4;
use mcu_abuffer::fixed_point::Coord;
use mcu_abuffer::fragment_buffer::{BufferConfig, OverflowPolicy};
use mcu_abuffer::scene::{Camera, Light, SceneError, Shading, Transform};
use std::path::Path;
use system_tests::{render as render_scene, Unit};

fn c(v: f64) -> Coord {
    Coord::from_num(v)
}

fn smallest_buffer(width: u16) -> FragmentStorage<Mask4x4> {
    FragmentStorage::new(
        BufferConfig {
            width,
            band_height: 1,
            main_slots: 1,
            extra_addresses: 0,
            policy: OverflowPolicy::MergeFarthest,
        },
        0,
    )
}

fn unit(v: [f64; 3]) -> [Unit; 3] {
    let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|x| Unit::from_num(x / len))
}

fn object(positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> OwnedObject {
    OwnedObject {
        positions: positions.iter().map(|p| p.map(c)).collect(),
        normals: vec![unit([0.0, 0.0, 1.0]); positions.len()],
        triangles: triangles.to_vec(),
        color: Rgb888::new(58, 58, 58),
        transform: Transform::default(),
        cull: false,
        openings: None,
        shading: Shading::Unlit,
    }
}

/// Renders through the smallest legal buffer; the scene must be valid.
fn draw(scene: &OwnedScene) -> Vec<u8> {
    let objects = scene.objects();
    let lib = scene.scene(&objects);
    lib.validate().expect("valid scene");
    let mut storage = smallest_buffer(scene.width);
    render_scene(&lib, &scene.options(), &mut storage.buffer(), |_, _, _| {}).0
}

/// Found by `render_device`: the camera's view direction, a difference of two
/// Q16.16 points, reaches 2^32 in magnitude; its squared length overflowed 64 bits
/// while the camera basis was normalized.
#[test]
fn camera_basis_of_points_at_opposite_ends_of_the_range() {
    let camera = Camera {
        eye: [Coord::MIN, c(179.7), Coord::MIN],
        target: [Coord::MAX, Coord::MIN, Coord::MAX],
        up: [c(0.0), c(1.0), c(0.0)],
        fov_y_deg: c(60.0),
        near: c(1.0),
        far: c(1000.0),
    };
    let basis = mcu_abuffer::geometry::ViewBasis::new(&camera);
    assert!(basis.is_some());
    let scene = OwnedScene {
        width: 8,
        height: 4,
        background: Rgb888::BLACK,
        camera,
        light: None,
        objects: vec![object(
            &[[0.0, 0.0, 0.0], [100.0, 0.0, 0.0], [0.0, 100.0, 0.0]],
            &[[0, 1, 2]],
        )],
        turntable_deg: Coord::ZERO,
    };
    draw(&scene);
}

/// Found by `render_device`: a light with a diffuse (or specular) coefficient of 8
/// or more is kept at 8.0 in Q2.14, and 8.0 times a dot product of 1.0 is 2^31:
/// one more than an `i32` holds. Any unit normal facing the light overflowed.
#[test]
fn light_coefficients_at_their_largest() {
    for shading in [
        Shading::Flat,
        Shading::Gouraud,
        Shading::Quadratic,
        Shading::Phong,
    ] {
        let mut obj = object(
            &[[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]],
            &[[0, 1, 2]],
        );
        obj.shading = shading;
        let scene = OwnedScene {
            width: 8,
            height: 8,
            background: Rgb888::BLACK,
            camera: Camera {
                eye: [c(0.0), c(0.0), c(3.0)],
                target: [Coord::ZERO; 3],
                up: [c(0.0), c(1.0), c(0.0)],
                fov_y_deg: c(60.0),
                near: c(0.5),
                far: c(10.0),
            },
            light: Some(Light {
                direction: [c(0.0), c(0.0), c(1.0)],
                ambient: c(179.0),
                diffuse: c(179.0),
                specular: Coord::MAX,
                shininess: 1,
            }),
            objects: vec![obj],
            turntable_deg: Coord::ZERO,
        };
        let image = draw(&scene);
        // Lit far beyond white: the middle pixel saturates.
        let mid = (4 * 8 + 4) * 3;
        assert_eq!(&image[mid..mid + 3], &[255, 255, 255], "{shading:?}");
    }
}

/// Found by `render_device` with it: normals of any length on the device API
/// (components up to 2 in Q2.14) drove the lighting's dot products past 32
/// bits. The renderer relies on unit normals, so the scene check now refuses
/// others instead of drawing with overflowed lighting.
#[test]
fn normals_of_other_than_unit_length_are_refused() {
    let mut obj = object(
        &[[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]],
        &[[0, 1, 2]],
    );
    obj.normals[1] = [
        Unit::from_num(-2),
        Unit::from_num(-2),
        Unit::from_num(0.9882),
    ];
    obj.shading = Shading::Quadratic;
    let scene = OwnedScene {
        width: 8,
        height: 1,
        background: Rgb888::BLACK,
        camera: Camera {
            eye: [c(0.0), c(0.0), c(3.0)],
            target: [Coord::ZERO; 3],
            up: [c(0.0), c(1.0), c(0.0)],
            fov_y_deg: c(60.0),
            near: c(0.5),
            far: c(10.0),
        },
        light: Some(Light {
            direction: [c(0.1445), c(-4608.0), c(0.0)],
            ambient: c(0.2),
            diffuse: c(179.0),
            specular: c(0.0),
            shininess: 63,
        }),
        objects: vec![obj],
        turntable_deg: Coord::ZERO,
    };
    let objects = scene.objects();
    assert_eq!(
        scene.scene(&objects).validate(),
        Err(SceneError::NormalLength {
            object: 0,
            vertex: 1
        })
    );
    // The zero vector is no normal either; normals rounded from unit vectors pass.
    let mut zero = scene.clone();
    zero.objects[0].normals[0] = [Unit::ZERO; 3];
    let objects = zero.objects();
    assert!(zero.scene(&objects).validate().is_err());
    let mut rounded = scene.clone();
    rounded.objects[0].normals = vec![
        unit([1.0, 2.0, 3.0]),
        unit([-5.0, 0.1, 0.2]),
        unit([0.0, 0.0, -1.0]),
    ];
    draw(&rounded);
}

/// Found by `render_device`: clip-space components reach 2^61, and a triangle
/// crossing the guard band then needed a 74-bit plane distance and an
/// interpolation product beyond 128 bits. A 1x1 image with a wide field of view
/// and a tiny scale puts the `w` row of the transform at its largest.
#[test]
fn clipping_vertices_at_the_largest_clip_coordinates() {
    let mut obj = object(
        &[
            [-64.0039, -0.0039, -0.0039],
            [1.0, -32767.99998, 179.0],
            [0.0, 0.0, 0.0],
            [-70.1836, 116.36328, 32767.99998],
            [1.0, 0.0, 0.0],
        ],
        &[[2, 3, 4], [3, 4, 1], [0, 2, 4], [4, 4, 0]],
    );
    obj.transform = Transform {
        position: [c(5.19531), c(2.21484), c(-8.0)],
        rotation_deg: [Coord::MIN; 3],
        scale: c(1.0 / 256.0),
    };
    let scene = OwnedScene {
        width: 1,
        height: 1,
        background: Rgb888::new(1, 130, 0),
        camera: Camera {
            eye: [c(14.98828), c(-15.7461), c(-15.52734)],
            target: [c(-3.54297), c(-1.0), c(12.47266)],
            up: [c(-0.75781); 3],
            fov_y_deg: c(134.02734),
            near: c(1.0 / 256.0),
            far: c(799.74219),
        },
        light: None,
        objects: vec![obj],
        turntable_deg: c(-1.0 / 256.0),
    };
    draw(&scene);
}

fn desc() -> SceneDesc {
    SceneDesc {
        width: 8,
        height: 8,
        background: [0, 0, 0],
        camera: CameraDesc {
            eye: [0.0, 0.0, 3.0],
            target: [0.0, 0.0, 0.0],
            up: [0.0, 1.0, 0.0],
            fov_y_deg: 40.0,
            near: 0.5,
            far: 20.0,
        },
        light: Some(LightDesc {
            direction: [0.0, 0.0, 1.0],
            ambient: 0.1,
            diffuse: 0.8,
            specular: 0.3,
            shininess: 8.0,
        }),
        objects: vec![ObjectDesc {
            mesh_name: "triangle".into(),
            mesh: MeshData {
                positions: vec![[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]],
                normals: vec![[0.0, 0.0, 1.0]; 3],
                triangles: vec![[0, 1, 2]],
            },
            color: [200, 100, 50],
            position: [0.0; 3],
            rotation_deg: [0.0; 3],
            scale: 1.0,
            cull_backfaces: false,
            bounds_solids: false,
            shading: None,
        }],
    }
}

/// Found by `render_host`: a NaN (and an infinity, or a value beyond the Q16.16
/// range) in the camera, the light or an object's placement reached the float to
/// fixed-point conversion, which panics on NaN (and saturated the others
/// silently). The conversion now refuses them with an error naming the value.
#[test]
fn non_finite_scene_values_are_refused_by_the_conversion() {
    assert!(to_fixed(&desc()).is_ok());
    type Edit = fn(&mut SceneDesc);
    let edits: [(Edit, &str); 8] = [
        (|d| d.camera.eye[1] = f32::NAN, "camera eye"),
        (
            |d| d.camera.near = f32::INFINITY,
            "camera fov_y_deg, near and far",
        ),
        (|d| d.camera.up[2] = f32::NEG_INFINITY, "camera up"),
        (|d| d.camera.target[0] = 1.0e6, "camera target"),
        (|d| d.light.as_mut().unwrap().shininess = f32::NAN, "light"),
        (
            |d| d.light.as_mut().unwrap().direction[0] = f32::NAN,
            "light direction",
        ),
        (
            |d| d.objects[0].scale = f32::NAN,
            "object 0 (triangle) scale",
        ),
        (
            |d| d.objects[0].rotation_deg[1] = f32::MAX,
            "object 0 (triangle) rotation_deg",
        ),
    ];
    for (edit, what) in edits {
        let mut d = desc();
        edit(&mut d);
        let err = to_fixed(&d).unwrap_err();
        assert!(err.starts_with(what), "{err}");
    }
}

/// Found by `render_host`: a NaN turntable angle panicked in host-sim's `render`
/// (and a zero-sized image would have panicked sizing its band); both are errors.
#[test]
fn host_render_refuses_a_nan_angle_and_an_empty_image() {
    let scene = to_fixed(&desc()).unwrap();
    let config = RenderConfig::default();
    assert!(render(&scene, &config, 30.0).is_ok());
    let err = render(&scene, &config, f32::NAN).unwrap_err();
    assert!(err.contains("not a number"), "{err}");
    let mut empty = scene.clone();
    empty.height = 0;
    let err = render(&empty, &config, 0.0).unwrap_err();
    assert!(err.contains("invalid scene"), "{err}");
}

/// Found by `scene_file`: a key with no value at the end of a file gave an error
/// with an empty message.
#[test]
fn truncated_scene_file_gets_a_message() {
    for text in ["esh =", "[camera]\neye =", "a.b ="] {
        let err = parse_scene(text, "cut.toml", Path::new(".")).unwrap_err();
        assert!(!err.message.is_empty(), "{text:?}");
        assert_eq!(err.file, "cut.toml");
    }
}

/// Not found by fuzzing (which cannot name files outside its data), but the same
/// class: a mesh path naming a device or a pipe made the loader read forever or
/// block. Only regular files are read.
#[test]
fn meshes_must_be_regular_files() {
    let text = "[camera]\neye = [0.0, 0.0, 3.0]\ntarget = [0.0, 0.0, 0.0]\n[[object]]\nmesh = \"/dev/zero\"\n";
    let err = parse_scene(text, "dev.toml", Path::new("/")).unwrap_err();
    assert!(err.message.contains("not a regular file"), "{err}");
    let err = host_sim::obj::load_obj(Path::new("/dev/zero")).unwrap_err();
    assert!(err.message.contains("not a regular file"), "{err}");
    let err = host_sim::obj::load_obj(Path::new("/")).unwrap_err();
    assert!(err.message.contains("not a regular file"), "{err}");
}
