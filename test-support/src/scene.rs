//! Scenes that own their meshes.

use embedded_graphics_core::pixelcolor::Rgb888;
use mcu_abuffer::fixed_point::Coord;
use mcu_abuffer::renderer::FrameOptions;
use mcu_abuffer::scene::{Camera, Light, Mesh, Normal, Scene, SceneObject, Shading, Transform};

/// One object of an [`OwnedScene`], owning its mesh.
#[derive(Clone, Debug)]
pub struct OwnedObject {
    /// Positions, Q16.16.
    pub positions: Vec<[Coord; 3]>,
    /// Normals, one per position (Q2.14).
    pub normals: Vec<Normal>,
    /// Index triples into the positions.
    pub triangles: Vec<[u32; 3]>,
    /// Base color.
    pub color: Rgb888,
    /// Placement.
    pub transform: Transform,
    /// Back-face culling.
    pub cull: bool,
    /// The mesh's openings ([`Mesh::openings`]).
    pub openings: Option<Vec<u32>>,
    /// Shading.
    pub shading: Shading,
}

/// A scene in the renderer's fixed-point types that owns its meshes;
/// [`OwnedScene::objects`] and [`OwnedScene::scene`] lend it to the renderer.
#[derive(Clone, Debug)]
pub struct OwnedScene {
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
    /// Objects in drawing order.
    pub objects: Vec<OwnedObject>,
    /// Turntable angle of the frame, degrees about the world Y axis
    /// ([`OwnedScene::options`]).
    pub turntable_deg: Coord,
}

impl OwnedScene {
    /// Triangles over all objects.
    pub fn triangle_count(&self) -> usize {
        self.objects.iter().map(|o| o.triangles.len()).sum()
    }

    /// Frame options (the turntable angle).
    pub fn options(&self) -> FrameOptions {
        FrameOptions {
            turntable_deg: self.turntable_deg,
            ..FrameOptions::default()
        }
    }

    /// The library objects, borrowing this scene's meshes.
    pub fn objects(&self) -> Vec<SceneObject<'_>> {
        self.objects
            .iter()
            .map(|o| object(o, &o.triangles))
            .collect()
    }

    /// The scene reduced to triangle `t` of object `o` (same camera, light and
    /// object placement), for capturing that triangle's fragments alone.
    pub fn single_triangle_objects(&self, o: usize, t: usize) -> Vec<SceneObject<'_>> {
        let obj = &self.objects[o];
        vec![object(obj, &obj.triangles[t..t + 1])]
    }

    /// The library scene over `objects` (from [`OwnedScene::objects`] or
    /// [`OwnedScene::single_triangle_objects`]).
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
}

/// The library object of `o` with the given triangles.
fn object<'a>(o: &'a OwnedObject, triangles: &'a [[u32; 3]]) -> SceneObject<'a> {
    SceneObject {
        mesh: Mesh {
            positions: &o.positions,
            normals: &o.normals,
            triangles,
            openings: o.openings.as_deref(),
        },
        color: o.color,
        transform: o.transform,
        cull_backfaces: o.cull,
        shading: o.shading,
    }
}
