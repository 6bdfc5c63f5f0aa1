//! Desktop simulator for the `mcu_abuffer` renderer: scene loading, built-in
//! scenes, image output and the measurement tools.
#![warn(missing_docs)]

pub use abuffer_scenes::{builtins, obj, scene_desc, scene_file};

pub mod animate;
pub mod bench;
pub mod bounded;
pub mod compare;
pub mod complexity;
pub mod convert;
pub mod fit;
pub mod heat;
pub mod image_io;
pub mod memory;
pub mod plot;
pub mod qemu;
pub mod render;
pub mod shading_compare;
pub mod ssaa;
pub mod sweep;
pub mod tune;
pub mod zbuffer_table;
