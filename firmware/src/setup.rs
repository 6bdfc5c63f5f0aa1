//! Triangle setup: edge functions with the top-left rule and the depth plane,
//! computed once per triangle (per band it touches). The color planes come
//! later, from [`crate::shading`], and only for a triangle that leaves a
//! visible fragment ([`TriangleSetup::color_planes`]); the triangle keeps its
//! ordered corners and the reciprocal of twice its area for them, so one
//! reciprocal serves every plane.
//!
//! Edge function of the edge from `a` to `b`, for a point `p` in 1/16 pixel:
//! `E(p) = (x_b - x_a)(y_p - y_a) - (y_b - y_a)(x_p - x_a) = A x_p + B y_p + C`.
//! Vertices are ordered so that `E > 0` inside. A sample exactly on an edge
//! (`E = 0`) is inside only for a top or a left edge (`A > 0`, or `A = 0` and
//! `B > 0`, with y growing downward), so two triangles sharing an edge never both
//! own a sample on it. The bias is folded into `C`, and "inside" is `E >= 0`.
//!
//! Ranges: vertices lie within the guard band, so `|A|, |B| < 2^18`, edge values
//! at pixels in the band stay below 2^37, and depth-plane numerators below 2^43.

use crate::coverage::CoverageMask;
use crate::fixed_point::{saturate, Reciprocal, GUARD_BAND_PX, SUBPIXEL_BITS};
use crate::fragment::GRADIENT_LIMIT;

/// A vertex in window coordinates, ready for setup.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SetupVertex {
    /// x in 1/16 pixel, within ±2^16 (the guard band; setup clamps any other
    /// value to it).
    pub x: i32,
    /// y in 1/16 pixel (downward), within ±2^16 like `x`.
    pub y: i32,
    /// Depth, 24 fraction bits, `0 ..= DEPTH_MAX`.
    pub z: u32,
}

/// One edge function, biased for the top-left rule.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
///
/// Ranges: `a` and `b` are differences of two clamped window coordinates, at most
/// 2^17 in magnitude. At any point `p` on the screen `E(p) = a (x_p - x_a) + b
/// (y_p - y_a)` with both distances below `1.5 * 2^16`, so every edge value the
/// rasterizer meets (including one step past the bounding box) is below 2^35;
/// within a pixel's margin (the edge's largest change from the center to a
/// sample, below `2 * 2^17 * 7 < 2^22`) the per-sample values fit `i32`.
pub struct Edge {
    /// dE/dx per 1/16 pixel.
    pub a: i32,
    /// dE/dy per 1/16 pixel.
    pub b: i32,
    /// Biased value at the center of the bounding box's first pixel.
    pub origin: i64,
}

/// A linear function over pixel centers, stepped by additions.
///
/// Ranges, by use:
/// - depth (`depth x 2^16`): gradients saturated to ±2^40 per pixel (a whole
///   depth range per pixel; steeper triangles are edge-on), so the value at any
///   on-screen pixel is below `2^44 + 2 * 2^40 * 1.5 * 2^16 < 2^59`;
/// - Gouraud colors (Q8 x 2^16): a gradient is `2^12 (dc1 dy2 - dc2 dy1) / area2`
///   with color differences below 2^16, coordinate differences at most 2^17 and
///   `area2 >= 1`: below 2^46. At an on-screen pixel `p` the value is
///   `c0 + 2^12 (dc1 (e2 x d) - dc2 (e1 x d)) / area2` with `d` from vertex 0 to
///   `p`; the two cross products have the same sign (the edges are the sides of a
///   triangle) and each is below `|e| |d| < 1.5 * 2^34`, and the color
///   differences cannot be of opposite signs at full size, so the value stays
///   below 2^62.6, the worst case being a sliver of area 1/512 pixel across the
///   whole guard band;
/// - Phong normals: see [`crate::shading::phong::NORMAL_PLANE_BITS`] and its limits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Plane {
    /// Value at the center of the bounding box's first pixel.
    pub origin: i64,
    /// Change per pixel in x.
    pub dx: i64,
    /// Change per pixel in y.
    pub dy: i64,
}

/// Why a triangle produced no setup.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rejection {
    /// Zero area.
    Degenerate,
    /// Facing away and culled.
    Backfacing,
    /// Bounding box misses the screen.
    Outside,
}

/// A triangle ready to rasterize: its edges, bounding box and depth plane.
///
/// Colors are set up separately, by [`TriangleSetup::color_planes`], and only for
/// triangles that turn out to leave a visible fragment: a hidden triangle never
/// pays for its lighting or its quadratic fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TriangleSetup {
    /// The three edges, inside where all are `>= 0`.
    pub edges: [Edge; 3],
    /// First pixel column of the bounding box (on screen).
    pub x0: u16,
    /// First pixel row of the bounding box (on screen).
    pub y0: u16,
    /// Last pixel column (inclusive).
    pub x1: u16,
    /// Last pixel row (inclusive).
    pub y1: u16,
    /// Depth at pixel centers with 16 extra fraction bits (depth units x 2^16);
    /// see [`Plane`] for its range.
    pub depth: Plane,
    /// Depth gradients as stored in fragments (depth units per pixel), rounded
    /// and saturated to ±[`GRADIENT_LIMIT`].
    pub dzdx: i32,
    /// See `dzdx`.
    pub dzdy: i32,
    /// What color setup needs: the ordered, clamped corners.
    pub(crate) corners: Corners,
}

impl TriangleSetup {
    /// The bounding box on screen.
    #[inline(always)]
    pub(crate) fn screen_box(&self) -> ScreenBox {
        ScreenBox {
            x0: self.x0,
            y0: self.y0,
            x1: self.x1,
        }
    }
}

/// The corners of a set-up triangle in edge order, for color setup.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Corners {
    /// x in 1/16 pixel, clamped to the guard band.
    pub(crate) xs: [i32; 3],
    /// y in 1/16 pixel, clamped to the guard band.
    pub(crate) ys: [i32; 3],
    /// Whether vertices 1 and 2 were swapped to make the edges positive inside.
    pub(crate) swapped: bool,
    /// The reciprocal of twice the area.
    pub(crate) area2: Reciprocal,
}

/// A triangle that passed setup's rejection tests ([`TriangleSetup::accept`]).
#[derive(Clone, Copy)]
pub(crate) struct Accepted<'v> {
    /// The vertices as given.
    vertices: &'v [SetupVertex; 3],
    /// Their indices in edge order (vertices 1 and 2 swapped or not).
    order: [usize; 3],
    /// Twice the area, positive.
    area2: i64,
    /// x of the corners in edge order, clamped to the guard band.
    xs: [i32; 3],
    /// y of the corners in edge order, clamped to the guard band.
    ys: [i32; 3],
    /// The bounding box on screen, first and last column and row.
    x0: i32,
    y0: i32,
    x1: i32,
    y1: i32,
}

/// The center of the first pixel of an accepted triangle's box, in 1/16
/// pixel.
#[inline(always)]
fn first_center(accepted: &Accepted<'_>) -> (i32, i32) {
    let half = 1i32 << (SUBPIXEL_BITS - 1);
    (
        (accepted.x0 << SUBPIXEL_BITS) + half,
        (accepted.y0 << SUBPIXEL_BITS) + half,
    )
}

/// The part of a triangle's setup that the whole-band test needs: its depth
/// plane and the fragments' gradients, with the reciprocal of its area that
/// the colors use later. Set up first, so that a face turned away that the
/// buffer hides costs no edges and no corners.
#[derive(Clone, Copy)]
pub(crate) struct DepthSetup {
    /// As [`TriangleSetup::depth`].
    pub(crate) plane: Plane,
    /// As [`TriangleSetup::dzdx`].
    pub(crate) dzdx: i32,
    /// As [`TriangleSetup::dzdy`].
    pub(crate) dzdy: i32,
    /// The reciprocal of twice the area.
    area2: Reciprocal,
}

impl DepthSetup {
    /// The depth plane of a triangle that passed [`TriangleSetup::accept`].
    #[inline(always)]
    pub(crate) fn of(accepted: &Accepted<'_>) -> Self {
        let Accepted {
            vertices,
            order,
            area2,
            xs,
            ys,
            ..
        } = *accepted;
        let v = order.map(|k| &vertices[k]);
        let (cx, cy) = first_center(accepted);
        // Depth plane: z = z0 + gx (x - x0) + gy (y - y0), gradients per pixel x 2^16.
        let (dx1, dy1) = (xs[1] - xs[0], ys[1] - ys[0]);
        let (dx2, dy2) = (xs[2] - xs[0], ys[2] - ys[0]);
        // Depths within `0 ..= DEPTH_MAX` (2^24): their differences are
        // words, and each product below one 32 x 32-bit multiplication
        // (wrapping: a depth beyond the range gives a wrong plane, no panic).
        let dz1 = (v[1].z as i32).wrapping_sub(v[0].z as i32) as i64;
        let dz2 = (v[2].z as i32).wrapping_sub(v[0].z as i32) as i64;
        let shift = 16 + SUBPIXEL_BITS;
        // One reciprocal of the area serves every plane of the triangle.
        let reciprocal = Reciprocal::new(area2 as u64);
        let [gx, gy] = reciprocal
            .mul_div_each(
                [
                    dz1 * dy2 as i64 - dz2 * dy1 as i64,
                    dx1 as i64 * dz2 - dx2 as i64 * dz1,
                ],
                shift,
            )
            .map(|g| saturate(g, DEPTH_STEP_LIMIT));
        let round16 = |g: i64| saturate((g + (1 << 15)) >> 16, GRADIENT_LIMIT as i64) as i32;
        Self {
            plane: Plane {
                origin: (((v[0].z as i64) << shift)
                    + gx * (cx - xs[0]) as i64
                    + gy * (cy - ys[0]) as i64)
                    >> SUBPIXEL_BITS,
                dx: gx,
                dy: gy,
            },
            dzdx: round16(gx),
            dzdy: round16(gy),
            area2: reciprocal,
        }
    }
}

impl Accepted<'_> {
    /// Whether vertices 1 and 2 were swapped to make the edges positive
    /// inside (the signed area was negative: the triangle faces the viewer).
    #[inline]
    fn swapped(&self) -> bool {
        self.order[1] == 2
    }

    /// Whether the triangle faces away from the viewer (as
    /// [`TriangleSetup::faces_away`] will say).
    #[inline]
    pub(crate) fn faces_away(&self) -> bool {
        !self.swapped()
    }

    /// The bounding box on screen: first and last column, first row.
    #[inline]
    pub(crate) fn screen_box(&self) -> ScreenBox {
        ScreenBox {
            x0: self.x0 as u16,
            y0: self.y0 as u16,
            x1: self.x1 as u16,
        }
    }

    /// The rows of the bounding box that can hold samples of grid `M` inside
    /// the triangle ([`sample_rows`]).
    #[inline(always)]
    pub(crate) fn sample_rows<M: CoverageMask>(&self) -> Option<(u16, u16)> {
        sample_rows::<M>(&self.ys, (self.y0, self.y1))
    }
}

/// The rows of a triangle's bounding box (`first..=last`, image rows) that
/// can hold samples of grid `M` inside it, given its corners' heights `ys`
/// (1/16 pixel): those whose sample rows, from the first to the last, reach
/// into the triangle's height; `None` when no row's do. The other rows can
/// hold no fragment of the triangle.
#[inline(always)]
fn sample_rows<M: CoverageMask>(ys: &[i32; 3], (y0, y1): (i32, i32)) -> Option<(u16, u16)> {
    let top = ys[0].min(ys[1]).min(ys[2]);
    let bottom = ys[0].max(ys[1]).max(ys[2]);
    let half = 1 << (SUBPIXEL_BITS - 1);
    let (reach, below_next) = (M::max_offset_y(), (1 << SUBPIXEL_BITS) - 1);
    // The first row whose lowest sample row is not above the top, the last
    // whose highest is not below the bottom (samples at the pixel center
    // plus or minus `reach`).
    let first = ((top - half - reach + below_next) >> SUBPIXEL_BITS).max(y0);
    let last = ((bottom - half + reach) >> SUBPIXEL_BITS).min(y1);
    (first <= last).then_some((first as u16, last as u16))
}

/// A triangle's bounding box on screen, in pixels: its columns (last one
/// included) and its first row, where the depth plane is anchored. Its rows
/// are asked through `sample_rows`, which keeps only those that can hold
/// samples.
#[derive(Clone, Copy)]
pub(crate) struct ScreenBox {
    /// First column.
    pub(crate) x0: u16,
    /// First row.
    pub(crate) y0: u16,
    /// Last column.
    pub(crate) x1: u16,
}

/// Whether a triangle with window-space area `area2` (twice the signed area, from
/// [`signed_area2`]) faces away from the viewer.
#[inline]
pub fn is_backfacing(area2: i64) -> bool {
    // Counter-clockwise in normalized device coordinates (y up) is clockwise in
    // window coordinates (y down), which gives a negative area2.
    area2 > 0
}

/// Twice the signed area of a window-space triangle, in (1/16 pixel)^2.
#[inline]
pub fn signed_area2(v: &[SetupVertex; 3]) -> i64 {
    let (x0, y0) = (v[0].x as i64, v[0].y as i64);
    (v[1].x as i64 - x0) * (v[2].y as i64 - y0) - (v[2].x as i64 - x0) * (v[1].y as i64 - y0)
}

/// [`signed_area2`] of corners within the guard band (`±2^16` in 1/16
/// pixel, as [`TriangleSetup`]'s accepted corners): their differences fit
/// `i32`, and each product is one 32 x 32 -> 64-bit multiplication instead
/// of a product of two 64-bit differences.
#[inline]
fn signed_area2_within_guard_band(v: &[SetupVertex; 3]) -> i64 {
    let (x0, y0) = (v[0].x, v[0].y);
    let product = |a: i32, b: i32| a as i64 * b as i64;
    product(v[1].x - x0, v[2].y - y0) - product(v[2].x - x0, v[1].y - y0)
}

/// The largest depth-plane step kept (a full depth range per pixel); steeper
/// triangles are edge-on and cover almost nothing.
const DEPTH_STEP_LIMIT: i64 = 1 << 40;

impl TriangleSetup {
    /// Sets up a triangle for a `width x height` screen: edges, bounding box
    /// and depth plane (colors come later, from [`TriangleSetup::color_planes`]).
    pub fn new(
        v: &[SetupVertex; 3],
        cull_backfaces: bool,
        width: u16,
        height: u16,
    ) -> Result<Self, Rejection> {
        Ok(Self::build(&Self::accept(
            v,
            cull_backfaces,
            (width, height),
            false,
        )?))
    }

    /// The rejection tests of [`TriangleSetup::new`] for a `width x height`
    /// screen: what passes them, with the corners in edge order and clamped
    /// and the bounding box on screen. `within_guard_band` says that every
    /// corner is known to lie within the guard band already (the frame
    /// driver's window positions are clamped to it): they are then neither
    /// tested nor clamped. (Kept apart from [`TriangleSetup::build`] so a
    /// caller's setup is built where it lives, not moved out of a `Result`.)
    #[inline(always)]
    pub(crate) fn accept(
        v: &[SetupVertex; 3],
        cull_backfaces: bool,
        (width, height): (u16, u16),
        within_guard_band: bool,
    ) -> Result<Accepted<'_>, Rejection> {
        // Clamped corners fit `i32` (±2^16), their differences too (±2^17):
        // the products of setup are single 32 x 32 -> 64-bit multiplications.
        let lim = GUARD_BAND_PX << SUBPIXEL_BITS;
        // Vertices already within the guard band (every one that was not
        // clipped) need no clamp: one unsigned comparison each says so.
        let within = |c: i32| c.wrapping_add(lim) as u32 <= 2 * lim as u32;
        let all_within = within_guard_band || v.iter().all(|p| within(p.x) & within(p.y));
        // The area of the corners as given; within the guard band, from
        // their differences in `i32` (the same integer).
        let area2 = if all_within {
            signed_area2_within_guard_band(v)
        } else {
            signed_area2(v)
        };
        if area2 == 0 {
            return Err(Rejection::Degenerate);
        }
        if cull_backfaces && is_backfacing(area2) {
            return Err(Rejection::Backfacing);
        }
        // Order so that the edge functions are positive inside.
        let swapped = area2 < 0;
        let order = if swapped { [0, 2, 1] } else { [0, 1, 2] };
        let (xs, ys) = if all_within {
            (order.map(|k| v[k].x), order.map(|k| v[k].y))
        } else {
            (
                order.map(|k| v[k].x.clamp(-lim, lim)),
                order.map(|k| v[k].y.clamp(-lim, lim)),
            )
        };
        // Bounding box in pixels, clipped to the screen.
        let min_x = xs[0].min(xs[1]).min(xs[2]) >> SUBPIXEL_BITS;
        let max_x = xs[0].max(xs[1]).max(xs[2]) >> SUBPIXEL_BITS;
        let min_y = ys[0].min(ys[1]).min(ys[2]) >> SUBPIXEL_BITS;
        let max_y = ys[0].max(ys[1]).max(ys[2]) >> SUBPIXEL_BITS;
        if max_x < 0 || max_y < 0 || min_x >= width as i32 || min_y >= height as i32 {
            return Err(Rejection::Outside);
        }
        Ok(Accepted {
            vertices: v,
            order,
            area2: area2.abs(),
            xs,
            ys,
            x0: min_x.max(0),
            y0: min_y.max(0),
            x1: max_x.min(width as i32 - 1),
            y1: max_y.min(height as i32 - 1),
        })
    }

    /// The setup of a triangle that passed [`TriangleSetup::accept`].
    #[inline(always)]
    pub(crate) fn build(accepted: &Accepted<'_>) -> Self {
        Self::build_with(accepted, DepthSetup::of(accepted))
    }

    /// The setup of a triangle that passed [`TriangleSetup::accept`], whose
    /// depth plane is `depth` ([`DepthSetup::of`]): its edges and corners.
    #[inline(always)]
    pub(crate) fn build_with(accepted: &Accepted<'_>, depth: DepthSetup) -> Self {
        let Accepted {
            xs,
            ys,
            x0,
            y0,
            x1,
            y1,
            ..
        } = *accepted;
        let swapped = accepted.swapped();
        let (cx, cy) = first_center(accepted);
        let wide = |a: i32, b: i32| a as i64 * b as i64;
        let mut edges = [Edge::default(); 3];
        for (i, e) in edges.iter_mut().enumerate() {
            let (ia, ib) = (i, (i + 1) % 3);
            let a = ys[ia] - ys[ib];
            let b = xs[ib] - xs[ia];
            let top_left = a > 0 || (a == 0 && b > 0);
            // E at the first pixel's center: a (cx - xa) + b (cy - ya), biased.
            *e = Edge {
                a,
                b,
                origin: wide(a, cx - xs[ia]) + wide(b, cy - ys[ia]) - if top_left { 0 } else { 1 },
            };
        }
        Self {
            edges,
            x0: x0 as u16,
            y0: y0 as u16,
            x1: x1 as u16,
            y1: y1 as u16,
            depth: depth.plane,
            dzdx: depth.dzdx,
            dzdy: depth.dzdy,
            corners: Corners {
                xs,
                ys,
                swapped,
                area2: depth.area2,
            },
        }
    }

    /// The rows of the bounding box that can hold samples of grid `M` inside
    /// the triangle ([`sample_rows`]).
    #[inline(always)]
    pub(crate) fn sample_rows<M: CoverageMask>(&self) -> Option<(u16, u16)> {
        sample_rows::<M>(&self.corners.ys, (self.y0 as i32, self.y1 as i32))
    }

    /// Whether the corners lie within 1,024 pixels of each other in x and
    /// in y. Then every edge value of the rasterizer stays below 2^30 in
    /// magnitude: at a pixel center of the bounding box or one step beyond
    /// it, `x - x_a` is within `W + 24` (1/16 pixel, `W` the corners' extent
    /// in x, below 2^14) and likewise `y`, and `|a| <= H`, `|b| <= W`, so
    /// `|E| <= 2 W H + 24 (W + H) + 1 < 2^29 + 2^20`.
    #[inline]
    pub(crate) fn corners_within_1024_px(&self) -> bool {
        let extent = |c: &[i32; 3]| c[0].max(c[1]).max(c[2]) - c[0].min(c[1]).min(c[2]);
        const LIMIT: i32 = 1024 << SUBPIXEL_BITS;
        extent(&self.corners.xs) < LIMIT && extent(&self.corners.ys) < LIMIT
    }

    /// Whether the triangle faces away from the viewer (clockwise on screen
    /// with y downward; see [`is_backfacing`]).
    #[inline]
    pub fn faces_away(&self) -> bool {
        // Vertices 1 and 2 were swapped exactly when the signed area was
        // negative, that is when the triangle faces the viewer.
        !self.corners.swapped
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coverage::{Mask1x1, Mask4x4, Mask8x8};

    /// The first and last rows of `accepted`'s box with a sample of grid `M`
    /// at a height within the triangle's, found sample row by sample row:
    /// [`Accepted::sample_rows`] must keep them (it may keep rows whose
    /// sample rows straddle a triangle thinner than their spacing).
    fn rows_by_sample<M: CoverageMask>(accepted: &Accepted<'_>) -> Option<(u16, u16)> {
        let top = accepted.ys.iter().min().copied().unwrap_or(0);
        let bottom = accepted.ys.iter().max().copied().unwrap_or(0);
        let holds_sample = |row: &i32| {
            (0..M::ROWS).any(|j| {
                let y = (row << SUBPIXEL_BITS) + (1 << (SUBPIXEL_BITS - 1)) + M::offset_y(j);
                top <= y && y <= bottom
            })
        };
        let first = (accepted.y0..=accepted.y1).find(holds_sample)?;
        let last = (accepted.y0..=accepted.y1).rev().find(holds_sample)?;
        Some((first as u16, last as u16))
    }

    fn check<M: CoverageMask>(next: &mut impl FnMut() -> u64) {
        let mut narrower = 0u32;
        for _ in 0..20_000 {
            // Small triangles near the screen's edges and around sample rows:
            // heights of a few sixteenths as often as of a few pixels.
            let corner = |next: &mut dyn FnMut() -> u64| {
                (next() % (60 << SUBPIXEL_BITS)) as i32 - (6 << SUBPIXEL_BITS)
            };
            let (x, y) = (corner(next), corner(next));
            let spread = if next() & 1 == 0 { 6 } else { 64 };
            let mut offset = || (next() % (2 * spread + 1)) as i32 - spread as i32;
            let v = [
                SetupVertex { x, y, z: 0 },
                SetupVertex {
                    x: x + offset(),
                    y: y + offset(),
                    z: 0,
                },
                SetupVertex {
                    x: x + offset(),
                    y: y + offset(),
                    z: 0,
                },
            ];
            let Ok(accepted) = TriangleSetup::accept(&v, false, (48, 40), false) else {
                continue;
            };
            let what = || format!("{} grid, corners {:?}", M::NAME, v.map(|p| (p.x, p.y)));
            let rows = accepted.sample_rows::<M>();
            if let Some((first, last)) = rows_by_sample::<M>(&accepted) {
                let (kept_first, kept_last) = rows.unwrap_or_else(|| panic!("{}", what()));
                assert!(kept_first <= first && last <= kept_last, "{}", what());
            }
            let rows = rows.map_or(0, |(first, last)| last - first + 1);
            let box_rows = (accepted.y1 - accepted.y0 + 1) as u16;
            assert!(rows <= box_rows, "{}", what());
            narrower += (rows < box_rows) as u32;
        }
        // Often an end of the box lies beyond the sample rows.
        assert!(narrower > 500, "{}: {narrower} boxes narrowed", M::NAME);
    }

    #[test]
    fn sample_rows_keep_every_row_with_a_sample_in_the_triangles_height() {
        let mut next = crate::test_rng::xorshift(0x5851_f42d_4c95_7f2d);
        check::<Mask1x1>(&mut next);
        check::<Mask4x4>(&mut next);
        check::<Mask8x8>(&mut next);
    }

    /// Within the guard band, the area from `i32` differences is
    /// [`signed_area2`]'s, corners at the band's edges included.
    #[test]
    fn area_within_the_guard_band_is_the_signed_area() {
        let lim = GUARD_BAND_PX << SUBPIXEL_BITS;
        let mut next = crate::test_rng::xorshift(0x9e37_79b9_7f4a_7c15);
        let mut coordinate = || match next() % 4 {
            0 => -lim,
            1 => lim,
            _ => (next() % (2 * lim as u64 + 1)) as i32 - lim,
        };
        for _ in 0..100_000 {
            let v: [SetupVertex; 3] = core::array::from_fn(|_| SetupVertex {
                x: coordinate(),
                y: coordinate(),
                z: 0,
            });
            assert_eq!(
                signed_area2_within_guard_band(&v),
                signed_area2(&v),
                "{v:?}"
            );
        }
    }
}
