//! Desktop simulator for the `mcu_abuffer` renderer: scene loading, built-in
//! scenes, image output and the measurement tools.
#![warn(missing_docs)]

pub mod builtins;
pub mod convert;
pub mod image_io;
pub mod obj;
pub mod render;
pub mod scene_desc;
pub mod scene_file;
