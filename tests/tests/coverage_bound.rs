//! SPEC section 2: the coverage of one straight edge crossing a pixel, measured by
//! the mask (`popcount / SAMPLES`), differs from the exact covered area by at most
//! `(V + H)^2 / (8 V^2 H)` (H columns, V rows; the seed's formula, valid for our
//! grids since V <= H). The exact area is computed in f64 by clipping the pixel
//! square against the half-plane.

use mcu_abuffer::coverage::{CoverageMask, Mask4x4, Mask8x4, Mask8x8};
use mcu_abuffer::raster::edge_mask;
use mcu_abuffer::setup::Edge;
use system_tests::Rng;

/// Edges tried per grid.
const EDGES: usize = 200_000;

/// The pixel is `[0, 16] x [0, 16]` in 1/16-pixel units, its center `(8, 8)`.
const PIXEL: f64 = 16.0;

/// The edge function of the edge from `(xa, ya)` to `(xb, yb)` as triangle setup
/// builds it: `a = -(yb - ya)`, `b = xb - xa`, inside where `a x + b y + c >= 0`,
/// with `c` lowered by one unless the edge is a top or left edge; `origin` is its
/// value at the pixel center.
fn edge(xa: i64, ya: i64, xb: i64, yb: i64) -> (Edge, i64) {
    let a = -(yb - ya);
    let b = xb - xa;
    let top_left = a > 0 || (a == 0 && b > 0);
    let c = -(a * xa + b * ya) - if top_left { 0 } else { 1 };
    let e = Edge {
        a: a as i32,
        b: b as i32,
        origin: a * 8 + b * 8 + c,
    };
    (e, c)
}

/// Area of `{ a x + b y + c >= 0 }` within the pixel square, as a fraction of the pixel.
fn exact_area(a: f64, b: f64, c: f64) -> f64 {
    let square = [(0.0, 0.0), (PIXEL, 0.0), (PIXEL, PIXEL), (0.0, PIXEL)];
    let f = |p: (f64, f64)| a * p.0 + b * p.1 + c;
    // Sutherland-Hodgman against one half-plane.
    let mut poly: Vec<(f64, f64)> = Vec::new();
    for i in 0..4 {
        let p = square[i];
        let q = square[(i + 1) % 4];
        let (fp, fq) = (f(p), f(q));
        if fp >= 0.0 {
            poly.push(p);
        }
        if (fp >= 0.0) != (fq >= 0.0) {
            let t = fp / (fp - fq);
            poly.push((p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1)));
        }
    }
    let mut twice = 0.0;
    for i in 0..poly.len() {
        let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
        twice += p.0 * q.1 - q.0 * p.1;
    }
    (twice / 2.0).abs() / (PIXEL * PIXEL)
}

/// The seed's bound for an `H x V` grid.
fn bound(h: f64, v: f64) -> f64 {
    (v + h) * (v + h) / (8.0 * v * v * h)
}

/// Sample offset from the pixel center in 1/16 pixel, computed here independently.
fn offset(i: u32, n: u32) -> i64 {
    (2 * i as i64 + 1 - n as i64) * 8 / n as i64
}

fn measure<M: CoverageMask>(seed: u64) -> (f64, f64) {
    let mut rng = Rng::new(seed);
    let limit = bound(M::COLS as f64, M::ROWS as f64);
    let mut max_err = 0.0f64;
    let mut max_err_sloped = 0.0f64;
    let mut worst = (0, 0, 0, 0);
    let mut tried = 0;
    while tried < EDGES {
        // Endpoints in 1/16 pixel around the pixel; some snapped to pixel-center or
        // sample coordinates, some making axis-aligned edges.
        let coord = |rng: &mut Rng, n: u32| -> i64 {
            match rng.below(4) {
                0 => 16 * rng.range(-4, 4) + 8 + offset(rng.below(n as u64) as u32, n),
                1 => 16 * rng.range(-4, 4) + 8,
                _ => rng.range(-80, 96),
            }
        };
        let (xa, ya) = (coord(&mut rng, M::COLS), coord(&mut rng, M::ROWS));
        let (mut xb, mut yb) = (coord(&mut rng, M::COLS), coord(&mut rng, M::ROWS));
        match rng.below(10) {
            0 => yb = ya,
            1 => xb = xa,
            _ => {}
        }
        let (dx, dy) = (xb - xa, yb - ya);
        if dx * dx + dy * dy < 16 * 16 {
            continue;
        }
        let (e, c) = edge(xa, ya, xb, yb);
        // The (unbiased) line must cross the pixel's interior.
        let unbiased = -(i64::from(e.a) * xa + i64::from(e.b) * ya);
        let corners = [(0, 0), (16, 0), (16, 16), (0, 16)]
            .map(|(x, y)| i64::from(e.a) * x + i64::from(e.b) * y + unbiased);
        if !(corners.iter().any(|&v| v > 0) && corners.iter().any(|&v| v < 0)) {
            continue;
        }
        tried += 1;
        let mask: M = edge_mask::<M>(e.origin, &e);
        // Every bit is the sign of the biased edge function at that sample.
        for j in 0..M::ROWS {
            for i in 0..M::COLS {
                let v = i64::from(e.a) * (8 + offset(i, M::COLS))
                    + i64::from(e.b) * (8 + offset(j, M::ROWS))
                    + c;
                assert_eq!(
                    mask.get(j * M::COLS + i),
                    v >= 0,
                    "{} edge ({xa},{ya})-({xb},{yb}): sample ({i},{j})",
                    M::NAME
                );
            }
        }
        let covered = mask.count() as f64 / M::SAMPLES as f64;
        let area = exact_area(
            i64::from(e.a) as f64,
            i64::from(e.b) as f64,
            unbiased as f64,
        );
        let err = (covered - area).abs();
        if dx != 0 && dy != 0 {
            max_err_sloped = max_err_sloped.max(err);
        }
        if err > max_err {
            max_err = err;
            worst = (xa, ya, xb, yb);
        }
        assert!(
            err <= limit + 1e-12,
            "{} edge ({xa},{ya})-({xb},{yb}): mask covers {covered}, exact area {area}, \
             error {err} above the bound {limit}",
            M::NAME
        );
    }
    println!(
        "{}: max |S_exact - S_mask| over {EDGES} edges = {max_err:.6} (bound {limit:.6}, \
         worst edge {worst:?} in 1/16 px); over the sloped ones alone {max_err_sloped:.6}",
        M::NAME
    );
    (max_err, limit)
}

fn check<M: CoverageMask>(seed: u64) {
    let (max_err, limit) = measure::<M>(seed);
    assert!(
        max_err >= 0.8 * limit,
        "{}: largest error {max_err} is far below the bound {limit}: the test does not probe it",
        M::NAME
    );
}

#[test]
fn exact_area_sanity() {
    // Half the pixel: vertical line through the center, inside to the right.
    assert!((exact_area(1.0, 0.0, -8.0) - 0.5).abs() < 1e-15);
    // Triangle cut off a corner: x + y <= 4 has area 8 of 256.
    assert!((exact_area(-1.0, -1.0, 4.0) - 8.0 / 256.0).abs() < 1e-15);
    assert_eq!(exact_area(1.0, 0.0, 100.0), 1.0);
    assert_eq!(exact_area(1.0, 0.0, -100.0), 0.0);
    assert_eq!(bound(4.0, 4.0), 0.125);
    assert_eq!(bound(8.0, 4.0), 0.140625);
    assert_eq!(bound(8.0, 8.0), 0.0625);
}

#[test]
fn coverage_error_bound_4x4() {
    check::<Mask4x4>(404);
}

#[test]
fn coverage_error_bound_8x4() {
    check::<Mask8x4>(804);
}

#[test]
fn coverage_error_bound_8x8() {
    check::<Mask8x8>(808);
}
