//! Shared helpers for the system tests of `mcu_abuffer`: a seeded PRNG, a
//! `render` wrapper that returns the RGB888 image, random scene generators, the
//! capture of each triangle's fragment stream, and the prerequisites of the
//! firmware tests. Owned scenes, workspaces, buffer storage, the per-sample
//! oracle and the invariant checks are `abuffer_test_support`'s. Colors are kept
//! as `[u8; 3]` in the tests and converted at the library boundary.

pub use abuffer_test_support::ScratchDir;
use abuffer_test_support::{render_rgb, FragmentStorage, OwnedObject, OwnedScene, OwnedWorkspace};
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};
use mcu_abuffer::band_buffer::BandBuffer;
use mcu_abuffer::clip::{clip_triangle, ClipVertex};
use mcu_abuffer::coverage::CoverageMask;
use mcu_abuffer::fixed_point::{Coord, DEPTH_MAX};
use mcu_abuffer::fragment::Fragment;
use mcu_abuffer::geometry::{outcode, project, ObjectTransform, ViewBasis};
use mcu_abuffer::renderer::FrameOptions;
use mcu_abuffer::scene::{Camera, Light, Normal, Scene, Shading, Transform};
use mcu_abuffer::setup::{is_backfacing, signed_area2, SetupVertex};
use mcu_abuffer::stats::FrameStats;

/// The fixed-point type of normal components (Q2.14), reached through the library's alias.
pub type Unit = <Normal as IntoIterator>::Item;

// ---------------------------------------------------------------------------------
// Random numbers
// ---------------------------------------------------------------------------------

/// A small deterministic PRNG (SplitMix64).
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Self {
        Self(seed ^ 0x5DEE_CE66_D1CE_4E5B)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (`n > 0`).
    pub fn below(&mut self, n: u64) -> u64 {
        assert!(n > 0);
        ((self.next_u64() as u128 * n as u128) >> 64) as u64
    }

    /// Uniform in `lo..=hi`.
    pub fn range(&mut self, lo: i64, hi: i64) -> i64 {
        assert!(lo <= hi);
        lo + self.below((hi - lo + 1) as u64) as i64
    }

    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[lo, hi)`.
    pub fn float(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    /// A random 8-bit color.
    pub fn color(&mut self) -> [u8; 3] {
        let v = self.next_u64();
        [v as u8, (v >> 8) as u8, (v >> 16) as u8]
    }
}

// ---------------------------------------------------------------------------------
// Colors
// ---------------------------------------------------------------------------------

/// The library color of `rgb`.
pub fn rgb888(rgb: [u8; 3]) -> Rgb888 {
    Rgb888::new(rgb[0], rgb[1], rgb[2])
}

/// The channels of a library color.
pub fn channels(c: Rgb888) -> [u8; 3] {
    [c.r(), c.g(), c.b()]
}

/// The color of a fragment as 8-bit channels.
pub fn rgb_of<M: CoverageMask>(f: &Fragment<M>) -> [u8; 3] {
    channels(f.color)
}

/// A fragment from its parts.
pub fn fragment<M: CoverageMask>(
    mask: M,
    z: u32,
    dzdx: i32,
    dzdy: i32,
    rgb: [u8; 3],
) -> Fragment<M> {
    Fragment {
        mask,
        z,
        dzdx,
        dzdy,
        color: rgb888(rgb),
    }
}

/// Sample `s` of grid `M` as (column, row).
pub fn sample_col_row<M: CoverageMask>(s: u32) -> (u32, u32) {
    (s % M::COLS, s / M::COLS)
}

// ---------------------------------------------------------------------------------
// Rendering
// ---------------------------------------------------------------------------------

/// Renders `scene` through `buffer` in a workspace of its own, returning the
/// RGB888 image and the statistics; panics when `render_frame` fails.
pub fn render<M, B, F>(
    scene: &Scene<'_>,
    options: &FrameOptions,
    buffer: &mut B,
    on_band: F,
) -> (Vec<u8>, FrameStats)
where
    M: CoverageMask,
    B: BandBuffer<M>,
    F: FnMut(u16, u16, &B),
{
    let mut workspace = OwnedWorkspace::for_scene(scene);
    let out = render_rgb(scene, options, &mut workspace, buffer, on_band)
        .unwrap_or_else(|e| panic!("render_frame failed: {e}"));
    (out.rgb, out.stats)
}

// ---------------------------------------------------------------------------------
// Random scenes
// ---------------------------------------------------------------------------------

/// What [`random_scene`] and [`deep_scene`] generate.
#[derive(Clone, Copy, Debug)]
pub struct SceneParams {
    /// Image width.
    pub width: u16,
    /// Image height.
    pub height: u16,
    /// Fewest triangles.
    pub min_triangles: usize,
    /// Most triangles.
    pub max_triangles: usize,
    /// Smallest triangle half-size, world units (about 4 px per unit at the origin).
    pub min_size: f64,
    /// Largest triangle half-size.
    pub max_size: f64,
    /// Random camera position, object rotations and turntable angle.
    pub rotate: bool,
}

fn unit_from(v: f64) -> Unit {
    Unit::from_num(v.clamp(-1.0, 1.0))
}

fn random_normal(rng: &mut Rng) -> Normal {
    loop {
        let v = [
            rng.float(-1.0, 1.0),
            rng.float(-1.0, 1.0),
            rng.float(-1.0, 1.0),
        ];
        let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if len > 0.1 && len <= 1.0 {
            return v.map(|c| unit_from(c / len));
        }
    }
}

fn coord(v: f64) -> Coord {
    Coord::from_num(v)
}

/// Half the visible width and height at the origin, in world units (camera 10 units
/// away with a 60-degree vertical field).
fn half_extent(p: &SceneParams) -> (f64, f64) {
    let half_h = 10.0 * (30f64).to_radians().tan();
    (half_h * p.width as f64 / p.height as f64, half_h)
}

/// A random scene: triangles of random size at random depths around the origin,
/// many of them crossing a partner (interpenetrating), a few exact duplicates
/// (depth ties), split over up to four objects with mixed shading.
pub fn random_scene(rng: &mut Rng, p: &SceneParams) -> OwnedScene {
    let (half_w, half_h) = half_extent(p);
    let n = rng.range(p.min_triangles as i64, p.max_triangles as i64) as usize;
    let mut tris: Vec<[[f64; 3]; 3]> = Vec::with_capacity(n);
    while tris.len() < n {
        if let Some(prev) = tris.last().copied() {
            if rng.chance(0.05) {
                // Exact duplicate: equal depths at every sample.
                tris.push(prev);
                continue;
            }
            if rng.chance(0.45) {
                // A partner whose plane crosses the previous one.
                let zc = (prev[0][2] + prev[1][2] + prev[2][2]) / 3.0;
                let j = 0.3;
                let t = prev.map(|v| {
                    [
                        v[0] + rng.float(-j, j),
                        v[1] + rng.float(-j, j),
                        2.0 * zc - v[2] + rng.float(-0.2, 0.2),
                    ]
                });
                tris.push(t);
                continue;
            }
            if rng.chance(0.03) {
                // Nearly edge-on: tiny on screen, steep in depth.
                let c = prev[0];
                let d = [rng.float(-1.0, 1.0), rng.float(-1.0, 1.0)];
                let t = [
                    c,
                    [c[0] + d[0], c[1] + d[1], c[2] + 2.0],
                    [c[0] + 0.02 * d[1], c[1] - 0.02 * d[0], c[2] - 2.0],
                ];
                tris.push(t);
                continue;
            }
        }
        let c = [
            rng.float(-half_w, half_w),
            rng.float(-half_h, half_h),
            rng.float(-3.0, 3.0),
        ];
        let s = rng.float(p.min_size, p.max_size);
        let tilt = rng.float(0.0, 1.5);
        let t = [0, 1, 2].map(|_| {
            [
                c[0] + rng.float(-s, s),
                c[1] + rng.float(-s, s),
                c[2] + tilt * rng.float(-s, s),
            ]
        });
        tris.push(t);
    }
    assemble(rng, p, tris)
}

/// A scene whose pixels are deep: thin triangles fanning out from a few hubs at
/// random depths, so the pixels near a hub hold many fragments, plus a few large
/// tilted triangles behind and through them.
pub fn deep_scene(rng: &mut Rng, p: &SceneParams) -> OwnedScene {
    let (half_w, half_h) = half_extent(p);
    let n = rng.range(p.min_triangles as i64, p.max_triangles as i64) as usize;
    let hubs: Vec<[f64; 2]> = (0..rng.range(1, 3))
        .map(|_| {
            [
                rng.float(-half_w, half_w) * 0.8,
                rng.float(-half_h, half_h) * 0.8,
            ]
        })
        .collect();
    let mut tris: Vec<[[f64; 3]; 3]> = Vec::with_capacity(n);
    for _ in 0..rng.range(1, 3) {
        let z = rng.float(-3.0, 0.0);
        tris.push([
            [-half_w * 1.2, -half_h * 1.2, z + rng.float(-1.0, 1.0)],
            [half_w * 1.2, -half_h * 1.2, z + rng.float(-1.0, 1.0)],
            [
                rng.float(-half_w, half_w),
                half_h * 1.2,
                z + rng.float(-1.0, 1.0),
            ],
        ]);
    }
    while tris.len() < n {
        let h = hubs[rng.below(hubs.len() as u64) as usize];
        let a = rng.float(0.0, std::f64::consts::TAU);
        let len = rng.float(p.min_size, p.max_size) * 2.0;
        let width = rng.float(0.01, 0.06);
        let hub = [h[0] + rng.float(-0.02, 0.02), h[1] + rng.float(-0.02, 0.02)];
        let (dx, dy) = (a.cos(), a.sin());
        let side = [-dy * width, dx * width];
        let z = rng.float(-3.0, 3.0);
        let tilt = rng.float(-1.0, 1.0);
        // A long thin triangle crossing the hub, half as wide there as at its base.
        let tip = [hub[0] - len * dx, hub[1] - len * dy];
        let base = [hub[0] + len * dx, hub[1] + len * dy];
        let zb = z + tilt * len;
        tris.push([
            [tip[0], tip[1], z - tilt * len],
            [
                base[0] + side[0],
                base[1] + side[1],
                zb + rng.float(-0.5, 0.5),
            ],
            [
                base[0] - side[0],
                base[1] - side[1],
                zb + rng.float(-0.5, 0.5),
            ],
        ]);
    }
    assemble(rng, p, tris)
}

/// Objects, camera, light and background around the given triangles.
fn assemble(rng: &mut Rng, p: &SceneParams, tris: Vec<[[f64; 3]; 3]>) -> OwnedScene {
    let n = tris.len();
    let n_objects = rng.range(1, 4.min(n as i64)) as usize;
    let mut cuts: Vec<usize> = (0..n_objects - 1)
        .map(|_| rng.range(1, n as i64 - 1) as usize)
        .collect();
    cuts.push(0);
    cuts.push(n);
    cuts.sort_unstable();
    cuts.dedup();
    let mut objects = Vec::new();
    for w in cuts.windows(2) {
        let group = &tris[w[0]..w[1]];
        let mut positions = Vec::new();
        let mut normals = Vec::new();
        let mut triangles = Vec::new();
        for t in group {
            let base = positions.len() as u32;
            for v in t {
                positions.push(v.map(coord));
                normals.push(random_normal(rng));
            }
            // Random winding, so culling removes some triangles.
            if rng.chance(0.5) {
                triangles.push([base, base + 1, base + 2]);
            } else {
                triangles.push([base, base + 2, base + 1]);
            }
        }
        let transform = if p.rotate {
            Transform {
                position: [0, 1, 2].map(|_| coord(rng.float(-1.0, 1.0))),
                rotation_deg: [0, 1, 2].map(|_| coord(rng.float(-180.0, 180.0))),
                scale: coord(rng.float(0.7, 1.2)),
            }
        } else {
            Transform::default()
        };
        let shading = match rng.below(5) {
            0 => Shading::Unlit,
            1 => Shading::Flat,
            2 => Shading::Gouraud,
            3 => Shading::Quadratic,
            _ => Shading::Phong,
        };
        objects.push(OwnedObject {
            positions,
            normals,
            triangles,
            color: rgb888(rng.color()),
            transform,
            cull: rng.chance(0.25),
            openings: None,
            shading,
        });
    }
    let eye = if p.rotate {
        let az = rng.float(-1.0, 1.0);
        let el = rng.float(-0.6, 0.6);
        let r = rng.float(5.0, 9.0);
        [
            r * el.cos() * az.sin(),
            r * el.sin(),
            r * el.cos() * az.cos(),
        ]
    } else {
        [0.0, 0.0, 10.0]
    };
    let camera = Camera {
        eye: eye.map(coord),
        target: [Coord::ZERO; 3],
        up: [Coord::ZERO, Coord::ONE, Coord::ZERO],
        fov_y_deg: coord(60.0),
        near: coord(1.0),
        far: coord(40.0),
    };
    let light = if rng.chance(0.8) {
        Some(Light {
            direction: [0, 1, 2].map(|_| coord(rng.float(-1.0, 1.0) + 0.01)),
            ambient: coord(rng.float(0.1, 0.4)),
            diffuse: coord(rng.float(0.3, 0.8)),
            specular: coord(rng.float(0.0, 0.5)),
            shininess: rng.range(1, 32) as u8,
        })
    } else {
        None
    };
    let turntable_deg = if p.rotate {
        coord(rng.float(-90.0, 90.0))
    } else {
        Coord::ZERO
    };
    OwnedScene {
        width: p.width,
        height: p.height,
        background: rgb888(rng.color()),
        camera,
        light,
        objects,
        turntable_deg,
    }
}

/// The order in which the renderer visits triangles within a pixel: triangles
/// facing the viewer before those facing away (clipped triangles count as
/// facing the viewer), each group by the top bits of its nearest corner's
/// window depth (a corner outside the view volume counts as depth 0), then
/// by object and triangle. With `b` the bits that number the objects and
/// the largest mesh's triangles, the depth keeps `min(30 - b, 24)` bits.
/// The second value is the first image row of the triangle's window
/// bounding box (of the clipped polygon for clipped triangles); triangles
/// the renderer skips (outside, back-facing and culled, degenerate) get
/// `None`. Mirrors the binning and the draw order of `render_frame`.
pub fn visiting_order(scene: &OwnedScene) -> Vec<((usize, usize), Option<u16>)> {
    let view = ViewBasis::new(&scene.camera).expect("camera basis");
    let (w, h) = (scene.width as i32, scene.height as i32);
    let bits = |n: usize| usize::BITS - n.saturating_sub(1).leading_zeros();
    let most = scene.objects.iter().map(|o| o.triangles.len()).max();
    let number_bits = bits(scene.objects.len()) + bits(most.unwrap_or(0));
    let depth_drop = 24 - (30 - number_bits).min(24);
    let mut keyed = Vec::new();
    for (oi, o) in scene.objects.iter().enumerate() {
        let xf = ObjectTransform::new(
            &scene.camera,
            &view,
            scene.width,
            scene.height,
            &o.transform,
            scene.turntable_deg,
        );
        for (ti, tri) in o.triangles.iter().enumerate() {
            let clip = tri.map(|v| xf.to_clip(&o.positions[v as usize]));
            let codes = clip.map(|c| outcode(&c));
            let nearest = (0..3)
                .map(|k| match codes[k] {
                    0 => project(&clip[k]).2.min(DEPTH_MAX),
                    _ => 0,
                })
                .min()
                .unwrap_or(0);
            let mut back = false;
            let row = if codes[0] & codes[1] & codes[2] != 0 {
                None
            } else if codes[0] | codes[1] | codes[2] != 0 {
                let input = clip.map(|c| ClipVertex {
                    clip: c,
                    color: [0; 3],
                    normal: [0; 3],
                });
                let poly = clip_triangle(&input, codes[0] | codes[1] | codes[2]);
                let ys: Vec<i32> = poly.vertices[..poly.len]
                    .iter()
                    .map(|v| project(&v.clip).1 >> 4)
                    .collect();
                match (ys.iter().min(), ys.iter().max()) {
                    (Some(&lo), Some(&hi)) if hi >= 0 && lo < h => Some(lo.max(0) as u16),
                    _ => None,
                }
            } else {
                let sv = clip.map(|c| {
                    let (x, y, z) = project(&c);
                    SetupVertex { x, y, z }
                });
                let area2 = signed_area2(&sv);
                let min_x = sv.iter().map(|v| v.x).min().unwrap_or(0) >> 4;
                let max_x = sv.iter().map(|v| v.x).max().unwrap_or(0) >> 4;
                let min_y = sv.iter().map(|v| v.y).min().unwrap_or(0) >> 4;
                let max_y = sv.iter().map(|v| v.y).max().unwrap_or(0) >> 4;
                back = is_backfacing(area2);
                if area2 == 0
                    || (o.cull && is_backfacing(area2))
                    || max_x < 0
                    || max_y < 0
                    || min_x >= w
                    || min_y >= h
                {
                    None
                } else {
                    Some(min_y.max(0) as u16)
                }
            };
            keyed.push(((oi, ti), row, (back, nearest >> depth_drop)));
        }
    }
    // Skipped ones last, the rest by facing, depth, object and triangle.
    keyed.sort_by_key(|&(t, row, key)| (row.is_none(), key, t));
    keyed.into_iter().map(|(t, row, _)| (t, row)).collect()
}

/// The fragments one triangle leaves, pixel by pixel: `(x, y, fragment)`.
pub type Stream<M> = Vec<(u16, u16, Fragment<M>)>;

/// Captures the fragments of every triangle of `scene` separately, by rendering
/// each triangle alone through an unlimited fragment buffer (full-height band), in
/// the renderer's visiting order. Returns `(triangle, skipped by binning, stream)`.
pub fn triangle_streams<M: CoverageMask>(
    scene: &OwnedScene,
    storage: &mut FragmentStorage<M>,
) -> Vec<((usize, usize), bool, Stream<M>)> {
    assert!(storage.config().band_height >= scene.height);
    let options = scene.options();
    let mut out = Vec::new();
    for ((o, t), row) in visiting_order(scene) {
        let objects = scene.single_triangle_objects(o, t);
        let lib_scene = scene.scene(&objects);
        let mut stream = Vec::new();
        let mut buffer = storage.buffer();
        render(&lib_scene, &options, &mut buffer, |y0, rows, b| {
            for row in 0..rows {
                for x in 0..b.width() {
                    for f in b.fragments(x, row) {
                        stream.push((x, y0 + row, f));
                    }
                }
            }
        });
        out.push(((o, t), row.is_none(), stream));
    }
    out
}

// ---------------------------------------------------------------------------------
// Scratch folders of the firmware tests
// ---------------------------------------------------------------------------------

/// An empty folder `abuffer-NAME-PID` under the system's temporary folder, where
/// a firmware test puts its ELF and QEMU's output files; removed when dropped,
/// kept when dropped while the test fails ([`ScratchDir`]).
pub fn scratch_dir(name: &str) -> ScratchDir {
    ScratchDir::new(&format!("abuffer-{name}"))
}

// ---------------------------------------------------------------------------------
// Prerequisites of the firmware tests
// ---------------------------------------------------------------------------------

/// Whether the tools a firmware test needs are here: `qemu-system-arm` on the
/// `PATH` (when `qemu` is set), the Rust `target` installed and `flip-link` (the
/// firmwares' linker) on the `PATH`. When one is
/// missing, the test should return early: this prints why and returns `false`,
/// unless `ABUFFER_REQUIRE_QEMU=1` is set (the README's test command sets it,
/// after installing both), in which case it panics instead, so that a missing
/// tool fails loudly rather than skipping.
pub fn firmware_tools_present(test: &str, target: &str, qemu: bool) -> bool {
    let mut missing = Vec::new();
    if qemu
        && std::process::Command::new("qemu-system-arm")
            .arg("--version")
            .output()
            .map(|o| !o.status.success())
            .unwrap_or(true)
    {
        missing.push("qemu-system-arm (apt-get install -y qemu-system-arm)".to_string());
    }
    let installed = std::process::Command::new("rustup")
        .args(["target", "list", "--installed"])
        .output()
        .map(|o| {
            String::from_utf8_lossy(&o.stdout)
                .lines()
                .any(|l| l.trim() == target)
        })
        // Without rustup the toolchain may still have the target: try the build.
        .unwrap_or(true);
    if !installed {
        missing.push(format!("the {target} target (rustup target add {target})"));
    }
    // Both firmware workspaces link through flip-link (stack below the statics).
    if std::process::Command::new("flip-link")
        .arg("--version")
        .output()
        .is_err()
    {
        missing.push("flip-link (cargo install flip-link)".to_string());
    }
    if missing.is_empty() {
        return true;
    }
    let missing = missing.join(" and ");
    if std::env::var("ABUFFER_REQUIRE_QEMU").as_deref() == Ok("1") {
        panic!("{test}: missing {missing}, required by ABUFFER_REQUIRE_QEMU=1");
    }
    // Straight to the process's stderr: the test harness would hide an
    // `eprintln!` of a passing test.
    use std::io::Write as _;
    let _ = writeln!(
        std::io::stderr().lock(),
        "{test}: skipped, missing {missing}"
    );
    false
}
