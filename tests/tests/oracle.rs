//! SPEC section 3: an unlimited A-buffer is exactly a per-sample z-buffer that shades
//! once per fragment. On random scenes, the image of `render_frame` through an
//! unlimited `FragmentBuffer` must equal, pixel for pixel, the image of
//! `render_frame` through a per-sample z-buffer (`PerSampleZBuffer`, a `BandBuffer`
//! written here), for every grid and band height; and the unlimited image must not
//! depend on the band height.
//!
//! A second, independent feed of the same oracle checks the fragment stream itself:
//! every triangle is rendered alone (same camera, light and placement), its fragments
//! are read back, and the streams are replayed in the renderer's visiting order
//! (first row of the bounding box, then scene order). A triangle's fragments depend
//! neither on the other triangles nor on the band height, so the replay must give
//! the same image.

use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};
use mcu_abuffer::band_buffer::BandBuffer;
use mcu_abuffer::coverage::{CoverageMask, Mask4x4, Mask8x4, Mask8x8};
use mcu_abuffer::fragment::Fragment;
use mcu_abuffer::stats::BufferStats;
use system_tests::{
    first_difference, render, rgb_of, triangle_streams, AStorage, OwnedScene, Rng, SceneParams,
    Stream,
};

const WIDTH: u16 = 64;
const HEIGHT: u16 = 48;
const BANDS: [u16; 4] = [1, 5, 16, HEIGHT];

/// Per-sample z-buffer over one band: a depth (`Fragment::depth_at`, i.e.
/// `16 z + dzdx ox + dzdy oy`) and a color per sample.
struct PerSampleZBuffer<M: CoverageMask> {
    width: u16,
    band_height: u16,
    depth: Vec<Option<i32>>,
    color: Vec<[u8; 3]>,
    stats: BufferStats,
    _grid: core::marker::PhantomData<M>,
}

impl<M: CoverageMask> PerSampleZBuffer<M> {
    fn new(width: u16, band_height: u16) -> Self {
        let n = width as usize * band_height as usize * M::SAMPLES as usize;
        Self {
            width,
            band_height,
            depth: vec![None; n],
            color: vec![[0; 3]; n],
            stats: BufferStats::default(),
            _grid: core::marker::PhantomData,
        }
    }

    fn base(&self, x: u16, row: u16) -> usize {
        (row as usize * self.width as usize + x as usize) * M::SAMPLES as usize
    }

    /// Per pixel: the mean of the sample colors (background where empty), rounded to
    /// nearest as `(sum + SAMPLES / 2) >> log2(SAMPLES)`.
    fn resolve_pixel(&self, x: u16, row: u16, background: [u8; 3]) -> [u8; 3] {
        let base = self.base(x, row);
        let mut sum = [0u32; 3];
        for i in base..base + M::SAMPLES as usize {
            let c = if self.depth[i].is_some() {
                self.color[i]
            } else {
                background
            };
            for (acc, v) in sum.iter_mut().zip(c) {
                *acc += v as u32;
            }
        }
        sum.map(|v| ((v + M::SAMPLES / 2) >> M::SAMPLES_LOG2) as u8)
    }

    /// The whole band as RGB888 bytes.
    fn resolve_all(&self, background: [u8; 3]) -> Vec<u8> {
        let mut out = Vec::new();
        for row in 0..self.band_height {
            for x in 0..self.width {
                out.extend(self.resolve_pixel(x, row, background));
            }
        }
        out
    }

    /// Distinct colors visible in pixel `(x, row)`.
    fn surfaces(&self, x: u16, row: u16) -> usize {
        let base = self.base(x, row);
        let mut seen: Vec<[u8; 3]> = Vec::new();
        for i in base..base + M::SAMPLES as usize {
            if self.depth[i].is_some() && !seen.contains(&self.color[i]) {
                seen.push(self.color[i]);
            }
        }
        seen.len()
    }
}

impl<M: CoverageMask> BandBuffer<M> for PerSampleZBuffer<M> {
    fn width(&self) -> u16 {
        self.width
    }

    fn band_height(&self) -> u16 {
        self.band_height
    }

    fn begin_band(&mut self, _y0: u16, rows: u16) {
        let n = self.base(0, rows.min(self.band_height));
        self.depth[..n].fill(None);
    }

    /// For every sample of the fragment's mask, the fragment wins when its depth there
    /// is nearer than or equal to the stored one (ties go to the newer fragment).
    fn insert(&mut self, x: u16, row: u16, f: &Fragment<M>) {
        self.stats.fragments_generated += 1;
        let base = self.base(x, row);
        let rgb = rgb_of(f);
        for s in 0..M::SAMPLES {
            if !f.mask.get(s) {
                continue;
            }
            let d = f.depth_at(s % M::COLS, s / M::COLS);
            let slot = base + s as usize;
            let wins = match self.depth[slot] {
                None => true,
                Some(stored) => d <= stored,
            };
            if wins {
                self.depth[slot] = Some(d);
                self.color[slot] = rgb;
            }
        }
    }

    fn resolve_row(&mut self, row: u16, background: Rgb888, out: &mut [Rgb888]) {
        let bg = [background.r(), background.g(), background.b()];
        for (x, px) in out.iter_mut().enumerate().take(self.width as usize) {
            let [r, g, b] = self.resolve_pixel(x as u16, row, bg);
            *px = Rgb888::new(r, g, b);
        }
    }

    fn pixel_fragment_count(&self, x: u16, row: u16) -> u32 {
        self.surfaces(x, row) as u32
    }

    fn stats(&self) -> BufferStats {
        self.stats
    }

    fn take_stats(&mut self) -> BufferStats {
        core::mem::take(&mut self.stats)
    }
}

fn describe_pixel<M: CoverageMask>(
    streams: &[((usize, usize), bool, Stream<M>)],
    x: usize,
    y: usize,
) -> String {
    let mut s = String::new();
    for (tri, _, stream) in streams {
        for (fx, fy, f) in stream {
            if *fx as usize == x && *fy as usize == y {
                s.push_str(&format!(
                    "  triangle {tri:?}: mask {:?} z {} dzdx {} dzdy {} rgb {:?}\n",
                    f.mask,
                    f.z,
                    f.dzdx,
                    f.dzdy,
                    rgb_of(f)
                ));
            }
        }
    }
    s
}

#[derive(Default)]
struct Coverage {
    scenes: usize,
    triangles: usize,
    mixed_pixels: usize,
    max_fragments_in_pixel: u32,
    removed_hidden: u64,
    clipped_or_rotated: usize,
    clipped_triangles: u64,
}

fn run_grid<M: CoverageMask>(scenes: u64, seed: u64) -> Coverage {
    let mut capture = AStorage::<M>::unlimited(WIDTH, HEIGHT);
    let mut buffers: Vec<(u16, AStorage<M>, PerSampleZBuffer<M>)> = BANDS
        .iter()
        .map(|&b| {
            (
                b,
                AStorage::<M>::unlimited(WIDTH, b),
                PerSampleZBuffer::<M>::new(WIDTH, b),
            )
        })
        .collect();
    let mut replay = PerSampleZBuffer::<M>::new(WIDTH, HEIGHT);
    let mut cov = Coverage::default();
    for i in 0..scenes {
        let scene_seed = seed.wrapping_mul(1_000_003).wrapping_add(i);
        let mut rng = Rng::new(scene_seed);
        let rotate = i % 6 == 5;
        let deep = i % 3 == 1;
        let params = SceneParams {
            width: WIDTH,
            height: HEIGHT,
            min_triangles: if deep { 20 } else { 3 },
            max_triangles: if deep { 120 } else { 40 },
            min_size: 0.3,
            max_size: 3.5,
            rotate,
        };
        let scene = if deep {
            OwnedScene::deep(&mut rng, &params)
        } else {
            OwnedScene::random(&mut rng, &params)
        };
        cov.scenes += 1;
        cov.triangles += scene.triangle_count();
        cov.clipped_or_rotated += rotate as usize;
        let what = format!("{} scene seed {scene_seed}", M::NAME);

        // The oracle fed with each triangle's fragments, in visiting order.
        let streams = triangle_streams(&scene, &mut capture);
        replay.begin_band(0, HEIGHT);
        for (tri, skipped, stream) in &streams {
            assert!(
                !*skipped || stream.is_empty(),
                "{what}: triangle {tri:?} is skipped by binning but drew fragments"
            );
            for (x, y, f) in stream {
                replay.insert(*x, *y, f);
            }
        }
        let replayed = replay.resolve_all(scene.background);
        for y in 0..HEIGHT {
            for x in 0..WIDTH {
                if replay.surfaces(x, y) >= 2 {
                    cov.mixed_pixels += 1;
                }
            }
        }

        // The oracle and the unlimited A-buffer through render_frame, every band height.
        let objects = scene.objects();
        let lib_scene = scene.scene(&objects);
        let options = scene.options();
        let mut first_image: Option<Vec<u8>> = None;
        for (band, storage, oracle) in buffers.iter_mut() {
            let (expected, _) = render(&lib_scene, &options, oracle, |_, _, _| {});
            if let Some((x, y, got, want)) = first_difference(WIDTH, &expected, &replayed) {
                panic!(
                    "{what} band {band}: the per-sample z-buffer gives {got:?} at ({x}, {y}) \
                     through render_frame but {want:?} from the replayed fragment streams"
                );
            }
            let mut buffer = storage.buffer();
            let (image, stats) = render(&lib_scene, &options, &mut buffer, |_, _, _| {});
            assert_eq!(
                stats.buffer.merges, 0,
                "{what} band {band}: the unlimited buffer merged"
            );
            assert_eq!(stats.buffer.fragments_discarded, 0);
            cov.max_fragments_in_pixel = cov
                .max_fragments_in_pixel
                .max(stats.buffer.max_fragments_in_pixel);
            cov.removed_hidden += stats.buffer.fragments_removed_hidden;
            cov.clipped_triangles += stats.geometry.triangles_clipped as u64;
            if let Some((x, y, got, want)) = first_difference(WIDTH, &image, &expected) {
                panic!(
                    "{what} band {band}: pixel ({x}, {y}) is {got:?}, \
                     the per-sample z-buffer gives {want:?}; fragments in visiting order:\n{}",
                    describe_pixel(&streams, x, y)
                );
            }
            match &first_image {
                None => first_image = Some(image),
                Some(first) => assert!(
                    first == &image,
                    "{what}: band {band} changes the unlimited image"
                ),
            }
        }
    }
    cov
}

fn check_grid<M: CoverageMask>(scenes: u64, seed: u64) {
    let cov = run_grid::<M>(scenes, seed);
    println!(
        "{}: {} scenes, {} triangles ({} rotated scenes, {} clipped triangle renders), {} pixels with 2+ visible surfaces, \
         at most {} fragments in a pixel, {} fragments removed as hidden",
        M::NAME,
        cov.scenes,
        cov.triangles,
        cov.clipped_or_rotated,
        cov.clipped_triangles,
        cov.mixed_pixels,
        cov.max_fragments_in_pixel,
        cov.removed_hidden
    );
    // The scenes must exercise what the oracle checks.
    assert!(
        cov.mixed_pixels > 1000,
        "too few pixels with several surfaces"
    );
    assert!(cov.max_fragments_in_pixel >= 8, "no deep pixel");
    assert!(cov.removed_hidden > 0);
    assert!(cov.clipped_triangles > 0, "no scene exercised clipping");
}

#[test]
fn unlimited_abuffer_equals_per_sample_zbuffer_4x4() {
    check_grid::<Mask4x4>(1000, 0x4A4A);
}

#[test]
fn unlimited_abuffer_equals_per_sample_zbuffer_8x4() {
    check_grid::<Mask8x4>(800, 0x8A4A);
}

#[test]
fn unlimited_abuffer_equals_per_sample_zbuffer_8x8() {
    check_grid::<Mask8x8>(600, 0x8A8A);
}

/// The oracle itself: a hand-checked pixel with two crossing fragments.
#[test]
fn oracle_resolves_a_split_pixel() {
    let mut z = PerSampleZBuffer::<Mask4x4>::new(1, 1);
    z.begin_band(0, 1);
    // Left half nearer for `a` (tilted in x), `b` flat at the same center depth.
    let a = system_tests::fragment(Mask4x4::FULL, 5000, 100, 0, [200, 0, 0]);
    let b = system_tests::fragment(Mask4x4::FULL, 5000, 0, 0, [0, 100, 0]);
    z.insert(0, 0, &b);
    z.insert(0, 0, &a);
    // 8 samples each: (200*8 + 8) >> 4 = 100, (100*8 + 8) >> 4 = 50.
    assert_eq!(z.resolve_all([0, 0, 255]), vec![100, 50, 0]);
    z.begin_band(0, 1);
    z.insert(
        0,
        0,
        &system_tests::fragment(Mask4x4(0x000F), 10, 0, 0, [255, 255, 255]),
    );
    // 4 white + 12 background (0, 0, 255): r = (255*4 + 8) >> 4 = 64, b = (255*16 + 8) >> 4 = 255.
    assert_eq!(z.resolve_all([0, 0, 255]), vec![64, 64, 255]);
}
