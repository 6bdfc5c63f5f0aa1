//! The z-buffer with midpoint subdivision (SPEC section 7): before a triangle is
//! rasterized, its three corners and its centroid are compared with the depth
//! buffer at the pixels they fall in.
//!
//! - All four farther than the buffer: the piece is judged hidden and skipped.
//! - All four nearer (or tied): the piece is judged visible and written without
//!   per-pixel depth tests, which is where comparisons are saved
//!   ([`MidpointConfig::test_visible_pixels`] keeps the tests, so that only the
//!   "hidden" verdict can be wrong).
//! - Otherwise the piece is split at its centroid into three (centroid + each
//!   edge) and each is judged the same way, down to
//!   [`MidpointConfig::max_depth`] levels; a piece still undecided there is
//!   rasterized with per-pixel tests.
//!
//! A triangle is first split [`MidpointConfig::initial_subdivisions`] times
//! without testing. Pieces wait on an explicit stack of
//! [`STACK_CAPACITY`] entries (depth-first, no recursion).
//!
//! Every piece of a triangle is judged before any is drawn: the pieces share
//! corners, and a corner's pixel written by one piece would otherwise make its
//! neighbors look hidden behind their own triangle. The first walk logs one
//! action per piece (two bits each, at most [`MAX_JUDGED_PIECES`]); the second
//! walk replays the log and draws, without reading the depth buffer except for
//! the per-pixel tests of pieces drawn with tests. When the three pieces of a
//! piece all end alike, the piece is drawn whole instead (the same pixels, the
//! same writes and tests). A drawn piece is walked in strips of rows over the
//! columns it reaches, since the pieces are often slivers with mostly empty
//! bounding boxes.
//!
//! The verdicts are guesses: a nearer surface, or a gap between surfaces, that
//! falls between the four test points goes unseen. That is the method as
//! published; the host simulator counts the pixels where it differs from the
//! plain z-buffer.
//!
//! Band-limited: the buffer holds only the band's rows, so a test point outside
//! the band (or off screen) cannot be compared; a piece with such a point is
//! undecided and split further. Once one point is nearer and another farther
//! the verdict is settled, so the remaining points are not read.
//!
//! Every piece is drawn with the whole triangle's depth and color planes, only
//! its edges are its own. The pieces share their inner edges exactly and the
//! top-left rule gives each pixel to one of them, so pieces drawn with tests
//! produce exactly the plain z-buffer's pixels.

use crate::band_buffer::{BandBuffer, DrawParams};
use crate::coverage::Mask1x1;
use crate::draw_order::TriangleOrder;
use crate::fixed_point::{GUARD_BAND_PX, SUBPIXEL_BITS};
use crate::fragment::Fragment;
use crate::raster::rasterize;
use crate::setup::{signed_area2, Edge, Plane, Rejection, SetupVertex, TriangleSetup};
use crate::shading::phong::PhongPlanes;
use crate::shading::quadratic::QuadraticPolynomial;
use crate::shading::ColorPlanes;
use crate::sink::LinePixel;
use crate::stats::BufferStats;
use crate::zbuffer::{with_most_in_a_pixel, DepthColorBand};
use embedded_graphics_core::pixelcolor::Rgb888;

/// The deepest subdivision accepted (`3^6 = 729` pieces per triangle at most).
pub const MAX_SUBDIVISION_DEPTH: u8 = 6;

/// Pieces the drawing walk's stack holds: a depth-first walk that replaces
/// one piece by three keeps at most two waiting siblings per level, plus the
/// three just pushed. (The judging walk keeps one piece per level.)
pub const STACK_CAPACITY: usize = 2 * MAX_SUBDIVISION_DEPTH as usize + 1;

/// Most pieces of one triangle that can be judged: every node of a full
/// ternary tree [`MAX_SUBDIVISION_DEPTH`] levels deep.
pub const MAX_JUDGED_PIECES: usize = (3usize.pow(MAX_SUBDIVISION_DEPTH as u32 + 1) - 1) / 2;

/// How [`MidpointZBuffer`] subdivides.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MidpointConfig {
    /// Subdivisions before the first test (`K`; the published method uses 2).
    pub initial_subdivisions: u8,
    /// Deepest subdivision level (`D`, at least `K`, at most
    /// [`MAX_SUBDIVISION_DEPTH`]); an undecided piece at this level is
    /// rasterized with per-pixel depth tests.
    pub max_depth: u8,
    /// Test every pixel of a piece judged visible too (only the "hidden"
    /// verdict can then be wrong). The published method writes them untested.
    pub test_visible_pixels: bool,
}

impl MidpointConfig {
    /// Two initial subdivisions and visible pieces written untested, as
    /// published; the depth limit of four levels is ours (the publication
    /// gives none).
    pub const DEFAULT: Self = Self {
        initial_subdivisions: 2,
        max_depth: 4,
        test_visible_pixels: false,
    };

    /// Whether `K <= D <= MAX_SUBDIVISION_DEPTH`.
    pub fn is_valid(&self) -> bool {
        self.initial_subdivisions <= self.max_depth && self.max_depth <= MAX_SUBDIVISION_DEPTH
    }
}

impl Default for MidpointConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// A corner or centroid: window position in 1/16 pixel and depth.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct TestPoint {
    x: i32,
    y: i32,
    z: u32,
}

/// A piece of a triangle waiting on the stack: corners ordered so that its
/// edge functions are positive inside, as [`TriangleSetup`] orders them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Piece {
    corners: [TestPoint; 3],
    level: u8,
}

impl Piece {
    /// The centroid, rounded down to 1/16 pixel; depth the mean of the corners'.
    fn centroid(&self) -> TestPoint {
        let [a, b, c] = self.corners;
        TestPoint {
            x: (a.x + b.x + c.x).div_euclid(3),
            y: (a.y + b.y + c.y).div_euclid(3),
            z: ((a.z as u64 + b.z as u64 + c.z as u64) / 3) as u32,
        }
    }

    /// The three pieces around the centroid, or `None` when the rounded
    /// centroid is not strictly inside (a sliver too thin to split).
    fn split(&self) -> Option<[Piece; 3]> {
        let g = self.centroid();
        let [a, b, c] = self.corners;
        let level = self.level + 1;
        let children = [[a, b, g], [b, c, g], [c, a, g]].map(|corners| Piece { corners, level });
        children
            .iter()
            .all(|p| area2(&p.corners) > 0)
            .then_some(children)
    }
}

/// Twice the signed area of three points, positive for the inside-positive order.
fn area2(p: &[TestPoint; 3]) -> i64 {
    let v = p.map(|t| SetupVertex {
        x: t.x,
        y: t.y,
        ..SetupVertex::default()
    });
    signed_area2(&v)
}

/// What happens to a piece: decided while judging, replayed while drawing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Action {
    /// Judged hidden.
    Skip = 0,
    /// Judged visible: written without per-pixel tests.
    DrawUntested = 1,
    /// Split in three.
    Split = 2,
    /// Rasterized with per-pixel tests.
    DrawTested = 3,
}

/// The actions of the pieces of one triangle in walking order (depth-first,
/// a piece before its children), two bits each.
struct ActionLog {
    words: [u32; MAX_JUDGED_PIECES.div_ceil(16)],
    len: usize,
    next: usize,
}

impl ActionLog {
    fn new() -> Self {
        Self {
            words: [0; MAX_JUDGED_PIECES.div_ceil(16)],
            len: 0,
            next: 0,
        }
    }

    /// Appends an action; returns its index.
    fn push(&mut self, action: Action) -> usize {
        let i = self.len;
        self.set(i, action);
        self.len += 1;
        i
    }

    /// Replaces action `i`.
    fn set(&mut self, i: usize, action: Action) {
        let shift = 2 * (i % 16);
        let word = &mut self.words[i / 16];
        *word = (*word & !(3 << shift)) | (action as u32) << shift;
    }

    /// Drops every action after the first `len`.
    fn truncate(&mut self, len: usize) {
        self.len = self.len.min(len);
    }

    /// The next action when replaying.
    fn take(&mut self) -> Action {
        let code = (self.words[self.next / 16] >> (2 * (self.next % 16))) & 3;
        self.next += 1;
        match code {
            0 => Action::Skip,
            1 => Action::DrawUntested,
            2 => Action::Split,
            _ => Action::DrawTested,
        }
    }
}

/// What the pieces of a subtree have in common, gathered while judging.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Common {
    /// No piece with pixels in the band yet.
    Nothing,
    /// Every piece so far ends in this action (never `Split`).
    Same(Action),
    /// The pieces end differently.
    Mixed,
}

impl Common {
    /// Adds the outcome of one more piece (`Split` for a piece whose own
    /// pieces ended differently).
    fn with(self, action: Action) -> Self {
        match (self, action) {
            (_, Action::Split) => Common::Mixed,
            (Common::Nothing, a) => Common::Same(a),
            (Common::Same(a), b) if a == b => self,
            _ => Common::Mixed,
        }
    }
}

/// A piece being split while judging: its log entry, which child comes next,
/// and what its children have in common so far.
#[derive(Clone, Copy, Debug)]
struct Frame {
    piece: Piece,
    slot: usize,
    next_child: usize,
    common: Common,
}

/// What judging a triangle found.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct JudgeOutcome {
    /// Some piece is to be drawn.
    drawn: bool,
    /// Some piece was judged hidden.
    culled: bool,
}

/// What the four test points say about a piece.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Verdict {
    Hidden,
    Visible,
    Undecided,
}

/// A band of depths and colors, one per pixel, drawing triangles by midpoint subdivision.
pub struct MidpointZBuffer<'a> {
    band: DepthColorBand<'a>,
    rows: u16,
    config: MidpointConfig,
    /// Set while a piece judged visible is written without tests.
    untested: bool,
    /// Draw a piece whose pieces all end alike in one go (off only in tests,
    /// to draw every piece on its own).
    merge_agreeing_pieces: bool,
    stack_peak: usize,
    stats: BufferStats,
}

impl<'a> MidpointZBuffer<'a> {
    /// A midpoint-subdivision z-buffer over `depth` and `color`, each of length
    /// `width * band_height`.
    ///
    /// Returns `None` when a slice has another length, a size is zero or the
    /// configuration is not valid ([`MidpointConfig::is_valid`]).
    pub fn new(
        width: u16,
        band_height: u16,
        depth: &'a mut [u32],
        color: &'a mut [Rgb888],
        config: MidpointConfig,
    ) -> Option<Self> {
        if !config.is_valid() {
            return None;
        }
        Some(Self {
            band: DepthColorBand::new(width, band_height, depth, color)?,
            rows: band_height,
            config,
            untested: false,
            merge_agreeing_pieces: true,
            stack_peak: 0,
            stats: BufferStats::default(),
        })
    }

    /// The configuration.
    pub fn config(&self) -> MidpointConfig {
        self.config
    }

    /// The most pieces the subdivision stack has held at once (at most
    /// [`STACK_CAPACITY`]).
    pub fn stack_peak(&self) -> usize {
        self.stack_peak
    }

    /// Compares the piece's corners and centroid with the depth buffer.
    fn judge(&mut self, piece: &Piece, band: (u16, u16)) -> Verdict {
        let (band_y0, rows) = band;
        let [a, b, c] = piece.corners;
        let points = [a, b, c, piece.centroid()];
        let mut index = [0usize; 4];
        for (slot, p) in index.iter_mut().zip(&points) {
            let (px, py) = (p.x >> SUBPIXEL_BITS, p.y >> SUBPIXEL_BITS);
            let row = py - band_y0 as i32;
            if px < 0 || px >= self.band.width as i32 || row < 0 || row >= rows as i32 {
                // Not in the band: nothing to compare with.
                return Verdict::Undecided;
            }
            *slot = self.band.index(px as u16, row as u16);
        }
        let (mut nearer, mut farther) = (false, false);
        for (p, &i) in points.iter().zip(&index) {
            self.stats.culling_depth_tests += 1;
            // Ties go to the new surface, as in the per-pixel test.
            if p.z <= self.band.depth[i] {
                nearer = true;
            } else {
                farther = true;
            }
            if nearer && farther {
                return Verdict::Undecided;
            }
        }
        if farther {
            Verdict::Hidden
        } else {
            Verdict::Visible
        }
    }

    /// The action for `piece` (in the band) while judging: forced splits
    /// above level `K`, then the verdict of its test points.
    fn decide(&mut self, piece: &Piece, band: (u16, u16)) -> Action {
        let config = self.config;
        let action = if piece.level < config.initial_subdivisions {
            Action::Split
        } else {
            match self.judge(piece, band) {
                Verdict::Hidden => {
                    self.stats.pieces_culled += 1;
                    Action::Skip
                }
                Verdict::Visible if config.test_visible_pixels => Action::DrawTested,
                Verdict::Visible => Action::DrawUntested,
                Verdict::Undecided if piece.level < config.max_depth => Action::Split,
                Verdict::Undecided => Action::DrawTested,
            }
        };
        if action == Action::Split && piece.split().is_none() {
            // Too thin to split: rasterize it with tests.
            return Action::DrawTested;
        }
        action
    }

    /// First walk over the pieces of `root` (a piece of `setup`) in the band
    /// `(first row, rows)`: judges them and logs one action per piece with
    /// pixels in the band, depth-first. Reads the depth buffer, writes nothing.
    ///
    /// A piece whose pieces all end in the same action takes that action
    /// itself and their entries are dropped: the same pixels, drawn in one go.
    fn judge_pieces(
        &mut self,
        setup: &TriangleSetup,
        root: Piece,
        band: (u16, u16),
        log: &mut ActionLog,
    ) -> JudgeOutcome {
        let (band_y0, rows) = band;
        let band_last = band_y0 as u32 + rows as u32 - 1;
        let mut outcome = JudgeOutcome::default();
        // Only pieces being split wait here: one per level above the deepest.
        let mut frames = [Frame {
            piece: root,
            slot: 0,
            next_child: 0,
            common: Common::Nothing,
        }; MAX_SUBDIVISION_DEPTH as usize + 1];
        let mut depth = 0usize;
        let mut next = Some(root);
        loop {
            // Visit the next piece: a leaf reports its action to its parent,
            // a piece to split becomes a frame.
            let mut finished = None;
            if let Some(piece) = next.take() {
                if piece_in_band(setup, &piece, band_y0, band_last) {
                    let action = self.decide(&piece, band);
                    let slot = log.push(action);
                    match action {
                        Action::Split => {
                            frames[depth] = Frame {
                                piece,
                                slot,
                                next_child: 0,
                                common: Common::Nothing,
                            };
                            depth += 1;
                            self.stack_peak = self.stack_peak.max(depth);
                        }
                        Action::Skip => {
                            outcome.culled = true;
                            finished = Some(action);
                        }
                        _ => {
                            outcome.drawn = true;
                            finished = Some(action);
                        }
                    }
                }
            } else if depth > 0 {
                // A frame whose children are all done: merge them if they agree.
                let frame = &frames[depth - 1];
                if frame.next_child == 3 {
                    depth -= 1;
                    let merged = match frame.common {
                        Common::Same(action) if self.merge_agreeing_pieces => {
                            log.set(frame.slot, action);
                            log.truncate(frame.slot + 1);
                            action
                        }
                        _ => Action::Split,
                    };
                    finished = Some(merged);
                }
            }
            if let Some(action) = finished {
                if depth == 0 {
                    break;
                }
                let parent = &mut frames[depth - 1];
                parent.common = parent.common.with(action);
            }
            if depth == 0 {
                break;
            }
            let top = &mut frames[depth - 1];
            if top.next_child < 3 && next.is_none() {
                next = top.piece.split().map(|c| c[top.next_child]);
                top.next_child += 1;
            }
        }
        outcome
    }

    /// Second walk: replays the log over the same pieces in the same order and
    /// draws them.
    fn draw_pieces(
        &mut self,
        setup: &TriangleSetup,
        colors: &ColorPlanes,
        root: Piece,
        band: (u16, u16),
        log: &mut ActionLog,
    ) {
        let (band_y0, rows) = band;
        let band_last = band_y0 as u32 + rows as u32 - 1;
        let mut stack = [Piece::default(); STACK_CAPACITY];
        stack[0] = root;
        let mut len = 1usize;
        while len > 0 {
            len -= 1;
            let piece = stack[len];
            if !piece_in_band(setup, &piece, band_y0, band_last) {
                continue;
            }
            match log.take() {
                Action::Skip => {}
                Action::Split => {
                    // Depth-first: at most two waiting siblings per level, so
                    // three more always fit (see STACK_CAPACITY).
                    if let Some(children) = piece.split() {
                        for child in children.iter().rev() {
                            stack[len] = *child;
                            len += 1;
                        }
                        self.stack_peak = self.stack_peak.max(len);
                    }
                }
                action => {
                    let untested = action == Action::DrawUntested;
                    self.draw_piece(setup, colors, &piece, band_y0, rows, untested);
                }
            }
        }
    }

    /// Rasterizes the pixels of `piece` (a piece of `setup`) in the band.
    fn draw_piece(
        &mut self,
        setup: &TriangleSetup,
        colors: &ColorPlanes,
        piece: &Piece,
        band_y0: u16,
        band_rows: u16,
        untested: bool,
    ) {
        self.untested = untested;
        if piece.level == 0 {
            rasterize(setup, band_y0, band_rows, self, || *colors);
        } else {
            // Pieces are often slivers whose bounding box is mostly empty:
            // walk them in strips of rows, each over the columns the piece
            // reaches within it.
            let band_last = band_y0 as i64 + band_rows as i64 - 1;
            let ys = piece.corners.map(|p| p.y as i64 >> SUBPIXEL_BITS);
            let top = ys.iter().copied().min().unwrap_or(0);
            let bottom = ys.iter().copied().max().unwrap_or(0);
            let mut y0 = top.max(setup.y0 as i64).max(band_y0 as i64);
            let y_end = bottom.min(setup.y1 as i64).min(band_last);
            while y0 <= y_end {
                let y1 = (y0 + STRIP_ROWS - 1).min(y_end);
                if let Some((x0, x1)) = columns_in_rows(piece, y0, y1) {
                    let x0 = x0.max(setup.x0 as i64);
                    let x1 = x1.min(setup.x1 as i64);
                    if x0 <= x1 {
                        let (part, part_colors) =
                            piece_setup(setup, colors, piece, (x0, x1), (y0, y1));
                        rasterize(&part, band_y0, band_rows, self, || part_colors);
                    }
                }
                y0 = y1 + 1;
            }
        }
        self.untested = false;
    }
}

/// Whether a piece has pixel rows in band rows `band_y0 ..= band_last` (and
/// within `setup`'s box).
fn piece_in_band(setup: &TriangleSetup, piece: &Piece, band_y0: u16, band_last: u32) -> bool {
    let ys = piece.corners.map(|p| p.y >> SUBPIXEL_BITS);
    let lo = ys
        .iter()
        .copied()
        .min()
        .unwrap_or(0)
        .max(setup.y0 as i32)
        .max(band_y0 as i32);
    let hi = ys
        .iter()
        .copied()
        .max()
        .unwrap_or(0)
        .min(setup.y1 as i32)
        .min(band_last as i32);
    lo <= hi
}

/// `plane` re-anchored from pixel `(0, 0)` of its box to pixel `(di, dj)`.
fn shift_plane(plane: &Plane, di: i64, dj: i64) -> Plane {
    Plane {
        origin: plane.origin + di * plane.dx + dj * plane.dy,
        ..*plane
    }
}

/// `q` re-anchored from lattice point `(0, 0)` to `(di, dj)`: the same values
/// at the same pixels (exact integer identity).
fn shift_quadratic(q: &QuadraticPolynomial, di: i64, dj: i64) -> QuadraticPolynomial {
    let (a, b, c) = (q.a as i128, q.b as i128, q.c as i128);
    let (i, j) = (di as i128, dj as i128);
    QuadraticPolynomial {
        d: (q.d as i128 + 2 * a * i + c * j) as i64,
        e: (q.e as i128 + 2 * b * j + c * i) as i64,
        f: q.eval(di, dj),
        ..*q
    }
}

/// Rows of a strip when a piece is rasterized strip by strip.
const STRIP_ROWS: i64 = 8;

/// Pixel columns (a conservative range) where `piece` may cover pixel
/// centers of rows `y0 ..= y1`, or `None` when it misses those rows.
///
/// The piece cut to the rows' horizontal slab is a convex polygon whose
/// corners are the piece's corners within the slab and its edges' crossings
/// of the slab's two borders.
fn columns_in_rows(piece: &Piece, y0: i64, y1: i64) -> Option<(i64, i64)> {
    let top = y0 << SUBPIXEL_BITS;
    let bottom = (y1 << SUBPIXEL_BITS) + (1 << SUBPIXEL_BITS) - 1;
    let (mut lo, mut hi) = (i64::MAX, i64::MIN);
    let c = piece.corners.map(|p| (p.x as i64, p.y as i64));
    for i in 0..3 {
        let (xa, ya) = c[i];
        let (xb, yb) = c[(i + 1) % 3];
        if (top..=bottom).contains(&ya) {
            lo = lo.min(xa);
            hi = hi.max(xa);
        }
        if ya == yb {
            continue;
        }
        for border in [top, bottom] {
            if (ya.min(yb)..=ya.max(yb)).contains(&border) {
                // The crossing, rounded down and up (divisor made positive).
                let (num, den) = ((xb - xa) * (border - ya), yb - ya);
                let (num, den) = if den < 0 { (-num, -den) } else { (num, den) };
                let x = xa + num.div_euclid(den);
                lo = lo.min(x);
                hi = hi.max(x + 1);
            }
        }
    }
    (lo <= hi).then_some((lo >> SUBPIXEL_BITS, hi >> SUBPIXEL_BITS))
}

/// The setup of `piece` over the pixel box `columns` x `rows` (within
/// `setup`'s box): its own edges, `setup`'s depth and colors moved to the
/// box's first pixel.
fn piece_setup(
    setup: &TriangleSetup,
    colors: &ColorPlanes,
    piece: &Piece,
    columns: (i64, i64),
    rows: (i64, i64),
) -> (TriangleSetup, ColorPlanes) {
    let xs = piece.corners.map(|p| p.x as i64);
    let ys = piece.corners.map(|p| p.y as i64);
    let ((x0, x1), (y0, y1)) = (columns, rows);
    // Edge functions exactly as the triangle setup builds them (top-left rule).
    let half = 1i64 << (SUBPIXEL_BITS - 1);
    let cx = (x0 << SUBPIXEL_BITS) + half;
    let cy = (y0 << SUBPIXEL_BITS) + half;
    let mut edges = [Edge::default(); 3];
    for (i, e) in edges.iter_mut().enumerate() {
        let (ia, ib) = (i, (i + 1) % 3);
        let a = -(ys[ib] - ys[ia]);
        let b = xs[ib] - xs[ia];
        let top_left = a > 0 || (a == 0 && b > 0);
        let c = -(a * xs[ia] + b * ys[ia]) - if top_left { 0 } else { 1 };
        // Within the guard band, `a` and `b` are below 2^18 (see `Edge`).
        *e = Edge {
            a: a as i32,
            b: b as i32,
            origin: a * cx + b * cy + c,
        };
    }
    let (di, dj) = (x0 - setup.x0 as i64, y0 - setup.y0 as i64);
    let colors = match colors {
        ColorPlanes::Constant(c) => ColorPlanes::Constant(*c),
        ColorPlanes::Linear(p) => ColorPlanes::Linear(p.map(|p| shift_plane(&p, di, dj))),
        ColorPlanes::Quadratic(q) => ColorPlanes::Quadratic(q.map(|q| shift_quadratic(&q, di, dj))),
        // The piece's box lies in the triangle's: the same values, still
        // within the bound of the `i32` walk.
        ColorPlanes::NarrowQuadratic(q) => {
            ColorPlanes::NarrowQuadratic(q.map(|q| shift_quadratic(&q, di, dj)))
        }
        ColorPlanes::Phong(p) => ColorPlanes::Phong(PhongPlanes {
            normal: p.normal.map(|n| shift_plane(&n, di, dj)),
            ..*p
        }),
    };
    let part = TriangleSetup {
        edges,
        x0: x0 as u16,
        y0: y0 as u16,
        x1: x1 as u16,
        y1: y1 as u16,
        depth: shift_plane(&setup.depth, di, dj),
        dzdx: setup.dzdx,
        dzdy: setup.dzdy,
        corners: setup.corners,
    };
    (part, colors)
}

/// The corners of a triangle in the order and the range the triangle setup
/// uses (inside-positive, clamped to the guard band).
fn ordered_corners(v: &[SetupVertex; 3]) -> [TestPoint; 3] {
    let ordered = if signed_area2(v) > 0 {
        [v[0], v[1], v[2]]
    } else {
        [v[0], v[2], v[1]]
    };
    let lim = GUARD_BAND_PX << SUBPIXEL_BITS;
    ordered.map(|p| TestPoint {
        x: p.x.clamp(-lim, lim),
        y: p.y.clamp(-lim, lim),
        z: p.z,
    })
}

impl BandBuffer<Mask1x1> for MidpointZBuffer<'_> {
    const ORDER: TriangleOrder = TriangleOrder::FirstRow;

    fn width(&self) -> u16 {
        self.band.width
    }

    fn band_height(&self) -> u16 {
        self.band.band_height
    }

    fn begin_band(&mut self, _y0: u16, rows: u16) {
        self.rows = rows.clamp(1, self.band.band_height);
        self.band.begin_band(self.rows);
    }

    fn draw_triangle(
        &mut self,
        vertices: &[SetupVertex; 3],
        params: &DrawParams<'_>,
        band_y0: u16,
        band_rows: u16,
    ) -> Result<(), Rejection> {
        let setup =
            TriangleSetup::new(vertices, params.cull_backfaces, params.width, params.height)?;
        let rows = band_rows.min(self.rows);
        if rows == 0 {
            return Ok(());
        }
        let root = Piece {
            corners: ordered_corners(vertices),
            level: 0,
        };
        // Judge every piece before drawing any: a piece's test points must not
        // see pixels its sibling pieces have just written.
        let mut log = ActionLog::new();
        let band = (band_y0, rows);
        let judged = self.judge_pieces(&setup, root, band, &mut log);
        if judged.drawn {
            let colors = (params.colors)(&setup);
            self.draw_pieces(&setup, &colors, root, band, &mut log);
        } else if judged.culled {
            self.stats.triangles_culled += 1;
        }
        Ok(())
    }

    #[inline]
    fn insert(&mut self, x: u16, row: u16, fragment: &Fragment<Mask1x1>) {
        self.stats.fragments_generated += 1;
        let p = self.band.index(x, row);
        if self.untested {
            self.band.depth[p] = fragment.z;
            self.band.color[p] = fragment.color;
            self.stats.fragments_stored += 1;
            self.stats.untested_writes += 1;
            return;
        }
        self.stats.depth_tests += 1;
        self.band.test_and_store(p, fragment, &mut self.stats);
    }

    fn resolve_row<P: LinePixel>(&mut self, row: u16, background: Rgb888, out: &mut [P]) {
        self.band.resolve_row(row, background, out);
    }

    fn pixel_fragment_count(&self, x: u16, row: u16) -> u32 {
        self.band.is_drawn(x, row) as u32
    }

    fn stats(&self) -> BufferStats {
        with_most_in_a_pixel(self.stats)
    }

    fn take_stats(&mut self) -> BufferStats {
        with_most_in_a_pixel(core::mem::take(&mut self.stats))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::ColorSource;
    use crate::zbuffer::ZBuffer;

    const W: u16 = 48;
    const H: u16 = 32;

    /// A corner of a test triangle: where it is and its Gouraud color.
    #[derive(Clone, Copy, Debug)]
    struct TestVertex {
        at: SetupVertex,
        color: crate::lighting::ColorQ8,
    }

    fn vertex(x: i32, y: i32, z: u32, c: i32) -> TestVertex {
        TestVertex {
            at: SetupVertex { x, y, z },
            color: [c << 8, (255 - c) << 8, 128 << 8],
        }
    }

    /// How the test triangles are colored.
    #[derive(Clone, Copy)]
    enum Shade {
        /// Their corners' colors, interpolated.
        Gouraud,
        /// One color.
        Constant(Rgb888),
    }

    impl Shade {
        fn source(self, t: &[TestVertex; 3]) -> ColorSource<'static> {
            match self {
                Shade::Gouraud => ColorSource::Linear(t.map(|v| v.color)),
                Shade::Constant(c) => ColorSource::Constant(c),
            }
        }
    }

    fn params(colors: &dyn Fn(&TriangleSetup) -> ColorPlanes) -> DrawParams<'_> {
        DrawParams {
            cull_backfaces: false,
            colors,
            width: W,
            height: H,
            test_whole_band: false,
            within_guard_band: false,
        }
    }

    /// Draws `triangles` over bands of `band` rows into `buffer`; returns the
    /// image and the counters.
    fn draw<B: BandBuffer<Mask1x1>>(
        buffer: &mut B,
        triangles: &[[TestVertex; 3]],
        colors: Shade,
        band: u16,
    ) -> (Vec<Rgb888>, BufferStats) {
        let bg = Rgb888::new(1, 2, 3);
        let mut image = Vec::new();
        let mut line = vec![bg; W as usize];
        let mut y0 = 0;
        while y0 < H {
            let rows = band.min(H - y0);
            buffer.begin_band(y0, rows);
            for t in triangles {
                let source = |s: &TriangleSetup| s.color_planes(colors.source(t));
                let _ = buffer.draw_triangle(&t.map(|v| v.at), &params(&source), y0, rows);
            }
            for row in 0..rows {
                buffer.resolve_row(row, bg, &mut line);
                image.extend_from_slice(&line);
            }
            y0 += rows;
        }
        (image, buffer.take_stats())
    }

    fn plain(
        triangles: &[[TestVertex; 3]],
        colors: Shade,
        band: u16,
    ) -> (Vec<Rgb888>, BufferStats) {
        let n = W as usize * band as usize;
        let (mut d, mut c) = (vec![0; n], vec![Rgb888::new(0, 0, 0); n]);
        draw(
            &mut ZBuffer::new(W, band, &mut d, &mut c).unwrap(),
            triangles,
            colors,
            band,
        )
    }

    fn midpoint(
        triangles: &[[TestVertex; 3]],
        colors: Shade,
        band: u16,
        config: MidpointConfig,
    ) -> (Vec<Rgb888>, BufferStats, usize) {
        midpoint_merging(triangles, colors, band, config, true)
    }

    /// As [`midpoint`]; `merge: false` draws every piece on its own.
    fn midpoint_merging(
        triangles: &[[TestVertex; 3]],
        colors: Shade,
        band: u16,
        config: MidpointConfig,
        merge: bool,
    ) -> (Vec<Rgb888>, BufferStats, usize) {
        let n = W as usize * band as usize;
        let (mut d, mut c) = (vec![0; n], vec![Rgb888::new(0, 0, 0); n]);
        let mut buffer = MidpointZBuffer::new(W, band, &mut d, &mut c, config).unwrap();
        buffer.merge_agreeing_pieces = merge;
        let (image, stats) = draw(&mut buffer, triangles, colors, band);
        (image, stats, buffer.stack_peak())
    }

    fn random_triangles(seed: u32, n: usize) -> Vec<[TestVertex; 3]> {
        let mut rng = Rng(seed);
        (0..n)
            .map(|_| {
                [0, 1, 2].map(|_| {
                    vertex(
                        rng.below((W as i32 + 16) * 16) - 128,
                        rng.below((H as i32 + 16) * 16) - 128,
                        1000 + rng.below(1 << 20) as u32,
                        rng.below(256),
                    )
                })
            })
            .collect()
    }

    #[test]
    fn drawing_agreeing_pieces_together_changes_nothing() {
        let triangles = random_triangles(77, 40);
        for k in 0..=3 {
            for safe in [false, true] {
                for band in [H, 16, 5] {
                    let config = MidpointConfig {
                        initial_subdivisions: k,
                        max_depth: k + 2,
                        test_visible_pixels: safe,
                    };
                    let colors = Shade::Gouraud;
                    let (a, sa, _) = midpoint_merging(&triangles, colors, band, config, true);
                    let (b, sb, _) = midpoint_merging(&triangles, colors, band, config, false);
                    assert!(a == b, "K = {k}, safe {safe}, band {band}");
                    assert_eq!(sa, sb, "K = {k}, safe {safe}, band {band}");
                }
            }
        }
    }

    struct Rng(u32);

    impl Rng {
        fn below(&mut self, n: i32) -> i32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 17;
            self.0 ^= self.0 << 5;
            (self.0 % n as u32) as i32
        }
    }

    #[test]
    fn pieces_cover_a_triangle_exactly_once() {
        // One triangle on an empty buffer: every piece is judged visible, so the
        // pieces' pixels are written (untested unless a test point is off
        // screen). They must be exactly the
        // triangle's pixels, each once, with the triangle's depth and colors.
        let mut rng = Rng(0x9e37_79b9);
        for i in 0..300 {
            let mut p = || {
                vertex(
                    rng.below((W as i32 + 16) * 16) - 128,
                    rng.below((H as i32 + 16) * 16) - 128,
                    1000 + rng.below(1 << 20) as u32,
                    rng.below(256),
                )
            };
            let t = [p(), p(), p()];
            for colors in [Shade::Gouraud, Shade::Constant(Rgb888::new(9, 8, 7))] {
                let (expected, expected_stats) = plain(&[t], colors, H);
                for k in 0..=5 {
                    let config = MidpointConfig {
                        initial_subdivisions: k,
                        max_depth: k,
                        test_visible_pixels: false,
                    };
                    // Every piece drawn on its own.
                    let (image, stats, _) = midpoint_merging(&[t], colors, H, config, false);
                    assert!(image == expected, "triangle {i} {t:?}, K = {k}");
                    assert_eq!(stats.fragments_stored, expected_stats.fragments_stored);
                    // Pieces with a test point off screen are drawn with tests.
                    let tested = stats.fragments_stored - stats.untested_writes;
                    assert_eq!(stats.depth_tests, tested);
                }
            }
        }
    }

    #[test]
    fn shifted_planes_give_the_same_values_at_the_same_pixels() {
        use crate::shading::quadratic::{QuadraticValue, QuadraticWalk};
        use crate::shading::ColorWalk;
        let mut rng = Rng(0x5eed);
        for _ in 0..200 {
            let mut c = || rng.below(1 << 20) as i64 - (1 << 19);
            let q = QuadraticPolynomial {
                a: c(),
                b: c(),
                c: c(),
                d: c() << 6,
                e: c() << 6,
                f: c() << 12,
            };
            let p = Plane {
                origin: c() << 10,
                dx: c(),
                dy: c(),
            };
            let (di, dj) = (rng.below(40) as i64, rng.below(30) as i64);
            let (sq, sp) = (shift_quadratic(&q, di, dj), shift_plane(&p, di, dj));
            // Walk a few rows and columns of the shifted box with additions.
            let mut walk = QuadraticWalk::<i64>::start(&[sq; 3], 0);
            for j in 0..5 {
                let mut row = walk.row();
                for i in 0..7 {
                    let bias = <i64 as QuadraticValue>::ROUNDING_BIAS;
                    assert_eq!(row.value[0], q.eval(di + i, dj + j) + bias);
                    assert_eq!(sq.eval(i, j), q.eval(di + i, dj + j));
                    let direct = p.origin + (di + i) * p.dx + (dj + j) * p.dy;
                    assert_eq!(sp.origin + i * sp.dx + j * sp.dy, direct);
                    walk.step(&mut row);
                }
                walk.next_row();
            }
        }
    }

    #[test]
    fn stack_never_overflows() {
        let big = [
            vertex(-200, -200, 5000, 0),
            vertex(900, 10, 5000, 0),
            vertex(40, 600, 5000, 0),
        ];
        // A nearer triangle covering part of it, drawn first, keeps pieces undecided.
        let near = [
            vertex(0, 0, 100, 200),
            vertex(500, 0, 100, 200),
            vertex(0, 300, 100, 200),
        ];
        let colors = Shade::Gouraud;
        for k in 0..=MAX_SUBDIVISION_DEPTH {
            for band in [H, 16, 5] {
                let config = MidpointConfig {
                    initial_subdivisions: k,
                    max_depth: MAX_SUBDIVISION_DEPTH,
                    test_visible_pixels: false,
                };
                for merge in [true, false] {
                    let (_, stats, peak) =
                        midpoint_merging(&[near, big], colors, band, config, merge);
                    assert!(peak <= STACK_CAPACITY, "K = {k}, band {band}: {peak}");
                    assert!(stats.pieces_culled > 0);
                }
            }
        }
        // Splitting to the deepest level fills the stack exactly.
        let deepest = MidpointConfig {
            initial_subdivisions: MAX_SUBDIVISION_DEPTH,
            max_depth: MAX_SUBDIVISION_DEPTH,
            test_visible_pixels: false,
        };
        let (image, _, peak) = midpoint_merging(&[big], colors, H, deepest, false);
        assert_eq!(peak, STACK_CAPACITY);
        assert!(image == plain(&[big], colors, H).0);
        assert!(!MidpointConfig {
            initial_subdivisions: 3,
            max_depth: 2,
            ..deepest
        }
        .is_valid());
        assert!(!MidpointConfig {
            max_depth: MAX_SUBDIVISION_DEPTH + 1,
            ..deepest
        }
        .is_valid());
        let mut d = vec![0; W as usize];
        let mut c = vec![Rgb888::new(0, 0, 0); W as usize];
        assert!(MidpointZBuffer::new(
            W,
            1,
            &mut d,
            &mut c,
            MidpointConfig {
                max_depth: 9,
                ..deepest
            }
        )
        .is_none());
    }

    #[test]
    fn hidden_triangle_is_culled_whole() {
        let occluder = [
            vertex(-64, -64, 100, 0),
            vertex(2000, -64, 100, 0),
            vertex(-64, 2000, 100, 0),
        ];
        // Rows 2 to 12: within the first band of 16 rows.
        let behind = [
            vertex(50, 40, 9000, 99),
            vertex(400, 60, 9000, 99),
            vertex(90, 200, 9000, 99),
        ];
        let colors = Shade::Gouraud;
        for band in [H, 16] {
            let (only_occluder, occluder_stats, _) =
                midpoint(&[occluder], colors, band, MidpointConfig::DEFAULT);
            let (image, stats, _) =
                midpoint(&[occluder, behind], colors, band, MidpointConfig::DEFAULT);
            assert!(image == plain(&[occluder, behind], colors, band).0);
            assert!(image == only_occluder);
            assert_eq!(stats.triangles_culled, 1, "band {band}");
            // Nothing of the hidden triangle was rasterized.
            assert_eq!(
                stats.fragments_generated,
                occluder_stats.fragments_generated
            );
            assert_eq!(stats.depth_tests, occluder_stats.depth_tests);
            assert!(stats.culling_depth_tests > occluder_stats.culling_depth_tests);
        }
    }

    #[test]
    fn points_outside_the_band_are_undecided() {
        // A triangle over three bands of 8 rows, no subdivision allowed: its test
        // points are never all in one band, so it is rasterized with tests.
        let t = [
            vertex(16, 16, 500, 0),
            vertex(600, 40, 500, 0),
            vertex(80, 460, 500, 0),
        ];
        let config = MidpointConfig {
            initial_subdivisions: 0,
            max_depth: 0,
            test_visible_pixels: false,
        };
        let (image, stats, _) = midpoint(&[t], Shade::Gouraud, 8, config);
        assert!(image == plain(&[t], Shade::Gouraud, 8).0);
        assert_eq!(stats.untested_writes, 0);
        assert_eq!(stats.culling_depth_tests, 0);
        assert_eq!(stats.depth_tests, stats.fragments_stored);
    }

    #[test]
    fn visible_verdict_can_be_wrong_and_safe_mode_repairs_it() {
        // A near sliver drawn first, then a far triangle whose four test points
        // all miss the sliver: judged visible, written over it untested.
        let sliver = [
            vertex(300, 0, 100, 250),
            vertex(340, 0, 100, 250),
            vertex(320, 500, 100, 250),
        ];
        let far = [
            vertex(0, 100, 8000, 0),
            vertex(760, 100, 8000, 0),
            vertex(380, 500, 8000, 0),
        ];
        let colors = Shade::Gouraud;
        let config = MidpointConfig {
            initial_subdivisions: 0,
            max_depth: 0,
            test_visible_pixels: false,
        };
        let expected = plain(&[sliver, far], colors, H).0;
        let (image, stats, _) = midpoint(&[sliver, far], colors, H, config);
        assert!(image != expected);
        assert_eq!(stats.depth_tests, 0);
        let safe = MidpointConfig {
            test_visible_pixels: true,
            ..config
        };
        assert!(midpoint(&[sliver, far], colors, H, safe).0 == expected);
    }
}
