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

    /// What [`CoverageMask::edge_coverage`] needs about one edge, prepared once
    /// per triangle by [`CoverageMask::edge_samples`].
    type EdgeSamples: Copy;
    /// Prepares the edge whose function grows by `a` per 1/16 pixel in x and by
    /// `b` in y (both at most 2^18 in magnitude).
    fn edge_samples(a: i32, b: i32) -> Self::EdgeSamples;
    /// The samples where the edge function is non-negative, given its value `e`
    /// at the pixel center (within the pixel's margin: below 2^22).
    fn edge_coverage(edge: &Self::EdgeSamples, e: i32) -> Self;
    /// [`CoverageMask::edge_coverage`] of an edge whose steps `a`, `b` are
    /// within `±2^15` ([`SHORT_STEP_LIMIT`]): the same samples, where the
    /// grid has a faster way for such edges.
    #[inline]
    fn edge_coverage_short(edge: &Self::EdgeSamples, e: i32) -> Self {
        Self::edge_coverage(edge, e)
    }
    /// [`CoverageMask::edge_coverage_short`] for a center value `e` below the
    /// edge's margin (`|a| max_offset_x + |b| max_offset_y`): some sample
    /// stays uncovered, which a grid may use to do less.
    #[inline]
    fn edge_coverage_short_partial(edge: &Self::EdgeSamples, e: i32) -> Self {
        Self::edge_coverage_short(edge, e)
    }

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

/// The samples of grid `M` where an edge function (value `e` at the pixel
/// center, steps `a` and `b` per 1/16 pixel) is non-negative, sample by sample.
// Out of line: inlined into a pixel loop, the compiler keeps every sample's edge
// value as its own induction variable, stepped (on the stack) at every pixel.
#[inline(never)]
pub fn edge_coverage_by_sample<M: CoverageMask>(e: i32, a: i32, b: i32) -> M {
    let mut row_value = e + a * M::offset_x(0) + b * M::offset_y(0);
    let step_x = a * (16 / M::COLS as i32);
    let step_y = b * (16 / M::ROWS as i32);
    let mut bits = 0u64;
    let mut bit = 0;
    for _ in 0..M::ROWS {
        let mut value = row_value;
        for _ in 0..M::COLS {
            bits |= ((value >= 0) as u64) << bit;
            bit += 1;
            value += step_x;
        }
        row_value += step_y;
    }
    M::from_u64(bits)
}

/// Exact 4x4 edge masks from sorted sample thresholds.
///
/// Sample `s` at offset `(ox, oy)` is covered when `e >= t_s` with
/// `t_s = -(a ox + b oy)`. Sorted by `t_s`, the covered samples are always a
/// prefix of the order: a binary search for how many thresholds are at most
/// `e` (four comparisons) and one table read give the mask. The order depends
/// only on the edge's direction: two samples swap places where `a ox + b oy`
/// ties, that is where `|b| / |a|` is 0, 1/3, 1/2, 2/3, 1 or their inverses,
/// which cuts the directions into 32 sectors with one order each (on a sector
/// boundary, the neighbouring sectors' orders are still sorted, ties side by
/// side). The tables are built at compile time from a direction inside each
/// sector; each threshold the search reads is `a ox + b oy` from the
/// sector's table of negated offsets, two multiplications (an edge keeps
/// only `a`, `b` and its sector: 12 bytes; with its 8 column and row
/// products, 36 bytes, the pixel loops reloaded them, 0.5 M more
/// instructions a teapot frame).
mod sorted_4x4 {
    #[cfg(any(arm_dual_multiply, test))]
    use crate::fixed_point::dual_mul_add;

    /// Sample offsets of the 4x4 grid in 1/16 pixel, per column (and per row).
    const OFFSETS: [i32; 4] = [-6, -2, 2, 6];

    /// The sector of direction `(a, b)` (not both zero).
    #[inline]
    pub(super) const fn sector(a: i32, b: i32) -> usize {
        let (ua, ub) = (a.unsigned_abs(), b.unsigned_abs());
        let swap = ub > ua;
        let (u, v) = if swap { (ub, ua) } else { (ua, ub) };
        let sub = (3 * v > u) as usize + (2 * v > u) as usize + (3 * v > 2 * u) as usize;
        (((b < 0) as usize) << 4) | (((a < 0) as usize) << 3) | ((swap as usize) << 2) | sub
    }

    /// A direction inside sector `s`.
    const fn representative(s: usize) -> (i32, i32) {
        let (u, v) = [(12, 2), (12, 5), (12, 7), (12, 10)][s & 3];
        let (a, b) = if s & 4 != 0 { (v, u) } else { (u, v) };
        (
            if s & 8 != 0 { -a } else { a },
            if s & 16 != 0 { -b } else { b },
        )
    }

    /// The threshold of sample `k` (`row * 4 + column`) for direction `(a, b)`.
    const fn threshold(a: i32, b: i32, k: u8) -> i32 {
        -(a * OFFSETS[(k & 3) as usize] + b * OFFSETS[(k >> 2) as usize])
    }

    /// Samples (`row * 4 + column`) of each sector by rising threshold.
    pub(super) const ORDER: [[u8; 16]; 32] = {
        let mut table = [[0u8; 16]; 32];
        let mut s = 0;
        while s < 32 {
            let (a, b) = representative(s);
            let mut order = [0u8; 16];
            let mut i = 0;
            while i < 16 {
                order[i] = i as u8;
                i += 1;
            }
            // Insertion sort by threshold -(a ox + b oy).
            let mut i = 1;
            while i < 16 {
                let mut j = i;
                while j > 0 && threshold(a, b, order[j - 1]) > threshold(a, b, order[j]) {
                    let x = order[j];
                    order[j] = order[j - 1];
                    order[j - 1] = x;
                    j -= 1;
                }
                i += 1;
            }
            table[s] = order;
            s += 1;
        }
        table
    };

    /// The masks of the first `k` samples of each sector's order, `k = 0..=16`.
    pub(super) const PREFIX: [[u16; 17]; 32] = {
        let mut table = [[0u16; 17]; 32];
        let mut s = 0;
        while s < 32 {
            let mut k = 0;
            while k < 16 {
                table[s][k + 1] = table[s][k] | 1 << ORDER[s][k];
                k += 1;
            }
            s += 1;
        }
        table
    };

    /// Each sector's sample offsets (x, then y, in 1/16 pixel) negated, in
    /// the order of rising threshold: the threshold of the `k`-th sample of
    /// sector `s` is `a x[k] + b y[k]` for `[x, y] = NEGATED_OFFSETS[s]`.
    const NEGATED_OFFSETS: [[[i8; 16]; 2]; 32] = {
        let mut table = [[[0i8; 16]; 2]; 32];
        let mut s = 0;
        while s < 32 {
            let mut k = 0;
            while k < 16 {
                let sample = ORDER[s][k];
                table[s][0][k] = -OFFSETS[(sample & 3) as usize] as i8;
                table[s][1][k] = -OFFSETS[(sample >> 2) as usize] as i8;
                k += 1;
            }
            s += 1;
        }
        table
    };

    /// One edge: its steps and its sector.
    #[derive(Clone, Copy, Debug)]
    pub struct Edge4x4 {
        a: i32,
        b: i32,
        /// `a` in the low half-word, `b` in the high one (both meaningful
        /// only for short steps, [`Edge4x4::mask_short`]).
        #[cfg(any(arm_dual_multiply, test))]
        steps: u32,
        sector: u8,
    }

    impl Edge4x4 {
        /// The edge with steps `a`, `b`.
        #[inline]
        pub fn new(a: i32, b: i32) -> Self {
            Self {
                a,
                b,
                #[cfg(any(arm_dual_multiply, test))]
                steps: (a as u32 & 0xffff) | (b as u32) << 16,
                sector: sector(a, b) as u8,
            }
        }

        /// The covered samples for center value `e`.
        #[inline]
        pub fn mask(&self, e: i32) -> u16 {
            let [xs, ys] = &NEGATED_OFFSETS[self.sector as usize & 31];
            // Masked indices: in range by construction, so no bounds checks.
            self.search::<true>(e, |k| {
                self.a * xs[k & 15] as i32 + self.b * ys[k & 15] as i32
            })
        }

        /// [`Edge4x4::mask`] for a center value `e` below the edge's margin
        /// `6 |a| + 6 |b|`. That margin is the largest threshold (the
        /// corner sample against the edge's direction), so the last
        /// threshold is above `e` and the search leaves out its test.
        #[inline]
        pub fn mask_partial(&self, e: i32) -> u16 {
            let [xs, ys] = &NEGATED_OFFSETS[self.sector as usize & 31];
            self.search::<false>(e, |k| {
                self.a * xs[k & 15] as i32 + self.b * ys[k & 15] as i32
            })
        }

        /// [`Edge4x4::mask_short`] for a center value `e` below the edge's
        /// margin, as [`Edge4x4::mask_partial`].
        #[inline]
        pub fn mask_short_partial(&self, e: i32) -> u16 {
            #[cfg(arm_dual_multiply)]
            {
                self.mask_packed_partial(e)
            }
            #[cfg(not(arm_dual_multiply))]
            {
                self.mask_partial(e)
            }
        }

        /// [`Edge4x4::mask`] for steps within `±2^15`: on the DSP extension
        /// (`arm_dual_multiply`) [`Edge4x4::mask_packed`], elsewhere the
        /// plain mask.
        #[inline]
        pub fn mask_short(&self, e: i32) -> u16 {
            #[cfg(arm_dual_multiply)]
            {
                self.mask_packed(e)
            }
            #[cfg(not(arm_dual_multiply))]
            {
                self.mask(e)
            }
        }

        /// [`Edge4x4::mask`] for steps within `±2^15`, each threshold from
        /// the steps and the sample's offsets packed in half-words: one load
        /// and one dual multiply-add ([`dual_mul_add`], `smuad`), where the
        /// plain threshold loads two offsets and multiplies twice. The same
        /// thresholds, so the same mask (each below `2 * 6 * 2^15` in
        /// magnitude: the sum fits).
        #[cfg(any(arm_dual_multiply, test))]
        #[inline]
        pub fn mask_packed(&self, e: i32) -> u16 {
            let offsets = &PACKED_OFFSETS[self.sector as usize & 31];
            self.search::<true>(e, |k| dual_mul_add(self.steps, offsets[k & 15]))
        }

        /// [`Edge4x4::mask_packed`] for a center value `e` below the edge's
        /// margin, as [`Edge4x4::mask_partial`].
        #[cfg(any(arm_dual_multiply, test))]
        #[inline]
        pub fn mask_packed_partial(&self, e: i32) -> u16 {
            let offsets = &PACKED_OFFSETS[self.sector as usize & 31];
            self.search::<false>(e, |k| dual_mul_add(self.steps, offsets[k & 15]))
        }

        /// The samples whose thresholds `threshold(k)` (rising with `k` in
        /// the sector's order) are at most `e`; without `CAN_COVER_ALL`,
        /// `e` is below the last threshold.
        #[inline(always)]
        fn search<const CAN_COVER_ALL: bool>(
            &self,
            e: i32,
            threshold: impl Fn(usize) -> i32,
        ) -> u16 {
            // How many thresholds are at most e: a binary search.
            let mut k = 0;
            if threshold(7) <= e {
                k = 8;
            }
            if threshold(k + 3) <= e {
                k += 4;
            }
            if threshold(k + 1) <= e {
                k += 2;
            }
            if threshold(k) <= e {
                k += 1;
            }
            if CAN_COVER_ALL && k == 15 && threshold(15) <= e {
                k = 16;
            }
            PREFIX[self.sector as usize & 31][k.min(16)]
        }
    }

    /// `NEGATED_OFFSETS` with each sample's x and y offsets packed in one
    /// word (x in the low half-word), as [`dual_mul_add`] takes them.
    #[cfg(any(arm_dual_multiply, test))]
    const PACKED_OFFSETS: [[u32; 16]; 32] = {
        let mut table = [[0u32; 16]; 32];
        let mut s = 0;
        while s < 32 {
            let mut k = 0;
            while k < 16 {
                let [xs, ys] = &NEGATED_OFFSETS[s];
                table[s][k] = (xs[k] as i32 as u32 & 0xffff) | (ys[k] as i32 as u32) << 16;
                k += 1;
            }
            s += 1;
        }
        table
    };
}

pub use sorted_4x4::Edge4x4;

/// The generic [`CoverageMask::EdgeSamples`]: the edge's steps.
#[derive(Clone, Copy, Debug)]
pub struct EdgeSteps {
    a: i32,
    b: i32,
}

macro_rules! edge_by_sample {
    () => {
        type EdgeSamples = EdgeSteps;
        #[inline]
        fn edge_samples(a: i32, b: i32) -> EdgeSteps {
            EdgeSteps { a, b }
        }
        #[inline]
        fn edge_coverage(edge: &EdgeSteps, e: i32) -> Self {
            edge_coverage_by_sample(e, edge.a, edge.b)
        }
    };
}

macro_rules! edge_by_table {
    () => {
        type EdgeSamples = Edge4x4;
        #[inline]
        fn edge_samples(a: i32, b: i32) -> Edge4x4 {
            Edge4x4::new(a, b)
        }
        #[inline]
        fn edge_coverage(edge: &Edge4x4, e: i32) -> Self {
            Self(edge.mask(e))
        }
        #[inline]
        fn edge_coverage_short(edge: &Edge4x4, e: i32) -> Self {
            Self(edge.mask_short(e))
        }
        #[inline]
        fn edge_coverage_short_partial(edge: &Edge4x4, e: i32) -> Self {
            Self(edge.mask_short_partial(e))
        }
    };
}

/// Bound (exclusive) on the magnitude of an edge's steps `a`, `b` for
/// [`CoverageMask::edge_coverage_short`]: they fit a signed half-word.
pub const SHORT_STEP_LIMIT: i32 = 1 << 15;

/// Set bits of each byte value.
const BYTE_BITS: [u8; 256] = {
    let mut table = [0u8; 256];
    let mut i = 0;
    while i < 256 {
        table[i] = (i as u32).count_ones() as u8;
        i += 1;
    }
    table
};

macro_rules! coverage_mask {
    ($(#[$doc:meta])* $name:ident, $bits:ty, $cols:expr, $rows:expr, $label:expr, $edge:ident) => {
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
                // Cortex-M has no population count: masks of up to 16 bits
                // take a table lookup per byte instead of the bit tricks.
                if <$bits>::BITS <= 16 {
                    let v = self.0 as u16;
                    (BYTE_BITS[(v & 0xFF) as usize] + BYTE_BITS[(v >> 8) as usize]) as u32
                } else {
                    self.0.count_ones()
                }
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

            $edge!();
        }
    };
}

coverage_mask!(
    /// 4 x 4 samples in 16 bits: the seed's "most common case".
    Mask4x4, u16, 4, 4, "4x4", edge_by_table
);
coverage_mask!(
    /// 8 columns x 4 rows in 32 bits (Carpenter's A-buffer grid).
    Mask8x4, u32, 8, 4, "8x4", edge_by_sample
);
coverage_mask!(
    /// 8 x 8 samples in 64 bits.
    Mask8x8, u64, 8, 8, "8x8", edge_by_sample
);
coverage_mask!(
    /// One sample at the pixel center: the plain z-buffer (no antialiasing).
    Mask1x1, u8, 1, 1, "1x1", edge_by_sample
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sorted_thresholds_equal_sample_by_sample() {
        let mut xorshift = crate::test_rng::xorshift(0x9E37_79B9_7F4A_7C15);
        let mut next = |range: i64| (xorshift() % (2 * range as u64 + 1)) as i64 - range;
        for round in 0..400_000 {
            // Small steps (exact ties are frequent), then any up to 2^18.
            let range = if round % 2 == 0 { 24 } else { 1 << 18 };
            let (a, b) = (next(range) as i32, next(range) as i32);
            if a == 0 && b == 0 {
                continue;
            }
            let margin = 6 * (a.abs() + b.abs());
            let e = next(margin as i64 + 2) as i32;
            let table = Edge4x4::new(a, b).mask(e);
            let direct = edge_coverage_by_sample::<Mask4x4>(e, a, b);
            assert_eq!(Mask4x4(table), direct, "a {a} b {b} e {e}");
        }
    }

    /// Calls `check(round, a, b, next)` for 400,000 random edges with
    /// short steps `a`, `b` (never both zero): small ones (exact ties) on
    /// even rounds, any short one on odd rounds, the limit's ends
    /// included; `next(r)` draws from `-r ..= r`.
    fn for_random_short_edges(
        seed: u64,
        mut check: impl FnMut(usize, i32, i32, &mut dyn FnMut(i64) -> i64),
    ) {
        let mut xorshift = crate::test_rng::xorshift(seed);
        let mut next = |range: i64| (xorshift() % (2 * range as u64 + 1)) as i64 - range;
        for round in 0..400_000 {
            let range = if round % 2 == 0 {
                24
            } else {
                SHORT_STEP_LIMIT as i64 - 1
            };
            let (a, b) = (next(range) as i32, next(range) as i32);
            if a == 0 && b == 0 {
                continue;
            }
            check(round, a, b, &mut next);
        }
    }

    #[test]
    fn packed_thresholds_equal_the_plain_ones() {
        for_random_short_edges(0x2545_F491_4F6C_DD1D, |_, a, b, next| {
            let margin = 6 * (a.abs() + b.abs());
            let e = next(margin as i64 + 2) as i32;
            let edge = Edge4x4::new(a, b);
            assert_eq!(edge.mask_packed(e), edge.mask(e), "a {a} b {b} e {e}");
            assert_eq!(edge.mask_short(e), edge.mask(e), "a {a} b {b} e {e}");
        });
        let edge = Edge4x4::new(-(SHORT_STEP_LIMIT - 1), SHORT_STEP_LIMIT - 1);
        for e in [-200_000, -1, 0, 1, 200_000] {
            assert_eq!(edge.mask_packed(e), edge.mask(e), "e {e}");
        }
    }

    #[test]
    fn partial_masks_equal_the_full_search_below_the_margin() {
        for_random_short_edges(0x94D0_49BB_1331_11EB, |round, a, b, next| {
            // Values up to just below the margin, the last ones below it
            // often.
            let margin = 6 * (a.abs() + b.abs());
            let e = if round % 4 < 2 {
                margin - 1 - (next(3).unsigned_abs() as i32)
            } else {
                (next(margin as i64 + 2) as i32).min(margin - 1)
            };
            let edge = Edge4x4::new(a, b);
            assert_ne!(edge.mask(e), u16::MAX, "a {a} b {b} e {e}");
            assert_eq!(edge.mask_partial(e), edge.mask(e), "a {a} b {b} e {e}");
            let packed = edge.mask_packed_partial(e);
            assert_eq!(packed, edge.mask(e), "a {a} b {b} e {e}");
            let short = edge.mask_short_partial(e);
            assert_eq!(short, edge.mask(e), "a {a} b {b} e {e}");
        });
    }

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
