//! Tessellation of the Bezier teapot into triangles.

use std::collections::HashMap;

use super::geom::{add, cross, dot, mul, normalize, sub, V3};
use super::teapot_data::{PATCHES, POINTS};
use crate::scene_desc::MeshData;

/// The cubic Bernstein polynomials at `t`.
fn bernstein(t: f32) -> [f32; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t]
}

/// Derivatives of the cubic Bernstein polynomials at `t`.
fn bernstein_deriv(t: f32) -> [f32; 4] {
    let s = 1.0 - t;
    [
        -3.0 * s * s,
        3.0 * s * s - 6.0 * t * s,
        6.0 * t * s - 3.0 * t * t,
        3.0 * t * t,
    ]
}

/// One bicubic patch; `cp[4 * i + j]`, where `j` runs along the rows of the
/// classic listing (parameter `v`) and `i` from row to row (parameter `u`).
struct Patch {
    cp: [V3; 16],
}

impl Patch {
    /// Weighted sum of the control points: `sum wu[i] * wv[j] * cp[i][j]`.
    /// Rows are summed first, so a boundary row or column reproduces exactly
    /// the same floats in both patches that share it.
    fn combine(&self, wu: [f32; 4], wv: [f32; 4]) -> V3 {
        let mut out = [0.0; 3];
        for (i, &a) in wu.iter().enumerate() {
            let mut row = [0.0; 3];
            for (j, &b) in wv.iter().enumerate() {
                row = add(row, mul(self.cp[4 * i + j], b));
            }
            out = add(out, mul(row, a));
        }
        out
    }

    fn point(&self, u: f32, v: f32) -> V3 {
        self.combine(bernstein(u), bernstein(v))
    }

    /// `dP/du x dP/dv` at `(u, v)`, not normalized (zero at a collapsed
    /// edge).
    fn raw_normal(&self, u: f32, v: f32) -> V3 {
        let du = self.combine(bernstein_deriv(u), bernstein(v));
        let dv = self.combine(bernstein(u), bernstein_deriv(v));
        cross(du, dv)
    }

    /// The unit normal at `(u, v)` along `dP/du x dP/dv`. Where that
    /// vanishes (an edge collapsed to a point, like the top of the lid), the
    /// parameters are moved a little towards the middle of the patch until
    /// the surface is regular again.
    fn normal(&self, u: f32, v: f32) -> V3 {
        let mut inset = 0.0f32;
        loop {
            let uu = u + (0.5 - u) * inset;
            let vv = v + (0.5 - v) * inset;
            let n = self.raw_normal(uu, vv);
            // Control points are of order 1, so |n| is too where the patch
            // is regular; anything tiny means a degenerate point.
            if length_sq(n) > 1e-10 {
                if let Some(n) = normalize(n) {
                    return n;
                }
            }
            inset = if inset == 0.0 { 1e-3 } else { inset * 4.0 };
            if inset > 1.0 {
                return [0.0, 1.0, 0.0];
            }
        }
    }

    /// +1 if `dP/du x dP/dv` points out of the teapot, -1 if it points in.
    ///
    /// Decided from the flux of `p - center` through the patch: for a
    /// closed surface around `center` it is three times the enclosed volume,
    /// positive with outward normals. The teapot's patches are pieces of
    /// such surfaces (the body, lid and bottom around the axis; the handle
    /// and the spout are tubes split along the symmetry plane `y = 0`, where
    /// `p - center` is tangent), so the sign carries over to every patch.
    fn outward_sign(&self, center: V3) -> f32 {
        const STEPS: usize = 8;
        let mut flux = 0.0;
        for a in 0..STEPS {
            for b in 0..STEPS {
                let u = (a as f32 + 0.5) / STEPS as f32;
                let v = (b as f32 + 0.5) / STEPS as f32;
                flux += dot(sub(self.point(u, v), center), self.raw_normal(u, v));
            }
        }
        if flux < 0.0 {
            -1.0
        } else {
            1.0
        }
    }
}

fn length_sq(a: V3) -> f32 {
    dot(a, a)
}

/// The control points turned Y-up (classic +Z becomes +Y, classic +Y
/// becomes -Z: a proper rotation, so windings are kept), centered on their
/// bounding box and scaled so that every control point, and with them the
/// whole surface (convex hull property), lies within radius 1 of the origin.
fn control_points() -> Vec<V3> {
    let turned: Vec<V3> = POINTS.iter().map(|p| [p[0], p[2], -p[1]]).collect();
    let mut lo = [f32::MAX; 3];
    let mut hi = [f32::MIN; 3];
    for p in &turned {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let center = mul(add(lo, hi), 0.5);
    let radius = turned
        .iter()
        .map(|&p| length_sq(sub(p, center)))
        .fold(0.0f32, f32::max)
        .sqrt();
    // A hair under 1 so rounding cannot push a point past the unit sphere.
    let k = 0.999 / radius;
    turned
        .into_iter()
        .map(|p| {
            let q = mul(sub(p, center), k);
            // `+ 0.0` folds -0.0 into 0.0 so equal seam points compare equal.
            [q[0] + 0.0, q[1] + 0.0, q[2] + 0.0]
        })
        .collect()
}

/// Reference point inside the body on its axis, for [`Patch::outward_sign`]:
/// the classic point (0, 0, 1.5), carried through [`control_points`]'s
/// transformation.
fn body_center(points: &[V3]) -> V3 {
    // Classic points 269 (0, 0, 0) and 203 (0, 0, 3.15) are the bottom and
    // top of the axis; interpolate to height 1.5.
    let bottom = points[269];
    let top = points[203];
    add(bottom, mul(sub(top, bottom), 1.5 / 3.15))
}

/// The teapot, each patch cut into `n` x `n` quads (two triangles each), so
/// `32 * n * n * 2` triangles. Vertices shared by neighbouring patches are
/// merged when their normals agree too.
pub(super) fn teapot(n: u32) -> MeshData {
    let points = control_points();
    let center = body_center(&points);
    let mut mesh = MeshData::default();
    // Exact position bits -> merged vertices there: (index, normal sum,
    // last patch that merged into it).
    let mut seam: HashMap<[u32; 3], Vec<(u32, V3, usize)>> = HashMap::new();
    let side = n as usize + 1;
    for (patch_index, indices) in PATCHES.iter().enumerate() {
        let patch = Patch {
            cp: std::array::from_fn(|k| points[indices[k] as usize]),
        };
        let sign = patch.outward_sign(center);
        let mut grid = Vec::with_capacity(side * side);
        for a in 0..side {
            let u = a as f32 / n as f32;
            for b in 0..side {
                let v = b as f32 / n as f32;
                let p = patch.point(u, v);
                let normal = mul(patch.normal(u, v), sign);
                let key = p.map(f32::to_bits);
                let entries = seam.entry(key).or_default();
                let merged = entries.iter_mut().find(|(_, sum, last)| {
                    *last != patch_index && normalize(*sum).is_some_and(|s| dot(s, normal) > 0.995)
                });
                let index = match merged {
                    Some((index, sum, last)) => {
                        *sum = add(*sum, normal);
                        *last = patch_index;
                        *index
                    }
                    None => {
                        let index = mesh.positions.len() as u32;
                        mesh.positions.push(p);
                        mesh.normals.push(normal);
                        entries.push((index, normal, patch_index));
                        index
                    }
                };
                grid.push(index);
            }
        }
        // Quad (a, b) .. (a + 1, b + 1): along +u then +v is counter-clockwise
        // around dP/du x dP/dv.
        for a in 0..n as usize {
            for b in 0..n as usize {
                let p00 = grid[a * side + b];
                let p10 = grid[(a + 1) * side + b];
                let p11 = grid[(a + 1) * side + b + 1];
                let p01 = grid[a * side + b + 1];
                if sign > 0.0 {
                    mesh.triangles.push([p00, p10, p11]);
                    mesh.triangles.push([p00, p11, p01]);
                } else {
                    mesh.triangles.push([p00, p11, p10]);
                    mesh.triangles.push([p00, p01, p11]);
                }
            }
        }
    }
    // Merged vertices take the average of their normals.
    for entries in seam.values() {
        for &(index, sum, _) in entries {
            if let Some(nrm) = normalize(sum) {
                mesh.normals[index as usize] = nrm;
            }
        }
    }
    mesh
}

#[cfg(test)]
pub(super) fn patch_signs() -> Vec<f32> {
    let points = control_points();
    let center = body_center(&points);
    PATCHES
        .iter()
        .map(|indices| {
            Patch {
                cp: std::array::from_fn(|k| points[indices[k] as usize]),
            }
            .outward_sign(center)
        })
        .collect()
}
