//! The one conversion from the scenes' `f32` values to the renderer's fixed-point
//! bits. host-sim and the firmware build script both use it, so a scene loaded on
//! the desktop and the same scene baked into flash are the same bits.

use crate::scene_desc::{SceneDesc, ShadingDesc};
use fixed::types::{I16F16, I2F14};

/// Largest model coordinate magnitude accepted (leaves headroom in Q16.16).
pub const MAX_MODEL_COORDINATE: f32 = 16384.0;

/// `v` as Q16.16 bits, rounded to nearest, saturated.
pub fn coord_bits(v: f32) -> i32 {
    I16F16::saturating_from_num(v).to_bits()
}

/// A vector as Q16.16 bits.
pub fn coord3_bits(v: [f32; 3]) -> [i32; 3] {
    v.map(coord_bits)
}

/// A normal, renormalized in `f32` and stored as Q2.14 bits; a zero or non-finite
/// normal becomes +Z.
pub fn normal_bits(n: [f32; 3]) -> [i16; 3] {
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let unit = if len > 0.0 && len.is_finite() { n.map(|c| c / len) } else { [0.0, 0.0, 1.0] };
    unit.map(|c| I2F14::saturating_from_num(c).to_bits())
}

/// The shading of an object as the renderer's mode name, resolving the default
/// (quadratic when the scene has a light, unlit otherwise).
pub fn resolve_shading(shading: Option<ShadingDesc>, has_light: bool) -> ShadingDesc {
    match (shading, has_light) {
        (Some(s), _) => s,
        (None, false) => ShadingDesc::Unlit,
        (None, true) => ShadingDesc::Quadratic,
    }
}

/// Checks what the fixed-point form needs: finite coordinates within
/// [`MAX_MODEL_COORDINATE`] and one normal per position. Errors name the object.
pub fn check_convertible(desc: &SceneDesc) -> Result<(), String> {
    for (i, o) in desc.objects.iter().enumerate() {
        let m = &o.mesh;
        if let Some(p) = m.positions.iter().flatten().find(|c| !c.is_finite() || c.abs() > MAX_MODEL_COORDINATE) {
            return Err(format!(
                "object {i} ({}): coordinate {p} is not finite or beyond ±{MAX_MODEL_COORDINATE}",
                o.mesh_name
            ));
        }
        if m.normals.len() != m.positions.len() {
            return Err(format!(
                "object {i} ({}): {} normals for {} positions",
                o.mesh_name,
                m.normals.len(),
                m.positions.len()
            ));
        }
    }
    Ok(())
}
