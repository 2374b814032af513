//! Small, dependency-free SVG charts for self-contained HTML reports: line charts with several
//! series, (grouped) bar charts, heatmaps with marked cells and a legend, scatter plots.
//!
//! Every function returns a complete `<svg>` element as a `String` (no XML declaration), so it
//! can be inlined in HTML or written to a `.svg` file. Values are plotted in whatever unit the
//! caller gives; axis labels carry the unit. Non-finite values are skipped (lines break, bars
//! and cells are left empty), never drawn at NaN coordinates. No physics here.

use std::fmt::Write as _;

/// A qualitative palette (colour-blind friendly, Okabe–Ito), cycled by series index.
pub(crate) const PALETTE: [&str; 8] = [
    "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#F0E442", "#000000",
];

/// Colour of series `i` from [`PALETTE`].
pub fn colour(i: usize) -> &'static str {
    PALETTE[i % PALETTE.len()]
}

/// Escape text for XML element content and attribute values.
pub fn esc(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&#39;"),
            _ => o.push(c),
        }
    }
    o
}

/// Size and labels common to every chart. Sizes in SVG user units (px).
#[derive(Clone, Debug)]
pub struct Frame {
    /// Title drawn above the plot.
    pub title: String,
    /// X-axis label (with unit).
    pub x_label: String,
    /// Y-axis label (with unit).
    pub y_label: String,
    /// Total width, px.
    pub width: f64,
    /// Total height, px.
    pub height: f64,
    /// Text written where a bar has no (finite) value, e.g. "infeasible".
    pub missing: String,
    /// Value the bars of a [`bar_chart`] start from (the y axis starts there, said in the
    /// chart), when the part below is common to every bar; `None`: 0.
    pub baseline: Option<f64>,
}

impl Frame {
    /// A 640 × 360 px chart.
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Frame {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            width: 640.0,
            height: 360.0,
            missing: "n/a".into(),
            baseline: None,
        }
    }
    /// Same frame with another size (px).
    pub fn size(mut self, width: f64, height: f64) -> Self {
        self.width = width;
        self.height = height;
        self
    }
    /// Same frame with another text for bars without a value.
    pub fn missing(mut self, text: &str) -> Self {
        self.missing = text.into();
        self
    }
    /// Same frame with the bars starting from `v` instead of 0 ([`Frame::baseline`]).
    pub fn baseline(mut self, v: f64) -> Self {
        self.baseline = v.is_finite().then_some(v);
        self
    }
}

const ML: f64 = 70.0; // left margin, px
const MR: f64 = 20.0;
const MT: f64 = 36.0;
const MB: f64 = 50.0;

/// "Nice" tick values covering `[lo, hi]` (about `n` of them).
pub fn ticks(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite()) || hi <= lo {
        return vec![lo];
    }
    let raw = (hi - lo) / n.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let mut t = (lo / step).ceil() * step;
    let mut out = Vec::new();
    while t <= hi + step * 1e-9 {
        out.push(if t.abs() < step * 1e-9 { 0.0 } else { t });
        t += step;
    }
    out
}

/// Format a tick label compactly.
pub fn fmt_num(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-3..1e6).contains(&a) {
        format!("{v:.2e}")
    } else if a >= 100.0 {
        format!("{v:.0}")
    } else if a >= 1.0 {
        let s = format!("{v:.2}");
        s.trim_end_matches('0').trim_end_matches('.').into()
    } else {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').into()
    }
}

fn finite_range(vals: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for v in vals.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo > hi {
        return None;
    }
    if hi - lo < 1e-12 * (1.0 + lo.abs()) {
        let d = if lo == 0.0 { 1.0 } else { lo.abs() * 0.05 };
        return Some((lo - d, hi + d));
    }
    Some((lo, hi))
}

struct Axes {
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
    px0: f64,
    px1: f64,
    py0: f64,
    py1: f64,
}

impl Axes {
    fn new(f: &Frame, (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> Self {
        Axes {
            x0,
            x1,
            y0,
            y1,
            px0: ML,
            px1: f.width - MR,
            py0: f.height - MB,
            py1: MT,
        }
    }
    fn x(&self, v: f64) -> f64 {
        self.px0 + (v - self.x0) / (self.x1 - self.x0) * (self.px1 - self.px0)
    }
    fn y(&self, v: f64) -> f64 {
        self.py0 + (v - self.y0) / (self.y1 - self.y0) * (self.py1 - self.py0)
    }
}

fn open(f: &Frame) -> String {
    let mut s = String::new();
    let _ = write!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" data-n="{DATA_N}" font-family="sans-serif" font-size="12"><title>{t}</title><rect x="0" y="0" width="{w}" height="{h}" fill="white"/><text x="{cx}" y="20" text-anchor="middle" font-size="14" font-weight="bold">{t}</text>"#,
        w = f.width,
        h = f.height,
        cx = f.width / 2.0,
        t = esc(&f.title)
    );
    s
}

/// Placeholder of the `data-n` attribute (number of data items drawn), set by [`finish`].
const DATA_N: &str = "@data-n@";

/// Close the SVG and record how many data items (points, bars, cells) it draws in the root's
/// `data-n` attribute, so a test (or a reader's script) can tell a chart from an empty frame.
fn finish(mut s: String, n: usize) -> String {
    s.push_str("</svg>");
    s.replacen(DATA_N, &n.to_string(), 1)
}

fn axis_labels(s: &mut String, f: &Frame) {
    let _ = write!(
        s,
        r#"<text x="{}" y="{}" text-anchor="middle">{}</text><text x="14" y="{}" text-anchor="middle" transform="rotate(-90 14 {})">{}</text>"#,
        (ML + f.width - MR) / 2.0,
        f.height - 10.0,
        esc(&f.x_label),
        (MT + f.height - MB) / 2.0,
        (MT + f.height - MB) / 2.0,
        esc(&f.y_label)
    );
}

/// Y ticks and labels; `grid` draws light horizontal grid lines across the plot.
fn y_axis(s: &mut String, a: &Axes, grid: bool) {
    for t in ticks(a.y0, a.y1, 6) {
        let y = a.y(t);
        let _ = write!(
            s,
            r##"<line x1="{}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="{}"/><text x="{}" y="{:.1}" text-anchor="end">{}</text>"##,
            if grid { a.px0 } else { a.px0 - 4.0 },
            if grid { a.px1 } else { a.px0 },
            if grid { "#ddd" } else { "#333" },
            a.px0 - 5.0,
            y + 4.0,
            fmt_num(t)
        );
    }
    let _ = write!(
        s,
        r##"<line x1="{0}" y1="{1}" x2="{0}" y2="{2}" stroke="#333"/><line x1="{0}" y1="{1}" x2="{3}" y2="{1}" stroke="#333"/>"##,
        a.px0, a.py0, a.py1, a.px1
    );
}

fn x_axis(s: &mut String, a: &Axes) {
    for t in ticks(a.x0, a.x1, 8) {
        let x = a.x(t);
        let _ = write!(
            s,
            r##"<line x1="{x:.1}" y1="{}" x2="{x:.1}" y2="{}" stroke="#333"/><text x="{x:.1}" y="{}" text-anchor="middle">{}</text>"##,
            a.py0,
            a.py0 + 4.0,
            a.py0 + 16.0,
            fmt_num(t)
        );
    }
}

/// Width (px) a legend of `names` takes to the right of the plot.
fn legend_width(names: &[&str]) -> f64 {
    if names.is_empty() {
        return 0.0;
    }
    24.0 + 7.0 * names.iter().map(|n| n.chars().count()).max().unwrap_or(0) as f64
}

/// Legend in the right margin (outside the plot area, so it never hides data).
fn legend(s: &mut String, f: &Frame, names: &[&str]) {
    let x = f.width - legend_width(names) + 4.0;
    for (i, n) in names.iter().enumerate() {
        let y = MT + 10.0 + 17.0 * i as f64;
        let _ = write!(
            s,
            r#"<rect x="{x}" y="{:.1}" width="12" height="10" fill="{}"/><text x="{}" y="{:.1}">{}</text>"#,
            y - 9.0,
            colour(i),
            x + 16.0,
            y,
            esc(n)
        );
    }
}

/// One series of a line or scatter chart: `(x, y)` points in the caller's units.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend name.
    pub name: String,
    /// Points; non-finite points break the line.
    pub points: Vec<(f64, f64)>,
}

impl Series {
    /// A named series from x and y slices of equal length (extra values are ignored).
    pub fn new(name: &str, x: &[f64], y: &[f64]) -> Self {
        Series {
            name: name.into(),
            points: x.iter().copied().zip(y.iter().copied()).collect(),
        }
    }
}

fn xy_axes(f: &Frame, series: &[Series], legend: &[&str]) -> Axes {
    let xr = finite_range(series.iter().flat_map(|s| s.points.iter().map(|p| p.0)))
        .unwrap_or((0.0, 1.0));
    let yr = finite_range(series.iter().flat_map(|s| s.points.iter().map(|p| p.1)))
        .unwrap_or((0.0, 1.0));
    padded_axes(f, xr, yr, legend)
}

/// Axes of an x–y chart over the ranges `xr` and `yr` (the latter padded by 5 % each way),
/// narrowed by the legend naming `legend`.
fn padded_axes(f: &Frame, xr: (f64, f64), yr: (f64, f64), legend: &[&str]) -> Axes {
    let pad = (yr.1 - yr.0) * 0.05;
    let mut a = Axes::new(f, xr, (yr.0 - pad, yr.1 + pad));
    a.px1 -= legend_width(legend);
    a
}

/// Draw series `i` through the points `pts` as one path in its colour; the pen is lifted
/// over non-finite points.
fn series_path(s: &mut String, a: &Axes, i: usize, pts: &[(f64, f64)]) {
    let mut d = String::new();
    let mut pen_up = true;
    for &(x, y) in pts {
        if !(x.is_finite() && y.is_finite()) {
            pen_up = true;
            continue;
        }
        // After "M", further coordinate pairs are implicit line-tos.
        let _ = write!(
            d,
            "{}{:.1},{:.1}",
            if pen_up { "M" } else { " " },
            a.x(x),
            a.y(y)
        );
        pen_up = false;
    }
    let _ = write!(
        s,
        r#"<path d="{d}" fill="none" stroke="{}" stroke-width="1.2"/>"#,
        colour(i)
    );
}

/// Legend entries of an x–y chart: none for a single unnamed or lone series (the title names it).
fn xy_legend(series: &[Series]) -> Vec<&str> {
    if series.len() > 1 {
        series.iter().map(|s| s.name.as_str()).collect()
    } else {
        Vec::new()
    }
}

/// Line chart with several series (a legend names them). Long series (logs) are decimated to
/// one bucket per two pixel columns of the plot, keeping each bucket's min and max, so the
/// drawn envelope is unchanged while the SVG stays small.
pub fn line_chart(f: &Frame, series: &[Series]) -> String {
    let names = xy_legend(series);
    let a = xy_axes(f, series, &names);
    let mut s = open(f);
    y_axis(&mut s, &a, true);
    x_axis(&mut s, &a);
    for (i, se) in series.iter().enumerate() {
        let pts = decimate(&se.points, ((a.px1 - a.px0) / 2.0).ceil().max(1.0) as usize);
        series_path(&mut s, &a, i, &pts);
    }
    legend(&mut s, f, &names);
    axis_labels(&mut s, f);
    let n = series
        .iter()
        .map(|se| {
            se.points
                .iter()
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .count()
        })
        .sum();
    finish(s, n)
}

/// Buckets of [`line_chart`]'s decimation for a chart in frame `f` whose series are named
/// `names` (one bucket per two pixel columns of the plot area, which the legend narrows).
pub(crate) fn line_buckets(f: &Frame, names: &[&str]) -> usize {
    let legend: &[&str] = if names.len() > 1 { names } else { &[] };
    let a = Axes::new(f, (0.0, 1.0), (0.0, 1.0));
    ((a.px1 - legend_width(legend) - a.px0) / 2.0)
        .ceil()
        .max(1.0) as usize
}

/// A series of [`line_chart`] taken in sample by sample, holding only what the chart draws:
/// the decimated points (each bucket's minimum and maximum, [`line_chart`]'s own decimation),
/// the ranges of x and y and the number of finite points. [`line_chart_streamed`] draws the
/// same SVG from these as [`line_chart`] from the whole series.
#[derive(Clone, Debug)]
pub(crate) struct StreamedSeries {
    /// Legend name.
    pub name: String,
    /// Points per bucket (0: every point is kept, the series being short).
    per: usize,
    kept: Vec<(f64, f64)>,
    in_chunk: usize,
    lo: Option<(f64, f64)>,
    hi: Option<(f64, f64)>,
    x: (f64, f64),
    y: (f64, f64),
    finite: usize,
}

impl StreamedSeries {
    /// A series of `len` points to be drawn with `buckets` buckets ([`line_buckets`]).
    pub fn new(name: &str, len: usize, buckets: usize) -> Self {
        let per = if len <= 2 * buckets {
            0
        } else {
            len.div_ceil(buckets)
        };
        StreamedSeries {
            name: name.into(),
            per,
            kept: Vec::with_capacity(2 * buckets + 2),
            in_chunk: 0,
            lo: None,
            hi: None,
            x: (f64::INFINITY, f64::NEG_INFINITY),
            y: (f64::INFINITY, f64::NEG_INFINITY),
            finite: 0,
        }
    }

    /// The next point.
    pub fn push(&mut self, x: f64, y: f64) {
        if x.is_finite() {
            self.x = (self.x.0.min(x), self.x.1.max(x));
        }
        if y.is_finite() {
            self.y = (self.y.0.min(y), self.y.1.max(y));
        }
        if x.is_finite() && y.is_finite() {
            self.finite += 1;
        }
        if self.per == 0 {
            self.kept.push((x, y));
            return;
        }
        if y.is_finite() {
            // min_by keeps the first of equal minima, max_by the last of equal maxima.
            if self.lo.is_none_or(|l| y.total_cmp(&l.1).is_lt()) {
                self.lo = Some((x, y));
            }
            if self.hi.is_none_or(|h| !y.total_cmp(&h.1).is_lt()) {
                self.hi = Some((x, y));
            }
        }
        self.in_chunk += 1;
        if self.in_chunk == self.per {
            self.close_chunk();
        }
    }

    fn close_chunk(&mut self) {
        match (self.lo.take(), self.hi.take()) {
            (Some(l), Some(h)) => {
                if l.0 <= h.0 {
                    self.kept.push(l);
                    self.kept.push(h);
                } else {
                    self.kept.push(h);
                    self.kept.push(l);
                }
            }
            _ => self.kept.push((f64::NAN, f64::NAN)),
        }
        self.in_chunk = 0;
    }

    /// The series is complete (a last, shorter bucket is closed).
    pub fn finish(&mut self) {
        if self.per > 0 && self.in_chunk > 0 {
            self.close_chunk();
        }
    }
}

/// [`line_chart`] of series taken in with [`StreamedSeries`] (each finished): the same SVG,
/// byte for byte, as [`line_chart`] over the whole series.
pub(crate) fn line_chart_streamed(f: &Frame, series: &[StreamedSeries]) -> String {
    let names: Vec<&str> = if series.len() > 1 {
        series.iter().map(|s| s.name.as_str()).collect()
    } else {
        Vec::new()
    };
    let range = |r: &mut dyn Iterator<Item = (f64, f64)>| {
        let (lo, hi) = r.fold((f64::INFINITY, f64::NEG_INFINITY), |a, b| {
            (a.0.min(b.0), a.1.max(b.1))
        });
        // finite_range over the two ends found (finite values only): the same range.
        finite_range([lo, hi].into_iter().filter(|v| v.is_finite()))
    };
    let xr = range(&mut series.iter().map(|s| s.x)).unwrap_or((0.0, 1.0));
    let yr = range(&mut series.iter().map(|s| s.y)).unwrap_or((0.0, 1.0));
    let a = padded_axes(f, xr, yr, &names);
    let mut s = open(f);
    y_axis(&mut s, &a, true);
    x_axis(&mut s, &a);
    for (i, se) in series.iter().enumerate() {
        series_path(&mut s, &a, i, &se.kept);
    }
    legend(&mut s, f, &names);
    axis_labels(&mut s, f);
    finish(s, series.iter().map(|se| se.finite).sum())
}

fn decimate(p: &[(f64, f64)], buckets: usize) -> Vec<(f64, f64)> {
    if p.len() <= 2 * buckets {
        return p.to_vec();
    }
    let per = p.len().div_ceil(buckets);
    let mut out = Vec::with_capacity(2 * buckets + 2);
    for c in p.chunks(per) {
        let lo = c
            .iter()
            .copied()
            .filter(|q| q.1.is_finite())
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let hi = c
            .iter()
            .copied()
            .filter(|q| q.1.is_finite())
            .max_by(|a, b| a.1.total_cmp(&b.1));
        match (lo, hi) {
            (Some(l), Some(h)) => {
                if l.0 <= h.0 {
                    out.push(l);
                    out.push(h);
                } else {
                    out.push(h);
                    out.push(l);
                }
            }
            _ => out.push((f64::NAN, f64::NAN)),
        }
    }
    out
}

/// Scatter chart: one marker per point, one colour per series. Dense series (long logs) are
/// thinned to one marker per 2 px × 2 px cell of the plot area, which draws the same picture
/// with a bounded number of markers; all markers of a series are one `<path>`.
pub fn scatter(f: &Frame, series: &[Series]) -> String {
    let names = xy_legend(series);
    let a = xy_axes(f, series, &names);
    let mut s = open(f);
    y_axis(&mut s, &a, true);
    x_axis(&mut s, &a);
    let dense = series.iter().map(|s| s.points.len()).sum::<usize>() > 400;
    let r = if dense { 1.6 } else { 3.0 };
    for (i, se) in series.iter().enumerate() {
        let mut seen = std::collections::HashSet::new();
        let mut last: Option<(i64, i64)> = None;
        let mut d = String::new();
        for &(x, y) in se
            .points
            .iter()
            .filter(|p| p.0.is_finite() && p.1.is_finite())
        {
            let (px, py) = (a.x(x), a.y(y));
            if dense {
                // Snap to the 2 px cell and write relative integer moves (small file).
                let cell = ((px / 2.0).floor() as i64, (py / 2.0).floor() as i64);
                if !seen.insert(cell) {
                    continue;
                }
                let (u, v) = (2 * cell.0 + 1, 2 * cell.1 + 1);
                // A round-capped zero-length segment draws a dot of diameter 2r.
                match last {
                    None => {
                        let _ = write!(d, "M{u} {v}h0");
                    }
                    Some((lu, lv)) => {
                        let _ = write!(d, "m{} {}h0", u - lu, v - lv);
                    }
                }
                last = Some((u, v));
            } else {
                let _ = write!(d, "M{px:.1} {py:.1}h0");
            }
        }
        let _ = write!(
            s,
            r#"<path d="{d}" stroke="{}" stroke-width="{:.1}" stroke-linecap="round" stroke-opacity="{}" fill="none"/>"#,
            colour(i),
            2.0 * r,
            if dense { 0.6 } else { 0.8 }
        );
    }
    legend(&mut s, f, &names);
    axis_labels(&mut s, f);
    let n = series
        .iter()
        .map(|se| {
            se.points
                .iter()
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .count()
        })
        .sum();
    finish(s, n)
}

/// Grouped bar chart: `categories` along x, one bar per group in `groups` (name, one value per
/// category). A single group is a plain bar chart. Values are printed above the bars.
/// The y axis starts at 0 (or below, for negative values).
pub(crate) fn bar_chart(f: &Frame, categories: &[String], groups: &[(String, Vec<f64>)]) -> String {
    let names: Vec<&str> = if groups.len() > 1 {
        groups.iter().map(|g| g.0.as_str()).collect()
    } else {
        Vec::new()
    };
    let lay = BarLayout::new(f, categories, groups, &names);
    let mut a = Axes::new(f, (0.0, categories.len().max(1) as f64), (lay.lo, lay.top));
    a.px1 -= legend_width(&names);
    let mut s = open(f);
    y_axis(&mut s, &a, true);
    for (c, name) in categories.iter().enumerate() {
        lay.category(&mut s, &a, (c, name), groups);
    }
    let base = lay.base;
    if base != 0.0 {
        // Said in the chart, and the axis broken: the bars do not start at 0.
        let _ = write!(
            s,
            r##"<path d="M{:.1},{:.1} l-6,4 l12,4 l-6,4" fill="white" stroke="#333"/><text class="axis-from" data-baseline="{base}" x="{:.1}" y="{:.1}" font-size="11" fill="#555">bars start at {} (not 0)</text>"##,
            a.px0,
            a.py0 - 14.0,
            a.px0 + 8.0,
            a.py0 - 4.0,
            fmt_num(base)
        );
    }
    legend(&mut s, f, &names);
    axis_labels(&mut s, f);
    let n = groups
        .iter()
        .flat_map(|g| g.1.iter())
        .filter(|v| v.is_finite())
        .count();
    finish(s, n)
}

/// Width of a bar chart's value label `t` (font 10, ~5.6 px per character), px.
fn text_w(t: &str) -> f64 {
    5.6 * t.chars().count() as f64 + 4.0
}

/// Where the bars of a [`bar_chart`] go and how their value labels are written.
struct BarLayout<'f> {
    /// The chart's frame (its text for a missing value).
    f: &'f Frame,
    /// Value the bars start from.
    base: f64,
    /// Bottom of the y axis.
    lo: f64,
    /// Top of the y axis, with head room for upright labels.
    top: f64,
    /// Width of one category, px.
    slot: f64,
    /// Width of one bar, px.
    bw: f64,
    /// Number of groups (at least 1).
    ng: f64,
    /// Whether every bar is labelled with its value (else only missing ones).
    labelled: bool,
    /// Whether the value labels are turned upright.
    upright: bool,
}

impl<'f> BarLayout<'f> {
    /// The layout of `groups` over `categories` in frame `f`, a legend naming `names` beside.
    fn new(
        f: &'f Frame,
        categories: &[String],
        groups: &[(String, Vec<f64>)],
        names: &[&str],
    ) -> Self {
        let all = groups.iter().flat_map(|g| g.1.iter().copied());
        // The bars start at the baseline (0 unless the frame gives one below every value).
        let base = f
            .baseline
            .filter(|b| {
                groups
                    .iter()
                    .flat_map(|g| g.1.iter())
                    .filter(|v| v.is_finite())
                    .all(|v| v > b)
            })
            .unwrap_or(0.0);
        let (lo, hi) = finite_range(all.chain([base])).unwrap_or((0.0, 1.0));
        let ng = groups.len().max(1) as f64;
        let plot_w = f.width - ML - MR - legend_width(names);
        let slot = plot_w / categories.len().max(1) as f64;
        // At most 80 px per bar, so one or two categories do not turn into slabs.
        let bw = (slot * 0.8 / ng).min(80.0);
        let mut lay = BarLayout {
            f,
            base,
            lo,
            top: hi,
            slot,
            bw,
            ng,
            labelled: groups.len() <= 3,
            upright: false,
        };
        // Value labels that do not fit above a bar are turned upright; leave head room for
        // the longest of them. All upright if any must be (mixed orientations read badly).
        lay.upright = groups
            .iter()
            .flat_map(|g| g.1.iter())
            .filter(|v| lay.labelled || !v.is_finite())
            .any(|v| text_w(&lay.label(*v)) > bw);
        let need = if lay.labelled {
            groups
                .iter()
                .flat_map(|g| g.1.iter())
                .map(|v| lay.label(*v))
                .filter(|_| lay.upright)
                .map(|t| text_w(&t))
                .fold(14.0, f64::max)
        } else {
            0.0
        };
        let ph = f.height - MT - MB;
        if hi > 0.0 {
            lay.top = hi + (hi - lo) * need / (ph - need).max(ph * 0.3);
        }
        lay
    }

    /// The value label of a bar: its value, or the frame's text for a missing one.
    fn label(&self, v: f64) -> String {
        if v.is_finite() {
            fmt_num(v)
        } else {
            self.f.missing.clone()
        }
    }

    /// Draw category `c` (named `name`): its bars, one per group, their value labels and its
    /// name under the axis.
    fn category(
        &self,
        s: &mut String,
        a: &Axes,
        (c, name): (usize, &str),
        groups: &[(String, Vec<f64>)],
    ) {
        let (bw, base) = (self.bw, self.base);
        let x0 = a.px0 + self.slot * (c as f64 + 0.5) - bw * self.ng / 2.0;
        for (g, (_, vals)) in groups.iter().enumerate() {
            let v = vals.get(c).copied().unwrap_or(f64::NAN);
            let cx = x0 + bw * (g as f64 + 0.5);
            let (ya, yb) = (a.y(base), a.y(if v.is_finite() { v } else { base }));
            if v.is_finite() {
                let _ = write!(
                    s,
                    r#"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}" fill="{}"><title>{}: {}</title></rect>"#,
                    x0 + bw * g as f64,
                    ya.min(yb),
                    bw * 0.95,
                    (ya - yb).abs(),
                    colour(g),
                    esc(name),
                    fmt_num(v)
                );
            }
            if self.labelled || !v.is_finite() {
                let t = self.label(v);
                let fill = if v.is_finite() { "#222" } else { "#888" };
                let y = ya.min(yb) - 3.0;
                if self.upright {
                    let _ = write!(
                        s,
                        r#"<text x="{:.1}" y="{y:.1}" transform="rotate(-90 {:.1} {y:.1})" font-size="10" fill="{fill}">{}</text>"#,
                        cx + 3.5,
                        cx + 3.5,
                        esc(&t)
                    );
                } else {
                    let _ = write!(
                        s,
                        r#"<text x="{cx:.1}" y="{y:.1}" text-anchor="middle" font-size="10" fill="{fill}">{}</text>"#,
                        esc(&t)
                    );
                }
            }
        }
        let _ = write!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
            a.px0 + self.slot * (c as f64 + 0.5),
            a.py0 + 16.0,
            esc(name)
        );
    }
}

/// A marked heatmap cell: drawn with a hatch/colour of its class and named in the legend.
#[derive(Clone, Debug)]
pub struct CellMark {
    /// Column index (x).
    pub col: usize,
    /// Row index (y, 0 = bottom).
    pub row: usize,
    /// Class name (legend entry), e.g. "unreachable", "collision", "optimum".
    pub class: String,
    /// Exact position in the axes' units, if the mark stands for a point rather than the
    /// whole cell (e.g. an optimum found off the grid); `None` = the cell centre.
    pub at: Option<(f64, f64)>,
}

/// A heatmap over a regular grid.
#[derive(Clone, Debug)]
pub struct Heatmap {
    /// Cell-centre x coordinates (ascending), caller's unit.
    pub xs: Vec<f64>,
    /// Cell-centre y coordinates (ascending), caller's unit.
    pub ys: Vec<f64>,
    /// Values, row-major: `values[row * xs.len() + col]`; non-finite = no colour.
    pub values: Vec<f64>,
    /// Marked cells (drawn over the colour); the classes get legend entries.
    pub marks: Vec<CellMark>,
    /// Unit of the colour scale, for the legend (e.g. "J").
    pub value_label: String,
}

/// Viridis-like colour for `t` in [0, 1].
pub fn ramp(t: f64) -> String {
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (STOPS.len() - 1) as f64;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let u = x - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    format!(
        "rgb({},{},{})",
        (a.0 + (b.0 - a.0) * u).round(),
        (a.1 + (b.1 - a.1) * u).round(),
        (a.2 + (b.2 - a.2) * u).round()
    )
}

const MARK_STYLES: [&str; 6] = [
    "#d62728", "#7f7f7f", "#ff7f0e", "#8c564b", "#e377c2", "#17becf",
];

/// A vertical colour bar: left edge, top and height (px), and the value range it spans.
struct ColourBar {
    bx: f64,
    top: f64,
    h: f64,
    vlo: f64,
    vhi: f64,
}

impl ColourBar {
    /// Height (px) of value `t` on the bar.
    fn y(&self, t: f64) -> f64 {
        self.top + self.h * (1.0 - (t - self.vlo) / (self.vhi - self.vlo))
    }

    /// Draw the colour slices and the ticks (nice values inside the range, and its ends unless
    /// a tick is within 14 px of them); `tick_attr` is added to each tick's text element.
    fn draw(&self, s: &mut String, tick_attr: &str) {
        let (bx, vlo, vhi) = (self.bx, self.vlo, self.vhi);
        let nb = 40;
        for i in 0..nb {
            // Slice i spans [i, i + 1] / nb of the range, so ticks line up with the colours.
            let (t0, t1) = (i as f64 / nb as f64, (i + 1) as f64 / nb as f64);
            let _ = write!(
                s,
                r#"<rect x="{bx}" y="{:.1}" width="14" height="{:.2}" fill="{}"/>"#,
                self.top + self.h * (1.0 - t1),
                self.h / nb as f64 + 0.5,
                ramp((t0 + t1) / 2.0)
            );
        }
        let mut cb = ticks(vlo, vhi, 4);
        cb.retain(|t| *t >= vlo - 1e-9 * (vhi - vlo).abs() && *t <= vhi + 1e-9 * (vhi - vlo).abs());
        for end in [vlo, vhi] {
            if cb.iter().all(|t| (self.y(*t) - self.y(end)).abs() > 14.0) {
                cb.push(end);
            }
        }
        for t in cb {
            let y = self.y(t);
            let _ = write!(
                s,
                r##"<line x1="{bx}" y1="{y:.1}" x2="{}" y2="{y:.1}" stroke="#333"/><text{tick_attr} x="{}" y="{:.1}">{}</text>"##,
                bx + 17.0,
                bx + 20.0,
                y + 4.0,
                fmt_num(t)
            );
        }
    }
}

/// Heatmap with a colour bar, marked cells and a legend of mark classes. A class named
/// `optimum` (or `best`) is drawn as a star-like ring rather than a filled cell.
pub fn heatmap(f: &Frame, h: &Heatmap) -> String {
    let nx = h.xs.len().max(1);
    let ny = h.ys.len().max(1);
    let step = |v: &[f64]| {
        if v.len() > 1 {
            (v[v.len() - 1] - v[0]) / (v.len() - 1) as f64
        } else {
            1.0
        }
    };
    let (dx, dy) = (step(&h.xs), step(&h.ys));
    let x0 = h.xs.first().copied().unwrap_or(0.0) - dx / 2.0;
    let y0 = h.ys.first().copied().unwrap_or(0.0) - dy / 2.0;
    let f2 = Frame {
        width: f.width - 120.0,
        ..f.clone()
    };
    let a = Axes::new(&f2, (x0, x0 + dx * nx as f64), (y0, y0 + dy * ny as f64));
    let (vlo, vhi) = finite_range(h.values.iter().copied()).unwrap_or((0.0, 1.0));
    let mut s = open(f);
    heatmap_cells(&mut s, &a, h, (vlo, vhi));
    let classes = heatmap_marks(&mut s, &a, h);
    y_axis(&mut s, &a, false);
    x_axis(&mut s, &a);
    let bar = ColourBar {
        bx: f.width - 110.0,
        top: a.py1,
        h: (a.py0 - a.py1) * 0.6,
        vlo,
        vhi,
    };
    bar.draw(&mut s, "");
    let _ = write!(
        s,
        r#"<text x="{}" y="{:.1}" font-weight="bold">{}</text>"#,
        bar.bx,
        a.py1 - 10.0,
        esc(&h.value_label)
    );
    heatmap_legend(&mut s, &bar, &classes);
    axis_labels(&mut s, &f2);
    let n = h.values.iter().filter(|v| v.is_finite()).count();
    finish(s, n)
}

/// Size `(cw, ch)` of one heatmap cell on axes `a`, px.
fn heatmap_cell_size(a: &Axes, h: &Heatmap) -> (f64, f64) {
    let nx = h.xs.len().max(1);
    let ny = h.ys.len().max(1);
    ((a.px1 - a.px0) / nx as f64, (a.py0 - a.py1) / ny as f64)
}

/// Draw the cells of a heatmap, coloured by value over `(vlo, vhi)` (light grey without one).
fn heatmap_cells(s: &mut String, a: &Axes, h: &Heatmap, (vlo, vhi): (f64, f64)) {
    let nx = h.xs.len().max(1);
    let ny = h.ys.len().max(1);
    let (cw, ch) = heatmap_cell_size(a, h);
    for r in 0..ny {
        for c in 0..nx {
            let v = h.values.get(r * nx + c).copied().unwrap_or(f64::NAN);
            let fill = if v.is_finite() {
                ramp((v - vlo) / (vhi - vlo))
            } else {
                "#f2f2f2".into()
            };
            let _ = write!(
                s,
                r#"<rect x="{:.1}" y="{:.1}" width="{:.2}" height="{:.2}" fill="{fill}"><title>({}, {}): {}</title></rect>"#,
                a.px0 + cw * c as f64,
                a.py0 - ch * (r + 1) as f64,
                cw + 0.3,
                ch + 0.3,
                fmt_num(h.xs.get(c).copied().unwrap_or(0.0)),
                fmt_num(h.ys.get(r).copied().unwrap_or(0.0)),
                if v.is_finite() {
                    fmt_num(v)
                } else {
                    "-".into()
                }
            );
        }
    }
}

/// Draw the marks of a heatmap: a ring for the optimum, a cross in its class's colour for the
/// others; returns the classes in order of first appearance (for the legend).
fn heatmap_marks<'h>(s: &mut String, a: &Axes, h: &'h Heatmap) -> Vec<&'h str> {
    let (cw, ch) = heatmap_cell_size(a, h);
    let mut classes: Vec<&str> = Vec::new();
    for m in &h.marks {
        if !classes.contains(&m.class.as_str()) {
            classes.push(&m.class);
        }
    }
    for m in &h.marks {
        let k = classes.iter().position(|c| *c == m.class).unwrap_or(0);
        let (cx, cy) = match m.at {
            Some((x, y)) if x.is_finite() && y.is_finite() => (a.x(x), a.y(y)),
            _ => (
                a.px0 + cw * (m.col as f64 + 0.5),
                a.py0 - ch * (m.row as f64 + 0.5),
            ),
        };
        if m.class == "optimum" || m.class == "best" {
            let _ = write!(
                s,
                r#"<circle class="mark-{}" cx="{cx:.1}" cy="{cy:.1}" r="{:.1}" fill="none" stroke="white" stroke-width="3"/><circle cx="{cx:.1}" cy="{cy:.1}" r="{:.1}" fill="none" stroke="black" stroke-width="1.5"/>"#,
                esc(&m.class),
                (cw.min(ch) * 0.45).max(4.0),
                (cw.min(ch) * 0.45).max(4.0)
            );
        } else {
            cross_mark(
                s,
                &m.class,
                (cx, cy),
                (cw, ch),
                MARK_STYLES[k % MARK_STYLES.len()],
            );
        }
    }
    classes
}

/// Draw the legend of a heatmap's mark classes below its colour bar.
fn heatmap_legend(s: &mut String, bar: &ColourBar, classes: &[&str]) {
    let bx = bar.bx;
    for (k, c) in classes.iter().enumerate() {
        let y = bar.top + bar.h + 24.0 + 16.0 * k as f64;
        let sym = if *c == "optimum" || *c == "best" {
            format!(
                r#"<circle cx="{}" cy="{:.1}" r="5" fill="none" stroke="black" stroke-width="1.5"/>"#,
                bx + 6.0,
                y - 4.0
            )
        } else {
            format!(
                r#"<line x1="{}" y1="{:.1}" x2="{}" y2="{:.1}" stroke="{}" stroke-width="2"/>"#,
                bx,
                y - 9.0,
                bx + 12.0,
                y + 1.0,
                MARK_STYLES[k % MARK_STYLES.len()]
            )
        };
        let _ = write!(
            s,
            r#"{sym}<text x="{}" y="{y:.1}" font-size="11">{}</text>"#,
            bx + 16.0,
            esc(c)
        );
    }
}

/// A point drawn on a [`top_view`]: a named position, optionally coloured by its value.
#[derive(Clone, Debug)]
pub struct MapPoint {
    /// Position, m (base frame x, y).
    pub x: f64,
    /// Position, m.
    pub y: f64,
    /// Label drawn beside it (e.g. "P1", "optimum").
    pub label: String,
    /// Value on the colour scale (non-finite: drawn hollow, e.g. infeasible).
    pub value: f64,
    /// Class (`mark-<class>` in the SVG): "optimum", "best-cell", "named", ...
    pub class: String,
}

/// A top view of the cell drawn to scale (one metre is as long on both axes).
#[derive(Clone, Debug, Default)]
pub struct TopView {
    /// Energy cells over the workspace (optional): centres, values and marks as for
    /// [`heatmap`].
    pub cells: Option<Heatmap>,
    /// Circles `(cx, cy, r, class, label)`, m: the robot base, the reachable annulus.
    pub circles: Vec<(f64, f64, f64, String, String)>,
    /// Polylines `(class, points)`, m: the part outline at the optimum.
    pub lines: Vec<(String, Vec<(f64, f64)>)>,
    /// Filled closed outlines `(class, label, points)`, m, drawn to scale and always inside the
    /// drawn extent: the robot base's footprint.
    pub footprints: Vec<Footprint>,
    /// Named points.
    pub points: Vec<MapPoint>,
    /// Unit of the colour scale.
    pub value_label: String,
}

/// A filled closed outline on a [`TopView`]: `(class, label, points)`, m.
pub(crate) type Footprint = (String, String, Vec<(f64, f64)>);

/// Width of the column beside a top view that holds its colour bar and legend, px.
const TOP_VIEW_BAR_W: f64 = 170.0;

/// Distance between neighbouring cell centres along one axis (0.1 for a single cell).
fn cell_step(c: &[f64]) -> f64 {
    if c.len() > 1 {
        (c[c.len() - 1] - c[0]) / (c.len() - 1) as f64
    } else {
        0.1
    }
}

/// The extent `(x0, x1, y0, y1)` a top view must show, m: the origin, the cells, the points,
/// the outlines, the base's and pedestal's circles and the footprints.
fn top_view_extent(v: &TopView) -> (f64, f64, f64, f64) {
    let (mut x0, mut x1, mut y0, mut y1) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut grow = |x: f64, y: f64| {
        if x.is_finite() && y.is_finite() {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
    };
    if let Some(h) = &v.cells {
        let (dx, dy) = (cell_step(&h.xs), cell_step(&h.ys));
        for x in &h.xs {
            for y in &h.ys {
                grow(x - dx / 2.0, y - dy / 2.0);
                grow(x + dx / 2.0, y + dy / 2.0);
            }
        }
    }
    for p in &v.points {
        grow(p.x, p.y);
    }
    for (_, l) in &v.lines {
        for &(x, y) in l {
            grow(x, y);
        }
    }
    for (cx, cy, r, class, _) in &v.circles {
        if class == "base" || class == "pedestal" {
            grow(cx - r, cy - r);
            grow(cx + r, cy + r);
        }
    }
    for (_, _, l) in &v.footprints {
        for &(x, y) in l {
            grow(x, y);
        }
    }
    (x0, x1, y0, y1)
}

/// Equal scales on a plot area `(pw, ph)` px: the range `(x0, x1, y0, y1)` widened along the
/// axis that would otherwise be stretched, about its centre, and the scale in px per unit.
pub(crate) fn equal_scales(
    (mut x0, mut x1, mut y0, mut y1): (f64, f64, f64, f64),
    (pw, ph): (f64, f64),
) -> ((f64, f64, f64, f64), f64) {
    let k = (pw / (x1 - x0)).min(ph / (y1 - y0));
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    x0 = cx - pw / k / 2.0;
    x1 = cx + pw / k / 2.0;
    y0 = cy - ph / k / 2.0;
    y1 = cy + ph / k / 2.0;
    ((x0, x1, y0, y1), k)
}

/// What every layer of a top view draws with: the axes, their scale (px per metre) and the
/// range of the colour scale.
struct TopViewScale {
    a: Axes,
    k: f64,
    vlo: f64,
    vhi: f64,
}

impl TopViewScale {
    /// The padded, equal-scaled axes of a top view in frame `f2` and its colour range, which
    /// covers every cell and point value.
    fn new(f2: &Frame, v: &TopView) -> Self {
        let (x0, x1, y0, y1) = top_view_extent(v);
        let pad = 0.05 * (x1 - x0).max(y1 - y0).max(0.1);
        let (pw, ph) = (f2.width - ML - MR, f2.height - MT - MB);
        let ((x0, x1, y0, y1), k) =
            equal_scales((x0 - pad, x1 + pad, y0 - pad, y1 + pad), (pw, ph));
        let a = Axes::new(f2, (x0, x1), (y0, y1));
        let vals = v
            .cells
            .iter()
            .flat_map(|h| h.values.iter().copied())
            .chain(v.points.iter().map(|p| p.value));
        let (vlo, vhi) = finite_range(vals).unwrap_or((0.0, 1.0));
        TopViewScale { a, k, vlo, vhi }
    }
}

/// Top view with equal axis scales: energy cells (colour bar covering every cell and point
/// value, so an optimum found off the grid is on the scale), infeasible cells crossed by
/// reason, circles (base, reach), outlines (the part) and labelled points. The drawn extent
/// covers the cells, the points, the outlines and the base; circles are clipped to it.
pub fn top_view(f: &Frame, v: &TopView) -> String {
    let f2 = Frame {
        width: f.width - TOP_VIEW_BAR_W,
        ..f.clone()
    };
    let sc = TopViewScale::new(&f2, v);
    let a = &sc.a;
    let mut n = 0usize;
    let mut s = open(f);
    let _ = write!(
        s,
        r#"<defs><clipPath id="plot-area"><rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}"/></clipPath></defs><g clip-path="url(#plot-area)">"#,
        a.px0,
        a.py1,
        a.px1 - a.px0,
        a.py0 - a.py1
    );
    let mut classes: Vec<String> = Vec::new();
    if let Some(h) = &v.cells {
        n += top_view_cells(&mut s, &sc, h);
        classes = top_view_marks(&mut s, &sc, h);
    }
    n += top_view_shapes(&mut s, &sc, v);
    s.push_str("</g>");
    let (drawn, any_infeasible) = top_view_points(&mut s, &sc, &v.points);
    n += drawn;
    y_axis(&mut s, a, false);
    x_axis(&mut s, a);
    let bar = ColourBar {
        bx: f.width - TOP_VIEW_BAR_W + 10.0,
        top: a.py1,
        h: (a.py0 - a.py1) * 0.5,
        vlo: sc.vlo,
        vhi: sc.vhi,
    };
    bar.draw(&mut s, r#" class="cbar-tick""#);
    let _ = write!(
        s,
        r#"<text x="{}" y="{:.1}" font-weight="bold" data-lo="{}" data-hi="{}" class="cbar">{}</text>"#,
        bar.bx,
        a.py1 - 10.0,
        sc.vlo,
        sc.vhi,
        esc(&v.value_label)
    );
    top_view_legend(&mut s, &bar, &classes, v, any_infeasible);
    axis_labels(&mut s, &f2);
    finish(s, n)
}

/// Draw the energy cells of a top view, coloured by value (light grey without one); returns
/// how many have a value.
fn top_view_cells(s: &mut String, sc: &TopViewScale, h: &Heatmap) -> usize {
    let (a, k) = (&sc.a, sc.k);
    let (dx, dy) = (cell_step(&h.xs), cell_step(&h.ys));
    let (cw, ch) = (dx * k, dy * k);
    let nx = h.xs.len();
    let mut n = 0;
    for (r, y) in h.ys.iter().enumerate() {
        for (c, x) in h.xs.iter().enumerate() {
            let val = h.values.get(r * nx + c).copied().unwrap_or(f64::NAN);
            let fill = if val.is_finite() {
                n += 1;
                ramp((val - sc.vlo) / (sc.vhi - sc.vlo))
            } else {
                "#f2f2f2".into()
            };
            let _ = write!(
                s,
                r#"<rect x="{:.1}" y="{:.1}" width="{:.2}" height="{:.2}" fill="{fill}"><title>({}, {}): {}</title></rect>"#,
                a.x(x - dx / 2.0),
                a.y(y + dy / 2.0),
                cw + 0.3,
                ch + 0.3,
                fmt_num(*x),
                fmt_num(*y),
                if val.is_finite() {
                    fmt_num(val)
                } else {
                    "-".into()
                }
            );
        }
    }
    n
}

/// Cross the marked cells of a top view in the colour of their class; returns the classes in
/// order of first appearance (for the legend).
fn top_view_marks(s: &mut String, sc: &TopViewScale, h: &Heatmap) -> Vec<String> {
    let a = &sc.a;
    let (cw, ch) = (cell_step(&h.xs) * sc.k, cell_step(&h.ys) * sc.k);
    let mut classes: Vec<String> = Vec::new();
    for m in &h.marks {
        if !classes.contains(&m.class) {
            classes.push(m.class.clone());
        }
        let kk = classes.iter().position(|c| *c == m.class).unwrap_or(0);
        let at = (
            a.x(h.xs.get(m.col).copied().unwrap_or(0.0)),
            a.y(h.ys.get(m.row).copied().unwrap_or(0.0)),
        );
        cross_mark(
            s,
            &m.class,
            at,
            (cw, ch),
            MARK_STYLES[kk % MARK_STYLES.len()],
        );
    }
    classes
}

/// Draw a cell mark of class `class`: a cross of colour `c` over the cell of size `(cw, ch)` px
/// centred at `(px, py)`.
fn cross_mark(s: &mut String, class: &str, (px, py): (f64, f64), (cw, ch): (f64, f64), c: &str) {
    let _ = write!(
        s,
        r#"<g class="mark-{}"><line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{c}" stroke-width="1.3"/><line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{c}" stroke-width="1.3"/></g>"#,
        esc(class),
        px - cw * 0.35,
        py - ch * 0.35,
        px + cw * 0.35,
        py + ch * 0.35,
        px - cw * 0.35,
        py + ch * 0.35,
        px + cw * 0.35,
        py - ch * 0.35,
    );
}

/// The SVG path data through `l` (m) on axes `a`: a move to the first point, then `sep`
/// before each further one.
fn path_data(a: &Axes, l: &[(f64, f64)], sep: &str) -> String {
    let mut d = String::new();
    for (i, &(x, y)) in l.iter().enumerate() {
        let _ = write!(
            d,
            "{}{:.1},{:.1}",
            if i == 0 { "M" } else { sep },
            a.x(x),
            a.y(y)
        );
    }
    d
}

/// Draw the circles (base, pedestal, reach), the filled footprints and the outlines of a top
/// view; returns how many outline and footprint points they draw.
fn top_view_shapes(s: &mut String, sc: &TopViewScale, v: &TopView) -> usize {
    let a = &sc.a;
    let mut n = 0;
    for (cx, cy, r, class, label) in &v.circles {
        let (dash, fill) = if class == "pedestal" {
            ("", "#999")
        } else if class == "base" {
            ("", "#555")
        } else {
            (r#" stroke-dasharray="6 4""#, "none")
        };
        let _ = write!(
            s,
            r##"<circle class="{}" cx="{:.1}" cy="{:.1}" r="{:.1}" fill="{fill}" fill-opacity="0.6" stroke="#333" stroke-width="1.2"{dash}><title>{}</title></circle>"##,
            esc(class),
            a.x(*cx),
            a.y(*cy),
            r * sc.k,
            esc(label)
        );
    }
    for (class, label, l) in &v.footprints {
        let d = path_data(a, l, " L");
        n += l.len();
        let _ = write!(
            s,
            r##"<path class="{}" d="{d} Z" fill="#555" fill-opacity="0.6" stroke="#333" stroke-width="1.2"><title>{}</title></path>"##,
            esc(class),
            esc(label)
        );
    }
    for (class, l) in &v.lines {
        let d = path_data(a, l, " ");
        n += l.len();
        let _ = write!(
            s,
            r##"<path class="{}" d="{d}" fill="none" stroke="#c00" stroke-width="1.5"/>"##,
            esc(class)
        );
    }
    n
}

/// Draw the labelled points of a top view: a disc coloured by value, or a red cross for an
/// infeasible placement. Labels of points at the same spot (a named placement at several
/// yaws) are stacked one below the other instead of printed over each other. Returns how many
/// points have a value and whether any placement is infeasible.
fn top_view_points(s: &mut String, sc: &TopViewScale, points: &[MapPoint]) -> (usize, bool) {
    let a = &sc.a;
    let mut n = 0;
    let mut placed: Vec<(f64, f64, usize)> = Vec::new();
    let mut any_infeasible = false;
    for p in points {
        let (px, py) = (a.x(p.x), a.y(p.y));
        let stack = match placed
            .iter_mut()
            .find(|q| (q.0 - px).abs() < 8.0 && (q.1 - py).abs() < 8.0)
        {
            Some(q) => {
                q.2 += 1;
                q.2 - 1
            }
            None => {
                placed.push((px, py, 1));
                0
            }
        };
        let label_y = py - 6.0 + 13.0 * stack as f64;
        if !p.value.is_finite() && p.class != "best-cell" {
            // An infeasible placement: a cross of its own (the legend names it), not a hollow
            // circle like the reach circles'.
            any_infeasible = true;
            infeasible_point(s, p, (px, py), label_y);
            continue;
        }
        let fill = if p.value.is_finite() {
            n += 1;
            ramp((p.value - sc.vlo) / (sc.vhi - sc.vlo))
        } else {
            "white".into()
        };
        let r = if p.class == "best-cell" { 9.0 } else { 6.0 };
        let label_y = if stack == 0 { py - r } else { label_y };
        let _ = write!(
            s,
            r##"<g class="mark-{}"><circle cx="{px:.1}" cy="{py:.1}" r="{r}" fill="none" stroke="white" stroke-width="3"/><circle cx="{px:.1}" cy="{py:.1}" r="{r}" fill="{fill}" fill-opacity="{}" stroke="black" stroke-width="1.5"><title>{}: {}</title></circle><text x="{:.1}" y="{:.1}" font-size="11" font-weight="bold">{}</text></g>"##,
            esc(&p.class),
            if p.class == "best-cell" { "0" } else { "1" },
            esc(&p.label),
            if p.value.is_finite() {
                fmt_num(p.value)
            } else {
                "infeasible".into()
            },
            px + r + 2.0,
            label_y,
            esc(&p.label)
        );
    }
    (n, any_infeasible)
}

/// Draw an infeasible placement at `(px, py)`: a red cross with its label at `label_y`.
fn infeasible_point(s: &mut String, p: &MapPoint, (px, py): (f64, f64), label_y: f64) {
    let _ = write!(
        s,
        r##"<g class="mark-{}" data-infeasible="1"><path d="M{:.1},{:.1} l10,10 m0,-10 l-10,10" stroke="white" stroke-width="4"/><path d="M{:.1},{:.1} l10,10 m0,-10 l-10,10" stroke="#d62728" stroke-width="2"><title>{}: infeasible</title></path><text x="{:.1}" y="{label_y:.1}" font-size="11" font-weight="bold">{}</text></g>"##,
        esc(&p.class),
        px - 5.0,
        py - 5.0,
        px - 5.0,
        py - 5.0,
        esc(&p.label),
        px + 8.0,
        esc(&p.label)
    );
}

/// Draw the legend of a top view below its colour bar: the mark classes, the circles, the
/// outlines and, if any placement is infeasible, its cross.
fn top_view_legend(
    s: &mut String,
    bar: &ColourBar,
    classes: &[String],
    v: &TopView,
    any_infeasible: bool,
) {
    let bx = bar.bx;
    let mut y = bar.top + bar.h + 24.0;
    for (kk, c) in classes.iter().enumerate() {
        let _ = write!(
            s,
            r#"<line x1="{bx}" y1="{:.1}" x2="{}" y2="{:.1}" stroke="{}" stroke-width="2"/><text x="{}" y="{y:.1}" font-size="11">{}</text>"#,
            y - 9.0,
            bx + 12.0,
            y + 1.0,
            MARK_STYLES[kk % MARK_STYLES.len()],
            bx + 16.0,
            esc(c)
        );
        y += 16.0;
    }
    for (_, _, _, class, label) in &v.circles {
        let _ = write!(
            s,
            r##"<circle cx="{}" cy="{:.1}" r="5" fill="{}" stroke="#333"/><text x="{}" y="{y:.1}" font-size="11">{}</text>"##,
            bx + 6.0,
            y - 4.0,
            if class == "base" { "#555" } else { "none" },
            bx + 16.0,
            esc(label)
        );
        y += 16.0;
    }
    for (class, _) in &v.lines {
        let _ = write!(
            s,
            r##"<line x1="{bx}" y1="{:.1}" x2="{}" y2="{:.1}" stroke="#c00" stroke-width="1.5"/><text x="{}" y="{y:.1}" font-size="11">{}</text>"##,
            y - 4.0,
            bx + 12.0,
            y - 4.0,
            bx + 16.0,
            esc(class)
        );
        y += 16.0;
    }
    if any_infeasible {
        let _ = write!(
            s,
            r##"<path class="legend-infeasible" d="M{},{:.1} l10,10 m0,-10 l-10,10" stroke="#d62728" stroke-width="2"/><text x="{}" y="{y:.1}" font-size="11">infeasible placement</text>"##,
            bx + 1.0,
            y - 9.0,
            bx + 16.0
        );
    }
}

/// Stacked bars: one bar per category, `parts` (name, one value per category) stacked; positive
/// parts upward from 0, negative ones downward. A legend names the parts.
pub(crate) fn stacked_bars(
    f: &Frame,
    categories: &[String],
    parts: &[(String, Vec<f64>)],
) -> String {
    let nc = categories.len().max(1);
    let (mut lo, mut hi) = (0.0f64, 0.0f64);
    for c in 0..nc {
        let (mut p, mut m) = (0.0, 0.0);
        for (_, v) in parts {
            let x = v.get(c).copied().unwrap_or(0.0);
            if x.is_finite() {
                if x >= 0.0 {
                    p += x
                } else {
                    m += x
                }
            }
        }
        hi = hi.max(p);
        lo = lo.min(m);
    }
    if hi - lo <= 0.0 {
        hi = 1.0;
    }
    let names: Vec<&str> = parts.iter().map(|p| p.0.as_str()).collect();
    let mut a = Axes::new(f, (0.0, nc as f64), (lo, hi * 1.05));
    a.px1 -= legend_width(&names);
    let slot = (a.px1 - a.px0) / nc as f64;
    let bw = (slot * 0.6).min(90.0);
    let mut s = open(f);
    y_axis(&mut s, &a, true);
    let mut n = 0;
    for (c, name) in categories.iter().enumerate() {
        let x = a.px0 + slot * (c as f64 + 0.5) - bw / 2.0;
        let (mut up, mut down) = (0.0, 0.0);
        for (g, (pn, v)) in parts.iter().enumerate() {
            let val = v.get(c).copied().unwrap_or(f64::NAN);
            if !val.is_finite() || val == 0.0 {
                continue;
            }
            let (b0, b1) = if val > 0.0 {
                up += val;
                (up - val, up)
            } else {
                down += val;
                (down - val, down)
            };
            n += 1;
            let _ = write!(
                s,
                r#"<rect x="{x:.1}" y="{:.1}" width="{bw:.1}" height="{:.1}" fill="{}"><title>{}, {}: {} </title></rect>"#,
                a.y(b0.max(b1)),
                (a.y(b0) - a.y(b1)).abs(),
                colour(g),
                esc(name),
                esc(pn),
                fmt_num(val)
            );
        }
        let _ = write!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text><text x="{:.1}" y="{:.1}" text-anchor="middle" font-size="10">{}</text>"#,
            x + bw / 2.0,
            a.py0 + 16.0,
            esc(name),
            x + bw / 2.0,
            a.y(up) - 4.0,
            fmt_num(up + down)
        );
    }
    legend(&mut s, f, &names);
    axis_labels(&mut s, f);
    finish(s, n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_cover_range() {
        let t = ticks(0.0, 10.0, 5);
        assert_eq!(t.first(), Some(&0.0));
        assert_eq!(t.last(), Some(&10.0));
    }

    #[test]
    fn charts_are_balanced_and_skip_nan() {
        let f = Frame::new("t <1>", "x [s]", "y [W]");
        let l = line_chart(
            &f,
            &[Series::new("a", &[0.0, 1.0, 2.0], &[1.0, f64::NAN, 3.0])],
        );
        assert!(l.starts_with("<svg") && l.ends_with("</svg>"));
        assert!(!l.contains("NaN"));
        assert!(l.contains("t &lt;1&gt;"));
        let b = bar_chart(&f, &["P1".into()], &[("E".into(), vec![2.0])]);
        assert!(b.contains("<rect"));
        let h = heatmap(
            &f,
            &Heatmap {
                xs: vec![0.0, 1.0],
                ys: vec![0.0],
                values: vec![1.0, f64::NAN],
                marks: vec![CellMark {
                    col: 1,
                    row: 0,
                    class: "unreachable".into(),
                    at: None,
                }],
                value_label: "J".into(),
            },
        );
        assert!(h.contains("mark-unreachable") && !h.contains("NaN"));
    }
}
