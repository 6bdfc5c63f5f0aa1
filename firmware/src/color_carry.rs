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
//! An entry is free once the band its triangle ends in took it, or once its
//! triangle ended above the band being drawn. New planes take the next free
//! entry in turn; when none is free they are not kept, and the entries
//! stay with the planes kept earlier (replacing those in turn would lose
//! each one before the next band asks for it whenever more triangles go on
//! than the table holds). A triangle not found gets its planes computed
//! again: the same bits, so the image never depends on the table's size
//! (an empty table carries nothing). Only planes that cost much are worth
//! the copies: those of quadratic shading, that is the quadratic surfaces
//! and the linear planes that replace them where the lit samples lie on a
//! plane (both paid for the lighting of the midpoints). Gouraud planes cost
//! less to set up than to copy twice, and Phong shading (the reference) is
//! not carried.
//!
//! An entry holds nine 64-bit words: three linear planes, or the three
//! polynomials of a quadratic that walks in `i32` (each coefficient a
//! multiple of `2^8` below `2^39` in magnitude, kept as the 32 bits above
//! its 8 low ones, two to a word). A wider quadratic takes two entries,
//! each naming the other. The search for a triangle starts after the entry
//! found last: the next band asks in about the order this one kept.

use crate::setup::Plane;

use crate::shading::quadratic::{QuadraticPolynomial, NARROW_QUADRATIC_DROPPED_BITS};
use crate::shading::ColorPlanes;

/// The key of an entry holding no triangle. Zero, so that a table of empty
/// entries is all zeros and a `static` one takes no flash for its image.
const NO_TRIANGLE: u32 = 0;

/// The key an entry of `triangle` holds: triangle numbers are the frame's
/// order entries, whose bit 30 is always zero (`draw_order`), so one more
/// never wraps and never equals [`NO_TRIANGLE`].
#[inline]
fn key_of(triangle: u32) -> u32 {
    triangle + 1
}

/// Words of color planes in one entry.
const ENTRY_WORDS: usize = 9;

/// What an entry holds (zero, the first, in an empty entry).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
enum Held {
    /// [`ColorPlanes::Linear`]: per channel the origin, `dx` and `dy` of its
    /// plane.
    Linear = 0,
    /// [`ColorPlanes::NarrowQuadratic`]: the 18 coefficients (per channel
    /// `a` to `f`), two to a word, each shifted down by
    /// [`NARROW_QUADRATIC_DROPPED_BITS`] into 32 bits (the first low).
    NarrowQuadratic = 1,
    /// [`ColorPlanes::Quadratic`]: the first 9 of its 18 coefficients; its
    /// partner entry holds the rest.
    Quadratic = 2,
    /// The second entry of a [`Held::Quadratic`] (never found by itself).
    QuadraticRest = 3,
}

/// One entry of the carried-colors table: color planes of a triangle (or
/// half of a large quadratic's) and the last image row it covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CarriedColors {
    words: [i64; ENTRY_WORDS],
    /// [`key_of`] the triangle, or [`NO_TRIANGLE`].
    key: u32,
    last_row: u16,
    held: Held,
    /// The other entry of a two-entry quadratic (this entry's own index
    /// otherwise).
    partner: u8,
}

impl CarriedColors {
    /// An entry holding nothing: the initial value of workspace arrays
    /// (`static` arrays included).
    pub const EMPTY: Self = Self {
        words: [0; ENTRY_WORDS],
        key: NO_TRIANGLE,
        last_row: 0,
        held: Held::Linear,
        partner: 0,
    };

    /// Whether the entry can take new planes while the band at `band_y0`
    /// is drawn: it holds nothing, or a triangle that ended above the band.
    #[inline]
    fn is_free(&self, band_y0: u16) -> bool {
        self.key == NO_TRIANGLE || self.last_row < band_y0
    }
}

impl Default for CarriedColors {
    fn default() -> Self {
        Self::EMPTY
    }
}

/// Coefficient `j` (`a` to `f`, channel after channel) of `p`.
#[inline(always)]
fn coefficient(p: &[QuadraticPolynomial; 3], j: usize) -> i64 {
    p[j / 6].coefficients()[j % 6]
}

/// The polynomials whose coefficient `j` (as [`coefficient`] counts them)
/// is `k(j)`.
#[inline(always)]
fn polynomials(k: impl Fn(usize) -> i64) -> [QuadraticPolynomial; 3] {
    core::array::from_fn(|c| {
        QuadraticPolynomial::from_coefficients(core::array::from_fn(|j| k(6 * c + j)))
    })
}

/// The color planes an entry holding `held` keeps in `first` (and, for a
/// [`Held::Quadratic`], its partner entry's, `rest`).
#[inline(always)]
fn load(held: Held, first: &[i64; ENTRY_WORDS], rest: &[i64; ENTRY_WORDS]) -> ColorPlanes {
    match held {
        Held::Linear => ColorPlanes::Linear(core::array::from_fn(|c| Plane {
            origin: first[3 * c],
            dx: first[3 * c + 1],
            dy: first[3 * c + 2],
        })),
        Held::NarrowQuadratic => ColorPlanes::NarrowQuadratic(polynomials(|j| {
            let half = (first[j / 2] >> (32 * (j % 2))) as i32;
            (half as i64) << NARROW_QUADRATIC_DROPPED_BITS
        })),
        Held::Quadratic | Held::QuadraticRest => ColorPlanes::Quadratic(polynomials(|j| {
            if j < ENTRY_WORDS {
                first[j]
            } else {
                rest[j - ENTRY_WORDS]
            }
        })),
    }
}

/// The carried-colors table of one frame, over the workspace's entries (at
/// most [`MAX_ENTRIES`] of them are used).
pub(crate) struct ColorCarry<'a> {
    entries: &'a mut [CarriedColors],
    /// Where the search for a free entry starts: after the entry taken last.
    next: usize,
    /// Where the search for a triangle starts: after the entry found last.
    cursor: usize,
    /// The band (its first row) in which no free entry was left, until an
    /// entry is freed: the search is not repeated there.
    full_in_band: Option<u16>,
    /// Planes taken from the table in this frame.
    pub(crate) carried: u32,
}

/// Entries a table uses at most: an entry names its partner in one byte.
pub const MAX_ENTRIES: usize = 256;

impl<'a> ColorCarry<'a> {
    /// An empty table over `entries` (what an earlier frame left there is
    /// forgotten: the vertices have moved).
    pub(crate) fn new(entries: &'a mut [CarriedColors]) -> Self {
        let used = entries.len().min(MAX_ENTRIES);
        let entries = &mut entries[..used];
        entries.fill(CarriedColors::EMPTY);
        Self {
            entries,
            next: 0,
            cursor: 0,
            full_in_band: None,
            carried: 0,
        }
    }

    /// The color planes of `triangle`, whose bounding box covers image rows
    /// `first_row..=last_row`, drawn in the band of rows
    /// `band_y0..band_end`: from the table when an earlier band kept them,
    /// else from `set_up` (kept when worth carrying and the triangle goes on
    /// below the band). An entry taken by the band its triangle ends in is
    /// free again at once.
    #[inline]
    pub(crate) fn planes(
        &mut self,
        triangle: u32,
        (first_row, last_row): (u16, u16),
        band_y0: u16,
        band_end: u32,
        set_up: impl FnOnce() -> ColorPlanes,
    ) -> ColorPlanes {
        // Only a triangle that began above this band can have been kept.
        if first_row < band_y0 {
            if let Some(i) = self.find(key_of(triangle)) {
                self.carried += 1;
                self.cursor = i + 1;
                let first = &self.entries[i];
                let rest = first.partner as usize;
                if (first.last_row as u32) < band_end {
                    // The band the triangle ends in: its entries are free.
                    self.full_in_band = None;
                    self.entries[i].key = NO_TRIANGLE;
                    if let Some(e) = self.entries.get_mut(rest) {
                        e.key = NO_TRIANGLE;
                    }
                }
                return self.read(i);
            }
        }
        if (last_row as u32) < band_end {
            // Its last band: nothing to keep (and the planes go straight
            // to the caller, with no copy).
            return set_up();
        }
        let planes = set_up();
        let key = key_of(triangle);
        let kept = match &planes {
            ColorPlanes::Linear(p) => self.keep(key, last_row, band_y0, false, |first, _| {
                *first = core::array::from_fn(|i| {
                    let plane = &p[i / 3];
                    [plane.origin, plane.dx, plane.dy][i % 3]
                });
                Held::Linear
            }),
            ColorPlanes::NarrowQuadratic(p) => {
                self.keep(key, last_row, band_y0, false, |first, _| {
                    // Exact: a polynomial that walks in `i32` has its
                    // dropped bits zero and each coefficient below 2^39 in
                    // magnitude (its bound over the box counts each one at
                    // least once).
                    let word =
                        |j: usize| (coefficient(p, j) >> NARROW_QUADRATIC_DROPPED_BITS) as u32;
                    *first = core::array::from_fn(|i| {
                        (word(2 * i) as u64 | (word(2 * i + 1) as u64) << 32) as i64
                    });
                    Held::NarrowQuadratic
                })
            }
            ColorPlanes::Quadratic(p) => self.keep(key, last_row, band_y0, true, |first, rest| {
                *first = core::array::from_fn(|i| coefficient(p, i));
                if let Some(rest) = rest {
                    *rest = core::array::from_fn(|i| coefficient(p, ENTRY_WORDS + i));
                }
                Held::Quadratic
            }),
            ColorPlanes::Constant(_) | ColorPlanes::Phong(_) => None,
        };
        // Kept planes are read back from their entries (exactly the same
        // planes): that costs fewer instructions than a copy of `planes`.
        match kept {
            Some(i) => self.read(i),
            None => planes,
        }
    }

    /// The planes held by entry `i` (the first of its triangle's entries).
    #[inline(always)]
    fn read(&self, i: usize) -> ColorPlanes {
        let first = &self.entries[i];
        let rest = self.entries.get(first.partner as usize).unwrap_or(first);
        load(first.held, &first.words, &rest.words)
    }

    /// The entry holding (the first part of) the planes kept under `key`,
    /// searched from after the entry found last.
    #[inline(always)]
    fn find(&self, key: u32) -> Option<usize> {
        let found = |e: &CarriedColors| e.key == key && e.held != Held::QuadraticRest;
        let cursor = self.cursor.min(self.entries.len());
        let (before, after) = self.entries.split_at(cursor);
        match after.iter().position(found) {
            Some(i) => Some(cursor + i),
            None => before.iter().position(found),
        }
    }

    /// Keeps planes of the triangle with `key`, which goes on to row
    /// `last_row` below the band at `band_y0`, in one entry or (`two`) in
    /// two: `store` writes them (into the first entry's words and, when
    /// there are two, the second's) and says what the first holds. Returns
    /// the first entry, or `None` when nothing was kept.
    #[inline(always)]
    fn keep(
        &mut self,
        key: u32,
        last_row: u16,
        band_y0: u16,
        two: bool,
        store: impl FnOnce(&mut [i64; ENTRY_WORDS], Option<&mut [i64; ENTRY_WORDS]>) -> Held,
    ) -> Option<usize> {
        // Only free entries are written: their triangles ended above the
        // band (no band asks for them again) or they hold nothing, so no
        // planes anyone asks for lose an entry.
        let first = self.free_entry(band_y0)?;
        // An entry names itself as its partner when it holds everything.
        let mut rest = first;
        if two {
            // Taken for now, so that the search passes over it.
            self.entries[first].key = key;
            self.entries[first].last_row = last_row;
            let Some(second) = self.free_entry(band_y0) else {
                self.entries[first].key = NO_TRIANGLE;
                return None;
            };
            rest = second;
        }
        let label = |e: &mut CarriedColors, held: Held, partner: usize| {
            e.held = held;
            e.key = key;
            e.last_row = last_row;
            e.partner = partner as u8;
        };
        if two {
            // Two distinct entries within the table (from `free_entry`).
            let Ok([a, b]) = self.entries.get_disjoint_mut([first, rest]) else {
                self.entries[first].key = NO_TRIANGLE;
                return None;
            };
            let held = store(&mut a.words, Some(&mut b.words));
            label(a, held, rest);
            label(b, Held::QuadraticRest, first);
        } else {
            let e = &mut self.entries[first];
            let held = store(&mut e.words, None);
            label(e, held, first);
        }
        Some(first)
    }

    /// A free entry to keep new planes in (drawing the band at
    /// `band_y0`): the first from the one after the entry taken last, in
    /// turn; `None` when there is none. Planes already kept stay when the
    /// table is full: replacing them in turn would lose every one before
    /// the next band asks, when more triangles go on than the table holds.
    #[inline(never)]
    fn free_entry(&mut self, band_y0: u16) -> Option<usize> {
        if self.full_in_band == Some(band_y0) {
            return None;
        }
        let next = self.next.min(self.entries.len());
        let (before, after) = self.entries.split_at(next);
        let free = |e: &CarriedColors| e.is_free(band_y0);
        let Some(i) = after
            .iter()
            .position(free)
            .map(|i| next + i)
            .or_else(|| before.iter().position(free))
        else {
            self.full_in_band = Some(band_y0);
            return None;
        };
        self.next = i + 1;
        Some(i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::cell::Cell;
    use embedded_graphics_core::pixelcolor::Rgb888;

    /// A xorshift generator.
    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }
        fn below(&mut self, n: u64) -> u64 {
            self.next() % n
        }
    }

    /// Planes that depend only on `triangle` (each kind in turn): what a
    /// setup would compute for it every time.
    fn planes_of(triangle: u32) -> ColorPlanes {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15 ^ ((triangle as u64 + 1) * 0x2545_f491));
        let mut wide = || rng.next() as i64;
        let polynomial = |k: &mut dyn FnMut() -> i64| QuadraticPolynomial {
            a: k(),
            b: k(),
            c: k(),
            d: k(),
            e: k(),
            f: k(),
        };
        match triangle % 5 {
            0 => ColorPlanes::Linear(core::array::from_fn(|_| Plane {
                origin: wide(),
                dx: wide(),
                dy: wide(),
            })),
            1 => {
                // Multiples of 2^8 within ±2^39, both ends included.
                let mut narrow = || {
                    let k = (wide() >> 24) & !0xff;
                    match k & 0x300 {
                        0x100 => -(1 << 39),
                        0x200 => (1 << 39) - 256,
                        _ => k,
                    }
                };
                ColorPlanes::NarrowQuadratic(core::array::from_fn(|_| polynomial(&mut narrow)))
            }
            2 => ColorPlanes::Quadratic(core::array::from_fn(|_| polynomial(&mut wide))),
            3 => ColorPlanes::Constant(Rgb888::new(triangle as u8, 7, 9)),
            _ => ColorPlanes::Quadratic(core::array::from_fn(|_| polynomial(&mut wide))),
        }
    }

    #[test]
    fn every_kind_comes_back_bit_for_bit() {
        let mut entries = [CarriedColors::EMPTY; 4];
        let mut carry = ColorCarry::new(&mut entries);
        for t in 0..5 {
            let kept = !matches!(planes_of(t), ColorPlanes::Constant(_));
            let rows = (2, 15);
            let set_ups = Cell::new(0);
            let mut ask = |band_y0: u16| {
                carry.planes(t, rows, band_y0, band_y0 as u32 + 6, || {
                    set_ups.set(set_ups.get() + 1);
                    planes_of(t)
                })
            };
            // Set up in its first band, taken in the next and in the one it
            // ends in (which frees the entries), set up again after that.
            for band_y0 in [0, 6, 12, 12] {
                assert_eq!(ask(band_y0), planes_of(t), "triangle {t}");
            }
            assert_eq!(set_ups.get(), if kept { 2 } else { 4 }, "triangle {t}");
        }
        assert_eq!(carry.carried, 8);
    }

    #[test]
    fn full_tables_never_give_other_planes() {
        // Random frames over tables of 0 to 7 entries: whatever is kept,
        // replaced or forgotten, the planes asked for are the triangle's.
        let mut rng = Rng(0x0123_4567_89ab_cdef);
        let mut carried = 0;
        for frame in 0..400 {
            let n = frame % 8;
            let mut entries = [CarriedColors::EMPTY; 7];
            let mut carry = ColorCarry::new(&mut entries[..n]);
            let triangles: [(u32, (u16, u16)); 40] = core::array::from_fn(|i| {
                let first = rng.below(200) as u16;
                (
                    i as u32 * 3 + frame as u32,
                    (first, first + rng.below(40) as u16),
                )
            });
            for band_y0 in (0..240).step_by(6) {
                let band_end = band_y0 as u32 + 6;
                for _ in 0..rng.below(30) {
                    let (t, rows) = triangles[rng.below(40) as usize];
                    if rows.1 < band_y0 || rows.0 as u32 >= band_end {
                        continue;
                    }
                    let set_up = Cell::new(false);
                    let planes = carry.planes(t, rows, band_y0, band_end, || {
                        set_up.set(true);
                        planes_of(t)
                    });
                    assert_eq!(planes, planes_of(t), "frame {frame} triangle {t}");
                    // Only a triangle that began above the band is carried.
                    assert!(set_up.get() || rows.0 < band_y0);
                }
            }
            carried += carry.carried;
        }
        assert!(carried > 1_000, "{carried}");
    }
}
