//! Owned memory for the renderer: the frame workspace and a fragment buffer's
//! storage, and one frame rendered into an image.

use mcu_abuffer::band_buffer::BandBuffer;
use mcu_abuffer::color_carry::CarriedColors;
use mcu_abuffer::coverage::CoverageMask;
use mcu_abuffer::fragment::PackedFragment;
use mcu_abuffer::fragment_buffer::{
    BufferConfig, BufferError, BufferShape, BufferStorage, FragmentBuffer, OverflowPolicy,
    ShapeOfConfig,
};
use mcu_abuffer::memory::defaults;
use mcu_abuffer::pool::PoolAddress;
use mcu_abuffer::renderer::{
    render_frame, FrameOptions, FrameWorkspace, ObjectFrame, RenderError, ScreenVertex,
};
use mcu_abuffer::scene::Scene;
use mcu_abuffer::sink::{ImageSink, OutOfImage};
use mcu_abuffer::stats::FrameStats;

/// The vectors behind a [`FrameWorkspace`], one field for each of its slices.
/// Keep one for frame after frame, as a device keeps its static arrays.
pub struct OwnedWorkspace {
    /// One entry per object.
    pub objects: Vec<ObjectFrame>,
    /// One entry per vertex.
    pub vertices: Vec<ScreenVertex>,
    /// One entry per triangle.
    pub triangle_rows: Vec<u16>,
    /// One entry per triangle.
    pub triangle_order: Vec<u32>,
    /// Image height plus one entries.
    pub row_starts: Vec<u32>,
    /// Carried color planes ([`defaults::CARRIED_COLORS`] entries).
    pub carried_colors: Vec<CarriedColors>,
}

impl OwnedWorkspace {
    /// A workspace of the sizes `scene` needs: one entry per object, vertex,
    /// triangle and row (plus one).
    pub fn for_scene(scene: &Scene<'_>) -> Self {
        Self {
            objects: vec![ObjectFrame::EMPTY; scene.objects.len()],
            vertices: vec![ScreenVertex::default(); scene.vertex_count()],
            triangle_rows: vec![0; scene.triangle_count()],
            triangle_order: vec![0; scene.triangle_count()],
            row_starts: vec![0; scene.height as usize + 1],
            carried_colors: vec![CarriedColors::EMPTY; defaults::CARRIED_COLORS],
        }
    }

    /// The workspace the renderer takes, over these vectors.
    pub fn borrow(&mut self) -> FrameWorkspace<'_> {
        FrameWorkspace {
            objects: &mut self.objects,
            vertices: &mut self.vertices,
            triangle_rows: &mut self.triangle_rows,
            triangle_order: &mut self.triangle_order,
            row_starts: &mut self.row_starts,
            carried_colors: &mut self.carried_colors,
        }
    }
}

/// The vectors behind a [`FragmentBuffer`] with pool addresses of type `A`.
/// Every [`FragmentStorage::buffer`] works in the same memory, so what one
/// frame leaves there is what the next one finds.
pub struct FragmentStorage<M: CoverageMask, A: PoolAddress = u32> {
    config: BufferConfig,
    counts: Vec<u8>,
    main: Vec<PackedFragment<M>>,
    addresses: Vec<A>,
    pool: Vec<PackedFragment<M>>,
}

impl<M: CoverageMask, A: PoolAddress> FragmentStorage<M, A> {
    /// Storage for `config` with a pool of `pool` slots (not checked here:
    /// [`FragmentStorage::try_buffer`] says what does not fit).
    pub fn new(config: BufferConfig, pool: usize) -> Self {
        Self {
            config,
            counts: vec![0; config.pixels()],
            main: vec![PackedFragment::default(); config.main_slot_count()],
            addresses: vec![A::default(); config.address_count()],
            pool: vec![PackedFragment::default(); pool],
        }
    }

    /// The "unlimited" configuration of SPEC section 3: one main slot,
    /// `SAMPLES - 1` pool addresses per pixel and a pool big enough for every
    /// pixel of the band to use them all; two farthest fragments merge (never,
    /// with this much room).
    pub fn unlimited(width: u16, band_height: u16) -> Self {
        let extra = M::SAMPLES - 1;
        let config = BufferConfig {
            width,
            band_height,
            main_slots: 1,
            extra_addresses: extra as u8,
            policy: OverflowPolicy::MergeFarthest,
        };
        Self::new(
            config,
            width as usize * band_height as usize * extra as usize,
        )
    }

    /// The configuration.
    pub fn config(&self) -> BufferConfig {
        self.config
    }

    /// Pool slots.
    pub fn pool_len(&self) -> usize {
        self.pool.len()
    }

    /// A fragment buffer over this storage, or why the library refuses it.
    pub fn try_buffer(&mut self) -> Result<FragmentBuffer<'_, M, A>, BufferError> {
        self.try_shaped_buffer::<ShapeOfConfig>()
    }

    /// A fragment buffer of shape `S` over this storage, or why the library
    /// refuses it (a shape whose constants differ from the configuration).
    pub fn try_shaped_buffer<S: BufferShape>(
        &mut self,
    ) -> Result<FragmentBuffer<'_, M, A, S>, BufferError> {
        FragmentBuffer::new(
            self.config,
            BufferStorage {
                counts: &mut self.counts,
                main: &mut self.main,
                addresses: &mut self.addresses,
                pool: &mut self.pool,
            },
        )
    }

    /// A fragment buffer over this storage; panics when the library refuses it.
    pub fn buffer(&mut self) -> FragmentBuffer<'_, M, A> {
        self.try_buffer()
            .unwrap_or_else(|e| panic!("fragment buffer storage: {e}"))
    }
}

/// What one frame produced.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rendered {
    /// RGB888 pixels, rows top to bottom.
    pub rgb: Vec<u8>,
    /// Frame statistics.
    pub stats: FrameStats,
}

/// Renders one frame of `scene` through `workspace` and `buffer` into a new
/// RGB888 image; `on_band` is `render_frame`'s (called with each band's
/// fragments in, before it is resolved).
pub fn render_rgb<M, B, F>(
    scene: &Scene<'_>,
    options: &FrameOptions,
    workspace: &mut OwnedWorkspace,
    buffer: &mut B,
    on_band: F,
) -> Result<Rendered, RenderError<OutOfImage>>
where
    M: CoverageMask,
    B: BandBuffer<M>,
    F: FnMut(u16, u16, &B),
{
    let mut rgb = vec![0u8; scene.width as usize * scene.height as usize * 3];
    let mut sink = ImageSink::new(scene.width, &mut rgb);
    let stats = render_frame(
        scene,
        options,
        &mut workspace.borrow(),
        buffer,
        &mut sink,
        on_band,
    )?;
    Ok(Rendered { rgb, stats })
}

/// The first pixel in which two RGB888 images `width` pixels wide differ, as
/// `(x, y, a's color, b's color)`.
pub fn first_difference(
    width: u16,
    a: &[u8],
    b: &[u8],
) -> Option<(usize, usize, [u8; 3], [u8; 3])> {
    assert_eq!(a.len(), b.len());
    let w = width as usize;
    (0..a.len() / 3).find_map(|p| {
        let pa = [a[3 * p], a[3 * p + 1], a[3 * p + 2]];
        let pb = [b[3 * p], b[3 * p + 1], b[3 * p + 2]];
        (pa != pb).then_some((p % w, p / w, pa, pb))
    })
}
