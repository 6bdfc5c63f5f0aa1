//! Overflows the stack on purpose (Cortex-M4F, `mps2-an386`): a runaway recursion
//! of 128-byte frames, which the renderer never does. Linked with flip-link, the
//! stack lies below the statics at the start of RAM, so the overflow runs off the
//! RAM into the guard region below it (a bus fault on the real chip; QEMU needs
//! the MPU guard of `common.rs`); the hard-fault handler (`common.rs`) reports
//! `hard fault: stack overflow (...); statics intact` and exits with a failure
//! code. The recursion runs while the firmware's static buffers are lent out, as
//! a frame would; linked the usual way, the stack would grow down into them
//! first, silently. `tests/tests/qemu_stack.rs` runs it.
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use defmt_semihosting as _;
use mcu_abuffer::band_buffer::BandBuffer;
use mcu_abuffer::coverage::CoverageMask;
use mcu_abuffer::renderer::FrameWorkspace;

// The instruction counter is not needed here.
#[allow(dead_code)]
#[path = "../common.rs"]
mod common;

/// Recurses with the static buffers lent out.
struct Overflow;

impl common::WithBuffers for Overflow {
    fn run<M: CoverageMask, B: BandBuffer<M>>(self, buffer: &mut B, ws: &mut FrameWorkspace<'_>) {
        core::hint::black_box((buffer, ws));
        descend(0);
        common::fail("the recursion returned without a fault");
    }
}

/// One level of the recursion: a 128-byte frame that stays alive across the call.
fn descend(depth: u32) -> u32 {
    let mut frame = [depth; 32];
    core::hint::black_box(&mut frame);
    if core::hint::black_box(depth) == u32::MAX {
        return frame[0];
    }
    descend(depth + 1).wrapping_add(core::hint::black_box(frame)[31])
}

#[entry]
fn main() -> ! {
    let Some(mut core) = cortex_m::Peripherals::take() else {
        common::fail("peripherals taken twice");
    };
    common::guard_below_stack(&mut core.MPU);
    common::with_buffers(Overflow);
    common::fail("the recursion returned without a fault")
}
