//! The renderer on the desktop, set up as a firmware would set it up: the
//! memory in `static`s, a scene in code, one frame into an RGB image, written
//! as a binary PPM.
//!
//!     cargo run --release -p mcu-abuffer --example octahedron -- octahedron.ppm
//!
//! For whole scenes, meshes from files, reference images and measurements,
//! use `host-sim`.

use embedded_graphics_core::pixelcolor::Rgb888;
use mcu_abuffer::memory::{FragmentMemory, WorkspaceMemory};
use mcu_abuffer::scene::OCTAHEDRON;
use mcu_abuffer::{Camera, Coord, FrameOptions, ImageSink, Light, Mask4x4, OverflowPolicy};
use mcu_abuffer::{Renderer, Scene, SceneObject, Shading, Transform};
use static_cell::ConstStaticCell;

const WIDTH: usize = 240;
const HEIGHT: usize = 240;

static FRAGMENTS: ConstStaticCell<FragmentMemory<Mask4x4, WIDTH, 6, 1, 2, 1152>> =
    ConstStaticCell::new(FragmentMemory::new());
static WORKSPACE: ConstStaticCell<WorkspaceMemory<HEIGHT, 1, 6, 8>> =
    ConstStaticCell::new(WorkspaceMemory::new());

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "octahedron.ppm".to_string());
    let objects = [SceneObject {
        mesh: OCTAHEDRON,
        color: Rgb888::new(220, 170, 120),
        transform: Transform {
            rotation_deg: [Coord::ZERO, Coord::from_num(30), Coord::ZERO],
            ..Transform::default()
        },
        cull_backfaces: true,
        shading: Shading::Quadratic,
    }];
    let scene = Scene {
        width: WIDTH as u16,
        height: HEIGHT as u16,
        background: Rgb888::new(16, 18, 28),
        camera: Camera {
            eye: [Coord::ZERO, Coord::from_num(1.2), Coord::from_num(3.5)],
            target: [Coord::ZERO; 3],
            up: [Coord::ZERO, Coord::ONE, Coord::ZERO],
            fov_y_deg: Coord::from_num(40),
            near: Coord::ONE,
            far: Coord::from_num(10),
        },
        light: Some(Light {
            direction: [Coord::from_num(-0.4), Coord::from_num(0.7), Coord::ONE],
            ambient: Coord::from_num(0.15),
            diffuse: Coord::from_num(0.75),
            specular: Coord::from_num(0.4),
            shininess: 24,
        }),
        objects: &objects,
    };

    let buffer = FRAGMENTS.take().buffer(OverflowPolicy::SplitBands);
    let mut renderer = Renderer::new(WORKSPACE.take().workspace(), buffer);
    let mut rgb = vec![0u8; WIDTH * HEIGHT * 3];
    let stats = renderer
        .render(
            &scene,
            &FrameOptions::default(),
            &mut ImageSink::new(WIDTH as u16, &mut rgb),
        )
        .map_err(|e| format!("{e}"))?;

    let mut ppm = format!("P6\n{WIDTH} {HEIGHT}\n255\n").into_bytes();
    ppm.extend_from_slice(&rgb);
    std::fs::write(&out, ppm).map_err(|e| format!("{out}: {e}"))?;
    println!(
        "{out}: {} fragments, {} stored, {} merges",
        stats.buffer.fragments_generated, stats.buffer.fragments_stored, stats.buffer.merges
    );
    Ok(())
}
