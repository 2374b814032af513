//! Lanes back to samples: the values of a batch appended sample by sample to a vector,
//! without a zero fill ahead of them, by register transposes where the shape allows.

use super::reg::F64s;
use super::LANES;
use std::mem::MaybeUninit;

/// Append lanes `0 .. count` (`count ≤` [`LANES`]) of `rows` to `out` sample by sample:
/// for each lane `l`, `rows[0][l], rows[1][l], …` (`count · rows.len()` values, the same
/// values, moved). A full batch of 12 rows goes by 4 × 4 block transposes where `R` has
/// them (AVX), a full batch of an even number of rows by 2 × 2 ones (SSE2, x86-64's
/// baseline); anything else value by value.
#[inline(always)]
pub(crate) fn push_transposed<R: F64s>(out: &mut Vec<f64>, rows: &[&[f64; LANES]], count: usize) {
    let (count, k) = (count.min(LANES), rows.len());
    let len = out.len();
    out.reserve(count * k);
    let spare = &mut out.spare_capacity_mut()[..count * k];
    let done = count == LANES && full_batch::<R>(rows, spare);
    if !done {
        for (l, sample) in spare.chunks_exact_mut(k).enumerate() {
            for (v, row) in sample.iter_mut().zip(rows) {
                v.write(row[l]);
            }
        }
    }
    // SAFETY: the `count · k` values past `len` were written just above (by the transposes,
    // or `chunks_exact_mut` of exactly that length, every entry of each chunk).
    unsafe { out.set_len(len + count * k) };
}

/// A full batch of `rows` into `spare` (`LANES · rows.len()` values) by transposes, `false`
/// (nothing written) where the shape has none.
#[inline(always)]
fn full_batch<R: F64s>(rows: &[&[f64; LANES]], spare: &mut [MaybeUninit<f64>]) -> bool {
    const _: () = assert!(LANES == 8);
    if let Ok(rows12) = <&[&[f64; LANES]; 12]>::try_from(rows) {
        if R::transpose_8x12(rows12, spare) {
            return true;
        }
    }
    #[cfg(target_arch = "x86_64")]
    if rows.len().is_multiple_of(2) {
        use std::arch::x86_64::{_mm_loadu_pd, _mm_storeu_pd, _mm_unpackhi_pd, _mm_unpacklo_pd};
        let k = rows.len();
        assert!(spare.len() >= LANES * k);
        let o = spare.as_mut_ptr() as *mut f64;
        for j in (0..k).step_by(2) {
            for l in (0..LANES).step_by(2) {
                // SAFETY: SSE2 is in the x86-64 baseline; the loads read lanes l, l + 1 of
                // rows j, j + 1 (in bounds), the stores write entries l·k + j, + 1 and
                // (l + 1)·k + j, + 1 of `spare`, which holds LANES · k values (asserted).
                unsafe {
                    let a = _mm_loadu_pd(rows[j].as_ptr().add(l));
                    let b = _mm_loadu_pd(rows[j + 1].as_ptr().add(l));
                    _mm_storeu_pd(o.add(l * k + j), _mm_unpacklo_pd(a, b));
                    _mm_storeu_pd(o.add((l + 1) * k + j), _mm_unpackhi_pd(a, b));
                }
            }
        }
        return true;
    }
    false
}
