//! Every fixed-point quantity of the pipeline at the edges of its range (the table
//! at the top of `firmware/src/fixed_point.rs`), with overflow checks on (system
//! tests build with them): the bounds the documentation states are asserted, and
//! nothing on the way may overflow.

use abuffer_test_support::{FragmentStorage, OwnedObject, OwnedScene};
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};
use mcu_abuffer::band_buffer::BandBuffer;
use mcu_abuffer::clip::{clip_triangle, ClipVertex};
use mcu_abuffer::coverage::{CoverageMask, Mask4x4, Mask8x8};
use mcu_abuffer::fixed_point::{Coord, DEPTH_MAX, GUARD_BAND_PX, UNIT_ONE};
use mcu_abuffer::fragment::{Fragment, PackedFragment, GRADIENT_LIMIT};
use mcu_abuffer::fragment_buffer::{
    BufferConfig, BufferError, BufferShape, BufferStorage, ConstShape, FragmentBuffer,
    OverflowPolicy, ShapeOfConfig,
};
use mcu_abuffer::geometry::{outcode, project, ObjectTransform, ViewBasis};
use mcu_abuffer::lighting::{rgb888_rounded, ColorQ8, LightSetup};
use mcu_abuffer::merge::merge_fragments;
use mcu_abuffer::raster::rasterize;
use mcu_abuffer::renderer::RenderError;
use mcu_abuffer::scene::{Camera, Light, SceneError, Transform};
use mcu_abuffer::setup::{SetupVertex, TriangleSetup};
use mcu_abuffer::shading::{ColorPlanes, ColorSource, TriangleLighting};
use mcu_abuffer::sink::LinePixel;
use mcu_abuffer::stats::BufferStats;
use mcu_abuffer::visibility::visibility_mask;
use system_tests::{render, Rng, Unit};

const LIMIT: i32 = GUARD_BAND_PX << 4;

fn extremes() -> [Coord; 7] {
    [
        Coord::MIN,
        Coord::from_bits(i32::MIN + 1),
        -Coord::ONE,
        Coord::ZERO,
        Coord::DELTA,
        Coord::from_num(16384),
        Coord::MAX,
    ]
}

fn camera(eye: [Coord; 3], target: [Coord; 3], fov: Coord, near: Coord, far: Coord) -> Camera {
    Camera {
        eye,
        target,
        up: [Coord::ZERO, Coord::ONE, Coord::ZERO],
        fov_y_deg: fov,
        near,
        far,
    }
}

/// Q16.16 positions through the transforms of extreme cameras, placements and
/// image sizes: entries within ±2^27, offsets within ±2^59, clip coordinates below
/// 2^61, window coordinates within the guard band, depths within 24 bits.
#[test]
fn coordinates_at_their_extremes_through_the_transform() {
    let big = Coord::MAX;
    let cameras = [
        camera(
            [Coord::ZERO, Coord::ZERO, Coord::from_num(4)],
            [Coord::ZERO; 3],
            Coord::from_num(60),
            Coord::ONE,
            Coord::from_num(10),
        ),
        camera(
            [Coord::MIN, Coord::MIN, Coord::MIN],
            [big, big, big],
            Coord::ONE,
            Coord::DELTA,
            Coord::from_num(1000),
        ),
        camera(
            [big, Coord::ZERO, big],
            [Coord::MIN, Coord::DELTA, Coord::MIN],
            Coord::from_num(179),
            Coord::from_num(999),
            Coord::from_num(1000),
        ),
        camera(
            [Coord::ZERO; 3],
            [Coord::DELTA, Coord::ZERO, Coord::ZERO],
            Coord::from_num(90),
            Coord::DELTA,
            Coord::DELTA * 2,
        ),
    ];
    let transforms = [
        Transform::default(),
        Transform {
            position: [big; 3],
            rotation_deg: [Coord::MIN, big, Coord::from_num(45)],
            scale: big,
        },
        Transform {
            position: [Coord::MIN; 3],
            rotation_deg: [Coord::from_num(-45); 3],
            scale: Coord::DELTA,
        },
        Transform {
            position: [Coord::ZERO; 3],
            rotation_deg: [Coord::from_num(90), Coord::ZERO, Coord::from_num(270)],
            scale: big,
        },
    ];
    let sizes = [(1u16, 1u16), (2048, 2048), (2048, 1), (1, 2048)];
    let mut projected = 0;
    for cam in &cameras {
        let view = ViewBasis::new(cam).expect("camera basis");
        for t in &transforms {
            for &(w, h) in &sizes {
                for turn in [Coord::ZERO, Coord::MIN, Coord::from_num(33.3)] {
                    let xf = ObjectTransform::new(cam, &view, w, h, t, turn);
                    for row in &xf.clip.rows {
                        assert!(row.iter().all(|v| v.unsigned_abs() <= 1 << 27), "{row:?}");
                    }
                    assert!(xf.clip.offsets.iter().all(|v| v.unsigned_abs() <= 1 << 59));
                    for x in extremes() {
                        for y in extremes() {
                            for z in extremes() {
                                let c = xf.to_clip(&[x, y, z]);
                                assert!(c.iter().all(|v| v.unsigned_abs() < 1 << 61), "{c:?}");
                                if outcode(&c) == 0 {
                                    let (px, py, pz) = project(&c);
                                    assert!(px.abs() <= LIMIT && py.abs() <= LIMIT);
                                    assert!(pz <= DEPTH_MAX);
                                    projected += 1;
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    assert!(projected > 0);
}

/// Clipping triangles whose vertices have clip coordinates at the largest
/// magnitude a transform can produce, against every combination of planes.
#[test]
fn clipping_at_the_largest_clip_coordinates() {
    let m = (1i64 << 61) - 1;
    let values = [-m, -(1 << 40), -1, 0, 1, 1 << 38, m];
    let mut rng = Rng::new(61);
    let pick = |rng: &mut Rng| values[rng.below(values.len() as u64) as usize];
    for _ in 0..20_000 {
        let tri: [ClipVertex; 3] = core::array::from_fn(|_| ClipVertex {
            clip: [
                pick(&mut rng),
                pick(&mut rng),
                pick(&mut rng),
                pick(&mut rng),
            ],
            color: [0, 255 << 8, 128 << 8],
            normal: [0, 0, UNIT_ONE],
        });
        let planes = rng.below(64) as u8;
        let poly = clip_triangle(&tri, planes);
        assert!(poly.len == 0 || (3..=9).contains(&poly.len));
        for v in &poly.vertices[..poly.len] {
            assert!(v.clip.iter().all(|c| c.unsigned_abs() <= 1 << 38), "{v:?}");
            assert!(v.color.iter().all(|c| (0..=255 << 8).contains(c)));
        }
    }
}

/// Records where fragments land and checks their fields.
struct Sink<M: CoverageMask> {
    width: u16,
    rows: u16,
    fragments: u64,
    _grid: core::marker::PhantomData<M>,
}

impl<M: CoverageMask> BandBuffer<M> for Sink<M> {
    fn width(&self) -> u16 {
        self.width
    }
    fn band_height(&self) -> u16 {
        self.rows
    }
    fn begin_band(&mut self, _y0: u16, _rows: u16) {}
    fn insert(&mut self, x: u16, row: u16, f: &Fragment<M>) {
        assert!(x < self.width && row < self.rows);
        assert!(f.z <= DEPTH_MAX);
        assert!(f.dzdx.abs() <= GRADIENT_LIMIT && f.dzdy.abs() <= GRADIENT_LIMIT);
        let d = f
            .depth_at(0, 0)
            .unsigned_abs()
            .max(f.depth_at(M::COLS - 1, M::ROWS - 1).unsigned_abs());
        assert!(d < 1 << 29);
        self.fragments += 1;
    }
    fn resolve_row<P: LinePixel>(&mut self, _row: u16, _background: Rgb888, _out: &mut [P]) {}
    fn pixel_fragment_count(&self, _x: u16, _row: u16) -> u32 {
        0
    }
    fn stats(&self) -> BufferStats {
        BufferStats::default()
    }
    fn take_stats(&mut self) -> BufferStats {
        BufferStats::default()
    }
}

fn light_setup(coefficient: Coord, shininess: u8) -> LightSetup {
    let cam = camera(
        [Coord::ZERO, Coord::ZERO, Coord::from_num(4)],
        [Coord::ZERO; 3],
        Coord::from_num(60),
        Coord::ONE,
        Coord::from_num(10),
    );
    let light = Light {
        direction: [Coord::DELTA, Coord::ZERO, Coord::MAX],
        ambient: coefficient,
        diffuse: coefficient,
        specular: coefficient,
        shininess,
    };
    LightSetup::new(&light, &ViewBasis::new(&cam).unwrap())
}

/// Triangle setup and rasterization with vertices on (and beyond) the guard
/// band, depths and colors at both ends, slivers of area 1/512 pixel across the
/// whole band, and every color source: the bounds of `Edge` and `Plane` hold.
#[test]
fn setup_and_rasterization_at_the_guard_band() {
    let mut rng = Rng::new(16);
    let corner = [
        -LIMIT,
        -LIMIT + 1,
        0,
        1 << 15,
        LIMIT - 1,
        LIMIT,
        1 << 20,
        -(1 << 20),
    ];
    // Normals and a light, drawn in that order.
    let lighting = |rng: &mut Rng| {
        let normals = [[0, 0, UNIT_ONE], [UNIT_ONE, 0, 0], [0, -UNIT_ONE, 0]].map(|n| {
            if rng.chance(0.5) {
                n
            } else {
                [11585, 0, -11585]
            }
        });
        let light = light_setup(
            if rng.chance(0.5) {
                Coord::MAX
            } else {
                Coord::ZERO
            },
            rng.range(0, 255) as u8,
        );
        (normals, light)
    };
    let mut gouraud = 0;
    for i in 0..60_000 {
        let corners: [(SetupVertex, ColorQ8); 3] = core::array::from_fn(|_| {
            (
                SetupVertex {
                    x: corner[rng.below(corner.len() as u64) as usize],
                    y: corner[rng.below(corner.len() as u64) as usize],
                    z: if rng.chance(0.5) { 0 } else { DEPTH_MAX },
                },
                [0, 255 << 8, if rng.chance(0.5) { 0 } else { 255 << 8 }],
            )
        });
        let mut v = corners.map(|(at, _)| at);
        let vertex_colors = corners.map(|(_, color)| color);
        if i % 2 == 0 {
            // A sliver: twice its area is 1 in (1/16 pixel)^2, across the band.
            let k = rng.range(1, 1 << 16);
            v[0].x = -LIMIT;
            v[0].y = if rng.chance(0.5) { -LIMIT } else { LIMIT };
            let s = if v[0].y < 0 { 1 } else { -1 };
            v[1].x = v[0].x + 2 * k as i32;
            v[1].y = v[0].y + s * 2 * k as i32;
            v[2].x = v[0].x + k as i32;
            v[2].y = v[0].y + s * k as i32 + 1;
        }
        let (normals, light) = match i % 4 {
            0 | 1 => ([[0; 3]; 3], light_setup(Coord::ZERO, 0)),
            _ => lighting(&mut rng),
        };
        let lit = TriangleLighting {
            normals,
            light: &light,
            base: Rgb888::new(255, 255, 255),
        };
        let colors = match i % 4 {
            0 | 1 => ColorSource::Linear(vertex_colors),
            2 => ColorSource::Quadratic(lit, vertex_colors.map(rgb888_rounded)),
            _ => ColorSource::Phong(lit),
        };
        let (w, h) = if rng.chance(0.5) {
            (2048, 2048)
        } else {
            (1, 2048)
        };
        let Ok(setup) = TriangleSetup::new(&v, false, w, h) else {
            continue;
        };
        for e in &setup.edges {
            assert!(e.a.unsigned_abs() <= 1 << 17 && e.b.unsigned_abs() <= 1 << 17);
            assert!(e.origin.unsigned_abs() < 1 << 35, "{e:?}");
        }
        assert!(
            setup.depth.dx.unsigned_abs() <= 1 << 40 && setup.depth.dy.unsigned_abs() <= 1 << 40
        );
        assert!(setup.depth.origin.unsigned_abs() < 1 << 59);
        assert!(setup.dzdx.abs() <= GRADIENT_LIMIT && setup.dzdy.abs() <= GRADIENT_LIMIT);
        let planes = setup.color_planes(colors);
        if let ColorPlanes::Linear(planes) = planes {
            gouraud += 1;
            for p in &planes {
                assert!(p.dx.unsigned_abs() < 1 << 46 && p.dy.unsigned_abs() < 1 << 46);
                // 2^62.6 > 1.5 * 2^62
                assert!(p.origin.unsigned_abs() < 3 << 61, "{p:?}");
            }
        }
        // The first and last rows of the screen, two rows each.
        for band_y0 in [setup.y0, h.saturating_sub(2)] {
            let mut sink = Sink::<Mask4x4> {
                width: w,
                rows: 2,
                fragments: 0,
                _grid: Default::default(),
            };
            rasterize(
                &setup,
                band_y0.min(h - 1),
                2.min(h - band_y0.min(h - 1)),
                &mut sink,
                || planes,
            );
        }
    }
    assert!(gouraud > 10_000);
}

/// Triangles just under 1,024 pixels across walk their edges in 32 bits
/// without asking the edge values (`TriangleSetup`'s corner test): the
/// largest such triangles, in every orientation, on and partly off the
/// screen, rasterized over their first and last rows (and so one step
/// beyond), with overflow checks on.
#[test]
fn triangles_under_1024_pixels_walk_in_32_bits() {
    let mut rng = Rng::new(1024);
    let span = (1024 << 4) - 1;
    let mut fragments = 0;
    for i in 0..400 {
        // A triangle spanning `span` both ways (the largest edge values the
        // corner test lets through): its first corner anywhere on or just
        // off the screen, mirrored in x and in y in turn, the third corner
        // above the first or anywhere along the far side.
        let (sx, sy) = ([1, -1][i % 2], [1, -1][i / 2 % 2]);
        let x0 = rng.range(-8 << 4, 2048 << 4) as i32;
        let y0 = rng.range(-8 << 4, 2048 << 4) as i32;
        let third = if i % 8 < 4 {
            (x0, y0 + sy * span)
        } else {
            (x0 + sx * rng.range(0, span as i64) as i32, y0 + sy * span)
        };
        let v = [(x0, y0), (x0 + sx * span, y0), third].map(|(x, y)| SetupVertex {
            x,
            y,
            z: DEPTH_MAX / 2,
        });
        let Ok(setup) = TriangleSetup::new(&v, false, 2048, 2048) else {
            continue;
        };
        for band_y0 in [setup.y0, setup.y1.saturating_sub(1)] {
            let mut sink = Sink::<Mask4x4> {
                width: 2048,
                rows: 2,
                fragments: 0,
                _grid: Default::default(),
            };
            rasterize(&setup, band_y0, 2.min(2048 - band_y0), &mut sink, || {
                ColorPlanes::Constant(Rgb888::new(255, 255, 255))
            });
            fragments += sink.fragments;
        }
    }
    assert!(fragments > 100_000, "{fragments}");
}

/// Sample depths and visibility masks with depths and gradients at their limits:
/// `16 z + dzdx ox + dzdy oy` below 2^29, and every visibility bit as the exact
/// comparison in 64 bits says.
#[test]
fn sample_depths_and_visibility_at_their_limits() {
    let zs = [0, 1, DEPTH_MAX / 2, DEPTH_MAX - 1, DEPTH_MAX];
    let gradients = [-GRADIENT_LIMIT, -1, 0, 1, GRADIENT_LIMIT];
    let frag = |z, dx, dy| Fragment {
        mask: Mask8x8::FULL,
        z,
        dzdx: dx,
        dzdy: dy,
        color: Rgb888::new(0, 0, 0),
    };
    let exact = |f: &Fragment<Mask8x8>, c: u32, r: u32| {
        16 * f.z as i64
            + f.dzdx as i64 * Mask8x8::offset_x(c) as i64
            + f.dzdy as i64 * Mask8x8::offset_y(r) as i64
    };
    for &za in &zs {
        for &ga in &gradients {
            for &zb in &zs {
                for &gb in &gradients {
                    let a = frag(za, ga, -ga);
                    let b = frag(zb, gb, gb);
                    let vis = visibility_mask(&a, &b);
                    for s in 0..64 {
                        let (c, r) = (s % 8, s / 8);
                        assert!(a.depth_at(c, r).unsigned_abs() < 1 << 29);
                        assert_eq!(a.depth_at(c, r) as i64, exact(&a, c, r));
                        assert_eq!(vis.get(s), exact(&a, c, r) <= exact(&b, c, r));
                    }
                    // Packing keeps every field.
                    assert_eq!(PackedFragment::pack(&a).unpack(), a);
                }
            }
        }
    }
}

/// Merges of the nearest and the farthest depth with one and 63 samples.
#[test]
fn merge_at_its_limits() {
    let low = |k: u32| (1u64 << k) - 1;
    for (ka, kb) in [(1u32, 63u32), (63, 1), (32, 32), (1, 1)] {
        let a = Fragment {
            mask: Mask8x8(low(ka)),
            z: 0,
            dzdx: GRADIENT_LIMIT,
            dzdy: -GRADIENT_LIMIT,
            color: Rgb888::new(255, 0, 255),
        };
        let b = Fragment {
            mask: Mask8x8(low(kb) << (64 - kb)),
            z: DEPTH_MAX,
            dzdx: -GRADIENT_LIMIT,
            dzdy: GRADIENT_LIMIT,
            color: Rgb888::new(0, 255, 255),
        };
        let m = merge_fragments(&a, &b);
        assert_eq!(m.z as u64, DEPTH_MAX as u64 * kb as u64 / (ka + kb) as u64);
        assert_eq!(m.mask.count(), ka + kb);
        assert_eq!(m.dzdx.unsigned_abs(), GRADIENT_LIMIT as u32);
    }
}

/// Lighting with every coefficient at its largest, the exponent at both ends and
/// unit normals in every direction (rounded to Q2.14, so a step above 1).
#[test]
fn lighting_at_its_limits() {
    let normals = [
        [0, 0, UNIT_ONE],
        [0, 0, -UNIT_ONE],
        [UNIT_ONE, 0, 0],
        [9459, 9459, 9459],
        [0, 0, UNIT_ONE + 1],
    ];
    for coefficient in [
        Coord::ZERO,
        Coord::from_num(7.9),
        Coord::from_num(8),
        Coord::MAX,
        Coord::MIN,
    ] {
        for shininess in [0, 1, 2, 255] {
            let light = light_setup(coefficient, shininess);
            for n in &normals {
                let c = light.shade(n, Rgb888::new(255, 255, 255));
                assert!(c.iter().all(|v| (0..=255 << 8).contains(v)), "{c:?}");
            }
        }
    }
}

/// Resolve with 64 samples of full intensity: the sums stay exact.
#[test]
fn resolve_at_its_limits() {
    let mut storage = FragmentStorage::<Mask8x8>::new(
        BufferConfig {
            width: 2,
            band_height: 1,
            main_slots: 1,
            extra_addresses: 0,
            policy: OverflowPolicy::MergeFarthest,
        },
        0,
    );
    let mut b = storage.buffer();
    b.begin_band(0, 1);
    b.insert(
        0,
        0,
        &Fragment {
            mask: Mask8x8::FULL,
            z: DEPTH_MAX,
            dzdx: 0,
            dzdy: 0,
            color: Rgb888::new(255, 255, 255),
        },
    );
    let mut out = [Rgb888::new(0, 0, 0); 2];
    b.resolve_row(0, Rgb888::new(255, 255, 255), &mut out);
    assert_eq!(out, [Rgb888::new(255, 255, 255); 2]);
}

/// The limits checked when buffers and frames start: 255 fragments per pixel, a
/// pool as large as its addresses reach, 2048-pixel images, 255 objects.
#[test]
fn buffer_and_frame_limits() {
    let config = |main: u8, extra: u8| BufferConfig {
        width: 1,
        band_height: 1,
        main_slots: main,
        extra_addresses: extra,
        policy: OverflowPolicy::MergeFarthest,
    };
    fn build_shaped<S: BufferShape>(c: BufferConfig, pool: usize) -> Option<BufferError> {
        let mut counts = vec![0u8; c.pixels()];
        let mut main = vec![PackedFragment::<Mask4x4>::EMPTY; c.main_slot_count()];
        let mut addresses = vec![0u16; c.address_count()];
        let mut slots = vec![PackedFragment::<Mask4x4>::EMPTY; pool];
        FragmentBuffer::<Mask4x4, u16, S>::new(
            c,
            BufferStorage {
                counts: &mut counts,
                main: &mut main,
                addresses: &mut addresses,
                pool: &mut slots,
            },
        )
        .err()
    }
    let build = build_shaped::<ShapeOfConfig>;
    assert_eq!(build(config(255, 0), 0), None);
    assert_eq!(build(config(200, 55), 0), None);
    assert_eq!(
        build(config(200, 56), 0),
        Some(BufferError::PixelCapacityTooLarge)
    );
    assert_eq!(build(config(1, 1), u16::MAX as usize), None);
    // A buffer type with constant sizes takes only a configuration of them.
    assert_eq!(build_shaped::<ConstShape<1, 1, 1>>(config(1, 1), 4), None);
    assert_eq!(
        build_shaped::<ConstShape<1, 1, 0>>(config(1, 1), 4),
        Some(BufferError::ShapeMismatch)
    );
    assert_eq!(
        build_shaped::<ConstShape<2, 1, 1>>(config(1, 1), 4),
        Some(BufferError::ShapeMismatch)
    );
    assert_eq!(
        build_shaped::<ConstShape<1, 2, 1>>(config(1, 1), 4),
        Some(BufferError::ShapeMismatch)
    );
    assert_eq!(
        build(config(1, 1), u16::MAX as usize + 1),
        Some(BufferError::PoolTooLarge {
            max: u16::MAX as usize
        })
    );

    let unit = [Unit::ZERO, Unit::ZERO, Unit::ONE];
    let object = OwnedObject {
        positions: vec![[Coord::ZERO; 3]; 3],
        normals: vec![unit; 3],
        triangles: vec![[0, 1, 2]],
        color: Rgb888::new(1, 2, 3),
        transform: Transform::default(),
        cull: false,
        openings: None,
        shading: mcu_abuffer::scene::Shading::Unlit,
    };
    let mut scene = OwnedScene {
        width: 2048,
        height: 2048,
        background: Rgb888::BLACK,
        camera: camera(
            [Coord::ZERO, Coord::ZERO, Coord::from_num(4)],
            [Coord::ZERO; 3],
            Coord::from_num(60),
            Coord::ONE,
            Coord::from_num(10),
        ),
        light: None,
        objects: vec![object.clone()],
        turntable_deg: Coord::ZERO,
    };
    let objects = scene.objects();
    assert_eq!(scene.scene(&objects).validate(), Ok(()));
    scene.width = 2049;
    let objects = scene.objects();
    assert_eq!(scene.scene(&objects).validate(), Err(SceneError::ImageSize));
    scene.width = 1;
    scene.height = 1;
    scene.objects = vec![object; 256];
    let objects = scene.objects();
    let lib = scene.scene(&objects);
    let mut storage = FragmentStorage::<Mask4x4>::new(config(1, 0), 0);
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        render(
            &lib,
            &Default::default(),
            &mut storage.buffer(),
            |_, _, _| {},
        )
    }));
    let message = result
        .err()
        .and_then(|e| e.downcast_ref::<String>().cloned())
        .unwrap_or_default();
    assert!(
        message.contains(&format!("{}", RenderError::<()>::TooManyObjects)),
        "{message}"
    );
    scene.objects.truncate(255);
    let objects = scene.objects();
    let lib = scene.scene(&objects);
    render(
        &lib,
        &Default::default(),
        &mut storage.buffer(),
        |_, _, _| {},
    );
}
