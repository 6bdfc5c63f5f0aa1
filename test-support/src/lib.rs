//! What the host simulator, the system tests and the fuzz targets share to run
//! the `mcu_abuffer` renderer on a host, kept once:
//!
//! - [`OwnedScene`] and [`OwnedObject`]: a scene that owns its meshes and lends
//!   them to the renderer's borrowed [`Scene`](mcu_abuffer::scene::Scene);
//! - [`OwnedWorkspace`]: the vectors behind a
//!   [`FrameWorkspace`](mcu_abuffer::renderer::FrameWorkspace);
//! - [`FragmentStorage`]: the vectors behind a
//!   [`FragmentBuffer`](mcu_abuffer::fragment_buffer::FragmentBuffer);
//! - [`render_rgb`]: one frame into an RGB888 image;
//! - [`PerSampleZBuffer`]: the oracle of SPEC section 3, a z-buffer per sample
//!   that an unlimited A-buffer must equal;
//! - [`Checked`]: a band buffer wrapper that asserts the A-buffer's invariants
//!   after every insertion and at the end of every band;
//! - [`ScratchDir`]: a test's own temporary folder, removed when dropped unless
//!   the test is failing.
#![warn(missing_docs)]

mod checked;
mod oracle;
mod scene;
mod scratch;
mod workspace;

pub use checked::{Checked, Inspect};
pub use oracle::PerSampleZBuffer;
pub use scene::{OwnedObject, OwnedScene};
pub use scratch::ScratchDir;
pub use workspace::{first_difference, render_rgb, FragmentStorage, OwnedWorkspace, Rendered};
