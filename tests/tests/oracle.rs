//! SPEC section 3: an unlimited A-buffer is exactly a per-sample z-buffer that shades
//! once per fragment. On random scenes, the image of `render_frame` through an
//! unlimited `FragmentBuffer` must equal, pixel for pixel, the image of a per-sample
//! z-buffer fed with the same fragments in the same order, for every grid and band
//! height.
//!
//! The tests cannot implement `BandBuffer` (its `resolve_row` names `Rgb888`, which
//! this crate cannot name; see the crate docs), so the oracle is fed differently:
//! every triangle is rendered alone (same camera, light and placement) and its
//! fragments are read back, then the streams are replayed in the renderer's visiting
//! order (first row of the bounding box, then scene order). A triangle's fragments do
//! not depend on the other triangles or on the band height, so this is the stream
//! the full render produces.

use mcu_abuffer::coverage::{CoverageMask, Mask4x4, Mask8x4, Mask8x8};
use mcu_abuffer::fragment::Fragment;
use system_tests::{
    first_difference, render, rgb_of, triangle_streams, AStorage, OwnedScene, Rng, SceneParams,
    Stream,
};

const WIDTH: u16 = 64;
const HEIGHT: u16 = 48;
const BANDS: [u16; 4] = [1, 5, 16, HEIGHT];

/// Per-sample z-buffer: a depth (`Fragment::depth_at`, 16x scaled) and a color per sample.
struct PerSampleZBuffer<M: CoverageMask> {
    width: usize,
    depth: Vec<Option<i32>>,
    color: Vec<[u8; 3]>,
    _grid: core::marker::PhantomData<M>,
}

impl<M: CoverageMask> PerSampleZBuffer<M> {
    fn new(width: u16, height: u16) -> Self {
        let n = width as usize * height as usize * M::SAMPLES as usize;
        Self {
            width: width as usize,
            depth: vec![None; n],
            color: vec![[0; 3]; n],
            _grid: core::marker::PhantomData,
        }
    }

    /// For every sample of the fragment's mask, the fragment wins when its depth there
    /// is nearer than or equal to the stored one (ties go to the newer fragment).
    fn insert(&mut self, x: u16, y: u16, f: &Fragment<M>) {
        let base = (y as usize * self.width + x as usize) * M::SAMPLES as usize;
        let rgb = rgb_of(f);
        for s in 0..M::SAMPLES {
            if !f.mask.get(s) {
                continue;
            }
            let d = f.depth_at(s % M::COLS, s / M::COLS);
            let slot = base + s as usize;
            if self.depth[slot].map_or(true, |stored| d <= stored) {
                self.depth[slot] = Some(d);
                self.color[slot] = rgb;
            }
        }
    }

    /// Per pixel: the mean of the sample colors (background where empty), rounded to
    /// nearest as `(sum + SAMPLES / 2) >> log2(SAMPLES)`.
    fn resolve(&self, background: [u8; 3]) -> Vec<u8> {
        let samples = M::SAMPLES as usize;
        let pixels = self.depth.len() / samples;
        let mut out = Vec::with_capacity(pixels * 3);
        for p in 0..pixels {
            let mut sum = [0u32; 3];
            for s in 0..samples {
                let i = p * samples + s;
                let c = if self.depth[i].is_some() {
                    self.color[i]
                } else {
                    background
                };
                for ch in 0..3 {
                    sum[ch] += c[ch] as u32;
                }
            }
            for s in sum {
                out.push(((s + M::SAMPLES / 2) >> M::SAMPLES_LOG2) as u8);
            }
        }
        out
    }

    /// Distinct fragments (by color) visible in pixel `(x, y)`.
    fn surfaces(&self, x: usize, y: usize) -> usize {
        let samples = M::SAMPLES as usize;
        let base = (y * self.width + x) * samples;
        let mut seen: Vec<[u8; 3]> = Vec::new();
        for s in 0..samples {
            if self.depth[base + s].is_some() && !seen.contains(&self.color[base + s]) {
                seen.push(self.color[base + s]);
            }
        }
        seen.len()
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
}

fn run_grid<M: CoverageMask>(scenes: u64, seed: u64) -> Coverage {
    let mut capture = AStorage::<M>::unlimited(WIDTH, HEIGHT);
    let mut storages: Vec<(u16, AStorage<M>)> = BANDS
        .iter()
        .map(|&b| (b, AStorage::<M>::unlimited(WIDTH, b)))
        .collect();
    let mut cov = Coverage::default();
    for i in 0..scenes {
        let scene_seed = seed.wrapping_mul(1_000_003).wrapping_add(i);
        let mut rng = Rng::new(scene_seed);
        let rotate = i % 6 == 5;
        let params = SceneParams {
            width: WIDTH,
            height: HEIGHT,
            min_triangles: 3,
            max_triangles: 40,
            min_size: 0.3,
            max_size: 3.5,
            rotate,
        };
        let scene = OwnedScene::random(&mut rng, &params);
        cov.scenes += 1;
        cov.triangles += scene.triangle_count();
        cov.clipped_or_rotated += rotate as usize;

        // The oracle, fed with each triangle's fragments in visiting order.
        let streams = triangle_streams(&scene, &mut capture);
        let mut oracle = PerSampleZBuffer::<M>::new(WIDTH, HEIGHT);
        for (tri, skipped, stream) in &streams {
            assert!(
                !*skipped || stream.is_empty(),
                "scene seed {scene_seed}: triangle {tri:?} is skipped by binning but drew fragments"
            );
            for (x, y, f) in stream {
                oracle.insert(*x, *y, f);
            }
        }
        let expected = oracle.resolve(scene.background);
        for y in 0..HEIGHT as usize {
            for x in 0..WIDTH as usize {
                if oracle.surfaces(x, y) >= 2 {
                    cov.mixed_pixels += 1;
                }
            }
        }

        // The unlimited A-buffer through render_frame, for every band height.
        let objects = scene.objects();
        let lib_scene = scene.scene(&objects);
        let options = scene.options();
        let mut first_image: Option<Vec<u8>> = None;
        for (band, storage) in storages.iter_mut() {
            let mut buffer = storage.buffer();
            let (image, stats) = render(&lib_scene, &options, &mut buffer, |_, _, _| {});
            assert_eq!(
                stats.buffer.merges,
                0,
                "{} scene seed {scene_seed} band {band}: the unlimited buffer merged",
                M::NAME
            );
            assert_eq!(stats.buffer.fragments_discarded, 0);
            cov.max_fragments_in_pixel = cov
                .max_fragments_in_pixel
                .max(stats.buffer.max_fragments_in_pixel);
            cov.removed_hidden += stats.buffer.fragments_removed_hidden;
            if let Some((x, y, got, want)) = first_difference(WIDTH, &image, &expected) {
                panic!(
                    "{} scene seed {scene_seed} band {band}: pixel ({x}, {y}) is {got:?}, \
                     the per-sample z-buffer gives {want:?}; fragments in visiting order:\n{}",
                    M::NAME,
                    describe_pixel(&streams, x, y)
                );
            }
            match &first_image {
                None => first_image = Some(image),
                Some(first) => assert!(
                    first == &image,
                    "{} scene seed {scene_seed}: band {band} changes the unlimited image",
                    M::NAME
                ),
            }
        }
    }
    cov
}

fn check_grid<M: CoverageMask>(scenes: u64, seed: u64) {
    let cov = run_grid::<M>(scenes, seed);
    println!(
        "{}: {} scenes, {} triangles ({} rotated scenes), {} pixels with 2+ visible surfaces, \
         at most {} fragments in a pixel, {} fragments removed as hidden",
        M::NAME,
        cov.scenes,
        cov.triangles,
        cov.clipped_or_rotated,
        cov.mixed_pixels,
        cov.max_fragments_in_pixel,
        cov.removed_hidden
    );
    // The scenes must exercise what the oracle checks.
    assert!(
        cov.mixed_pixels > 1000,
        "too few pixels with several surfaces"
    );
    assert!(cov.max_fragments_in_pixel >= 3);
    assert!(cov.removed_hidden > 0);
}

#[test]
fn unlimited_abuffer_equals_per_sample_zbuffer_4x4() {
    check_grid::<Mask4x4>(60, 0x4A4A);
}

#[test]
fn unlimited_abuffer_equals_per_sample_zbuffer_8x4() {
    check_grid::<Mask8x4>(50, 0x8A4A);
}

#[test]
fn unlimited_abuffer_equals_per_sample_zbuffer_8x8() {
    check_grid::<Mask8x8>(40, 0x8A8A);
}

/// The oracle itself: a hand-checked pixel with two crossing fragments.
#[test]
fn oracle_resolves_a_split_pixel() {
    let mut z = PerSampleZBuffer::<Mask4x4>::new(1, 1);
    // Left half nearer for `a` (tilted in x), `b` flat at the same center depth.
    let a = system_tests::fragment(Mask4x4::FULL, 5000, 100, 0, [200, 0, 0]);
    let b = system_tests::fragment(Mask4x4::FULL, 5000, 0, 0, [0, 100, 0]);
    z.insert(0, 0, &b);
    z.insert(0, 0, &a);
    // 8 samples each: (200*8 + 8) >> 4 = 100, (100*8 + 8) >> 4 = 50.
    assert_eq!(z.resolve([0, 0, 255]), vec![100, 50, 0]);
    let mut e = PerSampleZBuffer::<Mask4x4>::new(1, 1);
    e.insert(
        0,
        0,
        &system_tests::fragment(Mask4x4(0x000F), 10, 0, 0, [255, 255, 255]),
    );
    // 4 white + 12 background (0, 0, 255): r = (255*4 + 8) >> 4 = 64, b = (255*16 + 8) >> 4 = 255.
    assert_eq!(e.resolve([0, 0, 255]), vec![64, 64, 255]);
}
