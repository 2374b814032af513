//! The one place printwatt integrates and differentiates sampled signals.
//!
//! - Integration: the trapezoidal rule `∫ y dt ≈ Σ ½ (t[k] − t[k−1]) (y[k−1] + y[k])`
//!   ([`trapezoid`], over a column of a row-major array with [`trapezoid_column`], as a running
//!   sum with [`cumulative_trapezoid`], and as per-sample weights on a uniform grid with
//!   [`trapezoid_weight`]). Units: those of `y` times those of `t` (W and s give J).
//! - Differentiation: the derivative of the quadratic through three neighbouring samples
//!   (Lagrange form) with [`differentiate`]: on a uniform grid it is the second-order central
//!   difference; it handles non-uniform steps; the first and last samples use the one-sided
//!   windows (0, 1, 2) and (N−3, N−2, N−1). [`third_derivative_uniform`] adds the jerk on a
//!   uniform grid. For noisy measurements, [`smooth_differentiate`] fits a local cubic over a
//!   wider window before differentiating (Savitzky–Golay on non-uniform time stamps).
//!   Units: those of `q` per second (q̇) and per second squared (q̈) when `t` is in s.
//!
//! Signals with several channels are row-major `len × n` (`q[k * n + j]`: sample `k`,
//! channel `j`).

use crate::error::{Error, Result};

/// The sample times of a signal: a uniform grid (step in s) or explicit times (s, strictly
/// increasing).
#[derive(Clone, Copy, Debug)]
pub enum Grid<'a> {
    /// `len` samples at `t_k = k · dt` (dt in s, > 0).
    Uniform {
        /// Step, s.
        dt: f64,
        /// Number of samples.
        len: usize,
    },
    /// Explicit sample times, s.
    Times(&'a [f64]),
}

impl Grid<'_> {
    /// Number of samples.
    pub fn len(&self) -> usize {
        match self {
            Grid::Uniform { len, .. } => *len,
            Grid::Times(t) => t.len(),
        }
    }

    /// Whether the grid has no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Time of sample `k`, s.
    #[inline]
    pub fn t(&self, k: usize) -> f64 {
        match self {
            Grid::Uniform { dt, .. } => k as f64 * dt,
            Grid::Times(t) => t[k],
        }
    }
}

/// Trapezoidal `∫ y dt` over samples `y` at times `t` (s); units of `y` × s. Fewer than two
/// samples integrate to 0. Extra samples of the longer slice are ignored.
pub fn trapezoid(t: &[f64], y: &[f64]) -> f64 {
    trapezoid_by(t, |k| y[k], t.len().min(y.len()))
}

/// The trapezoidal rule over the first `len` samples, the value of sample `k` given by `y(k)`.
fn trapezoid_by(t: &[f64], y: impl Fn(usize) -> f64, len: usize) -> f64 {
    (1..len)
        .map(|k| 0.5 * (t[k] - t[k - 1]) * (y(k - 1) + y(k)))
        .sum()
}

/// Running trapezoidal integral: `out[k] = ∫_{t_0}^{t_k} y dt` (units of `y` × s; `out[0] = 0`).
pub(crate) fn cumulative_trapezoid(t: &[f64], y: &[f64]) -> Vec<f64> {
    let len = t.len().min(y.len());
    let mut out = Vec::with_capacity(len);
    let mut acc = 0.0;
    for k in 0..len {
        if k > 0 {
            acc += 0.5 * (y[k] + y[k - 1]) * (t[k] - t[k - 1]);
        }
        out.push(acc);
    }
    out
}

/// Weight (s) of sample `k` of `m` uniform samples `dt` (s) apart in the trapezoidal rule:
/// `dt / 2` at the ends, `dt` inside, so that `Σ_k w_k y_k` is [`trapezoid`] on that grid
/// (summed in sample order: what a loop that cannot keep the samples uses).
#[inline]
pub fn trapezoid_weight(k: usize, m: usize, dt: f64) -> f64 {
    if k == 0 || k + 1 == m {
        0.5 * dt
    } else {
        dt
    }
}

/// First and second derivatives (row-major `len × n`, units of `q` per s and per s²) of the
/// samples `q` (row-major `len × n`) on `grid`: the quadratic through samples (k−1, k, k+1),
/// differentiated at `t_k` (see the module docs). Two samples: constant velocity, zero
/// acceleration; one or none: zeros.
///
/// Errors: [`Error::SizeMismatch`] if `q` is not `len × n`; [`Error::Invalid`] if the times
/// are not strictly increasing (naming the sample) or a uniform step is not positive.
pub fn differentiate(grid: Grid<'_>, q: &[f64], n: usize) -> Result<(Vec<f64>, Vec<f64>)> {
    let len = grid.len();
    if q.len() != len * n {
        return Err(Error::SizeMismatch {
            what: "differentiate: samples × channels".into(),
            got: q.len(),
            expected: len * n,
        });
    }
    match grid {
        Grid::Uniform { dt, .. } if !(dt > 0.0 && dt.is_finite()) => {
            return Err(Error::Invalid(format!(
                "differentiate: the sample step {dt} s is not a positive number"
            )))
        }
        Grid::Times(t) => {
            if let Some(k) = t
                .windows(2)
                .position(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
            {
                return Err(Error::Invalid(format!(
                    "differentiate: time is not strictly increasing at sample {}",
                    k + 1
                )));
            }
        }
        _ => {}
    }
    let mut qd = vec![0.0; len * n];
    let mut qdd = vec![0.0; len * n];
    fill_derivatives(grid, q, n, &mut qd, &mut qdd);
    Ok((qd, qdd))
}

/// `v` resized to `len` (new entries 0) with its capacity grown to `len` exactly, not
/// doubled: per-sample buffers of a long path are hundreds of megabytes.
pub(crate) fn resize_exact(v: &mut Vec<f64>, len: usize) {
    v.reserve_exact(len.saturating_sub(v.len()));
    v.resize(len, 0.0);
}

/// [`differentiate_uniform_into`] on the instruction-set level `level`
/// ([`crate::simd::Level`]): [`crate::simd::Level::Scalar`] runs the per-sample formulas
/// sample by sample and channel by channel (the reference); every other level computes the
/// interior samples row by row as one three-point stencil over the row-major array (sample
/// `k` channel `j` is entry `k n + j`, its neighbours `± n` entries away), vectorised for the
/// level. Each entry takes the same operations in the same order, so every level gives the
/// reference's values bit for bit. Every entry is written, so the buffers are not cleared
/// first (a reused buffer of the right length is not zeroed).
pub(crate) fn differentiate_uniform_into_on(
    q: &[f64],
    n: usize,
    dt: f64,
    qd: &mut Vec<f64>,
    qdd: &mut Vec<f64>,
    level: crate::simd::Level,
) {
    let len = q.len().checked_div(n).unwrap_or(0);
    // Exactly what is needed: a reused buffer a little short (a re-planned, longer path)
    // would otherwise double.
    resize_exact(qd, len * n);
    resize_exact(qdd, len * n);
    let q = &q[..len * n];
    let valid = dt > 0.0 && dt.is_finite();
    if !valid || len < 3 {
        // Not every entry is written below (two samples: no acceleration).
        qd.fill(0.0);
        qdd.fill(0.0);
        if valid {
            fill_derivatives(Grid::Uniform { dt, len }, q, n, qd, qdd);
        }
        return;
    }
    if level == crate::simd::Level::Scalar {
        fill_derivatives(Grid::Uniform { dt, len }, q, n, qd, qdd);
        return;
    }
    let w = uniform_weights(dt);
    uniform_end_rows(q, n, &w, qd, qdd);
    // Interior samples 1 ..= len − 2: entry i from entries i − n, i, i + n.
    uniform_stencil_entries_on(q, n, w[1], n..(len - 1) * n, qd, qdd, level);
}

/// The first and last samples of [`differentiate_uniform_into_on`] (one-sided windows, as
/// `fill_derivatives` computes them): `q` row-major `len × n` with `len ≥ 3`, `w` from
/// [`uniform_weights`], `qd` and `qdd` of length `len × n` (units of `q` per s, per s²).
pub(crate) fn uniform_end_rows(
    q: &[f64],
    n: usize,
    w: &[([f64; 3], [f64; 3]); 3],
    qd: &mut [f64],
    qdd: &mut [f64],
) {
    let len = qd.len() / n;
    for (k, c, (d1, d2)) in [(0, 1, w[0]), (len - 1, len - 2, w[2])] {
        for j in 0..n {
            let f = [q[(c - 1) * n + j], q[c * n + j], q[(c + 1) * n + j]];
            qd[k * n + j] = d1[0] * f[0] + d1[1] * f[1] + d1[2] * f[2];
            qdd[k * n + j] = d2[0] * f[0] + d2[1] * f[1] + d2[2] * f[2];
        }
    }
}

/// The interior stencil of [`differentiate_uniform_into_on`] over the row-major entries
/// `range` (all in samples 1 ..= len − 2 of `q`, row-major `len × n`): entry `i` of `qd`
/// and `qdd` from entries `i − n`, `i`, `i + n` of `q` with the interior weights `(d1, d2)`
/// of [`uniform_weights`], vectorised for `level`, the same values bit for bit on every
/// level.
pub(crate) fn uniform_stencil_entries_on(
    q: &[f64],
    n: usize,
    (d1, d2): ([f64; 3], [f64; 3]),
    range: std::ops::Range<usize>,
    qd: &mut [f64],
    qdd: &mut [f64],
    level: crate::simd::Level,
) {
    let (a, b) = (range.start, range.end);
    if a >= b {
        return;
    }
    let (od, odd) = (&mut qd[a..b], &mut qdd[a..b]);
    stencil_into(q, n, (d1, d2), a, od, odd, level);
}

/// [`uniform_stencil_entries_on`] of the entries `a .. a + od.len()` written to `od`, `odd`
/// (entry `a` first).
fn stencil_into(
    q: &[f64],
    n: usize,
    (d1, d2): ([f64; 3], [f64; 3]),
    a: usize,
    od: &mut [f64],
    odd: &mut [f64],
    level: crate::simd::Level,
) {
    let b = a + od.len();
    let lo = &q[a - n..b - n];
    let mid = &q[a..b];
    let hi = &q[a + n..b + n];
    crate::simd::run(
        level,
        #[inline(always)]
        || stencil3(lo, mid, hi, d1, d2, od, odd),
    )
}

/// Samples `k0 .. k0 + count` of [`differentiate_uniform_into_on`]'s velocities and
/// accelerations of `q` (row-major `len × n`, `len ≥ 3`, `w` the [`uniform_weights`] of a
/// step `dt` > 0 finite) written to `qd`, `qdd` (at least `count × n` each, sample `k0`
/// first): the same values bit for bit, for a consumer that takes the rates of a long path a
/// block at a time instead of keeping them (the weights found once, not per block).
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
pub(crate) fn uniform_rates_rows(
    q: &[f64],
    n: usize,
    w: &[([f64; 3], [f64; 3]); 3],
    k0: usize,
    count: usize,
    qd: &mut [f64],
    qdd: &mut [f64],
    level: crate::simd::Level,
) {
    let len = q.len() / n;
    let end = k0 + count;
    let end_row =
        |k: usize, c: usize, (d1, d2): ([f64; 3], [f64; 3]), qd: &mut [f64], qdd: &mut [f64]| {
            let o = (k - k0) * n;
            for j in 0..n {
                let f = [q[(c - 1) * n + j], q[c * n + j], q[(c + 1) * n + j]];
                qd[o + j] = d1[0] * f[0] + d1[1] * f[1] + d1[2] * f[2];
                qdd[o + j] = d2[0] * f[0] + d2[1] * f[1] + d2[2] * f[2];
            }
        };
    if k0 == 0 && count > 0 {
        end_row(0, 1, w[0], qd, qdd);
    }
    let (a, b) = (k0.max(1), end.min(len - 1));
    if a < b {
        let o = (a - k0) * n;
        let (od, odd) = (&mut qd[o..o + (b - a) * n], &mut qdd[o..o + (b - a) * n]);
        stencil_into(q, n, w[1], a * n, od, odd, level);
    }
    if end == len && count > 0 {
        end_row(len - 1, len - 2, w[2], qd, qdd);
    }
}

/// `od[i] = d1·(lo, mid, hi)[i]` and `odd[i] = d2·(…)[i]`, each as `w0·a + w1·b + w2·c`
/// evaluated left to right (fill_derivatives' expression).
#[inline(always)]
fn stencil3(
    lo: &[f64],
    mid: &[f64],
    hi: &[f64],
    d1: [f64; 3],
    d2: [f64; 3],
    od: &mut [f64],
    odd: &mut [f64],
) {
    let it = od
        .iter_mut()
        .zip(odd.iter_mut())
        .zip(lo.iter().zip(mid).zip(hi));
    for ((v, a), ((&f0, &f1), &f2)) in it {
        *v = d1[0] * f0 + d1[1] * f1 + d1[2] * f2;
        *a = d2[0] * f0 + d2[1] * f1 + d2[2] * f2;
    }
}

/// Lagrange basis derivatives at `x` for the nodes `ts`: `d1` (first), `d2` (second,
/// constant).
#[inline]
fn lagrange_weights(ts: [f64; 3], x: f64) -> ([f64; 3], [f64; 3]) {
    let mut d1 = [0.0; 3];
    let mut d2 = [0.0; 3];
    for a in 0..3 {
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        let den = (ts[a] - ts[b]) * (ts[a] - ts[c]);
        d1[a] = ((x - ts[b]) + (x - ts[c])) / den;
        d2[a] = 2.0 / den;
    }
    (d1, d2)
}

/// On a uniform grid (`dt` s) the weights depend only on where the sample sits in its
/// window: the first sample, an interior one, the last.
#[allow(clippy::type_complexity)]
pub(crate) fn uniform_weights(dt: f64) -> [([f64; 3], [f64; 3]); 3] {
    let ts = [0.0, dt, 2.0 * dt];
    [
        lagrange_weights(ts, 0.0),
        lagrange_weights(ts, dt),
        lagrange_weights(ts, 2.0 * dt),
    ]
}

/// The body of [`differentiate`]: `qd`, `qdd` zeroed and of length `len × n`, the grid
/// already checked.
fn fill_derivatives(grid: Grid<'_>, q: &[f64], n: usize, qd: &mut [f64], qdd: &mut [f64]) {
    let len = grid.len();
    if len < 2 {
        return;
    }
    if len == 2 {
        let h = grid.t(1) - grid.t(0);
        for j in 0..n {
            let v = (q[n + j] - q[j]) / h;
            qd[j] = v;
            qd[n + j] = v;
        }
        return;
    }
    // On a uniform grid the weights are computed once (see uniform_weights).
    let uniform = match grid {
        Grid::Uniform { dt, .. } => Some(uniform_weights(dt)),
        Grid::Times(_) => None,
    };
    for k in 0..len {
        let c = k.clamp(1, len - 2);
        let (d1, d2) = match &uniform {
            Some(w) => w[1 + k - c],
            None => lagrange_weights([grid.t(c - 1), grid.t(c), grid.t(c + 1)], grid.t(k)),
        };
        for j in 0..n {
            let f = [q[(c - 1) * n + j], q[c * n + j], q[(c + 1) * n + j]];
            qd[k * n + j] = d1[0] * f[0] + d1[1] * f[1] + d1[2] * f[2];
            qdd[k * n + j] = d2[0] * f[0] + d2[1] * f[1] + d2[2] * f[2];
        }
    }
}

/// Third derivative (units of `q` per s³) of samples `q` (row-major `len × n`) `dt` s apart:
/// the central difference `(q[c+2] − 2q[c+1] + 2q[c−1] − q[c−2]) / (2 dt³)` at `c = k`,
/// clamped to the interior (the two first and last samples take their neighbour's value).
/// Fewer than five samples: zeros.
pub(crate) fn third_derivative_uniform(q: &[f64], n: usize, dt: f64) -> Vec<f64> {
    let m = q.len().checked_div(n).unwrap_or(0);
    let mut out = vec![0.0; m * n];
    if m < 5 {
        return out;
    }
    for k in 0..m {
        for j in 0..n {
            out[k * n + j] = third_derivative_uniform_at(q, n, dt, k, j);
        }
    }
    out
}

/// Entry `(k, j)` of [`third_derivative_uniform`] (`q` with at least five samples), without
/// storing the others.
#[inline]
pub fn third_derivative_uniform_at(q: &[f64], n: usize, dt: f64, k: usize, j: usize) -> f64 {
    let m = q.len() / n;
    let at = |k: usize| q[k * n + j];
    let c = k.clamp(2, m - 3);
    (at(c + 2) - 2.0 * at(c + 1) + 2.0 * at(c - 1) - at(c - 2)) / (2.0 * dt * dt * dt)
}

/// Row `k` of [`smooth_differentiate`] into `qd[..n]` and `qdd[..n]` (left untouched where
/// the window's normal equations are singular, and for fewer than 4 samples): the same
/// arithmetic, so a log's derivatives can be made a block of rows at a time.
pub(crate) fn smooth_differentiate_row(
    t: &[f64],
    q: &[f64],
    n: usize,
    m: usize,
    k: usize,
    qd: &mut [f64],
    qdd: &mut [f64],
) {
    let len = t.len();
    if len < 4 || q.len() < len * n || k >= len {
        return;
    }
    let w = (2 * m + 1).min(len);
    let start = k.saturating_sub(w / 2).min(len - w);
    let idx = start..start + w;
    let t0 = t[k];
    let scale = (t[start + w - 1] - t[start]).max(1e-12);
    // Normal equations of the cubic in s = (t − t0)/scale.
    let mut a = nalgebra::Matrix4::<f64>::zeros();
    for i in idx.clone() {
        let s = (t[i] - t0) / scale;
        let p = [1.0, s, s * s, s * s * s];
        for r in 0..4 {
            for c in 0..4 {
                a[(r, c)] += p[r] * p[c];
            }
        }
    }
    let Some(inv) = a.try_inverse() else { return };
    for j in 0..n {
        let mut b = nalgebra::Vector4::<f64>::zeros();
        for i in idx.clone() {
            let s = (t[i] - t0) / scale;
            let v = q[i * n + j];
            b += nalgebra::Vector4::new(v, v * s, v * s * s, v * s * s * s);
        }
        let c = inv * b;
        qd[j] = c[1] / scale;
        qdd[j] = 2.0 * c[2] / (scale * scale);
    }
}

/// Significant digits the operands of a [`difference`] are taken to carry: those every JSON
/// number and report keeps ([`crate::output::JSON_SIGNIFICANT_DIGITS`]).
pub(crate) const OPERAND_DIGITS: i32 = crate::output::JSON_SIGNIFICANT_DIGITS as i32;

/// `a − b` (units of `a` and `b`) rounded to the digits its operands carry: to the unit of the
/// [`OPERAND_DIGITS`]-th significant digit of the larger of `|a|` and `|b|`. Two numbers equal
/// to that many digits (two sums of the same energies taken in another order, differing by
/// 2e-11 J out of 1.3e4 J) give exactly 0: "no difference", not float noise. Non-finite
/// operands give their plain difference.
pub fn difference(a: f64, b: f64) -> f64 {
    let d = a - b;
    let scale = a.abs().max(b.abs());
    if !d.is_finite() || scale == 0.0 || !scale.is_finite() {
        return d;
    }
    let unit = 10f64.powi(scale.log10().floor() as i32 - (OPERAND_DIGITS - 1));
    let r = (d / unit).round() * unit;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

/// `(a − b) / a` in % from [`difference`]: 0 where the difference is within rounding, and
/// where `a` is 0.
pub(crate) fn relative_difference_pct(a: f64, b: f64) -> f64 {
    if a == 0.0 {
        0.0
    } else {
        difference(a, b) / a * 100.0
    }
}

/// Trapezoidal `∫ y_j dt` over column `j` of a row-major `len × n` array `y` at times `t` (s).
#[cfg(test)]
pub(crate) fn trapezoid_column(t: &[f64], y: &[f64], n: usize, j: usize) -> f64 {
    let len = y.len().checked_div(n).map_or(0, |rows| t.len().min(rows));
    trapezoid_by(t, |k| y[k * n + j], len)
}

/// Smoothed first and second derivatives (units of `q` per s and per s²) of noisy samples `q`
/// (row-major `len × n`) at times `t` (s): a local cubic least-squares fit over `2m + 1`
/// samples (Savitzky–Golay on non-uniform time stamps; the window is shifted inwards at the
/// ends), differentiated at `t_k`. Fewer than four samples: zeros.
#[cfg(test)]
pub(crate) fn smooth_differentiate(
    t: &[f64],
    q: &[f64],
    n: usize,
    m: usize,
) -> (Vec<f64>, Vec<f64>) {
    let len = t.len();
    let mut qd = vec![0.0; len * n];
    let mut qdd = vec![0.0; len * n];
    for k in 0..len {
        smooth_differentiate_row(
            t,
            q,
            n,
            m,
            k,
            &mut qd[k * n..(k + 1) * n],
            &mut qdd[k * n..(k + 1) * n],
        );
    }
    (qd, qdd)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs().max(1e-300)
    }

    #[test]
    fn trapezoid_is_exact_for_a_line_and_converges_for_sine() {
        // ∫_0^2 (3t + 1) dt = 8: exact for a line, on any grid.
        let t = [0.0, 0.3, 0.35, 1.2, 2.0];
        let y: Vec<f64> = t.iter().map(|t| 3.0 * t + 1.0).collect();
        assert!(rel(trapezoid(&t, &y), 8.0) < 1e-15);
        // ∫_0^π sin t dt = 2; error π³/(12 N²) · max|sin| for N steps.
        let n = 1000;
        let t: Vec<f64> = (0..=n)
            .map(|k| std::f64::consts::PI * k as f64 / n as f64)
            .collect();
        let y: Vec<f64> = t.iter().map(|t| t.sin()).collect();
        let e = (trapezoid(&t, &y) - 2.0).abs();
        assert!(e < 2.0e-6 && e > 1.0e-7, "error {e}");
        // The column form, the running sum and the uniform weights agree with it.
        let both: Vec<f64> = y.iter().flat_map(|&v| [v, 2.0 * v]).collect();
        assert_eq!(trapezoid_column(&t, &both, 2, 0), trapezoid(&t, &y));
        assert!(rel(trapezoid_column(&t, &both, 2, 1), 4.0) < 1e-6);
        let cum = cumulative_trapezoid(&t, &y);
        assert_eq!(cum[0], 0.0);
        assert!(rel(*cum.last().unwrap(), trapezoid(&t, &y)) < 1e-14);
        let dt = t[1];
        let w: f64 = (0..=n).map(|k| trapezoid_weight(k, n + 1, dt) * y[k]).sum();
        assert!(rel(w, trapezoid(&t, &y)) < 1e-12);
        assert_eq!(trapezoid(&[1.0], &[5.0]), 0.0);
    }

    #[test]
    fn differentiate_is_exact_for_a_quadratic_on_any_grid() {
        // q = 2 t² − t + 3: q̇ = 4t − 1, q̈ = 4 at every sample, ends included.
        let t = [0.0, 0.1, 0.25, 0.3, 0.7, 1.0];
        let q: Vec<f64> = t.iter().map(|t| 2.0 * t * t - t + 3.0).collect();
        let (qd, qdd) = differentiate(Grid::Times(&t), &q, 1).unwrap();
        for k in 0..t.len() {
            assert!((qd[k] - (4.0 * t[k] - 1.0)).abs() < 1e-12, "{k}: {}", qd[k]);
            assert!((qdd[k] - 4.0).abs() < 1e-10, "{k}: {}", qdd[k]);
        }
        let dt = 0.01;
        let q: Vec<f64> = (0..20)
            .map(|k| {
                let t = k as f64 * dt;
                2.0 * t * t - t + 3.0
            })
            .collect();
        let (qd, qdd) = differentiate(Grid::Uniform { dt, len: 20 }, &q, 1).unwrap();
        for k in 0..20 {
            let t = k as f64 * dt;
            assert!((qd[k] - (4.0 * t - 1.0)).abs() < 1e-10, "{k}: {}", qd[k]);
            assert!((qdd[k] - 4.0).abs() < 1e-7, "{k}: {}", qdd[k]);
        }
    }

    #[test]
    fn differentiate_converges_at_second_order_for_sine() {
        // q = sin(ω t): q̇ = ω cos, q̈ = −ω² sin; halving the step divides the interior error
        // by about four.
        let err = |steps: usize| {
            let dt = 1.0 / steps as f64;
            let w = 3.0;
            let q: Vec<f64> = (0..=steps).map(|k| (w * k as f64 * dt).sin()).collect();
            let (qd, qdd) = differentiate(Grid::Uniform { dt, len: steps + 1 }, &q, 1).unwrap();
            let mut e = (0.0f64, 0.0f64);
            for k in 1..steps {
                let t = k as f64 * dt;
                e.0 = e.0.max((qd[k] - w * (w * t).cos()).abs());
                e.1 = e.1.max((qdd[k] + w * w * (w * t).sin()).abs());
            }
            e
        };
        let (a, b) = (err(100), err(200));
        assert!((a.0 / b.0 - 4.0).abs() < 0.1, "{a:?} {b:?}");
        assert!((a.1 / b.1 - 4.0).abs() < 0.1, "{a:?} {b:?}");
        assert!(a.0 < 2e-3 && a.1 < 5e-3, "{a:?}");
    }

    #[test]
    fn row_stencil_derivatives_equal_the_per_sample_formulas_bit_for_bit_on_every_level() {
        // Every length from 0 to 40 samples and a long one, 1 to 7 channels, steps of
        // several sizes (and a bad one), into fresh buffers and into reused ones of another
        // length holding garbage: every SIMD level writes the per-sample formulas' values
        // (the scalar level, and differentiate on the same uniform grid) to the bit.
        let mut s = 7u64;
        let mut u = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            2.0 * ((s >> 11) as f64 / (1u64 << 53) as f64) - 1.0
        };
        let levels: Vec<_> = crate::simd::Level::ALL
            .into_iter()
            .filter(|l| l.available())
            .collect();
        for n in 1..=7 {
            for len in (0..=40).chain([1001]) {
                let q: Vec<f64> = (0..len * n).map(|_| 3.0 * u()).collect();
                for dt in [0.004, 1e-3 / 3.0, 0.25, 0.0] {
                    let (mut wd, mut wdd) = (Vec::new(), Vec::new());
                    differentiate_uniform_into_on(
                        &q,
                        n,
                        dt,
                        &mut wd,
                        &mut wdd,
                        crate::simd::Level::Scalar,
                    );
                    if dt > 0.0 {
                        let (d, dd) = differentiate(Grid::Uniform { dt, len }, &q, n).unwrap();
                        assert_eq!(
                            d.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                            wd.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
                        );
                        assert_eq!(
                            dd.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                            wdd.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
                        );
                    }
                    for &level in &levels {
                        for garbage in [0usize, len * n / 2, len * n, len * n + 5] {
                            let mut qd = vec![f64::NAN; garbage];
                            let mut qdd = vec![-1.0; garbage];
                            differentiate_uniform_into_on(&q, n, dt, &mut qd, &mut qdd, level);
                            let bits =
                                |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                            assert_eq!(bits(&qd), bits(&wd), "n={n} len={len} dt={dt} {level:?}");
                            assert_eq!(bits(&qdd), bits(&wdd), "n={n} len={len} dt={dt} {level:?}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn third_derivative_of_a_cubic_is_exact() {
        // q = t³ − 2t: q⃛ = 6 everywhere.
        let dt = 0.05;
        let q: Vec<f64> = (0..12)
            .map(|k| {
                let t = k as f64 * dt;
                t * t * t - 2.0 * t
            })
            .collect();
        for v in third_derivative_uniform(&q, 1, dt) {
            assert!((v - 6.0).abs() < 1e-8, "{v}");
        }
        assert!(third_derivative_uniform(&q[..4], 1, dt)
            .iter()
            .all(|&v| v == 0.0));
    }

    #[test]
    fn smooth_differentiate_is_exact_for_a_cubic() {
        let t: Vec<f64> = (0..40)
            .map(|k| 0.004 * k as f64 + 0.0001 * (k % 3) as f64)
            .collect();
        let q: Vec<f64> = t.iter().map(|t| t * t * t - t * t + 0.5).collect();
        let (qd, qdd) = smooth_differentiate(&t, &q, 1, 5);
        for (k, t) in t.iter().enumerate() {
            assert!((qd[k] - (3.0 * t * t - 2.0 * t)).abs() < 1e-8, "{k}");
            assert!((qdd[k] - (6.0 * t - 2.0)).abs() < 1e-5, "{k}");
        }
    }

    #[test]
    fn differences_of_nearly_equal_numbers_are_rounded_to_their_operands_digits() {
        // The same energy summed in two orders: 2e-11 J apart out of 1.3e4 J is no difference.
        let a = 13_091.831_002_345;
        let b = a + 2.0e-11;
        assert_ne!(a - b, 0.0);
        assert_eq!(difference(a, b), 0.0);
        assert_eq!(
            difference(b, a).to_bits(),
            0.0f64.to_bits(),
            "no negative zero"
        );
        assert_eq!(relative_difference_pct(a, b), 0.0);
        // A real difference keeps the digits its operands carry (1e-4 J here: 9 significant
        // digits of 1.3e4 J).
        let d = difference(13091.83102, 12850.7);
        assert!((d - 241.1310).abs() < 1e-9, "{d}");
        assert!((difference(1.0, 0.75) - 0.25).abs() < 1e-15);
        // Below the operands' resolution it is 0, above it is kept.
        assert_eq!(difference(1.0e4, 1.0e4 + 4.0e-6), 0.0);
        assert!(difference(1.0e4, 1.0e4 + 2.0e-4) < 0.0);
        assert_eq!(difference(0.0, 0.0), 0.0);
        assert!(difference(f64::INFINITY, 1.0).is_infinite());
    }

    #[test]
    fn differentiate_refuses_bad_grids() {
        let e = differentiate(Grid::Times(&[0.0, 1.0, 1.0]), &[0.0; 3], 1).unwrap_err();
        assert!(e.to_string().contains("sample 2"), "{e}");
        assert!(differentiate(Grid::Times(&[0.0, 1.0]), &[0.0; 3], 1).is_err());
        assert!(differentiate(Grid::Uniform { dt: 0.0, len: 3 }, &[0.0; 3], 1).is_err());
    }
}
