//! Shared parts of the fuzz targets.
//!
//! - Decoders that turn fuzzer bytes into scenes, leaning towards extreme values:
//!   every fixed-point extreme of [`Coord`] and the unit type for the device API
//!   ([`device_scene`]), and NaN, infinities, subnormals and huge or tiny floats for
//!   the host API ([`host_scene`]).
//! - [`BufferParams`]: legal buffer parameters, down to the smallest (one main slot,
//!   no pool address, a pool of 0 or 1 slot, bands of one row).
//! - [`render_checked`]: renders through a fragment buffer wrapped in
//!   `abuffer_test_support`'s `Checked`, which after every insertion and at the
//!   end of every band asserts the A-buffer's invariants: stored masks non-empty
//!   and pairwise disjoint, lists sorted by depth, no pixel over its budget, every
//!   pool slot accounted for while the band is open and the whole pool free once
//!   it closes, fragments only inside the band. Every scene is rendered twice
//!   through the same buffer and the same workspace and must give the same image
//!   and statistics; an unlimited buffer must also match `abuffer_test_support`'s
//!   per-sample z-buffer.
//!
//! A failed check panics, which libFuzzer reports as a crash.

use abuffer_test_support::{
    first_difference, render_rgb, Checked, FragmentStorage, OwnedObject, OwnedScene,
    OwnedWorkspace, PerSampleZBuffer,
};
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};
use fixed::types::I2F14;
use libfuzzer_sys::arbitrary::{Result, Unstructured};
use mcu_abuffer::band_buffer::BandBuffer;
use mcu_abuffer::coverage::{CoverageMask, Mask1x1, Mask4x4, Mask8x4, Mask8x8};
use mcu_abuffer::fixed_point::Coord;
use mcu_abuffer::fragment_buffer::{BufferConfig, OverflowPolicy};
use mcu_abuffer::renderer::FrameOptions;
use mcu_abuffer::scene::{Camera, Light, Normal, Scene, Shading, Transform};
use mcu_abuffer::zbuffer::ZBuffer;

/// What a checked rendering produced.
pub use abuffer_test_support::Rendered;

/// The largest image side the fuzz targets render. The extremes are in the
/// coordinates, not the image size; small images keep executions fast.
pub const MAX_SIDE: u16 = 40;

/// Most objects, vertices per object and triangles per object of a decoded scene.
pub const MAX_OBJECTS: usize = 3;
/// See [`MAX_OBJECTS`].
pub const MAX_VERTICES: usize = 9;
/// See [`MAX_OBJECTS`].
pub const MAX_TRIANGLES: usize = 12;

// ---------------------------------------------------------------------------------
// Extreme values
// ---------------------------------------------------------------------------------

/// A Q16.16 value: one of its extremes, a value near the ones the renderer treats
/// specially, a raw bit pattern, or (most often) a small value near the origin.
pub fn extreme_coord(u: &mut Unstructured<'_>) -> Result<Coord> {
    Ok(match u.int_in_range(0u8..=23)? {
        0 => Coord::MIN,
        1 => Coord::MAX,
        2 => Coord::ZERO,
        3 => Coord::DELTA,
        4 => -Coord::DELTA,
        5 => Coord::ONE,
        6 => -Coord::ONE,
        7 => Coord::from_bits(i32::MIN + 1),
        8 => Coord::from_num(16384),
        9 => Coord::from_num(-16384),
        10 => Coord::from_num(1000),
        11 => Coord::from_num(179),
        12..=14 => Coord::from_bits(u.arbitrary()?),
        _ => Coord::from_bits((u.arbitrary::<i16>()? as i32) << 8),
    })
}

/// Three [`extreme_coord`]s.
pub fn extreme_coord3(u: &mut Unstructured<'_>) -> Result<[Coord; 3]> {
    Ok([extreme_coord(u)?, extreme_coord(u)?, extreme_coord(u)?])
}

/// A Q2.14 normal component: an extreme, a unit value or raw bits.
pub fn extreme_unit(u: &mut Unstructured<'_>) -> Result<I2F14> {
    Ok(match u.int_in_range(0u8..=7)? {
        0 => I2F14::MIN,
        1 => I2F14::MAX,
        2 => I2F14::ZERO,
        3 => I2F14::from_num(1),
        4 => I2F14::from_num(-1),
        _ => I2F14::from_bits(u.arbitrary()?),
    })
}

/// A normal: mostly a unit vector in any direction (rounded to Q2.14), sometimes
/// any three [`extreme_unit`]s (which the scene check refuses unless of unit length).
pub fn extreme_normal(u: &mut Unstructured<'_>) -> Result<Normal> {
    if u.ratio(1u8, 8)? {
        return Ok([extreme_unit(u)?, extreme_unit(u)?, extreme_unit(u)?]);
    }
    let v: [f64; 3] = [0; 3].map(|_| u.arbitrary::<i16>().unwrap_or(0) as f64);
    let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let unit = if len > 0.0 {
        v.map(|c| c / len)
    } else {
        [0.0, 0.0, 1.0]
    };
    Ok(unit.map(I2F14::from_num))
}

/// A value for a camera or a placement: half of the time [`extreme_coord`], else
/// one from `usual` (in whole units over 256).
fn coord_or(u: &mut Unstructured<'_>, usual: core::ops::RangeInclusive<i32>) -> Result<Coord> {
    if u.arbitrary()? {
        extreme_coord(u)
    } else {
        Ok(Coord::from_bits(u.int_in_range(usual)? << 8))
    }
}

fn coord3_or(
    u: &mut Unstructured<'_>,
    usual: core::ops::RangeInclusive<i32>,
) -> Result<[Coord; 3]> {
    Ok([
        coord_or(u, usual.clone())?,
        coord_or(u, usual.clone())?,
        coord_or(u, usual)?,
    ])
}

/// An `f32` as a scene file or program may hand it over: NaN, infinities, signed
/// zeros, subnormals, the largest magnitudes, values just inside and outside the
/// fixed-point range, raw bits, or (most often) a small value.
pub fn extreme_f32(u: &mut Unstructured<'_>) -> Result<f32> {
    Ok(match u.int_in_range(0u8..=27)? {
        0 => f32::NAN,
        1 => f32::INFINITY,
        2 => f32::NEG_INFINITY,
        3 => 0.0,
        4 => -0.0,
        5 => f32::MIN_POSITIVE,
        6 => f32::from_bits(1),
        7 => f32::MAX,
        8 => f32::MIN,
        9 => 1.0e6,
        10 => -1.0e6,
        11 => 16384.0,
        12 => -16384.0,
        13 => 16384.002,
        14 => 32767.998,
        15 => -32768.0,
        16 => 1.0e-6,
        17..=19 => f32::from_bits(u.arbitrary()?),
        _ => u.arbitrary::<i16>()? as f32 / 256.0,
    })
}

/// Three [`extreme_f32`]s.
pub fn extreme_f32_3(u: &mut Unstructured<'_>) -> Result<[f32; 3]> {
    Ok([extreme_f32(u)?, extreme_f32(u)?, extreme_f32(u)?])
}

fn shading(u: &mut Unstructured<'_>) -> Result<Shading> {
    Ok(match u.int_in_range(0u8..=4)? {
        0 => Shading::Unlit,
        1 => Shading::Flat,
        2 => Shading::Gouraud,
        3 => Shading::Quadratic,
        _ => Shading::Phong,
    })
}

/// A mesh's openings as a scene may claim them, true or not: vertex indices
/// (now and then past the last vertex) and ends of loops. A wrong claim may
/// change the image, never the memory the renderer touches.
fn openings(u: &mut Unstructured<'_>, n_vertices: usize) -> Result<Option<Vec<u32>>> {
    if !u.arbitrary::<bool>()? {
        return Ok(None);
    }
    let n = u.int_in_range(0..=24)?;
    let mut list = Vec::with_capacity(n);
    for _ in 0..n {
        list.push(match u.int_in_range(0..=7u8)? {
            0 => mcu_abuffer::scene::OPENING_END,
            1 => u.arbitrary()?,
            _ => u.int_in_range(0..=n_vertices as u32)?,
        });
    }
    Ok(Some(list))
}

fn color(u: &mut Unstructured<'_>) -> Result<Rgb888> {
    Ok(Rgb888::new(u.arbitrary()?, u.arbitrary()?, u.arbitrary()?))
}

/// Triangle indices: mostly valid ones, sometimes one past the end or any `u32`.
fn indices(u: &mut Unstructured<'_>, vertices: usize) -> Result<[u32; 3]> {
    let mut t = [0u32; 3];
    for v in &mut t {
        *v = if u.ratio(1u8, 16)? {
            u.arbitrary()?
        } else {
            u.int_in_range(0..=vertices as u32)?
        };
    }
    Ok(t)
}

// ---------------------------------------------------------------------------------
// Device scenes: raw fixed-point values straight into `mcu_abuffer::Scene`
// ---------------------------------------------------------------------------------

/// Decodes a scene in the renderer's own fixed-point types; values lean towards
/// the extremes of their types (any camera, light and transform, normals of any
/// bits, triangle indices possibly out of range).
pub fn device_scene(u: &mut Unstructured<'_>) -> Result<OwnedScene> {
    let width = u.int_in_range(1..=MAX_SIDE)?;
    let height = u.int_in_range(1..=MAX_SIDE)?;
    let background = color(u)?;
    // Units of 1/256: eyes and targets within 16 units, fields of view of
    // 10 to 170 degrees, near planes from 1/256 to 2, far ones to 1000.
    let camera = Camera {
        eye: coord3_or(u, -4096..=4096)?,
        target: coord3_or(u, -4096..=4096)?,
        up: coord3_or(u, -256..=256)?,
        fov_y_deg: coord_or(u, 2560..=43520)?,
        near: coord_or(u, 1..=512)?,
        far: coord_or(u, 1024..=256_000)?,
    };
    let light = if u.arbitrary()? {
        Some(Light {
            direction: extreme_coord3(u)?,
            ambient: extreme_coord(u)?,
            diffuse: extreme_coord(u)?,
            specular: extreme_coord(u)?,
            shininess: u.arbitrary()?,
        })
    } else {
        None
    };
    let turntable = extreme_coord(u)?;
    let n_objects = u.int_in_range(1..=MAX_OBJECTS)?;
    let mut objects = Vec::with_capacity(n_objects);
    for _ in 0..n_objects {
        let n_vertices = u.int_in_range(0..=MAX_VERTICES)?;
        let mut positions = Vec::with_capacity(n_vertices);
        let mut normals = Vec::with_capacity(n_vertices);
        for _ in 0..n_vertices {
            positions.push(extreme_coord3(u)?);
            normals.push(extreme_normal(u)?);
        }
        let n_triangles = u.int_in_range(0..=MAX_TRIANGLES)?;
        let mut triangles = Vec::with_capacity(n_triangles);
        for _ in 0..n_triangles {
            triangles.push(indices(u, n_vertices)?);
        }
        objects.push(OwnedObject {
            positions,
            normals,
            triangles,
            color: color(u)?,
            transform: Transform {
                position: coord3_or(u, -2048..=2048)?,
                rotation_deg: extreme_coord3(u)?,
                scale: coord_or(u, 1..=1024)?,
            },
            cull: u.arbitrary()?,
            openings: openings(u, n_vertices)?,
            shading: shading(u)?,
        });
    }
    Ok(OwnedScene {
        width,
        height,
        background,
        camera,
        light,
        objects,
        turntable_deg: turntable,
    })
}

// ---------------------------------------------------------------------------------
// Host scenes: floats through host-sim's conversion
// ---------------------------------------------------------------------------------

/// An image side for a host scene: mostly small, sometimes 0 or beyond the limit.
fn host_side(u: &mut Unstructured<'_>) -> Result<u32> {
    Ok(match u.int_in_range(0u8..=15)? {
        0 => 0,
        1 => 2049,
        2 => 70_000,
        _ => u.int_in_range(1..=MAX_SIDE as u32)?,
    })
}

fn shading_desc(
    u: &mut Unstructured<'_>,
) -> Result<Option<abuffer_scenes::scene_desc::ShadingDesc>> {
    use abuffer_scenes::scene_desc::ShadingDesc;
    Ok(match u.int_in_range(0u8..=5)? {
        0 => None,
        1 => Some(ShadingDesc::Unlit),
        2 => Some(ShadingDesc::Flat),
        3 => Some(ShadingDesc::Gouraud),
        4 => Some(ShadingDesc::Quadratic),
        _ => Some(ShadingDesc::Phong),
    })
}

/// A floating-point scene description as a program could build it, with any `f32`
/// anywhere (NaN, infinities, huge and tiny values), and a turntable angle.
pub fn host_scene(
    u: &mut Unstructured<'_>,
) -> Result<(abuffer_scenes::scene_desc::SceneDesc, f32)> {
    use abuffer_scenes::scene_desc::{CameraDesc, LightDesc, MeshData, ObjectDesc, SceneDesc};
    let width = host_side(u)?;
    let height = host_side(u)?;
    let background = [u.arbitrary()?, u.arbitrary()?, u.arbitrary()?];
    let camera = CameraDesc {
        eye: extreme_f32_3(u)?,
        target: extreme_f32_3(u)?,
        up: extreme_f32_3(u)?,
        fov_y_deg: extreme_f32(u)?,
        near: extreme_f32(u)?,
        far: extreme_f32(u)?,
    };
    let light = if u.arbitrary()? {
        Some(LightDesc {
            direction: extreme_f32_3(u)?,
            ambient: extreme_f32(u)?,
            diffuse: extreme_f32(u)?,
            specular: extreme_f32(u)?,
            shininess: extreme_f32(u)?,
        })
    } else {
        None
    };
    let angle = extreme_f32(u)?;
    let n_objects = u.int_in_range(1..=MAX_OBJECTS)?;
    let mut objects = Vec::with_capacity(n_objects);
    for _ in 0..n_objects {
        let n_vertices = u.int_in_range(0..=MAX_VERTICES)?;
        let mut mesh = MeshData::default();
        for _ in 0..n_vertices {
            mesh.positions.push(extreme_f32_3(u)?);
            mesh.normals.push(extreme_f32_3(u)?);
        }
        // Occasionally a normal too many or too few.
        if u.ratio(1u8, 32)? {
            if u.arbitrary()? {
                mesh.normals.push([0.0, 0.0, 1.0]);
            } else {
                mesh.normals.pop();
            }
        }
        for _ in 0..u.int_in_range(0..=MAX_TRIANGLES)? {
            mesh.triangles.push(indices(u, n_vertices)?);
        }
        objects.push(ObjectDesc {
            mesh_name: "fuzz".into(),
            mesh,
            color: [u.arbitrary()?, u.arbitrary()?, u.arbitrary()?],
            position: extreme_f32_3(u)?,
            rotation_deg: extreme_f32_3(u)?,
            scale: extreme_f32(u)?,
            cull_backfaces: u.arbitrary()?,
            bounds_solids: false,
            shading: shading_desc(u)?,
        });
    }
    Ok((
        SceneDesc {
            width,
            height,
            background,
            camera,
            light,
            objects,
        },
        angle,
    ))
}

// ---------------------------------------------------------------------------------
// Buffer parameters
// ---------------------------------------------------------------------------------

/// The pixel memory of a rendering.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Memory {
    /// A-buffer, 4x4 samples.
    Grid4x4,
    /// A-buffer, 8x4 samples.
    Grid8x4,
    /// A-buffer, 8x8 samples.
    Grid8x8,
    /// The plain z-buffer.
    ZBuffer,
}

/// Legal buffer parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BufferParams {
    /// Pixel memory.
    pub memory: Memory,
    /// `N_main`, 1 to 4.
    pub main: u8,
    /// `N_extra`, 0 to 4.
    pub extra: u8,
    /// `N_pool`, 0 to 24 (0 or 1 half of the time).
    pub pool: usize,
    /// Band height, 1 to the image height (1 half of the time).
    pub band: u16,
    /// Overflow policy.
    pub policy: OverflowPolicy,
}

impl BufferParams {
    /// Decodes parameters for an image `height` rows high.
    pub fn decode(u: &mut Unstructured<'_>, height: u16) -> Result<Self> {
        let memory = match u.int_in_range(0u8..=6)? {
            0 | 1 => Memory::Grid4x4,
            2 | 3 => Memory::Grid8x4,
            4 | 5 => Memory::Grid8x8,
            _ => Memory::ZBuffer,
        };
        let main = if u.arbitrary()? {
            1
        } else {
            u.int_in_range(1..=4)?
        };
        let extra = if u.arbitrary()? {
            0
        } else {
            u.int_in_range(0..=4)?
        };
        let pool = if u.arbitrary()? {
            u.int_in_range(0..=1)?
        } else {
            u.int_in_range(0..=24)?
        };
        let band = if u.arbitrary()? {
            1
        } else {
            u.int_in_range(1..=height.max(1))?
        };
        let policy = match u.int_in_range(0u8..=3)? {
            0 => OverflowPolicy::MergeFarthest,
            1 => OverflowPolicy::MergeClosest,
            2 => OverflowPolicy::Discard,
            _ => OverflowPolicy::SplitBands,
        };
        Ok(Self {
            memory,
            main,
            extra,
            pool,
            band,
            policy,
        })
    }

    /// The smallest legal parameters (one main slot, nothing else, one-row bands).
    pub fn minimal(memory: Memory) -> Self {
        Self {
            memory,
            main: 1,
            extra: 0,
            pool: 0,
            band: 1,
            policy: OverflowPolicy::MergeFarthest,
        }
    }
}

// ---------------------------------------------------------------------------------
// Checked rendering
// ---------------------------------------------------------------------------------

/// Renders one frame through `workspace` and `buffer`; the scene must be valid.
fn frame<M: CoverageMask, B: BandBuffer<M>>(
    scene: &Scene<'_>,
    options: &FrameOptions,
    workspace: &mut OwnedWorkspace,
    buffer: &mut B,
) -> Rendered {
    render_rgb(scene, options, workspace, buffer, |_, _, _| {})
        .unwrap_or_else(|e| panic!("a valid scene failed to render: {e}"))
}

/// Renders `scene` twice through the same `buffer` and the same workspace, as a
/// device renders frame after frame; the two frames must be equal.
fn twice<M: CoverageMask, B: BandBuffer<M>>(
    scene: &Scene<'_>,
    options: &FrameOptions,
    buffer: &mut B,
    what: &str,
) -> Rendered {
    let mut workspace = OwnedWorkspace::for_scene(scene);
    let first = frame(scene, options, &mut workspace, buffer);
    let second = frame(scene, options, &mut workspace, buffer);
    assert_eq!(first, second, "the same scene rendered twice differs{what}");
    first
}

/// Renders `scene` twice through one A-buffer of `params`, checking every band.
fn abuffer_twice<M: CoverageMask>(
    scene: &Scene<'_>,
    options: &FrameOptions,
    params: &BufferParams,
) -> Rendered {
    let config = BufferConfig {
        width: scene.width,
        band_height: params.band.clamp(1, scene.height),
        main_slots: params.main,
        extra_addresses: params.extra,
        policy: params.policy,
    };
    let mut storage = FragmentStorage::<M, u16>::new(config, params.pool);
    let inner = storage
        .try_buffer()
        .unwrap_or_else(|e| panic!("legal parameters {params:?} rejected: {e}"));
    twice(scene, options, &mut Checked::new(inner), "")
}

/// Renders `scene` twice through a z-buffer, checking that bands are begun and
/// ended in turn and that fragments land inside them.
fn zbuffer_twice(scene: &Scene<'_>, options: &FrameOptions, band: u16) -> Rendered {
    let band = band.clamp(1, scene.height);
    let n = scene.width as usize * band as usize;
    let mut depth = vec![0u32; n];
    let mut color = vec![Rgb888::BLACK; n];
    let inner = ZBuffer::new(scene.width, band, &mut depth, &mut color).expect("z-buffer");
    twice::<Mask1x1, _>(scene, options, &mut Checked::new(inner), " (z-buffer)")
}

/// Band height of the oracle comparison (keeps the unlimited pool small).
const ORACLE_BAND: u16 = 3;

/// Renders `scene` with an unlimited A-buffer (checked) and a per-sample z-buffer;
/// the images must be equal.
fn oracle<M: CoverageMask>(scene: &Scene<'_>, options: &FrameOptions) {
    let band = ORACLE_BAND.min(scene.height);
    let extra = (M::SAMPLES - 1) as u8;
    let params = BufferParams {
        memory: Memory::Grid4x4,
        main: 1,
        extra,
        pool: scene.width as usize * band as usize * extra as usize,
        band,
        policy: OverflowPolicy::MergeFarthest,
    };
    let unlimited = abuffer_twice::<M>(scene, options, &params);
    assert_eq!(
        unlimited.stats.buffer.merges, 0,
        "an unlimited buffer merged"
    );
    let mut reference = PerSampleZBuffer::<M>::new(scene.width, band);
    let expected = frame(
        scene,
        options,
        &mut OwnedWorkspace::for_scene(scene),
        &mut reference,
    );
    assert!(reference.rows() >= 1);
    if let Some((x, y, a, b)) = first_difference(scene.width, &unlimited.rgb, &expected.rgb) {
        panic!(
            "unlimited A-buffer differs from the per-sample z-buffer at pixel ({x}, {y}): {a:?} vs {b:?}"
        );
    }
}

/// Renders a valid `scene` with `params`, checking the invariants on every band and
/// that a second rendering is identical; with `with_oracle`, also compares an
/// unlimited A-buffer of the same grid with a per-sample z-buffer.
pub fn render_checked(
    scene: &Scene<'_>,
    options: &FrameOptions,
    params: &BufferParams,
    with_oracle: bool,
) -> Rendered {
    scene
        .validate()
        .expect("render_checked needs a valid scene");
    match params.memory {
        Memory::Grid4x4 => {
            if with_oracle {
                oracle::<Mask4x4>(scene, options);
            }
            abuffer_twice::<Mask4x4>(scene, options, params)
        }
        Memory::Grid8x4 => {
            if with_oracle {
                oracle::<Mask8x4>(scene, options);
            }
            abuffer_twice::<Mask8x4>(scene, options, params)
        }
        Memory::Grid8x8 => {
            if with_oracle {
                oracle::<Mask8x8>(scene, options);
            }
            abuffer_twice::<Mask8x8>(scene, options, params)
        }
        Memory::ZBuffer => zbuffer_twice(scene, options, params.band),
    }
}
