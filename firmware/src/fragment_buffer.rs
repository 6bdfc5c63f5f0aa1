//! The modified A-buffer: per-pixel fragment lists in a main buffer of fixed slots
//! plus pool addresses, a shared overflow pool, and merging when memory runs out
//! (SPEC sections 3 to 5).
//!
//! Each pixel owns `N_main` fragment slots and `N_extra` addresses into the
//! [`SharedPool`]. Its list is kept sorted by depth at the pixel center, nearest
//! first: list positions below `N_main` live in the pixel's own slots, the rest in
//! pool slots through the pixel's addresses. When a fragment arrives, visibility
//! masks settle every sample it shares with a stored fragment; fragments left with
//! no sample are removed and their pool slots freed at once. A survivor that finds
//! no room triggers the [`OverflowPolicy`].
//!
//! Storage is borrowed ([`BufferStorage`]): the firmware lends `static` arrays, the
//! host lends vectors. Nothing is allocated.

use core::marker::PhantomData;

use crate::band_buffer::{BandBuffer, PoolUse};
use crate::coverage::CoverageMask;
use crate::fragment::{Fragment, PackedFragment};
use crate::merge::merge_fragments;
use crate::pool::{PoolAddress, SharedPool};
use crate::sink::LinePixel;
use crate::stats::BufferStats;
use crate::visibility::visibility_against_plane;
use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};

/// What happens when a pixel must hold one fragment more than it may.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum OverflowPolicy {
    /// Merge the two fragments farthest from the viewer (the seed's method).
    MergeFarthest,
    /// Merge the two fragments adjacent in depth with the smallest depth difference
    /// (what Z3 does), for comparison.
    MergeClosest,
    /// Of the two farthest fragments, drop the one with smaller coverage (the
    /// farther one on a tie), as in the fixed-slot A-buffer the seed cites.
    Discard,
    /// Bounded memory without the pool's artifacts: when the shared pool runs
    /// out, the band is drawn again in halves (down to single rows, see
    /// [`BandBuffer::pool_use`]), so no pixel merges for want of pool
    /// slots (unless a single row needs more than the whole pool); a pixel
    /// whose own list is full merges its closest pair in depth, as
    /// [`OverflowPolicy::MergeClosest`]. The image does not depend on the
    /// pool size then, only on the slots per pixel.
    SplitBands,
}

impl OverflowPolicy {
    /// Whether the pool running out asks for the band to be drawn again in halves.
    pub const fn splits_bands(self) -> bool {
        matches!(self, Self::SplitBands)
    }
}

/// Sizes of a fragment buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BufferConfig {
    /// Pixels per row (`W`).
    pub width: u16,
    /// Rows per band (`R`).
    pub band_height: u16,
    /// Fragment slots per pixel in the main buffer (`N_main`, at least 1).
    pub main_slots: u8,
    /// Pool addresses per pixel (`N_extra`).
    pub extra_addresses: u8,
    /// Overflow handling.
    pub policy: OverflowPolicy,
}

impl BufferConfig {
    /// Pixels in a band, `W R`.
    pub const fn pixels(&self) -> usize {
        self.width as usize * self.band_height as usize
    }

    /// Length of the main fragment slot array: `W R N_main`.
    pub const fn main_slot_count(&self) -> usize {
        self.pixels() * self.main_slots as usize
    }

    /// Length of the pool address array: `W R N_extra`.
    pub const fn address_count(&self) -> usize {
        self.pixels() * self.extra_addresses as usize
    }

    /// Most fragments one pixel may hold, `N_main + N_extra`.
    pub const fn pixel_capacity(&self) -> usize {
        self.main_slots as usize + self.extra_addresses as usize
    }

    /// Bytes of the seed's `M_shared` formula for this configuration and pool size:
    /// `W R (N_main M_frag + N_extra M_addr) + N_pool M_frag`.
    pub const fn shared_bytes(
        &self,
        fragment_bytes: usize,
        address_bytes: usize,
        pool_slots: usize,
    ) -> usize {
        self.pixels()
            * (self.main_slots as usize * fragment_bytes
                + self.extra_addresses as usize * address_bytes)
            + pool_slots * fragment_bytes
    }
}

/// The memory a [`FragmentBuffer`] works in.
pub struct BufferStorage<'a, M: CoverageMask, A: PoolAddress> {
    /// Fragment count per pixel; length `W R`. At most `N_main + N_extra`, which
    /// [`FragmentBuffer::new`] keeps within 255.
    pub counts: &'a mut [u8],
    /// Main fragment slots; length `W R N_main`.
    pub main: &'a mut [PackedFragment<M>],
    /// Pool addresses; length `W R N_extra`.
    pub addresses: &'a mut [A],
    /// The shared pool's slots (`N_pool`, any length the address type can index).
    pub pool: &'a mut [PackedFragment<M>],
}

/// The row width and the slots per pixel of a [`FragmentBuffer`], as its
/// pixel loops see them: each is either a constant of the type or read
/// from the buffer's [`BufferConfig`] at run time.
///
/// [`ShapeOfConfig`] reads every size from the configuration (any shape, one
/// compiled copy). [`ConstShape`] fixes them, as the static memory of a
/// firmware does ([`crate::memory::FragmentMemory::buffer`]), and the
/// compiler folds the pixel index and the slot arithmetic (3.4 % fewer
/// instructions in a teapot frame on the Cortex-M4, `docs/m4-benchmark-history.md`).
/// The image and the statistics are the same bits either way;
/// [`FragmentBuffer::new`] refuses a configuration whose sizes differ from
/// the shape's constants.
pub trait BufferShape {
    /// Pixels per row (`W`), when fixed.
    const WIDTH: Option<usize>;
    /// Fragment slots per pixel in the main buffer (`N_main`), when fixed.
    const MAIN_SLOTS: Option<usize>;
    /// Pool addresses per pixel (`N_extra`), when fixed.
    const EXTRA_ADDRESSES: Option<usize>;

    /// Whether `config` has this shape's fixed sizes.
    fn admits(config: &BufferConfig) -> bool {
        Self::WIDTH.is_none_or(|w| w == config.width as usize)
            && Self::MAIN_SLOTS.is_none_or(|m| m == config.main_slots as usize)
            && Self::EXTRA_ADDRESSES.is_none_or(|e| e == config.extra_addresses as usize)
    }
}

/// The [`BufferShape`] read from the buffer's [`BufferConfig`] at run time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ShapeOfConfig;

impl BufferShape for ShapeOfConfig {
    const WIDTH: Option<usize> = None;
    const MAIN_SLOTS: Option<usize> = None;
    const EXTRA_ADDRESSES: Option<usize> = None;
}

/// A [`BufferShape`] fixed at compile time: `WIDTH` pixels per row, `MAIN`
/// main slots and `EXTRA` pool addresses per pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ConstShape<const WIDTH: usize, const MAIN: usize, const EXTRA: usize>;

impl<const WIDTH: usize, const MAIN: usize, const EXTRA: usize> BufferShape
    for ConstShape<WIDTH, MAIN, EXTRA>
{
    const WIDTH: Option<usize> = Some(WIDTH);
    const MAIN_SLOTS: Option<usize> = Some(MAIN);
    const EXTRA_ADDRESSES: Option<usize> = Some(EXTRA);
}

/// Why a fragment buffer could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BufferError {
    /// `main_slots` is zero.
    NoMainSlot,
    /// Width or band height is zero.
    EmptyBand,
    /// `N_main + N_extra` exceeds what a per-pixel count can hold (255).
    PixelCapacityTooLarge,
    /// A storage slice has the wrong length.
    StorageLength {
        /// Which slice: 0 counts, 1 main slots, 2 addresses.
        slice: u8,
        /// Length required.
        expected: usize,
        /// Length given.
        actual: usize,
    },
    /// The pool is larger than the address type can index.
    PoolTooLarge {
        /// Largest pool the address type can index.
        max: usize,
    },
    /// The configuration's width or slots per pixel differ from the
    /// buffer's [`BufferShape`] constants.
    ShapeMismatch,
}

impl core::fmt::Display for BufferError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::NoMainSlot => write!(f, "a pixel needs at least one main fragment slot"),
            Self::EmptyBand => write!(f, "band width and height must be at least 1"),
            Self::PixelCapacityTooLarge => write!(
                f,
                "main slots plus pool addresses per pixel must be at most 255"
            ),
            Self::StorageLength {
                slice,
                expected,
                actual,
            } => {
                let name = ["counts", "main slots", "pool addresses"][*slice as usize % 3];
                write!(f, "{name} storage has {actual} entries, needs {expected}")
            }
            Self::PoolTooLarge { max } => {
                write!(f, "pool larger than {max} slots cannot be addressed")
            }
            Self::ShapeMismatch => write!(
                f,
                "the configuration's width or slots per pixel differ from the buffer type's"
            ),
        }
    }
}

/// The A-buffer for one band: main buffer, pool addresses and shared pool,
/// of the sizes `config` gives; `S` says which of them are constants
/// ([`BufferShape`]).
pub struct FragmentBuffer<'a, M: CoverageMask, A: PoolAddress, S: BufferShape = ShapeOfConfig> {
    config: BufferConfig,
    shape: PhantomData<S>,
    counts: &'a mut [u8],
    main: &'a mut [PackedFragment<M>],
    addresses: &'a mut [A],
    pool: SharedPool<'a, M>,
    rows: u16,
    /// Whether an allocation from the pool failed in the current band.
    pool_ran_out: bool,
    stats: BufferStats,
    /// What the whole-band test of hidden triangles asks first
    /// ([`BandBuffer::hides_columns`]).
    strips: StripSummary,
}

/// Columns per strip of [`StripSummary`]: about a small triangle's width
/// (the teapot's back faces are skipped with 0.23 M fewer instructions a
/// frame than with strips of 8; strips of 2 gain nothing more).
const STRIP_WIDTH: usize = 4;
/// Strips kept: images up to 512 pixels wide (the summary lives in the
/// buffer itself, 6 bytes a strip; wider images are tested pixel by pixel).
const MAX_STRIPS: usize = 128;

/// Per strip of [`STRIP_WIDTH`] columns over the band's rows: how many of its pixels are
/// fully covered, and a bound on the farthest sample depth of any fragment
/// stored there in this band. Both only grow while a band is drawn: a
/// pixel's covered samples never shrink (merges keep the union of their
/// masks, hidden fragments leave only where another covers them), and the
/// bound keeps fragments that have left. So a strip whose pixels are all
/// covered and whose bound is nearer than a triangle's nearest sample hides
/// the triangle there, as [`BandBuffer::hides`] would say pixel by pixel.
/// Kept from the band after the frame's first question on ([`BandBuffer::hides_columns`]
/// is asked only about triangles facing away, which scenes that cull them
/// never draw: those pay nothing for it); not under
/// [`OverflowPolicy::Discard`], which drops coverage, nor for images wider
/// than 512 pixels.
struct StripSummary {
    /// Whether the current band keeps the summary (decided when it begins).
    kept: bool,
    /// Whether the summary may be kept at all.
    allowed: bool,
    /// Whether it has been asked for.
    asked: bool,
    full_pixels: [u16; MAX_STRIPS],
    farthest: [i32; MAX_STRIPS],
}

impl StripSummary {
    fn new(config: &BufferConfig) -> Self {
        Self {
            kept: false,
            allowed: config.policy != OverflowPolicy::Discard
                && config.width as usize <= MAX_STRIPS * STRIP_WIDTH,
            asked: false,
            full_pixels: [0; MAX_STRIPS],
            farthest: [i32::MIN; MAX_STRIPS],
        }
    }

    /// Starts a band `width` pixels wide at row `y0`. The band at row 0
    /// starts a frame, which forgets the earlier frames' questions: a frame
    /// does the same work however many were drawn before it.
    fn begin(&mut self, y0: u16, width: u16) {
        if y0 == 0 {
            self.asked = false;
        }
        self.kept = self.allowed && self.asked;
        if self.kept {
            let n = (width as usize).div_ceil(STRIP_WIDTH).min(MAX_STRIPS);
            self.full_pixels[..n].fill(0);
            self.farthest[..n].fill(i32::MIN);
        }
    }

    /// Notes a fragment stored (or merged) at column `x`.
    #[inline]
    fn stored<M: CoverageMask>(&mut self, x: usize, f: &PackedFragment<M>) {
        self.stored_farthest(x, f.farthest_sample_depth());
    }

    /// [`StripSummary::stored`] for a fragment not packed yet.
    #[inline]
    fn stored_fragment<M: CoverageMask>(&mut self, x: usize, f: &Fragment<M>) {
        self.stored_farthest(x, f.farthest_sample_depth());
    }

    /// The strip of column `x` of a band the summary is kept for (at most
    /// `MAX_STRIPS * STRIP_WIDTH` pixels wide, so `x / STRIP_WIDTH` is a
    /// strip). Taken modulo `MAX_STRIPS`, a power of two: the same strip,
    /// one bit-field extract and no bounds check in the insertion's first
    /// fragment path.
    #[inline(always)]
    fn strip_of(x: usize) -> usize {
        const _: () = assert!(MAX_STRIPS.is_power_of_two());
        (x / STRIP_WIDTH) % MAX_STRIPS
    }

    /// Notes a fragment whose farthest sample depth is `farthest` at column `x`.
    #[inline(always)]
    fn stored_farthest(&mut self, x: usize, farthest: i32) {
        if self.kept {
            let s = &mut self.farthest[Self::strip_of(x)];
            *s = (*s).max(farthest);
        }
    }

    /// Whether strip `s` of a band `width` pixels wide and `rows` rows tall
    /// hides a fragment whose nearest sample depth is at least `depth`: all
    /// its pixels covered, by fragments all nearer than `depth`. `s` is a
    /// strip of the band (the summary is kept only for bands it covers).
    #[inline(always)]
    fn hides(&self, s: usize, width: usize, rows: usize, depth: i64) -> bool {
        let columns = STRIP_WIDTH.min(width - s * STRIP_WIDTH);
        self.full_pixels[s] as usize == columns * rows && (self.farthest[s] as i64) < depth
    }

    /// Notes that a pixel at column `x` covered `before` and now covers
    /// `before | added`.
    #[inline]
    fn covered<M: CoverageMask>(&mut self, x: usize, before: M, added: M) {
        if self.kept && before != M::FULL && (before | added) == M::FULL {
            self.full_pixels[Self::strip_of(x)] += 1;
        }
    }
}

/// Where one list position of a pixel lives.
#[derive(Clone, Copy)]
enum Slot {
    Main(usize),
    Pool(usize),
}

impl<'a, M: CoverageMask, A: PoolAddress, S: BufferShape> FragmentBuffer<'a, M, A, S> {
    /// A buffer over `storage`, checked against `config`.
    pub fn new(
        config: BufferConfig,
        storage: BufferStorage<'a, M, A>,
    ) -> Result<Self, BufferError> {
        if config.main_slots == 0 {
            return Err(BufferError::NoMainSlot);
        }
        if config.width == 0 || config.band_height == 0 {
            return Err(BufferError::EmptyBand);
        }
        if config.pixel_capacity() > u8::MAX as usize {
            return Err(BufferError::PixelCapacityTooLarge);
        }
        if !S::admits(&config) {
            return Err(BufferError::ShapeMismatch);
        }
        let checks = [
            (0u8, config.pixels(), storage.counts.len()),
            (1, config.main_slot_count(), storage.main.len()),
            (2, config.address_count(), storage.addresses.len()),
        ];
        for (slice, expected, actual) in checks {
            if expected != actual {
                return Err(BufferError::StorageLength {
                    slice,
                    expected,
                    actual,
                });
            }
        }
        if storage.pool.len() > A::MAX_POOL {
            return Err(BufferError::PoolTooLarge { max: A::MAX_POOL });
        }
        storage.counts.fill(0);
        Ok(Self {
            config,
            shape: PhantomData,
            counts: storage.counts,
            main: storage.main,
            addresses: storage.addresses,
            pool: SharedPool::new(storage.pool),
            rows: config.band_height,
            pool_ran_out: false,
            stats: BufferStats::default(),
            strips: StripSummary::new(&config),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &BufferConfig {
        &self.config
    }

    /// The shared pool.
    pub fn pool(&self) -> &SharedPool<'a, M> {
        &self.pool
    }

    /// The fragments of pixel `(x, row)`, nearest first.
    pub fn fragments(&self, x: u16, row: u16) -> impl Iterator<Item = Fragment<M>> + '_ {
        let p = self.pixel_index(x, row);
        (0..self.counts[p] as usize).map(move |i| self.slot_ref(p, i).unpack())
    }

    #[inline]
    fn pixel_index(&self, x: u16, row: u16) -> usize {
        row as usize * self.width_px() + x as usize
    }

    /// Pixels per row (`W`).
    #[inline(always)]
    fn width_px(&self) -> usize {
        S::WIDTH.unwrap_or(self.config.width as usize)
    }

    /// Main slots per pixel (`N_main`).
    #[inline(always)]
    fn main_slots(&self) -> usize {
        S::MAIN_SLOTS.unwrap_or(self.config.main_slots as usize)
    }

    /// Pool addresses per pixel (`N_extra`).
    #[inline(always)]
    fn extra_addresses(&self) -> usize {
        S::EXTRA_ADDRESSES.unwrap_or(self.config.extra_addresses as usize)
    }

    /// Most fragments a pixel holds (`N_main + N_extra`).
    #[inline(always)]
    fn pixel_capacity(&self) -> usize {
        self.main_slots() + self.extra_addresses()
    }

    #[inline]
    fn locate(&self, p: usize, i: usize) -> Slot {
        let n_main = self.main_slots();
        if i < n_main {
            Slot::Main(p * n_main + i)
        } else {
            let a = self.addresses[p * self.extra_addresses() + (i - n_main)];
            Slot::Pool(a.index())
        }
    }

    /// Calls `visit` with each of pixel `p`'s `n` fragments, nearest first
    /// (its main slots, then the pool slots its addresses name), until it
    /// returns `true`; returns whether it did. Walking the slices directly
    /// spares the per-position lookup of [`Self::slot_ref`] on the hot paths.
    #[inline(always)]
    fn any_stored(
        &mut self,
        p: usize,
        n: usize,
        mut visit: impl FnMut(&mut PackedFragment<M>) -> bool,
    ) -> bool {
        let n_main = self.main_slots();
        let in_main = n.min(n_main);
        for f in &mut self.main[p * n_main..p * n_main + in_main] {
            if visit(f) {
                return true;
            }
        }
        if n > n_main {
            let n_extra = self.extra_addresses();
            let first = p * n_extra;
            for a in &self.addresses[first..first + (n - n_main)] {
                if visit(self.pool.get_mut(a.index())) {
                    return true;
                }
            }
        }
        false
    }

    #[inline]
    fn slot_ref(&self, p: usize, i: usize) -> &PackedFragment<M> {
        match self.locate(p, i) {
            Slot::Main(s) => &self.main[s],
            Slot::Pool(s) => self.pool.get(s),
        }
    }

    #[inline]
    fn slot_mut(&mut self, p: usize, i: usize) -> &mut PackedFragment<M> {
        match self.locate(p, i) {
            Slot::Main(s) => &mut self.main[s],
            Slot::Pool(s) => self.pool.get_mut(s),
        }
    }

    #[inline]
    fn read(&self, p: usize, i: usize) -> PackedFragment<M> {
        *self.slot_ref(p, i)
    }

    #[inline]
    fn write(&mut self, p: usize, i: usize, f: PackedFragment<M>) {
        *self.slot_mut(p, i) = f;
    }

    /// Moves list positions `from..to` one place later (position `to` is overwritten).
    #[inline(always)]
    fn shift_later(&mut self, p: usize, from: usize, to: usize) {
        let mut j = to;
        while j > from {
            let f = self.read(p, j - 1);
            self.write(p, j, f);
            j -= 1;
        }
    }

    /// Moves list positions `from+1..=to` one place earlier (position `from` is overwritten).
    fn shift_earlier(&mut self, p: usize, from: usize, to: usize) {
        for j in from..to {
            let f = self.read(p, j + 1);
            self.write(p, j, f);
        }
    }

    /// Removes fragments with empty masks from pixel `p`'s first `n` positions,
    /// frees the pool slots no longer needed, and returns the new count.
    fn compact(&mut self, p: usize, n: usize) -> usize {
        let mut kept = 0;
        for i in 0..n {
            let f = self.read(p, i);
            if !f.mask().is_empty() {
                if kept != i {
                    self.write(p, kept, f);
                }
                kept += 1;
            }
        }
        self.stats.fragments_removed_hidden += (n - kept) as u32;
        self.release_positions(p, kept, n);
        kept
    }

    /// Frees the pool slots behind list positions `from..to` of pixel `p`.
    fn release_positions(&mut self, p: usize, from: usize, to: usize) {
        let n_main = self.main_slots();
        for i in from.max(n_main)..to {
            let a = self.addresses[p * self.extra_addresses() + (i - n_main)];
            self.pool.release(a.index());
        }
    }

    /// Inserts `f` at list position `k` of pixel `p`, which holds `n` fragments and
    /// has room for one more (a pool slot is allocated when `n >= N_main`).
    fn insert_at(&mut self, p: usize, n: usize, k: usize, f: &Fragment<M>) -> bool {
        let n_main = self.main_slots();
        if n >= n_main {
            let Some(slot) = self.pool.allocate() else {
                self.pool_ran_out = true;
                return false;
            };
            self.addresses[p * self.extra_addresses() + (n - n_main)] = A::from_index(slot);
        }
        self.shift_later(p, k, n);
        let packed = PackedFragment::pack(f);
        self.write(p, k, packed);
        self.strips.stored_fragment(p % self.width_px(), f);
        true
    }

    /// Handles a survivor `f` (sorted position `k`) that finds pixel `p` full with
    /// `n >= 1` fragments. The list keeps `n` fragments.
    fn overflow(&mut self, p: usize, n: usize, k: usize, f: &Fragment<M>) {
        // The virtual list L has n + 1 entries: the stored ones with f at position k.
        match self.config.policy {
            OverflowPolicy::MergeFarthest => self.merge_pair(p, k, f, n - 1),
            OverflowPolicy::MergeClosest | OverflowPolicy::SplitBands => {
                let z_at = |s: &Self, i: usize| -> u32 {
                    if i < k {
                        s.slot_ref(p, i).z()
                    } else if i == k {
                        f.z
                    } else {
                        s.slot_ref(p, i - 1).z()
                    }
                };
                let mut best = n - 1;
                let mut best_gap = u32::MAX;
                let mut z = z_at(self, 0);
                for i in 0..n {
                    let next = z_at(self, i + 1);
                    if next - z <= best_gap {
                        best_gap = next - z;
                        best = i;
                    }
                    z = next;
                }
                self.merge_pair(p, k, f, best);
            }
            OverflowPolicy::Discard => {
                // The two farthest are L[n-1] and L[n]; drop the smaller coverage.
                let entry = |s: &Self, i: usize| {
                    if i == k {
                        *f
                    } else {
                        s.read(p, if i < k { i } else { i - 1 }).unpack()
                    }
                };
                let (near, far) = (entry(self, n - 1), entry(self, n));
                let drop = if far.mask.count() <= near.mask.count() {
                    n
                } else {
                    n - 1
                };
                self.stats.fragments_discarded += 1;
                if drop == k {
                    // Neither stored nor hidden: counted as generated here.
                    self.stats.fragments_generated += 1;
                    return;
                }
                let stored = if drop < k { drop } else { drop - 1 };
                self.shift_earlier(p, stored, n - 1);
                let k_after = if stored < k { k - 1 } else { k };
                self.shift_later(p, k_after, n - 1);
                self.write(p, k_after, PackedFragment::pack(f));
                self.stats.fragments_stored += 1;
            }
        }
    }

    /// The color of pixel `p`, which holds `n >= 1` fragments: each
    /// fragment's color weighted by its samples, the uncovered samples
    /// `background`, rounded to nearest. A pixel whose one fragment covers
    /// every sample (an interior pixel) is its color and is taken before
    /// the call ([`Self::resolve_row`]).
    #[inline(never)]
    fn resolve_pixel(&self, p: usize, n: usize, background: Rgb888) -> Rgb888 {
        let n_main = self.main_slots();
        // Red and blue share a word (blue from bit 16): a channel's sum is
        // at most 255 times the samples, below 2^16 on every grid.
        const { assert!(255 * M::SAMPLES + M::SAMPLES / 2 < 1 << 16) };
        let (mut red_blue, mut green, mut covered) = (0u32, 0u32, 0u32);
        let mut add = |f: &PackedFragment<M>| {
            let k = f.mask().count();
            let [fr, fg, fb] = f.rgb();
            red_blue += (fr as u32 | (fb as u32) << 16) * k;
            green += fg as u32 * k;
            covered += k;
        };
        // The pixel's main slots (an index loop: the slice's iterator cost
        // more set-up than the one to three entries a pixel holds), then the
        // pool slots its addresses name, over the addresses' slice, its
        // bounds checked once (indexed, the loop checked each address and
        // kept the pool's slice on the stack).
        let in_main = n.min(n_main);
        let main = p * n_main;
        // The first main slot outside the loop: the pixel holds a fragment
        // (the loop tested `n` for zero).
        add(&self.main[main]);
        for i in 1..in_main {
            add(&self.main[main + i]);
        }
        let n_extra = self.extra_addresses();
        for a in &self.addresses[p * n_extra..][..n - in_main] {
            add(self.pool.get(a.index()));
        }
        let rest = M::SAMPLES - covered.min(M::SAMPLES);
        let (half, shift) = (M::SAMPLES / 2, M::SAMPLES_LOG2);
        let background_red_blue = background.r() as u32 | (background.b() as u32) << 16;
        let red_blue = (red_blue + background_red_blue * rest + (half | half << 16)) >> shift;
        Rgb888::new(
            red_blue as u8,
            ((green + background.g() as u32 * rest + half) >> shift) as u8,
            (red_blue >> 16) as u8,
        )
    }

    /// Merges entries `i` and `i + 1` of the virtual list (stored fragments with `f`
    /// at position `k`) and writes the resulting entries back (the count is unchanged).
    fn merge_pair(&mut self, p: usize, k: usize, f: &Fragment<M>, i: usize) {
        let entry = |s: &Self, j: usize| {
            if j == k {
                *f
            } else {
                s.read(p, if j < k { j } else { j - 1 }).unpack()
            }
        };
        let merged = merge_fragments(&entry(self, i), &entry(self, i + 1));
        let merged = PackedFragment::pack(&merged);
        let column = p % self.width_px();
        self.strips.stored(column, &merged);
        self.strips.stored_fragment(column, f);
        if k <= i {
            // Stored k..i-1 move one later; the merged one lands at i; f at k (if k < i).
            self.shift_later(p, k, i.saturating_sub(1).max(k));
            self.write(p, i, merged);
            if k < i {
                self.write(p, k, PackedFragment::pack(f));
            }
        } else if k == i + 1 {
            self.write(p, i, merged);
        } else {
            // Stored i+2..k-1 move one earlier; f lands at k-1.
            self.write(p, i, merged);
            self.shift_earlier(p, i + 1, k - 1);
            self.write(p, k - 1, PackedFragment::pack(f));
        }
        self.stats.merges += 1;
        self.stats.fragments_stored += 1;
    }

    /// [`BandBuffer::survives`] for pixel `p`, which holds `count` fragments
    /// (at least one).
    #[inline(never)]
    fn survives_in_list(&mut self, p: usize, count: u8, fragment: &Fragment<M>) -> bool {
        let n = count as usize;
        let mut left = fragment.mask;
        let hidden = self.any_stored(p, n, |stored| {
            let overlap = stored.mask() & left;
            if !overlap.is_empty() {
                // Samples where the stored fragment is strictly nearer stay its own.
                let vis =
                    visibility_against_plane(fragment, stored.z(), stored.dzdx(), stored.dzdy());
                left = left & !(overlap & !vis);
            }
            left.is_empty()
        });
        if hidden {
            self.stats.fragments_hidden_on_arrival += 1;
            return false;
        }
        true
    }

    /// [`Self::insert_into_list`] for a pixel holding `N` fragments (one or
    /// two) none of whose samples `fragment` shares (at the edges between
    /// the triangles of a mesh, the commonest case): nothing to settle, the
    /// new one goes into depth order, and list position `N` takes a main
    /// slot or a pool slot. `false` (nothing done) when the samples overlap
    /// or no slot is left; the general path then decides.
    #[inline(always)]
    fn insert_beside<const N: usize>(&mut self, x: u16, p: usize, fragment: &Fragment<M>) -> bool {
        if fragment.mask.is_empty() || self.pixel_capacity() <= N {
            return false;
        }
        let stored: [PackedFragment<M>; N] = core::array::from_fn(|i| self.read(p, i));
        let covered = stored.iter().fold(M::EMPTY, |c, f| c | f.mask());
        if !(covered & fragment.mask).is_empty() {
            return false;
        }
        let n_main = self.main_slots();
        if N >= n_main {
            let Some(slot) = self.pool.allocate() else {
                return false;
            };
            self.addresses[p * self.extra_addresses() + (N - n_main)] = A::from_index(slot);
        }
        let packed = PackedFragment::pack(fragment);
        // After every stored fragment up to the first that lies farther (as
        // the sorted insertion places it); the ones from there move one
        // place later.
        let k = (0..N).find(|&i| stored[i].z() > fragment.z).unwrap_or(N);
        for i in (k..N).rev() {
            self.write(p, i + 1, stored[i]);
        }
        self.write(p, k, packed);
        self.strips.stored_fragment(x as usize, fragment);
        self.strips.covered(x as usize, covered, fragment.mask);
        self.counts[p] = N as u8 + 1;
        self.stats.fragments_stored += 1;
        self.stats.max_fragments_in_pixel = self.stats.max_fragments_in_pixel.max(N as u32 + 1);
        true
    }

    /// [`BandBuffer::insert`] into pixel `p` (column `x`) that already holds
    /// `count` fragments, the fragment given by its fields.
    // Fields, not a reference: for the reference the rasterizer's loops
    // (where `insert` is inlined) wrote every fragment to the stack, taken
    // this path or not (0.24 M instructions a teapot frame, 0.57 M on
    // `blob`).
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn insert_into_list(
        &mut self,
        x: u16,
        p: usize,
        count: u8,
        mask: M,
        z: u32,
        dzdx: i32,
        dzdy: i32,
        color: Rgb888,
    ) {
        let fragment = &Fragment {
            mask,
            z,
            dzdx,
            dzdy,
            color,
        };
        let mut n = count as usize;
        let beside = match n {
            1 => self.insert_beside::<1>(x, p, fragment),
            2 => self.insert_beside::<2>(x, p, fragment),
            _ => false,
        };
        if beside {
            return;
        }
        let mut f = *fragment;
        // Settle every shared sample with each stored fragment (their masks are
        // disjoint, so the order of comparison does not matter), and find the
        // sorted position on the way: after every stored fragment at the same or
        // nearer depth.
        let mut emptied = false;
        let mut k = n;
        let mut position = 0;
        // The samples the pixel covered before (complete unless the fragment
        // turns out hidden, which changes nothing).
        let mut covered = M::EMPTY;
        self.any_stored(p, n, |stored| {
            covered = covered | stored.mask();
            if k == n && stored.z() > f.z {
                k = position;
            }
            position += 1;
            let overlap = stored.mask() & f.mask;
            if overlap.is_empty() {
                return false;
            }
            let vis = visibility_against_plane(&f, stored.z(), stored.dzdx(), stored.dzdy());
            let b_mask = stored.mask() & !(overlap & vis);
            f.mask = f.mask & !(overlap & !vis);
            if b_mask != stored.mask() {
                stored.set_mask(b_mask);
                emptied |= b_mask.is_empty();
            }
            f.mask.is_empty()
        });
        if emptied {
            n = self.compact(p, n);
        }
        if f.mask.is_empty() {
            self.stats.fragments_hidden_on_arrival += 1;
            self.counts[p] = n as u8;
            return;
        }
        if emptied {
            // Removed fragments moved the later ones: find the position again.
            k = n;
            for i in 0..n {
                if self.slot_ref(p, i).z() > f.z {
                    k = i;
                    break;
                }
            }
        }
        if n < self.pixel_capacity() && self.insert_at(p, n, k, &f) {
            n += 1;
            self.stats.fragments_stored += 1;
        } else {
            self.overflow(p, n, k, &f);
        }
        // Stored or merged, the pixel now covers its old samples and the new ones.
        self.strips.covered(x as usize, covered, fragment.mask);
        self.counts[p] = n as u8;
        self.stats.max_fragments_in_pixel = self.stats.max_fragments_in_pixel.max(n as u32);
    }
}

impl<M: CoverageMask, A: PoolAddress, S: BufferShape> BandBuffer<M>
    for FragmentBuffer<'_, M, A, S>
{
    fn width(&self) -> u16 {
        self.config.width
    }

    fn band_height(&self) -> u16 {
        self.config.band_height
    }

    fn begin_band(&mut self, y0: u16, rows: u16) {
        self.rows = rows.min(self.config.band_height);
        let used = self.width_px() * self.rows as usize;
        crate::words::fill_bytes(&mut self.counts[..used], 0);
        // The pool's peak becomes the band's; the frame's is kept here.
        self.stats.pool_peak = self.stats.pool_peak.max(self.pool.peak() as u32);
        self.pool.reset();
        self.pool.clear_peak();
        self.pool_ran_out = false;
        self.strips.begin(y0, self.config.width);
    }

    fn pool_use(&self) -> PoolUse {
        PoolUse {
            ran_out: self.pool_ran_out && self.config.policy.splits_bands(),
            peak: self.pool.peak(),
            capacity: self.pool.capacity(),
        }
    }

    #[inline]
    fn hides(&mut self, x: u16, row: u16, depth: i64) -> bool {
        let (width, rows) = (self.width_px(), self.rows as usize);
        // A column of the image lies in a strip the kept summary covers.
        if self.strips.kept
            && (x as usize) < width
            && self
                .strips
                .hides(x as usize / STRIP_WIDTH, width, rows, depth)
        {
            return true;
        }
        let p = self.pixel_index(x, row);
        let n = self.counts[p] as usize;
        if n == 0 {
            return false;
        }
        let mut covered = M::EMPTY;
        let farther = self.any_stored(p, n, |f| {
            covered = covered | f.mask();
            // The farthest sample of the stored fragment's plane (below 2^29).
            f.farthest_sample_depth() as i64 >= depth
        });
        !farther && covered == M::FULL
    }

    fn hides_columns(&mut self, x0: u16, x1: u16, depth: i64) -> bool {
        self.strips.asked = true;
        if !self.strips.kept {
            return false;
        }
        let width = self.width_px();
        let rows = self.rows as usize;
        let last = (x1 as usize).min(width - 1) / STRIP_WIDTH;
        (x0 as usize / STRIP_WIDTH..=last).all(|s| self.strips.hides(s, width, rows, depth))
    }

    fn count_triangle_test(&mut self, pixels: u32, hidden: bool) {
        self.stats.culling_depth_tests += pixels;
        self.stats.triangles_culled += hidden as u32;
    }

    // Inlined into the probe: an empty pixel keeps every fragment; pixels
    // that hold some are asked out of line.
    #[inline]
    fn survives(&mut self, x: u16, row: u16, fragment: &Fragment<M>) -> bool {
        let p = self.pixel_index(x, row);
        let count = self.counts[p];
        count == 0 || self.survives_in_list(p, count, fragment)
    }

    // Inlined into the rasterizer: a pixel's first fragment (most of them) is
    // one store; the others take the out-of-line path.
    #[inline]
    fn insert(&mut self, x: u16, row: u16, fragment: &Fragment<M>) {
        let p = self.pixel_index(x, row);
        let count = self.counts[p];
        if count == 0 {
            // The first fragment of a pixel goes to its first main slot.
            let packed = PackedFragment::pack(fragment);
            self.main[p * self.main_slots()] = packed;
            self.strips.stored_fragment(x as usize, fragment);
            self.strips.covered(x as usize, M::EMPTY, fragment.mask);
            self.counts[p] = 1;
            // (A pixel holding one fragment is counted in `stats`.)
            self.stats.fragments_stored += 1;
            return;
        }
        self.insert_into_list(
            x,
            p,
            count,
            fragment.mask,
            fragment.z,
            fragment.dzdx,
            fragment.dzdy,
            fragment.color,
        );
    }

    // Out of line, as the z-buffer's: inlined into the frame loop, the
    // row's loop reloads what the registers there cannot hold.
    #[inline(never)]
    fn resolve_row<P: LinePixel>(&mut self, row: u16, background: Rgb888, out: &mut [P]) {
        let width = self.width_px();
        let start = row as usize * width;
        let shown = width.min(out.len());
        // The loop over the row stays small (background pixels are about half
        // of them, in runs: four counts are read as one word); covered
        // pixels are resolved out of line.
        let counts = &self.counts[start..start + shown];
        let out = &mut out[..shown];
        let n_main = self.main_slots();
        let empty = P::from_rgb888(background);
        let each = |s: &Self, x: usize, counts: &[u8], out: &mut [P]| {
            for (k, (px, &n)) in out.iter_mut().zip(counts).enumerate() {
                let p = start + x + k;
                // Each branch stores its own pixel (`set_rgb888`: a format
                // of bytes stores them one by one rather than packed).
                if n == 0 {
                    *px = empty;
                } else if n == 1 && s.main[p * n_main].mask() == M::FULL {
                    // An interior pixel: one fragment covers every sample.
                    let [r, g, b] = s.main[p * n_main].rgb();
                    px.set_rgb888(Rgb888::new(r, g, b));
                } else {
                    px.set_rgb888(s.resolve_pixel(p, n as usize, background));
                }
            }
        };
        // Background runs are filled whole (a format may store several
        // pixels at once), found four counts at a time.
        let quads = shown / 4;
        let quad_empty = |q: usize| {
            let four = &counts[4 * q..4 * q + 4];
            u32::from_ne_bytes([four[0], four[1], four[2], four[3]]) == 0
        };
        let mut q = 0;
        while q < quads {
            if quad_empty(q) {
                let first = q;
                while q < quads && quad_empty(q) {
                    q += 1;
                }
                P::fill(&mut out[4 * first..4 * q], empty);
            } else {
                each(
                    self,
                    4 * q,
                    &counts[4 * q..4 * q + 4],
                    &mut out[4 * q..4 * q + 4],
                );
                q += 1;
            }
        }
        let done = shown - shown % 4;
        each(self, done, &counts[done..], &mut out[done..]);
    }

    fn end_band(&mut self) {
        // The counts are cleared when the next band begins.
        self.pool.reset();
    }

    fn pixel_fragment_count(&self, x: u16, row: u16) -> u32 {
        self.counts[self.pixel_index(x, row)] as u32
    }

    fn stats(&self) -> BufferStats {
        // The pool keeps its own peak, so inserting needs not copy it; a
        // pixel's first fragment does not update the most in a pixel, which
        // is at least one once anything is stored. Every fragment offered is
        // stored (or merged), hidden on arrival, or (`Discard`) dropped on
        // arrival, which alone counts itself as generated: the sum is the
        // fragments generated, with no counter on the per-pixel paths.
        BufferStats {
            fragments_generated: self.stats.fragments_generated
                + self.stats.fragments_stored
                + self.stats.fragments_hidden_on_arrival,
            pool_peak: self.stats.pool_peak.max(self.pool.peak() as u32),
            max_fragments_in_pixel: self
                .stats
                .max_fragments_in_pixel
                .max((self.stats.fragments_stored > 0) as u32),
            ..self.stats
        }
    }

    #[inline]
    fn hidden_count(&self) -> u32 {
        self.stats.fragments_hidden_on_arrival + self.stats.triangles_culled
    }

    fn take_stats(&mut self) -> BufferStats {
        let s = self.stats();
        self.stats = BufferStats::default();
        self.pool.clear_peak();
        s
    }
}
