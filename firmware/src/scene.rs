//! The scene in the renderer's fixed-point form: meshes, objects, camera, light.
//!
//! Everything here is plain data that can live in flash (`static`) on a device or be
//! built from files on the host. [`Scene::validate`] checks what the renderer relies
//! on, so a bad scene is an error, never a panic or an out-of-bounds access.

use crate::fixed_point::Coord;
use embedded_graphics_core::pixelcolor::Rgb888;
use fixed::types::I2F14;

/// A unit normal in Q2.14.
pub type Normal = [I2F14; 3];

/// A triangle mesh: positions, one unit normal per position, and index triples
/// (counter-clockwise seen from the front).
#[derive(Clone, Copy, Debug)]
pub struct Mesh<'a> {
    /// Model-space positions.
    pub positions: &'a [[Coord; 3]],
    /// Unit normals, one per position.
    pub normals: &'a [Normal],
    /// Triangles as indices into `positions`.
    pub triangles: &'a [[u32; 3]],
    /// What is known of the mesh's shape. `Some`: the mesh bounds solids,
    /// its faces turned outwards, and these are its openings (the loops of
    /// edges that only one triangle uses, as vertex indices in the order
    /// that triangle runs them, each loop ended by [`OPENING_END`]; empty
    /// when the mesh is closed). A two-sided object
    /// then skips the faces it turns away that no opening can show (see
    /// [`crate::openings`]). `None`: nothing is known; every face is drawn.
    ///
    /// `abuffer-scenes` finds the openings and checks the shape
    /// (`object_openings`, which leaves out an opening that lies inside
    /// another part's solid: no ray enters through it); a wrong `Some`
    /// changes the image, never memory safety.
    pub openings: Option<&'a [u32]>,
}

/// Ends each loop of [`Mesh::openings`].
pub const OPENING_END: u32 = u32::MAX;

/// Position, orientation and size of an object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    /// Translation, world units.
    pub position: [Coord; 3],
    /// Rotation in degrees about X, then Y, then Z.
    pub rotation_deg: [Coord; 3],
    /// Uniform scale (positive).
    pub scale: Coord,
}

impl Default for Transform {
    fn default() -> Self {
        Self {
            position: [Coord::ZERO; 3],
            rotation_deg: [Coord::ZERO; 3],
            scale: Coord::ONE,
        }
    }
}

/// How a surface gets its color.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Shading {
    /// The object's color exactly; no lighting.
    Unlit,
    /// One lit color per triangle, from the mean of its vertex normals.
    Flat,
    /// Lit at the vertices, colors interpolated linearly across the triangle.
    Gouraud,
    /// Lit at the vertices and the edge midpoints, colors from the quadratic
    /// through those six samples, stepped by forward differences.
    Quadratic,
    /// The normal interpolated across the triangle and lit at every pixel
    /// (the reference for the others; an integer square root and divisions per pixel).
    Phong,
}

/// A mesh placed in the world.
#[derive(Clone, Copy, Debug)]
pub struct SceneObject<'a> {
    /// The mesh.
    pub mesh: Mesh<'a>,
    /// Base color.
    pub color: Rgb888,
    /// Placement.
    pub transform: Transform,
    /// Skip triangles facing away from the camera.
    pub cull_backfaces: bool,
    /// Shading mode (without a scene light every mode draws unlit).
    pub shading: Shading,
}

/// Look-at camera with a perspective projection (as `gluLookAt` + `gluPerspective`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: [Coord; 3],
    /// Point looked at.
    pub target: [Coord; 3],
    /// Up direction.
    pub up: [Coord; 3],
    /// Vertical field of view, degrees.
    pub fov_y_deg: Coord,
    /// Near plane distance.
    pub near: Coord,
    /// Far plane distance.
    pub far: Coord,
}

/// One white directional light; the viewer is at infinity (constant half vector).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Direction towards the light, world space (any nonzero length).
    pub direction: [Coord; 3],
    /// Ambient coefficient.
    pub ambient: Coord,
    /// Diffuse coefficient.
    pub diffuse: Coord,
    /// Specular coefficient.
    pub specular: Coord,
    /// Blinn-Phong exponent.
    pub shininess: u8,
}

/// A scene ready to render.
#[derive(Clone, Copy, Debug)]
pub struct Scene<'a> {
    /// Image width in pixels.
    pub width: u16,
    /// Image height in pixels.
    pub height: u16,
    /// Color where nothing is drawn.
    pub background: Rgb888,
    /// The camera.
    pub camera: Camera,
    /// The light, if any.
    pub light: Option<Light>,
    /// Objects in drawing order.
    pub objects: &'a [SceneObject<'a>],
}

/// A regular octahedron of radius 1 about the origin (6 vertices, 8
/// triangles, normals pointing out from the center): a closed mesh for a first
/// frame and for examples.
pub const OCTAHEDRON: Mesh<'static> = {
    const O: Coord = Coord::ZERO;
    const P: Coord = Coord::ONE;
    const N: Coord = Coord::lit("-1");
    const OX: I2F14 = I2F14::ZERO;
    const PX: I2F14 = I2F14::ONE;
    const NX: I2F14 = I2F14::lit("-1");
    Mesh {
        positions: &[
            [P, O, O],
            [N, O, O],
            [O, P, O],
            [O, N, O],
            [O, O, P],
            [O, O, N],
        ],
        normals: &[
            [PX, OX, OX],
            [NX, OX, OX],
            [OX, PX, OX],
            [OX, NX, OX],
            [OX, OX, PX],
            [OX, OX, NX],
        ],
        // Counter-clockwise seen from outside.
        triangles: &[
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ],
        // Closed, faces turned outwards.
        openings: Some(&[]),
    }
};

/// The largest image side the renderer accepts (window coordinates must stay
/// well inside the guard band).
pub const MAX_IMAGE_SIDE: u16 = 2048;

/// What is wrong with a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SceneError {
    /// Width or height is 0 or above [`MAX_IMAGE_SIDE`].
    ImageSize,
    /// Near plane not positive, far not beyond near, or far beyond 1000 units.
    ClipPlanes,
    /// Field of view outside (1, 179) degrees.
    FieldOfView,
    /// Eye and target coincide, or up is parallel to the view direction.
    CameraBasis,
    /// An object's scale is not positive.
    Scale {
        /// Object index.
        object: u16,
    },
    /// An object's mesh has a different number of normals than positions.
    NormalCount {
        /// Object index.
        object: u16,
    },
    /// A triangle refers to a vertex that does not exist.
    IndexOutOfRange {
        /// Object index.
        object: u16,
        /// Triangle index within the object's mesh.
        triangle: u32,
    },
    /// The light direction is zero.
    LightDirection,
    /// A normal is not of unit length (within [`NORMAL_LENGTH_TOLERANCE`]).
    NormalLength {
        /// Object index.
        object: u16,
        /// Vertex index within the object's mesh.
        vertex: u32,
    },
}

/// How far the squared length of a normal may be from 1, in units of
/// `2^-28` (the square of the unit format's step): 1/64 of it. Lighting relies
/// on `|n . l| <= 1` up to this margin; normals rounded to Q2.14 from unit
/// vectors are far closer.
pub const NORMAL_LENGTH_TOLERANCE: u32 = 1 << 22;

impl core::fmt::Display for SceneError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::ImageSize => write!(f, "image width and height must be 1..={MAX_IMAGE_SIDE}"),
            Self::ClipPlanes => write!(f, "camera needs 0 < near < far <= 1000"),
            Self::FieldOfView => write!(f, "field of view must be between 1 and 179 degrees"),
            Self::CameraBasis => write!(
                f,
                "camera eye equals target, or up is parallel to the view direction"
            ),
            Self::Scale { object } => write!(f, "object {object}: scale must be positive"),
            Self::NormalCount { object } => {
                write!(f, "object {object}: mesh needs one normal per position")
            }
            Self::IndexOutOfRange { object, triangle } => {
                write!(
                    f,
                    "object {object}: triangle {triangle} refers to a vertex that does not exist"
                )
            }
            Self::LightDirection => write!(f, "light direction must not be zero"),
            Self::NormalLength { object, vertex } => {
                write!(f, "object {object}: normal {vertex} is not of unit length")
            }
        }
    }
}

impl Scene<'_> {
    /// Checks everything the renderer relies on.
    pub fn validate(&self) -> Result<(), SceneError> {
        if self.width == 0
            || self.height == 0
            || self.width > MAX_IMAGE_SIDE
            || self.height > MAX_IMAGE_SIDE
        {
            return Err(SceneError::ImageSize);
        }
        let c = &self.camera;
        if c.near <= Coord::ZERO || c.far <= c.near || c.far > Coord::from_num(1000) {
            return Err(SceneError::ClipPlanes);
        }
        if c.fov_y_deg < Coord::ONE || c.fov_y_deg > Coord::from_num(179) {
            return Err(SceneError::FieldOfView);
        }
        if crate::geometry::ViewBasis::new(c).is_none() {
            return Err(SceneError::CameraBasis);
        }
        if let Some(light) = &self.light {
            if light.direction.iter().all(|d| *d == Coord::ZERO) {
                return Err(SceneError::LightDirection);
            }
        }
        for (i, o) in self.objects.iter().enumerate() {
            let object = i as u16;
            if o.transform.scale <= Coord::ZERO {
                return Err(SceneError::Scale { object });
            }
            if o.mesh.normals.len() != o.mesh.positions.len() {
                return Err(SceneError::NormalCount { object });
            }
            // Components are below 2^15 in magnitude: squares below 2^30, sums below 2^32.
            if let Some(v) = o.mesh.normals.iter().position(|n| {
                let len2: u32 = n.iter().map(|c| (c.to_bits() as i32).pow(2) as u32).sum();
                len2.abs_diff(1 << 28) > NORMAL_LENGTH_TOLERANCE
            }) {
                return Err(SceneError::NormalLength {
                    object,
                    vertex: v as u32,
                });
            }
            let n = o.mesh.positions.len() as u64;
            if let Some(t) = o
                .mesh
                .triangles
                .iter()
                .position(|t| t.iter().any(|&v| v as u64 >= n))
            {
                return Err(SceneError::IndexOutOfRange {
                    object,
                    triangle: t as u32,
                });
            }
        }
        Ok(())
    }

    /// Vertices over all objects.
    pub fn vertex_count(&self) -> usize {
        self.objects.iter().map(|o| o.mesh.positions.len()).sum()
    }

    /// Triangles over all objects.
    pub fn triangle_count(&self) -> usize {
        self.objects.iter().map(|o| o.mesh.triangles.len()).sum()
    }
}
