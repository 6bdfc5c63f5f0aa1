//! Coverage masks: one bit per sample of an `H x V` grid inside a pixel.
//!
//! Sample `(i, j)` (column `i`, row `j`) sits at offset
//! `((2i + 1 - H) / 2H, (2j + 1 - V) / 2V)` pixels from the pixel center and is bit
//! `j * H + i` of the mask. A triangle covers a sample when all three of its edge
//! functions say "inside" there (see [`crate::setup`]); the mask's popcount over
//! `H V` is the covered area.
//!
//! One trait, [`CoverageMask`], serves all grids; the renderer is generic over it.

use core::ops::{BitAnd, BitOr, Not};

/// A coverage mask for one pixel: a bit set over an `H x V` sample grid.
pub trait CoverageMask:
    Copy
    + Eq
    + Default
    + core::fmt::Debug
    + BitAnd<Output = Self>
    + BitOr<Output = Self>
    + Not<Output = Self>
    + 'static
{
    /// Sample columns (`H`).
    const COLS: u32;
    /// Sample rows (`V`).
    const ROWS: u32;
    /// Samples per pixel, `H V`.
    const SAMPLES: u32 = Self::COLS * Self::ROWS;
    /// log2 of [`Self::SAMPLES`] (sample counts are powers of two).
    const SAMPLES_LOG2: u32 = Self::SAMPLES.trailing_zeros();
    /// Human-readable grid name, such as `"4x4"`.
    const NAME: &'static str;
    /// The mask with no sample set.
    const EMPTY: Self;
    /// The mask with every sample set.
    const FULL: Self;

    /// Number of covered samples.
    fn count(self) -> u32;
    /// Whether sample `index` is set.
    fn get(self, index: u32) -> bool;
    /// Sets sample `index`.
    fn with(self, index: u32) -> Self;
    /// The raw bits, widened.
    fn to_u64(self) -> u64;
    /// A mask from raw bits (bits above `SAMPLES` are dropped).
    fn from_u64(bits: u64) -> Self;

    /// Whether no sample is set.
    #[inline]
    fn is_empty(self) -> bool {
        self == Self::EMPTY
    }

    /// Horizontal offset of sample column `i` from the pixel center, in 1/16 pixel.
    #[inline]
    fn offset_x(i: u32) -> i32 {
        (2 * i as i32 + 1 - Self::COLS as i32) * (8 / Self::COLS as i32)
    }

    /// Vertical offset of sample row `j` from the pixel center, in 1/16 pixel.
    #[inline]
    fn offset_y(j: u32) -> i32 {
        (2 * j as i32 + 1 - Self::ROWS as i32) * (8 / Self::ROWS as i32)
    }

    /// The largest `|offset_x|`, in 1/16 pixel.
    #[inline]
    fn max_offset_x() -> i32 {
        Self::offset_x(Self::COLS - 1)
    }

    /// The largest `|offset_y|`, in 1/16 pixel.
    #[inline]
    fn max_offset_y() -> i32 {
        Self::offset_y(Self::ROWS - 1)
    }
}

macro_rules! coverage_mask {
    ($(#[$doc:meta])* $name:ident, $bits:ty, $cols:expr, $rows:expr, $label:expr) => {
        $(#[$doc])*
        #[derive(Clone, Copy, PartialEq, Eq, Default, Hash)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        #[repr(transparent)]
        pub struct $name(pub $bits);

        impl core::fmt::Debug for $name {
            fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                write!(f, "{}({:#x})", stringify!($name), self.0)
            }
        }

        impl BitAnd for $name {
            type Output = Self;
            #[inline]
            fn bitand(self, rhs: Self) -> Self {
                Self(self.0 & rhs.0)
            }
        }

        impl BitOr for $name {
            type Output = Self;
            #[inline]
            fn bitor(self, rhs: Self) -> Self {
                Self(self.0 | rhs.0)
            }
        }

        impl Not for $name {
            type Output = Self;
            #[inline]
            fn not(self) -> Self {
                Self(!self.0 & Self::FULL.0)
            }
        }

        impl CoverageMask for $name {
            const COLS: u32 = $cols;
            const ROWS: u32 = $rows;
            const NAME: &'static str = $label;
            const EMPTY: Self = Self(0);
            const FULL: Self = Self(<$bits>::MAX >> (<$bits>::BITS - $cols * $rows));

            #[inline]
            fn count(self) -> u32 {
                self.0.count_ones()
            }
            #[inline]
            fn get(self, index: u32) -> bool {
                (self.0 >> index) & 1 != 0
            }
            #[inline]
            fn with(self, index: u32) -> Self {
                Self(self.0 | (1 << index))
            }
            #[inline]
            fn to_u64(self) -> u64 {
                self.0 as u64
            }
            #[inline]
            fn from_u64(bits: u64) -> Self {
                Self(bits as $bits & Self::FULL.0)
            }
        }
    };
}

coverage_mask!(
    /// 4 x 4 samples in 16 bits: the seed's "most common case".
    Mask4x4, u16, 4, 4, "4x4"
);
coverage_mask!(
    /// 8 columns x 4 rows in 32 bits (Carpenter's A-buffer grid).
    Mask8x4, u32, 8, 4, "8x4"
);
coverage_mask!(
    /// 8 x 8 samples in 64 bits.
    Mask8x8, u64, 8, 8, "8x8"
);
coverage_mask!(
    /// One sample at the pixel center: the plain z-buffer (no antialiasing).
    Mask1x1, u8, 1, 1, "1x1"
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_are_centered_and_odd() {
        fn check<M: CoverageMask>() {
            let sum: i32 = (0..M::COLS).map(M::offset_x).sum();
            assert_eq!(sum, 0);
            let sum: i32 = (0..M::ROWS).map(M::offset_y).sum();
            assert_eq!(sum, 0);
            // Offset (2i+1-H)/2H pixels expressed in 1/16 pixel.
            for i in 0..M::COLS {
                let exact = (2.0 * i as f64 + 1.0 - M::COLS as f64) / (2.0 * M::COLS as f64);
                assert_eq!(M::offset_x(i) as f64 / 16.0, exact);
            }
            assert_eq!(M::FULL.count(), M::SAMPLES);
            assert_eq!(!M::EMPTY, M::FULL);
        }
        check::<Mask4x4>();
        check::<Mask8x4>();
        check::<Mask8x8>();
        check::<Mask1x1>();
        assert_eq!(Mask8x4::max_offset_x(), 7);
        assert_eq!(Mask8x4::max_offset_y(), 6);
        assert_eq!(Mask1x1::offset_x(0), 0);
    }
}
