//! Fragment memory of a configuration, from the library's real packed sizes and
//! the formulas of SPEC section 5:
//!
//! ```text
//! M_shared = W R (N_main M_frag + N_extra M_addr) + N_pool M_frag
//! M_fixed  = W R N_fixed M_frag
//! ```
//!
//! `W R` is the band the buffer holds (the renderer works in bands), `M_frag` the
//! size of [`PackedFragment`] for the mask grid and `M_addr` the size of a pool
//! address on a device: 2 bytes while the pool has at most 65,535 slots, else 4.
//! The per-pixel fragment counts (one byte per pixel of the band) are listed
//! apart, as the seed's formulas leave them out.

use crate::render::Grid;
use mcu_abuffer::coverage::{Mask4x4, Mask8x4, Mask8x8};
use mcu_abuffer::fragment::PackedFragment;
use mcu_abuffer::fragment_buffer::{BufferConfig, OverflowPolicy};

/// Bytes of one stored fragment for a mask grid (`M_frag`).
pub fn fragment_bytes(grid: Grid) -> usize {
    match grid {
        Grid::G4x4 => PackedFragment::<Mask4x4>::SIZE,
        Grid::G8x4 => PackedFragment::<Mask8x4>::SIZE,
        Grid::G8x8 => PackedFragment::<Mask8x8>::SIZE,
    }
}

/// Bytes of a pool address on a device (`M_addr`): `u16` when it can index the
/// pool, else `u32`.
pub fn address_bytes(pool_slots: usize) -> usize {
    if pool_slots <= u16::MAX as usize {
        2
    } else {
        4
    }
}

/// The fragment memory of one band buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct MemoryReport {
    /// Pixels of the band, `W R`.
    pub band_pixels: usize,
    /// `M_frag`.
    pub fragment_bytes: usize,
    /// `M_addr`.
    pub address_bytes: usize,
    /// `N_main`.
    pub main_slots: u8,
    /// `N_extra`.
    pub extra_addresses: u8,
    /// `N_pool`.
    pub pool_slots: usize,
    /// The main buffer: `W R (N_main M_frag + N_extra M_addr)`.
    pub main_buffer_bytes: usize,
    /// The shared pool: `N_pool M_frag`.
    pub pool_bytes: usize,
    /// `M_shared`, the sum of the two (for fixed slots: `M_fixed`).
    pub total_bytes: usize,
    /// `M_fixed` of the same per-pixel capacity: `W R (N_main + N_extra) M_frag`.
    pub fixed_equivalent_bytes: usize,
    /// Per-pixel fragment counts, one byte per pixel (not in the seed's formulas).
    pub count_bytes: usize,
}

impl MemoryReport {
    /// Total bytes per pixel of the band.
    pub fn bytes_per_pixel(&self) -> f64 {
        self.total_bytes as f64 / self.band_pixels.max(1) as f64
    }

    /// `M_fixed / M_shared` for the same per-pixel capacity.
    pub fn fixed_to_shared_ratio(&self) -> f64 {
        self.fixed_equivalent_bytes as f64 / self.total_bytes.max(1) as f64
    }
}

/// The memory of a band `width x band_height` with `main` slots and `extra` pool
/// addresses per pixel and `pool` shared slots, for mask grid `grid`.
pub fn band_memory(
    width: u16,
    band_height: u16,
    grid: Grid,
    main: u8,
    extra: u8,
    pool: usize,
) -> MemoryReport {
    let config = BufferConfig {
        width,
        band_height,
        main_slots: main,
        extra_addresses: extra,
        policy: OverflowPolicy::MergeFarthest,
    };
    let m_frag = fragment_bytes(grid);
    let m_addr = address_bytes(pool);
    let total = config.shared_bytes(m_frag, m_addr, pool);
    let pool_bytes = pool * m_frag;
    MemoryReport {
        band_pixels: config.pixels(),
        fragment_bytes: m_frag,
        address_bytes: m_addr,
        main_slots: main,
        extra_addresses: extra,
        pool_slots: pool,
        main_buffer_bytes: total - pool_bytes,
        pool_bytes,
        total_bytes: total,
        fixed_equivalent_bytes: config.pixels() * config.pixel_capacity() * m_frag,
        count_bytes: config.pixels(),
    }
}
