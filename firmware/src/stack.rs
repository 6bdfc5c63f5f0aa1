//! The stack's high-water mark on a bare-metal firmware linked with cortex-m-rt.
//!
//! With cortex-m-rt's `paint-stack` feature the start-up code fills the whole
//! stack, from `_stack_end` up to `_stack_start`, with a pattern before `main`; the
//! lowest word that no longer holds it is the deepest the stack has reached since
//! reset. (Only on bare-metal ARM targets; the symbols come from cortex-m-rt's
//! `link.x`.)

/// Stack use in bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StackUse {
    /// The deepest the stack has been since reset.
    pub high_water: usize,
    /// What the linker reserved for it (`_stack_start - _stack_end`).
    pub reserved: usize,
}

/// Scans the painted stack for the high-water mark. `pattern` is the paint value
/// (`cortex_m_rt::STACK_PAINT_VALUE`). Call it from a binary linked with
/// cortex-m-rt's `link.x` and its `paint-stack` feature, or the mark means nothing.
#[cfg(all(target_arch = "arm", target_os = "none"))]
pub fn painted_stack_use(pattern: u32) -> StackUse {
    extern "C" {
        static _stack_start: u32;
        static _stack_end: u32;
    }
    // SAFETY: only the symbols' addresses are taken, and the words between them are
    // stack RAM, read with volatile loads from the far end up to the first one in
    // use, which lies below the live frames.
    unsafe {
        let top = core::ptr::addr_of!(_stack_start) as usize;
        let mut word = core::ptr::addr_of!(_stack_end);
        let bottom = word as usize;
        while (word as usize) < top && core::ptr::read_volatile(word) == pattern {
            word = word.add(1);
        }
        StackUse {
            high_water: top - word as usize,
            reserved: top - bottom,
        }
    }
}
