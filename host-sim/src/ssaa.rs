//! Ground truth by brute supersampling: `N x N` samples per pixel, each with its
//! own depth test and its own shading, averaged with a box filter.
//!
//! Shared with the renderer: the geometry (transform, outcodes, projection,
//! clipping, vertex lighting) and each triangle's color model, taken from the
//! library's triangle setup (Gouraud planes, quadratic polynomials, Phong normal
//! planes), so both draw the same surfaces. Written here, independently of the
//! A-buffer and its fragments: edge functions and coverage at every sample, the
//! depth plane, per-sample depth tests, the color model evaluated at every sample,
//! and the box filter.
//!
//! The conventions are the renderer's, so that one sample per pixel reproduces the
//! plain z-buffer bit for bit:
//! - sample `(k, l)` of pixel `(i, j)` sits at `(i + (2k + 1) / 2N, j + (2l + 1) / 2N)`
//!   (the pixel center for `N = 1`; the coverage-mask grid for `N = 4` and `N = 8`);
//! - a sample is inside a triangle when every edge function is positive there, or
//!   zero on a top or left edge (SPEC section 1);
//! - depth is the triangle's plane and color its color model, evaluated at the
//!   sample (in exact integer arithmetic scaled by `2N`) and rounded to 24-bit
//!   depth and 8-bit channels as the renderer rounds them at pixel centers, so at
//!   the pixel center they are the same numbers;
//! - a sample keeps the nearer-or-equal surface, so the later triangle wins a tie;
//! - triangles are visited as the renderer visits them: sorted by their first row,
//!   then in scene order (a clipped triangle counts from row 0, its pieces in fan
//!   order).
//!
//! Work is split into bands of rows rendered in parallel; the result does not
//! depend on the band height or the number of threads.

use crate::convert::FixedScene;
use crate::render::RenderOutput;
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};
use mcu_abuffer::clip::{clip_triangle, ClipVertex};
use mcu_abuffer::fixed_point::{saturate, Coord, DEPTH_MAX, GUARD_BAND_PX, SUBPIXEL_BITS};
use mcu_abuffer::geometry::{outcode_and_project, project, ObjectTransform, ViewBasis};
use mcu_abuffer::lighting::{
    channels_rounded, color_q8, normalize_unit, rgb888_rounded, ColorQ8, LightSetup,
};
use mcu_abuffer::scene::Shading;
use mcu_abuffer::setup::{Plane, SetupVertex, TriangleSetup};
use mcu_abuffer::shading::phong::shade_interpolated;
use mcu_abuffer::shading::quadratic::{QuadraticPolynomial, QUADRATIC_FRACTION_BITS};
use mcu_abuffer::shading::{clipped_piece_source, ColorPlanes, ColorSource, TriangleLighting};
use mcu_abuffer::stats::{BufferStats, FrameStats, GeometryStats};
use rayon::prelude::*;
use std::time::Instant;

/// The largest number of samples per pixel side.
pub const MAX_SAMPLES_PER_SIDE: u8 = 32;

/// Rows rendered together (each band is one parallel task).
const BAND_ROWS: u16 = 8;

/// The renderer's limit on a depth-plane step (a full depth range per pixel).
const DEPTH_STEP_LIMIT: i64 = 1 << 40;

/// A vertex in window coordinates: 1/16 pixel, 24-bit depth, color in Q8.
#[derive(Clone, Copy, Debug, Default)]
struct WindowVertex {
    x: i32,
    y: i32,
    z: u32,
    color: ColorQ8,
}

impl WindowVertex {
    fn for_setup(&self) -> SetupVertex {
        SetupVertex {
            x: self.x,
            y: self.y,
            z: self.z,
        }
    }
}

/// An edge function `E(x, y) = a x + b y + c` (1/16 pixel units), positive inside.
#[derive(Clone, Copy, Debug)]
struct EdgeFunction {
    a: i64,
    b: i64,
    c: i64,
    /// Samples with `E = 0` are inside (a top or left edge).
    owns_zero: bool,
}

/// A function over pixel centers with 16 fraction bits: value at the first pixel
/// of the bounding box and its change per pixel.
#[derive(Clone, Copy, Debug)]
struct PixelPlane {
    origin: i64,
    dx: i64,
    dy: i64,
}

impl PixelPlane {
    #[inline]
    fn at(&self, dx: i64, dy: i64) -> i64 {
        self.origin + dx * self.dx + dy * self.dy
    }
}

/// A triangle ready for sampling.
#[derive(Clone, Copy, Debug)]
struct SampleTriangle {
    edges: [EdgeFunction; 3],
    x0: i32,
    y0: i32,
    x1: i32,
    y1: i32,
    depth: PixelPlane,
    /// The surface's color model from the library's setup, over the pixel
    /// lattice of the same bounding box.
    colors: ColorPlanes,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Rejection {
    Degenerate,
    Backfacing,
    Outside,
}

fn signed_area2(v: &[WindowVertex; 3]) -> i64 {
    let (x0, y0) = (v[0].x as i64, v[0].y as i64);
    (v[1].x as i64 - x0) * (v[2].y as i64 - y0) - (v[2].x as i64 - x0) * (v[1].y as i64 - y0)
}

/// Edge functions, bounding box and depth plane of a window-space triangle (SPEC
/// sections 1 and 3; the depth plane is the renderer's, so its values at pixel
/// centers are the same integers), with the color model of `source`.
fn set_up(
    v: &[WindowVertex; 3],
    cull_backfaces: bool,
    source: ColorSource,
    width: u16,
    height: u16,
) -> Result<SampleTriangle, Rejection> {
    let area2 = signed_area2(v);
    if area2 == 0 {
        return Err(Rejection::Degenerate);
    }
    // Counter-clockwise on screen with y up is a positive area here (y down).
    if cull_backfaces && area2 > 0 {
        return Err(Rejection::Backfacing);
    }
    let ordered = if area2 > 0 {
        [v[0], v[1], v[2]]
    } else {
        [v[0], v[2], v[1]]
    };
    let area2 = area2.abs();
    let lim = (GUARD_BAND_PX << SUBPIXEL_BITS) as i64;
    let xs = ordered.map(|p| (p.x as i64).clamp(-lim, lim));
    let ys = ordered.map(|p| (p.y as i64).clamp(-lim, lim));
    let min_x = xs.iter().min().copied().unwrap_or(0) >> SUBPIXEL_BITS;
    let max_x = xs.iter().max().copied().unwrap_or(0) >> SUBPIXEL_BITS;
    let min_y = ys.iter().min().copied().unwrap_or(0) >> SUBPIXEL_BITS;
    let max_y = ys.iter().max().copied().unwrap_or(0) >> SUBPIXEL_BITS;
    if max_x < 0 || max_y < 0 || min_x >= width as i64 || min_y >= height as i64 {
        return Err(Rejection::Outside);
    }
    let x0 = min_x.max(0);
    let y0 = min_y.max(0);
    let x1 = max_x.min(width as i64 - 1);
    let y1 = max_y.min(height as i64 - 1);
    let half = 1i64 << (SUBPIXEL_BITS - 1);
    let cx = (x0 << SUBPIXEL_BITS) + half;
    let cy = (y0 << SUBPIXEL_BITS) + half;
    let edges = std::array::from_fn(|i| {
        let (ia, ib) = (i, (i + 1) % 3);
        let a = -(ys[ib] - ys[ia]);
        let b = xs[ib] - xs[ia];
        EdgeFunction {
            a,
            b,
            c: -(a * xs[ia] + b * ys[ia]),
            owns_zero: a > 0 || (a == 0 && b > 0),
        }
    });
    let (dx1, dy1) = (xs[1] - xs[0], ys[1] - ys[0]);
    let (dx2, dy2) = (xs[2] - xs[0], ys[2] - ys[0]);
    let (dz1, dz2) = (
        ordered[1].z as i64 - ordered[0].z as i64,
        ordered[2].z as i64 - ordered[0].z as i64,
    );
    let shift = 16 + SUBPIXEL_BITS;
    let gx = saturate(((dz1 * dy2 - dz2 * dy1) << shift) / area2, DEPTH_STEP_LIMIT);
    let gy = saturate(((dx1 * dz2 - dx2 * dz1) << shift) / area2, DEPTH_STEP_LIMIT);
    let depth = PixelPlane {
        origin: (((ordered[0].z as i64) << shift) + gx * (cx - xs[0]) + gy * (cy - ys[0]))
            >> SUBPIXEL_BITS,
        dx: gx,
        dy: gy,
    };
    // The color model: the library's planes over the same bounding box.
    let library = TriangleSetup::new(&v.map(|p| p.for_setup()), cull_backfaces, width, height)
        .map_err(|_| Rejection::Degenerate)?;
    if (library.x0 as i64, library.y0 as i64) != (x0, y0) {
        return Err(Rejection::Degenerate);
    }
    Ok(SampleTriangle {
        edges,
        x0: x0 as i32,
        y0: y0 as i32,
        x1: x1 as i32,
        y1: y1 as i32,
        depth,
        colors: library.color_planes(source),
    })
}

/// A transformed vertex: window position (when `outcode == 0`), color and
/// model-space normal (lit with the object's light in model space, as the
/// renderer does).
#[derive(Clone, Copy, Debug, Default)]
struct ProjectedVertex {
    window: WindowVertex,
    normal: [i32; 3],
    outcode: u8,
}

/// All triangles of a frame, set up, in the renderer's visiting order.
struct FrameTriangles {
    triangles: Vec<SampleTriangle>,
    geometry: GeometryStats,
}

/// Transforms, lights, clips and sets up every triangle of `scene` turned by
/// `turntable_deg`, in the order the renderer visits them, with the renderer's
/// color model per triangle.
fn frame_triangles(scene: &FixedScene, turntable_deg: f32) -> Result<FrameTriangles, String> {
    let objects = scene.objects();
    let lib_scene = scene.scene(&objects);
    lib_scene.validate().map_err(|e| e.to_string())?;
    let view = ViewBasis::new(&lib_scene.camera).ok_or("camera has no basis")?;
    let light = lib_scene.light.as_ref().map(|l| LightSetup::new(l, &view));
    let turn = Coord::saturating_from_num(turntable_deg);
    let (width, height) = (scene.width, scene.height);
    let mut geometry = GeometryStats {
        triangles_in: lib_scene.triangle_count() as u32,
        ..Default::default()
    };
    // (first row, scene order) and the set-up triangle.
    let mut keyed: Vec<(u16, usize, SampleTriangle)> = Vec::new();
    let mut order = 0usize;
    for object in &objects {
        let transform = ObjectTransform::new(
            &lib_scene.camera,
            &view,
            width,
            height,
            &object.transform,
            turn,
        );
        // The renderer lights each object's normals in its model space.
        let object_light = light.map(|l| l.in_model_space(&transform.normal));
        let light = &object_light;
        let base = object.color;
        let base_rgb = [base.r(), base.g(), base.b()];
        let shading = if light.is_some() {
            object.shading
        } else {
            Shading::Unlit
        };
        let lit_vertices = matches!(shading, Shading::Gouraud | Shading::Quadratic);
        let mesh = &object.mesh;
        let vertices: Vec<ProjectedVertex> = mesh
            .positions
            .iter()
            .zip(mesh.normals)
            .map(|(p, n)| {
                let c = transform.to_clip(p);
                let (code, (x, y, z)) = outcode_and_project(&c);
                let normal = n.map(|v| v.to_bits() as i32);
                let color = match light {
                    Some(l) if lit_vertices => channels_rounded(l.shade(&normal, base)),
                    _ => base_rgb,
                };
                ProjectedVertex {
                    window: WindowVertex {
                        x,
                        y,
                        z,
                        color: color.map(|c| (c as i32) << 8),
                    },
                    normal,
                    outcode: code,
                }
            })
            .collect();
        for tri in mesh.triangles {
            let pv = tri.map(|i| vertices[i as usize]);
            let normals = pv.map(|p| p.normal);
            let colors = pv.map(|p| p.window.color);
            let source = match (shading, light) {
                (Shading::Flat, Some(l)) => {
                    let mut sum = [0i64; 3];
                    for p in &pv {
                        for (s, c) in sum.iter_mut().zip(p.normal) {
                            *s += c as i64;
                        }
                    }
                    let c = match normalize_unit(sum) {
                        Some(n) => channels_rounded(l.shade(&n, base)),
                        None => base_rgb,
                    };
                    ColorSource::Constant(Rgb888::new(c[0], c[1], c[2]))
                }
                (Shading::Gouraud, Some(_)) => ColorSource::Linear(colors),
                (Shading::Quadratic, Some(light)) => ColorSource::Quadratic(
                    TriangleLighting {
                        normals,
                        light,
                        base,
                    },
                    // The vertices' lit colors, whole 8-bit steps in Q8.
                    colors.map(rgb888_rounded),
                ),
                (Shading::Phong, Some(light)) => ColorSource::Phong(TriangleLighting {
                    normals,
                    light,
                    base,
                }),
                _ => ColorSource::Constant(base),
            };
            let and = pv[0].outcode & pv[1].outcode & pv[2].outcode;
            let or = pv[0].outcode | pv[1].outcode | pv[2].outcode;
            if and != 0 {
                geometry.triangles_outside += 1;
            } else if or == 0 {
                match set_up(
                    &pv.map(|p| p.window),
                    object.cull_backfaces,
                    source,
                    width,
                    height,
                ) {
                    Ok(t) => {
                        geometry.triangle_setups += 1;
                        keyed.push((t.y0 as u16, order, t));
                    }
                    Err(Rejection::Degenerate) => geometry.triangles_degenerate += 1,
                    Err(Rejection::Backfacing) => geometry.triangles_backfacing += 1,
                    Err(Rejection::Outside) => geometry.triangles_outside += 1,
                }
            } else {
                geometry.triangles_clipped += 1;
                let per_pixel_normals =
                    matches!(source, ColorSource::Quadratic(..) | ColorSource::Phong(_));
                let clip_in: [ClipVertex; 3] = std::array::from_fn(|k| ClipVertex {
                    clip: transform.to_clip(&mesh.positions[tri[k] as usize]),
                    color: color_q8(Rgb888::new(
                        (pv[k].window.color[0] >> 8) as u8,
                        (pv[k].window.color[1] >> 8) as u8,
                        (pv[k].window.color[2] >> 8) as u8,
                    )),
                    normal: if per_pixel_normals {
                        pv[k].normal
                    } else {
                        [0; 3]
                    },
                });
                let poly = clip_triangle(&clip_in, or);
                if poly.len >= 3 {
                    let corners = &poly.vertices[..poly.len];
                    let window: Vec<WindowVertex> = corners
                        .iter()
                        .map(|cv| {
                            let (x, y, z) = project(&cv.clip);
                            WindowVertex {
                                x,
                                y,
                                z,
                                color: cv.color,
                            }
                        })
                        .collect();
                    for k in 1..poly.len - 1 {
                        let fan = [window[0], window[k], window[k + 1]];
                        // Per-pixel shading relights the pieces' corners.
                        let normals = [0, k, k + 1].map(|c| corners[c].normal);
                        let colors = fan.map(|p| p.color);
                        let piece = clipped_piece_source(source, &normals, colors);
                        if let Ok(t) = set_up(&fan, object.cull_backfaces, piece, width, height) {
                            geometry.triangle_setups += 1;
                            // Clipped triangles are visited from row 0.
                            keyed.push((0, order, t));
                        }
                    }
                }
            }
            order += 1;
        }
    }
    // Stable: equal rows keep scene order, pieces keep fan order.
    keyed.sort_by_key(|&(row, order, _)| (row, order));
    Ok(FrameTriangles {
        triangles: keyed.into_iter().map(|(_, _, t)| t).collect(),
        geometry,
    })
}

/// Evaluates a triangle's color model at samples: `(i2, j2)` is the sample
/// position relative to the first pixel of the bounding box, times `2N` (so
/// `2N i + 2k + 1 - N` for sample column `k` of pixel column `i`).
struct ColorSampler {
    n2: i64,
    round: FloorDivisor,
}

impl ColorSampler {
    fn new(n: u32) -> Self {
        Self {
            n2: 2 * n as i64,
            round: FloorDivisor::new(2 * n as i64 * (1 << 16)),
        }
    }

    /// A linear function with 16 fraction bits, rounded to 8 bits.
    #[inline]
    fn linear(&self, p: &Plane, i2: i64, j2: i64) -> u8 {
        let v = self.n2 * p.origin + p.dx * i2 + p.dy * j2;
        self.round.apply(v + self.n2 * (1 << 15)).clamp(0, 255) as u8
    }

    /// A lattice quadratic in [`QUADRATIC_FRACTION_BITS`], rounded to 8 bits.
    #[inline]
    fn quadratic(&self, q: &QuadraticPolynomial, i2: i64, j2: i64) -> u8 {
        // (2N)^2 Q(i2 / 2N, j2 / 2N), exact in 128 bits.
        let (u, v, n2) = (i2 as i128, j2 as i128, self.n2 as i128);
        let scaled = q.a as i128 * u * u
            + q.b as i128 * v * v
            + q.c as i128 * u * v
            + n2 * (q.d as i128 * u + q.e as i128 * v)
            + n2 * n2 * q.f as i128;
        let unit = n2 * n2 * (1i128 << QUADRATIC_FRACTION_BITS);
        (scaled + unit / 2).div_euclid(unit).clamp(0, 255) as u8
    }

    /// The sample's color.
    fn color(&self, colors: &ColorPlanes, i2: i64, j2: i64) -> [u8; 3] {
        match colors {
            ColorPlanes::Constant(c) => [c.r(), c.g(), c.b()],
            ColorPlanes::Linear(p) => std::array::from_fn(|ch| self.linear(&p[ch], i2, j2)),
            ColorPlanes::Quadratic(q) | ColorPlanes::NarrowQuadratic(q) => {
                std::array::from_fn(|ch| self.quadratic(&q[ch], i2, j2))
            }
            ColorPlanes::Phong(p) => {
                // The normal at the sample (floor, exact at pixel centers), lit.
                let n: [i64; 3] = std::array::from_fn(|k| {
                    let pl = &p.normal[k];
                    (self.n2 * pl.origin + pl.dx * i2 + pl.dy * j2).div_euclid(self.n2)
                });
                channels_rounded(shade_interpolated(&n, &p.light, p.base))
            }
        }
    }
}

/// Per-sample memory of one band.
struct BandSamples {
    depth: Vec<u32>,
    color: Vec<[u8; 3]>,
    /// Index + 1 of the triangle seen at each sample, 0 for none.
    owner: Vec<u32>,
    /// Triangles covering at least one sample, per pixel.
    generated: Vec<u16>,
}

/// What one band produced.
struct BandResult {
    rgb: Vec<u8>,
    generated: Vec<u16>,
    visible: Vec<u8>,
    depth_tests: u64,
}

/// `floor(v / 2^shift)` or `floor(v / d)`.
#[derive(Clone, Copy)]
struct FloorDivisor {
    d: i64,
    shift: Option<u32>,
}

impl FloorDivisor {
    fn new(d: i64) -> Self {
        Self {
            d,
            shift: (d.count_ones() == 1).then(|| d.trailing_zeros()),
        }
    }

    #[inline]
    fn apply(self, v: i64) -> i64 {
        match self.shift {
            Some(s) => v >> s,
            None => v.div_euclid(self.d),
        }
    }
}

/// Samples every triangle into the band of rows `band_y0 .. band_y0 + rows`.
fn render_band(
    triangles: &[SampleTriangle],
    width: u16,
    band_y0: u16,
    rows: u16,
    n: u32,
    background: [u8; 3],
) -> BandResult {
    let w = width as usize;
    let ns = (n * n) as usize;
    let pixels = w * rows as usize;
    let mut band = BandSamples {
        depth: vec![u32::MAX; pixels * ns],
        color: vec![[0; 3]; pixels * ns],
        owner: vec![0; pixels * ns],
        generated: vec![0; pixels],
    };
    let n64 = n as i64;
    // Depth and colors are planes with 16 fraction bits; at a sample they are
    // evaluated times 2N and rounded: floor((v + N 2^16) / (2N 2^16)).
    let unit = 1i64 << 16;
    let round_div = FloorDivisor::new(2 * n64 * unit);
    let round_bias = n64 * unit;
    let sampler = ColorSampler::new(n);
    // Sample offsets from the pixel center, times 2N: 2k + 1 - N.
    let offsets: Vec<i64> = (0..n64).map(|k| 2 * k + 1 - n64).collect();
    // Largest change of N E from the center to a sample: (|a| + |b|) 8 (N - 1).
    let spread = 8 * (n64 - 1);
    let band_last = band_y0 as i32 + rows as i32 - 1;
    let mut depth_tests = 0u64;
    for (index, t) in triangles.iter().enumerate() {
        if t.y1 < band_y0 as i32 || t.y0 > band_last {
            continue;
        }
        let id = index as u32 + 1;
        let margins = t.edges.map(|e| (e.a.abs() + e.b.abs()) * spread);
        for py in t.y0.max(band_y0 as i32)..=t.y1.min(band_last) {
            let row = (py - band_y0 as i32) as usize;
            let dy = (py - t.y0) as i64;
            for px in t.x0..=t.x1 {
                let dx = (px - t.x0) as i64;
                // N E at the pixel center.
                let center_x = 16 * px as i64 + 8;
                let center_y = 16 * py as i64 + 8;
                let mut center = [0i64; 3];
                let mut inside_all = true;
                let mut outside_any = false;
                for (i, e) in t.edges.iter().enumerate() {
                    let v = n64 * (e.a * center_x + e.b * center_y + e.c);
                    center[i] = v;
                    inside_all &= v - margins[i] > 0;
                    outside_any |= v + margins[i] < 0;
                }
                if outside_any {
                    continue;
                }
                let z_center = t.depth.at(dx, dy);
                let pixel = row * w + px as usize;
                let first = pixel * ns;
                let mut covered = false;
                for (l, &oy) in offsets.iter().enumerate() {
                    // N E at sample (0, l): the center plus a (1 - N) 8 + b oy 8.
                    let mut e: [i64; 3] = std::array::from_fn(|i| {
                        center[i] + 8 * (t.edges[i].a * offsets[0] + t.edges[i].b * oy)
                    });
                    let z_row = 2 * n64 * z_center + t.depth.dx * offsets[0] + t.depth.dy * oy;
                    let mut z_scaled = z_row;
                    for (k, &ox) in offsets.iter().enumerate() {
                        let inside = inside_all
                            || (0..3).all(|i| e[i] > 0 || (e[i] == 0 && t.edges[i].owns_zero));
                        if inside {
                            covered = true;
                            depth_tests += 1;
                            let z = round_div
                                .apply(z_scaled + round_bias)
                                .clamp(0, DEPTH_MAX as i64)
                                as u32;
                            let s = first + l * n as usize + k;
                            if z <= band.depth[s] {
                                band.depth[s] = z;
                                band.owner[s] = id;
                                band.color[s] =
                                    sampler.color(&t.colors, 2 * n64 * dx + ox, 2 * n64 * dy + oy);
                            }
                        }
                        for (v, edge) in e.iter_mut().zip(&t.edges) {
                            *v += 16 * edge.a;
                        }
                        z_scaled += 2 * t.depth.dx;
                    }
                }
                if covered {
                    band.generated[pixel] = band.generated[pixel].saturating_add(1);
                }
            }
        }
    }
    // Box filter, background where no triangle covers a sample; count the
    // distinct triangles left visible in each pixel.
    let mut rgb = vec![0u8; pixels * 3];
    let mut visible = vec![0u8; pixels];
    let mut owners: Vec<u32> = Vec::with_capacity(ns);
    let half = ns as u32 / 2;
    for p in 0..pixels {
        let mut sum = [0u32; 3];
        owners.clear();
        for s in p * ns..(p + 1) * ns {
            let c = if band.owner[s] == 0 {
                background
            } else {
                owners.push(band.owner[s]);
                band.color[s]
            };
            for ch in 0..3 {
                sum[ch] += c[ch] as u32;
            }
        }
        for ch in 0..3 {
            rgb[p * 3 + ch] = ((sum[ch] + half) / ns as u32) as u8;
        }
        owners.sort_unstable();
        owners.dedup();
        visible[p] = owners.len().min(255) as u8;
    }
    BandResult {
        rgb,
        generated: band.generated,
        visible,
        depth_tests,
    }
}

/// Renders `scene` turned by `turntable_deg` with `samples_per_side^2` samples per
/// pixel. The output's per-pixel counts are the triangles covering at least one
/// sample (generated) and the distinct triangles visible at some sample (stored).
pub fn render_ssaa(
    scene: &FixedScene,
    samples_per_side: u8,
    turntable_deg: f32,
) -> Result<RenderOutput, String> {
    if !(1..=MAX_SAMPLES_PER_SIDE).contains(&samples_per_side) {
        return Err(format!(
            "samples per pixel side must be 1..={MAX_SAMPLES_PER_SIDE}"
        ));
    }
    let start = Instant::now();
    let frame = frame_triangles(scene, turntable_deg)?;
    let (w, h) = (scene.width, scene.height);
    let bg = scene.background;
    let background = [bg.r(), bg.g(), bg.b()];
    let bands: Vec<(u16, u16)> = (0..h)
        .step_by(BAND_ROWS as usize)
        .map(|y0| (y0, BAND_ROWS.min(h - y0)))
        .collect();
    let results: Vec<BandResult> = bands
        .par_iter()
        .map(|&(y0, rows)| {
            render_band(
                &frame.triangles,
                w,
                y0,
                rows,
                samples_per_side as u32,
                background,
            )
        })
        .collect();
    let mut rgb = Vec::with_capacity(w as usize * h as usize * 3);
    let mut generated = Vec::with_capacity(w as usize * h as usize);
    let mut stored = Vec::with_capacity(w as usize * h as usize);
    let mut buffer = BufferStats::default();
    let mut depth_tests = 0u64;
    for r in &results {
        rgb.extend_from_slice(&r.rgb);
        generated.extend_from_slice(&r.generated);
        stored.extend_from_slice(&r.visible);
        depth_tests += r.depth_tests;
    }
    // The frame's counters are 32-bit; a reference of more samples saturates.
    let counter = |n: u64| u32::try_from(n).unwrap_or(u32::MAX);
    buffer.depth_tests = counter(depth_tests);
    buffer.fragments_generated = counter(generated.iter().map(|&g| g as u64).sum());
    buffer.fragments_stored = counter(stored.iter().map(|&s| s as u64).sum());
    buffer.max_fragments_in_pixel = stored.iter().copied().max().unwrap_or(0) as u32;
    Ok(RenderOutput {
        width: w,
        height: h,
        rgb,
        stats: FrameStats {
            geometry: frame.geometry,
            buffer,
            bands: bands.len() as u32,
            band_splits: 0,
        },
        generated_per_pixel: generated,
        stored_per_pixel: stored,
        pool_slots: 0,
        elapsed: start.elapsed(),
    })
}
