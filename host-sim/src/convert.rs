//! From the floating-point scene description to the renderer's fixed-point scene.
//!
//! This is the only place where floats become fixed point; the conversion rounds to
//! nearest and is the same on every machine, so a scene baked into firmware and the
//! same scene loaded here are the same bits.

use crate::scene_desc::{SceneDesc, ShadingDesc};
use embedded_graphics_core::pixelcolor::Rgb888;
use fixed::types::{I16F16, I2F14};
use mcu_abuffer::scene::{Camera, Light, Mesh, Normal, Scene, SceneObject, Shading, Transform};

pub use abuffer_scenes::fixed_bits::MAX_MODEL_COORDINATE;
use abuffer_scenes::fixed_bits::{check_convertible, coord_bits, normal_bits};

/// A mesh in fixed point, owned.
#[derive(Clone, Debug, Default)]
pub struct FixedMesh {
    /// Positions, Q16.16.
    pub positions: Vec<[I16F16; 3]>,
    /// Unit normals, Q2.14.
    pub normals: Vec<Normal>,
    /// Index triples.
    pub triangles: Vec<[u32; 3]>,
}

/// A scene in fixed point that owns its meshes; [`FixedScene::objects`] and
/// [`FixedScene::scene`] lend it to the renderer.
#[derive(Clone, Debug)]
pub struct FixedScene {
    /// Image width.
    pub width: u16,
    /// Image height.
    pub height: u16,
    /// Background color.
    pub background: Rgb888,
    /// Camera.
    pub camera: Camera,
    /// Light.
    pub light: Option<Light>,
    /// Meshes, one per object.
    pub meshes: Vec<FixedMesh>,
    /// Per object: color, transform, culling, shading.
    pub placements: Vec<(Rgb888, Transform, bool, Shading)>,
    /// Mesh names, for messages.
    pub mesh_names: Vec<String>,
}

fn fix(v: f32) -> I16F16 {
    I16F16::from_bits(coord_bits(v))
}

fn fix3(v: [f32; 3]) -> [I16F16; 3] {
    v.map(fix)
}

/// Converts a scene description. Errors name the object and the problem.
pub fn to_fixed(desc: &SceneDesc) -> Result<FixedScene, String> {
    let mut meshes = Vec::new();
    let mut placements = Vec::new();
    let mut mesh_names = Vec::new();
    check_convertible(desc)?;
    for o in &desc.objects {
        let m = &o.mesh;
        let normals = m
            .normals
            .iter()
            .map(|n| normal_bits(*n).map(I2F14::from_bits))
            .collect();
        meshes.push(FixedMesh {
            positions: m.positions.iter().map(|p| fix3(*p)).collect(),
            normals,
            triangles: m.triangles.clone(),
        });
        let shading = match (o.shading, desc.light.is_some()) {
            (Some(ShadingDesc::Unlit), _) | (None, false) => Shading::Unlit,
            (Some(ShadingDesc::Flat), _) => Shading::Flat,
            (Some(ShadingDesc::Gouraud), _) => Shading::Gouraud,
            (Some(ShadingDesc::Quadratic), _) | (None, true) => Shading::Quadratic,
            (Some(ShadingDesc::Phong), _) => Shading::Phong,
        };
        let transform = Transform {
            position: fix3(o.position),
            rotation_deg: fix3(o.rotation_deg),
            scale: fix(o.scale),
        };
        placements.push((
            Rgb888::new(o.color[0], o.color[1], o.color[2]),
            transform,
            o.cull_backfaces,
            shading,
        ));
        mesh_names.push(o.mesh_name.clone());
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
        meshes,
        placements,
        mesh_names,
    })
}

impl FixedScene {
    /// The objects, borrowing the meshes.
    pub fn objects(&self) -> Vec<SceneObject<'_>> {
        self.meshes
            .iter()
            .zip(&self.placements)
            .map(
                |(m, &(color, transform, cull_backfaces, shading))| SceneObject {
                    mesh: Mesh {
                        positions: &m.positions,
                        normals: &m.normals,
                        triangles: &m.triangles,
                    },
                    color,
                    transform,
                    cull_backfaces,
                    shading,
                },
            )
            .collect()
    }

    /// The scene over `objects` (from [`FixedScene::objects`]).
    pub fn scene<'a>(&self, objects: &'a [SceneObject<'a>]) -> Scene<'a> {
        Scene {
            width: self.width,
            height: self.height,
            background: self.background,
            camera: self.camera,
            light: self.light,
            objects,
        }
    }

    /// Triangles over all objects.
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.triangles.len()).sum()
    }
}
