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
//! | [`tanh`], [`tanh_lanes`] | `|x| < 20` (polynomial; ±1 from 20 on, identical to libm) | `4 u(y)` | 3 ulp |
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
const PIO2_1: f64 = f64::from_bits(0x3FF9_21FB_5440_0000);
/// π/2 − [`PIO2_1`].
const PIO2_1T: f64 = f64::from_bits(0x3DD0_B461_1A62_6331);
/// 1.5 · 2⁵²: adding and subtracting it rounds to the nearest integer (|v| < 2⁵¹).
const ROUND_MAGIC: f64 = 6_755_399_441_055_744.0;

// fdlibm's kernel coefficients, as bit patterns (exact; the decimal forms are in musl).
const S1: f64 = f64::from_bits(0xBFC5_5555_5555_5549);
const S2: f64 = f64::from_bits(0x3F81_1111_1110_F8A6);
const S3: f64 = f64::from_bits(0xBF2A_01A0_19C1_61D5);
const S4: f64 = f64::from_bits(0x3EC7_1DE3_57B1_FE7D);
const S5: f64 = f64::from_bits(0xBE5A_E5E6_8A2B_9CEB);
const S6: f64 = f64::from_bits(0x3DE5_D93A_5ACF_D57C);

const C1: f64 = f64::from_bits(0x3FA5_5555_5555_554C);
const C2: f64 = f64::from_bits(0xBF56_C16C_16C1_5177);
const C3: f64 = f64::from_bits(0x3EFA_01A0_19CB_1590);
const C4: f64 = f64::from_bits(0xBE92_7E4F_809C_52AD);
const C5: f64 = f64::from_bits(0x3E21_EE9E_BDB4_B1C4);
const C6: f64 = f64::from_bits(0xBDA8_FAE9_BE88_38D4);

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
    if libm_selected() || x.is_nan() || x.abs() > SIN_COS_MAX {
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

/// [`sin_cos`] of [`crate::simd::LANES`] angles at once (rad), lane by lane bit-identical to
/// [`sin_cos`]: the same reduction and kernels as plain lane arithmetic, the quadrant chosen
/// by selects; lanes outside the fast path's domain (tiny, NaN, beyond [`SIN_COS_MAX`], or
/// with the libm switch on) go through [`sin_cos`] one by one. Inlined into the caller, so it
/// runs on the caller's instruction set ([`crate::simd`]).
#[inline(always)]
pub fn sin_cos_lanes(
    x: &[f64; crate::simd::LANES],
) -> ([f64; crate::simd::LANES], [f64; crate::simd::LANES]) {
    sin_cos_lanes_n(x)
}

/// [`sin_cos_lanes`] of any number `LANES` of angles (rad): the same operations per lane, so
/// lane by lane bit-identical to [`sin_cos`] (a wider call gives the vector units two or more
/// independent chains per operation, e.g. [`crate::kinematics::opw::solve_branch_pair_into`]).
#[inline(always)]
pub fn sin_cos_lanes_n<const LANES: usize>(x: &[f64; LANES]) -> ([f64; LANES], [f64; LANES]) {
    let mut s = [0.0; LANES];
    let mut c = [0.0; LANES];
    let mut special = false;
    for l in 0..LANES {
        let a = x[l].abs();
        // NaN fails the comparison: special.
        special |= !(7.450_580_596_923_828e-9..=SIN_COS_MAX).contains(&a);
        let t = x[l] * FRAC_2_PI + ROUND_MAGIC;
        let quadrant = t.to_bits() & 3;
        let k = t - ROUND_MAGIC;
        let r = (x[l] - k * PIO2_1) - k * PIO2_1T;
        let (ks, kc) = (k_sin(r), k_cos(r));
        let swap = quadrant & 1 == 1;
        let (a, b) = if swap { (kc, ks) } else { (ks, kc) };
        // quadrant 0: (s, c); 1: (c, −s); 2: (−s, −c); 3: (−c, s).
        s[l] = if quadrant & 2 != 0 { -a } else { a };
        c[l] = if (quadrant + 1) & 2 != 0 { -b } else { b };
    }
    if special || libm_selected() {
        for l in 0..LANES {
            let a = x[l].abs();
            if libm_selected() || !(7.450_580_596_923_828e-9..=SIN_COS_MAX).contains(&a) {
                (s[l], c[l]) = sin_cos(x[l]);
            }
        }
    }
    (s, c)
}

/// [`sin_cos_lanes`] with its tiny lanes (`|x| < 2⁻²⁷`, ±0 included: [`sin_cos`]'s `(x, 1)`)
/// taken by select instead of through the one-by-one path: bit for bit the same results, for
/// callers whose angles are often exactly 0 (a joint fitted onto 0 by a 2π shift). Inlined
/// into the caller, so it runs on the caller's instruction set.
#[inline(always)]
pub fn sin_cos_lanes_with_zeros(
    x: &[f64; crate::simd::LANES],
) -> ([f64; crate::simd::LANES], [f64; crate::simd::LANES]) {
    use crate::simd::LANES;
    let mut y = [0.0; LANES];
    let mut tiny = [0u64; LANES];
    for l in 0..LANES {
        tiny[l] = u64::from(x[l].abs() < 7.450_580_596_923_828e-9);
        y[l] = if tiny[l] != 0 { 1.0 } else { x[l] };
    }
    let (mut s, mut c) = sin_cos_lanes(&y);
    for l in 0..LANES {
        s[l] = if tiny[l] != 0 { x[l] } else { s[l] };
        c[l] = if tiny[l] != 0 { 1.0 } else { c[l] };
    }
    (s, c)
}

/// [`sin_cos_lanes_with_zeros`] with the tiny lanes (`|x| < 2⁻²⁷`) through the kernels
/// themselves: for them the reduction is exact (`k` = 0, `r` = `x`) and the kernels round to
/// `(x, 1)`, [`sin_cos`]'s answer, save for `−0`, whose sine the kernel makes `+0`: a select
/// keeps `x` where `x == 0`. Bit for bit the same results as [`sin_cos_lanes_with_zeros`]
/// (tests/fastmath.rs), without its two selects per lane. Inlined into the caller, so it runs
/// on the caller's instruction set.
#[allow(clippy::neg_cmp_op_on_partial_ord)] // `!(|x| <= max)`: NaN is special
#[inline(always)]
pub fn sin_cos_lanes_tiny_in_kernel(
    x: &[f64; crate::simd::LANES],
) -> ([f64; crate::simd::LANES], [f64; crate::simd::LANES]) {
    use crate::simd::LANES;
    let mut s = [0.0; LANES];
    let mut c = [0.0; LANES];
    let mut special = false;
    for l in 0..LANES {
        // NaN fails the comparison: special.
        special |= !(x[l].abs() <= SIN_COS_MAX);
        let t = x[l] * FRAC_2_PI + ROUND_MAGIC;
        let quadrant = t.to_bits() & 3;
        let k = t - ROUND_MAGIC;
        let r = (x[l] - k * PIO2_1) - k * PIO2_1T;
        let (ks, kc) = (k_sin(r), k_cos(r));
        let swap = quadrant & 1 == 1;
        let (a, b) = if swap { (kc, ks) } else { (ks, kc) };
        // quadrant 0: (s, c); 1: (c, −s); 2: (−s, −c); 3: (−c, s).
        let sl = if quadrant & 2 != 0 { -a } else { a };
        s[l] = if x[l] == 0.0 { x[l] } else { sl };
        c[l] = if (quadrant + 1) & 2 != 0 { -b } else { b };
    }
    if special || libm_selected() {
        for l in 0..LANES {
            if libm_selected() || !(x[l].abs() <= SIN_COS_MAX) {
                // As sin_cos_lanes_with_zeros: (x, 1) for the tiny lanes, also with libm.
                (s[l], c[l]) = if x[l].abs() < 7.450_580_596_923_828e-9 {
                    (x[l], 1.0)
                } else {
                    sin_cos(x[l])
                };
            }
        }
    }
    (s, c)
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
    f64::from_bits(0x3FDD_AC67_0561_BB4F), // atan(0.5) hi
    f64::from_bits(0x3FE9_21FB_5444_2D18), // atan(1.0) hi
];
const ATANLO: [f64; 2] = [
    f64::from_bits(0x3C7A_2B7F_222F_65E2), // atan(0.5) lo
    f64::from_bits(0x3C81_A626_3314_5C07), // atan(1.0) lo
];
const AT: [f64; 11] = [
    f64::from_bits(0x3FD5_5555_5555_550D),
    f64::from_bits(0xBFC9_9999_9998_EBC4),
    f64::from_bits(0x3FC2_4924_9200_83FF),
    f64::from_bits(0xBFBC_71C6_FE23_1671),
    f64::from_bits(0x3FB7_45CD_C54C_206E),
    f64::from_bits(0xBFB3_B0F2_AF74_9A6D),
    f64::from_bits(0x3FB1_0D66_A0D0_3D51),
    f64::from_bits(0xBFAD_DE2D_52DE_FD9A),
    f64::from_bits(0x3FA9_7B4B_2476_0DEB),
    f64::from_bits(0xBFA2_B444_2C6A_6C2F),
    f64::from_bits(0x3F90_AD3A_E322_DA11),
];
const PIO2_HI: f64 = f64::from_bits(0x3FF9_21FB_5444_2D18);
const PIO2_LO: f64 = f64::from_bits(0x3C91_A626_3314_5C07);
const PI_LO: f64 = f64::from_bits(0x3CA1_A626_3314_5C07);

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
    if libm_selected() || x.is_nan() || x.abs() > 1.0 {
        return x.acos();
    }
    atan2(((1.0 - x) * (1.0 + x)).sqrt(), x)
}

/// [`atan2`] of [`crate::simd::LANES`] pairs at once (rad), lane by lane bit-identical to
/// [`atan2`]: the three reductions of `atan_unit` chosen by selects before its one division,
/// the quadrant fix-ups by selects; lanes outside the fast path's domain (a zero, huge or
/// non-finite operand, or the libm switch on) go through [`atan2`] one by one. Inlined into
/// the caller, so it runs on the caller's instruction set ([`crate::simd`]).
#[inline(always)]
pub fn atan2_lanes(
    y: &[f64; crate::simd::LANES],
    x: &[f64; crate::simd::LANES],
) -> [f64; crate::simd::LANES] {
    atan2_lanes_n(y, x)
}

/// [`atan2_lanes`] of any number `LANES` of pairs: the same operations per lane, so lane by
/// lane bit-identical to [`atan2`].
#[inline(always)]
pub fn atan2_lanes_n<const LANES: usize>(y: &[f64; LANES], x: &[f64; LANES]) -> [f64; LANES] {
    let mut out = [0.0; LANES];
    let mut special = false;
    for l in 0..LANES {
        let (ax, ay) = (x[l].abs(), y[l].abs());
        let big = ax.max(ay);
        special |= !(big > 0.0 && big <= 1e300);
        let swap = ay > ax;
        let n = if swap { ax } else { ay };
        let d = if swap { ay } else { ax };
        // atan_unit's reduction: id 0 (none), 1 (atan ½), 2 (atan 1).
        let lo = n < 0.4375 * d;
        let mid = n < 0.6875 * d;
        let num = if lo {
            n
        } else if mid {
            2.0 * n - d
        } else {
            n - d
        };
        let den = if lo {
            d
        } else if mid {
            2.0 * d + n
        } else {
            n + d
        };
        let z = num / den;
        let z2 = z * z;
        let w = z2 * z2;
        let s1 = z2 * (AT[0] + w * (AT[2] + w * (AT[4] + w * (AT[6] + w * (AT[8] + w * AT[10])))));
        let s2 = w * (AT[1] + w * (AT[3] + w * (AT[5] + w * (AT[7] + w * AT[9]))));
        let hi = if mid { ATANHI[0] } else { ATANHI[1] };
        let lo_c = if mid { ATANLO[0] } else { ATANLO[1] };
        let reduced = hi - ((z * (s1 + s2) - lo_c) - z);
        let mut r = if lo { z - z * (s1 + s2) } else { reduced };
        if swap {
            r = (PIO2_HI - r) + PIO2_LO;
        }
        if x[l].is_sign_negative() {
            r = (PI - r) + PI_LO;
        }
        out[l] = r.copysign(y[l]);
    }
    if special || libm_selected() {
        for l in 0..LANES {
            let big = x[l].abs().max(y[l].abs());
            if libm_selected() || !(big > 0.0 && big <= 1e300) {
                out[l] = atan2(y[l], x[l]);
            }
        }
    }
    out
}

/// [`acos`] of [`crate::simd::LANES`] values at once, lane by lane bit-identical to
/// [`acos`] (`atan2(√((1−x)(1+x)), x)`; lanes with `|x| > 1`, NaN or the libm switch on go
/// through [`acos`]).
#[inline(always)]
pub fn acos_lanes(x: &[f64; crate::simd::LANES]) -> [f64; crate::simd::LANES] {
    acos_lanes_n(x)
}

/// [`acos_lanes`] of any number `LANES` of values: the same operations per lane, so lane by
/// lane bit-identical to [`acos`].
#[allow(clippy::neg_cmp_op_on_partial_ord)] // `!(|x| <= 1)`: NaN is special
#[inline(always)]
pub fn acos_lanes_n<const LANES: usize>(x: &[f64; LANES]) -> [f64; LANES] {
    let mut y = [0.0; LANES];
    let mut special = false;
    for l in 0..LANES {
        // `|`, not `||`: one vector compare for all lanes (NaN fails `<=`: special).
        special |= !(x[l].abs() <= 1.0);
        y[l] = ((1.0 - x[l]) * (1.0 + x[l])).sqrt();
    }
    let mut out = atan2_lanes_n(&y, x);
    if special || libm_selected() {
        for l in 0..LANES {
            if libm_selected() || x[l].is_nan() || x[l].abs() > 1.0 {
                out[l] = acos(x[l]);
            }
        }
    }
    out
}

/// Largest `|x|` below which [`tanh`] evaluates its polynomial; from it on, ±1 (where libm's
/// result rounds to ±1 as well: `1 − tanh 20 ≈ 8.5e-18` is below half an ulp of 1).
pub(crate) const TANH_SATURATED: f64 = 20.0;

/// ln 2 to 32 bits (fdlibm's `ln2_hi`: its low 21 bits are zero, so `k · LN2_HI` is exact for
/// `|k| < 2²¹`).
const LN2_HI: f64 = f64::from_bits(0x3FE6_2E42_FEE0_0000);
/// ln 2 − [`LN2_HI`] (fdlibm's `ln2_lo`).
const LN2_LO: f64 = f64::from_bits(0x3DEA_39EF_3579_3C76);
/// 1/ln 2 (fdlibm's `invln2`).
const INV_LN2: f64 = f64::from_bits(0x3FF7_1547_652B_82FE);

/// `expm1 r − r − r²/2` over `r²`, i.e. Taylor's `1/n!` for n = 2..13 in Horner form: on
/// `|r| ≤ ln 2 / 2` the truncated terms are below `|r|¹⁴/14! < 4.2e-18`, 0.13 ulp of
/// `|expm1 r|`.
const EXPM1_TAYLOR: [f64; 12] = [
    1.0 / 2.0,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5040.0,
    1.0 / 40320.0,
    1.0 / 362880.0,
    1.0 / 3628800.0,
    1.0 / 39916800.0,
    1.0 / 479001600.0,
    1.0 / 6227020800.0,
];

/// The branch-free `tanh` that [`tanh`] and [`tanh_lanes`] share (the same operations in the
/// same order, so both give the same bits): with `a = |x|` and `t = expm1(−2a)`,
/// `tanh x = sign(x) · (−t / (t + 2))`, the form glibc uses below 1. `expm1(y)`, `y ∈ [−40, 0]`:
/// `k = round(y / ln 2)` (to-nearest by adding and subtracting 1.5 · 2⁵²), `r = (y − k ln2_hi)
/// − k ln2_lo` (the first difference exact), `expm1 r` by its Taylor polynomial to degree 13
/// (`|r| ≤ ln 2 / 2`), then `2ᵏ expm1 r + (2ᵏ − 1)`. `|x| ≥` [`TANH_SATURATED`] gives ±1 by
/// select; NaN stays NaN. No fused multiply-adds, no table, no libm: the same bits on every
/// machine.
#[inline(always)]
fn tanh_kernel(x: f64) -> f64 {
    let a = x.abs();
    // NaN compares false: it goes through the polynomial and stays NaN.
    let saturated = a >= TANH_SATURATED;
    let y = -2.0 * if saturated { 0.0 } else { a };
    let t = y * INV_LN2 + ROUND_MAGIC;
    let k = t - ROUND_MAGIC;
    // 2^k from the integer in t's low bits (k ∈ [−58, 0] here; garbage, unused, for NaN).
    let ki = (t.to_bits() as i64).wrapping_sub(ROUND_MAGIC.to_bits() as i64);
    let scale = f64::from_bits((ki.wrapping_add(1023) as u64) << 52);
    let r = (y - k * LN2_HI) - k * LN2_LO;
    let c = &EXPM1_TAYLOR;
    let p = c[0]
        + r * (c[1]
            + r * (c[2]
                + r * (c[3]
                    + r * (c[4]
                        + r * (c[5]
                            + r * (c[6]
                                + r * (c[7]
                                    + r * (c[8] + r * (c[9] + r * (c[10] + r * c[11]))))))))));
    let e = r + (r * r) * p;
    // t = 2ᵏ e + (2ᵏ − 1) and t + 2 = 2ᵏ e + (2ᵏ + 1), each with one rounding (2ᵏ ± 1 and
    // 2ᵏ e are exact).
    let se = scale * e;
    let th = -(se + (scale - 1.0)) / (se + (scale + 1.0));
    let m = if saturated { 1.0 } else { th };
    m.copysign(x)
}

/// `tanh x` (dimensionless): a polynomial below [`TANH_SATURATED`] (see `tanh_kernel`:
/// stated bound `|fast − libm| ≤ 4 u(libm)` over `|x| < 20`, measured 3 ulp by
/// `tests/fastmath.rs`, and 2 ulp from the correctly rounded value, measured against 120-bit
/// mpmath at 2·10⁵ points), ±1 from it on (identical to libm), NaN for NaN; libm's with the libm
/// switch on. The smoothed Coulomb sign `tanh(q̇/ε)` with ε = 1e-3 rad/s is saturated
/// whenever `|q̇| ≥ 0.02 rad/s`. Unlike glibc's `tanh` (which calls `__expm1_fma` on a CPU
/// with FMA, a machine dependence) it gives the same bits on every machine.
#[inline]
pub fn tanh(x: f64) -> f64 {
    if libm_selected() {
        return x.tanh();
    }
    if x.abs() >= TANH_SATURATED {
        return 1.0f64.copysign(x);
    }
    tanh_kernel(x)
}

/// [`tanh`] of [`crate::simd::LANES`] values at once, lane by lane bit-identical to [`tanh`]
/// (the same kernel as plain lane arithmetic, which vectorises); when every lane is
/// saturated (`|x| ≥` [`TANH_SATURATED`]) only the selects run. Inlined into the caller, so it
/// runs on the caller's instruction set ([`crate::simd`]).
#[inline(always)]
pub fn tanh_lanes(x: &[f64; crate::simd::LANES]) -> [f64; crate::simd::LANES] {
    use crate::simd::LANES;
    let mut r = [0.0; LANES];
    if libm_selected() {
        for l in 0..LANES {
            r[l] = x[l].tanh();
        }
        return r;
    }
    let mut slow = false;
    for l in 0..LANES {
        // NaN is not saturated: slow.
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        let unsaturated = !(x[l].abs() >= TANH_SATURATED);
        slow |= unsaturated;
        r[l] = 1.0f64.copysign(x[l]);
    }
    if slow {
        for l in 0..LANES {
            r[l] = tanh_kernel(x[l]);
        }
    }
    r
}

/// The saturation threshold of [`tanh_lanes_of_ratio_at`] for the width `eps`:
/// `20 ε (1 + 2⁻⁵⁰)`, above `20 ε` by more than its rounding error, for a positive normal
/// finite `eps` with libm's switch off; NaN otherwise (no lane then compares saturated). Made
/// once per batch, outside the joints' loop.
#[inline(always)]
pub fn ratio_saturation_threshold(eps: f64) -> f64 {
    if eps >= f64::MIN_POSITIVE && eps.is_finite() && !libm_selected() {
        (TANH_SATURATED * eps) * (1.0 + 4.0 * f64::EPSILON)
    } else {
        f64::NAN
    }
}

/// [`tanh_lanes`] of `x / eps` (`x` in any unit, `eps` in the same unit), lane by lane bit for
/// bit `tanh(x[l] / eps)`: the smoothed sign `tanh(q̇/ε)` of the friction effects. See
/// [`tanh_lanes_of_ratio_at`].
#[inline(always)]
pub fn tanh_lanes_of_ratio(x: &[f64; crate::simd::LANES], eps: f64) -> [f64; crate::simd::LANES] {
    tanh_lanes_of_ratio_at(x, eps, ratio_saturation_threshold(eps))
}

/// [`tanh_lanes_of_ratio`] with its threshold `threshold =`
/// [`ratio_saturation_threshold`]`(eps)` made by the caller. When every lane has
/// `|x| ≥ threshold` (then `|x/ε| ≥ 20` exactly, rounding being monotonic, and `x/ε` has the
/// sign of `x` since `ε > 0`) the result is `±1` with `x`'s sign and the 8 divisions are
/// skipped; otherwise (a slower lane, a NaN, a NaN threshold) it divides and runs `tanh`'s
/// kernel on every lane (libm's `tanh` per lane with its switch on), which gives `tanh`'s bits
/// for saturated lanes too. Inlined into the caller, so it runs on the caller's instruction set.
#[inline(always)]
pub fn tanh_lanes_of_ratio_at(
    x: &[f64; crate::simd::LANES],
    eps: f64,
    threshold: f64,
) -> [f64; crate::simd::LANES] {
    use crate::simd::LANES;
    let mut saturated = true;
    let mut r = [0.0; LANES];
    for l in 0..LANES {
        // NaN compares false: not saturated.
        saturated &= x[l].abs() >= threshold;
        r[l] = 1.0f64.copysign(x[l]);
    }
    if saturated {
        return r;
    }
    if libm_selected() {
        for l in 0..LANES {
            r[l] = (x[l] / eps).tanh();
        }
        return r;
    }
    for l in 0..LANES {
        r[l] = tanh_kernel(x[l] / eps);
    }
    r
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
