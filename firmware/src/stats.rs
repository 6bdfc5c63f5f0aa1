//! Per-frame statistics.

/// Counters kept by a band buffer (A-buffer or z-buffer) over a frame.
///
/// 32-bit: one addition each on the per-pixel paths, and a frame would need
/// more than 4 x 10^9 fragments or depth tests to reach their limit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BufferStats {
    /// Fragments the rasterizer produced (non-empty coverage).
    pub fragments_generated: u32,
    /// Fragments that survived visibility and were stored (possibly by a merge).
    pub fragments_stored: u32,
    /// New fragments hidden at every sample they covered, so never stored.
    pub fragments_hidden_on_arrival: u32,
    /// Stored fragments removed because later fragments hid all their samples.
    pub fragments_removed_hidden: u32,
    /// Merges of two fragments into one (overflow under a merging policy).
    pub merges: u32,
    /// Fragments dropped on overflow (the discard policy).
    pub fragments_discarded: u32,
    /// Most pool slots in use at once.
    pub pool_peak: u32,
    /// Most fragments held by one pixel at once.
    pub max_fragments_in_pixel: u32,
    /// Depth comparisons made (z-buffer modes: one per tested pixel).
    pub depth_tests: u32,
    /// Depth comparisons made to decide about a whole triangle or a piece of one
    /// before rasterizing it: test points of the midpoint subdivision, tile tests
    /// of the hierarchical z-buffer, pixels asked whether the band already
    /// hides them (`raster::hidden_in_band`: the plain z-buffer's of a
    /// triangle's box, the A-buffer's of its row spans). Not included in
    /// `depth_tests`.
    pub culling_depth_tests: u32,
    /// Depth-buffer reads that keep the hierarchical z-buffer's tile depths
    /// exact (a tile's farthest depth recomputed after its last farthest pixel
    /// was overwritten). Not comparisons against a new fragment.
    pub tile_refresh_reads: u32,
    /// Triangles skipped without writing a pixel because a whole-triangle test
    /// judged every part of them hidden (counted once per band they were drawn in).
    pub triangles_culled: u32,
    /// Pieces judged hidden and skipped: sub-triangles of the midpoint
    /// subdivision, or tiles of the hierarchical z-buffer.
    pub pieces_culled: u32,
    /// Pixels written without a depth test (midpoint subdivision's "visible"
    /// verdict); these are included in `fragments_stored`.
    pub untested_writes: u32,
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
    /// Color setups performed (lighting and fit, or planes): once per band a
    /// triangle leaves a visible fragment in, unless carried.
    pub color_setups: u32,
    /// Color setups saved: planes taken from an earlier band's
    /// ([`crate::color_carry`]).
    pub colors_carried: u32,
}

/// Statistics of one rendered frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FrameStats {
    /// Geometry counters.
    pub geometry: GeometryStats,
    /// Fragment buffer counters.
    pub buffer: BufferStats,
    /// Bands rendered (resolved and sent), halves of split bands included.
    pub bands: u32,
    /// Bands drawn and then split because the shared pool ran out (their
    /// fragments are counted in `buffer` too: the work was done).
    pub band_splits: u32,
}
