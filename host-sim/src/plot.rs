//! Plots as standalone SVG: line charts (linear or log axes) and bar panels.
//! Written by hand so the plots need no plotting library and diff well in git.

use crate::heat::hex;
use std::fmt::Write as _;

/// Line colors that stay distinct for color-blind readers (Okabe and Ito).
pub const PALETTE: [[u8; 3]; 8] = [
    [0, 114, 178],
    [213, 94, 0],
    [0, 158, 115],
    [204, 121, 167],
    [230, 159, 0],
    [86, 180, 233],
    [0, 0, 0],
    [240, 228, 66],
];

/// How an axis maps values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    /// Evenly spaced values.
    Linear,
    /// Evenly spaced decades; values at or below zero are drawn on the axis.
    Log10,
}

/// One point of a series, with an optional label drawn next to it.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// Horizontal value.
    pub x: f64,
    /// Vertical value.
    pub y: f64,
    /// Text next to the marker.
    pub label: Option<String>,
}

/// A polyline with markers.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// Line and marker color.
    pub color: [u8; 3],
    /// Dashed line.
    pub dashed: bool,
    /// Points in drawing order.
    pub points: Vec<Point>,
}

/// A chart of several series over shared axes.
#[derive(Clone, Debug, PartialEq)]
pub struct LineChart {
    /// Title above the chart.
    pub title: String,
    /// Horizontal axis label.
    pub x_label: String,
    /// Vertical axis label.
    pub y_label: String,
    /// Horizontal scale.
    pub x_scale: Scale,
    /// Vertical scale.
    pub y_scale: Scale,
    /// The series.
    pub series: Vec<Series>,
    /// A line of small print under the chart.
    pub note: Option<String>,
}

const WIDTH: f64 = 820.0;
const HEIGHT: f64 = 500.0;
const LEFT: f64 = 86.0;
const RIGHT: f64 = 230.0;
const TOP: f64 = 46.0;
const BOTTOM: f64 = 74.0;

/// Escapes text for SVG.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// A compact number: `1e-4`, `2.5e-3`, `0.5`, `120`, `1.2k`.
pub fn short_number(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        let e = a.log10().floor() as i32;
        let m = v / 10f64.powi(e);
        if (m.round() - m).abs() < 1e-9 {
            format!("{}e{e}", m.round())
        } else {
            format!("{m:.1}e{e}")
        }
    } else if a >= 1000.0 {
        format!("{}k", trim(v / 1000.0))
    } else {
        trim(v)
    }
}

fn trim(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

/// Nice tick positions covering `[lo, hi]` on a linear axis.
pub fn linear_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let span = (hi - lo).max(1e-12);
    let raw = span / 6.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| span / s <= 7.0)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|i| i as f64 * step).collect()
}

/// An axis: value range and scale, mapped onto `[a, b]` pixels.
#[derive(Clone, Copy)]
struct Axis {
    lo: f64,
    hi: f64,
    scale: Scale,
    a: f64,
    b: f64,
}

impl Axis {
    fn fit(values: impl Iterator<Item = f64>, scale: Scale, a: f64, b: f64) -> Self {
        let vals: Vec<f64> = values
            .filter(|v| v.is_finite() && (scale == Scale::Linear || *v > 0.0))
            .collect();
        let (mut lo, mut hi) = vals
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                (l.min(v), h.max(v))
            });
        if !lo.is_finite() {
            (lo, hi) = if scale == Scale::Log10 {
                (1e-6, 1.0)
            } else {
                (0.0, 1.0)
            };
        }
        match scale {
            Scale::Linear => {
                let pad = ((hi - lo) * 0.06).max(1e-9);
                lo = if lo >= 0.0 && lo - pad < 0.0 {
                    0.0
                } else {
                    lo - pad
                };
                hi += pad;
            }
            Scale::Log10 => {
                lo = 10f64.powf(lo.log10().floor());
                hi = 10f64.powf(hi.log10().ceil());
                if hi <= lo {
                    hi = lo * 10.0;
                }
            }
        }
        Self {
            lo,
            hi,
            scale,
            a,
            b,
        }
    }

    /// Pixel position of `v`; values a log axis cannot show go to its low end.
    fn map(&self, v: f64) -> f64 {
        let t = match self.scale {
            Scale::Linear => (v - self.lo) / (self.hi - self.lo),
            Scale::Log10 => {
                if v <= 0.0 {
                    0.0
                } else {
                    (v.log10() - self.lo.log10()) / (self.hi.log10() - self.lo.log10())
                }
            }
        };
        self.a + (self.b - self.a) * t.clamp(-0.02, 1.02)
    }

    fn ticks(&self) -> Vec<f64> {
        match self.scale {
            Scale::Linear => linear_ticks(self.lo, self.hi),
            Scale::Log10 => {
                let (l, h) = (
                    self.lo.log10().round() as i32,
                    self.hi.log10().round() as i32,
                );
                (l..=h).map(|e| 10f64.powi(e)).collect()
            }
        }
    }
}

/// The horizontal grid lines of the value axis `ya` from `x0` to `x1`, each
/// labelled at its left.
fn value_grid(out: &mut String, ya: &Axis, x0: f64, x1: f64) {
    for t in ya.ticks() {
        let y = ya.map(t);
        let _ = writeln!(
            out,
            r##"<line x1="{x0}" y1="{y:.1}" x2="{x1}" y2="{y:.1}" stroke="#e4e4e4"/><text x="{}" y="{:.1}" text-anchor="end">{}</text>"##,
            x0 - 6.0,
            y + 4.0,
            short_number(t)
        );
    }
}

fn svg_open(out: &mut String, width: f64, height: f64, title: &str) {
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="DejaVu Sans, Helvetica, Arial, sans-serif" font-size="13">"#
    );
    let _ = writeln!(out, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        out,
        r#"<text x="{}" y="26" text-anchor="middle" font-size="16" font-weight="bold">{}</text>"#,
        width / 2.0,
        esc(title)
    );
}

impl LineChart {
    /// The chart as an SVG document.
    pub fn to_svg(&self) -> String {
        let (x0, x1) = (LEFT, WIDTH - RIGHT);
        let (y0, y1) = (HEIGHT - BOTTOM, TOP);
        let all = || self.series.iter().flat_map(|s| s.points.iter());
        let xa = Axis::fit(all().map(|p| p.x), self.x_scale, x0, x1);
        let ya = Axis::fit(all().map(|p| p.y), self.y_scale, y0, y1);
        let mut out = String::new();
        svg_open(&mut out, WIDTH, HEIGHT, &self.title);
        // Grid and ticks.
        for t in xa.ticks() {
            let x = xa.map(t);
            let _ = writeln!(
                out,
                r##"<line x1="{x:.1}" y1="{y1}" x2="{x:.1}" y2="{y0}" stroke="#e4e4e4"/><text x="{x:.1}" y="{}" text-anchor="middle">{}</text>"##,
                y0 + 18.0,
                short_number(t)
            );
        }
        value_grid(&mut out, &ya, x0, x1);
        let _ = writeln!(
            out,
            r#"<rect x="{x0}" y="{y1}" width="{}" height="{}" fill="none" stroke="black"/>"#,
            x1 - x0,
            y0 - y1
        );
        let _ = writeln!(
            out,
            r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
            (x0 + x1) / 2.0,
            y0 + 40.0,
            esc(&self.x_label)
        );
        let _ = writeln!(
            out,
            r#"<text transform="translate(22 {}) rotate(-90)" text-anchor="middle">{}</text>"#,
            (y0 + y1) / 2.0,
            esc(&self.y_label)
        );
        // Series.
        for s in &self.series {
            let color = hex(s.color);
            let pts: Vec<String> = s
                .points
                .iter()
                .map(|p| format!("{:.1},{:.1}", xa.map(p.x), ya.map(p.y)))
                .collect();
            let dash = if s.dashed {
                r#" stroke-dasharray="6 4""#
            } else {
                ""
            };
            let _ = writeln!(
                out,
                r#"<polyline points="{}" fill="none" stroke="{color}" stroke-width="2"{dash}/>"#,
                pts.join(" ")
            );
            for p in &s.points {
                let (x, y) = (xa.map(p.x), ya.map(p.y));
                let shown = self.y_scale == Scale::Linear || p.y > 0.0;
                let fill = if shown { color.as_str() } else { "white" };
                let _ = writeln!(
                    out,
                    r#"<circle cx="{x:.1}" cy="{y:.1}" r="3.6" fill="{fill}" stroke="{color}" stroke-width="1.5"/>"#
                );
                if let Some(label) = &p.label {
                    let _ = writeln!(
                        out,
                        r#"<text x="{:.1}" y="{:.1}" font-size="10" fill="{color}">{}</text>"#,
                        x + 5.0,
                        y - 5.0,
                        esc(label)
                    );
                }
            }
        }
        // Legend.
        for (i, s) in self.series.iter().enumerate() {
            let y = TOP + 14.0 + 22.0 * i as f64;
            let x = WIDTH - RIGHT + 18.0;
            let dash = if s.dashed {
                r#" stroke-dasharray="6 4""#
            } else {
                ""
            };
            let _ = writeln!(
                out,
                r#"<line x1="{x}" y1="{y}" x2="{}" y2="{y}" stroke="{}" stroke-width="2"{dash}/><circle cx="{}" cy="{y}" r="3.6" fill="{}"/><text x="{}" y="{}">{}</text>"#,
                x + 28.0,
                hex(s.color),
                x + 14.0,
                hex(s.color),
                x + 36.0,
                y + 4.0,
                esc(&s.name)
            );
        }
        if let Some(note) = &self.note {
            let _ = writeln!(
                out,
                r##"<text x="{x0}" y="{}" font-size="11" fill="#555">{}</text>"##,
                HEIGHT - 10.0,
                esc(note)
            );
        }
        out.push_str("</svg>\n");
        out
    }
}

/// One bar chart: a value and a color per category.
#[derive(Clone, Debug, PartialEq)]
pub struct BarPanel {
    /// Title of the panel.
    pub title: String,
    /// Vertical axis label.
    pub y_label: String,
    /// Category names under the bars.
    pub categories: Vec<String>,
    /// Bar heights.
    pub values: Vec<f64>,
    /// Bar colors.
    pub colors: Vec<[u8; 3]>,
}

/// Bar panels stacked vertically under one title, sharing the horizontal label.
pub fn bar_panels_svg(
    title: &str,
    x_label: &str,
    panels: &[BarPanel],
    note: Option<&str>,
) -> String {
    let panel_height = 230.0;
    let height = TOP + panel_height * panels.len() as f64 + 70.0;
    let width = 760.0;
    let (x0, x1) = (LEFT, width - 30.0);
    let mut out = String::new();
    svg_open(&mut out, width, height, title);
    for (k, panel) in panels.iter().enumerate() {
        let top = TOP + 26.0 + panel_height * k as f64;
        let bottom = top + panel_height - 60.0;
        let ya = Axis::fit(
            panel.values.iter().copied().chain([0.0]),
            Scale::Linear,
            bottom,
            top,
        );
        let _ = writeln!(
            out,
            r#"<text x="{x0}" y="{}" font-weight="bold">{}</text>"#,
            top - 8.0,
            esc(&panel.title)
        );
        value_grid(&mut out, &ya, x0, x1);
        let n = panel.values.len().max(1) as f64;
        let slot = (x1 - x0) / n;
        for (i, &v) in panel.values.iter().enumerate() {
            let x = x0 + slot * i as f64 + slot * 0.12;
            let y = ya.map(v.max(0.0));
            let color = panel.colors.get(i).copied().unwrap_or([80, 80, 80]);
            let _ = writeln!(
                out,
                r##"<rect x="{x:.1}" y="{y:.1}" width="{:.1}" height="{:.1}" fill="{}" stroke="#333" stroke-width="0.6"><title>{}: {}</title></rect>"##,
                slot * 0.76,
                (bottom - y).max(0.0),
                hex(color),
                esc(panel.categories.get(i).map(String::as_str).unwrap_or("")),
                short_number(v)
            );
            if let Some(c) = panel.categories.get(i) {
                let _ = writeln!(
                    out,
                    r#"<text x="{:.1}" y="{}" text-anchor="middle" font-size="11">{}</text>"#,
                    x0 + slot * (i as f64 + 0.5),
                    bottom + 15.0,
                    esc(c)
                );
            }
        }
        let _ = writeln!(
            out,
            r#"<line x1="{x0}" y1="{bottom}" x2="{x1}" y2="{bottom}" stroke="black"/><text transform="translate(22 {}) rotate(-90)" text-anchor="middle" font-size="12">{}</text>"#,
            (top + bottom) / 2.0,
            esc(&panel.y_label)
        );
        let _ = writeln!(
            out,
            r#"<text x="{}" y="{}" text-anchor="middle" font-size="12">{}</text>"#,
            (x0 + x1) / 2.0,
            bottom + 34.0,
            esc(x_label)
        );
    }
    if let Some(note) = note {
        let _ = writeln!(
            out,
            r##"<text x="{x0}" y="{}" font-size="11" fill="#555">{}</text>"##,
            height - 12.0,
            esc(note)
        );
    }
    out.push_str("</svg>\n");
    out
}
