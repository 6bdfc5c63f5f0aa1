//! The order in which a band draws its triangles: faces towards the viewer
//! before faces turned away, and within each group the nearest first
//! ([`TriangleOrder::NearestFirst`], what every buffer but one asks for).
//!
//! Each drawn triangle is one `u32` of the frame's order (the workspace's
//! `triangle_order`), built once per frame when the triangles are binned.
//! From the top bit down it holds:
//!
//! | bits | what |
//! |---|---|
//! | 31 | the triangle faces away |
//! | 30 | zero |
//! | `key_bits` | its key: the top bits of its nearest corner's window depth (a corner outside the view volume counts as 0), or its first row |
//! | `object_bits` | its object |
//! | `triangle_bits` | its index in its object's mesh |
//!
//! `object_bits` and `triangle_bits` are as few as the scene's object count
//! and largest mesh need; the key takes what is left of 30 bits, at most
//! what it has (24 bits of depth, 11 of rows). Each band keeps its entries
//! sorted as integers, which is the order above (ties of the key broken by
//! object and triangle, so the order is one and the same whatever the
//! sort and whatever the band's height).
//!
//! Why nearest first: a surface drawn early hides what arrives behind it.
//! The whole-band test then skips a hidden triangle before its setup, and
//! a fragment that arrives behind stored ones is hidden on arrival, before
//! its triangle's colors are set up and before it takes memory. Drawing far
//! surfaces first, every one of them is lit, fitted and stored, and then
//! removed when the near surface arrives. The per-sample z-buffers and the
//! unlimited A-buffer keep the same image in any order but for exact ties
//! of depth; the bounded-memory methods merge what arrives, so their images
//! depend on the order, as they depend on the memory.

/// Bits of window depth ([`crate::fixed_point::DEPTH_BITS`]).
const DEPTH_BITS: u32 = crate::fixed_point::DEPTH_BITS;

/// Bits of an image row (images are at most 2048 pixels high).
const ROW_BITS: u32 = 11;

/// What orders a band's triangles within each facing group: a buffer's
/// choice ([`crate::band_buffer::BandBuffer::ORDER`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TriangleOrder {
    /// The nearest corner's window depth, nearest first.
    NearestFirst,
    /// The first image row, top first (then object and triangle): the order
    /// of binning. The z-buffer with midpoint subdivision keeps it, since
    /// its "visible" verdict trusts what it reads, and nearer surfaces drawn
    /// first would fool it more often.
    FirstRow,
}

/// Bits for object and triangle numbers and the key together; bit 30
/// stays zero, so no entry is `u32::MAX` (the color carry's keys add one).
const NUMBER_AND_KEY_BITS: u32 = 30;

/// The flag of a triangle facing away.
const FACES_AWAY: u32 = 1 << 31;

/// Bits that number `n` things (`0..n`).
const fn bits_for(n: usize) -> u32 {
    if n <= 1 {
        0
    } else {
        usize::BITS - (n - 1).leading_zeros()
    }
}

/// How a frame packs its order entries (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct DrawOrder {
    triangle_bits: u32,
    object_bits: u32,
    /// The bits of the object and triangle numbers together, and of the
    /// triangle number: kept as masks, so that [`DrawOrder::split`] (several
    /// times per triangle and band) does not make them again.
    number_mask: u32,
    triangle_mask: u32,
    /// What the key is.
    by: TriangleOrder,
    /// How far the key's value (a depth or a row) is shifted down to keep
    /// its top bits.
    key_drop: u32,
}

impl DrawOrder {
    /// The packing for `objects` objects whose largest mesh has
    /// `most_triangles` triangles, ordered `by`; `None` when their numbers
    /// need more than 30 bits together.
    pub(crate) fn new(objects: usize, most_triangles: usize, by: TriangleOrder) -> Option<Self> {
        let (object_bits, triangle_bits) = (bits_for(objects), bits_for(most_triangles));
        let number_bits = object_bits + triangle_bits;
        if number_bits > NUMBER_AND_KEY_BITS {
            return None;
        }
        let value_bits = match by {
            TriangleOrder::NearestFirst => DEPTH_BITS,
            TriangleOrder::FirstRow => ROW_BITS,
        };
        let key_bits = (NUMBER_AND_KEY_BITS - number_bits).min(value_bits);
        Some(Self {
            triangle_bits,
            object_bits,
            number_mask: ((1u64 << number_bits) - 1) as u32,
            triangle_mask: (1u32 << triangle_bits) - 1,
            by,
            key_drop: value_bits - key_bits,
        })
    }

    /// The entry of triangle `triangle` of object `object`, which faces away
    /// when `back`, whose nearest corner has window depth `nearest` (below
    /// 2^24) and whose first row is `first_row` (below 2048).
    #[inline]
    pub(crate) fn entry(
        &self,
        (object, triangle): (usize, usize),
        back: bool,
        nearest: u32,
        first_row: u16,
    ) -> u32 {
        let number = ((object as u32) << self.triangle_bits) | triangle as u32;
        let value = match self.by {
            TriangleOrder::NearestFirst => nearest,
            TriangleOrder::FirstRow => first_row as u32,
        };
        let key = (value >> self.key_drop) << (self.object_bits + self.triangle_bits);
        (if back { FACES_AWAY } else { 0 }) | key | number
    }

    /// The entry of a triangle whose facing and key do not matter (yet):
    /// enough for [`DrawOrder::split`].
    #[inline]
    pub(crate) fn number(&self, object: usize, triangle: usize) -> u32 {
        self.entry((object, triangle), false, 0, 0)
    }

    /// The object and the triangle within its mesh of `entry`.
    #[inline]
    pub(crate) fn split(&self, entry: u32) -> (usize, usize) {
        let number = entry & self.number_mask;
        (
            (number >> self.triangle_bits) as usize,
            (number & self.triangle_mask) as usize,
        )
    }

    /// Adds the triangles that start in a band to its active list, in
    /// drawing order: `order[..kept]` holds the entries kept from the band
    /// above, sorted; `order[next..starting]` the new ones, in any order.
    /// Afterwards `order[..kept + starting - next]` holds both, sorted; the
    /// new count is returned. `order[binned..]` is free space (the entries
    /// of triangles not drawn).
    ///
    /// The new entries are sorted where they lie and merged into the kept
    /// ones from the back: no more work than their own sort and one pass,
    /// where sorting the whole list again would cost about as much as the
    /// drawing order saves on a scene whose surfaces do not hide each other.
    /// The merge reads them from where they lie when the entries dropped
    /// since leave room before them, else from a copy in the free space;
    /// with neither, the whole list is sorted (the same order).
    pub(crate) fn admit(
        order: &mut [u32],
        kept: usize,
        (next, starting): (usize, usize),
        binned: usize,
    ) -> usize {
        let new = starting - next;
        let active = kept + new;
        if new == 0 {
            return kept;
        }
        order[next..starting].sort_unstable();
        if kept == 0 || order[kept - 1] < order[next] {
            // Already in order after the kept ones.
            order.copy_within(next..starting, kept);
        } else if active <= next {
            merge_from_back(order, kept, next, new);
        } else if order.len() - binned >= new {
            order.copy_within(next..starting, binned);
            merge_from_back(order, kept, binned, new);
        } else {
            order.copy_within(next..starting, kept);
            order[..active].sort_unstable();
        }
        active
    }
}

/// Merges the sorted runs `order[..kept]` and `order[from..from + new]`
/// into `order[..kept + new]`, from the back; `from >= kept + new`, so no
/// write lands on an entry not yet read.
fn merge_from_back(order: &mut [u32], kept: usize, from: usize, new: usize) {
    // The two runs and the output as slices of their own, so the loop's
    // indices need no checks beyond the slices' lengths.
    let (head, tail) = order.split_at_mut(from);
    let (out, run) = (&mut head[..kept + new], &tail[..new]);
    let mut i = kept;
    for (j, &b) in run.iter().enumerate().rev() {
        // The kept entries above `b` move up past the new ones not yet placed.
        while i > 0 && out[i - 1] > b {
            out[i + j] = out[i - 1];
            i -= 1;
        }
        out[i + j] = b;
    }
}

#[cfg(test)]
mod tests {
    use super::TriangleOrder::{FirstRow, NearestFirst};
    use super::*;

    #[test]
    fn entries_split_back_and_sort_front_faces_nearest_first() {
        for (objects, triangles) in [(1, 1), (1, 4096), (7, 300), (255, 1 << 22), (1, 1 << 30)] {
            let order = DrawOrder::new(objects, triangles, NearestFirst).unwrap();
            for (o, t) in [
                (0, 0),
                (objects - 1, triangles - 1),
                (objects / 2, triangles / 3),
            ] {
                for back in [false, true] {
                    for z in [0, 1 << 23, (1 << 24) - 1] {
                        let e = order.entry((o, t), back, z, 0);
                        assert_eq!(order.split(e), (o, t));
                        assert_eq!(order.split(order.number(o, t)), (o, t));
                        assert_ne!(e, u32::MAX);
                    }
                }
            }
            let near_back = order.entry((0, 0), true, 0, 0);
            let far_front = order.entry((objects - 1, triangles - 1), false, (1 << 24) - 1, 0);
            assert!(far_front < near_back);
        }
        // With room for the depth, nearer sorts first whatever the numbers.
        let order = DrawOrder::new(3, 5000, NearestFirst).unwrap();
        let entry = |o, t, z, row| order.entry((o, t), false, z, row);
        assert!(entry(2, 4999, 1 << 20, 9) < entry(0, 0, 2 << 20, 3));
        // By rows, the depth does not count.
        let order = DrawOrder::new(3, 5000, FirstRow).unwrap();
        let entry = |o, t, z, row| order.entry((o, t), false, z, row);
        assert!(entry(2, 4999, 2 << 20, 2047) > entry(0, 0, 1 << 20, 2046));
        assert!(entry(0, 1, 2 << 20, 7) > entry(0, 0, 1 << 20, 7));
        assert_eq!(DrawOrder::new(257, 1 << 22, NearestFirst), None);
        assert_eq!(DrawOrder::new(2, 1 << 30, FirstRow), None);
    }

    /// `admit` equals sorting the kept and new entries together, whichever
    /// way it merges.
    #[test]
    fn admitted_entries_are_sorted_with_the_kept_ones() {
        let mut xorshift = crate::test_rng::xorshift(0x2545_f491_4f6c_dd1d);
        let mut next = |n: u64| xorshift() % n;
        for round in 0..4000 {
            let len = 1 + next(40) as usize;
            let binned = next(len as u64 + 1) as usize;
            let starting = next(binned as u64 + 1) as usize;
            let from = next(starting as u64 + 1) as usize;
            let kept = next(from as u64 + 1) as usize;
            // Distinct values; small ranges make runs already in order.
            let range = if round % 2 == 0 {
                1 << 20
            } else {
                3 * len as u64
            };
            let mut order: Vec<u32> = Vec::new();
            while order.len() < len {
                let v = next(range) as u32 + 1;
                if !order.contains(&v) {
                    order.push(v);
                }
            }
            order[..kept].sort_unstable();
            let mut expected: Vec<u32> = order[..kept].to_vec();
            expected.extend_from_slice(&order[from..starting]);
            expected.sort_unstable();
            let active = DrawOrder::admit(&mut order, kept, (from, starting), binned);
            assert_eq!(active, expected.len());
            assert_eq!(order[..active], expected[..], "round {round}");
        }
    }
}
