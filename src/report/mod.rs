//! Writers for what people and scripts read: SVG charts ([`svg`]), HTML pages ([`html`]) and
//! the placement-run report ([`placement`]: `summary.json`, `placements.csv`, `report.html`).
//! No physics here: every number arrives computed.

pub mod html;
pub(crate) mod identify;
pub mod placement;
pub mod site;
pub mod stations;
pub mod study;
pub mod svg;
