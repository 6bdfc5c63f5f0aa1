//! Scene descriptions as they come from files and generators, in `f32`.
//!
//! These are the host-side, floating-point form of a scene. They are converted
//! once into the renderer's fixed-point form (`mcu_abuffer::scene`) by
//! host-sim's `convert` module, so everything after loading is integer
//! arithmetic and identical on the host and on a device.

/// A triangle mesh with one normal per vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    /// Vertex positions in model space.
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<[f32; 3]>,
    /// Triangles as indices into `positions`/`normals`, counter-clockwise when
    /// seen from the front (OpenGL convention).
    pub triangles: Vec<[u32; 3]>,
}

/// The camera of a scene: a look-at view and a perspective projection.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraDesc {
    /// Eye position, world space.
    pub eye: [f32; 3],
    /// The point looked at, world space.
    pub target: [f32; 3],
    /// The up direction, world space.
    pub up: [f32; 3],
    /// Vertical field of view in degrees.
    pub fov_y_deg: f32,
    /// Near plane distance (> 0).
    pub near: f32,
    /// Far plane distance (> near).
    pub far: f32,
}

/// One directional light (direction towards the light, world space).
#[derive(Clone, Debug, PartialEq)]
pub struct LightDesc {
    /// Direction towards the light, world space (need not be unit length).
    pub direction: [f32; 3],
    /// Ambient coefficient.
    pub ambient: f32,
    /// Diffuse (Lambert) coefficient.
    pub diffuse: f32,
    /// Specular (Blinn-Phong) coefficient.
    pub specular: f32,
    /// Blinn-Phong exponent.
    pub shininess: f32,
}

/// How an object's surface is shaded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShadingDesc {
    /// The object's color exactly, no lighting.
    Unlit,
    /// One lit color per triangle (face normal).
    Flat,
    /// Lit per vertex, interpolated linearly (Gouraud).
    Gouraud,
    /// Lit at the vertices and edge midpoints, a quadratic per triangle stepped
    /// by forward differences.
    Quadratic,
    /// The normal interpolated and lit at every pixel (the reference).
    Phong,
}

/// One object of a scene: a mesh placed in the world.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectDesc {
    /// Where the mesh came from (file path or `builtin:name`), for messages.
    pub mesh_name: String,
    /// The mesh itself.
    pub mesh: MeshData,
    /// Base color, 8-bit sRGB.
    pub color: [u8; 3],
    /// Translation, world space.
    pub position: [f32; 3],
    /// Rotation in degrees about X, then Y, then Z.
    pub rotation_deg: [f32; 3],
    /// Uniform scale.
    pub scale: f32,
    /// Skip triangles that face away from the camera.
    pub cull_backfaces: bool,
    /// The mesh bounds solids, its faces turned outwards, closed but for
    /// openings: a two-sided object then skips the faces it turns away that no
    /// opening can show ([`crate::openings`]; checked when the scene is
    /// converted).
    pub bounds_solids: bool,
    /// Shading mode; `None` means the default (lit when the scene has a light).
    pub shading: Option<ShadingDesc>,
}

/// A whole scene.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneDesc {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Background color, 8-bit sRGB.
    pub background: [u8; 3],
    /// The camera.
    pub camera: CameraDesc,
    /// The light; without one every object is drawn unlit.
    pub light: Option<LightDesc>,
    /// The objects, drawn in this order.
    pub objects: Vec<ObjectDesc>,
}
