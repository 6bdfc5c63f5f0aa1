//! Color planes carried from one band to the next.
//!
//! A triangle that reaches below its band is set up again in the next band
//! (its edges, box and depth are cheap), and so were its colors: the
//! lighting of its edge midpoints and the quadratic fit, about 3,000
//! instructions on the Cortex-M4 for a quadratic triangle. The planes
//! depend only on the triangle (its corners, its bounding box on screen and
//! its lighting), not on the band, so the frame driver keeps those of
//! triangles that go on below the band in a small table
//! ([`CarriedColors`] entries in the frame workspace) and the next band
//! takes them from there.
//!
//! The table is a ring: an entry is free once the band its triangle ends in
//! took it, or once its triangle ended above the band being drawn; when
//! every entry is still wanted, they are replaced in turn. A triangle not
//! found gets its planes computed again: the same bits, so the image never
//! depends on the table's size (an empty table carries nothing). Only
//! planes that cost much are worth the copies: quadratic surfaces are
//! carried; Gouraud planes cost less to set up than to copy twice, and
//! Phong shading (the reference) is not carried.

use crate::setup::{ColorPlanes, ColorSource, TriangleSetup};
use crate::shading::QuadraticPolynomial;

/// The key of an entry holding no triangle. Zero, so that a table of empty
/// entries is all zeros and a `static` one takes no flash for its image.
const NO_TRIANGLE: u32 = 0;

/// The key an entry of `triangle` holds: triangle numbers are
/// `object << 24 | triangle` with at most 255 objects, so one more never
/// wraps and never equals [`NO_TRIANGLE`].
#[inline]
fn key_of(triangle: u32) -> u32 {
    triangle + 1
}

/// One entry of the carried-colors table: a triangle's quadratic color
/// surfaces and the last image row it covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CarriedColors {
    polynomials: [QuadraticPolynomial; 3],
    /// [`key_of`] the triangle, or [`NO_TRIANGLE`].
    key: u32,
    last_row: u16,
    /// The polynomials walk in `i32` ([`ColorPlanes::NarrowQuadratic`]).
    narrow: bool,
}

impl CarriedColors {
    /// An entry holding nothing: the initial value of workspace arrays
    /// (`static` arrays included).
    pub const EMPTY: Self = Self {
        polynomials: [QuadraticPolynomial::ZERO; 3],
        key: NO_TRIANGLE,
        last_row: 0,
        narrow: false,
    };
}

impl Default for CarriedColors {
    fn default() -> Self {
        Self::EMPTY
    }
}

/// The carried-colors table of one frame, over the workspace's entries.
pub(crate) struct ColorCarry<'a> {
    entries: &'a mut [CarriedColors],
    /// The entry to replace next, in turn.
    next: usize,
    /// Planes taken from the table in this frame.
    pub(crate) carried: u32,
}

impl<'a> ColorCarry<'a> {
    /// An empty table over `entries` (what an earlier frame left there is
    /// forgotten: the vertices have moved).
    pub(crate) fn new(entries: &'a mut [CarriedColors]) -> Self {
        entries.fill(CarriedColors::EMPTY);
        Self {
            entries,
            next: 0,
            carried: 0,
        }
    }

    /// The color planes of `triangle`, set up as `setup`, drawn in the band
    /// of image rows `band_y0..band_end`: from the table when an earlier band
    /// kept them, else from `source` (quadratic surfaces are kept when the
    /// triangle goes on below the band). An entry taken by the band its
    /// triangle ends in is free again at once.
    #[inline]
    pub(crate) fn planes<'l>(
        &mut self,
        triangle: u32,
        setup: &TriangleSetup,
        band_y0: u16,
        band_end: u32,
        source: impl FnOnce() -> ColorSource<'l>,
    ) -> ColorPlanes {
        // Only a triangle that began above this band can have been kept.
        if setup.y0 < band_y0 {
            let key = key_of(triangle);
            if let Some(entry) = self.entries.iter_mut().find(|e| e.key == key) {
                self.carried += 1;
                if (entry.last_row as u32) < band_end {
                    entry.key = NO_TRIANGLE;
                }
                return if entry.narrow {
                    ColorPlanes::NarrowQuadratic(entry.polynomials)
                } else {
                    ColorPlanes::Quadratic(entry.polynomials)
                };
            }
        }
        let planes = setup.color_planes(source());
        if setup.y1 as u32 >= band_end {
            if let ColorPlanes::NarrowQuadratic(polynomials) = &planes {
                self.keep(triangle, setup.y1, band_y0, polynomials, true);
            } else if let ColorPlanes::Quadratic(polynomials) = &planes {
                self.keep(triangle, setup.y1, band_y0, polynomials, false);
            }
        }
        planes
    }

    /// Keeps the quadratic `polynomials` of `triangle` (`narrow`: they walk
    /// in `i32`), which goes on to row `last_row` below the band at `band_y0`.
    #[inline]
    fn keep(
        &mut self,
        triangle: u32,
        last_row: u16,
        band_y0: u16,
        polynomials: &[QuadraticPolynomial; 3],
        narrow: bool,
    ) {
        if let Some(slot) = self.slot_to_keep(band_y0) {
            self.entries[slot] = CarriedColors {
                polynomials: *polynomials,
                key: key_of(triangle),
                last_row,
                narrow,
            };
        }
    }

    /// The entry to keep new planes in (drawing the band at `band_y0`): the
    /// next in turn, or the first after it that is free or whose triangle
    /// ended above the band; `None` when the table has no entries.
    #[inline(never)]
    fn slot_to_keep(&mut self, band_y0: u16) -> Option<usize> {
        let n = self.entries.len();
        let mut slot = self.next;
        for _ in 0..n {
            let e = self.entries.get(slot)?;
            if e.key == NO_TRIANGLE || e.last_row < band_y0 {
                break;
            }
            slot = if slot + 1 == n { 0 } else { slot + 1 };
        }
        // When every entry is still wanted, `slot` is back at `next`: the
        // oldest kept is replaced.
        self.next = if slot + 1 >= n { 0 } else { slot + 1 };
        (slot < n).then_some(slot)
    }
}
