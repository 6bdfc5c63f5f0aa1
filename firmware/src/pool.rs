//! The shared pool: fragment slots for the whole band, handed out to the pixels
//! that need more than their own main slots (SPEC section 5).

use crate::coverage::CoverageMask;
use crate::fragment::PackedFragment;

/// An index into the shared pool, as stored in the main buffer (`M_addr` bytes).
pub trait PoolAddress: Copy + Default + core::fmt::Debug + 'static {
    /// The largest pool size this address type can index.
    const MAX_POOL: usize;
    /// Converts a pool index (below `MAX_POOL`).
    fn from_index(index: usize) -> Self;
    /// The pool index.
    fn index(self) -> usize;
}

impl PoolAddress for u16 {
    const MAX_POOL: usize = u16::MAX as usize;
    #[inline]
    fn from_index(index: usize) -> Self {
        index as u16
    }
    #[inline]
    fn index(self) -> usize {
        self as usize
    }
}

impl PoolAddress for u32 {
    const MAX_POOL: usize = u32::MAX as usize;
    #[inline]
    fn from_index(index: usize) -> Self {
        index as u32
    }
    #[inline]
    fn index(self) -> usize {
        self as usize
    }
}

const NO_SLOT: u32 = u32::MAX;

/// A pool of fragment slots with O(1) allocation, release and reset.
///
/// Never-used slots are handed out in order (a bump index), and only when
/// none is left the released ones, which wait on a free list threaded
/// through the slots themselves, so the pool needs no memory beyond its
/// slots. Either way an allocation fails only when every slot is in use.
/// [`SharedPool::reset`] empties it at the end of a band.
///
/// Slots in use are the bump index less the slots on the free list, and the
/// peak is brought up to date only where that number falls (a release, a
/// reset) and when asked: an allocation from the bump index, the common
/// one, writes nothing but the index.
pub struct SharedPool<'a, M: CoverageMask> {
    slots: &'a mut [PackedFragment<M>],
    bump: u32,
    free_head: u32,
    /// Slots on the free list.
    released: u32,
    /// The most slots in use at once, up to the last release, reset or
    /// [`SharedPool::clear_peak`] (the slots in use now may be more).
    peak: u32,
}

impl<'a, M: CoverageMask> SharedPool<'a, M> {
    /// A pool over the given slots (which may be empty).
    pub fn new(slots: &'a mut [PackedFragment<M>]) -> Self {
        Self {
            slots,
            bump: 0,
            free_head: NO_SLOT,
            released: 0,
            peak: 0,
        }
    }

    /// Number of slots.
    #[inline]
    pub fn capacity(&self) -> usize {
        self.slots.len()
    }

    /// Slots in use now.
    #[inline]
    pub fn in_use(&self) -> usize {
        (self.bump - self.released) as usize
    }

    /// The most slots in use at once since the last [`SharedPool::clear_peak`].
    #[inline]
    pub fn peak(&self) -> usize {
        (self.peak as usize).max(self.in_use())
    }

    /// Forgets the peak.
    pub fn clear_peak(&mut self) {
        self.peak = self.in_use() as u32;
    }

    /// Whether a slot can be allocated.
    #[inline]
    pub fn has_free(&self) -> bool {
        self.in_use() < self.slots.len()
    }

    /// Takes a free slot, or `None` when the pool is full.
    #[inline]
    pub fn allocate(&mut self) -> Option<usize> {
        if (self.bump as usize) < self.slots.len() {
            self.bump += 1;
            Some(self.bump as usize - 1)
        } else if self.free_head != NO_SLOT {
            let i = self.free_head;
            self.free_head = self.slots[i as usize].link();
            self.released -= 1;
            Some(i as usize)
        } else {
            None
        }
    }

    /// Returns a slot to the pool.
    #[inline]
    pub fn release(&mut self, index: usize) {
        self.peak = self.peak() as u32;
        self.slots[index].set_link(self.free_head);
        self.free_head = index as u32;
        self.released += 1;
    }

    /// Frees every slot at once (end of a band); the peak stays.
    pub fn reset(&mut self) {
        self.peak = self.peak() as u32;
        self.bump = 0;
        self.free_head = NO_SLOT;
        self.released = 0;
    }

    /// The slot at `index`.
    #[inline]
    pub fn get(&self, index: usize) -> &PackedFragment<M> {
        &self.slots[index]
    }

    /// The slot at `index`, mutable.
    #[inline]
    pub fn get_mut(&mut self, index: usize) -> &mut PackedFragment<M> {
        &mut self.slots[index]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coverage::Mask4x4;

    #[test]
    fn allocate_release_reset() {
        let mut slots = [PackedFragment::<Mask4x4>::default(); 3];
        let mut pool = SharedPool::new(&mut slots);
        let a = pool.allocate().unwrap();
        let b = pool.allocate().unwrap();
        let c = pool.allocate().unwrap();
        assert_eq!((a, b, c), (0, 1, 2));
        assert!(pool.allocate().is_none());
        pool.release(b);
        pool.release(a);
        assert_eq!(pool.allocate(), Some(a));
        assert_eq!(pool.allocate(), Some(b));
        assert_eq!(pool.peak(), 3);
        pool.reset();
        assert_eq!(pool.in_use(), 0);
        assert_eq!(pool.peak(), 3, "a reset keeps the peak");
        pool.clear_peak();
        assert_eq!(pool.peak(), 0);
        assert_eq!(pool.allocate(), Some(0));
        let d = pool.allocate().unwrap();
        pool.release(d);
        assert_eq!(
            (pool.in_use(), pool.peak()),
            (1, 2),
            "a release keeps the peak"
        );
    }
}
