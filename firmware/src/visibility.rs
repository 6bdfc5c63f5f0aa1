//! Visibility masks: per-sample depth comparison of two fragments (SPEC section 3).
//!
//! Bit `s` of the visibility mask of a new fragment `A` against a stored fragment
//! `B` is set where `A` is nearer than `B` or at the same depth (ties go to the
//! new fragment). Both fragments' depth planes are evaluated at the sample
//! positions exactly, in integers: the difference plane is stepped across the grid
//! with one addition per sample.

use crate::coverage::CoverageMask;
use crate::fragment::Fragment;

/// Samples where `a` is nearer than or as near as `b`.
#[inline]
pub fn visibility_mask<M: CoverageMask>(a: &Fragment<M>, b: &Fragment<M>) -> M {
    visibility_against_plane(a, b.z, b.dzdx, b.dzdy)
}

/// [`visibility_mask`] of `a` against the depth plane of a fragment given
/// by its center depth `z` and gradients `dzdx`, `dzdy` (a stored
/// fragment's, read from its packed form without unpacking the rest: the
/// function is called out of line, and the whole fragment went through
/// the stack).
#[inline]
pub fn visibility_against_plane<M: CoverageMask>(
    a: &Fragment<M>,
    z: u32,
    dzdx: i32,
    dzdy: i32,
) -> M {
    // Difference plane D = depth_a - depth_b (scaled by 16), |D| < 2^30.
    let dz = ((a.z as i32) - (z as i32)) << 4;
    let ddx = a.dzdx - dzdx;
    let ddy = a.dzdy - dzdy;
    let d_first = dz + ddx * M::offset_x(0) + ddy * M::offset_y(0);
    let span_x = ddx * (M::offset_x(M::COLS - 1) - M::offset_x(0));
    let span_y = ddy * (M::offset_y(M::ROWS - 1) - M::offset_y(0));
    // D is affine over the grid, so its extremes are at the corner samples.
    let corners = [
        d_first,
        d_first + span_x,
        d_first + span_y,
        d_first + span_x + span_y,
    ];
    if corners.iter().all(|&d| d <= 0) {
        return M::FULL;
    }
    if corners.iter().all(|&d| d > 0) {
        return M::EMPTY;
    }
    let step_x = ddx * (16 / M::COLS as i32);
    let step_y = ddy * (16 / M::ROWS as i32);
    let mut bits: u64 = 0;
    let mut d_row = d_first;
    let mut bit = 0;
    for _ in 0..M::ROWS {
        let mut d = d_row;
        for _ in 0..M::COLS {
            bits |= ((d <= 0) as u64) << bit;
            bit += 1;
            d += step_x;
        }
        d_row += step_y;
    }
    M::from_u64(bits)
}

/// Applies the seed's mask update to a new fragment `a` and a stored fragment `b`.
///
/// Returns `(new mask of a, new mask of b)`:
/// `M_A & !(M_A & M_B & !vis)` and `M_B & !(M_A & M_B & vis)`, computed from the
/// masks before the update.
#[inline]
pub fn resolve_overlap<M: CoverageMask>(a: &Fragment<M>, b: &Fragment<M>) -> (M, M) {
    let overlap = a.mask & b.mask;
    if overlap.is_empty() {
        return (a.mask, b.mask);
    }
    let vis = visibility_mask(a, b);
    (a.mask & !(overlap & !vis), b.mask & !(overlap & vis))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coverage::{Mask4x4, Mask8x8};
    use embedded_graphics_core::pixelcolor::Rgb888;

    fn frag<M: CoverageMask>(mask: M, z: u32, dzdx: i32, dzdy: i32) -> Fragment<M> {
        Fragment {
            mask,
            z,
            dzdx,
            dzdy,
            color: Rgb888::new(0, 0, 0),
        }
    }

    fn brute<M: CoverageMask>(a: &Fragment<M>, b: &Fragment<M>) -> M {
        let mut m = M::EMPTY;
        for j in 0..M::ROWS {
            for i in 0..M::COLS {
                if a.depth_at(i, j) <= b.depth_at(i, j) {
                    m = m.with(j * M::COLS + i);
                }
            }
        }
        m
    }

    #[test]
    fn matches_per_sample_comparison() {
        let mut seed = 12345u32;
        let mut rnd = |r: i32| {
            seed = seed.wrapping_mul(1664525).wrapping_add(1013904223);
            ((seed >> 8) as i32).rem_euclid(2 * r + 1) - r
        };
        for _ in 0..20_000 {
            let za = 1_000_000 + rnd(5000);
            let zb = 1_000_000 + rnd(5000);
            let a = frag(Mask8x8::FULL, za as u32, rnd(20000), rnd(20000));
            let b = frag(Mask8x8::FULL, zb as u32, rnd(20000), rnd(20000));
            assert_eq!(visibility_mask(&a, &b), brute(&a, &b));
            let a4 = frag(Mask4x4::FULL, za as u32, rnd(20000), rnd(20000));
            let b4 = frag(Mask4x4::FULL, zb as u32, rnd(20000), rnd(20000));
            assert_eq!(visibility_mask(&a4, &b4), brute(&a4, &b4));
        }
    }

    #[test]
    fn intersecting_planes_split_the_pixel() {
        // A tilts in x through the center, B is flat at the same center depth:
        // A is nearer on the left half, and the tie on no sample (offsets are odd).
        let a = frag(Mask4x4::FULL, 5000, 100, 0);
        let b = frag(Mask4x4::FULL, 5000, 0, 0);
        let (ma, mb) = resolve_overlap(&a, &b);
        assert_eq!(ma, Mask4x4(0x3333));
        assert_eq!(mb, Mask4x4(0xCCCC));
        assert!((ma & mb).is_empty());
    }

    #[test]
    fn ties_go_to_the_new_fragment() {
        let a = frag(Mask4x4(0x00FF), 7, 0, 0);
        let b = frag(Mask4x4(0x0FF0), 7, 0, 0);
        assert_eq!(resolve_overlap(&a, &b), (Mask4x4(0x00FF), Mask4x4(0x0F00)));
    }
}
