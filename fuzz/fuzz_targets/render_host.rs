//! The renderer through its host API: a floating-point scene description with any
//! `f32` anywhere (NaN, infinities, subnormals, huge and tiny values) goes through
//! host-sim's conversion to fixed point and its `render`, then through the checked
//! harness with any legal buffer parameters.
//!
//! Conversion and rendering may refuse a scene with an error, never with a panic.
//! A scene that converts and validates must render through host-sim, and the
//! checked rendering with the same parameters must give the same image and
//! statistics. Some inputs also render with host-sim's other z-buffers: the
//! hierarchical one and one-sample supersampling must equal the plain z-buffer,
//! midpoint subdivision must repeat itself.
#![no_main]

use abuffer_fuzz::{host_scene, render_checked, BufferParams, Memory};
use host_sim::convert::to_fixed;
use host_sim::render::{render, Grid, Method, MidpointSettings, RenderConfig};
use libfuzzer_sys::arbitrary::Unstructured;
use libfuzzer_sys::fuzz_target;
use mcu_abuffer::fragment_buffer::OverflowPolicy;
use mcu_abuffer::renderer::FrameOptions;
use mcu_abuffer::zbuffer_midpoint::MAX_SUBDIVISION_DEPTH;

fuzz_target!(|data: &[u8]| {
    let mut u = Unstructured::new(data);
    let Ok((desc, angle)) = host_scene(&mut u) else {
        return;
    };
    let Ok(fixed) = to_fixed(&desc) else {
        return;
    };
    let Ok(params) = BufferParams::decode(&mut u, fixed.height.max(1)) else {
        return;
    };
    let (method, grid) = match (params.memory, params.policy) {
        (Memory::ZBuffer, _) => (Method::Zbuffer, Grid::G4x4),
        (m, policy) => (
            match policy {
                OverflowPolicy::MergeFarthest => Method::Shared,
                OverflowPolicy::MergeClosest => Method::MergeClosest,
                OverflowPolicy::SplitBands => Method::SplitBands,
                OverflowPolicy::Discard => Method::FixedDiscard,
            },
            match m {
                Memory::Grid8x4 => Grid::G8x4,
                Memory::Grid8x8 => Grid::G8x8,
                _ => Grid::G4x4,
            },
        ),
    };
    let config = RenderConfig {
        method,
        grid,
        main: params.main,
        extra: params.extra,
        pool: Some(params.pool),
        fixed: params.main,
        band: params.band,
        ssaa: 2,
        ..RenderConfig::default()
    };
    if std::env::var_os("FUZZ_PRINT").is_some() {
        eprintln!("{desc:#?}\nangle {angle}\n{params:?}");
    }
    let host = render(&fixed, &config, angle);
    if angle.is_nan() {
        assert!(host.is_err(), "host-sim rendered with a NaN angle");
        return;
    }
    let objects = fixed.objects();
    let scene = fixed.scene(&objects);
    if scene.validate().is_err() {
        assert!(host.is_err(), "host-sim rendered an invalid scene");
        return;
    }
    let host = host.unwrap_or_else(|e| panic!("host-sim failed on a valid scene: {e}"));
    // host-sim's fixed-discard keeps no pool and no addresses.
    let params = if method == Method::FixedDiscard {
        BufferParams {
            extra: 0,
            pool: 0,
            ..params
        }
    } else {
        params
    };
    let options = FrameOptions {
        turntable_deg: mcu_abuffer::fixed_point::Coord::from_bits(
            abuffer_scenes::fixed_bits::coord_bits(angle),
        ),
        ..FrameOptions::default()
    };
    let checked = render_checked(&scene, &options, &params, false);
    assert!(
        checked.rgb == host.rgb,
        "host-sim and the checked rendering differ"
    );
    assert_eq!(checked.stats, host.stats, "statistics differ");

    // host-sim's other z-buffers: the hierarchical one and supersampling with one
    // sample must equal the plain z-buffer bit for bit; midpoint subdivision
    // (inexact by design) must at least not fail and repeat itself.
    let zbuffer = RenderConfig {
        method: Method::Zbuffer,
        ..config
    };
    let other = match u.int_in_range(0u8..=3).unwrap_or(0) {
        1 => RenderConfig {
            method: Method::ZbufferHiz,
            ..config
        },
        2 => RenderConfig {
            method: Method::Ssaa,
            ssaa: 1,
            ..config
        },
        3 => RenderConfig {
            method: Method::ZbufferMidpoint,
            midpoint: MidpointSettings {
                initial: u.int_in_range(0..=3).unwrap_or(0),
                max: u.int_in_range(0..=MAX_SUBDIVISION_DEPTH + 1).unwrap_or(0),
                safe: u.arbitrary().unwrap_or(false),
            },
            ..config
        },
        _ => return,
    };
    let Ok(first) = render(&fixed, &other, angle) else {
        assert!(
            other.method == Method::ZbufferMidpoint && other.midpoint.config().is_err(),
            "{:?} failed on a valid scene",
            other.method
        );
        return;
    };
    let second = render(&fixed, &other, angle).expect("second rendering");
    assert!(
        first.rgb == second.rgb,
        "{:?} is not repeatable",
        other.method
    );
    if other.method != Method::ZbufferMidpoint {
        let plain = render(&fixed, &zbuffer, angle).expect("z-buffer");
        assert!(
            first.rgb == plain.rgb,
            "{:?} differs from the plain z-buffer",
            other.method
        );
    }
});
