//! SPEC sections 3 to 5: invariants of the fragment buffer (main slots + pool
//! addresses + shared pool) while `render_frame` draws dense random scenes, under
//! every overflow policy and several memory configurations:
//!
//! - stored masks are non-empty and pairwise disjoint;
//! - each pixel's list is sorted by depth at the pixel center, nearest first;
//! - a pixel holds at most `N_main + N_extra` fragments;
//! - the pool holds exactly the fragments beyond each pixel's main slots;
//! - the pool is empty once the frame is done.
//!
//! And with room for every sample (`N_main + N_extra >= SAMPLES`, a pool for every
//! address) the shared buffer draws exactly the unlimited image, without merging.
//!
//! A buffer whose width and slots per pixel are constants of its type
//! (`ConstShape`, as the firmware's static memory makes it) draws the same bits
//! and counts the same statistics as one that reads them from its configuration.

use abuffer_test_support::{first_difference, FragmentStorage, OwnedScene};
use mcu_abuffer::band_buffer::BandBuffer;
use mcu_abuffer::coverage::{CoverageMask, Mask4x4, Mask8x4, Mask8x8};
use mcu_abuffer::fragment::Fragment;
use mcu_abuffer::fragment_buffer::{BufferConfig, ConstShape, FragmentBuffer, OverflowPolicy};
use system_tests::{deep_scene, random_scene, render, Rng, SceneParams};

const WIDTH: u16 = 48;
const HEIGHT: u16 = 32;
const BANDS: [u16; 3] = [1, 6, HEIGHT];
const POLICIES: [OverflowPolicy; 3] = [
    OverflowPolicy::MergeFarthest,
    OverflowPolicy::MergeClosest,
    OverflowPolicy::Discard,
];
/// `(N_main, N_extra, N_pool)`.
const CONFIGS: [(u8, u8, usize); 5] = [(1, 0, 0), (1, 1, 4), (1, 2, 16), (2, 2, 64), (1, 3, 200)];

/// Dense scenes: many small overlapping triangles, or (every other seed) thin
/// triangles crossing at a few hubs, which makes pixels very deep.
fn dense_scene(seed: u64) -> OwnedScene {
    let mut rng = Rng::new(seed);
    let params = SceneParams {
        width: WIDTH,
        height: HEIGHT,
        min_triangles: 120,
        max_triangles: 260,
        min_size: 0.3,
        max_size: 1.8,
        rotate: seed % 5 == 4,
    };
    if seed % 2 == 1 {
        deep_scene(&mut rng, &params)
    } else {
        random_scene(&mut rng, &params)
    }
}

/// Checks every pixel of the band just filled; returns the fragments held.
fn check_band<M: CoverageMask>(
    b: &FragmentBuffer<'_, M, u32>,
    rows: u16,
    what: &str,
) -> (u64, u32) {
    let config = b.config();
    let capacity = config.pixel_capacity();
    let main = config.main_slots as usize;
    let mut beyond_main = 0usize;
    let mut held = 0u64;
    let mut most = 0u32;
    for row in 0..rows {
        for x in 0..config.width {
            let frags: Vec<Fragment<M>> = b.fragments(x, row).collect();
            let n = frags.len();
            assert_eq!(b.pixel_fragment_count(x, row) as usize, n, "{what}");
            assert!(
                n <= capacity,
                "{what}: pixel ({x}, row {row}) holds {n} fragments, capacity {capacity}"
            );
            let mut union = M::EMPTY;
            for (i, f) in frags.iter().enumerate() {
                assert!(
                    !f.mask.is_empty(),
                    "{what}: pixel ({x}, row {row}) keeps an empty fragment: {frags:?}"
                );
                assert!(
                    (union & f.mask).is_empty(),
                    "{what}: pixel ({x}, row {row}) has overlapping masks: {frags:?}"
                );
                union = union | f.mask;
                if i > 0 {
                    assert!(
                        frags[i - 1].z <= f.z,
                        "{what}: pixel ({x}, row {row}) not sorted nearest first: {frags:?}"
                    );
                }
            }
            beyond_main += n.saturating_sub(main);
            held += n as u64;
            most = most.max(n as u32);
        }
    }
    assert_eq!(
        b.pool().in_use(),
        beyond_main,
        "{what}: pool slots in use differ from the fragments beyond the main slots"
    );
    assert!(b.pool().in_use() <= b.pool().capacity());
    (held, most)
}

#[derive(Default)]
struct Seen {
    merges: u64,
    discarded: u64,
    held: u64,
    most: u32,
    frames: usize,
}

fn invariants<M: CoverageMask>(scenes: u64, seed: u64) {
    let mut seen = Seen::default();
    for i in 0..scenes {
        let scene_seed = seed * 1000 + i;
        let scene = dense_scene(scene_seed);
        let objects = scene.objects();
        let lib_scene = scene.scene(&objects);
        let options = scene.options();
        for &band in &BANDS {
            for (main, extra, pool) in CONFIGS {
                for policy in POLICIES {
                    let config = BufferConfig {
                        width: WIDTH,
                        band_height: band,
                        main_slots: main,
                        extra_addresses: extra,
                        policy,
                    };
                    let what = format!(
                        "{} scene seed {scene_seed}, band {band}, {policy:?} main {main} \
                         extra {extra} pool {pool}",
                        M::NAME
                    );
                    let mut storage = FragmentStorage::<M>::new(config, pool);
                    let mut buffer = storage.buffer();
                    let mut next_y0 = 0u16;
                    let (_, stats) = render(&lib_scene, &options, &mut buffer, |y0, rows, b| {
                        assert_eq!(y0, next_y0, "{what}: bands out of order");
                        next_y0 = y0 + rows;
                        let (held, most) = check_band(b, rows, &what);
                        seen.held += held;
                        seen.most = seen.most.max(most);
                    });
                    assert_eq!(next_y0, HEIGHT, "{what}: bands do not cover the image");
                    assert_eq!(
                        buffer.pool().in_use(),
                        0,
                        "{what}: pool not emptied after the frame"
                    );
                    assert!(
                        stats.buffer.max_fragments_in_pixel as usize <= config.pixel_capacity()
                    );
                    if policy == OverflowPolicy::Discard {
                        assert_eq!(stats.buffer.merges, 0, "{what}: discard policy merged");
                    } else {
                        assert_eq!(
                            stats.buffer.fragments_discarded, 0,
                            "{what}: merging policy discarded"
                        );
                    }
                    seen.merges += u64::from(stats.buffer.merges);
                    seen.discarded += u64::from(stats.buffer.fragments_discarded);
                    seen.frames += 1;
                }
            }
        }
    }
    println!(
        "{}: {} frames, {} merges, {} discards, {} fragments held at band ends, \
         at most {} in a pixel",
        M::NAME,
        seen.frames,
        seen.merges,
        seen.discarded,
        seen.held,
        seen.most
    );
    // The scenes must overflow the small configurations.
    assert!(seen.merges > 1000 && seen.discarded > 1000);
    assert!(
        seen.most >= 4,
        "no pixel ever filled a 4-fragment configuration"
    );
}

#[test]
fn buffer_invariants_4x4() {
    invariants::<Mask4x4>(60, 44);
}

#[test]
fn buffer_invariants_8x4() {
    invariants::<Mask8x4>(50, 84);
}

#[test]
fn buffer_invariants_8x8() {
    invariants::<Mask8x8>(40, 88);
}

/// With `N_main + N_extra >= SAMPLES` and a pool for every address, the shared buffer
/// (merge-farthest) never overflows and draws the unlimited image exactly.
fn room_for_every_sample<M: CoverageMask>(scenes: u64, seed: u64) {
    let s = M::SAMPLES as u8;
    let mut deepest = 0;
    for i in 0..scenes {
        let scene_seed = seed * 1000 + i;
        let scene = dense_scene(scene_seed);
        let objects = scene.objects();
        let lib_scene = scene.scene(&objects);
        let options = scene.options();
        let mut unlimited = FragmentStorage::<M>::unlimited(WIDTH, HEIGHT);
        let (reference, ref_stats) =
            render(&lib_scene, &options, &mut unlimited.buffer(), |_, _, _| {});
        assert_eq!(ref_stats.buffer.merges, 0);
        deepest = deepest.max(ref_stats.buffer.max_fragments_in_pixel);
        for &band in &BANDS {
            for (main, extra) in [(2, s - 2), (4, s - 4), (3, s)] {
                let config = BufferConfig {
                    width: WIDTH,
                    band_height: band,
                    main_slots: main,
                    extra_addresses: extra,
                    policy: OverflowPolicy::MergeFarthest,
                };
                let pool = WIDTH as usize * band as usize * extra as usize;
                let mut storage = FragmentStorage::<M>::new(config, pool);
                let mut buffer = storage.buffer();
                let (image, stats) = render(&lib_scene, &options, &mut buffer, |_, rows, b| {
                    check_band(b, rows, "room for every sample");
                });
                let what = format!(
                    "{} scene seed {scene_seed}, band {band}, main {main} extra {extra} pool {pool}",
                    M::NAME
                );
                assert_eq!(stats.buffer.merges, 0, "{what}: merged");
                if let Some((x, y, got, want)) = first_difference(WIDTH, &image, &reference) {
                    panic!(
                        "{what}: pixel ({x}, {y}) is {got:?}, the unlimited buffer gives {want:?}"
                    );
                }
            }
        }
    }
    println!(
        "{}: at most {deepest} fragments in a pixel of the unlimited buffer",
        M::NAME
    );
    // Some pixels must need pool slots even with 4 main slots.
    assert!(
        deepest >= 5,
        "scenes too simple: at most {deepest} fragments in a pixel"
    );
}

#[test]
fn shared_with_room_for_every_sample_equals_unlimited_4x4() {
    room_for_every_sample::<Mask4x4>(60, 144);
}

#[test]
fn shared_with_room_for_every_sample_equals_unlimited_8x4() {
    room_for_every_sample::<Mask8x4>(50, 184);
}

#[test]
fn shared_with_room_for_every_sample_equals_unlimited_8x8() {
    room_for_every_sample::<Mask8x8>(40, 188);
}

/// Renders `scenes` dense scenes in every band height and overflow policy with
/// `MAIN` main slots, `EXTRA` pool addresses and `pool` pool slots per band,
/// once with the sizes read from the configuration and once with them as
/// constants of the buffer's type: the images and statistics must be equal.
fn const_shape_draws_the_same<M: CoverageMask, const MAIN: usize, const EXTRA: usize>(
    pool: usize,
    scenes: u64,
    seed: u64,
) {
    const W: usize = WIDTH as usize;
    for i in 0..scenes {
        let scene = dense_scene(seed * 1000 + i);
        let objects = scene.objects();
        let lib_scene = scene.scene(&objects);
        let options = scene.options();
        for &band in &BANDS {
            for policy in POLICIES.into_iter().chain([OverflowPolicy::SplitBands]) {
                let config = BufferConfig {
                    width: WIDTH,
                    band_height: band,
                    main_slots: MAIN as u8,
                    extra_addresses: EXTRA as u8,
                    policy,
                };
                let mut read = FragmentStorage::<M>::new(config, pool);
                let (want, want_stats) =
                    render(&lib_scene, &options, &mut read.buffer(), |_, _, _| {});
                let mut fixed = FragmentStorage::<M>::new(config, pool);
                let mut buffer = fixed
                    .try_shaped_buffer::<ConstShape<W, MAIN, EXTRA>>()
                    .expect("the shape's constants are the configuration's");
                let (got, got_stats) = render(&lib_scene, &options, &mut buffer, |_, _, _| {});
                let what = format!(
                    "{} scene seed {}, band {band}, {policy:?}, main {MAIN} extra {EXTRA} pool {pool}",
                    M::NAME,
                    seed * 1000 + i
                );
                if let Some((x, y, got, want)) = first_difference(WIDTH, &got, &want) {
                    panic!(
                        "{what}: pixel ({x}, {y}) is {got:?} with constant sizes, {want:?} without"
                    );
                }
                assert_eq!(got_stats, want_stats, "{what}: statistics differ");
            }
        }
    }
}

#[test]
fn const_shape_draws_the_same_4x4() {
    const_shape_draws_the_same::<Mask4x4, 1, 2>(60, 12, 401);
    const_shape_draws_the_same::<Mask4x4, 1, 0>(0, 6, 402);
    const_shape_draws_the_same::<Mask4x4, 2, 3>(200, 6, 403);
}

#[test]
fn const_shape_draws_the_same_8x8() {
    const_shape_draws_the_same::<Mask8x8, 1, 2>(60, 8, 404);
    const_shape_draws_the_same::<Mask8x8, 3, 1>(16, 6, 405);
}
