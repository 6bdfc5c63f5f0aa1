//! The color ramp of every heat map and plot: black for "nothing", then dark
//! purple, red, orange and pale yellow for growing values (close to matplotlib's
//! "inferno", which stays readable in gray and for common color blindness).

/// Ramp control points: position in `[0, 1]` and color.
const RAMP: [(f64, [f64; 3]); 6] = [
    (0.0, [0.0, 0.0, 4.0]),
    (0.2, [66.0, 10.0, 104.0]),
    (0.4, [147.0, 38.0, 103.0]),
    (0.6, [221.0, 81.0, 58.0]),
    (0.8, [252.0, 165.0, 10.0]),
    (1.0, [252.0, 255.0, 164.0]),
];

/// The ramp's color at `t` in `[0, 1]` (clamped).
pub fn heat_color(t: f64) -> [u8; 3] {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let i = RAMP
        .windows(2)
        .position(|w| t <= w[1].0)
        .unwrap_or(RAMP.len() - 2);
    let ((t0, c0), (t1, c1)) = (RAMP[i], RAMP[i + 1]);
    let f = (t - t0) / (t1 - t0);
    std::array::from_fn(|k| (c0[k] + (c1[k] - c0[k]) * f).round() as u8)
}

/// The color of count `n` on a scale up to `max`: black for 0, then the ramp from
/// a visible dark purple (1) to pale yellow (`max` and above).
pub fn count_color(n: u32, max: u32) -> [u8; 3] {
    if n == 0 {
        return [0, 0, 0];
    }
    let max = max.max(2);
    let t = (n.min(max) - 1) as f64 / (max - 1) as f64;
    heat_color(0.18 + 0.82 * t)
}

/// An RGB888 heat map of per-pixel counts (black for 0, `max` and above saturate).
pub fn count_heat_map(counts: &[u16], max: u32) -> Vec<u8> {
    counts
        .iter()
        .flat_map(|&n| count_color(n as u32, max))
        .collect()
}

/// `[r, g, b]` as `#rrggbb`.
pub fn hex(c: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}
