//! SPEC section 1 (fill rule): with the top-left rule, triangles that tile a region
//! cover each of its samples exactly once: no cracks, no double coverage. And since
//! a sample on an edge goes to the triangle on a fixed side, the covered set depends
//! only on the region, not on how it is triangulated.
//!
//! Triangles are rasterized into a `SampleCounter` (a `BandBuffer` that adds one per
//! covered sample). Each triangle's masks are also compared with a direct per-sample
//! inside test. Vertices are in 1/16 pixel, often exactly on pixel centers, pixel
//! corners or sample positions; grids have shared horizontal and vertical edges.

use embedded_graphics_core::pixelcolor::Rgb888;
use mcu_abuffer::band_buffer::BandBuffer;
use mcu_abuffer::coverage::{CoverageMask, Mask4x4, Mask8x4, Mask8x8};
use mcu_abuffer::fragment::Fragment;
use mcu_abuffer::raster::rasterize;
use mcu_abuffer::setup::{Rejection, SetupVertex, TriangleSetup};
use mcu_abuffer::shading::ColorSource;
use mcu_abuffer::sink::LinePixel;
use mcu_abuffer::stats::BufferStats;
use system_tests::Rng;

const W: u16 = 24;
const H: u16 = 20;

type P = (i64, i64);
type Tri = [P; 3];

/// Twice the signed area of `(a, b, c)` (positive: counter-clockwise with y up).
fn orient(a: P, b: P, c: P) -> i64 {
    (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
}

/// Sample offset in 1/16 pixel, computed here independently of the library.
fn offset(i: u32, n: u32) -> i64 {
    (2 * i as i64 + 1 - n as i64) * 8 / n as i64
}

/// A band buffer covering the whole `W x H` image that counts, per sample, the
/// fragments covering it, and remembers the fragments since the last `take_new`.
struct SampleCounter<M: CoverageMask> {
    counts: Vec<u8>,
    new: Vec<(u16, u16, M)>,
    stats: BufferStats,
    on_edge: u64,
    triangles: usize,
}

impl<M: CoverageMask> SampleCounter<M> {
    fn new() -> Self {
        Self {
            counts: vec![0; W as usize * H as usize * M::SAMPLES as usize],
            new: Vec::new(),
            stats: BufferStats::default(),
            on_edge: 0,
            triangles: 0,
        }
    }

    fn base(x: u16, row: u16) -> usize {
        (row as usize * W as usize + x as usize) * M::SAMPLES as usize
    }

    fn covered(&self) -> Vec<bool> {
        self.counts.iter().map(|&c| c > 0).collect()
    }

    fn covered_count(&self) -> usize {
        self.counts.iter().filter(|&&c| c > 0).count()
    }
}

impl<M: CoverageMask> BandBuffer<M> for SampleCounter<M> {
    fn width(&self) -> u16 {
        W
    }

    fn band_height(&self) -> u16 {
        H
    }

    fn begin_band(&mut self, _y0: u16, _rows: u16) {}

    fn insert(&mut self, x: u16, row: u16, fragment: &Fragment<M>) {
        self.stats.fragments_generated += 1;
        let base = Self::base(x, row);
        for s in 0..M::SAMPLES {
            if fragment.mask.get(s) {
                let c = &mut self.counts[base + s as usize];
                *c = c.saturating_add(1);
            }
        }
        self.new.push((x, row, fragment.mask));
    }

    fn resolve_row<P: LinePixel>(&mut self, row: u16, background: Rgb888, out: &mut [P]) {
        for (x, px) in out.iter_mut().enumerate().take(W as usize) {
            let base = Self::base(x as u16, row);
            let any = self.counts[base..base + M::SAMPLES as usize]
                .iter()
                .any(|&c| c > 0);
            *px = P::from_rgb888(if any {
                Rgb888::new(255, 255, 255)
            } else {
                background
            });
        }
    }

    fn pixel_fragment_count(&self, x: u16, row: u16) -> u32 {
        let base = Self::base(x, row);
        self.counts[base..base + M::SAMPLES as usize]
            .iter()
            .map(|&c| c as u32)
            .max()
            .unwrap_or(0)
    }

    fn stats(&self) -> BufferStats {
        self.stats
    }

    fn take_stats(&mut self) -> BufferStats {
        core::mem::take(&mut self.stats)
    }
}

/// Draws every triangle into a fresh counter; panics on a sample covered twice or a
/// mask that differs from the direct inside test.
fn draw<M: CoverageMask>(tris: &[Tri], what: &str) -> SampleCounter<M> {
    let mut counter = SampleCounter::<M>::new();
    counter.begin_band(0, H);
    for (k, t) in tris.iter().enumerate() {
        let v = t.map(|(x, y)| SetupVertex {
            x: x as i32,
            y: y as i32,
            z: 1000,
        });
        let setup = match TriangleSetup::new(&v, false, W, H) {
            Ok(s) => s,
            Err(Rejection::Degenerate) | Err(Rejection::Outside) => continue,
            Err(Rejection::Backfacing) => unreachable!("culling is off"),
        };
        counter.triangles += 1;
        counter.on_edge += on_edge_samples::<M>(&setup);
        counter.new.clear();
        rasterize::<M, _, _>(&setup, 0, H, &mut counter, || {
            setup.color_planes(ColorSource::Linear([[0; 3]; 3]))
        });
        let new = std::mem::take(&mut counter.new);
        check_exact::<M>(t, &new, what);
        for &(x, y, mask) in &new {
            let base = SampleCounter::<M>::base(x, y);
            for s in 0..M::SAMPLES {
                assert!(
                    !mask.get(s) || counter.counts[base + s as usize] <= 1,
                    "{} {what}: sample {s} of pixel ({x}, {y}) covered twice \
                     (second time by triangle {k} {t:?}); all triangles: {tris:?}",
                    M::NAME
                );
            }
        }
    }
    counter
}

/// Whether sample point `p` (1/16 pixel) is in triangle `t` under the top-left rule,
/// evaluated directly: strictly inside every edge, or exactly on an edge whose
/// inward normal points right (or straight down), i.e. the point nudged right and
/// a hair down is inside.
fn inside(t: &Tri, p: P) -> bool {
    let t = if orient(t[0], t[1], t[2]) < 0 {
        [t[0], t[2], t[1]]
    } else {
        *t
    };
    (0..3).all(|i| {
        let (a, b) = (t[i], t[(i + 1) % 3]);
        let o = orient(a, b, p);
        // Inward normal of edge a -> b (interior where orient > 0).
        let (nx, ny) = (-(b.1 - a.1), b.0 - a.0);
        o > 0 || (o == 0 && (nx > 0 || (nx == 0 && ny > 0)))
    })
}

/// The rasterizer's masks of one triangle equal the direct per-sample test on every
/// on-screen pixel.
fn check_exact<M: CoverageMask>(t: &Tri, captured: &[(u16, u16, M)], what: &str) {
    let min_x = t.iter().map(|p| p.0).min().unwrap().div_euclid(16).max(0);
    let max_x = t
        .iter()
        .map(|p| p.0)
        .max()
        .unwrap()
        .div_euclid(16)
        .min(W as i64 - 1);
    let min_y = t.iter().map(|p| p.1).min().unwrap().div_euclid(16).max(0);
    let max_y = t
        .iter()
        .map(|p| p.1)
        .max()
        .unwrap()
        .div_euclid(16)
        .min(H as i64 - 1);
    let mut got = std::collections::HashMap::new();
    for &(x, y, m) in captured {
        got.insert((x as i64, y as i64), m.to_u64());
    }
    let mut expected_pixels = 0;
    for y in min_y..=max_y {
        for x in min_x..=max_x {
            let mut want = 0u64;
            for j in 0..M::ROWS {
                for i in 0..M::COLS {
                    let p = (
                        16 * x + 8 + offset(i, M::COLS),
                        16 * y + 8 + offset(j, M::ROWS),
                    );
                    if inside(t, p) {
                        want |= 1 << (j * M::COLS + i);
                    }
                }
            }
            let have = got.get(&(x, y)).copied().unwrap_or(0);
            assert_eq!(
                have,
                want,
                "{} {what}: triangle {t:?}, pixel ({x}, {y}): mask {have:#x}, direct test {want:#x}",
                M::NAME
            );
            expected_pixels += (want != 0) as usize;
        }
    }
    assert_eq!(
        expected_pixels,
        got.len(),
        "{what}: fragments outside the triangle's box"
    );
}

/// Samples of a set-up triangle's bounding box lying exactly on one of its edge lines
/// (edge function 0 before the bias): the cases the fill rule decides.
fn on_edge_samples<M: CoverageMask>(s: &TriangleSetup) -> u64 {
    let mut n = 0;
    for y in s.y0..=s.y1 {
        for x in s.x0..=s.x1 {
            for j in 0..M::ROWS {
                for i in 0..M::COLS {
                    let hit = s.edges.iter().any(|e| {
                        let top_left = e.a > 0 || (e.a == 0 && e.b > 0);
                        let v = e.origin
                            + (x - s.x0) as i64 * 16 * e.a as i64
                            + (y - s.y0) as i64 * 16 * e.b as i64
                            + e.a as i64 * offset(i, M::COLS)
                            + e.b as i64 * offset(j, M::ROWS)
                            + if top_left { 0 } else { 1 };
                        v == 0
                    });
                    n += hit as u64;
                }
            }
        }
    }
    n
}

/// A coordinate near `ideal` (1/16 pixel): exactly on a pixel center, a pixel corner
/// or a sample position of the grid, or just `ideal`.
fn special(rng: &mut Rng, ideal: i64, n: u32) -> i64 {
    let cell = ideal.div_euclid(16) * 16;
    match rng.below(4) {
        0 => cell + 8,
        1 => cell,
        2 => cell + 8 + offset(rng.below(n as u64) as u32, n),
        _ => ideal,
    }
}

fn random_point<M: CoverageMask>(rng: &mut Rng, x: (i64, i64), y: (i64, i64)) -> P {
    (
        {
            let ideal = rng.range(x.0, x.1);
            special(rng, ideal, M::COLS)
        },
        {
            let ideal = rng.range(y.0, y.1);
            special(rng, ideal, M::ROWS)
        },
    )
}

fn shuffle_winding(rng: &mut Rng, t: Tri) -> Tri {
    match rng.below(3) {
        0 => t,
        1 => [t[1], t[2], t[0]],
        _ => [t[0], t[2], t[1]],
    }
}

fn assert_same_cover<M: CoverageMask>(a: &SampleCounter<M>, b: &SampleCounter<M>, what: &str) {
    let (ca, cb) = (a.covered(), b.covered());
    if let Some(i) = (0..ca.len()).find(|&i| ca[i] != cb[i]) {
        let s = i % M::SAMPLES as usize;
        let p = i / M::SAMPLES as usize;
        panic!(
            "{} {what}: sample {s} of pixel ({}, {}) covered by one triangulation ({}) \
             but not the other ({})",
            M::NAME,
            p % W as usize,
            p / W as usize,
            ca[i],
            cb[i]
        );
    }
}

/// Convex hull (counter-clockwise in `orient`'s sense, no collinear points).
fn hull(mut pts: Vec<P>) -> Vec<P> {
    pts.sort_unstable();
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let mut lower: Vec<P> = Vec::new();
    for &p in &pts {
        while lower.len() >= 2 && orient(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<P> = Vec::new();
    for &p in pts.iter().rev() {
        while upper.len() >= 2 && orient(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 0 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

fn strictly_inside_convex(poly: &[P], p: P) -> bool {
    (0..poly.len()).all(|i| orient(poly[i], poly[(i + 1) % poly.len()], p) > 0)
}

#[derive(Default)]
struct Totals {
    cases: usize,
    triangles: usize,
    on_edge: u64,
    covered: usize,
}

impl Totals {
    fn add<M: CoverageMask>(&mut self, t: &SampleCounter<M>) {
        self.cases += 1;
        self.triangles += t.triangles;
        self.on_edge += t.on_edge;
        self.covered += t.covered_count();
    }

    fn report(&self, name: &str, case: &str) {
        println!(
            "{name} {case}: {} cases, {} triangles, {} covered samples, {} sample-on-edge hits",
            self.cases, self.triangles, self.covered, self.on_edge
        );
        assert!(self.covered > 0, "{name} {case}: nothing was drawn");
        assert!(
            self.on_edge > 100,
            "{name} {case}: samples on edges never occurred"
        );
    }
}

/// A convex polygon drawn as a fan around an interior point and as a fan from one of
/// its vertices.
fn fans<M: CoverageMask>(cases: usize, seed: u64) {
    let mut rng = Rng::new(seed);
    let mut totals = Totals::default();
    let mut done = 0;
    while done < cases {
        let cx = rng.range(-16, W as i64 * 16 + 16);
        let cy = rng.range(-16, H as i64 * 16 + 16);
        let r = rng.range(24, 160);
        let n = rng.range(3, 14) as usize;
        let pts: Vec<P> = (0..n)
            .map(|_| {
                let a = rng.float(0.0, std::f64::consts::TAU);
                let rr = r as f64 * rng.float(0.6, 1.0);
                let ideal = (cx + (rr * a.cos()) as i64, cy + (rr * a.sin()) as i64);
                (
                    special(&mut rng, ideal.0, M::COLS),
                    special(&mut rng, ideal.1, M::ROWS),
                )
            })
            .collect();
        let poly = hull(pts);
        if poly.len() < 3 {
            continue;
        }
        // An interior center, preferably on a special coordinate.
        let mut center = None;
        for _ in 0..50 {
            let c = (
                {
                    let ideal = cx + rng.range(-r / 3, r / 3);
                    special(&mut rng, ideal, M::COLS)
                },
                {
                    let ideal = cy + rng.range(-r / 3, r / 3);
                    special(&mut rng, ideal, M::ROWS)
                },
            );
            if strictly_inside_convex(&poly, c) {
                center = Some(c);
                break;
            }
        }
        let Some(c) = center else { continue };
        let m = poly.len();
        let fan: Vec<Tri> = (0..m)
            .map(|i| shuffle_winding(&mut rng, [c, poly[i], poly[(i + 1) % m]]))
            .collect();
        let from_vertex: Vec<Tri> = (1..m - 1)
            .map(|i| shuffle_winding(&mut rng, [poly[0], poly[i], poly[i + 1]]))
            .collect();
        let a = draw::<M>(&fan, "fan around a center");
        let b = draw::<M>(&from_vertex, "fan from a vertex");
        assert_same_cover(&a, &b, &format!("convex polygon {poly:?} center {c:?}"));
        totals.add(&a);
        done += 1;
    }
    totals.report(M::NAME, "fans");
}

/// Grid lines: strictly increasing coordinates starting near `start`.
fn grid_lines(rng: &mut Rng, start: i64, cells: usize, n: u32) -> Vec<i64> {
    let mut v = vec![special(rng, start, n)];
    while v.len() <= cells {
        let last = *v.last().unwrap();
        let next = {
            let ideal = last + rng.range(20, 90);
            special(rng, ideal, n)
        };
        if next > last {
            v.push(next);
        }
    }
    v
}

/// A quad `[p00, p10, p11, p01]` split along one diagonal or the other.
fn split_quad(rng: &mut Rng, q: [P; 4], main_diagonal: bool) -> [Tri; 2] {
    let [a, b, c, d] = q;
    let t = if main_diagonal {
        [[a, b, c], [a, c, d]]
    } else {
        [[a, b, d], [b, c, d]]
    };
    t.map(|t| shuffle_winding(rng, t))
}

/// Grids of quads, each split along a random diagonal: an axis-aligned grid against
/// its bounding rectangle as two triangles, and a jittered grid against itself with
/// other diagonals.
fn quad_grids<M: CoverageMask>(cases: usize, seed: u64) {
    let mut rng = Rng::new(seed);
    let mut totals = Totals::default();
    for case in 0..cases {
        let nx = rng.range(1, 6) as usize;
        let ny = rng.range(1, 5) as usize;
        let xs = {
            let ideal = rng.range(-40, 100);
            grid_lines(&mut rng, ideal, nx, M::COLS)
        };
        let ys = {
            let ideal = rng.range(-40, 80);
            grid_lines(&mut rng, ideal, ny, M::ROWS)
        };
        let jitter = case % 2 == 1;
        // Vertex (i, j); jittered grids keep some lines straight (shared horizontal
        // and vertical edges) and move the rest a little.
        let keep_col: Vec<bool> = (0..=nx).map(|_| rng.chance(0.3)).collect();
        let keep_row: Vec<bool> = (0..=ny).map(|_| rng.chance(0.3)).collect();
        let mut vertex = vec![vec![(0i64, 0i64); ny + 1]; nx + 1];
        for i in 0..=nx {
            for j in 0..=ny {
                let (mut x, mut y) = (xs[i], ys[j]);
                if jitter && !keep_col[i] {
                    x = {
                        let ideal = x + rng.range(-4, 4);
                        special(&mut rng, ideal, M::COLS)
                    };
                }
                if jitter && !keep_row[j] {
                    y = {
                        let ideal = y + rng.range(-4, 4);
                        special(&mut rng, ideal, M::ROWS)
                    };
                }
                vertex[i][j] = (x, y);
            }
        }
        let quad = |i: usize, j: usize| {
            [
                vertex[i][j],
                vertex[i + 1][j],
                vertex[i + 1][j + 1],
                vertex[i][j + 1],
            ]
        };
        // Both diagonals must be valid splits: every quad strictly convex.
        let convex = (0..nx).all(|i| {
            (0..ny).all(|j| {
                let q = quad(i, j);
                (0..4).all(|k| orient(q[k], q[(k + 1) % 4], q[(k + 2) % 4]) > 0)
            })
        });
        if !convex {
            continue;
        }
        let tiling = |rng: &mut Rng| -> Vec<Tri> {
            let mut out = Vec::new();
            for i in 0..nx {
                for j in 0..ny {
                    let main = rng.chance(0.5);
                    out.extend(split_quad(rng, quad(i, j), main));
                }
            }
            out
        };
        let first = tiling(&mut rng);
        let a = draw::<M>(&first, "quad grid");
        if jitter {
            let second = tiling(&mut rng);
            let b = draw::<M>(&second, "quad grid, other diagonals");
            assert_same_cover(&a, &b, &format!("jittered grid {vertex:?}"));
        } else {
            let rect = [
                (xs[0], ys[0]),
                (xs[nx], ys[0]),
                (xs[nx], ys[ny]),
                (xs[0], ys[ny]),
            ];
            let main = rng.chance(0.5);
            let whole = split_quad(&mut rng, rect, main);
            let b = draw::<M>(&whole, "rectangle as two triangles");
            assert_same_cover(&a, &b, &format!("grid x {xs:?} y {ys:?}"));
        }
        totals.add(&a);
    }
    totals.report(M::NAME, "quad grids");
}

/// Splits random triangles of `tris` at random interior points, `steps` times.
fn subdivide<M: CoverageMask>(rng: &mut Rng, mut tris: Vec<Tri>, steps: usize) -> Vec<Tri> {
    for _ in 0..steps {
        let k = rng.below(tris.len() as u64) as usize;
        let mut t = tris[k];
        if orient(t[0], t[1], t[2]) < 0 {
            t.swap(1, 2);
        }
        let xs = (
            t.iter().map(|p| p.0).min().unwrap(),
            t.iter().map(|p| p.0).max().unwrap(),
        );
        let ys = (
            t.iter().map(|p| p.1).min().unwrap(),
            t.iter().map(|p| p.1).max().unwrap(),
        );
        for _ in 0..40 {
            let p = random_point::<M>(rng, xs, ys);
            if strictly_inside_convex(&t, p) {
                tris.swap_remove(k);
                for i in 0..3 {
                    tris.push(shuffle_winding(rng, [t[i], t[(i + 1) % 3], p]));
                }
                break;
            }
        }
    }
    tris
}

/// A rectangle (two triangles) and a triangle, each recursively split at random
/// interior points, against the undivided shape.
fn subdivisions<M: CoverageMask>(cases: usize, seed: u64) {
    let mut rng = Rng::new(seed);
    let mut totals = Totals::default();
    for case in 0..cases {
        let steps = rng.range(1, 40) as usize;
        let whole: Vec<Tri> = if case % 2 == 0 {
            let x0 = {
                let ideal = rng.range(-30, 200);
                special(&mut rng, ideal, M::COLS)
            };
            let y0 = {
                let ideal = rng.range(-30, 150);
                special(&mut rng, ideal, M::ROWS)
            };
            let x1 = {
                let ideal = x0 + rng.range(32, 300);
                special(&mut rng, ideal, M::COLS)
            };
            let y1 = {
                let ideal = y0 + rng.range(32, 250);
                special(&mut rng, ideal, M::ROWS)
            };
            if x1 <= x0 || y1 <= y0 {
                continue;
            }
            let main = rng.chance(0.5);
            split_quad(&mut rng, [(x0, y0), (x1, y0), (x1, y1), (x0, y1)], main).to_vec()
        } else {
            let t = [0, 1, 2].map(|_| random_point::<M>(&mut rng, (-40, 420), (-40, 350)));
            if orient(t[0], t[1], t[2]).abs() < 16 * 16 * 4 {
                continue;
            }
            vec![t]
        };
        let pieces = subdivide::<M>(&mut rng, whole.clone(), steps);
        let a = draw::<M>(&pieces, "subdivided shape");
        let b = draw::<M>(&whole, "undivided shape");
        assert_same_cover(
            &a,
            &b,
            &format!("shape {whole:?} subdivided into {pieces:?}"),
        );
        totals.add(&a);
    }
    totals.report(M::NAME, "subdivisions");
}

fn all_cases<M: CoverageMask>(seed: u64) {
    fans::<M>(1000, seed);
    quad_grids::<M>(800, seed + 1);
    subdivisions::<M>(800, seed + 2);
}

#[test]
fn tilings_cover_each_sample_once_4x4() {
    all_cases::<Mask4x4>(0x7110);
}

#[test]
fn tilings_cover_each_sample_once_8x4() {
    all_cases::<Mask8x4>(0x7120);
}

#[test]
fn tilings_cover_each_sample_once_8x8() {
    all_cases::<Mask8x8>(0x7130);
}

/// Two triangles sharing a vertical and a horizontal edge through sample positions:
/// the samples on the shared edges belong to exactly one of them.
#[test]
fn shared_edges_through_samples_hand_made() {
    // Square from (2, 2) to (66, 66) in 1/16 px: x = 2 and x = 66 are sample columns.
    let (a, b, c, e) = ((2, 2), (66, 2), (66, 66), (2, 66));
    let split = draw::<Mask4x4>(&[[a, b, c], [a, c, e]], "square");
    // The square [2, 66) x [2, 66) in 1/16 px contains sample positions 2, 6, ..., 62
    // in each direction: 16 x 16 samples; the right and bottom edges (x = 66, y = 66)
    // are excluded by the top-left rule, the left and top ones included.
    assert_eq!(split.covered_count(), 16 * 16);
    // Split the other way: identical coverage.
    let other = draw::<Mask4x4>(&[[a, b, e], [b, c, e]], "square");
    assert_same_cover(&split, &other, "square both diagonals");
}

/// The counters catch double coverage: a square drawn with both diagonal splits.
#[test]
#[should_panic(expected = "covered twice")]
fn overlap_is_detected() {
    let (a, b, c, e) = ((20, 20), (120, 20), (120, 120), (20, 120));
    draw::<Mask4x4>(&[[a, b, c], [a, c, e], [a, b, e]], "overlapping triangles");
}

/// The comparison catches a crack: a subdivided triangle with one piece missing.
#[test]
#[should_panic(expected = "covered by one triangulation")]
fn gap_is_detected() {
    let t = [(10, 10), (300, 40), (60, 280)];
    let p = (120, 110);
    let pieces = [[t[0], t[1], p], [t[1], t[2], p]];
    let a = draw::<Mask4x4>(&pieces, "two of three pieces");
    let b = draw::<Mask4x4>(&[t], "whole triangle");
    assert_same_cover(&a, &b, "triangle with a missing piece");
}

/// `rasterize` with an empty band (`band_rows == 0`) must draw nothing and must not
/// panic. (Regression: it used to compute `band_y0 + band_rows - 1` in `u32` before
/// checking `band_rows`, which underflows for a band at row 0 and panics where
/// overflow checks are on, as in the test profile of `cargo test`.)
#[test]
fn rasterize_with_an_empty_band_draws_nothing() {
    let v = |x, y| SetupVertex { x, y, z: 100 };
    let setup = TriangleSetup::new(&[v(0, 0), v(64, 0), v(0, 64)], false, W, H).expect("setup");
    let mut counter = SampleCounter::<Mask4x4>::new();
    counter.begin_band(0, H);
    for band_y0 in [5, 0] {
        rasterize::<Mask4x4, _, _>(&setup, band_y0, 0, &mut counter, || {
            setup.color_planes(ColorSource::Linear([[0; 3]; 3]))
        });
    }
    assert_eq!(counter.stats().fragments_generated, 0);
}
