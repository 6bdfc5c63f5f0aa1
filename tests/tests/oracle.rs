//! SPEC section 3: an unlimited A-buffer is exactly a per-sample z-buffer that shades
//! once per fragment. On random scenes, the image of `render_frame` through an
//! unlimited `FragmentBuffer` must equal, pixel for pixel, the image of
//! `render_frame` through a per-sample z-buffer (`abuffer_test_support`'s
//! `PerSampleZBuffer`), for every grid and band height; and the unlimited image
//! must not depend on the band height.
//!
//! A second, independent feed of the same oracle checks the fragment stream itself:
//! every triangle is rendered alone (same camera, light and placement), its fragments
//! are read back, and the streams are replayed in the renderer's visiting order
//! (first row of the bounding box, then scene order). A triangle's fragments depend
//! neither on the other triangles nor on the band height, so the replay must give
//! the same image.

use abuffer_test_support::{first_difference, FragmentStorage, PerSampleZBuffer};
use mcu_abuffer::band_buffer::BandBuffer;
use mcu_abuffer::coverage::{CoverageMask, Mask4x4, Mask8x4, Mask8x8};
use system_tests::{
    deep_scene, random_scene, render, rgb888, rgb_of, triangle_streams, Rng, SceneParams, Stream,
};

const WIDTH: u16 = 64;
const HEIGHT: u16 = 48;
const BANDS: [u16; 4] = [1, 5, 16, HEIGHT];

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
    let mut capture = FragmentStorage::<M>::unlimited(WIDTH, HEIGHT);
    let mut buffers: Vec<(u16, FragmentStorage<M>, PerSampleZBuffer<M>)> = BANDS
        .iter()
        .map(|&b| {
            (
                b,
                FragmentStorage::<M>::unlimited(WIDTH, b),
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
            deep_scene(&mut rng, &params)
        } else {
            random_scene(&mut rng, &params)
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
            cov.removed_hidden += u64::from(stats.buffer.fragments_removed_hidden);
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
    assert_eq!(z.resolve_all(rgb888([0, 0, 255])), vec![100, 50, 0]);
    z.begin_band(0, 1);
    z.insert(
        0,
        0,
        &system_tests::fragment(Mask4x4(0x000F), 10, 0, 0, [255, 255, 255]),
    );
    // 4 white + 12 background (0, 0, 255): r = (255*4 + 8) >> 4 = 64, b = (255*16 + 8) >> 4 = 255.
    assert_eq!(z.resolve_all(rgb888([0, 0, 255])), vec![64, 64, 255]);
}
