//! Small vector helpers and a mesh builder shared by the built-in generators.

use crate::scene_desc::MeshData;

/// A 3-vector.
pub(super) type V3 = [f32; 3];

pub(super) fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub(super) fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(super) fn mul(a: V3, k: f32) -> V3 {
    [a[0] * k, a[1] * k, a[2] * k]
}

pub(super) fn dot(a: V3, b: V3) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(super) fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(super) fn length(a: V3) -> f32 {
    dot(a, a).sqrt()
}

/// `a` scaled to unit length, or `None` when it is (nearly) zero.
pub(super) fn normalize(a: V3) -> Option<V3> {
    let len = length(a);
    if len > 1e-12 && len.is_finite() {
        Some(mul(a, 1.0 / len))
    } else {
        None
    }
}

/// Geometric (unnormalized) normal of a triangle, by the right-hand rule.
pub(super) fn tri_normal(a: V3, b: V3, c: V3) -> V3 {
    cross(sub(b, a), sub(c, a))
}

/// A 3x3 matrix, rows first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Mat3(pub [[f32; 3]; 3]);

impl Mat3 {
    pub(super) const IDENTITY: Mat3 = Mat3([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);

    /// Rotation by `deg` degrees about the X axis (right-handed).
    pub(super) fn rot_x(deg: f32) -> Mat3 {
        let (s, c) = deg.to_radians().sin_cos();
        Mat3([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    }

    /// Rotation by `deg` degrees about the Y axis (right-handed).
    pub(super) fn rot_y(deg: f32) -> Mat3 {
        let (s, c) = deg.to_radians().sin_cos();
        Mat3([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    }

    /// Rotation by `deg` degrees about the Z axis (right-handed).
    pub(super) fn rot_z(deg: f32) -> Mat3 {
        let (s, c) = deg.to_radians().sin_cos();
        Mat3([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    }

    /// The rotation of an [`ObjectDesc`](crate::scene_desc::ObjectDesc):
    /// about X first, then Y, then Z.
    pub(super) fn euler_xyz(deg: [f32; 3]) -> Mat3 {
        Mat3::rot_z(deg[2])
            .mul(&Mat3::rot_y(deg[1]))
            .mul(&Mat3::rot_x(deg[0]))
    }

    /// Matrix product `self * other` (apply `other` first).
    pub(super) fn mul(&self, other: &Mat3) -> Mat3 {
        let mut out = [[0.0f32; 3]; 3];
        for (r, row) in out.iter_mut().enumerate() {
            for (c, cell) in row.iter_mut().enumerate() {
                *cell = (0..3).map(|k| self.0[r][k] * other.0[k][c]).sum();
            }
        }
        Mat3(out)
    }

    /// `self * v`.
    pub(super) fn apply(&self, v: V3) -> V3 {
        [dot(self.0[0], v), dot(self.0[1], v), dot(self.0[2], v)]
    }
}

/// Placement of a part: scale per axis (all positive), then rotate, then
/// translate.
#[derive(Clone, Copy, Debug)]
pub(super) struct Placement {
    pub(super) scale: V3,
    pub(super) rotation: Mat3,
    pub(super) offset: V3,
}

impl Placement {
    /// A pure translation.
    pub(super) fn at(offset: V3) -> Placement {
        Placement {
            scale: [1.0; 3],
            rotation: Mat3::IDENTITY,
            offset,
        }
    }

    /// This placement with another rotation.
    pub(super) fn rotated(mut self, rotation: Mat3) -> Placement {
        self.rotation = rotation;
        self
    }

    /// This placement with a per-axis scale.
    pub(super) fn scaled(mut self, scale: V3) -> Placement {
        self.scale = scale;
        self
    }

    fn point(&self, p: V3) -> V3 {
        let s = [
            p[0] * self.scale[0],
            p[1] * self.scale[1],
            p[2] * self.scale[2],
        ];
        add(self.rotation.apply(s), self.offset)
    }

    /// Normals go through the inverse transpose: divide by the scale, rotate.
    fn normal(&self, n: V3) -> V3 {
        let s = [
            n[0] / self.scale[0],
            n[1] / self.scale[1],
            n[2] / self.scale[2],
        ];
        normalize(self.rotation.apply(s)).unwrap_or(n)
    }
}

/// Collects vertices and triangles into a [`MeshData`].
#[derive(Default)]
pub(super) struct MeshBuilder {
    mesh: MeshData,
}

impl MeshBuilder {
    pub(super) fn new() -> MeshBuilder {
        MeshBuilder::default()
    }

    /// The index the next vertex will get.
    pub(super) fn next_index(&self) -> u32 {
        self.mesh.positions.len() as u32
    }

    /// Adds a vertex (the normal is normalized here) and returns its index.
    pub(super) fn vertex(&mut self, position: V3, normal: V3) -> u32 {
        let index = self.mesh.positions.len() as u32;
        self.mesh.positions.push(position);
        self.mesh
            .normals
            .push(normalize(normal).unwrap_or([0.0, 1.0, 0.0]));
        index
    }

    /// Adds a triangle as given.
    pub(super) fn tri(&mut self, a: u32, b: u32, c: u32) {
        self.mesh.triangles.push([a, b, c]);
    }

    /// Adds a triangle wound so that it is counter-clockwise when seen from
    /// the side `outward` points to.
    pub(super) fn tri_facing(&mut self, a: u32, b: u32, c: u32, outward: V3) {
        let p = &self.mesh.positions;
        let n = tri_normal(p[a as usize], p[b as usize], p[c as usize]);
        if dot(n, outward) < 0.0 {
            self.tri(a, c, b);
        } else {
            self.tri(a, b, c);
        }
    }

    /// Adds a flat convex polygon (a fan from its first corner) with its own
    /// vertices, all carrying the face normal; the face is turned to look
    /// away from `inside`.
    pub(super) fn flat_face(&mut self, corners: &[V3], inside: V3) {
        let center = mul(
            corners.iter().fold([0.0; 3], |acc, &c| add(acc, c)),
            1.0 / corners.len() as f32,
        );
        // Newell's method: robust for slightly non-planar quads.
        let mut n = [0.0f32; 3];
        for (i, &a) in corners.iter().enumerate() {
            let b = corners[(i + 1) % corners.len()];
            n = add(n, cross(a, b));
        }
        if dot(n, sub(center, inside)) < 0.0 {
            n = mul(n, -1.0);
        }
        let first = self.mesh.positions.len() as u32;
        for &c in corners {
            self.vertex(c, n);
        }
        for k in 1..corners.len() as u32 - 1 {
            self.tri_facing(first, first + k, first + k + 1, n);
        }
    }

    /// Appends a whole mesh, moved into place by `placement`.
    pub(super) fn append(&mut self, part: &MeshData, placement: &Placement) {
        let base = self.mesh.positions.len() as u32;
        for (&p, &n) in part.positions.iter().zip(&part.normals) {
            self.mesh.positions.push(placement.point(p));
            self.mesh.normals.push(placement.normal(n));
        }
        for t in &part.triangles {
            self.tri(base + t[0], base + t[1], base + t[2]);
        }
    }

    pub(super) fn finish(self) -> MeshData {
        self.mesh
    }
}
