//! The frame driver: transforms every vertex once, bins triangles by their first
//! row, then renders the image band by band into a [`BandBuffer`] and streams the
//! resolved lines to a [`LineSink`].
//!
//! Order of work within a pixel is the same for every band height: each band
//! draws its active triangles in one total order, the faces of the viewer before
//! those turned away and each group nearest first ([`crate::draw_order`]). Only
//! the band's pixel memory depends on `R`.

use crate::band_buffer::{BandBuffer, DrawParams};
use crate::clip::{clip_triangle, ClipVertex};
use crate::color_carry::{CarriedColors, ColorCarry};
use crate::coverage::CoverageMask;
use crate::draw_order::DrawOrder;
use crate::fixed_point::{Coord, DEPTH_MAX, GUARD_BAND_PX, SUBPIXEL_BITS};
use crate::geometry::{outcode_and_project, project, ObjectTransform, ViewBasis, OUT_NEAR};
use crate::lighting::{color_q8, normalize_unit, rgb888_rounded, LightSetup};
use crate::openings::OpeningBoxes;
use crate::scene::{Scene, SceneError, Shading};
use crate::setup::{is_backfacing, signed_area2, SetupVertex, TriangleSetup};
use crate::shading::{clipped_piece_source, ColorSource, TriangleLighting};
use crate::sink::LineSink;
use crate::stats::{FrameStats, GeometryStats};
use core::cell::{Cell, RefCell};
use embedded_graphics_core::pixelcolor::Rgb888;

/// A vertex after transformation: window position, depth, outcode and lit
/// color, packed into three words (12 bytes instead of 16: the frame
/// workspace holds one per vertex of the scene).
///
/// Position and depth are valid when [`ScreenVertex::outcode`] is zero; they
/// are kept within the guard band (`±2^16` in 1/16 pixel, 18 bits) and below
/// `2^24` ([`DEPTH_MAX`]), which leaves room for the outcode (6 bits) and
/// the color's three bytes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ScreenVertex {
    /// `x << 14 | outcode << 8 | red`.
    x_outcode_red: i32,
    /// `y << 8 | green`.
    y_green: i32,
    /// `z | blue << 24`.
    z_blue: u32,
}

impl ScreenVertex {
    /// All zero: the initial value of workspace arrays (`static` arrays included).
    pub const EMPTY: Self = Self {
        x_outcode_red: 0,
        y_green: 0,
        z_blue: 0,
    };

    /// A vertex at window position `x`, `y` (1/16 pixel, clamped to the guard
    /// band), depth `z` (24 fraction bits, clamped to [`DEPTH_MAX`]), with
    /// `color` and `outcode` (the clip planes it is outside of; six bits).
    #[inline]
    pub fn new(x: i32, y: i32, z: u32, color: [u8; 3], outcode: u8) -> Self {
        let lim = GUARD_BAND_PX << SUBPIXEL_BITS;
        let (x, y) = (x.clamp(-lim, lim), y.clamp(-lim, lim));
        Self {
            x_outcode_red: (x << 14) | ((outcode & 0x3f) as i32) << 8 | color[0] as i32,
            y_green: (y << 8) | color[1] as i32,
            z_blue: z.min(DEPTH_MAX) | (color[2] as u32) << 24,
        }
    }

    /// x in 1/16 pixel.
    #[inline]
    pub fn x(&self) -> i32 {
        self.x_outcode_red >> 14
    }

    /// y in 1/16 pixel.
    #[inline]
    pub fn y(&self) -> i32 {
        self.y_green >> 8
    }

    /// Depth, 24 fraction bits.
    #[inline]
    pub fn z(&self) -> u32 {
        self.z_blue & DEPTH_MAX
    }

    /// Vertex color (lit, or the object's color).
    #[inline]
    pub fn color(&self) -> Rgb888 {
        Rgb888::new(
            self.x_outcode_red as u8,
            self.y_green as u8,
            (self.z_blue >> 24) as u8,
        )
    }

    /// Clip planes the vertex is outside of ([`crate::geometry::outcode`]).
    #[inline]
    pub fn outcode(&self) -> u8 {
        (self.x_outcode_red >> 8) as u8 & 0x3f
    }
}

/// Per-object state of the current frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ObjectFrame {
    /// Model to clip space and normal transform.
    pub transform: ObjectTransform,
    /// Index of the object's first vertex in the vertex array.
    pub vertex_base: u32,
    /// Index of the object's first triangle over all objects.
    pub triangle_base: u32,
    /// Where the object's openings lie on screen: which faces turned away
    /// can show.
    pub(crate) openings: OpeningBoxes,
    /// The scene's light in the object's model space
    /// ([`LightSetup::in_model_space`]): its normals are lit as they are.
    pub(crate) light: LightSetup,
}

impl ObjectFrame {
    /// All zero: the initial value of workspace arrays (`static` arrays included);
    /// every frame overwrites it.
    pub const EMPTY: Self = Self {
        transform: ObjectTransform {
            clip: crate::geometry::ClipTransform {
                rows: [[0; 3]; 4],
                offsets: [0; 4],
            },
            normal: [[0; 3]; 3],
        },
        vertex_base: 0,
        triangle_base: 0,
        openings: OpeningBoxes::DRAW_ALL,
        light: LightSetup::NONE,
    };
}

/// Working memory of a frame, borrowed from the caller (static arrays on a device).
pub struct FrameWorkspace<'a> {
    /// One entry per scene object.
    pub objects: &'a mut [ObjectFrame],
    /// One entry per vertex over all objects.
    pub vertices: &'a mut [ScreenVertex],
    /// One entry per triangle over all objects: its last row (below 2048, the
    /// largest image side) and whether it faces away, or a skip mark
    /// (`u16::MAX`).
    pub triangle_rows: &'a mut [u16],
    /// One entry per triangle: the visiting order (facing, nearest depth,
    /// object and triangle in one word; at most 255 objects, and object and
    /// triangle numbers within 30 bits together, else
    /// [`RenderError::TooManyObjects`]).
    ///
    /// Its first entries double as each band's list of active triangles, so a band
    /// can have every triangle of the scene active: there is no per-band bin to
    /// overflow, and nothing is dropped however many triangles share a band.
    pub triangle_order: &'a mut [u32],
    /// `height + 1` entries for the counting sort by first row (counts of
    /// triangles, below 2^32).
    pub row_starts: &'a mut [u32],
    /// Color planes carried from one band to the next (any number of
    /// entries, none included: the image is the same, only the work
    /// differs; see [`crate::color_carry`]).
    pub carried_colors: &'a mut [CarriedColors],
}

/// Which workspace array is too small.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum WorkspacePart {
    /// `objects`.
    Objects,
    /// `vertices`.
    Vertices,
    /// `triangle_rows` or `triangle_order`.
    Triangles,
    /// `row_starts`.
    Rows,
}

/// Why a frame could not be rendered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RenderError<E> {
    /// The scene is invalid.
    Scene(SceneError),
    /// A workspace array is smaller than the scene needs.
    Workspace {
        /// Which array.
        part: WorkspacePart,
        /// Entries needed.
        needed: usize,
        /// Entries available.
        available: usize,
    },
    /// The band buffer's width differs from the image width.
    BufferWidth {
        /// Buffer width.
        buffer: u16,
        /// Image width.
        image: u16,
    },
    /// Too many objects or triangles in one object for the order encoding.
    TooManyObjects,
    /// The sink failed.
    Sink(E),
}

impl<E: core::fmt::Debug> core::fmt::Display for RenderError<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Scene(e) => write!(f, "invalid scene: {e}"),
            Self::Workspace {
                part,
                needed,
                available,
            } => {
                write!(
                    f,
                    "workspace {part:?} holds {available} entries, the scene needs {needed}"
                )
            }
            Self::BufferWidth { buffer, image } => {
                write!(f, "band buffer is {buffer} pixels wide, image is {image}")
            }
            Self::TooManyObjects => {
                write!(
                    f,
                    "at most 255 objects, whose object and triangle numbers fit 30 bits together"
                )
            }
            Self::Sink(e) => write!(f, "line sink failed: {e:?}"),
        }
    }
}

/// Per-frame options.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameOptions {
    /// Extra rotation of every object about the world Y axis, degrees (turntables).
    pub turntable_deg: Coord,
    /// Rasterize every face of the viewer in full, so that the buffer's
    /// count of fragments generated measures the scene's depth complexity.
    /// When `false` (the default), a face of the viewer drawn right after a
    /// triangle the buffer hid meets the whole-band test first and is
    /// skipped when the band hides it. The image is the same either way;
    /// only the counts of fragments differ.
    pub rasterize_every_front_face: bool,
}

/// `triangle_rows` entry of a triangle that is not drawn.
const SKIP_ROW: u16 = u16::MAX;
/// `triangle_rows` flag of a triangle facing away (drawn after the front faces).
const BACK_FACING: u16 = 1 << 14;
/// `triangle_rows` bits of the row.
const ROW_BITS: u16 = BACK_FACING - 1;

#[inline]
fn last_row(entry: u16) -> u16 {
    entry & ROW_BITS
}

#[inline]
fn is_back(entry: u16) -> bool {
    entry & BACK_FACING != 0
}
struct FrameContext<'s, 'a> {
    scene: &'s Scene<'a>,
    light: Option<LightSetup>,
    order: DrawOrder,
}

impl FrameContext<'_, '_> {
    fn shading(&self, object: usize) -> Shading {
        if self.light.is_some() {
            self.scene.objects[object].shading
        } else {
            Shading::Unlit
        }
    }
}

fn check<E>(part: WorkspacePart, needed: usize, available: usize) -> Result<(), RenderError<E>> {
    if available < needed {
        Err(RenderError::Workspace {
            part,
            needed,
            available,
        })
    } else {
        Ok(())
    }
}

/// Draws scenes: a frame workspace and a band buffer, borrowed for as long as
/// the renderer lives (on a device, from `static`s made with
/// [`crate::memory`]).
///
/// ```
/// use mcu_abuffer::memory::{FragmentMemory, WorkspaceMemory};
/// use mcu_abuffer::{FrameOptions, ImageSink, Mask4x4, OverflowPolicy, Renderer};
/// # use mcu_abuffer::fixed_point::Coord;
/// # use mcu_abuffer::scene::*;
/// # use embedded_graphics_core::pixelcolor::Rgb888;
/// # let objects = [SceneObject { mesh: OCTAHEDRON, color: Rgb888::new(200, 120, 60),
/// #     transform: Transform::default(), cull_backfaces: true, shading: Shading::Gouraud }];
/// # let scene = Scene { width: 32, height: 24, background: Rgb888::new(0, 0, 0),
/// #     camera: Camera { eye: [Coord::ZERO, Coord::ONE, Coord::from_num(4)],
/// #         target: [Coord::ZERO; 3], up: [Coord::ZERO, Coord::ONE, Coord::ZERO],
/// #         fov_y_deg: Coord::from_num(40), near: Coord::ONE, far: Coord::from_num(10) },
/// #     light: None, objects: &objects };
///
/// let mut fragments = Box::new(FragmentMemory::<Mask4x4, 32, 8, 1, 2, 64>::new());
/// let mut workspace = Box::new(WorkspaceMemory::<24, 1, 8, 12>::new());
/// let mut renderer = Renderer::new(
///     workspace.workspace(),
///     fragments.buffer(OverflowPolicy::SplitBands),
/// );
/// let mut rgb = [0u8; 32 * 24 * 3];
/// let stats = renderer
///     .render(&scene, &FrameOptions::default(), &mut ImageSink::new(32, &mut rgb))
///     .unwrap();
/// assert!(stats.buffer.fragments_stored > 0);
/// ```
pub struct Renderer<'m, M: CoverageMask, B: BandBuffer<M>> {
    workspace: FrameWorkspace<'m>,
    buffer: B,
    mask: core::marker::PhantomData<M>,
}

impl<'m, M: CoverageMask, B: BandBuffer<M>> Renderer<'m, M, B> {
    /// A renderer working in `workspace` and `buffer`.
    pub fn new(workspace: FrameWorkspace<'m>, buffer: B) -> Self {
        Self {
            workspace,
            buffer,
            mask: core::marker::PhantomData,
        }
    }

    /// Renders one frame of `scene` into `sink`, line by line from the top.
    /// A scene larger than the workspace or wider than the buffer is refused
    /// with the part that is too small; nothing is drawn then.
    pub fn render<S: LineSink>(
        &mut self,
        scene: &Scene<'_>,
        options: &FrameOptions,
        sink: &mut S,
    ) -> Result<FrameStats, RenderError<S::Error>> {
        self.render_observed(scene, options, sink, |_, _, _| {})
    }

    /// As [`Self::render`], calling `on_band(y0, rows, buffer)` after each
    /// band's fragments are in and before it is resolved (depth-complexity
    /// maps, per-band statistics).
    pub fn render_observed<S: LineSink, F: FnMut(u16, u16, &B)>(
        &mut self,
        scene: &Scene<'_>,
        options: &FrameOptions,
        sink: &mut S,
        on_band: F,
    ) -> Result<FrameStats, RenderError<S::Error>> {
        render_frame(
            scene,
            options,
            &mut self.workspace,
            &mut self.buffer,
            sink,
            on_band,
        )
    }

    /// The band buffer (its configuration and statistics).
    pub fn buffer(&self) -> &B {
        &self.buffer
    }

    /// The band buffer, mutably (to wrap or reconfigure it between frames).
    pub fn buffer_mut(&mut self) -> &mut B {
        &mut self.buffer
    }

    /// The workspace and the buffer back.
    pub fn into_parts(self) -> (FrameWorkspace<'m>, B) {
        (self.workspace, self.buffer)
    }
}

/// Renders one frame of `scene` band by band through `buffer` into `sink`.
///
/// `on_band(y0, rows, buffer)` is called after each band's fragments are in, before
/// it is resolved (for depth-complexity maps; pass `|_, _, _| {}` otherwise).
pub fn render_frame<M, B, S, F>(
    scene: &Scene<'_>,
    options: &FrameOptions,
    ws: &mut FrameWorkspace<'_>,
    buffer: &mut B,
    sink: &mut S,
    mut on_band: F,
) -> Result<FrameStats, RenderError<S::Error>>
where
    M: CoverageMask,
    B: BandBuffer<M>,
    S: LineSink,
    F: FnMut(u16, u16, &B),
{
    scene.validate().map_err(RenderError::Scene)?;
    let n_vertices = scene.vertex_count();
    let n_triangles = scene.triangle_count();
    check(
        WorkspacePart::Objects,
        scene.objects.len(),
        ws.objects.len(),
    )?;
    check(WorkspacePart::Vertices, n_vertices, ws.vertices.len())?;
    check(
        WorkspacePart::Triangles,
        n_triangles,
        ws.triangle_rows.len().min(ws.triangle_order.len()),
    )?;
    check(
        WorkspacePart::Rows,
        scene.height as usize + 1,
        ws.row_starts.len(),
    )?;
    if buffer.width() != scene.width {
        return Err(RenderError::BufferWidth {
            buffer: buffer.width(),
            image: scene.width,
        });
    }
    let most_triangles = scene.objects.iter().map(|o| o.mesh.triangles.len());
    let most_triangles = most_triangles.max().unwrap_or(0);
    let order = DrawOrder::new(scene.objects.len(), most_triangles, B::ORDER)
        .filter(|_| scene.objects.len() <= 255)
        .ok_or(RenderError::TooManyObjects)?;
    let view = ViewBasis::new(&scene.camera).ok_or(RenderError::Scene(SceneError::CameraBasis))?;
    let ctx = FrameContext {
        scene,
        light: scene.light.as_ref().map(|l| LightSetup::new(l, &view)),
        order,
    };
    let mut stats = FrameStats::default();
    stats.geometry.triangles_in = n_triangles as u32;

    transform_vertices(&ctx, &view, options, ws);
    let binned = bin_triangles(&ctx, ws, &mut stats.geometry);
    let carry = RefCell::new(ColorCarry::new(ws.carried_colors));
    let color_requests = Cell::new(0u32);
    let frame = FrameVertices {
        objects: ws.objects,
        vertices: ws.vertices,
        carry: &carry,
        color_requests: &color_requests,
    };

    // Bands.
    let (width, height) = (scene.width, scene.height);
    let band_height = buffer.band_height().max(1);
    let mut active = 0usize;
    let mut next = 0usize;
    let mut y0 = 0u16;
    // Rows of the band being drawn. When the buffer asks for smaller bands
    // (its shared pool ran out), the rows are drawn again as halves; the next
    // band keeps the height that fitted, or doubles it (up to the band height)
    // when the band used little of the pool.
    // Within a pixel the order of work is the same for every band height, so
    // the image does not depend on how the rows were split.
    let mut rows = band_height.min(height);
    while y0 < height {
        rows = rows.min(height - y0);
        let y_end = y0 + rows;
        buffer.begin_band(y0, rows);
        // Drop triangles that ended above this band, keeping the order.
        let mut kept = 0;
        for i in 0..active {
            let t = ws.triangle_order[i];
            if last_row(ws.triangle_rows[global_index(&ctx, ws.objects, t)]) >= y0 {
                ws.triangle_order[kept] = t;
                kept += 1;
            }
        }
        active = kept;
        // Add triangles that start in this band (the counting sort's row
        // starts), in drawing order: front faces first, then the back faces
        // of two-sided objects, each nearest first. Surfaces drawn early
        // hide what arrives behind them, which then costs no colors and no
        // memory.
        let starting = (ws.row_starts[y_end as usize - 1] as usize).min(binned);
        if next < starting {
            active = DrawOrder::admit(ws.triangle_order, active, (next, starting), binned);
            next = starting;
        }
        // Whether the buffer hid the last triangle: it asked for no colors,
        // and fragments or the whole triangle were hidden. Triangles drawn
        // nearest first come hidden in runs, behind whatever hid the first.
        let mut after_hidden = false;
        for &t in &ws.triangle_order[..active] {
            let (requests, hidden) = (color_requests.get(), buffer.hidden_count());
            let band = (y0, rows, after_hidden);
            draw_triangle(&ctx, &frame, t, band, buffer, &mut stats.geometry);
            after_hidden = !options.rasterize_every_front_face
                && color_requests.get() == requests
                && buffer.hidden_count() != hidden;
            if rows > 1 && buffer.pool_use().ran_out {
                break;
            }
        }
        let pool = buffer.pool_use();
        if rows > 1 && pool.ran_out {
            // Draw the same rows again as two bands of half the height: the
            // active list still holds every triangle that touches them.
            buffer.end_band();
            stats.band_splits += 1;
            rows = rows.div_ceil(2);
            continue;
        }
        stats.bands += 1;
        on_band(y0, rows, buffer);
        for row in 0..rows {
            // Resolved straight into the sink's line, in its pixel format.
            let resolve = |line: &mut [S::Pixel]| buffer.resolve_row(row, scene.background, line);
            sink.fill_line(y0 + row, width, resolve)
                .map_err(RenderError::Sink)?;
        }
        buffer.end_band();
        y0 = y_end;
        // A band that used at most a third of the pool: twice its rows likely
        // fit. Measured with 8-row bands and 512 slots (teapot on the M4: a
        // third 59.0 M instructions, 40 % 60.1 M, a half 63.9 M, never growing
        // back 65.7 M); in the default memory (6 rows, 1,152 slots) a third and
        // a half give the same counts on all four benchmark scenes.
        if rows < band_height && pool.peak * 3 <= pool.capacity {
            rows = (rows * 2).min(band_height);
        }
    }
    let carried = carry.into_inner().carried;
    stats.geometry.color_setups = color_requests.get() - carried;
    stats.geometry.colors_carried = carried;
    stats.buffer = buffer.take_stats();
    Ok(stats)
}

fn transform_vertices(
    ctx: &FrameContext<'_, '_>,
    view: &ViewBasis,
    options: &FrameOptions,
    ws: &mut FrameWorkspace<'_>,
) {
    let scene = ctx.scene;
    let mut base = 0u32;
    let mut triangle_base = 0u32;
    for (oi, object) in scene.objects.iter().enumerate() {
        let transform = ObjectTransform::new(
            &scene.camera,
            view,
            scene.width,
            scene.height,
            &object.transform,
            options.turntable_deg,
        );
        let light = ctx.light.map(|l| l.in_model_space(&transform.normal));
        ws.objects[oi] = ObjectFrame {
            transform,
            vertex_base: base,
            triangle_base,
            openings: OpeningBoxes::DRAW_ALL,
            light: light.unwrap_or(LightSetup::NONE),
        };
        triangle_base += object.mesh.triangles.len() as u32;
        let shading = ctx.shading(oi);
        let base_color = object.color;
        let flat = [base_color.r(), base_color.g(), base_color.b()];
        let mesh = &object.mesh;
        let mut codes = 0u8;
        for (i, p) in mesh.positions.iter().enumerate() {
            let c = transform.to_clip(p);
            let (code, (x, y, z)) = outcode_and_project(&c);
            codes |= code;
            let color = match (shading, &light) {
                (Shading::Gouraud | Shading::Quadratic, Some(light)) => {
                    let n = mesh.normals[i].map(|v| v.to_bits() as i32);
                    light.shade_rounded(&n, base_color)
                }
                _ => flat,
            };
            ws.vertices[base as usize + i] = ScreenVertex::new(x, y, z, color, code);
        }
        let vertices = base as usize..base as usize + mesh.positions.len();
        if let (Some(openings), false) = (mesh.openings, object.cull_backfaces) {
            ws.objects[oi].openings =
                OpeningBoxes::of(openings, &ws.vertices[vertices], codes & OUT_NEAR == 0);
        }
        base += mesh.positions.len() as u32;
    }
}

use embedded_graphics_core::pixelcolor::RgbColor;

#[inline]
fn global_index(ctx: &FrameContext<'_, '_>, objects: &[ObjectFrame], t: u32) -> usize {
    let (o, i) = ctx.order.split(t);
    objects[o].triangle_base as usize + i
}

#[inline]
fn corners_of(
    ctx: &FrameContext<'_, '_>,
    objects: &[ObjectFrame],
    vertices: &[ScreenVertex],
    t: u32,
) -> [ScreenVertex; 3] {
    let (o, i) = ctx.order.split(t);
    let base = objects[o].vertex_base as usize;
    let tri = ctx.scene.objects[o].mesh.triangles[i];
    // Written out rather than `tri.map`: the map's array was built on the
    // stack and copied to the caller's once more.
    let corner = |k: usize| vertices[base + tri[k] as usize];
    [corner(0), corner(1), corner(2)]
}

#[inline]
fn corners(ctx: &FrameContext<'_, '_>, ws: &FrameWorkspace<'_>, t: u32) -> [ScreenVertex; 3] {
    corners_of(ctx, ws.objects, ws.vertices, t)
}

fn setup_vertex(v: &ScreenVertex) -> SetupVertex {
    SetupVertex {
        x: v.x(),
        y: v.y(),
        z: v.z(),
    }
}

/// The rows a drawn triangle spans on screen, `(first, last)`, and whether it
/// faces away; `None` when it is not drawn (counted in `stats`). Clipped
/// triangles are clipped here to find their rows, and count as facing the
/// viewer (their pieces decide for themselves).
fn triangle_rows(
    ctx: &FrameContext<'_, '_>,
    ws: &FrameWorkspace<'_>,
    t: u32,
    stats: &mut GeometryStats,
) -> Option<(u16, u16, bool)> {
    let scene = ctx.scene;
    let (width, height) = (scene.width as i32, scene.height as i32);
    let v = corners(ctx, ws, t);
    let and = v[0].outcode() & v[1].outcode() & v[2].outcode();
    let or = v[0].outcode() | v[1].outcode() | v[2].outcode();
    let (o, i) = ctx.order.split(t);
    let object = &scene.objects[o];
    let (min_y, max_y, back) = if and != 0 {
        stats.triangles_outside += 1;
        return None;
    } else if or != 0 {
        stats.triangles_clipped += 1;
        let transform = &ws.objects[o].transform;
        let tri = object.mesh.triangles[i];
        let clip_in: [ClipVertex; 3] = core::array::from_fn(|k| ClipVertex {
            clip: transform.to_clip(&object.mesh.positions[tri[k] as usize]),
            color: [0; 3],
            normal: [0; 3],
        });
        let poly = clip_triangle(&clip_in, or);
        if poly.len < 3 {
            return None;
        }
        let ys = poly.vertices[..poly.len].iter().map(|p| project(&p.clip).1);
        let (lo, hi) = ys.fold((i32::MAX, i32::MIN), |(lo, hi), y| (lo.min(y), hi.max(y)));
        (lo >> SUBPIXEL_BITS, hi >> SUBPIXEL_BITS, false)
    } else {
        let area2 = signed_area2(&v.map(|p| setup_vertex(&p)));
        // Facing first: a culled object's faces turned away (about half of
        // them) need nothing more.
        if area2 == 0 {
            stats.triangles_degenerate += 1;
            return None;
        } else if object.cull_backfaces && is_backfacing(area2) {
            stats.triangles_backfacing += 1;
            return None;
        }
        let min_x = v.iter().map(|p| p.x()).min().unwrap_or(0) >> SUBPIXEL_BITS;
        let max_x = v.iter().map(|p| p.x()).max().unwrap_or(0) >> SUBPIXEL_BITS;
        let min_y = v.iter().map(|p| p.y()).min().unwrap_or(0) >> SUBPIXEL_BITS;
        let max_y = v.iter().map(|p| p.y()).max().unwrap_or(0) >> SUBPIXEL_BITS;
        if max_x < 0 || max_y < 0 || min_x >= width || min_y >= height {
            stats.triangles_outside += 1;
            return None;
        }
        let back = is_backfacing(area2);
        if back && ws.objects[o].openings.hide_face(min_x, max_x, min_y, max_y) {
            stats.triangles_backfacing += 1;
            return None;
        }
        (min_y, max_y, back)
    };
    if max_y < 0 || min_y >= height {
        stats.triangles_outside += 1;
        return None;
    }
    Some((min_y.max(0) as u16, max_y.min(height - 1) as u16, back))
}

/// Sorts the drawn triangles by first row (counting sort, stable), returns how
/// many. Afterwards `row_starts[r]` is the number of triangles that start at
/// rows up to `r`, and `triangle_rows` holds each drawn triangle's last row
/// and facing (`SKIP_ROW` for the others).
fn bin_triangles(
    ctx: &FrameContext<'_, '_>,
    ws: &mut FrameWorkspace<'_>,
    stats: &mut GeometryStats,
) -> usize {
    let scene = ctx.scene;
    let height = scene.height as usize;
    ws.row_starts[..height + 1].fill(0);
    let mut g = 0usize;
    let mut binned = 0usize;
    // Count by first row; each entry keeps its triangle's last row and facing.
    for (oi, object) in scene.objects.iter().enumerate() {
        for ti in 0..object.mesh.triangles.len() {
            let t = ctx.order.number(oi, ti);
            ws.triangle_rows[g] = match triangle_rows(ctx, ws, t, stats) {
                Some((first, last, back)) => {
                    ws.row_starts[first as usize + 1] += 1;
                    binned += 1;
                    last | if back { BACK_FACING } else { 0 }
                }
                None => SKIP_ROW,
            };
            g += 1;
        }
    }
    for r in 0..height {
        ws.row_starts[r + 1] += ws.row_starts[r];
    }
    // Scatter by first row (found again: the lowest corner, or the clipped polygon's).
    let mut g = 0usize;
    let mut unused = GeometryStats::default();
    for (oi, object) in scene.objects.iter().enumerate() {
        for ti in 0..object.mesh.triangles.len() {
            let entry = ws.triangle_rows[g];
            if entry != SKIP_ROW {
                let t = ctx.order.number(oi, ti);
                let v = corners(ctx, ws, t);
                let first = if v.iter().any(|p| p.outcode() != 0) {
                    triangle_rows(ctx, ws, t, &mut unused).map_or(0, |(first, _, _)| first)
                } else {
                    let top = v.iter().map(|p| p.y()).min().unwrap_or(0) >> SUBPIXEL_BITS;
                    top.max(0) as u16
                };
                let nearest = v.iter().map(|p| p.z()).min().unwrap_or(0);
                let slot = &mut ws.row_starts[first as usize];
                ws.triangle_order[*slot as usize] =
                    ctx.order.entry((oi, ti), is_back(entry), nearest, first);
                *slot += 1;
            }
            g += 1;
        }
    }
    binned
}

/// What color setup needs of triangle `t` (corners `corners`): its vertex
/// colors, model-space normals and the object's light, as its shading asks.
// Always inlined into the request for colors: 0.11 M fewer instructions on
// the teapot's antialiased frame than the compiler's choice (out of line).
#[inline(always)]
fn color_source<'f>(
    ctx: &'f FrameContext<'_, '_>,
    objects: &'f [ObjectFrame],
    t: u32,
    corners: &[ScreenVertex; 3],
) -> ColorSource<'f> {
    let colors = || corners.map(|p| color_q8(p.color()));
    let (o, i) = ctx.order.split(t);
    let object = &ctx.scene.objects[o];
    let normal = |v: u32| object.mesh.normals[v as usize].map(|c| c.to_bits() as i32);
    let model_normals = || object.mesh.triangles[i].map(normal);
    let light = ctx.light.as_ref().map(|_| &objects[o].light);
    match (ctx.shading(o), light) {
        (Shading::Gouraud, Some(_)) => ColorSource::Linear(colors()),
        (Shading::Quadratic, Some(light)) => ColorSource::Quadratic(
            TriangleLighting {
                normals: model_normals(),
                light,
                base: object.color,
            },
            corners.map(|p| p.color()),
        ),
        (Shading::Phong, Some(light)) => ColorSource::Phong(TriangleLighting {
            normals: model_normals(),
            light,
            base: object.color,
        }),
        (Shading::Flat, Some(light)) => {
            let tri = object.mesh.triangles[i];
            let mut sum = [0i64; 3];
            for v in tri {
                let n = normal(v);
                for k in 0..3 {
                    sum[k] += n[k] as i64;
                }
            }
            match normalize_unit(sum) {
                Some(n) => ColorSource::Constant(rgb888_rounded(light.shade(&n, object.color))),
                None => ColorSource::Constant(object.color),
            }
        }
        _ => ColorSource::Constant(object.color),
    }
}

/// What drawing a triangle in a band reads of the frame: the objects'
/// transforms and the transformed vertices; the carried colors, and a count
/// of the triangles whose colors were asked for.
struct FrameVertices<'f, 'c> {
    objects: &'f [ObjectFrame],
    vertices: &'f [ScreenVertex],
    carry: &'f RefCell<ColorCarry<'c>>,
    color_requests: &'f Cell<u32>,
}

fn draw_triangle<M: CoverageMask, B: BandBuffer<M>>(
    ctx: &FrameContext<'_, '_>,
    frame: &FrameVertices<'_, '_>,
    t: u32,
    (y0, rows, after_hidden): (u16, u16, bool),
    buffer: &mut B,
    stats: &mut GeometryStats,
) {
    let o = ctx.order.split(t).0;
    let object = &ctx.scene.objects[o];
    let v = corners_of(ctx, frame.objects, frame.vertices, t);
    let or = v[0].outcode() | v[1].outcode() | v[2].outcode();
    let band_end = y0 as u32 + rows as u32;
    if or == 0 {
        stats.triangle_setups += 1;
        // Quadratic surfaces are worth carrying to the next band (lighting
        // and a fit); Gouraud planes cost less than the copies.
        let worth_carrying = ctx.shading(o) == Shading::Quadratic;
        let corners = &v;
        // Captures by value: the closure is built for every triangle in
        // every band, and holds the values rather than their addresses.
        let lazy = move |setup: &TriangleSetup| {
            frame.color_requests.set(frame.color_requests.get() + 1);
            let source = || color_source(ctx, frame.objects, t, corners);
            // Nothing else borrows the table while colors are set up.
            if worth_carrying {
                if let Ok(mut carry) = frame.carry.try_borrow_mut() {
                    let rows = (setup.y0, setup.y1);
                    return carry.planes(t, rows, y0, band_end, || setup.color_planes(source()));
                }
            }
            setup.color_planes(source())
        };
        let params = DrawParams {
            cull_backfaces: object.cull_backfaces,
            colors: &lazy,
            width: ctx.scene.width,
            height: ctx.scene.height,
            test_whole_band: after_hidden,
            // Screen vertices are clamped to it.
            within_guard_band: true,
        };
        // Rejections were counted when binning.
        let _ = buffer.draw_triangle(&v.map(|p| setup_vertex(&p)), &params, y0, rows);
        return;
    }
    draw_clipped(ctx, frame, t, &v, (y0, rows), buffer, stats);
}

/// [`draw_triangle`] for a triangle that crosses a clip plane (`v`, its
/// corners, have outcodes): cut, projected again and drawn as a fan.
// Out of line: the few clipped triangles' code kept the frame loop's
// registers busy for every triangle.
#[inline(never)]
fn draw_clipped<M: CoverageMask, B: BandBuffer<M>>(
    ctx: &FrameContext<'_, '_>,
    frame: &FrameVertices<'_, '_>,
    t: u32,
    v: &[ScreenVertex; 3],
    (y0, rows): (u16, u16),
    buffer: &mut B,
    stats: &mut GeometryStats,
) {
    let (o, i) = ctx.order.split(t);
    let object = &ctx.scene.objects[o];
    let or = v[0].outcode() | v[1].outcode() | v[2].outcode();
    let colors = color_source(ctx, frame.objects, t, v);
    let params = DrawParams {
        cull_backfaces: object.cull_backfaces,
        colors: &|setup: &TriangleSetup| setup.color_planes(colors),
        width: ctx.scene.width,
        height: ctx.scene.height,
        test_whole_band: false,
        // `project` clamps the pieces' corners to it.
        within_guard_band: true,
    };
    // Clipped path: transform the corners again at full range and cut the triangle.
    let transform = &frame.objects[o].transform;
    let tri = object.mesh.triangles[i];
    let normals = match colors {
        ColorSource::Quadratic(lighting, _) | ColorSource::Phong(lighting) => lighting.normals,
        _ => [[0; 3]; 3],
    };
    let clip_in: [ClipVertex; 3] = core::array::from_fn(|k| ClipVertex {
        clip: transform.to_clip(&object.mesh.positions[tri[k] as usize]),
        color: { color_q8(v[k].color()) },
        normal: normals[k],
    });
    let poly = clip_triangle(&clip_in, or);
    if poly.len < 3 {
        return;
    }
    let projected: [SetupVertex; crate::clip::MAX_CLIPPED_VERTICES] = core::array::from_fn(|k| {
        if k < poly.len {
            let (x, y, z) = project(&poly.vertices[k].clip);
            SetupVertex { x, y, z }
        } else {
            SetupVertex::default()
        }
    });
    for k in 1..poly.len - 1 {
        stats.triangle_setups += 1;
        let fan = [projected[0], projected[k], projected[k + 1]];
        // Pieces take their corners' colors; quadratic and Phong pieces
        // their normals too (and quadratic ones relight the corners).
        let corner_normals = [0, k, k + 1].map(|c| poly.vertices[c].normal);
        let corner_colors = [0, k, k + 1].map(|c| poly.vertices[c].color);
        let piece_colors = clipped_piece_source(colors, &corner_normals, corner_colors);
        // Pieces are not carried: their planes are their own.
        let piece_source = |setup: &TriangleSetup| {
            frame.color_requests.set(frame.color_requests.get() + 1);
            setup.color_planes(piece_colors)
        };
        let piece = DrawParams {
            colors: &piece_source,
            ..params
        };
        // A piece may be degenerate or off screen; nothing to count then.
        let _ = buffer.draw_triangle(&fan, &piece, y0, rows);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The frame driver tells setup its corners lie within the guard band
    /// (`DrawParams::within_guard_band`): screen vertices are clamped to
    /// it, and so are the projected corners of clipped pieces.
    #[test]
    fn window_positions_lie_within_the_guard_band() {
        let lim = GUARD_BAND_PX << SUBPIXEL_BITS;
        let within = |c: i32| (-lim..=lim).contains(&c);
        for c in [i32::MIN, -lim - 1, -lim, -1, 0, 1, lim, lim + 1, i32::MAX] {
            let v = ScreenVertex::new(c, -c.saturating_add(1), DEPTH_MAX, [255; 3], 0x3f);
            assert!(within(v.x()) && within(v.y()), "{c}");
        }
        let mut next = crate::test_rng::xorshift(0x2545_f491_4f6c_dd1d);
        for _ in 0..10_000 {
            // Clip-space points, near ones and far outside the view volume.
            let mut coordinate = || (next() as i64) >> (next() % 40);
            let w = coordinate().unsigned_abs().max(1) as i64;
            let (x, y, _) = project(&[coordinate(), coordinate(), coordinate(), w]);
            assert!(within(x) && within(y), "{x} {y}");
        }
    }
}
