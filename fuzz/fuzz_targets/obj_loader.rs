//! The OBJ loader on any text. A file is either refused with an error that names
//! the file (and a line within it, when it gives one) or becomes a mesh whose
//! indices are in range, with one finite unit normal per finite position. A small
//! accepted mesh is then converted and rendered through the checked harness.
#![no_main]

use abuffer_fuzz::{render_checked, BufferParams, Memory};
use abuffer_scenes::obj::parse_obj;
use abuffer_scenes::scene_desc::{CameraDesc, ObjectDesc, SceneDesc};
use libfuzzer_sys::fuzz_target;
use mcu_abuffer::renderer::FrameOptions;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let mesh = match parse_obj(text, "fuzz.obj") {
        Ok(mesh) => mesh,
        Err(e) => {
            assert_eq!(e.file, "fuzz.obj");
            assert!(!e.message.is_empty());
            if let Some(line) = e.line {
                assert!(line >= 1 && line <= text.split('\n').count(), "line {line}");
            }
            return;
        }
    };
    assert!(!mesh.triangles.is_empty());
    assert_eq!(mesh.normals.len(), mesh.positions.len());
    for t in &mesh.triangles {
        assert!(t.iter().all(|&i| (i as usize) < mesh.positions.len()));
    }
    assert!(mesh.positions.iter().flatten().all(|c| c.is_finite()));
    for n in &mesh.normals {
        assert!(n.iter().all(|c| c.is_finite()), "normal {n:?}");
        let len2: f32 = n.iter().map(|c| c * c).sum();
        assert!((len2 - 1.0).abs() < 1e-3, "normal {n:?} is not unit length");
    }
    if mesh.triangles.len() > 256 {
        return;
    }
    let mut desc = SceneDesc {
        width: 24,
        height: 16,
        background: [0, 0, 0],
        camera: CameraDesc {
            eye: [0.5, 1.0, 6.0],
            target: [0.0, 0.0, 0.0],
            up: [0.0, 1.0, 0.0],
            fov_y_deg: 40.0,
            near: 0.1,
            far: 100.0,
        },
        light: None,
        objects: vec![ObjectDesc {
            mesh_name: "fuzz.obj".into(),
            mesh,
            color: [200, 100, 50],
            position: [0.0; 3],
            rotation_deg: [0.0; 3],
            scale: 1.0,
            cull_backfaces: false,
            // The check of the mesh's shape runs on every loaded mesh; one
            // that fails it is drawn with every face.
            bounds_solids: true,
            shading: None,
        }],
    };
    let fixed = match host_sim::convert::to_fixed(&desc) {
        Ok(fixed) => fixed,
        Err(_) => {
            desc.objects[0].bounds_solids = false;
            let Ok(fixed) = host_sim::convert::to_fixed(&desc) else {
                return;
            };
            fixed
        }
    };
    let objects = fixed.objects();
    let scene = fixed.scene(&objects);
    let params = BufferParams {
        extra: 1,
        pool: 8,
        band: 3,
        ..BufferParams::minimal(Memory::Grid4x4)
    };
    render_checked(&scene, &FrameOptions::default(), &params, true);
});
