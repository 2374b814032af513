//! A slicer-style multi-layer wall as G-code text (shared by tests/reduce.rs and
//! benches/layers.rs; generated in code, never committed): a `length_mm` × `width_mm`
//! rectangular outline (nozzle centreline, centred on the part origin), `layers` layers of
//! `dz_mm`, the seam alternating between two corners (period 2), retract, z hop of 10 mm and
//! travel between layers, print F9000 (150 mm/s), travel F12000 (200 mm/s).

/// The G-code of the wall (mm, mm/min).
pub fn wall_gcode(length_mm: f64, width_mm: f64, dz_mm: f64, layers: usize) -> String {
    let (a, b) = (length_mm / 2.0, width_mm / 2.0);
    let corners = [(-a, -b), (a, -b), (a, b), (-a, b)];
    let mut t = String::from("; generated wall (tests/common/wall.rs)\nM82\nG21\nG90\n");
    let mut e = 0.0;
    for k in 0..layers {
        let z = dz_mm * (k + 1) as f64;
        let s = if k % 2 == 0 { 0 } else { 2 };
        let order: Vec<(f64, f64)> = (0..5).map(|i| corners[(s + i) % 4]).collect();
        let (x0, y0) = order[0];
        if k == 0 {
            t += &format!("G0 F12000 X{x0:.4} Y{y0:.4} Z{z:.4}\n");
        } else {
            t += &format!("G1 F2400 E{:.5}\n", e - 5.0);
            t += &format!(
                "G0 F12000 Z{:.4}\nG0 X{x0:.4} Y{y0:.4}\nG0 Z{z:.4}\n",
                z + 10.0
            );
            t += &format!("G1 F2400 E{e:.5}\n");
        }
        for (i, w) in order.windows(2).enumerate() {
            let ((px, py), (x, y)) = (w[0], w[1]);
            e += 0.05 * ((x - px).hypot(y - py));
            let f = if i == 0 { "F9000 " } else { "" };
            t += &format!("G1 {f}X{x:.4} Y{y:.4} E{e:.5}\n");
        }
    }
    t += &format!(
        "G1 F2400 E{:.5}\nG0 F12000 Z{:.4}\n",
        e - 5.0,
        dz_mm * layers as f64 + 50.0
    );
    t
}
