//! The renderer through its device API: raw fixed-point scenes (every extreme of
//! `Coord` and of the unit type, any camera, light and transform, indices out of
//! range) straight into `mcu_abuffer::Scene`, with any legal buffer parameters.
//!
//! A scene the library rejects must be rejected with an error, never a panic; a
//! scene it accepts must render with every invariant of `render_checked` holding.
#![no_main]

use abuffer_fuzz::{device_scene, render_checked, BufferParams};
use libfuzzer_sys::arbitrary::Unstructured;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let mut u = Unstructured::new(data);
    let Ok(scene) = device_scene(&mut u) else {
        return;
    };
    let Ok(params) = BufferParams::decode(&mut u, scene.height) else {
        return;
    };
    let with_oracle = u.arbitrary::<bool>().unwrap_or(false);
    if std::env::var_os("FUZZ_PRINT").is_some() {
        eprintln!("{scene:#?}\n{params:?} oracle {with_oracle}");
    }
    let objects = scene.objects();
    let lib_scene = scene.scene(&objects);
    let valid = lib_scene.validate();
    if std::env::var_os("FUZZ_PRINT").is_some() {
        eprintln!("validate: {valid:?}");
    }
    if valid.is_err() {
        return;
    }
    render_checked(&lib_scene, &scene.options(), &params, with_oracle);
});
