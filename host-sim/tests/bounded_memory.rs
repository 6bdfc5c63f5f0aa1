//! Bounded memory against `unlimited`: the `split-bands` policy keeps the
//! image within the error thresholds on dense, two-sided, interpenetrating
//! scenes in a tighter memory than the default Cortex-M4 configuration (band
//! 8, one main slot, two pool addresses, 512 pool slots, the former default;
//! today's has 6-row bands and 1,152 slots), where the paper's merge of the two
//! farthest fragments with a pinned pool does not.

use host_sim::builtins::builtin_scene;
use host_sim::compare::nmse;
use host_sim::convert::to_fixed;
use host_sim::render::{render, Method, RenderConfig, RenderOutput};

/// The error a bounded-memory image may have against `unlimited`.
const NMSE_LIMIT: f64 = 1e-4;
/// Differences above this many levels in a channel are visible speckles.
const SPECKLE_LEVELS: i32 = 24;
/// At most this fraction of the pixels may be speckles (0.02 %).
const SPECKLE_FRACTION: f64 = 0.0002;

/// NMSE against `unlimited` and the fraction of speckled pixels of `method`
/// on the built-in `scene` turned by `angle` degrees, in 8-row bands with a
/// pool of 512 slots.
fn errors(scene: &str, method: Method, angle: f32) -> (f64, f64) {
    let desc = builtin_scene(scene, 240, 240).expect("built-in scene");
    let fixed = to_fixed(&desc).expect("scene converts");
    let config = |method| RenderConfig {
        method,
        band: 8,
        main: 1,
        extra: 2,
        pool: Some(512),
        ..Default::default()
    };
    let image = render(&fixed, &config(method), angle).expect("renders");
    let reference = render(&fixed, &config(Method::Unlimited), angle).expect("renders");
    let speckles = image
        .rgb
        .chunks_exact(3)
        .zip(reference.rgb.chunks_exact(3))
        .filter(|(a, b)| (0..3).any(|c| (a[c] as i32 - b[c] as i32).abs() > SPECKLE_LEVELS))
        .count();
    (
        nmse(&image.rgb, &reference.rgb),
        speckles as f64 / (image.width as f64 * image.height as f64),
    )
}

#[test]
fn split_bands_looks_like_unlimited_on_dense_two_sided_scenes() {
    // The teapot is drawn two-sided (its inside shows); overdraw stacks
    // interpenetrating layers.
    for scene in ["teapot", "teapot:24", "overdraw"] {
        for angle in [0.0, 135.0] {
            let (error, speckles) = errors(scene, Method::SplitBands, angle);
            assert!(
                error <= NMSE_LIMIT,
                "{scene} at {angle} degrees: NMSE {error:.2e} against unlimited"
            );
            assert!(
                speckles <= SPECKLE_FRACTION,
                "{scene} at {angle} degrees: {:.3} % speckled pixels",
                speckles * 100.0
            );
        }
    }
}

#[test]
fn the_papers_merge_with_a_pinned_pool_does_not() {
    // The same memory under the paper's policy: the pool runs out and
    // pixels merge what later fragments would have told apart.
    let (error, speckles) = errors("teapot", Method::Shared, 0.0);
    assert!(error > NMSE_LIMIT, "NMSE {error:.2e}");
    assert!(speckles > SPECKLE_FRACTION, "{speckles}");
}

#[test]
fn split_bands_image_does_not_depend_on_the_pool_size() {
    // Within a pixel the order of work is the same for every band height,
    // so however often the pool runs out, the image is the same as with a
    // pool that never does, as long as every single row fits the pool (a
    // row is not split further).
    let with_pool = |pool| split_bands_image("teapot", 8, Some(pool));
    let small = with_pool(256);
    let large = with_pool(240 * 8 * 2);
    assert!(small.stats.band_splits > 0);
    assert_eq!(large.stats.band_splits, 0);
    assert_eq!(small.rgb, large.rgb);
}

#[test]
fn split_bands_image_does_not_depend_on_the_band_height() {
    // What is left of the error against `unlimited` (pixels whose lists are
    // full) cannot line up with band boundaries: the image is the same bits
    // whichever rows make up a band, from one row to the whole frame.
    let with_band = |band| split_bands_image("teapot:24", band, None).rgb;
    let whole_frame = with_band(240);
    for band in [1, 3, 6, 16] {
        assert!(
            with_band(band) == whole_frame,
            "band {band} differs from one band of 240 rows"
        );
    }
}

/// `split-bands` on the built-in `scene` turned by 30 degrees, in bands of
/// `band` rows with `pool` slots (the default pool when `None`).
fn split_bands_image(scene: &str, band: u16, pool: Option<usize>) -> RenderOutput {
    let desc = builtin_scene(scene, 240, 240).expect("built-in scene");
    let fixed = to_fixed(&desc).expect("scene converts");
    let config = RenderConfig {
        method: Method::SplitBands,
        band,
        pool,
        ..Default::default()
    };
    render(&fixed, &config, 30.0).expect("renders")
}
