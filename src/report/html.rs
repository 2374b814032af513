//! Minimal helpers for one self-contained HTML page: a document shell with inline CSS,
//! sections, tables and key–value lists. Text is escaped; SVG strings from
//! [`super::svg`] are inlined as they are. No physics here.

use super::svg::esc;
use std::fmt::Write as _;

/// A self-contained HTML page under construction.
#[derive(Clone, Debug, Default)]
pub struct Page {
    title: String,
    body: String,
}

impl Page {
    /// A new page with a title (shown as `<title>` and `<h1>`).
    pub fn new(title: &str) -> Self {
        Page {
            title: title.into(),
            body: String::new(),
        }
    }
    /// A second-level heading.
    pub fn h2(&mut self, text: &str) -> &mut Self {
        let _ = writeln!(self.body, "<h2>{}</h2>", esc(text));
        self
    }
    /// A paragraph of plain (escaped) text.
    pub fn p(&mut self, text: &str) -> &mut Self {
        let _ = writeln!(self.body, "<p>{}</p>", esc(text));
        self
    }
    /// Raw, already well-formed XHTML (e.g. an SVG from [`super::svg`]) inside a `<figure>`
    /// with an id and a caption.
    pub fn figure(&mut self, id: &str, svg: &str, caption: &str) -> &mut Self {
        let _ = writeln!(
            self.body,
            "<figure id=\"{}\">{}<figcaption>{}</figcaption></figure>",
            esc(id),
            svg,
            esc(caption)
        );
        self
    }
    /// Several figures side by side (wrapping on narrow pages): `(id, svg, caption)` each.
    pub fn figure_row(&mut self, figures: &[(String, String, String)]) -> &mut Self {
        self.body.push_str("<div class=\"row\">");
        for (id, svg, caption) in figures {
            self.figure(id, svg, caption);
        }
        self.body.push_str("</div>\n");
        self
    }
    /// A table (header row + rows of already formatted cells).
    pub fn table(&mut self, header: &[String], rows: &[Vec<String>]) -> &mut Self {
        self.body.push_str(&table(header, rows));
        self
    }
    /// A list of key: value lines.
    pub(crate) fn kv(&mut self, items: &[(String, String)]) -> &mut Self {
        self.body.push_str("<dl>");
        for (k, v) in items {
            let _ = write!(self.body, "<dt>{}</dt><dd>{}</dd>", esc(k), esc(v));
        }
        self.body.push_str("</dl>\n");
        self
    }
    /// A collapsed block: `summary` (escaped text) opens already well-formed XHTML `inner`
    /// (e.g. a [`table`]) on demand.
    pub fn collapsed(&mut self, summary: &str, inner: &str) -> &mut Self {
        let _ = writeln!(
            self.body,
            "<details><summary>{}</summary>{inner}</details>",
            esc(summary)
        );
        self
    }
    /// Already well-formed XHTML, inserted as it is (e.g. a table whose cells hold links, made
    /// with [`super::svg::esc`] on every text).
    pub fn raw(&mut self, xhtml: &str) -> &mut Self {
        self.body.push_str(xhtml);
        self.body.push('\n');
        self
    }
    /// Preformatted text (escaped).
    pub fn pre(&mut self, text: &str) -> &mut Self {
        let _ = writeln!(self.body, "<pre>{}</pre>", esc(text));
        self
    }
    /// The finished page: XHTML-compatible (every element closed), so it parses as XML.
    pub fn finish(&self) -> String {
        format!(
            "<!DOCTYPE html>\n<html xmlns=\"http://www.w3.org/1999/xhtml\" lang=\"en\"><head><meta charset=\"utf-8\"/><title>{t}</title><style>{CSS}</style></head><body><h1>{t}</h1>\n{b}</body></html>\n",
            t = esc(&self.title),
            b = self.body
        )
    }
}

const CSS: &str = "body{font-family:sans-serif;max-width:1100px;margin:1em auto;padding:0 1em;color:#222}\
table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #ccc;padding:2px 8px;text-align:right}\
th{background:#f3f3f3}td.t{text-align:left}figure{margin:1em 0}figcaption{font-size:0.9em;color:#555}\
dl{display:grid;grid-template-columns:max-content auto;gap:2px 12px}dt{font-weight:bold}dd{margin:0}\
.row{display:flex;flex-wrap:wrap;gap:0 12px}.row figure{margin:0.5em 0}svg{max-width:100%;height:auto}\
.answer{border:2px solid #0072B2;background:#f5faff;padding:0 1em 0.5em;margin:1em 0}.answer ul{margin:0;padding-left:1.2em}";

/// An HTML table (escaped cells).
pub fn table(header: &[String], rows: &[Vec<String>]) -> String {
    let mut s = String::from("<table><thead><tr>");
    for h in header {
        let _ = write!(s, "<th>{}</th>", esc(h));
    }
    s.push_str("</tr></thead><tbody>");
    for r in rows {
        s.push_str("<tr>");
        for c in r {
            // Text (not a number) reads better left-aligned.
            let class = if c.trim().parse::<f64>().is_ok() {
                ""
            } else {
                " class=\"t\""
            };
            let _ = write!(s, "<td{class}>{}</td>", esc(c));
        }
        s.push_str("</tr>");
    }
    s.push_str("</tbody></table>\n");
    s
}
