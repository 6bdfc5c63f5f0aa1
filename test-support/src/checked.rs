//! A band buffer wrapper that asserts the A-buffer's invariants as it goes.

use embedded_graphics_core::pixelcolor::Rgb888;
use mcu_abuffer::band_buffer::{BandBuffer, PoolUse};
use mcu_abuffer::coverage::{CoverageMask, Mask1x1};
use mcu_abuffer::draw_order::TriangleOrder;
use mcu_abuffer::fixed_point::DEPTH_MAX;
use mcu_abuffer::fragment::Fragment;
use mcu_abuffer::fragment_buffer::FragmentBuffer;
use mcu_abuffer::pool::PoolAddress;
use mcu_abuffer::sink::LinePixel;
use mcu_abuffer::stats::BufferStats;
use mcu_abuffer::zbuffer::ZBuffer;

/// What [`Checked`] reads of the buffer it wraps.
pub trait Inspect<M: CoverageMask>: BandBuffer<M> {
    /// The fragments pixel `(x, row)` stores, nearest first; `None` for a
    /// buffer that keeps no fragment lists (a z-buffer).
    fn stored(&self, x: u16, row: u16) -> Option<Vec<Fragment<M>>>;
    /// Most fragments a pixel may hold, and how many of those its own slots
    /// hold (the others take pool slots).
    fn pixel_slots(&self) -> (usize, usize);
    /// Shared pool slots in use, and in all (both 0 without a pool).
    fn pool_slots(&self) -> (usize, usize);
}

impl<M: CoverageMask, A: PoolAddress> Inspect<M> for FragmentBuffer<'_, M, A> {
    fn stored(&self, x: u16, row: u16) -> Option<Vec<Fragment<M>>> {
        Some(self.fragments(x, row).collect())
    }

    fn pixel_slots(&self) -> (usize, usize) {
        let config = self.config();
        (config.pixel_capacity(), config.main_slots as usize)
    }

    fn pool_slots(&self) -> (usize, usize) {
        (self.pool().in_use(), self.pool().capacity())
    }
}

impl Inspect<Mask1x1> for ZBuffer<'_> {
    fn stored(&self, _x: u16, _row: u16) -> Option<Vec<Fragment<Mask1x1>>> {
        None
    }

    fn pixel_slots(&self) -> (usize, usize) {
        (1, 1)
    }

    fn pool_slots(&self) -> (usize, usize) {
        (0, 0)
    }
}

/// Forwards to a band buffer and asserts, as the renderer drives it:
///
/// - bands are begun and ended in turn, with 1 to the band height rows, and
///   fragments, questions and resolved rows stay inside the open band;
/// - inserted fragments are non-empty, with a depth within `DEPTH_MAX`;
/// - after every insertion, in the pixel inserted into, and at the end of
///   every band, in every pixel: stored masks non-empty and pairwise
///   disjoint, lists sorted by depth, no pixel over its budget, the pixel's
///   count equal to its list's length, depths within `DEPTH_MAX`;
/// - at the end of every band, the pool holds exactly the slots the lists use;
///   the whole pool is free when a band begins and after it ends;
/// - asking whether a fragment survives changes no pixel.
///
/// It keeps `draw_triangle`'s default, so every fragment passes through it.
pub struct Checked<B> {
    inner: B,
    rows: u16,
    open: bool,
}

impl<B> Checked<B> {
    /// Checks `inner` from its next band on.
    pub fn new(inner: B) -> Self {
        Self {
            inner,
            rows: 0,
            open: false,
        }
    }

    /// The wrapped buffer.
    pub fn inner(&self) -> &B {
        &self.inner
    }

    /// Checks pixel `(x, row)` and returns how many pool slots it uses.
    fn check_pixel<M: CoverageMask>(&self, x: u16, row: u16) -> usize
    where
        B: Inspect<M>,
    {
        let Some(list) = self.inner.stored(x, row) else {
            return 0;
        };
        let (capacity, own) = self.inner.pixel_slots();
        assert!(
            list.len() <= capacity,
            "pixel ({x}, {row}) holds {} fragments, its budget is {capacity}",
            list.len()
        );
        assert_eq!(
            list.len() as u32,
            self.inner.pixel_fragment_count(x, row),
            "fragment count of pixel ({x}, {row})"
        );
        for (i, f) in list.iter().enumerate() {
            assert!(
                !f.mask.is_empty(),
                "pixel ({x}, {row}) stores an empty fragment"
            );
            assert!(
                f.z <= DEPTH_MAX,
                "pixel ({x}, {row}): depth {} out of range",
                f.z
            );
            for g in &list[i + 1..] {
                assert!(
                    (f.mask & g.mask).is_empty(),
                    "pixel ({x}, {row}): stored masks {:?} and {:?} overlap",
                    f.mask,
                    g.mask
                );
                assert!(f.z <= g.z, "pixel ({x}, {row}): list not sorted by depth");
            }
        }
        list.len().saturating_sub(own)
    }

    /// Checks every pixel of the open band and the pool's accounting.
    fn check_band<M: CoverageMask>(&self)
    where
        B: Inspect<M>,
    {
        let mut pool_slots = 0;
        for row in 0..self.rows {
            for x in 0..self.inner.width() {
                pool_slots += self.check_pixel(x, row);
            }
        }
        let (in_use, capacity) = self.inner.pool_slots();
        assert_eq!(
            in_use, pool_slots,
            "pool slots in use differ from the slots the pixels' lists hold"
        );
        assert!(in_use <= capacity);
    }

    /// Asserts that `(x, row)` is inside the open band.
    fn assert_in_band<M: CoverageMask>(&self, x: u16, row: u16)
    where
        B: Inspect<M>,
    {
        assert!(self.open, "pixel ({x}, {row}) asked outside a band");
        assert!(
            x < self.inner.width() && row < self.rows,
            "pixel ({x}, {row}) outside the {}x{} band",
            self.inner.width(),
            self.rows
        );
    }
}

impl<M: CoverageMask, B: Inspect<M>> BandBuffer<M> for Checked<B> {
    const ORDER: TriangleOrder = B::ORDER;

    fn width(&self) -> u16 {
        self.inner.width()
    }

    fn band_height(&self) -> u16 {
        self.inner.band_height()
    }

    fn begin_band(&mut self, y0: u16, rows: u16) {
        assert!(!self.open, "band begun twice");
        assert!(rows >= 1 && rows <= self.inner.band_height());
        self.inner.begin_band(y0, rows);
        assert_eq!(self.inner.pool_slots().0, 0, "pool not free at band start");
        self.rows = rows;
        self.open = true;
    }

    fn hides(&mut self, x: u16, row: u16, depth: i64) -> bool {
        self.assert_in_band(x, row);
        self.inner.hides(x, row, depth)
    }
    fn hidden_run(&mut self, row: u16, x0: u16, x1: u16, depth: i64) -> u32 {
        self.assert_in_band(x0, row);
        self.assert_in_band(x1, row);
        let run = self.inner.hidden_run(row, x0, x1, depth);
        // The run must be what asking pixel by pixel finds.
        let asked = (x0..=x1)
            .take_while(|&x| self.inner.hides(x, row, depth))
            .count() as u32;
        assert_eq!(
            run, asked,
            "hidden_run({row}, {x0}, {x1}, {depth}) differs from asking each pixel"
        );
        run
    }
    fn hides_columns(&mut self, x0: u16, x1: u16, depth: i64) -> bool {
        self.assert_in_band(x0, 0);
        self.assert_in_band(x1, 0);
        let hidden = self.inner.hides_columns(x0, x1, depth);
        if hidden {
            // The summary may only say what every pixel would say.
            for row in 0..self.rows {
                for x in x0..=x1 {
                    assert!(
                        self.inner.hides(x, row, depth),
                        "hides_columns({x0}, {x1}) holds but pixel ({x}, {row}) does not hide depth {depth}"
                    );
                }
            }
        }
        hidden
    }

    fn count_triangle_test(&mut self, pixels: u32, hidden: bool) {
        self.inner.count_triangle_test(pixels, hidden)
    }

    fn survives(&mut self, x: u16, row: u16, fragment: &Fragment<M>) -> bool {
        self.assert_in_band(x, row);
        let before = self.inner.stored(x, row);
        let survives = self.inner.survives(x, row, fragment);
        let after = self.inner.stored(x, row);
        assert_eq!(
            before, after,
            "asking whether a fragment survives changed the pixel"
        );
        survives
    }

    fn pool_use(&self) -> PoolUse {
        self.inner.pool_use()
    }

    fn insert(&mut self, x: u16, row: u16, fragment: &Fragment<M>) {
        self.assert_in_band(x, row);
        assert!(!fragment.mask.is_empty(), "empty fragment inserted");
        assert!(
            fragment.z <= DEPTH_MAX,
            "fragment depth {} out of range",
            fragment.z
        );
        self.inner.insert(x, row, fragment);
        self.check_pixel(x, row);
    }

    fn resolve_row<P: LinePixel>(&mut self, row: u16, background: Rgb888, out: &mut [P]) {
        assert!(
            self.open && row < self.rows,
            "row {row} resolved outside the band"
        );
        self.inner.resolve_row(row, background, out)
    }

    fn end_band(&mut self) {
        assert!(self.open, "band ended twice");
        self.check_band();
        self.inner.end_band();
        assert_eq!(self.inner.pool_slots().0, 0, "pool not free after the band");
        self.open = false;
    }

    fn pixel_fragment_count(&self, x: u16, row: u16) -> u32 {
        self.inner.pixel_fragment_count(x, row)
    }

    fn stats(&self) -> BufferStats {
        self.inner.stats()
    }

    fn hidden_count(&self) -> u32 {
        self.inner.hidden_count()
    }
    fn take_stats(&mut self) -> BufferStats {
        self.inner.take_stats()
    }
}
