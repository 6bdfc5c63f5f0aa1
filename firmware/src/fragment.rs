//! Fragments: what one triangle leaves in one pixel, and their packed storage form.

use crate::coverage::CoverageMask;
use crate::fixed_point::DEPTH_MAX;
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};

/// The largest magnitude of a stored depth gradient (24-bit signed), in depth units per pixel.
pub const GRADIENT_LIMIT: i32 = (1 << 23) - 1;

/// A fragment in working form: coverage, color and the depth plane at the pixel.
///
/// `z` is the triangle plane's depth at the pixel center (24 fraction bits, smaller
/// is nearer), `dzdx`/`dzdy` its gradients in depth units per pixel, saturated to
/// ±[`GRADIENT_LIMIT`]. The depth at the sample with offset `(ox, oy)` (in 1/16
/// pixel) is `(z * 16 + dzdx * ox + dzdy * oy) / 16`; see [`Fragment::depth_at`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fragment<M: CoverageMask> {
    /// Samples this fragment covers (and, once stored, owns).
    pub mask: M,
    /// Depth at the pixel center, `0 ..= DEPTH_MAX`.
    pub z: u32,
    /// Depth change per pixel step in x.
    pub dzdx: i32,
    /// Depth change per pixel step in y.
    pub dzdy: i32,
    /// Color, 8 bits per channel.
    pub color: Rgb888,
}

impl<M: CoverageMask> Fragment<M> {
    /// Depth at sample `(col, row)` of the grid, scaled by 16 (exact: no rounding).
    ///
    /// This is the quantity visibility compares: `16 z + dzdx ox + dzdy oy` with the
    /// sample offsets in 1/16 pixel. Its magnitude stays below 2^29.
    #[inline]
    pub fn depth_at(&self, col: u32, row: u32) -> i32 {
        ((self.z as i32) << 4) + self.dzdx * M::offset_x(col) + self.dzdy * M::offset_y(row)
    }

    /// The largest [`Fragment::depth_at`] over the grid's samples: the same
    /// as [`PackedFragment::farthest_sample_depth`] of the packed fragment.
    /// Within one triangle only the depth changes, so a loop over its
    /// pixels computes the gradients' part once.
    #[inline]
    pub fn farthest_sample_depth(&self) -> i32 {
        ((self.z as i32) << 4)
            + self.dzdx.abs() * M::max_offset_x()
            + self.dzdy.abs() * M::max_offset_y()
    }
}

/// Fraction bits of depth-plane values ([`crate::setup::Plane`]) beyond
/// those of stored depths.
pub const PLANE_EXTRA_BITS: u32 = 16;

/// Half a stored depth unit in depth-plane units: what rounds a plane value
/// to the nearest depth before the shift by [`PLANE_EXTRA_BITS`]. The pixel
/// walks add it once, to the depth of each row's first pixel, and round
/// every pixel's value with [`rounded_depth`] (a shift, no addition).
pub const PLANE_HALF_UNIT: i64 = 1 << (PLANE_EXTRA_BITS - 1);

/// Whether a depth plane's value that carries [`PLANE_HALF_UNIT`] rounds to
/// a depth in `0 ..= DEPTH_MAX`, where [`rounded_depth`] is the value
/// shifted down by [`PLANE_EXTRA_BITS`] and clamps nothing.
#[inline(always)]
pub fn rounds_in_range(biased: i64) -> bool {
    (biased as u64) < (DEPTH_MAX as u64 + 1) << PLANE_EXTRA_BITS
}

/// `v` saturated to the 24-bit signed range, `-2^23 ..= 2^23 - 1`: one
/// instruction on the Cortex-M4 (`ssat`). Gradients within
/// ±[`GRADIENT_LIMIT`] pass unchanged.
#[inline(always)]
fn saturate_24(v: i32) -> i32 {
    v.clamp(-(1 << 23), (1 << 23) - 1)
}

/// The depth a fragment stores for a depth-plane value `plane` at its pixel
/// center (depth units with [`PLANE_EXTRA_BITS`] extra fraction bits,
/// [`crate::setup::Plane`]): rounded to nearest and clamped to `0 ..=
/// DEPTH_MAX`.
#[inline(always)]
pub fn fragment_depth(plane: i64) -> u32 {
    rounded_depth(plane + PLANE_HALF_UNIT)
}

/// [`fragment_depth`] of a plane value that carries [`PLANE_HALF_UNIT`]:
/// shifted down (so rounded) and clamped.
#[inline(always)]
pub fn rounded_depth(biased: i64) -> u32 {
    const _: () = assert!(DEPTH_MAX == (1 << 24) - 1 && PLANE_EXTRA_BITS == 16);
    // The depth is in range exactly when the high word is below 2^8: one
    // comparison in the common case.
    let high = (biased >> 32) as i32;
    if (high as u32) < 1 << 8 {
        (biased >> PLANE_EXTRA_BITS) as u32
    } else if high < 0 {
        0
    } else {
        DEPTH_MAX
    }
}

/// [`rounded_depth`], on Armv7-M (the build script's `arm_long_multiply`)
/// as four instructions written out: the high word saturated to 16 bits
/// (`ssat`), the depth as the low 16 bits of that above the value's bits
/// 16 to 31, saturated to 24 unsigned bits (`usat`). The same value: in
/// range the two saturations change nothing; below it the word is
/// negative, above it at least 2^24. The compiler's code for
/// [`rounded_depth`] (a test of the high word and its selects) costs the
/// antialiased pixel walks about 0.1 M instructions more a teapot frame;
/// the z-buffer's walks, whose loops differ, keep it.
#[inline(always)]
pub fn rounded_depth_saturated(biased: i64) -> u32 {
    #[cfg(arm_long_multiply)]
    {
        const _: () = assert!(DEPTH_MAX == (1 << 24) - 1 && PLANE_EXTRA_BITS == 16);
        let (mut low, high) = (biased as u32, (biased >> 32) as i32);
        // SAFETY: register-only arithmetic, no memory or stack (the flags
        // are changed: no `preserves_flags`).
        unsafe {
            core::arch::asm!(
                "ssat {high}, #16, {high}",
                "lsrs {low}, {low}, #16",
                "orr {low}, {low}, {high}, lsl #16",
                "usat {low}, #24, {low}",
                low = inout(reg) low,
                high = inout(reg) high => _,
                options(pure, nomem, nostack)
            );
        }
        low
    }
    #[cfg(not(arm_long_multiply))]
    {
        rounded_depth(biased)
    }
}

/// A fragment as it sits in the main buffer or the shared pool.
///
/// Layout: the mask, then three 32-bit words that each hold a 24-bit depth
/// quantity and one 8-bit color channel: `z | r << 24`, `dzdx | g << 24`,
/// `dzdy | b << 24`. With a 16-bit mask this is the seed's 14-byte fragment;
/// see [`PackedFragment::SIZE`].
#[derive(Clone, Copy)]
#[repr(C, packed)]
pub struct PackedFragment<M: CoverageMask> {
    mask: M,
    z_red: u32,
    dzdx_green: u32,
    dzdy_blue: u32,
}

impl<M: CoverageMask> Default for PackedFragment<M> {
    fn default() -> Self {
        Self {
            mask: M::EMPTY,
            z_red: 0,
            dzdx_green: 0,
            dzdy_blue: 0,
        }
    }
}

impl<M: CoverageMask> core::fmt::Debug for PackedFragment<M> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        self.unpack().fmt(f)
    }
}

const LOW24: u32 = 0x00FF_FFFF;

#[inline]
fn sign_extend_24(v: u32) -> i32 {
    ((v << 8) as i32) >> 8
}

impl<M: CoverageMask> PackedFragment<M> {
    /// Bytes one stored fragment takes (`M_frag` of SPEC section 5).
    pub const SIZE: usize = core::mem::size_of::<Self>();

    /// An empty slot (for static initializers).
    pub const EMPTY: Self = Self {
        mask: M::EMPTY,
        z_red: 0,
        dzdx_green: 0,
        dzdy_blue: 0,
    };

    /// Packs a working fragment. A fragment's depth is within `0 ..= DEPTH_MAX`
    /// and its gradients within ±[`GRADIENT_LIMIT`] (the rasterizer keeps them
    /// there), and those pass unchanged; beyond, each is saturated as a signed
    /// 32-bit value, one instruction each on the Cortex-M4 (`usat`, `ssat`):
    /// depth to `0 ..= DEPTH_MAX` (a depth above `i32::MAX` counts as negative
    /// and packs as 0), gradients to 24 bits, `-2^23 ..= 2^23 - 1`.
    #[inline]
    pub fn pack(f: &Fragment<M>) -> Self {
        let z = (f.z as i32).clamp(0, DEPTH_MAX as i32) as u32;
        let dx = saturate_24(f.dzdx) as u32 & LOW24;
        let dy = saturate_24(f.dzdy) as u32 & LOW24;
        Self {
            mask: f.mask,
            z_red: z | (f.color.r() as u32) << 24,
            dzdx_green: dx | (f.color.g() as u32) << 24,
            dzdy_blue: dy | (f.color.b() as u32) << 24,
        }
    }

    /// Unpacks into the working form.
    #[inline]
    pub fn unpack(&self) -> Fragment<M> {
        let (zr, xg, yb) = (self.z_red, self.dzdx_green, self.dzdy_blue);
        Fragment {
            mask: self.mask,
            z: zr & LOW24,
            dzdx: sign_extend_24(xg),
            dzdy: sign_extend_24(yb),
            color: Rgb888::new((zr >> 24) as u8, (xg >> 24) as u8, (yb >> 24) as u8),
        }
    }

    /// The coverage mask.
    #[inline]
    pub fn mask(&self) -> M {
        self.mask
    }

    /// Replaces the coverage mask.
    #[inline]
    pub fn set_mask(&mut self, mask: M) {
        self.mask = mask;
    }

    /// The color channels, without unpacking the depth fields.
    #[inline]
    pub fn rgb(&self) -> [u8; 3] {
        let (zr, xg, yb) = (self.z_red, self.dzdx_green, self.dzdy_blue);
        [(zr >> 24) as u8, (xg >> 24) as u8, (yb >> 24) as u8]
    }

    /// The largest depth of the fragment's plane at any sample of the grid,
    /// times 16 ([`Fragment::depth_at`]'s scale), without unpacking.
    #[inline]
    pub fn farthest_sample_depth(&self) -> i32 {
        let (zr, xg, yb) = (self.z_red, self.dzdx_green, self.dzdy_blue);
        (((zr & LOW24) as i32) << 4)
            + sign_extend_24(xg).abs() * M::max_offset_x()
            + sign_extend_24(yb).abs() * M::max_offset_y()
    }

    /// Depth at the pixel center.
    #[inline]
    pub fn z(&self) -> u32 {
        self.z_red & LOW24
    }

    /// Depth change per pixel step in x.
    #[inline]
    pub fn dzdx(&self) -> i32 {
        sign_extend_24(self.dzdx_green)
    }

    /// Depth change per pixel step in y.
    #[inline]
    pub fn dzdy(&self) -> i32 {
        sign_extend_24(self.dzdy_blue)
    }

    /// The slot's link word while it sits on the pool's free list.
    #[inline]
    pub(crate) fn link(&self) -> u32 {
        self.z_red
    }

    /// Turns the slot into a free-list entry pointing at `next`.
    #[inline]
    pub(crate) fn set_link(&mut self, next: u32) {
        self.z_red = next;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coverage::{Mask4x4, Mask8x4, Mask8x8};

    #[test]
    fn packed_sizes() {
        assert_eq!(PackedFragment::<Mask4x4>::SIZE, 14);
        assert_eq!(PackedFragment::<Mask8x4>::SIZE, 16);
        assert_eq!(PackedFragment::<Mask8x8>::SIZE, 20);
    }

    #[test]
    fn pack_round_trip() {
        let f = Fragment {
            mask: Mask4x4(0xA5A5),
            z: DEPTH_MAX - 3,
            dzdx: -GRADIENT_LIMIT,
            dzdy: 12345,
            color: Rgb888::new(1, 128, 255),
        };
        assert_eq!(PackedFragment::pack(&f).unpack(), f);
        let g = Fragment {
            dzdx: i32::MAX,
            dzdy: i32::MIN,
            ..f
        };
        let u = PackedFragment::pack(&g).unpack();
        assert_eq!((u.dzdx, u.dzdy), (GRADIENT_LIMIT, -GRADIENT_LIMIT - 1));
        let deep = Fragment {
            z: DEPTH_MAX + 5,
            ..f
        };
        assert_eq!(PackedFragment::pack(&deep).unpack().z, DEPTH_MAX);
    }
}
