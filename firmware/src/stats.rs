//! Per-frame statistics.

/// Counters kept by a band buffer (A-buffer or z-buffer) over a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BufferStats {
    /// Fragments the rasterizer produced (non-empty coverage).
    pub fragments_generated: u64,
    /// Fragments that survived visibility and were stored (possibly by a merge).
    pub fragments_stored: u64,
    /// New fragments hidden at every sample they covered, so never stored.
    pub fragments_hidden_on_arrival: u64,
    /// Stored fragments removed because later fragments hid all their samples.
    pub fragments_removed_hidden: u64,
    /// Merges of two fragments into one (overflow under a merging policy).
    pub merges: u64,
    /// Fragments dropped on overflow (the discard policy).
    pub fragments_discarded: u64,
    /// Most pool slots in use at once.
    pub pool_peak: u32,
    /// Most fragments held by one pixel at once.
    pub max_fragments_in_pixel: u32,
    /// Depth comparisons made (z-buffer modes: one per tested pixel).
    pub depth_tests: u64,
}

/// Counters of the geometry stages over a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GeometryStats {
    /// Triangles in the scene.
    pub triangles_in: u32,
    /// Triangles skipped as back-facing.
    pub triangles_backfacing: u32,
    /// Triangles skipped with zero area in window coordinates.
    pub triangles_degenerate: u32,
    /// Triangles entirely outside the view volume or the screen.
    pub triangles_outside: u32,
    /// Triangles that crossed a clipping plane and were clipped.
    pub triangles_clipped: u32,
    /// Triangle setups performed (a triangle spanning several bands is set up once per band).
    pub triangle_setups: u32,
}

/// Statistics of one rendered frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FrameStats {
    /// Geometry counters.
    pub geometry: GeometryStats,
    /// Fragment buffer counters.
    pub buffer: BufferStats,
    /// Bands rendered.
    pub bands: u32,
}
