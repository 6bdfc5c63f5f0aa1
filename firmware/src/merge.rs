//! Merging two fragments into one (SPEC section 4).
//!
//! When a pixel must hold more fragments than its memory allows, two of them become
//! one: coverage is the union, depth lies between the two, nearer the one with more
//! coverage, the gradients are the smaller-magnitude ones (flatter fragments tend to
//! cover more of the pixel), and the color is the coverage-weighted mean.

use crate::coverage::CoverageMask;
use crate::fragment::Fragment;
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};

/// Merges `a` (the nearer) and `b` (the farther, `b.z >= a.z`) into one fragment.
///
/// - `mask = M_A | M_B`
/// - `z = z_A + (z_B - z_A) K_B / (K_A + K_B)`, rounded down
/// - `dzdx`, `dzdy`: each the one of smaller magnitude (`B`'s on a tie, as in the seed)
/// - `color = (color_A K_A + color_B K_B) / (K_A + K_B)` per channel, rounded to nearest
///
/// `K` is a mask's popcount. The seed writes the mask's total bit count in the
/// denominators; SPEC section 4 explains why `K_A + K_B` is the reading that
/// satisfies the seed's own text. If both masks are empty the result is `a`.
pub fn merge_fragments<M: CoverageMask>(a: &Fragment<M>, b: &Fragment<M>) -> Fragment<M> {
    // 32-bit arithmetic throughout (a hardware divide on Cortex-M3/M4): depths
    // differ by less than 2^24 and a popcount is at most 64, so products stay below
    // 2^30; color sums below 255 * 64.
    let ka = a.mask.count();
    let kb = b.mask.count();
    let k = ka + kb;
    if k == 0 {
        return *a;
    }
    let z = if b.z >= a.z {
        a.z + (b.z - a.z) * kb / k
    } else {
        a.z - (a.z - b.z) * kb / k
    };
    let smaller = |ga: i32, gb: i32| {
        if ga.unsigned_abs() < gb.unsigned_abs() {
            ga
        } else {
            gb
        }
    };
    let channel = |ca: u8, cb: u8| ((ca as u32 * ka + cb as u32 * kb + k / 2) / k) as u8;
    Fragment {
        mask: a.mask | b.mask,
        z,
        dzdx: smaller(a.dzdx, b.dzdx),
        dzdy: smaller(a.dzdy, b.dzdy),
        color: Rgb888::new(
            channel(a.color.r(), b.color.r()),
            channel(a.color.g(), b.color.g()),
            channel(a.color.b(), b.color.b()),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coverage::Mask4x4;

    #[test]
    fn hand_made_case() {
        let a = Fragment {
            mask: Mask4x4(0x000F), // 4 samples
            z: 1000,
            dzdx: -50,
            dzdy: 7,
            color: Rgb888::new(200, 0, 10),
        };
        let b = Fragment {
            mask: Mask4x4(0x0FF0), // 8 samples
            z: 1600,
            dzdx: 20,
            dzdy: -7,
            color: Rgb888::new(50, 90, 11),
        };
        let m = merge_fragments(&a, &b);
        assert_eq!(m.mask, Mask4x4(0x0FFF));
        // 1000 + 600 * 8 / 12 = 1400: nearer B, which covers more.
        assert_eq!(m.z, 1400);
        assert_eq!(m.dzdx, 20);
        assert_eq!(m.dzdy, -7, "tie in magnitude takes B's");
        // (200*4 + 50*8)/12 = 100; (0*4 + 90*8)/12 = 60; (10*4+11*8)/12 = 10.67 -> 11
        assert_eq!(m.color, Rgb888::new(100, 60, 11));
    }
}
