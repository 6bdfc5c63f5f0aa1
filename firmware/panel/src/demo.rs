//! The turntable demo: which scene and angle each frame shows, and the frame-rate
//! text, in integers (the board has no clock but its cycle counter).

use crate::link::PanelLink;
use crate::stream::{BandStream, StreamError};
use mcu_abuffer::band_buffer::BandBuffer;
use mcu_abuffer::coverage::CoverageMask;
use mcu_abuffer::fixed_point::Coord;
use mcu_abuffer::renderer::{render_frame, FrameOptions, FrameWorkspace, RenderError};
use mcu_abuffer::scene::Scene;
use mcu_abuffer::stats::FrameStats;

/// Decides which scene and turntable angle each frame of the demo shows.
///
/// Every frame turns the scene by a fixed step (so a frame's picture does not depend
/// on how long the previous one took); the demo moves on to the next scene once
/// `cycles_per_scene` clock cycles have passed in the current one, starting it at 0
/// degrees.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DemoSchedule {
    scene_count: usize,
    step_deg: Coord,
    cycles_per_scene: u64,
    scene: usize,
    angle_deg: Coord,
    cycles_in_scene: u64,
}

/// One frame of the demo.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DemoFrame {
    /// Index of the scene.
    pub scene: usize,
    /// Turntable angle, degrees.
    pub angle_deg: Coord,
}

impl DemoSchedule {
    /// A schedule over `scene_count` scenes (at least 1), turning by `step_deg`
    /// per frame and switching every `cycles_per_scene` cycles.
    pub fn new(scene_count: usize, step_deg: Coord, cycles_per_scene: u64) -> Self {
        Self {
            scene_count: scene_count.max(1),
            step_deg,
            cycles_per_scene,
            scene: 0,
            angle_deg: Coord::ZERO,
            cycles_in_scene: 0,
        }
    }

    /// The frame to draw now.
    pub fn current(&self) -> DemoFrame {
        DemoFrame {
            scene: self.scene,
            angle_deg: self.angle_deg,
        }
    }

    /// Accounts for a frame that took `cycles`, and moves to the next frame.
    pub fn advance(&mut self, cycles: u64) {
        self.cycles_in_scene = self.cycles_in_scene.saturating_add(cycles);
        if self.cycles_in_scene >= self.cycles_per_scene {
            self.cycles_in_scene = 0;
            self.scene = (self.scene + 1) % self.scene_count;
            self.angle_deg = Coord::ZERO;
        } else {
            let next = self.angle_deg.wrapping_add(self.step_deg);
            self.angle_deg = if next >= Coord::from_num(360) {
                next - Coord::from_num(360)
            } else {
                next
            };
        }
    }
}

/// Frames per second from cycle counts, in tenths, averaged over a window of frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameRate {
    clock_hz: u32,
    window: u32,
    frames: u32,
    cycles: u64,
    tenths: u32,
}

impl FrameRate {
    /// Averages over `window` frames (at least 1) at `clock_hz`.
    pub fn new(clock_hz: u32, window: u32) -> Self {
        Self {
            clock_hz,
            window: window.max(1),
            frames: 0,
            cycles: 0,
            tenths: 0,
        }
    }

    /// Adds a frame that took `cycles` (including sending it).
    pub fn add_frame(&mut self, cycles: u64) {
        self.frames += 1;
        self.cycles += cycles;
        if self.frames >= self.window {
            self.tenths = tenths_per_second(self.clock_hz, self.frames, self.cycles);
            self.frames = 0;
            self.cycles = 0;
        } else if self.tenths == 0 {
            // Show something from the first frame on.
            self.tenths = tenths_per_second(self.clock_hz, self.frames, self.cycles);
        }
    }

    /// Frames per second times ten, rounded (0 before the first frame).
    pub fn tenths(&self) -> u32 {
        self.tenths
    }
}

/// `frames` in `cycles` at `clock_hz`, in tenths of a frame per second, rounded.
pub fn tenths_per_second(clock_hz: u32, frames: u32, cycles: u64) -> u32 {
    if cycles == 0 {
        return 0;
    }
    let numerator = clock_hz as u128 * frames as u128 * 10;
    ((numerator + cycles as u128 / 2) / cycles as u128).min(u32::MAX as u128) as u32
}

/// Renders one turntable frame of `scene` into `stream` and sends its last band.
///
/// The board's main loop and the host tests call this same function; only the
/// link under the stream differs.
pub fn render_turntable_frame<'buf, M, B, L>(
    scene: &Scene<'_>,
    angle_deg: Coord,
    workspace: &mut FrameWorkspace<'_>,
    buffer: &mut B,
    stream: &mut BandStream<'buf, L>,
) -> Result<FrameStats, RenderError<StreamError<L::Error>>>
where
    M: CoverageMask,
    B: BandBuffer<M>,
    L: PanelLink<'buf>,
{
    let options = FrameOptions {
        turntable_deg: angle_deg,
        ..FrameOptions::default()
    };
    let stats = render_frame(scene, &options, workspace, buffer, stream, |_, _, _| {})?;
    stream.end_frame().map_err(RenderError::Sink)?;
    Ok(stats)
}

/// The board demo's parameters. The board build uses them as its defaults and the
/// host tests of the display path use them too, so both exercise the same
/// configuration.
pub mod defaults {
    /// Built-in scenes shown in turn.
    pub const SCENES: [&str; 3] = ["teapot", "spheres", "starfighter"];
    /// Image width, pixels.
    pub const WIDTH: u16 = 240;
    /// Image height, pixels.
    pub const HEIGHT: u16 = 240;
    use mcu_abuffer::memory::defaults as library;

    /// Rows per band (the render band and each of the two transfer buffers).
    /// The board's RAM also holds the two transfer buffers and the workspace
    /// of the largest scene, so its fragment memory is smaller than the
    /// library's default; of the layouts of that size, 5 rows with
    /// [`POOL_SLOTS`] drew the scenes fastest (teapot 47.0 M instructions a
    /// frame on the Cortex-M4, 53.9 M with 6 rows and 512 slots, 48.8 M with
    /// 4 rows and 1,300; docs/board.md).
    pub const BAND_ROWS: u16 = 5;
    /// Fragment slots per pixel in the main buffer (the library's default).
    pub const MAIN_SLOTS: u8 = library::MAIN_SLOTS;
    /// Pool addresses per pixel (the library's default).
    pub const EXTRA_ADDRESSES: u8 = library::EXTRA_ADDRESSES;
    /// Shared pool slots per band (see [`BAND_ROWS`]).
    pub const POOL_SLOTS: usize = 906;
    /// Entries of the carried-colors table (the library's default).
    pub const CARRIED_COLORS: usize = library::CARRIED_COLORS;
    /// Turntable step per frame, degrees.
    pub const STEP_DEG: i32 = 6;
    /// Seconds each scene is shown.
    pub const SECONDS_PER_SCENE: u32 = 8;
    /// Core clock of the board, Hz.
    pub const CLOCK_HZ: u32 = 100_000_000;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_schedule_turns_then_switches_scenes_by_time() {
        let mut s = DemoSchedule::new(3, Coord::from_num(100), 1_000);
        assert_eq!(
            s.current(),
            DemoFrame {
                scene: 0,
                angle_deg: Coord::ZERO
            }
        );
        s.advance(400);
        assert_eq!(s.current().angle_deg, Coord::from_num(100));
        s.advance(400);
        s.advance(100);
        s.advance(50);
        // 300 + 100 = 400 >= 360 wraps to 40.
        assert_eq!(
            s.current(),
            DemoFrame {
                scene: 0,
                angle_deg: Coord::from_num(40)
            }
        );
        s.advance(50); // 1,000 cycles in scene 0
        assert_eq!(
            s.current(),
            DemoFrame {
                scene: 1,
                angle_deg: Coord::ZERO
            }
        );
        s.advance(5_000);
        s.advance(5_000);
        assert_eq!(s.current().scene, 0, "after the last scene comes the first");
    }

    #[test]
    fn frame_rate_in_tenths_rounds_and_averages() {
        assert_eq!(tenths_per_second(100_000_000, 1, 0), 0);
        assert_eq!(tenths_per_second(100_000_000, 1, 100_000_000), 10);
        // 100 MHz / 72 M cycles = 1.389 fps -> 1.4
        assert_eq!(tenths_per_second(100_000_000, 1, 72_000_000), 14);
        assert_eq!(tenths_per_second(100_000_000, 4, 200_000_000), 20);
        let mut rate = FrameRate::new(100, 2);
        assert_eq!(rate.tenths(), 0);
        rate.add_frame(50); // first frame shown at once: 2 fps
        assert_eq!(rate.tenths(), 20);
        rate.add_frame(150); // window of 2: 2 frames in 200 cycles = 1 fps
        assert_eq!(rate.tenths(), 10);
        rate.add_frame(25);
        assert_eq!(rate.tenths(), 10, "kept until the window is full");
        rate.add_frame(25);
        assert_eq!(rate.tenths(), 40);
    }
}
