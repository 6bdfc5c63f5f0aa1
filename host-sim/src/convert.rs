//! From the floating-point scene description to the renderer's fixed-point scene.
//!
//! This is the only place where floats become fixed point; the conversion rounds to
//! nearest and is the same on every machine, so a scene baked into firmware and the
//! same scene loaded here are the same bits.

use crate::scene_desc::{SceneDesc, ShadingDesc};
use abuffer_test_support::{OwnedObject, OwnedScene};
use embedded_graphics_core::pixelcolor::Rgb888;
use fixed::types::{I16F16, I2F14};
use mcu_abuffer::scene::{Camera, Light, Shading, Transform, OPENING_END};

pub use abuffer_scenes::fixed_bits::MAX_MODEL_COORDINATE;
use abuffer_scenes::fixed_bits::{check_convertible, coord_bits, normal_bits};
use abuffer_scenes::openings::object_openings;

/// A scene in fixed point that owns its meshes (the shared owned scene;
/// [`to_fixed`] leaves its turntable angle at zero: the renderer takes the
/// frame's angle apart).
pub type FixedScene = OwnedScene;

fn fix(v: f32) -> I16F16 {
    I16F16::from_bits(coord_bits(v))
}

fn fix3(v: [f32; 3]) -> [I16F16; 3] {
    v.map(fix)
}

/// Converts a scene description. Errors name the object and the problem.
pub fn to_fixed(desc: &SceneDesc) -> Result<FixedScene, String> {
    check_convertible(desc)?;
    let mut objects = Vec::new();
    for (index, o) in desc.objects.iter().enumerate() {
        let m = &o.mesh;
        let openings = object_openings(o, index)?.map(|loops| {
            loops
                .iter()
                .flat_map(|l| l.iter().copied().chain([OPENING_END]))
                .collect()
        });
        let shading = match (o.shading, desc.light.is_some()) {
            (Some(ShadingDesc::Unlit), _) | (None, false) => Shading::Unlit,
            (Some(ShadingDesc::Flat), _) => Shading::Flat,
            (Some(ShadingDesc::Gouraud), _) => Shading::Gouraud,
            (Some(ShadingDesc::Quadratic), _) | (None, true) => Shading::Quadratic,
            (Some(ShadingDesc::Phong), _) => Shading::Phong,
        };
        objects.push(OwnedObject {
            positions: m.positions.iter().map(|p| fix3(*p)).collect(),
            normals: m
                .normals
                .iter()
                .map(|n| normal_bits(*n).map(I2F14::from_bits))
                .collect(),
            triangles: m.triangles.clone(),
            color: Rgb888::new(o.color[0], o.color[1], o.color[2]),
            transform: Transform {
                position: fix3(o.position),
                rotation_deg: fix3(o.rotation_deg),
                scale: fix(o.scale),
            },
            cull: o.cull_backfaces,
            openings,
            shading,
        });
    }
    let c = &desc.camera;
    let camera = Camera {
        eye: fix3(c.eye),
        target: fix3(c.target),
        up: fix3(c.up),
        fov_y_deg: fix(c.fov_y_deg),
        near: fix(c.near),
        far: fix(c.far),
    };
    let light = desc.light.as_ref().map(|l| Light {
        direction: fix3(l.direction),
        ambient: fix(l.ambient),
        diffuse: fix(l.diffuse),
        specular: fix(l.specular),
        shininess: l.shininess.round().clamp(1.0, 255.0) as u8,
    });
    let width = u16::try_from(desc.width).map_err(|_| "image width too large".to_string())?;
    let height = u16::try_from(desc.height).map_err(|_| "image height too large".to_string())?;
    let bg = desc.background;
    Ok(FixedScene {
        width,
        height,
        background: Rgb888::new(bg[0], bg[1], bg[2]),
        camera,
        light,
        objects,
        turntable_deg: I16F16::ZERO,
    })
}
