//! Desktop simulator for the `mcu_abuffer` renderer: scene loading, built-in
//! scenes, image output and the measurement tools.
//!
//! The `cli` feature (on by default) adds the `host-sim` program and the
//! modules behind its commands: image and GIF output, comparisons, sweeps,
//! fitting and tuning. Without it the library is scene conversion and the
//! renderings (`convert`, `render`, `ssaa`, `memory`, `heat`, `plot`).
#![warn(missing_docs)]

pub use abuffer_scenes::{builtins, obj, scene_desc, scene_file};

#[cfg(feature = "cli")]
pub mod animate;
#[cfg(feature = "cli")]
pub mod bounded;
#[cfg(feature = "cli")]
pub mod compare;
#[cfg(feature = "cli")]
pub mod complexity;
pub mod convert;
#[cfg(feature = "cli")]
pub mod fit;
pub mod heat;
#[cfg(feature = "cli")]
pub mod image_io;
pub mod memory;
pub mod plot;
pub mod render;
#[cfg(feature = "cli")]
pub mod shading_compare;
pub mod ssaa;
#[cfg(feature = "cli")]
pub mod sweep;
#[cfg(feature = "cli")]
pub mod tune;
#[cfg(feature = "cli")]
pub mod zbuffer_table;

use scene_desc::SceneDesc;
use std::path::Path;

/// The scene `spec` names: a scene file (`.toml`, or any existing path) or a
/// built-in scene, at `width` x `height` when given (a built-in's default is
/// 240x240). An error names the file and line of a malformed scene, or lists
/// the built-ins for an unknown name.
pub fn load_scene(
    spec: &str,
    width: Option<u32>,
    height: Option<u32>,
) -> Result<SceneDesc, String> {
    let mut desc = if spec.ends_with(".toml") || Path::new(spec).exists() {
        scene_file::load_scene_file(Path::new(spec)).map_err(|e| e.to_string())?
    } else {
        let w = width.unwrap_or(240);
        let h = height.unwrap_or(240);
        builtins::builtin_scene(spec, w, h).ok_or_else(|| {
            format!(
                "'{spec}' is neither a scene file nor a built-in scene (built-ins: {})",
                builtins::BUILTIN_SCENES.join(", ")
            )
        })?
    };
    if let Some(w) = width {
        desc.width = w;
    }
    if let Some(h) = height {
        desc.height = h;
    }
    if !(1..=2048).contains(&desc.width) || !(1..=2048).contains(&desc.height) {
        return Err(format!(
            "image size {}x{} is outside 1..=2048",
            desc.width, desc.height
        ));
    }
    Ok(desc)
}
