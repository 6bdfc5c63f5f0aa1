//! Desktop simulator for the `mcu_abuffer` renderer: scene loading, built-in
//! scenes, image output and the measurement tools.
#![warn(missing_docs)]

pub use abuffer_scenes::{builtins, obj, scene_desc, scene_file};

pub mod convert;
pub mod image_io;
pub mod render;
