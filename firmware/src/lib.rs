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
//! Pipeline, by module: [`geometry`] (transform, outcodes, projection), [`clip`],
//! [`lighting`], [`setup`] (edge functions, depth and color planes), [`shading`]
//! (quadratic and Phong shading, color walkers), [`raster`]
//! ([`coverage`] masks), [`fragment_buffer`] ([`visibility`], [`merge`], [`pool`])
//! or [`zbuffer`] ([`zbuffer_hiz`], [`zbuffer_midpoint`]), resolve, [`sink`].
//! [`renderer::render_frame`] drives it.
#![cfg_attr(not(test), no_std)]
#![warn(missing_docs)]
// Matrix and per-channel arithmetic reads best with explicit indices.
#![allow(clippy::needless_range_loop)]

pub mod band_buffer;
pub mod clip;
pub mod coverage;
pub mod fixed_point;
pub mod fragment;
pub mod fragment_buffer;
pub mod geometry;
pub mod lighting;
pub mod merge;
pub mod pool;
pub mod raster;
pub mod renderer;
pub mod scene;
pub mod setup;
pub mod shading;
pub mod sink;
pub mod stack;
pub mod stats;
pub mod visibility;
pub mod zbuffer;
pub mod zbuffer_hiz;
pub mod zbuffer_midpoint;

pub use band_buffer::BandBuffer;
pub use coverage::{CoverageMask, Mask1x1, Mask4x4, Mask8x4, Mask8x8};
pub use fragment::{Fragment, PackedFragment};
pub use fragment_buffer::{BufferConfig, BufferStorage, FragmentBuffer, OverflowPolicy};
pub use renderer::{render_frame, FrameOptions, FrameWorkspace, RenderError};
pub use scene::{Camera, Light, Mesh, Scene, SceneObject, Shading, Transform};
pub use sink::{DrawTargetSink, ImageSink, LineSink};
pub use stats::FrameStats;
pub use zbuffer::ZBuffer;
pub use zbuffer_hiz::HierarchicalZBuffer;
pub use zbuffer_midpoint::{MidpointConfig, MidpointZBuffer};
