//! The plain z-buffer: one sample at the pixel center, no antialiasing.

use crate::band_buffer::{insert_each, BandBuffer, FullRun};
use crate::coverage::{CoverageMask, Mask1x1};
use crate::fixed_point::uncounted;
use crate::fragment::{rounds_in_range, Fragment, PLANE_EXTRA_BITS};
use crate::shading::ColorWalk;
use crate::sink::LinePixel;
use crate::stats::BufferStats;
use embedded_graphics_core::pixelcolor::Rgb888;

/// Depth of an empty z-buffer pixel: farther than any fragment.
pub const EMPTY_DEPTH: u32 = u32::MAX;

/// A band of depths and colors, one per pixel, the colors kept in pixel
/// format `P`: give it the format of the sink the frame goes to (a
/// display's [`crate::sink::Rgb565BigEndian`], an image's
/// [`crate::sink::PackedRgb888`]), and its rows go out as copies, with no
/// conversion; another sink's rows are converted.
pub struct ZBuffer<'a, P: LinePixel = Rgb888> {
    band: DepthColorBand<'a, P>,
    stats: BufferStats,
}

impl<'a, P: LinePixel> ZBuffer<'a, P> {
    /// A z-buffer over `depth` and `color`, each of length `width * band_height`.
    ///
    /// Returns `None` when a slice has another length or a size is zero.
    pub fn new(
        width: u16,
        band_height: u16,
        depth: &'a mut [u32],
        color: &'a mut [P],
    ) -> Option<Self> {
        Some(Self {
            band: DepthColorBand::new(width, band_height, depth, color)?,
            stats: BufferStats::default(),
        })
    }
}

impl<P: LinePixel> BandBuffer<Mask1x1> for ZBuffer<'_, P> {
    fn width(&self) -> u16 {
        self.band.width
    }

    fn band_height(&self) -> u16 {
        self.band.band_height
    }

    fn begin_band(&mut self, _y0: u16, rows: u16) {
        self.band.begin_band(rows.min(self.band.band_height));
    }

    #[inline]
    fn hides(&mut self, x: u16, row: u16, depth: i64) -> bool {
        let stored = self.band.depth[self.band.index(x, row)];
        stored != EMPTY_DEPTH && 16 * (stored as i64) < depth
    }

    /// Scans the row's depths against one threshold: an empty pixel
    /// ([`EMPTY_DEPTH`]) is never nearer than a fragment's depth.
    fn hidden_run(&mut self, row: u16, x0: u16, x1: u16, depth: i64) -> u32 {
        // `16 stored < depth` exactly when `stored < ceil(depth / 16)`; the
        // clamp keeps empty pixels out and changes no other answer.
        let nearer_than = (depth + 15).div_euclid(16).clamp(0, EMPTY_DEPTH as i64) as u32;
        let start = self.band.index(0, row);
        let (x0, x1) = (x0 as usize, (x1 as usize).min(self.band.width as usize - 1));
        let Some(depths) = self.band.depth.get(start + x0..start + x1 + 1) else {
            return 0;
        };
        let mut hidden = 0;
        while hidden < depths.len() && depths[hidden] < nearer_than {
            hidden = uncounted(hidden + 1);
        }
        hidden as u32
    }

    fn count_triangle_test(&mut self, pixels: u32, hidden: bool) {
        self.stats.culling_depth_tests += pixels;
        self.stats.triangles_culled += hidden as u32;
    }

    #[inline]
    fn survives(&mut self, x: u16, row: u16, fragment: &Fragment<Mask1x1>) -> bool {
        if fragment.z <= self.band.depth[self.band.index(x, row)] {
            return true;
        }
        self.stats.fragments_hidden_on_arrival += 1;
        false
    }

    #[inline]
    fn insert(&mut self, x: u16, row: u16, fragment: &Fragment<Mask1x1>) {
        // Only what is stored and what is hidden are counted here; the
        // fragments and depth tests are their sum (see `stats`).
        let p = self.band.index(x, row);
        self.band.test_and_store(p, fragment, &mut self.stats);
    }

    /// One depth test and store per pixel, the run's slices checked once;
    /// where the run's depths are in range (nearly always), a pixel's depth
    /// is the high word of the rounded plane shifted up, with no clamp.
    #[inline(always)]
    fn insert_full_run<W: ColorWalk>(
        &mut self,
        x: u16,
        row: u16,
        run: &FullRun<Mask1x1>,
        walk: &W,
        color: &mut W::Row,
    ) {
        let start = self.band.index(x, row);
        let end = start + run.len as usize;
        // The plane is linear: when both ends of the run round into range,
        // every pixel between does.
        let last = run.depth + (run.len as i64 - 1) * run.depth_step;
        if end > self.band.depth.len() || !rounds_in_range(run.depth) || !rounds_in_range(last) {
            return insert_each(self, x, row, run, walk, color);
        }
        // The rounded plane shifted up so that a pixel's depth is the high
        // word: the step is one add with carry, the depth no shift. Both
        // ends are in range and the plane is linear, so every value of the
        // run lies in `0 .. 2^56`: the wrapping sum holds it exactly.
        const UP: u32 = 32 - PLANE_EXTRA_BITS;
        let mut rounded = (run.depth << UP) as u64;
        let step = (run.depth_step << UP) as u64;
        // The pixels stored in the low half-word and those of them that
        // replaced a fragment in the high one: a run is at most `u16::MAX`
        // pixels long, and one counter leaves the loop a register.
        const REPLACED: u32 = 1 << 16;
        let mut counts = 0u32;
        let depths = &mut self.band.depth[start..end];
        let colors = &mut self.band.color[start..end];
        let mut pixel = |stored_depth: &mut u32, stored_color: &mut P| {
            let z = (rounded >> 32) as u32;
            if z <= *stored_depth {
                counts += 1 + if *stored_depth != EMPTY_DEPTH {
                    REPLACED
                } else {
                    0
                };
                *stored_depth = z;
                stored_color.set_rgb888(walk.color(color));
            }
            walk.step(color);
            rounded = rounded.wrapping_add(step);
        };
        if W::UNROLLED_RUNS {
            for (stored_depth, stored_color) in depths.iter_mut().zip(colors) {
                pixel(stored_depth, stored_color);
            }
        } else {
            let mut i = 0;
            while i < depths.len() {
                pixel(&mut depths[i], &mut colors[i]);
                i = uncounted(i + 1);
            }
        }
        let (stored, replaced) = (counts & (REPLACED - 1), counts >> 16);
        self.stats.fragments_stored += stored;
        self.stats.fragments_removed_hidden += replaced;
        self.stats.fragments_hidden_on_arrival += run.len as u32 - stored;
    }

    fn resolve_row<Q: LinePixel>(&mut self, row: u16, background: Rgb888, out: &mut [Q]) {
        self.band.resolve_row(row, background, out);
    }

    fn pixel_fragment_count(&self, x: u16, row: u16) -> u32 {
        self.band.is_drawn(x, row) as u32
    }

    fn stats(&self) -> BufferStats {
        // One depth test per fragment, and every fragment is stored or hidden.
        let fragments = self.stats.fragments_stored + self.stats.fragments_hidden_on_arrival;
        BufferStats {
            fragments_generated: fragments,
            depth_tests: fragments,
            ..with_most_in_a_pixel(self.stats)
        }
    }

    #[inline]
    fn hidden_count(&self) -> u32 {
        self.stats.fragments_hidden_on_arrival + self.stats.triangles_culled
    }

    fn take_stats(&mut self) -> BufferStats {
        let stats = self.stats();
        self.stats = BufferStats::default();
        stats
    }
}

/// `stats` of a buffer with one fragment a pixel at most, with the most
/// fragments a pixel held derived from it: one, once anything was stored.
pub(crate) fn with_most_in_a_pixel(stats: BufferStats) -> BufferStats {
    BufferStats {
        max_fragments_in_pixel: (stats.fragments_stored > 0) as u32,
        ..stats
    }
}

/// The storage of the z-buffer modes: a band of depths and colors, one per
/// pixel, row by row, and the color its empty pixels hold.
///
/// A band's colors are filled at its start with the background the last
/// resolve asked for (a frame's bands share one), so that a row resolved
/// with that background is its colors as they are, a copy. A band begun
/// before any resolve, or a row asked with another background, is resolved
/// pixel by pixel from the depths (the same colors).
pub(crate) struct DepthColorBand<'a, P: LinePixel = Rgb888> {
    /// Pixels per row.
    pub(crate) width: u16,
    /// Rows the band holds.
    pub(crate) band_height: u16,
    /// Depths ([`EMPTY_DEPTH`] where nothing is drawn).
    pub(crate) depth: &'a mut [u32],
    /// Colors (the fill, where nothing is drawn).
    pub(crate) color: &'a mut [P],
    /// What the next band's colors are filled with.
    next_fill: Option<Rgb888>,
    /// What this band's colors were filled with.
    fill: Option<Rgb888>,
}

impl<'a, P: LinePixel> DepthColorBand<'a, P> {
    /// A band over `depth` and `color`, each of length `width * band_height`;
    /// `None` when a slice has another length or a size is zero.
    pub(crate) fn new(
        width: u16,
        band_height: u16,
        depth: &'a mut [u32],
        color: &'a mut [P],
    ) -> Option<Self> {
        let n = width as usize * band_height as usize;
        if n == 0 || depth.len() != n || color.len() != n {
            return None;
        }
        Some(Self {
            width,
            band_height,
            depth,
            color,
            next_fill: None,
            fill: None,
        })
    }

    /// Where pixel `(x, row)` of the band is in `depth` and `color`.
    #[inline(always)]
    pub(crate) fn index(&self, x: u16, row: u16) -> usize {
        row as usize * self.width as usize + x as usize
    }

    /// Whether pixel `(x, row)` holds a fragment.
    #[inline]
    pub(crate) fn is_drawn(&self, x: u16, row: u16) -> bool {
        self.depth[self.index(x, row)] != EMPTY_DEPTH
    }

    /// Starts a band of `rows` rows (at most `band_height`): every depth
    /// empty, every color the background of the last resolve (when there
    /// was one).
    #[inline]
    pub(crate) fn begin_band(&mut self, rows: u16) {
        let n = self.width as usize * rows as usize;
        crate::words::fill_words(&mut self.depth[..n], EMPTY_DEPTH);
        self.fill = self.next_fill;
        if let Some(background) = self.fill {
            P::fill(&mut self.color[..n], P::from_rgb888(background));
        }
    }

    /// The plain depth test of pixel `p` (ties go to the later fragment, as
    /// in the A-buffer's visibility masks), storing the fragment when it
    /// passes and counting it in `stats`; the depth it replaced, when it
    /// passes. A pixel outside the band is neither stored nor counted.
    #[inline]
    pub(crate) fn test_and_store(
        &mut self,
        p: usize,
        fragment: &Fragment<Mask1x1>,
        stats: &mut BufferStats,
    ) -> Option<u32> {
        let (Some(depth), Some(color)) = (self.depth.get_mut(p), self.color.get_mut(p)) else {
            return None;
        };
        let old = *depth;
        if fragment.mask == Mask1x1::FULL && fragment.z <= old {
            stats.fragments_removed_hidden += (old != EMPTY_DEPTH) as u32;
            *depth = fragment.z;
            color.set_rgb888(fragment.color);
            stats.fragments_stored += 1;
            Some(old)
        } else {
            stats.fragments_hidden_on_arrival += 1;
            None
        }
    }

    /// Row `row` into `out`: a pixel's color, or `background` where nothing
    /// was drawn.
    // Out of line: inlined into the frame loop, its loop reloads what the
    // registers there cannot hold.
    #[inline(never)]
    pub(crate) fn resolve_row<Q: LinePixel>(
        &mut self,
        row: u16,
        background: Rgb888,
        out: &mut [Q],
    ) {
        let start = self.index(0, row);
        let shown = (self.width as usize).min(out.len());
        let (colors, out) = (&self.color[start..start + shown], &mut out[..shown]);
        self.next_fill = Some(background);
        if self.fill == Some(background) {
            if let Some(same) = same_format_mut::<P, Q>(out) {
                // The row as it is: a copy.
                P::copy_line(same, colors);
            } else {
                for (px, &c) in out.iter_mut().zip(colors) {
                    *px = Q::from_rgb888(c.to_rgb888());
                }
            }
            return;
        }
        let depths = &self.depth[start..start + shown];
        for ((px, &z), &c) in out.iter_mut().zip(depths).zip(colors) {
            *px = Q::from_rgb888(if z == EMPTY_DEPTH {
                background
            } else {
                c.to_rgb888()
            });
        }
    }
}

/// `line` as pixels of format `P`, when `Q` is `P` (known when compiled: the
/// test folds away).
#[inline(always)]
fn same_format_mut<P: LinePixel, Q: LinePixel>(line: &mut [Q]) -> Option<&mut [P]> {
    if core::any::TypeId::of::<P>() == core::any::TypeId::of::<Q>() {
        // SAFETY: `P` and `Q` are the same type; the slice is reborrowed
        // with its length and lifetime.
        Some(unsafe { core::slice::from_raw_parts_mut(line.as_mut_ptr().cast::<P>(), line.len()) })
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::band_buffer::insert_each;
    use crate::fixed_point::DEPTH_MAX;
    use crate::setup::Plane;
    use crate::shading::linear::LinearWalk;

    const WIDTH: u16 = 16;
    const ROWS: u16 = 2;

    /// The depth of pixel `i` in [`band_with_pattern`].
    fn pattern_depth(i: usize) -> u32 {
        if i.is_multiple_of(5) {
            EMPTY_DEPTH
        } else {
            (i as u32).wrapping_mul(2_654_435_761) >> 8
        }
    }

    /// A band with a pattern of empty and drawn pixels.
    fn band_with_pattern<'a>(depth: &'a mut [u32], color: &'a mut [Rgb888]) -> ZBuffer<'a> {
        for (i, (d, c)) in depth.iter_mut().zip(color.iter_mut()).enumerate() {
            *d = pattern_depth(i);
            *c = Rgb888::new(i as u8, 1, 2);
        }
        ZBuffer::new(WIDTH, ROWS, depth, color).unwrap()
    }

    /// Inserts `run` with the z-buffer's own loop and pixel by pixel, and
    /// requires the same depths, colors, counters and color walk state.
    fn same_as_pixel_by_pixel(x: u16, run: &FullRun<Mask1x1>) {
        let n = (WIDTH * ROWS) as usize;
        let (mut d1, mut c1) = (vec![0; n], vec![Rgb888::new(0, 0, 0); n]);
        let (mut d2, mut c2) = (vec![0; n], vec![Rgb888::new(0, 0, 0); n]);
        let mut fast = band_with_pattern(&mut d1, &mut c1);
        let mut each = band_with_pattern(&mut d2, &mut c2);
        let planes = [
            Plane {
                origin: 40 << 16,
                dx: 9 << 16,
                dy: 0,
            },
            Plane {
                origin: 200 << 16,
                dx: -7 << 16,
                dy: 0,
            },
            Plane {
                origin: 3 << 16,
                dx: 1 << 15,
                dy: 0,
            },
        ];
        let walk = LinearWalk::<i32>::start(&planes, 0);
        let (mut row1, mut row2) = (walk.row(), walk.row());
        fast.insert_full_run(x, 1, run, &walk, &mut row1);
        insert_each(&mut each, x, 1, run, &walk, &mut row2);
        assert_eq!(row1, row2, "walk state after the run");
        assert_eq!(fast.stats(), each.stats());
        assert_eq!(d1, d2);
        assert_eq!(c1, c2);
    }

    #[test]
    fn full_runs_store_what_single_inserts_store() {
        let template = Fragment {
            mask: Mask1x1::FULL,
            z: 0,
            dzdx: 0,
            dzdy: 0,
            color: Rgb888::new(0, 0, 0),
        };
        let max = (DEPTH_MAX as i64) << 16;
        for (depth, depth_step) in [
            (max / 2, 1 << 20),
            (max / 2, -(1 << 22)),
            (0, 1 << 30),
            // Ends out of range: the clamped path.
            (-(1 << 20), 1 << 28),
            (max - (1 << 20), 1 << 19),
            (max, -(1 << 10)),
            // Steps with fraction bits: carries from the fraction into the
            // depth at irregular pixels, up and down.
            (max / 3 + 12_345, 98_765),
            (max / 2 + 777, -54_321),
            (max / 4 + (1 << 15) - 1, (3 << 16) + 1),
            // Exactly the stored depth of row 1's pixel 3 (a tie).
            ((pattern_depth(WIDTH as usize + 3) as i64) << 16, 0),
        ] {
            for (x, len) in [(0, 1), (0, WIDTH), (3, 7), (WIDTH - 2, 2)] {
                let run = FullRun {
                    len,
                    depth,
                    depth_step,
                    template,
                };
                same_as_pixel_by_pixel(x, &run);
            }
        }
    }

    /// A band's rows resolve to the drawn colors and the background, both
    /// before a resolve has named the background (each pixel told by its
    /// depth) and after (the band's colors filled with it when it begins).
    #[test]
    fn rows_resolve_alike_with_the_background_filled_in_or_not() {
        let n = (WIDTH * ROWS) as usize;
        let (mut depth, mut color) = (vec![0; n], vec![Rgb888::new(0, 0, 0); n]);
        let mut band = ZBuffer::new(WIDTH, ROWS, &mut depth, &mut color).unwrap();
        let background = Rgb888::new(10, 20, 30);
        let fragment = |i: u16| Fragment {
            mask: Mask1x1::FULL,
            z: 1000 + i as u32,
            dzdx: 0,
            dzdy: 0,
            color: Rgb888::new(i as u8, 7, 9),
        };
        let mut resolved = [Rgb888::new(0, 0, 0); WIDTH as usize];
        for band_index in 0..3 {
            band.begin_band(band_index * ROWS, ROWS);
            // Every third pixel drawn, the others empty.
            for row in 0..ROWS {
                for x in (row..WIDTH).step_by(3) {
                    band.insert(x, row, &fragment(x + band_index));
                }
            }
            for row in 0..ROWS {
                band.resolve_row(row, background, &mut resolved);
                for (x, c) in resolved.iter().enumerate() {
                    let drawn = x >= row as usize && (x - row as usize).is_multiple_of(3);
                    let expected = if drawn {
                        fragment(x as u16 + band_index).color
                    } else {
                        background
                    };
                    assert_eq!(*c, expected, "band {band_index}, row {row}, x {x}");
                }
            }
        }
    }
}
