//! An emulated ST7789 for host tests: it sits behind the embedded-hal 1.0
//! [`SpiDevice`] and [`OutputPin`] traits, as a real module does behind a board's
//! SPI peripheral and pins, and decodes the byte stream into controller memory.
//!
//! Decoded: `SWRESET`, `SLPOUT`, `NORON`, `INVOFF`/`INVON`, `DISPOFF`/`DISPON`,
//! `CASET`, `RASET`, `MADCTL` (row/column exchange and mirroring), `COLMOD`, and
//! `RAMWR` with its pixel data (16-bit color only). The hardware reset pin resets
//! the state. What a real controller would do wrong or ignore is recorded as a
//! protocol error instead: pixel data before `RAMWR`, a pixel split by the end of
//! an SPI transaction, pixel data in a color mode other than RGB565, a window
//! beyond the 240 x 320 memory, reads, a command with too few parameters.

use crate::st7789::*;
use core::convert::Infallible;
use embedded_hal::digital::{ErrorType as PinErrorType, OutputPin};
use embedded_hal::spi::{ErrorKind, ErrorType, Operation, SpiDevice};
use std::cell::RefCell;
use std::rc::Rc;
use std::string::String;
use std::vec::Vec;

/// Columns of the controller's memory.
pub const MEMORY_COLUMNS: u16 = 240;
/// Rows of the controller's memory.
pub const MEMORY_ROWS: u16 = 320;

/// What the emulated controller was told and holds.
#[derive(Clone, Debug)]
pub struct ControllerState {
    /// Controller memory, RGB565, row-major, [`MEMORY_COLUMNS`] x [`MEMORY_ROWS`].
    pub memory: Vec<u16>,
    /// Sleeping (true after reset until `SLPOUT`).
    pub sleeping: bool,
    /// Display on (`DISPON`).
    pub display_on: bool,
    /// Inversion on (`INVON`).
    pub inverted: bool,
    /// Last `MADCTL` parameter.
    pub madctl: u8,
    /// Last `COLMOD` parameter (0x66, 18-bit, after reset).
    pub colmod: u8,
    /// Column window (first, last).
    pub columns: (u16, u16),
    /// Row window (first, last).
    pub rows: (u16, u16),
    /// Every command byte received, in order.
    pub commands: Vec<u8>,
    /// Pixels written by `RAMWR`.
    pub pixels_written: u64,
    /// SPI transactions seen.
    pub transactions: u64,
    /// Protocol errors, in order.
    pub errors: Vec<String>,
    data_line_high: bool,
    command: Option<u8>,
    parameters: Vec<u8>,
    pending_byte: Option<u8>,
    cursor: (u16, u16),
}

impl ControllerState {
    fn after_reset(memory: Vec<u16>, log: (Vec<u8>, Vec<String>, u64, u64)) -> Self {
        let (commands, errors, pixels_written, transactions) = log;
        Self {
            memory,
            sleeping: true,
            display_on: false,
            inverted: false,
            madctl: 0,
            colmod: 0x66,
            columns: (0, MEMORY_COLUMNS - 1),
            rows: (0, MEMORY_ROWS - 1),
            commands,
            pixels_written,
            transactions,
            errors,
            data_line_high: false,
            command: None,
            parameters: Vec::new(),
            pending_byte: None,
            cursor: (0, 0),
        }
    }

    fn reset(&mut self) {
        let memory = std::mem::take(&mut self.memory);
        let log = (
            std::mem::take(&mut self.commands),
            std::mem::take(&mut self.errors),
            self.pixels_written,
            self.transactions,
        );
        *self = Self::after_reset(memory, log);
    }

    fn byte(&mut self, byte: u8) {
        if !self.data_line_high {
            self.begin_command(byte);
            return;
        }
        match self.command {
            None => self
                .errors
                .push(format!("data byte {byte:#04x} before any command")),
            Some(RAMWR) => self.pixel_byte(byte),
            Some(command) => {
                self.parameters.push(byte);
                self.parameter(command);
            }
        }
    }

    fn begin_command(&mut self, command: u8) {
        self.finish_command();
        self.commands.push(command);
        self.command = Some(command);
        self.parameters.clear();
        self.pending_byte = None;
        match command {
            SWRESET => self.reset(),
            SLPOUT => self.sleeping = false,
            NORON => {}
            INVOFF => self.inverted = false,
            INVON => self.inverted = true,
            DISPOFF => self.display_on = false,
            DISPON => self.display_on = true,
            RAMWR => {
                if self.colmod & 0x0F != 0x05 {
                    self.errors.push(format!(
                        "RAMWR with COLMOD {:#04x}: only RGB565 (0x55) is decoded",
                        self.colmod
                    ));
                }
                self.cursor = (self.columns.0, self.rows.0);
            }
            CASET | RASET | MADCTL | COLMOD => {}
            other => self
                .errors
                .push(format!("command {other:#04x} is not emulated")),
        }
    }

    fn finish_command(&mut self) {
        let needed = match self.command {
            Some(CASET | RASET) => 4,
            Some(MADCTL | COLMOD) => 1,
            _ => 0,
        };
        if self.parameters.len() < needed {
            self.errors.push(format!(
                "command {:#04x} ended after {} of {needed} parameter bytes",
                self.command.unwrap_or(0),
                self.parameters.len()
            ));
        }
    }

    fn parameter(&mut self, command: u8) {
        let p = &self.parameters;
        match (command, p.len()) {
            (CASET | RASET, 4) => {
                let first = u16::from_be_bytes([p[0], p[1]]);
                let last = u16::from_be_bytes([p[2], p[3]]);
                let limit = if command == CASET {
                    self.column_limit()
                } else {
                    self.row_limit()
                };
                if first > last || last >= limit {
                    self.errors.push(format!(
                        "{} window {first}..={last} outside 0..{limit}",
                        if command == CASET { "column" } else { "row" }
                    ));
                }
                if command == CASET {
                    self.columns = (first, last);
                } else {
                    self.rows = (first, last);
                }
            }
            (MADCTL, 1) => self.madctl = p[0],
            (COLMOD, 1) => self.colmod = p[0],
            (CASET | RASET, n) if n > 4 => self.errors.push(format!(
                "command {command:#04x} given more than 4 parameter bytes"
            )),
            _ => {}
        }
    }

    /// Logical columns in the current orientation (rows and columns exchange with MV).
    fn column_limit(&self) -> u16 {
        if self.madctl & 0x20 != 0 {
            MEMORY_ROWS
        } else {
            MEMORY_COLUMNS
        }
    }

    fn row_limit(&self) -> u16 {
        if self.madctl & 0x20 != 0 {
            MEMORY_COLUMNS
        } else {
            MEMORY_ROWS
        }
    }

    fn pixel_byte(&mut self, byte: u8) {
        let Some(high) = self.pending_byte.take() else {
            self.pending_byte = Some(byte);
            return;
        };
        let color = u16::from_be_bytes([high, byte]);
        let (column, row) = self.cursor;
        // MV exchanges the counters; MX and MY mirror the memory address.
        let (mut x, mut y) = if self.madctl & 0x20 != 0 {
            (row, column)
        } else {
            (column, row)
        };
        if self.madctl & 0x40 != 0 {
            x = (MEMORY_COLUMNS - 1).wrapping_sub(x);
        }
        if self.madctl & 0x80 != 0 {
            y = (MEMORY_ROWS - 1).wrapping_sub(y);
        }
        if x < MEMORY_COLUMNS && y < MEMORY_ROWS {
            self.memory[y as usize * MEMORY_COLUMNS as usize + x as usize] = color;
        } else {
            self.errors
                .push(format!("pixel written outside memory at ({x}, {y})"));
        }
        self.pixels_written += 1;
        // Row by row within the window; past its end the write wraps to the start.
        let (mut column, mut row) = (column + 1, row);
        if column > self.columns.1 {
            column = self.columns.0;
            row += 1;
            if row > self.rows.1 {
                row = self.rows.0;
            }
        }
        self.cursor = (column, row);
    }

    fn end_transaction(&mut self) {
        self.transactions += 1;
        if let Some(byte) = self.pending_byte.take() {
            self.errors.push(format!(
                "transaction ended in the middle of a pixel (byte {byte:#04x} dropped)"
            ));
        }
    }
}

/// The emulated controller. Clone it to keep a handle for reading the state while
/// the SPI device and pins are owned by the code under test.
#[derive(Clone)]
pub struct St7789Emulator {
    state: Rc<RefCell<ControllerState>>,
}

impl Default for St7789Emulator {
    fn default() -> Self {
        Self::new()
    }
}

impl St7789Emulator {
    /// A controller just powered on: memory black, asleep, display off.
    pub fn new() -> Self {
        let memory = vec![0; MEMORY_COLUMNS as usize * MEMORY_ROWS as usize];
        Self {
            state: Rc::new(RefCell::new(ControllerState::after_reset(
                memory,
                (Vec::new(), Vec::new(), 0, 0),
            ))),
        }
    }

    /// The SPI device of the module (chip select handled per transaction).
    pub fn spi(&self) -> EmulatedSpi {
        EmulatedSpi {
            state: self.state.clone(),
        }
    }

    /// The data/command pin (low: command, high: data).
    pub fn data_command_pin(&self) -> EmulatedDataCommandPin {
        EmulatedDataCommandPin {
            state: self.state.clone(),
        }
    }

    /// The hardware reset pin (low resets).
    pub fn reset_pin(&self) -> EmulatedResetPin {
        EmulatedResetPin {
            state: self.state.clone(),
        }
    }

    /// A copy of the controller state.
    pub fn state(&self) -> ControllerState {
        self.state.borrow().clone()
    }

    /// The `width` x `height` pixels of memory starting at column `x0`, row `y0`,
    /// RGB565, row-major.
    pub fn region(&self, x0: u16, y0: u16, width: u16, height: u16) -> Vec<u16> {
        let state = self.state.borrow();
        let mut out = Vec::with_capacity(width as usize * height as usize);
        for y in y0..y0 + height {
            let start = y as usize * MEMORY_COLUMNS as usize + x0 as usize;
            out.extend_from_slice(&state.memory[start..start + width as usize]);
        }
        out
    }

    /// Fills the memory with one color (to see which pixels a test writes).
    pub fn fill_memory(&self, color: u16) {
        self.state.borrow_mut().memory.fill(color);
    }

    /// Clears the command log, counters and errors.
    pub fn clear_log(&self) {
        let mut state = self.state.borrow_mut();
        state.commands.clear();
        state.errors.clear();
        state.pixels_written = 0;
        state.transactions = 0;
    }
}

/// The module's SPI device; writes only (the module's data line is write-only).
pub struct EmulatedSpi {
    state: Rc<RefCell<ControllerState>>,
}

/// Error of [`EmulatedSpi`]: the emulated module cannot be read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReadNotSupported;

impl embedded_hal::spi::Error for ReadNotSupported {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Other
    }
}

impl ErrorType for EmulatedSpi {
    type Error = ReadNotSupported;
}

impl SpiDevice for EmulatedSpi {
    fn transaction(
        &mut self,
        operations: &mut [Operation<'_, u8>],
    ) -> Result<(), ReadNotSupported> {
        let mut state = self.state.borrow_mut();
        let mut result = Ok(());
        for operation in operations.iter_mut() {
            match operation {
                Operation::Write(bytes) => bytes.iter().for_each(|&b| state.byte(b)),
                Operation::DelayNs(_) => {}
                Operation::Read(_) | Operation::Transfer(_, _) | Operation::TransferInPlace(_) => {
                    state
                        .errors
                        .push("SPI read from a write-only module".into());
                    result = Err(ReadNotSupported);
                }
            }
        }
        state.end_transaction();
        result
    }
}

/// The data/command pin.
pub struct EmulatedDataCommandPin {
    state: Rc<RefCell<ControllerState>>,
}

impl PinErrorType for EmulatedDataCommandPin {
    type Error = Infallible;
}

impl OutputPin for EmulatedDataCommandPin {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.state.borrow_mut().data_line_high = false;
        Ok(())
    }

    fn set_high(&mut self) -> Result<(), Infallible> {
        self.state.borrow_mut().data_line_high = true;
        Ok(())
    }
}

/// The hardware reset pin.
pub struct EmulatedResetPin {
    state: Rc<RefCell<ControllerState>>,
}

impl PinErrorType for EmulatedResetPin {
    type Error = Infallible;
}

impl OutputPin for EmulatedResetPin {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.state.borrow_mut().reset();
        Ok(())
    }

    fn set_high(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn send(emulator: &St7789Emulator, command: u8, data: &[u8]) {
        let (mut spi, mut dc) = (emulator.spi(), emulator.data_command_pin());
        dc.set_low().unwrap();
        spi.write(&[command]).unwrap();
        if !data.is_empty() {
            dc.set_high().unwrap();
            spi.write(data).unwrap();
        }
    }

    fn ready() -> St7789Emulator {
        let emulator = St7789Emulator::new();
        send(&emulator, SLPOUT, &[]);
        send(&emulator, COLMOD, &[COLMOD_RGB565]);
        emulator
    }

    #[test]
    fn a_window_fills_row_by_row_and_wraps() {
        let emulator = ready();
        send(&emulator, CASET, &address_range(10, 11));
        send(&emulator, RASET, &address_range(5, 6));
        // Five pixels into a 2 x 2 window: the fifth wraps to the first.
        let pixels: Vec<u8> = [1u16, 2, 3, 4, 5]
            .iter()
            .flat_map(|p| p.to_be_bytes())
            .collect();
        send(&emulator, RAMWR, &pixels);
        assert_eq!(emulator.region(10, 5, 2, 2), [5, 2, 3, 4]);
        let state = emulator.state();
        assert!(state.errors.is_empty(), "{:?}", state.errors);
        assert_eq!(state.pixels_written, 5);
        assert_eq!(state.commands, [SLPOUT, COLMOD, CASET, RASET, RAMWR]);
    }

    #[test]
    fn madctl_mirrors_and_exchanges() {
        let emulator = ready();
        // MX: column 0 lands in the last memory column.
        send(&emulator, MADCTL, &[0x40]);
        send(&emulator, CASET, &address_range(0, 0));
        send(&emulator, RASET, &address_range(0, 0));
        send(&emulator, RAMWR, &[0x12, 0x34]);
        assert_eq!(emulator.region(MEMORY_COLUMNS - 1, 0, 1, 1), [0x1234]);
        // MV: logical (column 7, row 3) is memory (3, 7); columns may reach 319.
        send(&emulator, MADCTL, &[0x20]);
        send(&emulator, CASET, &address_range(7, 319));
        send(&emulator, RASET, &address_range(3, 3));
        send(&emulator, RAMWR, &[0xAB, 0xCD]);
        assert_eq!(emulator.region(3, 7, 1, 1), [0xABCD]);
        assert!(emulator.state().errors.is_empty());
    }

    #[test]
    fn protocol_mistakes_are_recorded() {
        let emulator = St7789Emulator::new();
        let (mut spi, mut dc) = (emulator.spi(), emulator.data_command_pin());
        dc.set_high().unwrap();
        spi.write(&[0x00]).unwrap(); // data before any command
        send(&emulator, RAMWR, &[0x00, 0x00]); // still in the 18-bit mode of reset
        send(&emulator, COLMOD, &[COLMOD_RGB565]);
        send(&emulator, RAMWR, &[0x00]); // half a pixel, then the transaction ends
        send(&emulator, CASET, &address_range(0, 240)); // one column too many
        send(&emulator, RASET, &[0, 1]); // two of four parameters
        send(&emulator, NORON, &[]);
        let mut buffer = [0u8; 1];
        assert_eq!(spi.read(&mut buffer), Err(ReadNotSupported));
        let errors = emulator.state().errors;
        assert_eq!(errors.len(), 6, "{errors:?}");
        // A hardware reset returns to sleep, display off, 18-bit color.
        send(&emulator, SLPOUT, &[]);
        send(&emulator, DISPON, &[]);
        emulator.reset_pin().set_low().unwrap();
        let state = emulator.state();
        assert!(state.sleeping && !state.display_on && state.colmod == 0x66);
    }
}
