//! Triangle setup and rasterization on their own, fed window-space triangles with
//! every extreme the projection can hand them: vertices anywhere in the guard band
//! (and beyond it, where setup clamps), depths from 0 to the far plane, colors at
//! both ends of their range, slivers of almost no area, and every color source
//! (constant, Gouraud, quadratic and Phong with any unit normals and any light).
//!
//! Checked: no panic or overflow; fragments only on the screen and in the band,
//! once per pixel, with a depth in range; every pixel's coverage mask equal to
//! the one the exact edge functions (128-bit, top-left rule) give at its samples.
#![no_main]

use abuffer_fuzz::{extreme_coord3, extreme_normal};
use embedded_graphics_core::pixelcolor::Rgb888;
use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use mcu_abuffer::band_buffer::BandBuffer;
use mcu_abuffer::coverage::{CoverageMask, Mask4x4, Mask8x4, Mask8x8};
use mcu_abuffer::fixed_point::{Coord, DEPTH_MAX, GUARD_BAND_PX, SUBPIXEL_BITS};
use mcu_abuffer::fragment::{Fragment, GRADIENT_LIMIT};
use mcu_abuffer::geometry::ViewBasis;
use mcu_abuffer::lighting::{rgb888_rounded, LightSetup};
use mcu_abuffer::raster::rasterize;
use mcu_abuffer::scene::{Camera, Light};
use mcu_abuffer::setup::{signed_area2, SetupVertex, TriangleSetup};
use mcu_abuffer::shading::{ColorSource, TriangleLighting};
use mcu_abuffer::sink::LinePixel;
use mcu_abuffer::stats::BufferStats;

const LIMIT: i32 = GUARD_BAND_PX << SUBPIXEL_BITS;

/// A window coordinate in 1/16 pixel: an edge of the guard band or of the screen,
/// one step inside or outside them, or any value in (or a little beyond) the band.
fn coordinate(u: &mut Unstructured<'_>, side: u16) -> Result<i32> {
    let screen = (side as i32) << SUBPIXEL_BITS;
    Ok(match u.int_in_range(0u8..=11)? {
        0 => LIMIT,
        1 => -LIMIT,
        2 => LIMIT - 1,
        3 => -LIMIT + 1,
        4 => 0,
        5 => screen,
        6 => screen + u.int_in_range(-2..=2)?,
        7 => u.int_in_range(-2..=2)?,
        8 => u.int_in_range(-2 * LIMIT..=2 * LIMIT)?,
        _ => u.int_in_range(-LIMIT..=LIMIT)?,
    })
}

fn depth(u: &mut Unstructured<'_>) -> Result<u32> {
    Ok(match u.int_in_range(0u8..=4)? {
        0 => 0,
        1 => DEPTH_MAX,
        2 => DEPTH_MAX - u.int_in_range(0..=3)?,
        _ => u.int_in_range(0..=DEPTH_MAX)?,
    })
}

fn color_q8(u: &mut Unstructured<'_>) -> Result<[i32; 3]> {
    let mut c = [0; 3];
    for v in &mut c {
        *v = match u.int_in_range(0u8..=3)? {
            0 => 0,
            1 => 255 << 8,
            _ => u.int_in_range(0..=255 << 8)?,
        };
    }
    Ok(c)
}

/// A light prepared for a fixed camera, with any direction and coefficients.
fn light(u: &mut Unstructured<'_>) -> Result<LightSetup> {
    let camera = Camera {
        eye: [Coord::ZERO, Coord::ZERO, Coord::from_num(4)],
        target: [Coord::ZERO; 3],
        up: [Coord::ZERO, Coord::ONE, Coord::ZERO],
        fov_y_deg: Coord::from_num(60),
        near: Coord::ONE,
        far: Coord::from_num(10),
    };
    let view = ViewBasis::new(&camera).expect("camera basis");
    let mut direction = extreme_coord3(u)?;
    if direction == [Coord::ZERO; 3] {
        direction[2] = Coord::ONE;
    }
    let light = Light {
        direction,
        ambient: Coord::from_bits(u.arbitrary::<i32>()? >> u.int_in_range(0..=31)?),
        diffuse: Coord::from_bits(u.arbitrary::<i32>()? >> u.int_in_range(0..=31)?),
        specular: Coord::from_bits(u.arbitrary::<i32>()? >> u.int_in_range(0..=31)?),
        shininess: u.arbitrary()?,
    };
    Ok(LightSetup::new(&light, &view))
}

/// Vertex normals, a light and a base color, drawn in that order.
fn lighting(u: &mut Unstructured<'_>) -> Result<([[i32; 3]; 3], LightSetup, Rgb888)> {
    let mut normals = [[0i32; 3]; 3];
    for n in &mut normals {
        *n = extreme_normal(u)?.map(|c| c.to_bits() as i32);
        // Only unit normals reach shading (the scene check refuses others).
        let len2: i64 = n.iter().map(|&c| (c as i64).pow(2)).sum();
        if len2.abs_diff(1 << 28) > 1 << 22 {
            *n = [0, 0, 1 << 14];
        }
    }
    let light = light(u)?;
    let base = Rgb888::new(u.arbitrary()?, u.arbitrary()?, u.arbitrary()?);
    Ok((normals, light, base))
}

/// Records the fragments of one band and checks where they land.
struct Recorder<M: CoverageMask> {
    width: u16,
    rows: u16,
    masks: Vec<Option<M>>,
}

impl<M: CoverageMask> BandBuffer<M> for Recorder<M> {
    fn width(&self) -> u16 {
        self.width
    }
    fn band_height(&self) -> u16 {
        self.rows
    }
    fn begin_band(&mut self, _y0: u16, _rows: u16) {}
    fn insert(&mut self, x: u16, row: u16, f: &Fragment<M>) {
        assert!(
            x < self.width && row < self.rows,
            "fragment at ({x}, {row}) off the band"
        );
        assert!(!f.mask.is_empty());
        assert!(f.z <= DEPTH_MAX);
        assert!(f.dzdx.abs() <= GRADIENT_LIMIT && f.dzdy.abs() <= GRADIENT_LIMIT);
        let slot = &mut self.masks[row as usize * self.width as usize + x as usize];
        assert!(slot.is_none(), "pixel ({x}, {row}) rasterized twice");
        *slot = Some(f.mask);
    }
    fn resolve_row<P: LinePixel>(&mut self, _row: u16, _background: Rgb888, _out: &mut [P]) {}
    fn pixel_fragment_count(&self, _x: u16, _row: u16) -> u32 {
        0
    }
    fn stats(&self) -> BufferStats {
        BufferStats::default()
    }
    fn take_stats(&mut self) -> BufferStats {
        BufferStats::default()
    }
}

/// The mask the exact edge functions give pixel `(x, y)`: setup's orientation,
/// clamping and top-left rule, evaluated independently in 128 bits.
fn exact_mask<M: CoverageMask>(v: &[SetupVertex; 3], x: u16, y: u16) -> M {
    let area2 = signed_area2(v);
    let v = if area2 > 0 {
        [v[0], v[1], v[2]]
    } else {
        [v[0], v[2], v[1]]
    };
    let lim = LIMIT as i128;
    let xs = v.map(|p| (p.x as i128).clamp(-lim, lim));
    let ys = v.map(|p| (p.y as i128).clamp(-lim, lim));
    let mut mask = M::EMPTY;
    for s in 0..M::SAMPLES {
        let px = ((x as i128) << 4) + 8 + M::offset_x(s % M::COLS) as i128;
        let py = ((y as i128) << 4) + 8 + M::offset_y(s / M::COLS) as i128;
        let inside = (0..3).all(|i| {
            let (a, b) = (i, (i + 1) % 3);
            let ea = -(ys[b] - ys[a]);
            let eb = xs[b] - xs[a];
            let top_left = ea > 0 || (ea == 0 && eb > 0);
            ea * (px - xs[a]) + eb * (py - ys[a]) - if top_left { 0 } else { 1 } >= 0
        });
        if inside {
            mask = mask.with(s);
        }
    }
    mask
}

fn run<M: CoverageMask>(u: &mut Unstructured<'_>) -> Result<()> {
    let width = u.int_in_range(1..=64u16)?;
    let height = if u.arbitrary()? {
        u.int_in_range(1..=64u16)?
    } else {
        2048
    };
    let mut v = [SetupVertex::default(); 3];
    let mut vertex_colors = [[0; 3]; 3];
    for (p, color) in v.iter_mut().zip(&mut vertex_colors) {
        *p = SetupVertex {
            x: coordinate(u, width)?,
            y: coordinate(u, height)?,
            z: depth(u)?,
        };
        *color = color_q8(u)?;
    }
    // Slivers: the third vertex on or next to the line through the other two.
    if u.ratio(1u8, 4)? {
        let t: i64 = u.int_in_range(-4..=4)?;
        let (dx, dy) = ((v[1].x - v[0].x) as i64, (v[1].y - v[0].y) as i64);
        v[2].x = (v[0].x as i64 + t * dx / 4 + u.int_in_range(-1..=1)?) as i32;
        v[2].y = (v[0].y as i64 + t * dy / 4 + u.int_in_range(-1..=1)?) as i32;
    }
    let kind = u.int_in_range(0u8..=3)?;
    let light;
    let colors = match kind {
        0 => ColorSource::Constant(Rgb888::new(u.arbitrary()?, 1, 2)),
        1 => ColorSource::Linear(vertex_colors),
        _ => {
            let (normals, setup, base) = lighting(u)?;
            light = setup;
            let lit = TriangleLighting {
                normals,
                light: &light,
                base,
            };
            if kind == 2 {
                ColorSource::Quadratic(lit, vertex_colors.map(rgb888_rounded))
            } else {
                ColorSource::Phong(lit)
            }
        }
    };
    let cull = u.arbitrary()?;
    let setup = TriangleSetup::new(&v, cull, width, height);
    if std::env::var_os("FUZZ_PRINT").is_some() {
        eprintln!(
            "setup: {:?}",
            setup
                .as_ref()
                .map(|s| s.color_planes(colors))
                .map_err(|e| *e)
        );
    }
    let Ok(setup) = setup else {
        return Ok(());
    };
    assert!(setup.x0 <= setup.x1 && setup.x1 < width);
    assert!(setup.y0 <= setup.y1 && setup.y1 < height);
    let rows = u.int_in_range(1..=4u16)?;
    let band_y0 = u.int_in_range(0..=height - 1)?;
    let rows = rows.min(height - band_y0);
    let mut recorder = Recorder::<M> {
        width,
        rows,
        masks: vec![None; width as usize * rows as usize],
    };
    rasterize(&setup, band_y0, rows, &mut recorder, || {
        setup.color_planes(colors)
    });
    for row in 0..rows {
        for x in 0..width {
            let expected = exact_mask::<M>(&v, x, band_y0 + row);
            let got = recorder.masks[row as usize * width as usize + x as usize];
            assert_eq!(
                got.unwrap_or(M::EMPTY),
                expected,
                "coverage of pixel ({x}, {}) for {v:?}",
                band_y0 + row
            );
        }
    }
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let mut u = Unstructured::new(data);
    let _ = match u.int_in_range(0u8..=2).unwrap_or(0) {
        0 => run::<Mask4x4>(&mut u),
        1 => run::<Mask8x4>(&mut u),
        _ => run::<Mask8x8>(&mut u),
    };
});
