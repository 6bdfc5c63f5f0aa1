//! Memory for a renderer, sized by const generics, that a firmware places in
//! `static`s without `unsafe`.
//!
//! The renderer borrows all its memory ([`FrameWorkspace`], [`BufferStorage`]).
//! The types here own arrays of the right lengths, have `const fn new()`, so
//! they can initialize a `static` (a [`static_cell::ConstStaticCell`] hands
//! out the `&'static mut` once, with no copy through the stack), and lend their
//! arrays to a [`FragmentBuffer`], a [`ZBuffer`] or a [`FrameWorkspace`]. Sizes
//! that cannot be represented are rejected when the firmware compiles.
//!
//! [`static_cell::ConstStaticCell`]: https://docs.rs/static_cell
//!
//! ```
//! use mcu_abuffer::memory::{FragmentMemory, WorkspaceMemory};
//! use mcu_abuffer::{Mask4x4, OverflowPolicy, Renderer};
//!
//! // 240x240, 6-row bands, 1 slot and 2 pool addresses per pixel, 1,152 pool
//! // slots (the sizes of `defaults`); scenes of up to 2 objects, 600
//! // vertices and 1,000 triangles.
//! type Fragments = FragmentMemory<Mask4x4, 240, 6, 1, 2, 1152>;
//! type Workspace = WorkspaceMemory<240, 2, 600, 1000>;
//! // Per pixel a 14-byte slot, two 2-byte addresses and a count byte; 1,152
//! // pool slots of 14 bytes: 240 * 6 * 19 + 1,152 * 14 bytes.
//! assert_eq!(Fragments::BYTES, 43_488);
//! // 600 screen vertices of 12 bytes, 6 bytes per triangle (its rows and its
//! // place in the drawing order), 241 row counters and per object its
//! // transform (lines are resolved into the sink's own memory).
//! assert!(Workspace::BYTES > 600 * 12 + 1000 * 6 + 241 * 4);
//! assert!(Workspace::BYTES < 16 * 1024);
//! // An optional fifth size keeps the color planes of triangles from one
//! // band to the next in that many entries (80 bytes each, two for a
//! // large quadratic), so a triangle that spans several bands lights and
//! // fits its colors once.
//! type CarryingWorkspace = WorkspaceMemory<240, 2, 600, 1000, 8>;
//! assert_eq!(CarryingWorkspace::BYTES, Workspace::BYTES + 8 * 80);
//!
//! // On a device these are `static`s (see the crate documentation).
//! let mut fragments = Box::new(Fragments::new());
//! let mut workspace = Box::new(Workspace::new());
//! let buffer = fragments.buffer(OverflowPolicy::SplitBands);
//! let renderer = Renderer::new(workspace.workspace(), buffer);
//! assert_eq!(renderer.buffer().config().band_height, 6);
//! ```

use crate::color_carry::CarriedColors;
use crate::coverage::CoverageMask;
use crate::fragment::PackedFragment;
use crate::fragment_buffer::{
    BufferConfig, BufferStorage, ConstShape, FragmentBuffer, OverflowPolicy,
};
use crate::renderer::{FrameWorkspace, ObjectFrame, ScreenVertex};
use crate::sink::LinePixel;
use crate::zbuffer::ZBuffer;
use embedded_graphics_core::pixelcolor::Rgb888;

/// Whether a band of `width` x `band` pixels can be addressed (each side
/// 1 to 65,535).
const fn band_fits(width: usize, band: usize) -> bool {
    width >= 1 && width <= u16::MAX as usize && band >= 1 && band <= u16::MAX as usize
}

/// The pool address type of [`FragmentMemory`]: 16 bits, so at most 65,535
/// pool slots.
pub type PoolIndex = u16;

/// The fragment memory of one band for a [`FragmentBuffer`]: `WIDTH` pixels by
/// `BAND` rows, each with `MAIN` fragment slots and `EXTRA` addresses into a
/// shared pool of `POOL` slots (SPEC section 4's `N_main`, `N_extra`, `N_pool`).
///
/// Compiling `new` fails when a size cannot be represented: `WIDTH` or `BAND`
/// zero or above 65,535, `MAIN` zero, `MAIN + EXTRA` above 255, `POOL` above
/// 65,535.
pub struct FragmentMemory<
    M: CoverageMask,
    const WIDTH: usize,
    const BAND: usize,
    const MAIN: usize,
    const EXTRA: usize,
    const POOL: usize,
> {
    counts: [[u8; WIDTH]; BAND],
    main: [[[PackedFragment<M>; MAIN]; WIDTH]; BAND],
    addresses: [[[PoolIndex; EXTRA]; WIDTH]; BAND],
    pool: [PackedFragment<M>; POOL],
}

impl<
        M: CoverageMask,
        const WIDTH: usize,
        const BAND: usize,
        const MAIN: usize,
        const EXTRA: usize,
        const POOL: usize,
    > FragmentMemory<M, WIDTH, BAND, MAIN, EXTRA, POOL>
{
    /// Evaluated by `new`: a size out of range stops the build.
    const SIZES_FIT: () = {
        assert!(band_fits(WIDTH, BAND), "WIDTH and BAND must be 1..=65535");
        assert!(
            MAIN >= 1,
            "MAIN (fragment slots per pixel) must be at least 1"
        );
        assert!(
            MAIN + EXTRA <= u8::MAX as usize,
            "MAIN + EXTRA must be at most 255"
        );
        assert!(
            POOL <= PoolIndex::MAX as usize,
            "POOL must be at most 65535"
        );
    };

    /// Bytes this memory occupies (the seed's `M_shared` plus one count byte
    /// per pixel).
    pub const BYTES: usize = core::mem::size_of::<Self>();

    /// Empty memory (all zero, so a `static` of it lands in `.bss`).
    pub const fn new() -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::SIZES_FIT;
        Self {
            counts: [[0; WIDTH]; BAND],
            main: [[[PackedFragment::EMPTY; MAIN]; WIDTH]; BAND],
            addresses: [[[0; EXTRA]; WIDTH]; BAND],
            pool: [PackedFragment::EMPTY; POOL],
        }
    }

    /// The buffer configuration these sizes make, with `policy` on overflow.
    pub const fn config(policy: OverflowPolicy) -> BufferConfig {
        BufferConfig {
            width: WIDTH as u16,
            band_height: BAND as u16,
            main_slots: MAIN as u8,
            extra_addresses: EXTRA as u8,
            policy,
        }
    }

    /// A fragment buffer over this memory, handling overflow by `policy`;
    /// its width and slots per pixel are constants of its type
    /// ([`ConstShape`]).
    pub fn buffer(
        &mut self,
        policy: OverflowPolicy,
    ) -> FragmentBuffer<'_, M, PoolIndex, ConstShape<WIDTH, MAIN, EXTRA>> {
        let storage = BufferStorage {
            counts: self.counts.as_flattened_mut(),
            main: self.main.as_flattened_mut().as_flattened_mut(),
            addresses: self.addresses.as_flattened_mut().as_flattened_mut(),
            pool: &mut self.pool,
        };
        match FragmentBuffer::new(Self::config(policy), storage) {
            Ok(buffer) => buffer,
            // The lengths come from the same constants as the configuration,
            // and `SIZES_FIT` holds: the buffer accepts them.
            Err(_) => unreachable!("storage sized by the configuration's own constants"),
        }
    }
}

impl<
        M: CoverageMask,
        const WIDTH: usize,
        const BAND: usize,
        const MAIN: usize,
        const EXTRA: usize,
        const POOL: usize,
    > Default for FragmentMemory<M, WIDTH, BAND, MAIN, EXTRA, POOL>
{
    fn default() -> Self {
        Self::new()
    }
}

/// The memory of one band for a [`ZBuffer`] (no antialiasing): a depth and a
/// color per pixel, `WIDTH` by `BAND`, the colors in pixel format `P` (best
/// the format of the sink the frame goes to: see [`ZBuffer`]).
pub struct ZBufferMemory<const WIDTH: usize, const BAND: usize, P: LinePixel = Rgb888> {
    depth: [[u32; WIDTH]; BAND],
    color: [[P; WIDTH]; BAND],
}

impl<const WIDTH: usize, const BAND: usize, P: LinePixel> ZBufferMemory<WIDTH, BAND, P> {
    /// Evaluated by `new`: a size out of range stops the build.
    const SIZES_FIT: () = assert!(band_fits(WIDTH, BAND), "WIDTH and BAND must be 1..=65535");

    /// Bytes this memory occupies.
    pub const BYTES: usize = core::mem::size_of::<Self>();

    /// Empty memory.
    pub const fn new() -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::SIZES_FIT;
        Self {
            depth: [[0; WIDTH]; BAND],
            color: [[P::BLACK_PIXEL; WIDTH]; BAND],
        }
    }

    /// A z-buffer over this memory.
    pub fn buffer(&mut self) -> ZBuffer<'_, P> {
        match ZBuffer::new(
            WIDTH as u16,
            BAND as u16,
            self.depth.as_flattened_mut(),
            self.color.as_flattened_mut(),
        ) {
            Some(buffer) => buffer,
            None => unreachable!("storage sized by the buffer's own constants"),
        }
    }
}

impl<const WIDTH: usize, const BAND: usize, P: LinePixel> Default
    for ZBufferMemory<WIDTH, BAND, P>
{
    fn default() -> Self {
        Self::new()
    }
}

/// `HEIGHT + 1` row counters in one array (what the counting sort by first
/// row needs), without asking the user for `HEIGHT + 1` as a parameter.
#[repr(C)]
struct RowStarts<const HEIGHT: usize> {
    rows: [u32; HEIGHT],
    end: u32,
}

impl<const HEIGHT: usize> RowStarts<HEIGHT> {
    fn as_mut_slice(&mut self) -> &mut [u32] {
        // SAFETY: `repr(C)` lays out `rows` and then `end` with no padding
        // between them (both are `u32`-aligned and `rows` is a whole number of
        // `u32`s), so the struct is `HEIGHT + 1` consecutive `u32`s; the
        // slice borrows `self` mutably for its whole life.
        unsafe { core::slice::from_raw_parts_mut((self as *mut Self).cast::<u32>(), HEIGHT + 1) }
    }
}

const _: () = assert!(core::mem::size_of::<RowStarts<7>>() == 8 * 4);

/// The working memory of a frame ([`FrameWorkspace`]) for images of at most
/// `HEIGHT` rows and scenes of at most `OBJECTS` objects, `VERTICES`
/// vertices and `TRIANGLES` triangles (over all objects). A scene that needs
/// more is refused by [`Renderer::render`](crate::Renderer::render) with
/// [`RenderError::Workspace`](crate::RenderError::Workspace), naming the part.
///
/// `CARRIED` entries keep the color planes of triangles that reach into the
/// next band, so that band does not light and fit them again
/// ([`defaults::CARRIED_COLORS`] entries of 80 bytes, a large quadratic
/// taking two, at most [`crate::color_carry::MAX_ENTRIES`] used; in 6-row
/// bands the default spares the teapot about 800 color setups a frame).
/// The image does not depend on it; 0, the default, carries nothing.
pub struct WorkspaceMemory<
    const HEIGHT: usize,
    const OBJECTS: usize,
    const VERTICES: usize,
    const TRIANGLES: usize,
    const CARRIED: usize = 0,
> {
    objects: [ObjectFrame; OBJECTS],
    vertices: [ScreenVertex; VERTICES],
    triangle_rows: [u16; TRIANGLES],
    triangle_order: [u32; TRIANGLES],
    row_starts: RowStarts<HEIGHT>,
    carried_colors: [CarriedColors; CARRIED],
}

impl<
        const HEIGHT: usize,
        const OBJECTS: usize,
        const VERTICES: usize,
        const TRIANGLES: usize,
        const CARRIED: usize,
    > WorkspaceMemory<HEIGHT, OBJECTS, VERTICES, TRIANGLES, CARRIED>
{
    /// Bytes this memory occupies.
    pub const BYTES: usize = core::mem::size_of::<Self>();

    /// Empty memory.
    pub const fn new() -> Self {
        Self {
            objects: [ObjectFrame::EMPTY; OBJECTS],
            vertices: [ScreenVertex::EMPTY; VERTICES],
            triangle_rows: [0; TRIANGLES],
            triangle_order: [0; TRIANGLES],
            row_starts: RowStarts {
                rows: [0; HEIGHT],
                end: 0,
            },
            carried_colors: [CarriedColors::EMPTY; CARRIED],
        }
    }

    /// The frame workspace over this memory.
    pub fn workspace(&mut self) -> FrameWorkspace<'_> {
        FrameWorkspace {
            objects: &mut self.objects,
            vertices: &mut self.vertices,
            triangle_rows: &mut self.triangle_rows,
            triangle_order: &mut self.triangle_order,
            row_starts: self.row_starts.as_mut_slice(),
            carried_colors: &mut self.carried_colors,
        }
    }
}

impl<
        const HEIGHT: usize,
        const OBJECTS: usize,
        const VERTICES: usize,
        const TRIANGLES: usize,
        const CARRIED: usize,
    > Default for WorkspaceMemory<HEIGHT, OBJECTS, VERTICES, TRIANGLES, CARRIED>
{
    fn default() -> Self {
        Self::new()
    }
}

/// The default memory configuration: what the QEMU firmware, `host-sim`'s
/// commands and the examples use when no size is given (SPEC section 4's
/// parameters).
///
/// With 4x4 masks at 240 pixels the A-buffer's band takes 43,488 bytes
/// (6 rows of 19 bytes a pixel, 1,152 pool slots of 14 bytes) and the
/// z-buffer's 40,320 (24 rows of 7 bytes a pixel). Of the A-buffer layouts of
/// about that size on the Cortex-M4, 6 rows with this pool drew the built-in
/// scenes fastest with the default `split-bands` (teapot 45.6 M instructions a
/// frame, against 49.8 M with 7 rows and 837 slots, 56.7 M with 8 rows and
/// 512 slots, 46.8 M with 5 rows and 1,488 slots; docs/m4-benchmark-history.md): a
/// larger pool splits fewer bands, shorter bands set more triangles up twice.
/// The board demo keeps these sizes but a pool of 512 slots, which leaves its
/// two DMA line buffers and its stack room in 128 KiB.
pub mod defaults {
    /// Rows per band of the A-buffer.
    pub const BAND_ROWS: u16 = 6;
    /// Rows per band of the z-buffer, whose pixels take 7 bytes instead of
    /// 19: about the A-buffer's band in memory, and fewer bands to set
    /// triangles up in (teapot 20.5 M instructions a frame, 22.8 M at 8 rows).
    pub const ZBUFFER_BAND_ROWS: u16 = 24;
    /// Fragment slots per pixel in the main buffer (`N_main`).
    pub const MAIN_SLOTS: u8 = 1;
    /// Pool addresses per pixel (`N_extra`).
    pub const EXTRA_ADDRESSES: u8 = 2;
    /// Shared pool slots per band (`N_pool`).
    pub const POOL_SLOTS: usize = 1152;
    /// Fragment slots per pixel of the fixed-allocation methods (`N_fixed`).
    pub const FIXED_SLOTS: u8 = 3;
    /// Entries of the carried-colors table
    /// ([`WorkspaceMemory`](super::WorkspaceMemory)'s `CARRIED`), 80 bytes
    /// each (a wide quadratic takes two): 9,280 bytes (104 entries before
    /// lines were resolved into the sink's memory; the 960 bytes of the
    /// workspace's line went to 12 more). In 6-row bands the built-in
    /// scenes fill the table in their busiest bands (an entry stays until
    /// its triangle ends, asked for or not); what does not fit is set up
    /// again: in frame 0, 39 color setups on the teapot and 194 on the
    /// starfighter that a table of 256 entries would spare (58 and 255 with
    /// 104 entries; `docs/m4-benchmark-history.md`).
    pub const CARRIED_COLORS: usize = 116;
    const _: () = assert!(CARRIED_COLORS <= crate::color_carry::MAX_ENTRIES);
    /// Bytes of RAM the firmware build scripts and `host-sim fit` keep free
    /// for the stack (the deepest frame measured is about 7.6 KB).
    pub const STACK_RESERVE_BYTES: usize = 10 * 1024;

    /// The default rows per band of a method: [`ZBUFFER_BAND_ROWS`] for the
    /// z-buffer, [`BAND_ROWS`] for the A-buffer's methods.
    pub const fn band_rows(zbuffer: bool) -> u16 {
        if zbuffer {
            ZBUFFER_BAND_ROWS
        } else {
            BAND_ROWS
        }
    }
}

/// The byte counts of [`FragmentMemory`], [`ZBufferMemory`] and
/// [`WorkspaceMemory`] for sizes known only when a program runs (build
/// scripts that check a configuration against a board's SRAM, `host-sim
/// fit`): each equals the type's `BYTES` for the same sizes, to the byte.
pub mod bytes {
    use super::PoolIndex;
    use crate::color_carry::CarriedColors;
    use crate::renderer::{ObjectFrame, ScreenVertex};
    use core::mem::{align_of, size_of};
    use embedded_graphics_core::pixelcolor::Rgb888;

    /// Bytes of one pool address.
    pub const ADDRESS: usize = size_of::<PoolIndex>();
    /// Bytes of one transformed vertex.
    pub const SCREEN_VERTEX: usize = size_of::<ScreenVertex>();
    /// Bytes of one object's per-frame state.
    pub const OBJECT_FRAME: usize = size_of::<ObjectFrame>();
    /// Bytes of one entry of the carried-colors table.
    pub const CARRIED_COLORS: usize = size_of::<CarriedColors>();
    /// Bytes of one color of the z-buffer in its default pixel format
    /// ([`Rgb888`], a 32-bit word).
    pub const COLOR: usize = size_of::<Rgb888>();
    /// Bytes of one triangle's entries in the workspace: its rows (`u16`) and
    /// its place in the drawing order (`u32`).
    pub const TRIANGLE: usize = size_of::<u16>() + size_of::<u32>();

    /// Bytes of one stored fragment with a coverage mask of `mask_bytes`
    /// bytes (the seed's `M_frag`: the mask and three 32-bit words).
    pub const fn fragment(mask_bytes: usize) -> usize {
        mask_bytes + 3 * size_of::<u32>()
    }

    const fn round_up(n: usize, align: usize) -> usize {
        n.div_ceil(align) * align
    }

    /// The parts of a [`FragmentMemory`](super::FragmentMemory), in bytes.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub struct FragmentParts {
        /// Fragment counts, one byte per pixel: `W R`.
        pub counts: usize,
        /// Main slots: `W R N_main M_frag`.
        pub main_slots: usize,
        /// Pool addresses: `W R N_extra M_addr`.
        pub addresses: usize,
        /// The shared pool: `N_pool M_frag`.
        pub pool: usize,
    }

    impl FragmentParts {
        /// The parts for `width` x `band` pixels, `main` slots and `extra`
        /// addresses per pixel, `pool` pool slots, masks of `mask_bytes`.
        pub const fn new(
            mask_bytes: usize,
            width: usize,
            band: usize,
            main: usize,
            extra: usize,
            pool: usize,
        ) -> Self {
            let pixels = width * band;
            Self {
                counts: pixels,
                main_slots: pixels * main * fragment(mask_bytes),
                addresses: pixels * extra * ADDRESS,
                pool: pool * fragment(mask_bytes),
            }
        }

        /// The whole memory: the parts and the padding that rounds it to its
        /// alignment (that of the addresses; fragments are packed bytes).
        pub const fn total(&self) -> usize {
            round_up(
                self.counts + self.main_slots + self.addresses + self.pool,
                align_of::<super::FragmentMemory<crate::Mask8x8, 1, 1, 1, 1, 1>>(),
            )
        }

        /// The padding in [`Self::total`].
        pub const fn padding(&self) -> usize {
            self.total() - (self.counts + self.main_slots + self.addresses + self.pool)
        }
    }

    /// `FragmentMemory::<M, width, band, main, extra, pool>::BYTES` for masks
    /// of `mask_bytes` bytes.
    pub const fn fragment_memory(
        mask_bytes: usize,
        width: usize,
        band: usize,
        main: usize,
        extra: usize,
        pool: usize,
    ) -> usize {
        FragmentParts::new(mask_bytes, width, band, main, extra, pool).total()
    }

    /// `ZBufferMemory::<width, band, P>::BYTES` for pixels `P` of
    /// `pixel_bytes` bytes: a 32-bit depth and a color per pixel (padded to
    /// the depths' alignment).
    pub const fn zbuffer_memory(width: usize, band: usize, pixel_bytes: usize) -> usize {
        round_up(
            width * band * (size_of::<u32>() + pixel_bytes),
            align_of::<u32>(),
        )
    }

    /// `WorkspaceMemory::<height, objects, vertices, triangles,
    /// carried>::BYTES`.
    pub const fn workspace_memory(
        height: usize,
        objects: usize,
        vertices: usize,
        triangles: usize,
        carried: usize,
    ) -> usize {
        round_up(
            objects * OBJECT_FRAME
                + vertices * SCREEN_VERTEX
                + triangles * TRIANGLE
                + (height + 1) * size_of::<u32>()
                + carried * CARRIED_COLORS,
            align_of::<super::WorkspaceMemory<1, 1, 1, 1, 1>>(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Mask4x4;

    #[test]
    fn byte_counts_follow_the_formula() {
        type F = FragmentMemory<Mask4x4, 240, 8, 1, 2, 512>;
        let fragment = PackedFragment::<Mask4x4>::SIZE;
        let config = F::config(OverflowPolicy::MergeFarthest);
        assert_eq!(
            F::BYTES,
            config.shared_bytes(fragment, 2, 512) + config.pixels()
        );
        assert_eq!(ZBufferMemory::<240, 6>::BYTES, 240 * 6 * 8);
        assert_eq!(
            ZBufferMemory::<240, 6, crate::PackedRgb888>::BYTES,
            240 * 6 * 7
        );
        assert_eq!(
            ZBufferMemory::<240, 6, crate::Rgb565BigEndian>::BYTES,
            240 * 6 * 6
        );
    }

    #[test]
    fn run_time_byte_counts_equal_the_types() {
        use crate::{Mask8x4, Mask8x8};
        assert_eq!(bytes::fragment(2), PackedFragment::<Mask4x4>::SIZE);
        assert_eq!(bytes::fragment(4), PackedFragment::<Mask8x4>::SIZE);
        assert_eq!(bytes::fragment(8), PackedFragment::<Mask8x8>::SIZE);
        assert_eq!(
            bytes::fragment_memory(2, 240, 8, 1, 2, 512),
            FragmentMemory::<Mask4x4, 240, 8, 1, 2, 512>::BYTES
        );
        // An odd pixel count: padding.
        assert_eq!(
            bytes::fragment_memory(2, 7, 3, 1, 3, 5),
            FragmentMemory::<Mask4x4, 7, 3, 1, 3, 5>::BYTES
        );
        assert_eq!(
            bytes::fragment_memory(8, 64, 6, 2, 0, 0),
            FragmentMemory::<Mask8x8, 64, 6, 2, 0, 0>::BYTES
        );
        assert_eq!(
            bytes::fragment_memory(4, 33, 5, 3, 4, 100),
            FragmentMemory::<Mask8x4, 33, 5, 3, 4, 100>::BYTES
        );
        assert_eq!(
            bytes::zbuffer_memory(240, 6, bytes::COLOR),
            ZBufferMemory::<240, 6>::BYTES
        );
        assert_eq!(
            bytes::zbuffer_memory(7, 3, crate::PackedRgb888::BYTES),
            ZBufferMemory::<7, 3, crate::PackedRgb888>::BYTES
        );
        assert_eq!(
            bytes::workspace_memory(240, 4, 2562, 5120, 0),
            WorkspaceMemory::<240, 4, 2562, 5120>::BYTES
        );
        assert_eq!(
            bytes::workspace_memory(240, 1, 2562, 5120, 48),
            WorkspaceMemory::<240, 1, 2562, 5120, 48>::BYTES
        );
        assert_eq!(
            bytes::workspace_memory(5, 1, 3, 1, 3),
            WorkspaceMemory::<5, 1, 3, 1, 3>::BYTES
        );
    }

    #[test]
    fn row_starts_are_height_plus_one() {
        let mut memory = Box::new(WorkspaceMemory::<12, 1, 3, 1>::new());
        let ws = memory.workspace();
        assert_eq!(ws.row_starts.len(), 13);
        ws.row_starts[12] = 7;
        assert_eq!(memory.row_starts.end, 7);
    }

    #[test]
    fn buffers_take_the_configured_sizes() {
        let mut memory = Box::new(FragmentMemory::<Mask4x4, 32, 4, 2, 3, 100>::new());
        let buffer = memory.buffer(OverflowPolicy::SplitBands);
        assert_eq!(buffer.config().pixel_capacity(), 5);
        assert_eq!(buffer.pool().capacity(), 100);
        let mut z = Box::new(ZBufferMemory::<32, 4>::new());
        assert_eq!(
            crate::BandBuffer::<crate::Mask1x1>::band_height(&z.buffer()),
            4
        );
    }
}
