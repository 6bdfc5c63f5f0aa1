//! An antialiasing 3D renderer for microcontrollers.
//!
//! Triangle meshes are drawn with a modified A-buffer: each pixel keeps a short
//! list of fragments (coverage mask, color, depth and its gradients), per-sample
//! visibility masks resolve intersecting surfaces exactly, a few fixed slots per
//! pixel are backed by a shared overflow pool, and when memory runs out the two
//! farthest fragments merge into one. The image is rendered in bands of rows so the
//! fragment memory is a band, not a frame, and each finished line streams to a
//! display.
//!
//! The crate is `no_std` and never allocates: every buffer is borrowed from the
//! caller (static arrays on a device). All arithmetic after scene loading is
//! integer, so a device and the desktop simulator produce the same bits.
//!
//! The public API is what a firmware needs: the memory types ([`memory`]),
//! a [`Renderer`], the [`scene`] description, the output [`sink`]s, the
//! frame statistics ([`stats`]) and the band buffers with their options
//! ([`FragmentBuffer`] and [`OverflowPolicy`]; [`ZBuffer`] and its culling
//! variants). The pipeline's stages are modules named after them, in the
//! order a frame runs through them: `geometry` (transform, outcodes,
//! projection), `clip`, `lighting`, `setup` (edge functions, depth and color
//! planes), `shading` (quadratic and Phong shading, color walkers), `raster`
//! (with `coverage` masks), `fragment_buffer` (with `visibility`, `merge`,
//! `pool`) or `zbuffer` (`zbuffer_hiz`, `zbuffer_midpoint`), resolve, `sink`;
//! `renderer` drives them, drawing each band's triangles in `draw_order`.
//! Those modules are public for the simulator, the system tests and the fuzz
//! targets, but hidden from this documentation and not part of the stable
//! API.
//!
//! # Add it to your firmware
//!
//! The memory lives in `static`s sized by const generics ([`memory`]); a
//! [`static_cell::ConstStaticCell`](https://docs.rs/static_cell) hands each
//! out once, without `unsafe` and without a copy through the stack. A
//! [`Renderer`] then draws a [`Scene`] (meshes in flash) into any
//! [`LineSink`]: an embedded-graphics `DrawTarget` through [`DrawTargetSink`],
//! a display driver that takes lines, or an image in RAM as here.
//!
//! ```
//! use embedded_graphics_core::pixelcolor::Rgb888;
//! use mcu_abuffer::memory::{FragmentMemory, WorkspaceMemory};
//! use mcu_abuffer::scene::OCTAHEDRON;
//! use mcu_abuffer::{Camera, Coord, FrameOptions, ImageSink, Mask4x4, OverflowPolicy};
//! use mcu_abuffer::{Renderer, Scene, SceneObject, Shading, Transform};
//! use static_cell::ConstStaticCell;
//!
//! // 64x48 pixels in 8-row bands: per pixel 1 fragment slot and 2 addresses
//! // into a pool of 256; scenes of 1 object, 6 vertices, 8 triangles.
//! static FRAGMENTS: ConstStaticCell<FragmentMemory<Mask4x4, 64, 8, 1, 2, 256>> =
//!     ConstStaticCell::new(FragmentMemory::new());
//! static WORKSPACE: ConstStaticCell<WorkspaceMemory<48, 1, 6, 8>> =
//!     ConstStaticCell::new(WorkspaceMemory::new());
//!
//! let objects = [SceneObject {
//!     mesh: OCTAHEDRON,
//!     color: Rgb888::new(220, 170, 120),
//!     transform: Transform::default(),
//!     cull_backfaces: true,
//!     shading: Shading::Gouraud,
//! }];
//! let scene = Scene {
//!     width: 64,
//!     height: 48,
//!     background: Rgb888::new(16, 18, 28),
//!     camera: Camera {
//!         eye: [Coord::ZERO, Coord::ONE, Coord::from_num(4)],
//!         target: [Coord::ZERO; 3],
//!         up: [Coord::ZERO, Coord::ONE, Coord::ZERO],
//!         fov_y_deg: Coord::from_num(40),
//!         near: Coord::ONE,
//!         far: Coord::from_num(10),
//!     },
//!     light: None,
//!     objects: &objects,
//! };
//!
//! let buffer = FRAGMENTS.take().buffer(OverflowPolicy::SplitBands);
//! let mut renderer = Renderer::new(WORKSPACE.take().workspace(), buffer);
//! let mut rgb = [0u8; 64 * 48 * 3];
//! let stats = renderer
//!     .render(&scene, &FrameOptions::default(), &mut ImageSink::new(64, &mut rgb))
//!     .expect("the scene fits the workspace");
//! assert_eq!(stats.geometry.triangles_in, 8);
//! // The octahedron's center pixel has its color, the corner the background.
//! let center = (24 * 64 + 32) * 3;
//! assert_ne!(rgb[center..center + 3], [16, 18, 28]);
//! assert_eq!(rgb[..3], [16, 18, 28]);
//! ```
//!
//! The sizes say what the statics cost: `FragmentMemory::<..>::BYTES`,
//! `WorkspaceMemory::<..>::BYTES`; `host-sim fit` checks a configuration
//! against a board's SRAM. The `firmware/blackpill` crate is a complete board
//! firmware (ST7789 display, DMA band streaming).
#![cfg_attr(not(test), no_std)]
#![warn(missing_docs)]
// Matrix and per-channel arithmetic reads best with explicit indices.
#![allow(clippy::needless_range_loop)]

pub mod memory;
pub mod scene;
pub mod sink;
pub mod stats;

// The pipeline's stages: public for host-sim, the system tests and the fuzz
// targets, hidden from the documentation and outside the stable API.
#[doc(hidden)]
pub mod band_buffer;
#[doc(hidden)]
pub mod clip;
#[doc(hidden)]
pub mod color_carry;
#[doc(hidden)]
pub mod coverage;
#[doc(hidden)]
pub mod draw_order;
#[doc(hidden)]
pub mod fixed_point;
#[doc(hidden)]
pub mod fragment;
#[doc(hidden)]
pub mod fragment_buffer;
#[doc(hidden)]
pub mod geometry;
#[doc(hidden)]
pub mod lighting;
#[doc(hidden)]
pub mod merge;
#[doc(hidden)]
pub mod openings;
#[doc(hidden)]
pub mod pool;
#[doc(hidden)]
pub mod raster;
#[doc(hidden)]
pub mod renderer;
#[doc(hidden)]
pub mod setup;
#[doc(hidden)]
pub mod shading;
#[doc(hidden)]
pub mod stack;
#[cfg(test)]
mod test_rng;
#[doc(hidden)]
pub mod visibility;
#[doc(hidden)]
pub mod words;
#[doc(hidden)]
pub mod zbuffer;
#[doc(hidden)]
pub mod zbuffer_hiz;
#[doc(hidden)]
pub mod zbuffer_midpoint;

pub use band_buffer::BandBuffer;
pub use coverage::{CoverageMask, Mask1x1, Mask4x4, Mask8x4, Mask8x8};
pub use fragment_buffer::{
    BufferConfig, BufferShape, BufferStorage, ConstShape, FragmentBuffer, OverflowPolicy,
    ShapeOfConfig,
};
pub use renderer::{render_frame, FrameOptions, FrameWorkspace, RenderError, Renderer};
pub use scene::{Camera, Light, Mesh, Scene, SceneObject, Shading, Transform};
pub use sink::{
    DrawTargetSink, DrawTargetSinkError, ImageSink, LinePixel, LineSink, PackedRgb888,
    Rgb565BigEndian,
};
pub use stats::FrameStats;
pub use zbuffer::ZBuffer;
pub use zbuffer_hiz::HierarchicalZBuffer;
pub use zbuffer_midpoint::{MidpointConfig, MidpointZBuffer};

pub use fixed::types::I2F14;
pub use fixed_point::Coord;
