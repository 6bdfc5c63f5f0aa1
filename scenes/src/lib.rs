//! Scenes for the `mcu_abuffer` renderer in their floating-point form: the TOML
//! scene format, Wavefront OBJ meshes and the built-in scenes.
//!
//! This crate has no dependency on the renderer, so the firmware's build script can
//! use it to bake a scene into flash, and host-sim uses it to load scenes.
#![warn(missing_docs)]

pub mod bake;
pub mod builtins;
pub mod fixed_bits;
pub mod obj;
pub mod openings;
pub mod scene_desc;
pub mod scene_file;
mod wide_vector;
