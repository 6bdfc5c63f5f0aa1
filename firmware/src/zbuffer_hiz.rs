//! A hierarchical z-buffer: the plain z-buffer plus, for every 8 x 8 tile of
//! the band, the farthest depth its pixels hold (SPEC section 7, the baseline
//! of the midpoint subdivision).
//!
//! Before a triangle is rasterized, every tile of its bounding box (within the
//! band) is tested once: the triangle's nearest depth over the tile's part of
//! the box against the tile's farthest depth. A tile where the triangle is
//! behind is rejected: its pixels are passed over without reading the depth
//! buffer. A triangle rejected in every tile is not rasterized at all.
//!
//! The test is conservative, so the image is the plain z-buffer's bit for bit:
//! depth is affine over pixel centers, so its smallest value over a rectangle
//! of pixels is at a corner, and the rasterizer's rounding is monotonic, so the
//! nearest depth computed here is exactly the smallest depth any fragment of the
//! triangle gets in the tile. Ties go to the new fragment, as in the z-buffer,
//! so a tile rejects only when that depth is strictly farther than the tile's.
//!
//! A tile's farthest depth stays exact at little cost: each tile also counts
//! its pixels at that depth. Overwriting one of them lowers the count, and only
//! when the count reaches zero is the tile's farthest depth recomputed from its
//! pixels (counted as [`BufferStats::tile_refresh_reads`]).

use crate::band_buffer::{BandBuffer, DrawParams};
use crate::coverage::Mask1x1;
use crate::fixed_point::DEPTH_MAX;
use crate::fragment::Fragment;
use crate::raster::rasterize;
use crate::setup::{Rejection, SetupVertex, TriangleSetup};
use crate::sink::LinePixel;
use crate::stats::BufferStats;
use crate::zbuffer::{with_most_in_a_pixel, DepthColorBand, EMPTY_DEPTH};
use embedded_graphics_core::pixelcolor::Rgb888;

/// log2 of the tile side.
const TILE_SHIFT: u32 = 3;
/// Pixels per tile side.
pub const TILE_SIDE: u16 = 1 << TILE_SHIFT;

/// One tile of a [`HierarchicalZBuffer`]: its farthest depth and how many of
/// its pixels hold it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HizTile {
    far: u32,
    far_pixels: u8,
    rejected: bool,
}

impl HizTile {
    /// A tile of an empty band (for static initializers).
    pub const EMPTY: Self = Self {
        far: EMPTY_DEPTH,
        far_pixels: 0,
        rejected: false,
    };

    /// The farthest depth held by the tile's pixels ([`EMPTY_DEPTH`] while one is empty).
    pub fn far(&self) -> u32 {
        self.far
    }
}

impl Default for HizTile {
    fn default() -> Self {
        Self::EMPTY
    }
}

/// Tiles a band of `width x band_height` pixels needs.
pub const fn tile_count(width: u16, band_height: u16) -> usize {
    let side = TILE_SIDE as usize;
    (width as usize).div_ceil(side) * (band_height as usize).div_ceil(side)
}

/// A band of depths and colors, one per pixel, with a farthest depth per 8 x 8 tile.
pub struct HierarchicalZBuffer<'a> {
    band: DepthColorBand<'a>,
    rows: u16,
    tiles_x: u16,
    tiles: &'a mut [HizTile],
    stats: BufferStats,
}

impl<'a> HierarchicalZBuffer<'a> {
    /// A hierarchical z-buffer over `depth` and `color`, each of length
    /// `width * band_height`, and `tiles` of length [`tile_count`].
    ///
    /// Returns `None` when a slice has another length or a size is zero.
    pub fn new(
        width: u16,
        band_height: u16,
        depth: &'a mut [u32],
        color: &'a mut [Rgb888],
        tiles: &'a mut [HizTile],
    ) -> Option<Self> {
        if tiles.len() != tile_count(width, band_height) {
            return None;
        }
        Some(Self {
            band: DepthColorBand::new(width, band_height, depth, color)?,
            rows: band_height,
            tiles_x: width.div_ceil(TILE_SIDE),
            tiles,
            stats: BufferStats::default(),
        })
    }

    /// The tile holding pixel `(x, row)` of the band.
    #[inline]
    fn tile_index(&self, x: u16, row: u16) -> usize {
        (row >> TILE_SHIFT) as usize * self.tiles_x as usize + (x >> TILE_SHIFT) as usize
    }

    /// Pixel ranges (columns, band rows; end exclusive) of tile `(tx, ty)`.
    #[inline]
    fn tile_pixels(&self, tx: u16, ty: u16) -> (u16, u16, u16, u16) {
        let x0 = tx << TILE_SHIFT;
        let y0 = ty << TILE_SHIFT;
        (
            x0,
            (x0 + TILE_SIDE).min(self.band.width),
            y0,
            (y0 + TILE_SIDE).min(self.rows),
        )
    }

    /// Recomputes the farthest depth of tile `t` (at `(tx, ty)`) from its pixels.
    fn refresh_tile(&mut self, t: usize, tx: u16, ty: u16) {
        let (x0, x1, y0, y1) = self.tile_pixels(tx, ty);
        let mut far = 0u32;
        let mut count = 0u8;
        for row in y0..y1 {
            let start = self.band.index(0, row);
            for &d in &self.band.depth[start + x0 as usize..start + x1 as usize] {
                if d > far {
                    far = d;
                    count = 1;
                } else if d == far {
                    count += 1;
                }
            }
        }
        self.stats.tile_refresh_reads += (x1 - x0) as u32 * (y1 - y0) as u32;
        let tile = &mut self.tiles[t];
        tile.far = far;
        tile.far_pixels = count;
    }

    /// Marks every tile of band rows `r0 ..= r1` and columns `x0 ..= x1`
    /// where `setup` is behind; returns whether any tile stays open.
    fn reject_tiles(
        &mut self,
        setup: &TriangleSetup,
        band_y0: u16,
        cols: (u16, u16),
        rows: (u16, u16),
    ) -> bool {
        let (x0, x1) = cols;
        let (r0, r1) = rows;
        let mut open = false;
        for ty in (r0 >> TILE_SHIFT)..=(r1 >> TILE_SHIFT) {
            let ya = (ty << TILE_SHIFT).max(r0);
            let yb = ((ty << TILE_SHIFT) + TILE_SIDE - 1).min(r1);
            for tx in (x0 >> TILE_SHIFT)..=(x1 >> TILE_SHIFT) {
                let xa = (tx << TILE_SHIFT).max(x0);
                let xb = ((tx << TILE_SHIFT) + TILE_SIDE - 1).min(x1);
                // The corner of the rectangle where the depth plane is smallest.
                let x = if setup.depth.dx >= 0 { xa } else { xb };
                let y = band_y0 + if setup.depth.dy >= 0 { ya } else { yb };
                let nearest = depth_at(setup, x, y);
                let t = ty as usize * self.tiles_x as usize + tx as usize;
                self.stats.culling_depth_tests += 1;
                if nearest > self.tiles[t].far {
                    self.tiles[t].rejected = true;
                    self.stats.pieces_culled += 1;
                } else {
                    open = true;
                }
            }
        }
        open
    }

    /// Clears the rejection marks of the tiles of band rows `r0 ..= r1`, columns `x0 ..= x1`.
    fn clear_rejections(&mut self, cols: (u16, u16), rows: (u16, u16)) {
        for ty in (rows.0 >> TILE_SHIFT)..=(rows.1 >> TILE_SHIFT) {
            let start = ty as usize * self.tiles_x as usize;
            for tile in &mut self.tiles
                [start + (cols.0 >> TILE_SHIFT) as usize..=start + (cols.1 >> TILE_SHIFT) as usize]
            {
                tile.rejected = false;
            }
        }
    }
}

/// The depth the rasterizer gives `setup`'s fragment at pixel `(x, y)` of the image.
#[inline]
fn depth_at(setup: &TriangleSetup, x: u16, y: u16) -> u32 {
    let z = setup.depth.origin
        + (x as i64 - setup.x0 as i64) * setup.depth.dx
        + (y as i64 - setup.y0 as i64) * setup.depth.dy;
    ((z + (1 << 15)) >> 16).clamp(0, DEPTH_MAX as i64) as u32
}

impl BandBuffer<Mask1x1> for HierarchicalZBuffer<'_> {
    fn width(&self) -> u16 {
        self.band.width
    }

    fn band_height(&self) -> u16 {
        self.band.band_height
    }

    fn begin_band(&mut self, _y0: u16, rows: u16) {
        self.rows = rows.clamp(1, self.band.band_height);
        self.band.begin_band(self.rows);
        let tiles_y = self.rows.div_ceil(TILE_SIDE);
        for ty in 0..tiles_y {
            for tx in 0..self.tiles_x {
                let (x0, x1, y0, y1) = self.tile_pixels(tx, ty);
                self.tiles[ty as usize * self.tiles_x as usize + tx as usize] = HizTile {
                    far: EMPTY_DEPTH,
                    far_pixels: ((x1 - x0) * (y1 - y0)) as u8,
                    rejected: false,
                };
            }
        }
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
        let band_last = band_y0 as u32 + rows as u32 - 1;
        if (setup.y1 as u32) < band_y0 as u32 || setup.y0 as u32 > band_last {
            return Ok(());
        }
        let r0 = setup.y0.max(band_y0) - band_y0;
        let r1 = ((setup.y1 as u32).min(band_last) - band_y0 as u32) as u16;
        let cols = (setup.x0, setup.x1.min(self.band.width - 1));
        if self.reject_tiles(&setup, band_y0, cols, (r0, r1)) {
            rasterize(&setup, band_y0, rows, self, || (params.colors)(&setup));
        } else {
            self.stats.triangles_culled += 1;
        }
        self.clear_rejections(cols, (r0, r1));
        Ok(())
    }

    #[inline]
    fn insert(&mut self, x: u16, row: u16, fragment: &Fragment<Mask1x1>) {
        self.stats.fragments_generated += 1;
        let t = self.tile_index(x, row);
        if self.tiles[t].rejected {
            // Behind the tile's farthest depth: hidden without a look at the pixel.
            self.stats.fragments_hidden_on_arrival += 1;
            return;
        }
        self.stats.depth_tests += 1;
        let p = self.band.index(x, row);
        if let Some(old) = self.band.test_and_store(p, fragment, &mut self.stats) {
            let tile = &mut self.tiles[t];
            if old == tile.far && fragment.z != old {
                tile.far_pixels -= 1;
                if tile.far_pixels == 0 {
                    self.refresh_tile(t, x >> TILE_SHIFT, row >> TILE_SHIFT);
                }
            }
        }
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
    use crate::shading::{ColorPlanes, ColorSource};
    use crate::zbuffer::ZBuffer;

    const W: u16 = 40;
    const H: u16 = 24;

    fn vertex(x: i32, y: i32, z: u32) -> SetupVertex {
        SetupVertex {
            x: x * 16,
            y: y * 16,
            z,
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

    /// Draws `triangles` into both buffers over bands of `band` rows and
    /// returns the two images.
    fn draw_both(
        triangles: &[([SetupVertex; 3], u8)],
        band: u16,
    ) -> (Vec<Rgb888>, Vec<Rgb888>, BufferStats) {
        let n = W as usize * band as usize;
        let (mut d1, mut c1) = (vec![0; n], vec![Rgb888::new(0, 0, 0); n]);
        let (mut d2, mut c2) = (vec![0; n], vec![Rgb888::new(0, 0, 0); n]);
        let mut tiles = vec![HizTile::EMPTY; tile_count(W, band)];
        let mut plain = ZBuffer::new(W, band, &mut d1, &mut c1).unwrap();
        let mut hiz = HierarchicalZBuffer::new(W, band, &mut d2, &mut c2, &mut tiles).unwrap();
        let bg = Rgb888::new(1, 2, 3);
        let (mut a, mut b) = (Vec::new(), Vec::new());
        let mut line = vec![bg; W as usize];
        let mut y0 = 0;
        while y0 < H {
            let rows = band.min(H - y0);
            plain.begin_band(y0, rows);
            hiz.begin_band(y0, rows);
            for (t, c) in triangles {
                let colors = |s: &TriangleSetup| {
                    s.color_planes(ColorSource::Constant(Rgb888::new(*c, *c, *c)))
                };
                let _ = plain.draw_triangle(t, &params(&colors), y0, rows);
                let _ = hiz.draw_triangle(t, &params(&colors), y0, rows);
            }
            for row in 0..rows {
                plain.resolve_row(row, bg, &mut line);
                a.extend_from_slice(&line);
                hiz.resolve_row(row, bg, &mut line);
                b.extend_from_slice(&line);
            }
            y0 += rows;
        }
        (a, b, hiz.take_stats())
    }

    #[test]
    fn hidden_triangle_is_culled_whole_and_images_agree() {
        let near = [
            vertex(-2, -2, 1000),
            vertex(60, -2, 1000),
            vertex(-2, 60, 1000),
        ];
        let far = [vertex(3, 3, 5000), vertex(20, 4, 5000), vertex(6, 18, 5000)];
        for band in [H, 16, 8, 5] {
            let (a, b, stats) = draw_both(&[(near, 200), (far, 100)], band);
            assert_eq!(a, b, "band {band}");
            assert!(stats.triangles_culled >= 1, "band {band}: {stats:?}");
            assert!(stats.pieces_culled > 0);
        }
    }

    #[test]
    fn tile_depth_stays_exact_and_images_agree() {
        // Many overlapping triangles at mixed depths.
        let mut seed = 0x1234_5678u32;
        let mut next = |m: i32| {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            (seed % m as u32) as i32
        };
        let triangles: Vec<_> = (0..60)
            .map(|i| {
                let v = [0, 1, 2].map(|_| {
                    vertex(
                        next(W as i32 + 8) - 4,
                        next(H as i32 + 8) - 4,
                        1000 + next(100_000) as u32,
                    )
                });
                (v, i as u8)
            })
            .collect();
        for band in [H, 16, 7] {
            let (a, b, stats) = draw_both(&triangles, band);
            assert_eq!(a, b, "band {band}");
            assert!(stats.tile_refresh_reads > 0);
        }
    }
}
