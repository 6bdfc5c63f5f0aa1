//! The scene-file loader on any text, with OBJ files from `fuzz/data/` and the
//! built-in meshes available to it. A file is either refused with an error naming
//! it, or becomes a scene description whose values are all in the ranges the
//! loader documents. An accepted scene is converted, and if that succeeds and the
//! renderer accepts it, rendered (at most 32 x 32 pixels) through the checked
//! harness.
#![no_main]

use abuffer_fuzz::{render_checked, BufferParams, Memory};
use abuffer_scenes::scene_file::parse_scene;
use libfuzzer_sys::fuzz_target;
use mcu_abuffer::renderer::FrameOptions;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    // The large parameterized built-in meshes (up to millions of triangles) are
    // slow to generate and add nothing here; their bounds have their own tests.
    if ["grid", "knot", "teapot:", "sphere:"]
        .iter()
        .any(|s| text.contains(s))
    {
        return;
    }
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    let desc = match parse_scene(text, "fuzz.toml", &base) {
        Ok(desc) => desc,
        Err(e) => {
            assert!(!e.message.is_empty());
            if e.file == "fuzz.toml" {
                if let Some(line) = e.line {
                    assert!(line >= 1 && line <= text.split('\n').count().max(1));
                }
            }
            return;
        }
    };
    assert!((1..=2048).contains(&desc.width) && (1..=2048).contains(&desc.height));
    let c = &desc.camera;
    let finite = |v: &[f32]| v.iter().all(|x| x.is_finite());
    assert!(finite(&c.eye) && finite(&c.target) && finite(&c.up));
    assert!(c.fov_y_deg > 0.0 && c.fov_y_deg < 180.0);
    assert!(c.near > 0.0 && c.far > c.near && c.far <= 1000.0);
    assert!(c.eye != c.target);
    if let Some(l) = &desc.light {
        assert!(finite(&l.direction) && l.direction != [0.0; 3]);
        for k in [l.ambient, l.diffuse, l.specular] {
            assert!((0.0..=4.0).contains(&k));
        }
        assert!((1.0..=255.0).contains(&l.shininess));
    }
    assert!(!desc.objects.is_empty());
    for o in &desc.objects {
        assert!(o.scale > 0.0 && o.scale.is_finite());
        assert!(finite(&o.position) && finite(&o.rotation_deg));
        let m = &o.mesh;
        assert_eq!(m.normals.len(), m.positions.len());
        assert!(m
            .triangles
            .iter()
            .all(|t| t.iter().all(|&i| (i as usize) < m.positions.len())));
    }
    let mut desc = desc;
    desc.width = desc.width.min(32);
    desc.height = desc.height.min(32);
    let Ok(fixed) = host_sim::convert::to_fixed(&desc) else {
        return;
    };
    if fixed.triangle_count() > 20_000 {
        return;
    }
    let objects = fixed.objects();
    let scene = fixed.scene(&objects);
    if scene.validate().is_err() {
        return;
    }
    let params = BufferParams {
        extra: 2,
        pool: 16,
        band: 4,
        ..BufferParams::minimal(Memory::Grid8x4)
    };
    render_checked(&scene, &FrameOptions::default(), &params, false);
});
