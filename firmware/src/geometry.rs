//! Geometry in fixed point: model, view and projection transforms, outcodes,
//! the perspective divide and the viewport (SPEC section 1).
//!
//! Matrices are composed once per object per frame in 128-bit Q32 arithmetic, then
//! reduced to a [`ClipTransform`] of 32-bit entries with a common per-object scale.
//! The viewport is folded into the projection, so the transform yields
//! `(X, Y, Zs, w)` with window coordinates `x_w = X / w`, `y_w = Y / w` and window
//! depth `z_w = Zs / w`. A common scale of all four cancels in those divisions and
//! in every clip test, which is why each object may pick its own.

use crate::fixed_point::{
    isqrt_u64, sin_cos_deg, Coord, Reciprocal, DEPTH_BITS, DEPTH_MAX, GUARD_BAND_PX, SUBPIXEL_BITS,
    UNIT_BITS,
};
use crate::scene::{Camera, Transform};

type Vec3Q30 = [i64; 3];
/// A 3x4 affine matrix, Q32 entries.
type AffineQ32 = [[i128; 4]; 3];

const Q32: i128 = 1 << 32;

/// Normalizes a Q16 vector to Q30; `None` for the zero vector.
///
/// Components may reach 2^32 in magnitude (differences of two Q16.16 points), so
/// a vector is first shifted right until every component is below 2^31: the
/// three squares then sum below 2^64, and the direction is unchanged.
fn normalize_q16(v: [i64; 3]) -> Option<Vec3Q30> {
    let largest = v.iter().fold(0u64, |m, c| m | c.unsigned_abs());
    let v = v.map(|c| c >> (64 - largest.leading_zeros()).saturating_sub(31));
    let len2: u64 = v.iter().map(|c| (c * c) as u64).sum();
    let len = isqrt_u64(len2) as i64; // Q16
    if len == 0 {
        return None;
    }
    Some(v.map(|c| ((c as i128) << 30).div_euclid(len as i128) as i64))
}

fn cross_q30(a: Vec3Q30, b: Vec3Q30) -> [i64; 3] {
    // Q30 x Q30 = Q60, reduced to Q16 for renormalization.
    let c = |x: i64, y: i64, z: i64, w: i64| {
        (((x as i128) * (y as i128) - (z as i128) * (w as i128)) >> 44) as i64
    };
    [
        c(a[1], b[2], a[2], b[1]),
        c(a[2], b[0], a[0], b[2]),
        c(a[0], b[1], a[1], b[0]),
    ]
}

fn to_q16(v: &[Coord; 3]) -> [i64; 3] {
    v.map(|c| c.to_bits() as i64)
}

/// The camera's orthonormal basis: side `s`, up `u`, forward `f`, in Q30.
#[derive(Clone, Copy, Debug)]
pub struct ViewBasis {
    side: Vec3Q30,
    up: Vec3Q30,
    forward: Vec3Q30,
    eye: [i64; 3],
}

impl ViewBasis {
    /// The basis of a look-at camera; `None` if eye equals target or up is
    /// parallel to the view direction.
    pub fn new(camera: &Camera) -> Option<Self> {
        let eye = to_q16(&camera.eye);
        let target = to_q16(&camera.target);
        let forward = normalize_q16([target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]])?;
        let up_in = normalize_q16(to_q16(&camera.up))?;
        let side = normalize_q16(cross_q30(forward, up_in))?;
        // Both inputs are unit and orthogonal: the cross product is unit up to rounding.
        let up = normalize_q16(cross_q30(side, forward))?;
        Some(Self {
            side,
            up,
            forward,
            eye,
        })
    }

    /// The view rotation rows (side, up, -forward) in Q30.
    pub(crate) fn rotation_rows(&self) -> [[i64; 3]; 3] {
        [self.side, self.up, self.forward.map(|c| -c)]
    }
}

/// Rotation about X, then Y, then Z (`Rz Ry Rx`), Q30.
fn rotation_xyz(deg: &[Coord; 3]) -> [[i64; 3]; 3] {
    let (sx, cx) = sin_cos_deg(deg[0]);
    let (sy, cy) = sin_cos_deg(deg[1]);
    let (sz, cz) = sin_cos_deg(deg[2]);
    let one = 1i64 << 30;
    let rx = [
        [one, 0, 0],
        [0, cx as i64, -(sx as i64)],
        [0, sx as i64, cx as i64],
    ];
    let ry = [
        [cy as i64, 0, sy as i64],
        [0, one, 0],
        [-(sy as i64), 0, cy as i64],
    ];
    let rz = [
        [cz as i64, -(sz as i64), 0],
        [sz as i64, cz as i64, 0],
        [0, 0, one],
    ];
    mul3(&rz, &mul3(&ry, &rx))
}

/// Rotation about the world Y axis, Q30.
fn rotation_y(deg: Coord) -> [[i64; 3]; 3] {
    rotation_xyz(&[Coord::ZERO, deg, Coord::ZERO])
}

fn mul3(a: &[[i64; 3]; 3], b: &[[i64; 3]; 3]) -> [[i64; 3]; 3] {
    let mut r = [[0i64; 3]; 3];
    for (i, row) in r.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            let s: i128 = (0..3).map(|k| a[i][k] as i128 * b[k][j] as i128).sum();
            *v = ((s + (1 << 29)) >> 30) as i64;
        }
    }
    r
}

fn compose(a: &AffineQ32, b: &AffineQ32) -> AffineQ32 {
    let mut r = [[0i128; 4]; 3];
    for i in 0..3 {
        for j in 0..4 {
            let mut s: i128 = (0..3).map(|k| (a[i][k] * b[k][j]) >> 32).sum();
            if j == 3 {
                s += a[i][3];
            }
            r[i][j] = s;
        }
    }
    r
}

/// Per-object transform from model space to scaled clip space `(X, Y, Zs, w)`.
///
/// `rows` are 32-bit entries, `offsets` the translation column at the matching
/// scale: for a Q16 model position `v`, `c_i = sum_j rows[i][j] v_j + offsets[i]`.
/// Entries stay within ±2^27 and offsets within ±2^59, so for model
/// coordinates within the Q16.16 range every `c_i` fits in an `i64`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClipTransform {
    /// Linear part, rows X, Y, Zs, w.
    pub rows: [[i32; 3]; 4],
    /// Translation part.
    pub offsets: [i64; 4],
}

/// Everything the renderer needs to place one object in one frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ObjectTransform {
    /// Model space to clip space.
    pub clip: ClipTransform,
    /// Model-space normals to eye-space normals, Q2.14 (rotation only).
    pub normal: [[i32; 3]; 3],
}

impl ObjectTransform {
    /// The transform of an object with `transform`, turned by `turntable_deg` about
    /// the world Y axis, seen by `camera` into a `width x height` image.
    pub fn new(
        camera: &Camera,
        view: &ViewBasis,
        width: u16,
        height: u16,
        transform: &Transform,
        turntable_deg: Coord,
    ) -> Self {
        // Model: T * Rturn * R * S.
        let rot = mul3(
            &rotation_y(turntable_deg),
            &rotation_xyz(&transform.rotation_deg),
        );
        let scale = transform.scale.to_bits() as i128; // Q16
        let pos = to_q16(&transform.position);
        let turn = rotation_y(turntable_deg);
        let mut model: AffineQ32 = [[0; 4]; 3];
        for i in 0..3 {
            for j in 0..3 {
                model[i][j] = (rot[i][j] as i128 * scale) >> 14; // Q30*Q16 = Q46 -> Q32
            }
            // The turntable turns the placed object about the world origin.
            let t: i128 = (0..3)
                .map(|k| turn[i][k] as i128 * pos[k] as i128)
                .sum::<i128>()
                >> 14;
            model[i][3] = t;
        }
        // View: rows s, u, -f and translation -R eye.
        let vrot = view.rotation_rows();
        let mut viewm: AffineQ32 = [[0; 4]; 3];
        for i in 0..3 {
            for j in 0..3 {
                viewm[i][j] = (vrot[i][j] as i128) << 2;
            }
            let d: i128 = (0..3)
                .map(|k| vrot[i][k] as i128 * view.eye[k] as i128)
                .sum();
            viewm[i][3] = -(d >> 14);
        }
        let mv = compose(&viewm, &model);
        // Projection with the viewport folded in (see module docs).
        let (s, c) = sin_cos_deg(camera.fov_y_deg / 2);
        let f = ((c as i128) << 32) / s as i128; // cot(fov/2), Q32
        let half_w = (width as i128) * Q32 / 2;
        let half_h = (height as i128) * Q32 / 2;
        let hf = (half_h * f) >> 32;
        let near = camera.near.to_bits() as i128;
        let far = camera.far.to_bits() as i128;
        let a = (far << 32) / (near - far);
        let b = ((far * near) << 16) / (near - far);
        let (xe, ye, ze) = (mv[0], mv[1], mv[2]);
        let mut clip = [[0i128; 4]; 4];
        for j in 0..4 {
            clip[0][j] = ((hf * xe[j]) >> 32) - ((half_w * ze[j]) >> 32);
            clip[1][j] = -((hf * ye[j]) >> 32) - ((half_h * ze[j]) >> 32);
            clip[2][j] = (a * ze[j]) >> 32;
            clip[3][j] = -ze[j];
        }
        clip[2][3] += b;
        // Common scale: linear entries within ±2^27, offsets within ±2^59.
        let max_lin = clip
            .iter()
            .flat_map(|r| r[..3].iter())
            .map(|v| v.unsigned_abs())
            .max()
            .unwrap_or(0);
        let max_off = clip.iter().map(|r| r[3].unsigned_abs()).max().unwrap_or(0);
        let bits = |v: u128| 128 - v.leading_zeros() as i32;
        // Linear entries are Q32; shifting right by `sh` gives Q(32 - sh), and the
        // offset must then be in Q(48 - sh) to match products with Q16 positions.
        let sh = (bits(max_lin) - 27).max(bits(max_off) + 16 - 59).max(-16);
        let scale_down = |v: i128, by: i32| if by >= 0 { v >> by } else { v << -by };
        let mut out = ClipTransform {
            rows: [[0; 3]; 4],
            offsets: [0; 4],
        };
        for i in 0..4 {
            for j in 0..3 {
                out.rows[i][j] = scale_down(clip[i][j], sh) as i32;
            }
            out.offsets[i] = scale_down(clip[i][3], sh - 16) as i64;
        }
        // Eye-space normal matrix, Q14.
        let nm = mul3(&vrot, &rot);
        let normal = nm.map(|r| r.map(|v| ((v + (1 << 15)) >> 16) as i32));
        Self { clip: out, normal }
    }

    /// Model-space position to scaled clip space `[X, Y, Zs, w]`.
    ///
    /// Range: each component is at most `3 * 2^27 * 2^31 + 2^59 < 2^61` in
    /// magnitude for any [`Coord`] position (entries within ±2^27, offsets within
    /// ±2^59), so the three products and the sum fit `i64`. Outcodes and the
    /// divide shift a vertex down to 38 bits first, clipping shifts a triangle.
    #[inline]
    pub fn to_clip(&self, p: &[Coord; 3]) -> [i64; 4] {
        let v = [
            p[0].to_bits() as i64,
            p[1].to_bits() as i64,
            p[2].to_bits() as i64,
        ];
        let r = &self.clip.rows;
        let o = &self.clip.offsets;
        let row =
            |i: usize| r[i][0] as i64 * v[0] + r[i][1] as i64 * v[1] + r[i][2] as i64 * v[2] + o[i];
        [row(0), row(1), row(2), row(3)]
    }

    /// Model-space normal (Q2.14) to eye space (Q2.14).
    #[inline]
    pub fn normal_to_eye(&self, n: &[i32; 3]) -> [i32; 3] {
        let m = &self.normal;
        let row = |i: usize| {
            (m[i][0] * n[0] + m[i][1] * n[1] + m[i][2] * n[2] + (1 << (UNIT_BITS - 1))) >> UNIT_BITS
        };
        [row(0), row(1), row(2)]
    }
}

/// Outcode bit: in front of the near plane (`Zs < 0`).
pub const OUT_NEAR: u8 = 1;
/// Outcode bit: beyond the far plane (`Zs > w`).
pub const OUT_FAR: u8 = 2;
/// Outcode bit: left of the guard band.
pub const OUT_LEFT: u8 = 4;
/// Outcode bit: right of the guard band.
pub const OUT_RIGHT: u8 = 8;
/// Outcode bit: above the guard band.
pub const OUT_TOP: u8 = 16;
/// Outcode bit: below the guard band.
pub const OUT_BOTTOM: u8 = 32;

/// Shifts a clip-space vertex right so every component is at most 2^38 in
/// magnitude (positive ones below it, so `z << 25` in [`project`] fits `i64`).
/// Window coordinates and clip tests are ratios, so they do not change.
#[inline]
fn normalize_clip(c: &[i64; 4]) -> [i64; 4] {
    let m = c.iter().fold(0u64, |m, v| m | v.unsigned_abs());
    let bits = 64 - m.leading_zeros() as i32;
    let sh = bits - 38;
    if sh > 0 {
        c.map(|v| v >> sh)
    } else {
        *c
    }
}

/// Which clip planes a scaled clip-space vertex is outside of.
#[inline]
pub fn outcode(c: &[i64; 4]) -> u8 {
    outcode_of(&normalize_clip(c))
}

/// A vertex's [`outcode`] and, when that is zero, its window position
/// ([`project`]; zeros outside the view volume): the clip-space vertex is
/// brought into range once for both.
#[inline]
pub fn outcode_and_project(c: &[i64; 4]) -> (u8, (i32, i32, u32)) {
    let normalized = normalize_clip(c);
    let code = outcode_of(&normalized);
    let window = if code == 0 {
        project_inside(&normalized)
    } else {
        (0, 0, 0)
    };
    (code, window)
}

/// [`outcode`] of a vertex [`normalize_clip`] has brought into range.
#[inline]
fn outcode_of(&[x, y, z, w]: &[i64; 4]) -> u8 {
    let g = w * GUARD_BAND_PX as i64;
    let mut code = 0;
    if z < 0 {
        code |= OUT_NEAR;
    }
    if z > w {
        code |= OUT_FAR;
    }
    if x < -g {
        code |= OUT_LEFT;
    }
    if x > g {
        code |= OUT_RIGHT;
    }
    if y < -g {
        code |= OUT_TOP;
    }
    if y > g {
        code |= OUT_BOTTOM;
    }
    code
}

/// Window position of a vertex inside the view volume: `x`, `y` in 1/16 pixel
/// (rounded to nearest, clamped to the guard band) and depth with 24 fraction bits.
///
/// The vertex must have `w > 0` (true for every vertex on the inside of the near plane).
#[inline]
pub fn project(c: &[i64; 4]) -> (i32, i32, u32) {
    project_normalized(&normalize_clip(c))
}

/// [`project`] of a vertex [`normalize_clip`] has brought into range.
#[inline]
fn project_normalized(&[x, y, z, w]: &[i64; 4]) -> (i32, i32, u32) {
    // One reciprocal per vertex instead of three 64-bit divisions; the
    // components are at most 2^38, so the quotients times 2^24 fit.
    let w = Reciprocal::new(w.max(1) as u64);
    let lim = (GUARD_BAND_PX as i64) << SUBPIXEL_BITS;
    // A vertex inside the view volume lands within the guard band and the
    // depth range: one unsigned comparison says so, where the clamp takes
    // two 64-bit comparisons and their selects.
    let clamped = |q: i64, low: i64, high: i64| {
        if (q.wrapping_sub(low) as u64) <= (high - low) as u64 {
            q
        } else {
            q.clamp(low, high)
        }
    };
    let rounded = |n: i64| (w.mul_div_large_divisor(n, SUBPIXEL_BITS + 1) + 1) >> 1;
    let div = |n: i64| clamped(rounded(n), -lim, lim) as i32;
    let depth = w.mul_div_round(z.max(0), DEPTH_BITS);
    (div(x), div(y), clamped(depth, 0, DEPTH_MAX as i64) as u32)
}

/// [`project_normalized`] of a vertex inside the view volume (outcode zero),
/// rounded and clamped in 32 bits: the same bits.
///
/// Range: the reciprocal of `w` is below `2 / w` (its normalized divisor is
/// below 2^32, its mantissa at most 2^32), and the vertex has `|x|, |y| <=
/// GUARD_BAND_PX w` and `0 <= z <= w`, so the quotients before rounding are
/// below `2^12 2^5 2 + 1 < 2^19` and `2^25 2 + 1 < 2^27` in magnitude: they
/// fit `i32` with room for the rounding's `+ 1`.
#[inline]
fn project_inside(&[x, y, z, w]: &[i64; 4]) -> (i32, i32, u32) {
    let w = Reciprocal::new(w.max(1) as u64);
    let lim = GUARD_BAND_PX << SUBPIXEL_BITS;
    let round = |q: i64| ((q as i32) + 1) >> 1;
    // In 32 bits a clamp is two comparisons and their selects.
    let clamped = |q: i32, low: i32, high: i32| q.clamp(low, high);
    let div = |n: i64| {
        clamped(
            round(w.mul_div_large_divisor(n, SUBPIXEL_BITS + 1)),
            -lim,
            lim,
        )
    };
    let depth = round(w.mul_div(z.max(0), DEPTH_BITS + 1));
    (div(x), div(y), clamped(depth, 0, DEPTH_MAX as i32) as u32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Camera;

    fn camera() -> Camera {
        Camera {
            eye: [Coord::ZERO, Coord::ZERO, Coord::from_num(4)],
            target: [Coord::ZERO; 3],
            up: [Coord::ZERO, Coord::ONE, Coord::ZERO],
            fov_y_deg: Coord::from_num(90),
            near: Coord::ONE,
            far: Coord::from_num(10),
        }
    }

    fn project_point(p: [f64; 3], w: u16, h: u16) -> (f64, f64, f64) {
        let cam = camera();
        let view = ViewBasis::new(&cam).unwrap();
        let t = ObjectTransform::new(&cam, &view, w, h, &Transform::default(), Coord::ZERO);
        let c = t.to_clip(&p.map(Coord::from_num));
        assert_eq!(outcode(&c), 0);
        let (x, y, z) = project(&c);
        (
            x as f64 / 16.0,
            y as f64 / 16.0,
            z as f64 / (1u64 << 24) as f64,
        )
    }

    #[test]
    fn matches_opengl_conventions() {
        // Origin is 4 units ahead: screen center; depth per gluPerspective.
        let (x, y, z) = project_point([0.0, 0.0, 0.0], 200, 100);
        assert!(
            (x - 100.0).abs() < 0.07 && (y - 50.0).abs() < 0.07,
            "{x} {y}"
        );
        let (n, f) = (1.0, 10.0);
        let ze: f64 = -4.0;
        let zndc = ((f + n) / (n - f) * ze + 2.0 * f * n / (n - f)) / -ze;
        assert!((z - (zndc + 1.0) / 2.0).abs() < 1e-6, "{z}");
        // fov 90, distance 4: y = 4 is the top edge; up in the world is up on screen.
        let (_, y, _) = project_point([0.0, 4.0, 0.0], 200, 100);
        assert!(y.abs() < 0.07, "{y}");
        // aspect 2: x = 8 is the right edge.
        let (x, _, _) = project_point([8.0, 0.0, 0.0], 200, 100);
        assert!((x - 200.0).abs() < 0.07, "{x}");
    }

    #[test]
    fn near_plane_and_guard_band_outcodes() {
        let cam = camera();
        let view = ViewBasis::new(&cam).unwrap();
        let t = ObjectTransform::new(&cam, &view, 100, 100, &Transform::default(), Coord::ZERO);
        let behind = t.to_clip(&[Coord::ZERO, Coord::ZERO, Coord::from_num(5)]);
        assert_ne!(outcode(&behind) & OUT_NEAR, 0);
        let far = t.to_clip(&[Coord::ZERO, Coord::ZERO, Coord::from_num(-20)]);
        assert_ne!(outcode(&far) & OUT_FAR, 0);
        let wide = t.to_clip(&[Coord::from_num(1000), Coord::ZERO, Coord::ZERO]);
        assert_ne!(outcode(&wide) & OUT_RIGHT, 0);
    }

    #[test]
    fn outcode_and_project_answer_as_the_two_calls() {
        let cam = camera();
        let view = ViewBasis::new(&cam).unwrap();
        let t = ObjectTransform::new(&cam, &view, 240, 240, &Transform::default(), Coord::ZERO);
        let mut seed = 0x1234_5678u32;
        let mut coordinate = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            // Within ±64 units: inside, beside, behind and beyond the view.
            Coord::from_bits((seed as i32) >> 9)
        };
        let mut inside = 0;
        for _ in 0..20_000 {
            let c = t.to_clip(&[coordinate(), coordinate(), coordinate()]);
            let code = outcode(&c);
            let window = if code == 0 { project(&c) } else { (0, 0, 0) };
            assert_eq!(outcode_and_project(&c), (code, window), "{c:?}");
            inside += (code == 0) as u32;
        }
        assert!(inside > 1_000, "{inside} inside");
    }
}
