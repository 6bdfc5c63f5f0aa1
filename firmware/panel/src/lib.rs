//! The display half of the board firmware, independent of any chip.
//!
//! The renderer ([`mcu_abuffer`]) hands finished lines to a [`LineSink`]. On a
//! board the sink is a [`BandStream`]: it packs each line into a band buffer in the
//! display's RGB565 byte order, draws the on-screen overlay into the band once it
//! is complete, then gives the band to a [`PanelLink`], which sends the window
//! commands and starts the pixel transfer. With two band buffers the transfer of one
//! band (by DMA on a board) overlaps the rendering of the next.
//!
//! | module | what it holds |
//! |---|---|
//! | [`st7789`] | the controller's commands and window encoding |
//! | [`link`] | [`PanelLink`]: how bytes reach the panel; [`SpiPanelLink`] over any embedded-hal 1.0 `SpiDevice` and data/command `OutputPin` |
//! | [`stream`] | [`BandStream`]: the double-buffered band sink |
//! | [`overlay`] | text drawn with embedded-graphics into a band before it is sent |
//! | [`demo`] | the turntable demo: which scene and angle each frame shows, the frame-rate text |
//! | `emulator` (feature `emulator`, needs `std`) | an emulated ST7789 behind `SpiDevice` and `OutputPin`, decoding the byte stream into an image |
//!
//! [`LineSink`]: mcu_abuffer::LineSink
#![cfg_attr(not(any(test, feature = "emulator")), no_std)]
#![warn(missing_docs)]

pub mod demo;
#[cfg(feature = "emulator")]
pub mod emulator;
pub mod link;
pub mod overlay;
pub mod st7789;
pub mod stream;

pub use demo::{DemoSchedule, FrameRate};
pub use link::{PanelLink, SpiPanelLink};
pub use overlay::{BandCanvas, TextOverlay};
pub use stream::{BandStream, StreamError};
