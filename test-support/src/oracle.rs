//! The oracle of SPEC section 3: an unlimited A-buffer is exactly a per-sample
//! z-buffer that shades once per fragment.

use embedded_graphics_core::pixelcolor::{Rgb888, RgbColor};
use mcu_abuffer::band_buffer::BandBuffer;
use mcu_abuffer::coverage::CoverageMask;
use mcu_abuffer::fragment::Fragment;
use mcu_abuffer::sink::LinePixel;
use mcu_abuffer::stats::BufferStats;

/// A z-buffer per sample over one band: a depth ([`Fragment::depth_at`], i.e.
/// `16 z + dzdx ox + dzdy oy`) and a color for every sample of grid `M`. For
/// every sample of a fragment's mask, the fragment wins when its depth there is
/// nearer than or equal to the stored one (ties go to the newer fragment, as in
/// the A-buffer). A pixel resolves to the mean of its samples' colors, the
/// background where a sample is empty, rounded to nearest as
/// `(sum + SAMPLES / 2) >> log2(SAMPLES)`.
///
/// With [`PerSampleZBuffer::counting_hits`] it also counts, over the whole
/// image, how many fragments covered each sample.
pub struct PerSampleZBuffer<M: CoverageMask> {
    width: u16,
    band_height: u16,
    y0: u16,
    rows: u16,
    depth: Vec<Option<i32>>,
    color: Vec<Rgb888>,
    /// Coverage count of every sample of the image, rows top to bottom (empty
    /// unless counting).
    hits: Vec<u32>,
    image_height: u16,
    stats: BufferStats,
    _grid: core::marker::PhantomData<M>,
}

impl<M: CoverageMask> PerSampleZBuffer<M> {
    /// An empty buffer for bands of `band_height` rows of `width` pixels.
    pub fn new(width: u16, band_height: u16) -> Self {
        let n = width as usize * band_height as usize * M::SAMPLES as usize;
        Self {
            width,
            band_height,
            y0: 0,
            rows: 0,
            depth: vec![None; n],
            color: vec![Rgb888::BLACK; n],
            hits: Vec::new(),
            image_height: 0,
            stats: BufferStats::default(),
            _grid: core::marker::PhantomData,
        }
    }

    /// The same buffer, also counting how many fragments cover each sample of
    /// an image `image_height` rows high (from now on, over every frame).
    pub fn counting_hits(mut self, image_height: u16) -> Self {
        self.image_height = image_height;
        self.hits = vec![0; self.width as usize * image_height as usize * M::SAMPLES as usize];
        self
    }

    /// How many fragments covered sample `s` of image pixel `(x, y)`; needs
    /// [`PerSampleZBuffer::counting_hits`].
    pub fn hits(&self, x: u16, y: u16, s: u32) -> u32 {
        assert!(y < self.image_height, "not counting row {y}");
        self.hits[self.image_sample(x, y, s)]
    }

    /// Rows of the band last begun (0 before the first).
    pub fn rows(&self) -> u16 {
        self.rows
    }

    /// The mean of the sample colors of pixel `(x, row)`, `background` where a
    /// sample is empty.
    pub fn resolve_pixel(&self, x: u16, row: u16, background: Rgb888) -> [u8; 3] {
        let base = self.base(x, row);
        let mut sum = [0u32; 3];
        for i in base..base + M::SAMPLES as usize {
            let c = if self.depth[i].is_some() {
                self.color[i]
            } else {
                background
            };
            sum[0] += c.r() as u32;
            sum[1] += c.g() as u32;
            sum[2] += c.b() as u32;
        }
        sum.map(|v| ((v + M::SAMPLES / 2) >> M::SAMPLES_LOG2) as u8)
    }

    /// Every row of the band as RGB888 bytes.
    pub fn resolve_all(&self, background: Rgb888) -> Vec<u8> {
        let mut out = Vec::new();
        for row in 0..self.band_height {
            for x in 0..self.width {
                out.extend(self.resolve_pixel(x, row, background));
            }
        }
        out
    }

    /// Distinct colors visible in pixel `(x, row)`.
    pub fn surfaces(&self, x: u16, row: u16) -> usize {
        let base = self.base(x, row);
        let mut seen: Vec<Rgb888> = Vec::new();
        for i in base..base + M::SAMPLES as usize {
            if self.depth[i].is_some() && !seen.contains(&self.color[i]) {
                seen.push(self.color[i]);
            }
        }
        seen.len()
    }

    fn base(&self, x: u16, row: u16) -> usize {
        (row as usize * self.width as usize + x as usize) * M::SAMPLES as usize
    }

    fn image_sample(&self, x: u16, y: u16, s: u32) -> usize {
        (y as usize * self.width as usize + x as usize) * M::SAMPLES as usize + s as usize
    }
}

impl<M: CoverageMask> BandBuffer<M> for PerSampleZBuffer<M> {
    fn width(&self) -> u16 {
        self.width
    }

    fn band_height(&self) -> u16 {
        self.band_height
    }

    fn begin_band(&mut self, y0: u16, rows: u16) {
        self.y0 = y0;
        self.rows = rows;
        self.depth.fill(None);
    }

    fn insert(&mut self, x: u16, row: u16, f: &Fragment<M>) {
        self.stats.fragments_generated += 1;
        let base = self.base(x, row);
        let counting = !self.hits.is_empty();
        for s in 0..M::SAMPLES {
            if !f.mask.get(s) {
                continue;
            }
            if counting {
                let i = self.image_sample(x, self.y0 + row, s);
                self.hits[i] += 1;
            }
            let d = f.depth_at(s % M::COLS, s / M::COLS);
            let slot = base + s as usize;
            let wins = match self.depth[slot] {
                None => true,
                Some(stored) => d <= stored,
            };
            if wins {
                self.depth[slot] = Some(d);
                self.color[slot] = f.color;
            }
        }
    }

    fn resolve_row<P: LinePixel>(&mut self, row: u16, background: Rgb888, out: &mut [P]) {
        for (x, px) in out.iter_mut().enumerate().take(self.width as usize) {
            let [r, g, b] = self.resolve_pixel(x as u16, row, background);
            *px = P::from_rgb888(Rgb888::new(r, g, b));
        }
    }

    /// Distinct visible colors ([`PerSampleZBuffer::surfaces`]).
    fn pixel_fragment_count(&self, x: u16, row: u16) -> u32 {
        self.surfaces(x, row) as u32
    }

    fn stats(&self) -> BufferStats {
        self.stats
    }

    fn take_stats(&mut self) -> BufferStats {
        core::mem::take(&mut self.stats)
    }
}
