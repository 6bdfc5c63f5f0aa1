//! Running the library renderer on the desktop with vectors for its buffers.

use crate::convert::FixedScene;
use abuffer_test_support::{render_rgb, FragmentStorage, OwnedWorkspace};
use embedded_graphics_core::pixelcolor::Rgb888;
use mcu_abuffer::band_buffer::{draw_in_band, BandBuffer, DrawParams, FullRun, PoolUse};
use mcu_abuffer::coverage::{CoverageMask, Mask1x1, Mask4x4, Mask8x4, Mask8x8};
use mcu_abuffer::draw_order::TriangleOrder;
use mcu_abuffer::fixed_point::Coord;
use mcu_abuffer::fragment::Fragment;
use mcu_abuffer::fragment_buffer::{BufferConfig, OverflowPolicy};
use mcu_abuffer::memory::defaults;
use mcu_abuffer::pool::PoolAddress;
use mcu_abuffer::renderer::FrameOptions;
use mcu_abuffer::scene::Scene;
use mcu_abuffer::setup::{Rejection, SetupVertex};
use mcu_abuffer::shading::ColorWalk;
use mcu_abuffer::sink::LinePixel;
use mcu_abuffer::stats::{BufferStats, FrameStats};
use mcu_abuffer::zbuffer::ZBuffer;
use mcu_abuffer::zbuffer_hiz::{tile_count, HierarchicalZBuffer, HizTile};
use mcu_abuffer::zbuffer_midpoint::{MidpointConfig, MidpointZBuffer, MAX_SUBDIVISION_DEPTH};
use std::time::{Duration, Instant};

/// How pixels are stored and resolved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// The reference A-buffer: every pixel can hold one fragment per sample.
    Unlimited,
    /// Main slots + pool addresses + shared pool, merge the two farthest (the paper's method).
    Shared,
    /// `N_fixed` slots per pixel, overflow dropped.
    FixedDiscard,
    /// `N_fixed` slots per pixel, overflow merged (two farthest).
    FixedMerge,
    /// Like `shared`, merging the closest pair in depth.
    MergeClosest,
    /// Bounded memory without the pool's artifacts: main slots + pool
    /// addresses + shared pool; when the pool runs out, the band is drawn again
    /// in halves; a pixel whose list is full merges its closest pair in depth.
    SplitBands,
    /// One sample per pixel, no antialiasing.
    Zbuffer,
    /// The z-buffer with a farthest depth per 8x8 tile; triangles are rejected
    /// per tile before per-pixel tests (exactly the `zbuffer` image).
    ZbufferHiz,
    /// The z-buffer with midpoint subdivision: corners and centroid tested
    /// against the depth buffer decide about whole pieces of triangles
    /// (inexact; see [`MidpointSettings`]).
    ZbufferMidpoint,
    /// Ground truth: `ssaa x ssaa` samples per pixel, each depth-tested and shaded,
    /// box-filtered (see [`crate::ssaa`]); independent of the A-buffer.
    Ssaa,
}

/// The sample grid of coverage masks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Grid {
    /// 4 x 4 samples (16-bit masks).
    #[cfg_attr(feature = "cli", value(name = "4x4"))]
    #[serde(rename = "4x4")]
    G4x4,
    /// 8 columns x 4 rows (32-bit masks).
    #[cfg_attr(feature = "cli", value(name = "8x4"))]
    #[serde(rename = "8x4")]
    G8x4,
    /// 8 x 8 samples (64-bit masks).
    #[cfg_attr(feature = "cli", value(name = "8x8"))]
    #[serde(rename = "8x8")]
    G8x8,
}

impl Grid {
    /// The grid's name on the command line and in the CSV and JSON outputs
    /// (`4x4`, `8x4`, `8x8`).
    pub fn name(self) -> &'static str {
        match self {
            Grid::G4x4 => "4x4",
            Grid::G8x4 => "8x4",
            Grid::G8x8 => "8x8",
        }
    }

    /// Samples per pixel.
    pub fn samples(self) -> usize {
        match self {
            Grid::G4x4 => 16,
            Grid::G8x4 => 32,
            Grid::G8x8 => 64,
        }
    }
}

/// Buffer parameters of one rendering.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct RenderConfig {
    /// Method.
    pub method: Method,
    /// Sample grid.
    pub grid: Grid,
    /// `N_main` (shared, merge-closest).
    pub main: u8,
    /// `N_extra` (shared, merge-closest).
    pub extra: u8,
    /// `N_pool`; `None` picks the library's default (`defaults::POOL_SLOTS`).
    pub pool: Option<usize>,
    /// `N_fixed` (fixed-discard, fixed-merge).
    pub fixed: u8,
    /// Band height `R`.
    pub band: u16,
    /// Samples per pixel side for [`Method::Ssaa`].
    pub ssaa: u8,
    /// Subdivision of [`Method::ZbufferMidpoint`].
    pub midpoint: MidpointSettings,
    /// Rasterize every face of the viewer in full, so that the fragments
    /// generated measure depth complexity (the library's
    /// `FrameOptions::rasterize_every_front_face`; the image is the same).
    pub rasterize_every_front_face: bool,
}

/// How [`Method::ZbufferMidpoint`] subdivides (the library's
/// [`MidpointConfig`], serializable).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct MidpointSettings {
    /// Subdivisions before the first test (`K`).
    pub initial: u8,
    /// Deepest subdivision level (`D`).
    pub max: u8,
    /// Keep per-pixel tests in pieces judged visible.
    pub safe: bool,
}

impl Default for MidpointSettings {
    fn default() -> Self {
        let c = MidpointConfig::DEFAULT;
        Self {
            initial: c.initial_subdivisions,
            max: c.max_depth,
            safe: c.test_visible_pixels,
        }
    }
}

impl MidpointSettings {
    /// The library configuration, or why these settings are not valid.
    pub fn config(&self) -> Result<MidpointConfig, String> {
        let config = MidpointConfig {
            initial_subdivisions: self.initial,
            max_depth: self.max,
            test_visible_pixels: self.safe,
        };
        if config.is_valid() {
            Ok(config)
        } else {
            Err(format!(
                "subdivision depths need K <= D <= {MAX_SUBDIVISION_DEPTH} \
                 (--subdiv-initial {}, --subdiv-max {})",
                self.initial, self.max
            ))
        }
    }
}

impl Default for RenderConfig {
    fn default() -> Self {
        Self {
            method: Method::Shared,
            grid: Grid::G4x4,
            main: defaults::MAIN_SLOTS,
            extra: defaults::EXTRA_ADDRESSES,
            pool: None,
            fixed: defaults::FIXED_SLOTS,
            band: defaults::BAND_ROWS,
            ssaa: 4,
            midpoint: MidpointSettings::default(),
            rasterize_every_front_face: false,
        }
    }
}

/// What a rendering produced.
#[derive(Clone, Debug)]
pub struct RenderOutput {
    /// Image width.
    pub width: u16,
    /// Image height.
    pub height: u16,
    /// RGB888 pixels, rows top to bottom.
    pub rgb: Vec<u8>,
    /// Frame statistics.
    pub stats: FrameStats,
    /// Fragments the rasterizer produced per pixel: the depth complexity
    /// before visibility when [`RenderConfig::rasterize_every_front_face`]
    /// is set (faces turned away that a whole-band test shows hidden are
    /// skipped all the same). All zero for `zbuffer-hiz` and
    /// `zbuffer-midpoint`, whose buffers rasterize (or skip) whole triangles
    /// themselves.
    pub generated_per_pixel: Vec<u16>,
    /// Fragments stored per pixel after all insertions (after visibility and merging).
    pub stored_per_pixel: Vec<u8>,
    /// Pool slots of the configuration (0 for fixed and z-buffer).
    pub pool_slots: usize,
    /// Wall time of the frame, including the buffers' setup.
    pub elapsed: Duration,
}

/// Forwards to a band buffer and counts fragments per pixel over the whole image.
struct CountingBuffer<B> {
    inner: B,
    y0: u16,
    generated: Vec<u16>,
    /// Hand whole triangles to the inner buffer (which decides about them
    /// before rasterizing; its fragments are then not counted).
    forward_triangles: bool,
}

impl<B> CountingBuffer<B> {
    /// Counts one generated fragment at `(x, row)` of the current band.
    fn count<M: CoverageMask>(&mut self, x: u16, row: u16)
    where
        B: BandBuffer<M>,
    {
        let i = (self.y0 as usize + row as usize) * self.inner.width() as usize + x as usize;
        self.generated[i] = self.generated[i].saturating_add(1);
    }
}

impl<M: CoverageMask, B: BandBuffer<M>> BandBuffer<M> for CountingBuffer<B> {
    const ORDER: TriangleOrder = B::ORDER;
    fn width(&self) -> u16 {
        self.inner.width()
    }
    fn band_height(&self) -> u16 {
        self.inner.band_height()
    }
    fn begin_band(&mut self, y0: u16, rows: u16) {
        self.y0 = y0;
        self.inner.begin_band(y0, rows)
    }
    fn draw_triangle(
        &mut self,
        vertices: &[SetupVertex; 3],
        params: &DrawParams<'_>,
        band_y0: u16,
        band_rows: u16,
    ) -> Result<(), Rejection> {
        if self.forward_triangles {
            return self
                .inner
                .draw_triangle(vertices, params, band_y0, band_rows);
        }
        draw_in_band(self, vertices, params, band_y0, band_rows)
    }
    fn hides(&mut self, x: u16, row: u16, depth: i64) -> bool {
        self.inner.hides(x, row, depth)
    }
    fn hidden_run(&mut self, row: u16, x0: u16, x1: u16, depth: i64) -> u32 {
        self.inner.hidden_run(row, x0, x1, depth)
    }
    fn hides_columns(&mut self, x0: u16, x1: u16, depth: i64) -> bool {
        self.inner.hides_columns(x0, x1, depth)
    }
    fn count_triangle_test(&mut self, pixels: u32, hidden: bool) {
        self.inner.count_triangle_test(pixels, hidden)
    }
    fn survives(&mut self, x: u16, row: u16, fragment: &Fragment<M>) -> bool {
        let survives = self.inner.survives(x, row, fragment);
        if !survives {
            self.count(x, row);
        }
        survives
    }
    fn insert(&mut self, x: u16, row: u16, fragment: &Fragment<M>) {
        self.count(x, row);
        self.inner.insert(x, row, fragment)
    }
    fn insert_full_run<W: ColorWalk>(
        &mut self,
        x: u16,
        row: u16,
        run: &FullRun<M>,
        walk: &W,
        color: &mut W::Row,
    ) {
        for k in 0..run.len {
            self.count(x + k, row);
        }
        self.inner.insert_full_run(x, row, run, walk, color)
    }
    fn resolve_row<P: LinePixel>(&mut self, row: u16, background: Rgb888, out: &mut [P]) {
        self.inner.resolve_row(row, background, out)
    }
    fn end_band(&mut self) {
        self.inner.end_band()
    }
    fn pool_use(&self) -> PoolUse {
        self.inner.pool_use()
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

/// Renders `scene` with `config`, turned by `turntable_deg` about the world Y axis.
pub fn render(
    scene: &FixedScene,
    config: &RenderConfig,
    turntable_deg: f32,
) -> Result<RenderOutput, String> {
    let mut frames = render_frames(scene, config, &[turntable_deg])?;
    Ok(frames.remove(0))
}

/// Renders `scene` with `config` once for each angle of `turntable_degs`, frame
/// after frame through the same band buffer and frame workspace, as a device
/// does: what one frame leaves in them is what the next one finds. The first
/// frame's time includes the buffers' setup.
pub fn render_frames(
    scene: &FixedScene,
    config: &RenderConfig,
    turntable_degs: &[f32],
) -> Result<Vec<RenderOutput>, String> {
    // Refused here, before any buffer is sized from the scene: NaN has no
    // fixed-point angle, and a zero-sized image has no band.
    if turntable_degs.iter().any(|a| a.is_nan()) {
        return Err("the turntable angle is not a number".into());
    }
    scene
        .scene(&scene.objects())
        .validate()
        .map_err(|e| format!("invalid scene: {e}"))?;
    if config.method == Method::Ssaa {
        return turntable_degs
            .iter()
            .map(|&a| crate::ssaa::render_ssaa(scene, config.ssaa, a))
            .collect();
    }
    let start = Instant::now();
    let (w, h) = (scene.width, scene.height);
    let band = config.band.clamp(1, h);
    let objects = scene.objects();
    let lib_scene = scene.scene(&objects);
    let mut frames = Frames {
        scene: &lib_scene,
        turntable_degs,
        workspace: OwnedWorkspace::for_scene(&lib_scene),
        forward_triangles: matches!(config.method, Method::ZbufferHiz | Method::ZbufferMidpoint),
        rasterize_every_front_face: config.rasterize_every_front_face,
        pool_slots: 0,
        start,
    };
    if matches!(
        config.method,
        Method::Zbuffer | Method::ZbufferHiz | Method::ZbufferMidpoint
    ) {
        let mut depth = vec![0u32; w as usize * band as usize];
        let mut color = vec![Rgb888::new(0, 0, 0); w as usize * band as usize];
        return match config.method {
            Method::ZbufferHiz => {
                let mut tiles = vec![HizTile::EMPTY; tile_count(w, band)];
                let zb = HierarchicalZBuffer::new(w, band, &mut depth, &mut color, &mut tiles)
                    .ok_or("z-buffer storage")?;
                frames.run::<Mask1x1, _>(zb)
            }
            Method::ZbufferMidpoint => {
                let midpoint = config.midpoint.config()?;
                let zb = MidpointZBuffer::new(w, band, &mut depth, &mut color, midpoint)
                    .ok_or("z-buffer storage")?;
                frames.run::<Mask1x1, _>(zb)
            }
            _ => {
                let zb = ZBuffer::new(w, band, &mut depth, &mut color).ok_or("z-buffer storage")?;
                frames.run::<Mask1x1, _>(zb)
            }
        };
    }
    let samples = config.grid.samples();
    let (policy, main, extra, pool) = match config.method {
        Method::Unlimited => {
            let extra = samples - 1;
            (
                OverflowPolicy::MergeFarthest,
                1u8,
                extra as u8,
                w as usize * band as usize * extra,
            )
        }
        Method::Shared => (
            OverflowPolicy::MergeFarthest,
            config.main,
            config.extra,
            config.pool.unwrap_or(defaults::POOL_SLOTS),
        ),
        Method::MergeClosest => (
            OverflowPolicy::MergeClosest,
            config.main,
            config.extra,
            config.pool.unwrap_or(defaults::POOL_SLOTS),
        ),
        Method::SplitBands => (
            OverflowPolicy::SplitBands,
            config.main,
            config.extra,
            config.pool.unwrap_or(defaults::POOL_SLOTS),
        ),
        Method::FixedDiscard => (OverflowPolicy::Discard, config.fixed, 0, 0),
        Method::FixedMerge => (OverflowPolicy::MergeFarthest, config.fixed, 0, 0),
        Method::Zbuffer | Method::ZbufferHiz | Method::ZbufferMidpoint | Method::Ssaa => {
            unreachable!()
        }
    };
    frames.pool_slots = pool;
    let cfg = BufferConfig {
        width: w,
        band_height: band,
        main_slots: main,
        extra_addresses: extra,
        policy,
    };
    match config.grid {
        Grid::G4x4 => {
            let mut storage = abuffer::<Mask4x4, u32>(cfg, pool)?;
            frames.run(storage.try_buffer().map_err(|e| e.to_string())?)
        }
        Grid::G8x4 => {
            let mut storage = abuffer::<Mask8x4, u32>(cfg, pool)?;
            frames.run(storage.try_buffer().map_err(|e| e.to_string())?)
        }
        Grid::G8x8 => {
            let mut storage = abuffer::<Mask8x8, u32>(cfg, pool)?;
            frames.run(storage.try_buffer().map_err(|e| e.to_string())?)
        }
    }
}

/// The frames [`render_frames`] draws, and what they share besides the band buffer.
struct Frames<'s> {
    scene: &'s Scene<'s>,
    turntable_degs: &'s [f32],
    workspace: OwnedWorkspace,
    forward_triangles: bool,
    /// [`RenderConfig::rasterize_every_front_face`].
    rasterize_every_front_face: bool,
    pool_slots: usize,
    start: Instant,
}

impl Frames<'_> {
    /// Renders every frame through `buffer`, counting fragments per pixel.
    fn run<M: CoverageMask, B: BandBuffer<M>>(
        mut self,
        buffer: B,
    ) -> Result<Vec<RenderOutput>, String> {
        let (w, h) = (self.scene.width, self.scene.height);
        let pixels = w as usize * h as usize;
        let mut counting = CountingBuffer {
            inner: buffer,
            y0: 0,
            generated: Vec::new(),
            forward_triangles: self.forward_triangles,
        };
        let mut outputs = Vec::with_capacity(self.turntable_degs.len());
        for &angle in self.turntable_degs {
            let options = FrameOptions {
                turntable_deg: Coord::saturating_from_num(angle),
                rasterize_every_front_face: self.rasterize_every_front_face,
            };
            counting.generated = vec![0; pixels];
            let mut stored = vec![0u8; pixels];
            let frame = render_rgb(
                self.scene,
                &options,
                &mut self.workspace,
                &mut counting,
                |y0, rows, b| {
                    for row in 0..rows {
                        for x in 0..w {
                            let n = b.pixel_fragment_count(x, row).min(255) as u8;
                            stored[(y0 + row) as usize * w as usize + x as usize] = n;
                        }
                    }
                },
            )
            .map_err(|e| e.to_string())?;
            outputs.push(RenderOutput {
                width: w,
                height: h,
                rgb: frame.rgb,
                stats: frame.stats,
                generated_per_pixel: std::mem::take(&mut counting.generated),
                stored_per_pixel: stored,
                pool_slots: self.pool_slots,
                elapsed: self.start.elapsed(),
            });
            self.start = Instant::now();
        }
        Ok(outputs)
    }
}

/// Storage for a fragment buffer of `config` with `pool` slots, or why the
/// pool is larger than an address of type `A` reaches (before allocating it).
pub fn abuffer<M: CoverageMask, A: PoolAddress>(
    config: BufferConfig,
    pool: usize,
) -> Result<FragmentStorage<M, A>, String> {
    if pool > A::MAX_POOL {
        return Err(format!(
            "pool of {pool} slots exceeds the {} an address can reach",
            A::MAX_POOL
        ));
    }
    Ok(FragmentStorage::new(config, pool))
}
