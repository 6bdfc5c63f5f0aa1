//! The one conversion from the scenes' `f32` values to the renderer's fixed-point
//! bits. host-sim and the firmware build script both use it, so a scene loaded on
//! the desktop and the same scene baked into flash are the same bits.

use crate::scene_desc::{SceneDesc, ShadingDesc};
use fixed::types::{I16F16, I2F14};

/// Largest model coordinate magnitude accepted (leaves headroom in Q16.16).
pub const MAX_MODEL_COORDINATE: f32 = 16384.0;

/// `v` as Q16.16 bits, rounded to nearest, saturated; NaN (which has no value)
/// becomes 0. [`check_convertible`] refuses scenes with either.
pub fn coord_bits(v: f32) -> i32 {
    if v.is_nan() {
        return 0;
    }
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
    let unit = if len > 0.0 && len.is_finite() {
        n.map(|c| c / len)
    } else {
        [0.0, 0.0, 1.0]
    };
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

/// The largest magnitude a camera, light or placement value may have: the
/// Q16.16 range, so no value is saturated on the way to fixed point.
pub const MAX_FIXED_VALUE: f32 = 32767.0;

/// Checks what the fixed-point form needs: finite coordinates within
/// [`MAX_MODEL_COORDINATE`], one normal per position, and finite camera, light
/// and placement values within [`MAX_FIXED_VALUE`] (NaN has no fixed-point
/// value, and larger ones would saturate silently). Errors name the value.
pub fn check_convertible(desc: &SceneDesc) -> Result<(), String> {
    let in_range = |what: &str, values: &[f32]| match values
        .iter()
        .find(|v| !v.is_finite() || v.abs() > MAX_FIXED_VALUE)
    {
        Some(v) => Err(format!(
            "{what}: {v} is not a finite number within ±{MAX_FIXED_VALUE}"
        )),
        None => Ok(()),
    };
    let c = &desc.camera;
    in_range("camera eye", &c.eye)?;
    in_range("camera target", &c.target)?;
    in_range("camera up", &c.up)?;
    in_range(
        "camera fov_y_deg, near and far",
        &[c.fov_y_deg, c.near, c.far],
    )?;
    if let Some(l) = &desc.light {
        in_range("light direction", &l.direction)?;
        in_range(
            "light ambient, diffuse, specular and shininess",
            &[l.ambient, l.diffuse, l.specular, l.shininess],
        )?;
    }
    for (i, o) in desc.objects.iter().enumerate() {
        let what = format!("object {i} ({})", o.mesh_name);
        in_range(&format!("{what} position"), &o.position)?;
        in_range(&format!("{what} rotation_deg"), &o.rotation_deg)?;
        in_range(&format!("{what} scale"), &[o.scale])?;
    }
    for (i, o) in desc.objects.iter().enumerate() {
        let m = &o.mesh;
        if let Some(p) = m
            .positions
            .iter()
            .flatten()
            .find(|c| !c.is_finite() || c.abs() > MAX_MODEL_COORDINATE)
        {
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
