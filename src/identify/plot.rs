//! Minimal SVG charts for the identification reports (line charts, scatter plots): no
//! dependency, no physics. Written here because the shared `report::svg` module was not yet
//! available on this branch.

const W: f64 = 640.0;
const H: f64 = 260.0;
const L: f64 = 60.0;
const B: f64 = 36.0;
const COLORS: [&str; 4] = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"];

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

fn range(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (a, b) = v
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
    if !a.is_finite() {
        (0.0, 1.0)
    } else if b - a < 1e-12 {
        (a - 1.0, b + 1.0)
    } else {
        (a, b)
    }
}

fn frame(title: &str, xl: &str, yl: &str, xr: (f64, f64), yr: (f64, f64)) -> String {
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{W}\" height=\"{H}\" font-family=\"sans-serif\" font-size=\"11\">\
<rect width=\"{W}\" height=\"{H}\" fill=\"white\"/>\
<text x=\"{}\" y=\"14\" text-anchor=\"middle\" font-size=\"13\">{}</text>\
<rect x=\"{L}\" y=\"22\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#888\"/>\
<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\
<text x=\"12\" y=\"{}\" transform=\"rotate(-90 12 {})\" text-anchor=\"middle\">{}</text>\
<text x=\"{L}\" y=\"{}\">{:.4}</text><text x=\"{}\" y=\"{}\" text-anchor=\"end\">{:.4}</text>\
<text x=\"{}\" y=\"32\" text-anchor=\"end\">{:.4}</text><text x=\"{}\" y=\"{}\" text-anchor=\"end\">{:.4}</text>",
        W / 2.0,
        esc(title),
        W - L - 10.0,
        H - 22.0 - B,
        L + (W - L - 10.0) / 2.0,
        H - 4.0,
        esc(xl),
        (H - B) / 2.0,
        (H - B) / 2.0,
        esc(yl),
        H - B + 14.0,
        xr.0,
        W - 10.0,
        H - B + 14.0,
        xr.1,
        L - 3.0,
        yr.1,
        L - 3.0,
        H - B,
        yr.0
    )
}

fn map(x: f64, y: f64, xr: (f64, f64), yr: (f64, f64)) -> (f64, f64) {
    (
        L + (x - xr.0) / (xr.1 - xr.0) * (W - L - 10.0),
        H - B - (y - yr.0) / (yr.1 - yr.0) * (H - 22.0 - B),
    )
}

/// A line chart of series `(label, x, y)` sharing axes; at most ~2000 points per series drawn.
pub fn line_chart(title: &str, xl: &str, yl: &str, series: &[(&str, &[f64], &[f64])]) -> String {
    let xr = range(series.iter().flat_map(|s| s.1.iter().copied()));
    let yr = range(series.iter().flat_map(|s| s.2.iter().copied()));
    let mut s = frame(title, xl, yl, xr, yr);
    for (i, (label, x, y)) in series.iter().enumerate() {
        let step = (x.len() / 2000).max(1);
        let pts: Vec<String> = x
            .iter()
            .zip(y.iter())
            .step_by(step)
            .map(|(a, b)| {
                let (u, v) = map(*a, *b, xr, yr);
                format!("{u:.1},{v:.1}")
            })
            .collect();
        let c = COLORS[i % COLORS.len()];
        s.push_str(&format!(
            "<polyline fill=\"none\" stroke=\"{c}\" stroke-width=\"1\" points=\"{}\"/>\
<text x=\"{}\" y=\"{}\" fill=\"{c}\">{}</text>",
            pts.join(" "),
            L + 8.0 + 110.0 * i as f64,
            36.0,
            esc(label)
        ));
    }
    s.push_str("</svg>");
    s
}

/// A scatter plot of `(x, y)` (at most ~1500 points drawn).
pub fn scatter(title: &str, xl: &str, yl: &str, x: &[f64], y: &[f64]) -> String {
    let xr = range(x.iter().copied());
    let yr = range(y.iter().copied());
    let mut s = frame(title, xl, yl, xr, yr);
    let step = (x.len() / 1500).max(1);
    for (a, b) in x.iter().zip(y).step_by(step) {
        let (u, v) = map(*a, *b, xr, yr);
        s.push_str(&format!(
            "<circle cx=\"{u:.1}\" cy=\"{v:.1}\" r=\"1.5\" fill=\"{}\" fill-opacity=\"0.5\"/>",
            COLORS[0]
        ));
    }
    s.push_str("</svg>");
    s
}

/// A bar chart with one bar per label (e.g. the error ladder), values ≥ 0.
pub fn bar_chart(title: &str, yl: &str, labels: &[String], values: &[f64]) -> String {
    let ymax = values.iter().cloned().fold(0.0, f64::max).max(1e-12) * 1.1;
    let mut s = frame(title, "", yl, (0.0, labels.len() as f64), (0.0, ymax));
    let bw = (W - L - 10.0) / labels.len().max(1) as f64;
    for (i, (l, v)) in labels.iter().zip(values).enumerate() {
        let (x0, y0) = map(i as f64, *v, (0.0, labels.len() as f64), (0.0, ymax));
        let hgt = H - B - y0;
        s.push_str(&format!(
            "<rect x=\"{:.1}\" y=\"{y0:.1}\" width=\"{:.1}\" height=\"{hgt:.1}\" fill=\"{}\"/>\
<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{:.4}</text>\
<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>",
            x0 + 0.15 * bw,
            0.7 * bw,
            COLORS[0],
            x0 + 0.5 * bw,
            y0 - 3.0,
            v,
            x0 + 0.5 * bw,
            H - B + 26.0,
            esc(l)
        ));
    }
    s.push_str("</svg>");
    s
}
