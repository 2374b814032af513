//! Fast elementary functions for the per-sample hot loop (IK, forward kinematics, RNEA,
//! feasibility measures, friction): `sin`/`cos`, `atan2`, `acos` and `tanh`, each a few ulp
//! from the libm result, without libm's call overhead (glibc's `sin`/`cos` save and restore
//! the rounding mode on every call: measured 15 % of a placement evaluation).
//!
//! # Stated error bounds (checked densely against libm by `tests/fastmath.rs`)
//!
//! With `u(y)` the spacing of doubles at `|y|` (1 ulp):
//!
//! | function | domain of the fast path | stated bound on `|fast − libm|` | measured (tests) |
//! |---|---|---|---|
//! | [`sin_cos`], [`sin`], [`cos`] | `|x| ≤` [`SIN_COS_MAX`] (64 rad ≈ 20π) | `2 u(y) + 1e-24` | 1 ulp |
//! | [`atan2`] | `0 < max(|x|, |y|) ≤ 1e300`, both finite | `2 u(y)` | 1 ulp |
//! | [`acos`] | `|x| ≤ 1` | `3 u(y)` | 2 ulp |
//! | [`tanh`] | `|x| ≥ 20` (±1, identical to libm); libm below | `0` | 0 |
//!
//! Outside the domain (and for NaN, infinities, `atan2(±0, ±0)`) each function returns libm's
//! answer. The absolute term of `sin_cos` is the argument reduction's: `x − k π/2` is formed
//! with a 2-part π/2 (33 + 53 bits; Cody and Waite 1980) whose error, times `k ≤ 41`, stays
//! below 1e-24 rad: relative accuracy is kept down to results of ~1e-8, far below anything a
//! joint angle or a torque is compared with.
//!
//! The kernels are fdlibm's (Sun Microsystems, 1993; as in musl and Rust's `libm` crate):
//! `__kernel_sin`/`__kernel_cos` (degree-13/14 polynomials on `|r| ≤ π/4`, error < 2⁻⁵⁸ relative
//! before rounding) and `atan`'s degree-22 polynomial on `|t| ≤ 7/16` after reduction by
//! `atan(½)`, `atan(1)`. `acos(x) = atan2(√((1−x)(1+x)), x)`.
//!
//! The results are plain IEEE double arithmetic without fused multiply-add, so they are the
//! same on every x86-64 and aarch64 machine and for any thread count.
//!
//! # The libm switch
//!
//! [`set_libm`]`(true)` makes every function here return libm's result (process-wide; a
//! relaxed atomic load per call). Benchmarks use it to measure the before/after in one run
//! (`benches/placement.rs`); tests use it to compare whole evaluations. The default is the
//! fast path.

use std::f64::consts::{FRAC_2_PI, PI};
use std::sync::atomic::{AtomicBool, Ordering};

static USE_LIBM: AtomicBool = AtomicBool::new(false);

/// Route every function of this module to libm (`true`) or to the fast path (`false`, the
/// default). Process-wide; meant for benchmarks and A/B checks, not for normal use.
pub fn set_libm(on: bool) {
    USE_LIBM.store(on, Ordering::Relaxed);
}

/// Whether the functions of this module currently return libm's results.
#[inline(always)]
pub fn libm_selected() -> bool {
    USE_LIBM.load(Ordering::Relaxed)
}

/// Largest `|x|` (rad) that [`sin_cos`] reduces itself; beyond it, libm.
pub const SIN_COS_MAX: f64 = 64.0;

/// π/2 to 33 bits (its low 20 bits are zero, so `k · PIO2_1` is exact for `|k| < 2²⁰`).
const PIO2_1: f64 = 1.570_796_326_734_125_614_17e+00; // 0x3FF921FB, 0x54400000
/// π/2 − [`PIO2_1`].
const PIO2_1T: f64 = 6.077_100_506_506_192_249_32e-11; // 0x3DD0B461, 0x1A626331
/// 1.5 · 2⁵²: adding and subtracting it rounds to the nearest integer (|v| < 2⁵¹).
const ROUND_MAGIC: f64 = 6_755_399_441_055_744.0;

const S1: f64 = -1.666_666_666_666_663_243_48e-01;
const S2: f64 = 8.333_333_333_322_489_461_24e-03;
const S3: f64 = -1.984_126_982_985_794_931_34e-04;
const S4: f64 = 2.755_731_370_707_006_767_89e-06;
const S5: f64 = -2.505_076_025_340_686_341_95e-08;
const S6: f64 = 1.589_690_995_211_550_102_21e-10;

const C1: f64 = 4.166_666_666_666_660_190_37e-02;
const C2: f64 = -1.388_888_888_887_410_957_49e-03;
const C3: f64 = 2.480_158_728_947_672_941_78e-05;
const C4: f64 = -2.755_731_435_139_066_330_35e-07;
const C5: f64 = 2.087_572_321_298_174_827_90e-09;
const C6: f64 = -1.135_964_755_778_819_482_65e-11;

/// fdlibm `__kernel_sin(r, 0, 0)`: sin r for |r| ≤ π/4.
#[inline(always)]
fn k_sin(r: f64) -> f64 {
    let z = r * r;
    let v = z * r;
    let p = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    r + v * (S1 + z * p)
}

/// fdlibm `__kernel_cos(r, 0)`: cos r for |r| ≤ π/4.
#[inline(always)]
fn k_cos(r: f64) -> f64 {
    let z = r * r;
    let p = z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + (((1.0 - w) - hz) + z * p)
}

/// `(sin x, cos x)`; see the module docs for the error bound. `x` in rad.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    // `!(a <= b)` is also true for NaN.
    if libm_selected() || !(x.abs() <= SIN_COS_MAX) {
        return x.sin_cos();
    }
    if x.abs() < 7.450_580_596_923_828e-9 {
        // |x| < 2⁻²⁷: sin x = x and cos x = 1 to rounding (keeps the sign of −0).
        return (x, 1.0);
    }
    let t = x * FRAC_2_PI + ROUND_MAGIC;
    let quadrant = t.to_bits() & 3;
    let k = t - ROUND_MAGIC;
    // Exact (Sterbenz) then one rounding; |r| ≤ π/4 + tiny.
    let r = (x - k * PIO2_1) - k * PIO2_1T;
    let (s, c) = (k_sin(r), k_cos(r));
    match quadrant {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// `sin x` (rad); see [`sin_cos`].
#[inline]
pub fn sin(x: f64) -> f64 {
    sin_cos(x).0
}

/// `cos x` (rad); see [`sin_cos`].
#[inline]
pub fn cos(x: f64) -> f64 {
    sin_cos(x).1
}

const ATANHI: [f64; 2] = [
    4.636_476_090_008_060_935_15e-01, // atan(0.5) hi
    7.853_981_633_974_482_789_99e-01, // atan(1.0) hi
];
const ATANLO: [f64; 2] = [
    2.269_877_745_296_168_709_24e-17, // atan(0.5) lo
    3.061_616_997_868_383_017_93e-17, // atan(1.0) lo
];
const AT: [f64; 11] = [
    3.333_333_333_333_293_180_27e-01,
    -1.999_999_999_987_648_324_76e-01,
    1.428_571_427_250_346_637_11e-01,
    -1.111_111_040_546_235_578_80e-01,
    9.090_887_133_436_506_561_96e-02,
    -7.691_876_205_044_829_994_95e-02,
    6.661_073_137_387_531_206_69e-02,
    -5.833_570_133_790_573_486_45e-02,
    4.976_877_994_615_932_360_17e-02,
    -3.653_157_274_421_691_552_70e-02,
    1.628_582_011_536_578_236_23e-02,
];
const PIO2_HI: f64 = 1.570_796_326_794_896_558_00e+00;
const PIO2_LO: f64 = 6.123_233_995_736_766_035_87e-17;
const PI_LO: f64 = 1.224_646_799_147_353_207_17e-16;

/// `atan(n/d)` for `0 ≤ n ≤ d`, `d > 0` (fdlibm's reduction restricted to `[0, 1]`).
#[inline(always)]
fn atan_unit(n: f64, d: f64) -> f64 {
    // Reduce t = n/d ∈ [0, 1] to |z| ≤ 7/16 with one division.
    let (z, id) = if n < 0.4375 * d {
        (n / d, None)
    } else if n < 0.6875 * d {
        // atan(t) = atan(½) + atan((2t − 1)/(2 + t))
        ((2.0 * n - d) / (2.0 * d + n), Some(0))
    } else {
        // atan(t) = atan(1) + atan((t − 1)/(t + 1))
        ((n - d) / (n + d), Some(1))
    };
    let z2 = z * z;
    let w = z2 * z2;
    let s1 = z2 * (AT[0] + w * (AT[2] + w * (AT[4] + w * (AT[6] + w * (AT[8] + w * AT[10])))));
    let s2 = w * (AT[1] + w * (AT[3] + w * (AT[5] + w * (AT[7] + w * AT[9]))));
    match id {
        None => z - z * (s1 + s2),
        Some(i) => ATANHI[i] - ((z * (s1 + s2) - ATANLO[i]) - z),
    }
}

/// `atan2(y, x)` in (−π, π], rad; see the module docs for the error bound.
#[inline]
pub fn atan2(y: f64, x: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    let big = ax.max(ay);
    // Zero, non-finite or huge operands (and NaN): libm.
    if libm_selected() || !(big > 0.0 && big <= 1e300) {
        return y.atan2(x);
    }
    let swap = ay > ax;
    let (n, d) = if swap { (ax, ay) } else { (ay, ax) };
    let mut r = atan_unit(n, d);
    if swap {
        r = (PIO2_HI - r) + PIO2_LO;
    }
    if x.is_sign_negative() {
        r = (PI - r) + PI_LO;
    }
    r.copysign(y)
}

/// `acos x` in [0, π], rad, for `|x| ≤ 1` (libm otherwise); see the module docs.
#[inline]
pub fn acos(x: f64) -> f64 {
    if libm_selected() || !(x.abs() <= 1.0) {
        return x.acos();
    }
    atan2(((1.0 - x) * (1.0 + x)).sqrt(), x)
}

/// `tanh x`: ±1 for `|x| ≥ 20`, where libm's result rounds to ±1 as well (`1 − tanh 20 ≈
/// 8.5e-18` is below half an ulp of 1), libm below. The smoothed Coulomb sign `tanh(q̇/ε)`
/// with ε = 1e-3 rad/s is in this range whenever `|q̇| ≥ 0.02 rad/s`.
#[inline]
pub fn tanh(x: f64) -> f64 {
    if x.abs() >= 20.0 {
        1.0f64.copysign(x)
    } else {
        x.tanh()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadrant_boundaries_and_signs() {
        for &x in &[
            0.0,
            -0.0,
            1e-300,
            PI / 4.0,
            PI / 2.0,
            PI,
            -PI,
            3.0 * PI / 2.0,
            40.0,
        ] {
            let (s, c) = sin_cos(x);
            assert!((s - x.sin()).abs() <= 4.0 * f64::EPSILON, "sin {x}");
            assert!((c - x.cos()).abs() <= 4.0 * f64::EPSILON, "cos {x}");
        }
        assert_eq!(sin_cos(-0.0).0.to_bits(), (-0.0f64).to_bits());
        assert_eq!(atan2(0.0, -1.0), PI);
        assert_eq!(atan2(-0.0, -1.0), -PI);
        assert_eq!(atan2(-0.0, 1.0).to_bits(), (-0.0f64).to_bits());
        assert_eq!(acos(1.0), 0.0);
        assert_eq!(tanh(-25.0), -1.0);
    }
}
