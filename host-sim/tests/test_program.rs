//! The test program's commands: compare, sweep, stats, turntable animation, and
//! the synthetic scenes they run on.

use abuffer_test_support::ScratchDir;
use host_sim::builtins::builtin_scene;
use host_sim::convert::to_fixed;
use host_sim::render::{render, Grid, Method, RenderConfig};
use host_sim::sweep::{
    run_sweep, sweep_configs, to_csv, turntable_angles, Policy, PoolSizing, SweepParams, CSV_HEADER,
};
use std::path::Path;
use std::process::{Command, Output};

fn host_sim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .args(args)
        .output()
        .expect("host-sim runs")
}

fn stdout(o: &Output) -> String {
    assert!(
        o.status.success(),
        "failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn scratch(name: &str) -> ScratchDir {
    ScratchDir::new(&format!("host-sim-{name}"))
}

/// Writes a PNG of any 8-bit color type.
fn write_any_png(path: &Path, w: u32, h: u32, color: png::ColorType, data: &[u8]) {
    let file = std::fs::File::create(path).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), w, h);
    enc.set_color(color);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header().unwrap().write_image_data(data).unwrap();
}

/// The value printed on the `NMSE <value>` line.
fn printed_nmse(out: &str) -> f64 {
    let line = out
        .lines()
        .find(|l| l.starts_with("NMSE "))
        .unwrap_or_else(|| panic!("no NMSE line in {out}"));
    line["NMSE ".len()..].trim().parse().unwrap()
}

#[test]
fn compare_gives_the_exact_nmse_of_hand_made_images() {
    let dir = scratch("compare");
    let (a, b, c, d) = (
        dir.join("a.png"),
        dir.join("b.png"),
        dir.join("c.png"),
        dir.join("d.png"),
    );
    // Reference 2x1: (10, 20, 30), (0, 40, 0). Image: (13, 20, 26), (0, 40, 1).
    write_any_png(&a, 2, 1, png::ColorType::Rgb, &[13, 20, 26, 0, 40, 1]);
    write_any_png(&b, 2, 1, png::ColorType::Rgb, &[10, 20, 30, 0, 40, 0]);
    let out = stdout(&host_sim(&[
        "compare",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
    ]));
    // (9 + 0 + 16 + 0 + 0 + 1) / (100 + 400 + 900 + 0 + 1600 + 0)
    assert_eq!(printed_nmse(&out), 26.0 / 3000.0, "{out}");
    assert!(out.contains("max abs difference 4"), "{out}");
    assert!(out.contains("differing pixels 2 of 2"), "{out}");
    // Identical images: 0, infinite PSNR.
    let out = stdout(&host_sim(&[
        "compare",
        b.to_str().unwrap(),
        b.to_str().unwrap(),
    ]));
    assert_eq!(printed_nmse(&out), 0.0);
    assert!(out.contains("differing pixels 0"), "{out}");
    // RGBA (alpha ignored) and gray inputs.
    write_any_png(
        &c,
        2,
        1,
        png::ColorType::Rgba,
        &[13, 20, 26, 0, 0, 40, 1, 255],
    );
    let out = stdout(&host_sim(&[
        "compare",
        c.to_str().unwrap(),
        b.to_str().unwrap(),
    ]));
    assert_eq!(printed_nmse(&out), 26.0 / 3000.0);
    write_any_png(&d, 2, 1, png::ColorType::Grayscale, &[10, 0]);
    let out = stdout(&host_sim(&[
        "compare",
        d.to_str().unwrap(),
        b.to_str().unwrap(),
    ]));
    // Gray (10,10,10), (0,0,0): (0 + 100 + 400 + 0 + 1600 + 0) / 3000.
    assert_eq!(printed_nmse(&out), 2100.0 / 3000.0);
    // A heat map of the differences, same size.
    let heat = dir.join("heat.png");
    stdout(&host_sim(&[
        "compare",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--diff",
        heat.to_str().unwrap(),
    ]));
    let h = host_sim::image_io::read_png(&heat).unwrap();
    assert_eq!((h.width, h.height), (2, 1));
    assert_ne!(&h.rgb[..3], &[0, 0, 0]);
    // Different sizes are an error that says so.
    let big = dir.join("big.png");
    write_any_png(&big, 1, 2, png::ColorType::Rgb, &[0; 6]);
    let o = host_sim(&["compare", big.to_str().unwrap(), b.to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("differ in size"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn synthetic_scenes_render_the_same_for_a_seed() {
    let cfg = RenderConfig {
        method: Method::Unlimited,
        rasterize_every_front_face: true,
        ..Default::default()
    };
    let image = |name: &str| {
        let scene = to_fixed(&builtin_scene(name, 64, 64).unwrap()).unwrap();
        render(&scene, &cfg, 0.0).unwrap()
    };
    let a = image("layers:300:4:11");
    let b = image("layers:300:4:11");
    assert!(a.rgb == b.rgb && a.generated_per_pixel == b.generated_per_pixel);
    assert!(a.rgb != image("layers:300:4:12").rgb);
    // The target depth complexity shows in the fragments generated: over the
    // middle of the square the mean is near the requested depth. Fragments count
    // every pixel a triangle touches, so edge pixels add to the area-weighted
    // depth (by about a third for triangles of a few hundred pixels).
    let scene = to_fixed(&builtin_scene("layers:100:4:3", 128, 128).unwrap()).unwrap();
    let d = render(&scene, &cfg, 0.0).unwrap();
    let mut inner = Vec::new();
    for y in 40..88 {
        for x in 40..88 {
            inner.push(d.generated_per_pixel[y * 128 + x] as f64);
        }
    }
    let mean = inner.iter().sum::<f64>() / inner.len() as f64;
    eprintln!("mean depth complexity {mean}");
    assert!((4.0..5.6).contains(&mean), "mean depth complexity {mean}");
    // The grid puts many fragments of one surface into a pixel.
    let g = image("grid:128");
    let max = *g.generated_per_pixel.iter().max().unwrap();
    assert!(max >= 6, "grid: at most {max} fragments per pixel");
}

fn small_sweep() -> (host_sim::convert::FixedScene, SweepParams) {
    let scene = to_fixed(&builtin_scene("starfighter", 56, 48).unwrap()).unwrap();
    let budgets: Vec<u8> = (1..=8).collect();
    let params = SweepParams {
        grid: Grid::G4x4,
        band: 8,
        angles: turntable_angles(2, 15.0),
        pool: PoolSizing::Peak,
        configs: sweep_configs(&budgets, &Policy::ALL, &[1, 2]),
    };
    (scene, params)
}

#[test]
fn sweep_csv_is_well_formed_and_covers_every_configuration() {
    let (scene, params) = small_sweep();
    let result = run_sweep(&scene, &params, &indicatif::ProgressBar::hidden()).unwrap();
    let csv = to_csv("starfighter", &scene, &params, &result);
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header.join(","), CSV_HEADER);
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    for r in &rows {
        assert_eq!(r.len(), header.len(), "{r:?}");
        for name in ["nmse", "psnr_db", "bytes_per_pixel"] {
            let v: f64 = r[col(name)].parse().unwrap_or(f64::NAN);
            assert!(v >= 0.0, "{name} = {} in {r:?}", r[col(name)]);
        }
        for name in ["total_bytes", "pool_slots", "n_main", "n_extra", "frames"] {
            assert!(r[col(name)].parse::<u64>().is_ok(), "{name} in {r:?}");
        }
    }
    // Every policy at every budget; both splits where they differ.
    let get = |policy: &str, k: u8, main: u8| {
        rows.iter().find(|r| {
            r[col("policy")] == policy
                && r[col("fragments_per_pixel")] == k.to_string()
                && r[col("n_main")] == main.to_string()
        })
    };
    for k in 1..=8u8 {
        for policy in ["fixed-discard", "fixed-merge"] {
            let r = get(policy, k, k).unwrap_or_else(|| panic!("{policy} {k}"));
            assert_eq!(r[col("n_extra")], "0");
            assert_eq!(r[col("pool_slots")], "0");
            // M_fixed = W R N_fixed M_frag with 14-byte fragments, band 56 x 8.
            assert_eq!(
                r[col("total_bytes")],
                (56 * 8 * k as usize * 14).to_string()
            );
        }
        for policy in ["shared", "merge-closest"] {
            for main in [1, 2.min(k)] {
                let r = get(policy, k, main).unwrap_or_else(|| panic!("{policy} {k} {main}"));
                assert_eq!(r[col("n_extra")], (k - main).to_string());
                // M_shared = W R (N_main M_frag + N_extra M_addr) + N_pool M_frag,
                // N_pool the worst peak over the frames.
                let pool: usize = r[col("pool_slots")].parse().unwrap();
                assert_eq!(r[col("pool_peak")], pool.to_string());
                let expected = 56 * 8 * (main as usize * 14 + (k - main) as usize * 2) + pool * 14;
                assert_eq!(r[col("total_bytes")], expected.to_string());
            }
        }
    }
    let expected_rows = 8 * 2 + 2 * (1 + 7 * 2);
    assert_eq!(rows.len(), expected_rows);
    assert_eq!(result.renders, (expected_rows + 1) * 2);
    // With the pool sized to the peak, the pool never forces a merge: shared at
    // budget k renders what fixed-merge renders with k slots.
    for k in 1..=8u8 {
        let fixed = get("fixed-merge", k, k).unwrap();
        let shared = get("shared", k, 1).unwrap();
        assert_eq!(fixed[col("nmse")], shared[col("nmse")], "budget {k}");
    }
    // Merging beats discarding at small budgets on this scene.
    for k in 1..=3u8 {
        let nmse = |r: &Vec<String>| r[col("nmse")].parse::<f64>().unwrap();
        assert!(
            nmse(get("fixed-merge", k, k).unwrap()) < nmse(get("fixed-discard", k, k).unwrap())
        );
    }
}

#[test]
fn a_pool_of_exactly_the_peak_renders_the_same_image() {
    let scene = to_fixed(&builtin_scene("teapot", 64, 64).unwrap()).unwrap();
    let roomy = RenderConfig {
        method: Method::Shared,
        main: 1,
        extra: 3,
        pool: Some(64 * 16 * 3),
        ..Default::default()
    };
    let a = render(&scene, &roomy, 20.0).unwrap();
    let peak = a.stats.buffer.pool_peak as usize;
    assert!(peak > 0);
    let exact = render(
        &scene,
        &RenderConfig {
            pool: Some(peak),
            ..roomy
        },
        20.0,
    )
    .unwrap();
    assert!(a.rgb == exact.rgb);
    assert_eq!(a.stats.buffer.merges, exact.stats.buffer.merges);
    // One slot fewer and the pool runs out somewhere.
    let short = render(
        &scene,
        &RenderConfig {
            pool: Some(peak - 1),
            ..roomy
        },
        20.0,
    )
    .unwrap();
    assert!(short.stats.buffer.merges > a.stats.buffer.merges);
}

#[test]
fn sweep_stats_and_turntable_commands_write_their_files() {
    let dir = scratch("commands");
    let d = dir.to_str().unwrap();
    let out = stdout(&host_sim(&[
        "sweep",
        "--scene",
        "layers:200:4:2",
        "--width",
        "48",
        "--height",
        "40",
        "--frames",
        "2",
        "--max-fragments",
        "3",
        "--quiet",
        "--out-dir",
        d,
    ]));
    assert!(out.contains("NMSE against unlimited"), "{out}");
    for suffix in [
        "sweep.csv",
        "nmse-memory.svg",
        "nmse-budget.svg",
        "sweep.md",
    ] {
        let p = dir.join(format!("layers-200-4-2-{suffix}"));
        let text = std::fs::read_to_string(&p).unwrap_or_else(|_| panic!("{p:?}"));
        assert!(!text.is_empty());
    }
    let csv = std::fs::read_to_string(dir.join("layers-200-4-2-sweep.csv")).unwrap();
    // 3 budgets: discard 3, merge 3, shared 1 + 2 + 2, merge-closest 1 + 2 + 2.
    assert_eq!(csv.lines().count(), 1 + 3 + 3 + 5 + 5);

    let out = stdout(&host_sim(&[
        "stats",
        "--scene",
        "teapot",
        "--width",
        "64",
        "--height",
        "48",
        "--out-dir",
        d,
    ]));
    assert!(
        out.contains("M_shared") && out.contains("pool peak"),
        "{out}"
    );
    assert!(out.contains("4096 triangles"), "{out}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("teapot-stats.json")).unwrap())
            .unwrap();
    for key in [
        "generated_histogram",
        "visible_histogram",
        "stored_histogram",
    ] {
        let total: u64 = json[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_u64().unwrap())
            .sum();
        assert_eq!(total, 64 * 48, "{key}");
    }
    for f in [
        "teapot-generated.png",
        "teapot-visible.png",
        "teapot-histogram.svg",
    ] {
        assert!(dir.join(f).exists(), "{f}");
    }

    let gif = dir.join("turn.gif");
    let out = stdout(&host_sim(&[
        "render",
        "--scene",
        "starfighter",
        "--width",
        "40",
        "--height",
        "32",
        "--turntable",
        "--frames",
        "4",
        "--out",
        gif.to_str().unwrap(),
    ]));
    assert!(out.contains("worst pool peak"), "{out}");
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::RGBA);
    let mut decoder = options
        .read_info(std::fs::File::open(&gif).unwrap())
        .unwrap();
    let mut frames = 0;
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        assert_eq!((frame.width, frame.height), (40, 32));
        frames += 1;
    }
    assert_eq!(frames, 4);
    // --frames without --turntable is refused.
    let o = host_sim(&[
        "render",
        "--scene",
        "teapot",
        "--frames",
        "3",
        "--out",
        gif.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
}

/// The test program's parts, each through its module's public functions.
mod parts {
    /// The library and the program are not built for tests (`Cargo.toml`), so
    /// a test written in `src/` would never run: there are none.
    #[test]
    fn the_sources_hold_no_tests() {
        let mut folders = vec![std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src")];
        let mut with_tests = Vec::new();
        while let Some(folder) = folders.pop() {
            for entry in std::fs::read_dir(&folder).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    folders.push(path);
                    continue;
                }
                let text = std::fs::read_to_string(&path).unwrap_or_default();
                if text.contains("#[test]") || text.contains("#[cfg(test)]") {
                    with_tests.push(path.display().to_string());
                }
            }
        }
        assert!(
            with_tests.is_empty(),
            "{with_tests:?} hold tests that never run: move them to host-sim/tests/"
        );
    }

    mod sweep {
        use host_sim::sweep::*;

        #[test]
        fn configurations_follow_the_split_rule() {
            let c = sweep_configs(&[1, 2, 3], &[Policy::FixedMerge, Policy::Shared], &[1, 2]);
            let shared: Vec<(u8, u8, u8)> = c
                .iter()
                .filter(|c| c.policy == Policy::Shared)
                .map(|c| (c.budget, c.main, c.extra))
                .collect();
            assert_eq!(
                shared,
                vec![(1, 1, 0), (2, 1, 1), (2, 2, 0), (3, 1, 2), (3, 2, 1)]
            );
            let fixed: Vec<(u8, u8, u8)> = c
                .iter()
                .filter(|c| c.policy == Policy::FixedMerge)
                .map(|c| (c.budget, c.main, c.extra))
                .collect();
            assert_eq!(fixed, vec![(1, 1, 0), (2, 2, 0), (3, 3, 0)]);
            assert_eq!(turntable_angles(4, 10.0), vec![10.0, 100.0, 190.0, 280.0]);
        }
    }

    mod bounded {
        use host_sim::bounded::*;

        #[test]
        fn a_streak_along_band_boundaries_shows_in_the_band_row_ratio() {
            // 4 x 8 image, bands of 4 rows: every band's last row is off.
            let reference = vec![100u8; 4 * 8 * 3];
            let mut image = reference.clone();
            for y in [3usize, 7] {
                for x in 0..4 {
                    image[3 * (4 * y + x)] = 140;
                }
            }
            let e = frame_errors(&image, &reference, 4, 4);
            assert_eq!(e.speckles, 8);
            // All the error sits in one of four row positions.
            assert!((e.worst_band_row - 4.0).abs() < 1e-9);
            let rows = row_errors(&image, &reference, 4);
            assert_eq!(rows.len(), 8);
            // Row 3: one channel of four pixels off by 40, over 12 channels.
            assert!((rows[3] - 4.0 * 1600.0 / 12.0).abs() < 1e-9);
            assert_eq!(rows[0], 0.0);
            let same = frame_errors(&reference, &reference, 4, 4);
            assert_eq!(
                (same.nmse, same.speckles, same.worst_band_row),
                (0.0, 0, 0.0)
            );
        }
    }

    mod tune {
        use host_sim::fit::parse_bytes;
        use host_sim::tune::*;
        use mcu_abuffer::memory::defaults;

        fn args(ram: &str) -> TuneArgs {
            TuneArgs {
                scene: "spheres".into(),
                frames: 2,
                ram: parse_bytes(ram).unwrap(),
                stack: defaults::STACK_RESERVE_BYTES,
                nmse: 1e-4,
                size: 64,
                show: 3,
            }
        }

        #[test]
        fn the_winner_fits_and_meets_the_target() {
            let result = search(&args("112K")).unwrap();
            assert!(result.fitting > 0 && result.fitting <= result.tried);
            let best = result.passing.first().expect("a configuration passes");
            assert!(best.bytes <= 112 * 1024);
            assert!(best.nmse <= 1e-4);
            assert!(result.passing.windows(2).all(|w| w[0].time <= w[1].time));
        }

        #[test]
        fn too_little_memory_says_by_how_much() {
            let result = search(&args("8K")).unwrap();
            assert_eq!(result.fitting, 0);
            assert!(result.passing.is_empty());
            assert!(result.smallest > 8 * 1024);
        }
    }

    mod plot {
        use host_sim::plot::*;

        #[test]
        fn numbers_and_ticks() {
            assert_eq!(short_number(0.0), "0");
            assert_eq!(short_number(1e-5), "1e-5");
            assert_eq!(short_number(2.5e-4), "2.5e-4");
            assert_eq!(short_number(0.25), "0.25");
            assert_eq!(short_number(1500.0), "1.5k");
            assert_eq!(linear_ticks(0.0, 10.0), vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        }

        #[test]
        fn chart_is_well_formed_svg() {
            let chart = LineChart {
                title: "a < b & c".into(),
                x_label: "x".into(),
                y_label: "y".into(),
                x_scale: Scale::Linear,
                y_scale: Scale::Log10,
                series: vec![Series {
                    name: "s".into(),
                    color: PALETTE[0],
                    dashed: true,
                    points: vec![
                        Point {
                            x: 1.0,
                            y: 1e-3,
                            label: Some("1".into()),
                        },
                        Point {
                            x: 2.0,
                            y: 0.0,
                            label: None,
                        },
                    ],
                }],
                note: Some("n".into()),
            };
            let svg = chart.to_svg();
            assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
            assert!(svg.contains("a &lt; b &amp; c"));
            assert_eq!(svg.matches("<circle").count(), 3);
            let bars = bar_panels_svg(
                "t",
                "n",
                &[BarPanel {
                    title: "p".into(),
                    y_label: "%".into(),
                    categories: vec!["0".into(), "1".into()],
                    values: vec![10.0, 90.0],
                    colors: vec![[0, 0, 0], [255, 0, 0]],
                }],
                None,
            );
            assert_eq!(bars.matches("<rect").count(), 3);
        }
    }

    mod heat {
        use host_sim::heat::*;

        #[test]
        fn ramp_ends_and_order() {
            assert_eq!(heat_color(0.0), [0, 0, 4]);
            assert_eq!(heat_color(1.0), [252, 255, 164]);
            assert_eq!(heat_color(7.0), [252, 255, 164]);
            assert_eq!(count_color(0, 8), [0, 0, 0]);
            // Brightness grows with the count.
            let luma = |c: [u8; 3]| 3 * c[0] as u32 + 6 * c[1] as u32 + c[2] as u32;
            for n in 1..8 {
                assert!(luma(count_color(n + 1, 8)) > luma(count_color(n, 8)), "{n}");
            }
            assert_eq!(hex([255, 0, 16]), "#ff0010");
        }
    }

    mod memory {
        use host_sim::memory::*;
        use host_sim::render::Grid;

        #[test]
        fn seed_formulas_with_real_sizes() {
            // 240 x 16 band, 1 main slot, 2 addresses, 1,000 pool slots, 14-byte fragments.
            let m = band_memory(240, 16, Grid::G4x4, 1, 2, 1000);
            assert_eq!(m.fragment_bytes, 14);
            assert_eq!(m.address_bytes, 2);
            assert_eq!(m.main_buffer_bytes, 3840 * (14 + 2 * 2));
            assert_eq!(m.pool_bytes, 14_000);
            assert_eq!(m.total_bytes, 3840 * 18 + 14_000);
            assert_eq!(m.fixed_equivalent_bytes, 3840 * 3 * 14);
            // Fixed slots: no pool, no addresses, M_shared = M_fixed.
            let f = band_memory(240, 16, Grid::G8x8, 3, 0, 0);
            assert_eq!(f.total_bytes, 3840 * 3 * 20);
            assert_eq!(f.fixed_to_shared_ratio(), 1.0);
            assert_eq!(address_bytes(65_535), 2);
            assert_eq!(address_bytes(65_536), 4);
        }
    }

    mod compare {
        use host_sim::compare::*;

        #[test]
        fn nmse_of_hand_made_values() {
            let reference = [10u8, 20, 30, 0, 0, 0];
            let image = [13u8, 20, 26, 0, 0, 1];
            // (9 + 0 + 16 + 1) / (100 + 400 + 900)
            assert_eq!(nmse(&image, &reference), 26.0 / 1400.0);
            assert_eq!(nmse(&reference, &reference), 0.0);
            assert_eq!(nmse(&[0, 0, 0], &[0, 0, 0]), 0.0);
            assert_eq!(nmse(&[1, 0, 0], &[0, 0, 0]), f64::INFINITY);
            let d = compare_rgb(&image, &reference).unwrap();
            assert_eq!((d.max_abs_diff, d.differing_pixels, d.pixels), (4, 2, 2));
            assert!((d.psnr_db - 10.0 * (65025.0f64 / (26.0 / 6.0)).log10()).abs() < 1e-12);
            assert!(compare_rgb(&image, &reference[..3]).is_err());
        }

        #[test]
        fn heat_map_is_black_where_equal() {
            let heat = diff_heat_map(&[5, 5, 5, 9, 9, 9], &[5, 5, 5, 0, 9, 9], 0);
            assert_eq!(&heat[..3], &[0, 0, 0]);
            assert_ne!(&heat[3..], &[0, 0, 0]);
        }
    }

    mod complexity {
        use host_sim::complexity::*;

        #[test]
        fn histogram_counts_pixels() {
            assert_eq!(histogram([0, 2, 2, 5].into_iter()), vec![1, 0, 2, 0, 0, 1]);
            assert_eq!(histogram(std::iter::empty()), vec![0]);
            assert_eq!(mean_over_covered(&[7, 1, 0, 1]), 2.0);
            assert_eq!(file_tag("scenes/a b.toml"), "a-b");
            assert_eq!(file_tag("layers:10:2.5:1"), "layers-10-2.5-1");
        }
    }
}
