use super::fit::{fit_channels, FitBasis, SMALL_BARYCENTRIC_LIMIT};
use super::midpoints::{rsqrt_q28, scaled_into_one_to_four, RSQRT_START};
use super::*;
use crate::fixed_point::{Reciprocal, GUARD_BAND_PX, SUBPIXEL_BITS, UNIT_ONE};
use crate::shading::ColorWalk;

/// A small deterministic generator (xorshift64*).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn range(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next() % (hi - lo + 1) as u64) as i64
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A bounding box on a `w x h` screen as setup computes it.
fn bounding_box(xs: &[i64; 3], ys: &[i64; 3], w: i64, h: i64) -> Option<((i64, i64), (i64, i64))> {
    let x0 = (xs.iter().min()? >> 4).max(0);
    let y0 = (ys.iter().min()? >> 4).max(0);
    let x1 = (xs.iter().max()? >> 4).min(w - 1);
    let y1 = (ys.iter().max()? >> 4).min(h - 1);
    (x0 <= x1 && y0 <= y1).then_some(((x0, y0), (x1 - x0 + 1, y1 - y0 + 1)))
}

fn random_samples(rng: &mut Rng) -> QuadraticSamples {
    let mut color = || core::array::from_fn(|_| rng.range(0, 255 << 8) as i32);
    QuadraticSamples {
        vertices: [color(), color(), color()],
        midpoints: [color(), color(), color()],
    }
}

/// A random triangle: small, medium, or reaching over the whole screen
/// (vertices up to the guard band).
fn random_triangle(rng: &mut Rng, w: i64, h: i64) -> ([i64; 3], [i64; 3]) {
    let kind = rng.range(0, 3);
    let (cx, cy) = (rng.range(0, w * 16), rng.range(0, h * 16));
    let r = match kind {
        0 => 64,
        1 => 1024,
        2 => w.max(h) * 16,
        _ => 4096 * 16,
    };
    let lim = 4096 * 16;
    let xs = [0; 3].map(|_| (cx + rng.range(-r, r)).clamp(-lim, lim));
    let ys = [0; 3].map(|_| (cy + rng.range(-r, r)).clamp(-lim, lim));
    (xs, ys)
}

/// The fitted channel at a point given in 1/16 pixel, as a real number of 8-bit steps.
fn at_point(p: &QuadraticPolynomial, origin: (i64, i64), x: f64, y: f64) -> f64 {
    let i = (x - (origin.0 * 16 + 8) as f64) / 16.0;
    let j = (y - (origin.1 * 16 + 8) as f64) / 16.0;
    let v = p.a as f64 * i * i
        + p.b as f64 * j * j
        + p.c as f64 * i * j
        + p.d as f64 * i
        + p.e as f64 * j
        + p.f as f64;
    v / (1u64 << QUADRATIC_FRACTION_BITS) as f64
}

#[test]
fn fit_reproduces_the_six_samples() {
    let mut rng = Rng(0x1234_5678_9abc_def1);
    let (w, h) = (2048, 2048);
    let mut worst = 0.0f64;
    let mut fitted = 0;
    for _ in 0..20_000 {
        // On-screen triangles: the samples lie in the box.
        let xs = [0; 3].map(|_| rng.range(0, w * 16 - 1));
        let ys = [0; 3].map(|_| rng.range(0, h * 16 - 1));
        let Some((origin, size)) = bounding_box(&xs, &ys, w, h) else {
            continue;
        };
        let samples = random_samples(&mut rng);
        let Some(poly) = fit_quadratic(&xs, &ys, origin, size, &samples) else {
            continue;
        };
        fitted += 1;
        for ch in 0..3 {
            for k in 0..3 {
                let l = (k + 1) % 3;
                let vertex = at_point(&poly[ch], origin, xs[k] as f64, ys[k] as f64);
                let mid = at_point(
                    &poly[ch],
                    origin,
                    (xs[k] + xs[l]) as f64 / 2.0,
                    (ys[k] + ys[l]) as f64 / 2.0,
                );
                worst = worst.max((vertex - samples.vertices[k][ch] as f64 / 256.0).abs());
                worst = worst.max((mid - samples.midpoints[k][ch] as f64 / 256.0).abs());
            }
        }
    }
    assert!(fitted > 19_000, "only {fitted} triangles fitted");
    // The stated bound: within 1/16 of an 8-bit step (analysis: below 0.06).
    assert!(worst < 1.0 / 16.0, "worst deviation {worst} steps");
}

#[test]
fn samples_out_of_range_are_clamped_before_the_fit() {
    // The public fit clamps its samples; the fit itself takes them in
    // range (color setup clamps the vertex colors it is given).
    let mut rng = Rng(0x5a3c_0ff5_e7c1_a3b9);
    let mut outside = 0;
    for _ in 0..2_000 {
        let (xs, ys) = random_triangle(&mut rng, 128, 128);
        let Some((origin, size)) = bounding_box(&xs, &ys, 128, 128) else {
            continue;
        };
        let mut wide = || core::array::from_fn(|_| rng.range(0, 3 * 256 * 256) as i32 - 256 * 256);
        let samples = QuadraticSamples {
            vertices: [wide(), wide(), wide()],
            midpoints: [wide(), wide(), wide()],
        };
        outside += !samples.in_range() as u32;
        let clamped = samples.clamped();
        assert!(clamped.in_range());
        assert_eq!(
            fit_quadratic(&xs, &ys, origin, size, &samples),
            fit_quadratic_over(&xs, &ys, origin, size, &clamped, None)
        );
    }
    assert!(outside > 1_000, "only {outside} sample sets out of range");
}

#[test]
fn a_reciprocal_handed_over_gives_the_same_fit() {
    // Setup hands over the reciprocal of its own area: the same bits
    // as the fit's own where no corner lies on the guard band's edge;
    // there a wrong one is not used.
    let mut rng = Rng(0x7ec1_9e0c_a1ea_2024);
    let guard = (GUARD_BAND_PX as i64) << SUBPIXEL_BITS;
    let (mut handed, mut refused) = (0, 0);
    for n in 0..5_000 {
        let (w, h) = if n % 2 == 0 { (128, 128) } else { (2048, 2048) };
        let (mut xs, ys) = random_triangle(&mut rng, w, h);
        let on_edge = n % 5 == 0;
        if on_edge {
            xs[0] = -guard;
        }
        let Some((origin, size)) = bounding_box(&xs, &ys, w, h) else {
            continue;
        };
        let samples = random_samples(&mut rng);
        let area2 = ((xs[1] - xs[0]) * (ys[2] - ys[0]) - (xs[2] - xs[0]) * (ys[1] - ys[0])).abs();
        // On the edge, a reciprocal of another area.
        let given = if on_edge { area2 + 1 } else { area2 };
        let reciprocal = Reciprocal::new(given.max(1) as u64);
        let own = fit_quadratic(&xs, &ys, origin, size, &samples);
        let over = fit_quadratic_over(&xs, &ys, origin, size, &samples, Some(reciprocal));
        assert_eq!(own, over, "{xs:?} {ys:?}");
        handed += (own.is_some() && !on_edge) as u32;
        refused += (own.is_some() && on_edge) as u32;
    }
    assert!(handed > 2_000, "{handed}");
    assert!(refused > 100, "{refused}");
}

#[test]
fn i32_monomials_give_the_i64_fit() {
    // Any triangle whose planes pass `monomials_fit_i32`, slivers up to
    // the bound included, fits to the same bits with 32-bit monomials.
    let mut rng = Rng(0x5eed_0f17_32b1_7500);
    let (mut compared, mut near_bound) = (0, 0);
    for n in 0..40_000 {
        let (w, h) = if n % 2 == 0 { (128, 128) } else { (2048, 2048) };
        let mut xs = [0; 3].map(|_| rng.range(0, w * 16 - 1));
        let mut ys = [0; 3].map(|_| rng.range(0, h * 16 - 1));
        if n % 4 < 2 {
            // A sliver: the third corner close to the line of the others.
            let t = rng.range(0, 256);
            xs[2] = xs[0] + (xs[1] - xs[0]) * t / 256 + rng.range(-2, 2);
            ys[2] = ys[0] + (ys[1] - ys[0]) * t / 256 + rng.range(-2, 2);
        }
        let Some((origin, size)) = bounding_box(&xs, &ys, w, h) else {
            continue;
        };
        let Some(basis) = FitBasis::new(&xs, &ys, origin, size, None) else {
            continue;
        };
        if !basis.monomials_fit_i32() {
            continue;
        }
        near_bound += (basis.extent >= SMALL_BARYCENTRIC_LIMIT / 4) as u32;
        let samples = random_samples(&mut rng);
        assert_eq!(
            fit_channels::<i32>(&basis, &samples),
            fit_channels::<i64>(&basis, &samples),
            "{xs:?} {ys:?}"
        );
        compared += 1;
    }
    assert!(compared > 15_000, "{compared}");
    assert!(near_bound > 20, "{near_bound}");
}

#[test]
fn walks_in_i32_in_words_equals_the_64_bit_bound() {
    // The test as first written: every coefficient and product in 64 bits.
    fn in_64_bits(p: &[QuadraticPolynomial; 3], size: (i64, i64)) -> bool {
        if !is_narrow_box(size) || size.0 < 1 || size.1 < 1 {
            return false;
        }
        let (w, h) = (size.0 as u64, size.1 as u64);
        const DROPPED: i64 = (1 << NARROW_QUADRATIC_DROPPED_BITS) - 1;
        p.iter().all(|p| {
            let ks = p.coefficients();
            let low_bits = ks.iter().fold(0, |or, k| or | k);
            let high = ks.iter().fold(0, |or, k| or | k.unsigned_abs());
            if low_bits & DROPPED != 0 || high >= 1 << 40 {
                return false;
            }
            let monomials = [w * w, h * h, w * h, w, h, 1];
            let bound: u64 = ks
                .iter()
                .zip(monomials)
                .map(|(k, m)| k.unsigned_abs() * m)
                .sum();
            bound < ((1 << 31) - (1 << 20)) << NARROW_QUADRATIC_DROPPED_BITS
        })
    }
    let mut rng = Rng(0x0005_eed0_fb0d);
    let (mut narrow, mut wide) = (0, 0);
    for n in 0..200_000 {
        // One magnitude per set, from small (the bound passes) to far
        // beyond it; mostly multiples of 2^8; the edges of the high
        // word's range, and any word, now and then.
        let bits = rng.range(4, 41) as u32;
        let coefficient = |rng: &mut Rng| -> i64 {
            let k = match rng.range(0, 40) {
                0 => (1i64 << 39) - rng.range(0, 1 << 10),
                1 => -(1i64 << 39) + rng.range(-(1 << 10), 1 << 10),
                2 => rng.next() as i64,
                // Below 2^40, where a wider test of the high word
                // would let `k >> 8` wrap in `i32`.
                3 => (1i64 << 40) - rng.range(1, 1 << 12),
                _ => rng.range(-(1i64 << bits), 1i64 << bits),
            };
            if n % 7 == 0 {
                k
            } else {
                k & !0xff
            }
        };
        let poly: [QuadraticPolynomial; 3] = core::array::from_fn(|_| {
            QuadraticPolynomial::from_coefficients(core::array::from_fn(|_| coefficient(&mut rng)))
        });
        let side = |rng: &mut Rng| {
            if rng.range(0, 1) == 0 {
                rng.range(0, 12)
            } else {
                rng.range(0, 130)
            }
        };
        let size = (side(&mut rng), side(&mut rng));
        let expected = in_64_bits(&poly, size);
        assert_eq!(walks_in_i32(&poly, size), expected, "{poly:?} {size:?}");
        if expected {
            narrow += 1;
        } else {
            wide += 1;
        }
    }
    assert!(narrow > 5_000 && wide > 5_000, "{narrow} {wide}");
}

#[test]
fn narrow_coefficients_are_words_above_the_dropped_bits() {
    // What the carried-colors table relies on to keep a polynomial that
    // walks in `i32` in one word per coefficient.
    let mut rng = Rng(0x00c0_ffee_1234_8765);
    let mut narrow = 0;
    for n in 0..20_000 {
        let (w, h) = if n % 2 == 0 { (128, 128) } else { (40, 24) };
        let (xs, ys) = random_triangle(&mut rng, w, h);
        let Some((origin, size)) = bounding_box(&xs, &ys, w, h) else {
            continue;
        };
        let samples = random_samples(&mut rng);
        let Some(p) = fit_quadratic(&xs, &ys, origin, size, &samples) else {
            continue;
        };
        if !walks_in_i32(&p, size) {
            continue;
        }
        narrow += 1;
        for q in &p {
            for k in q.coefficients() {
                let word = k >> NARROW_QUADRATIC_DROPPED_BITS;
                assert_eq!(word << NARROW_QUADRATIC_DROPPED_BITS, k, "{q:?}");
                assert_eq!(word as i32 as i64, word, "{q:?}");
            }
        }
    }
    assert!(narrow > 5_000, "{narrow}");
    // At the bound: a value coefficient as large as the walk takes.
    let big = (((1i64 << 31) - (1 << 20)) << NARROW_QUADRATIC_DROPPED_BITS) - 256;
    let p = QuadraticPolynomial {
        f: big,
        ..QuadraticPolynomial::ZERO
    };
    assert!(walks_in_i32(&[p; 3], (1, 1)));
    assert_eq!(
        (big >> NARROW_QUADRATIC_DROPPED_BITS) as i32 as i64,
        big >> 8
    );
}

#[test]
fn stepping_equals_direct_evaluation_exactly() {
    let mut rng = Rng(0x0fed_cba9_8765_4321);
    let mut checked_pixels = 0u64;
    let (mut boxes, mut fitted, mut narrow_boxes) = (0, 0, 0u32);
    for round in 0..1_500 {
        // Every third screen is small: boxes the `i32` walk may take.
        let (w, h) = match round % 3 {
            0 => (2048, 2048),
            1 => (320, 240),
            _ => (100, 100),
        };
        let (xs, ys) = random_triangle(&mut rng, w, h);
        let Some((origin, size)) = bounding_box(&xs, &ys, w, h) else {
            continue;
        };
        boxes += 1;
        let samples = random_samples(&mut rng);
        let Some(poly) = fit_quadratic(&xs, &ys, origin, size, &samples) else {
            continue;
        };
        fitted += 1;
        // Large boxes: a band of rows starting anywhere, plus the first rows.
        let first = if size.1 > 64 {
            rng.range(0, size.1 - 1)
        } else {
            0
        };
        let last = (first + 40).min(size.1);
        let mut walk = QuadraticWalk::<i64>::start(&poly, first);
        // Where the fit allows it, the `i32` walk alongside: at every pixel
        // of the box, the same polynomial without its zero low bits.
        let narrow = walks_in_i32(&poly, size);
        narrow_boxes += narrow as u32;
        let mut walk32 = QuadraticWalk::<i32>::start(&poly, first);
        for j in first..=last {
            let mut row = walk.row();
            let mut row32 = walk32.row();
            for i in 0..=size.0 {
                for ch in 0..3 {
                    // The walk's values carry the rounding bias.
                    let exact = poly[ch].eval(i, j) + <i64 as QuadraticValue>::ROUNDING_BIAS;
                    assert_eq!(row.value[ch], exact, "({i}, {j})");
                    assert_eq!(
                        row.first_x[ch],
                        poly[ch].eval(i + 1, j) - poly[ch].eval(i, j)
                    );
                    if narrow && i < size.0 && j < size.1 {
                        assert_eq!(exact & 0xff, 0);
                        assert_eq!(row32.value[ch] as i64, exact >> 8, "({i}, {j})");
                    }
                }
                if narrow && i < size.0 && j < size.1 {
                    let walks = QuadraticWalk::<i64>::rgb(&row);
                    assert_eq!(QuadraticWalk::<i32>::rgb(&row32), walks);
                }
                walk.step(&mut row);
                walk32.step(&mut row32);
                checked_pixels += 1;
            }
            walk.next_row();
            walk32.next_row();
        }
    }
    // Random samples curve steeply, so a third of the small boxes pass.
    assert!(narrow_boxes > 100, "{narrow_boxes} boxes walked in i32");
    // Random triangles are rarely slivers: nearly all take the quadratic.
    assert!(
        fitted * 100 >= boxes * 99,
        "{fitted} of {boxes} triangles fitted"
    );
    assert!(fitted > 1_000, "only {fitted} triangles fitted");
    assert!(checked_pixels > 10_000_000, "{checked_pixels}");
}

#[test]
fn screen_spanning_triangle_steps_exactly_over_every_pixel() {
    // Corners far outside a 2048 x 2048 screen: the box is the whole screen.
    let lim = 4096 * 16;
    let xs = [-lim, lim, -lim / 2];
    let ys = [-lim, -lim / 3, lim];
    let (origin, size) = ((0, 0), (2048, 2048));
    let mut rng = Rng(99);
    for _ in 0..3 {
        let samples = random_samples(&mut rng);
        let poly = fit_quadratic(&xs, &ys, origin, size, &samples).expect("fits");
        let mut walk = QuadraticWalk::<i64>::start(&poly, 0);
        for j in 0..=size.1 {
            let mut row = walk.row();
            for i in 0..=size.0 {
                for ch in 0..3 {
                    let exact = poly[ch].eval(i, j) + <i64 as QuadraticValue>::ROUNDING_BIAS;
                    assert_eq!(row.value[ch], exact);
                }
                walk.step(&mut row);
            }
            walk.next_row();
        }
    }
}

#[test]
fn equal_samples_shade_constant() {
    let mut rng = Rng(7);
    for _ in 0..2_000 {
        let (xs, ys) = random_triangle(&mut rng, 640, 480);
        let Some((origin, size)) = bounding_box(&xs, &ys, 640, 480) else {
            continue;
        };
        let color = [rng.range(0, 255) as i32 * 256, 77 * 256 + 13, 0];
        let samples = QuadraticSamples {
            vertices: [color; 3],
            midpoints: [color; 3],
        };
        let Some(poly) = fit_quadratic(&xs, &ys, origin, size, &samples) else {
            continue;
        };
        for ch in 0..3 {
            let expected = (color[ch] as i64) << BARYCENTRIC_BITS;
            assert_eq!(
                poly[ch],
                QuadraticPolynomial {
                    f: expected,
                    ..Default::default()
                }
            );
        }
    }
}

#[test]
fn degenerate_triangles_fit_nothing() {
    let samples = QuadraticSamples::default();
    // Collinear and coincident vertices.
    assert!(fit_quadratic(&[0, 160, 320], &[0, 160, 320], (0, 0), (21, 21), &samples).is_none());
    assert!(fit_quadratic(&[5, 5, 5], &[9, 9, 9], (0, 0), (1, 1), &samples).is_none());
    // A sliver far thinner than its box falls back to linear planes.
    let xs = [0, 2047 * 16, 2047 * 16];
    let ys = [0, 2047 * 16, 2047 * 16 + 1];
    assert!(fit_quadratic(&xs, &ys, (0, 0), (2048, 2048), &samples).is_none());
}

#[test]
fn fitted_surface_matches_the_quadratic_inside() {
    // A smooth surface given by a known quadratic in barycentric coordinates
    // is reproduced at every pixel center inside the triangle.
    let xs = [10 * 16 + 3, 200 * 16, 90 * 16 + 7];
    let ys = [5 * 16, 60 * 16 + 9, 230 * 16 + 1];
    let (origin, size) = bounding_box(&xs, &ys, 240, 240).unwrap();
    let value = |s: f64, t: f64| 40.0 + 120.0 * s + 60.0 * t - 90.0 * s * s + 30.0 * s * t;
    let q8 = |v: f64| [(v * 256.0).round() as i32; 3];
    let samples = QuadraticSamples {
        vertices: [
            q8(value(0.0, 0.0)),
            q8(value(1.0, 0.0)),
            q8(value(0.0, 1.0)),
        ],
        midpoints: [
            q8(value(0.5, 0.0)),
            q8(value(0.5, 0.5)),
            q8(value(0.0, 0.5)),
        ],
    };
    let poly = fit_quadratic(&xs, &ys, origin, size, &samples).unwrap();
    let (x0, y0) = (xs[0] as f64, ys[0] as f64);
    let (dx1, dy1) = (xs[1] as f64 - x0, ys[1] as f64 - y0);
    let (dx2, dy2) = (xs[2] as f64 - x0, ys[2] as f64 - y0);
    let area = dx1 * dy2 - dx2 * dy1;
    for j in 0..size.1 {
        for i in 0..size.0 {
            let (x, y) = (
                ((origin.0 + i) * 16 + 8) as f64,
                ((origin.1 + j) * 16 + 8) as f64,
            );
            let s = ((x - x0) * dy2 - (y - y0) * dx2) / area;
            let t = (dx1 * (y - y0) - dy1 * (x - x0)) / area;
            if s < 0.0 || t < 0.0 || s + t > 1.0 {
                continue;
            }
            let got = poly[0].eval(i, j) as f64 / (1u64 << QUADRATIC_FRACTION_BITS) as f64;
            // Samples rounded to Q8: within 1/256 plus the fit's rounding.
            assert!(
                (got - value(s, t)).abs() < 0.02,
                "({i}, {j}): {got} vs {}",
                value(s, t)
            );
        }
    }
}

#[test]
fn midpoint_normal_matches_float_normalization() {
    let mut rng = Rng(3);
    let unit = |rng: &mut Rng| loop {
        let v = [0; 3].map(|_| rng.unit() * 2.0 - 1.0);
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if l > 0.1 && l <= 1.0 {
            break v.map(|c| ((c / l) * UNIT_ONE as f64).round() as i32);
        }
    };
    let mut worst = 0.0f64;
    for _ in 0..200_000 {
        let a = unit(&mut rng);
        // Mostly nearby normals (meshes), some far apart.
        let b = if rng.range(0, 3) > 0 {
            let d = [0; 3].map(|_| rng.range(-3000, 3000) as i32);
            let v = [a[0] + d[0], a[1] + d[1], a[2] + d[2]];
            let l = v.iter().map(|c| (*c as f64).powi(2)).sum::<f64>().sqrt();
            v.map(|c| (c as f64 / l * UNIT_ONE as f64).round() as i32)
        } else {
            unit(&mut rng)
        };
        let s = [a[0] + b[0], a[1] + b[1], a[2] + b[2]].map(|c| c as f64);
        let l = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
        match midpoint_normal(&a, &b) {
            Some(n) => {
                for k in 0..3 {
                    worst = worst.max((n[k] as f64 - s[k] / l * UNIT_ONE as f64).abs());
                }
            }
            None => assert_eq!(l, 0.0),
        }
    }
    assert!(worst <= 1.0, "worst component error {worst} units of 2^-14");
    assert_eq!(midpoint_normal(&[UNIT_ONE, 0, 0], &[-UNIT_ONE, 0, 0]), None);
}

#[test]
fn midpoint_normal_scaled_by_the_high_word_equals_the_64_bit_shift() {
    // The normal as first scaled: each component times the reciprocal
    // square root, rounded by a 64-bit shift of 29 to 31 bits.
    fn scaled_in_64_bits(a: &[i32; 3], b: &[i32; 3]) -> Option<[i32; 3]> {
        let sum = [0, 1, 2].map(|k| a[k].wrapping_add(b[k]) as i64);
        let len2 = sum.iter().map(|c| (c * c) as u64).sum::<u64>();
        if !(1 << 26..1 << 31).contains(&len2) {
            return midpoint_normal(a, b);
        }
        let (x, extra) = scaled_into_one_to_four(len2);
        let y = rsqrt_q28(x) as i32 as i64;
        let shift = (30 - extra) as u32;
        Some(sum.map(|c| ((c * y + (1 << (shift - 1))) >> shift) as i32))
    }
    let mut rng = Rng(0x5ca1_ed0f_f00d_2024);
    for n in 0..300_000 {
        // Unit-length pairs (every case of the scaling), then any words
        // whose sum stays in the fast path's range.
        let reach = if n % 4 == 0 { 46_340 } else { UNIT_ONE as i64 };
        let mut vector = || [0; 3].map(|_| rng.range(-reach, reach) as i32);
        let (a, b) = (vector(), vector());
        assert_eq!(
            midpoint_normal(&a, &b),
            scaled_in_64_bits(&a, &b),
            "{a:?} {b:?}"
        );
    }
}

#[test]
fn rsqrt_in_words_equals_the_64_bit_steps() {
    // The steps as first written, every value in 64 bits.
    fn in_64_bits(x: u64) -> u64 {
        let k = ((x >> 24) - 16).min(47) as usize;
        let mut y = RSQRT_START[k] as u64;
        for _ in 0..2 {
            let h = (((y * y) >> 30) * x) >> 28;
            y = (y * ((3 << 30) - h)) >> 31;
        }
        y
    }
    // Both ends of every table interval and a stride through all.
    let mut xs: std::vec::Vec<u64> = (16..64u64)
        .flat_map(|k| [k << 24, ((k + 1) << 24) - 1])
        .collect();
    xs.extend(((1u64 << 28)..(4 << 28)).step_by(997));
    for x in xs {
        assert_eq!(rsqrt_q28(x), in_64_bits(x), "x {x}");
        assert!(rsqrt_q28(x) < 1 << 31);
    }
}

#[test]
fn rsqrt_table_and_newton_steps() {
    let mut x = 1u64 << 28;
    while x < 4 << 28 {
        let y = rsqrt_q28(x) as f64 / (1u64 << 30) as f64;
        let exact = 1.0 / (x as f64 / (1u64 << 28) as f64).sqrt();
        assert!((y / exact - 1.0).abs() < 1.0 / (1 << 21) as f64, "x {x}");
        x += 12_345;
    }
}
