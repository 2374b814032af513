//! The register abstraction: [`F64s`], the lanes of `f64` the kernels compute on, and its
//! per-instruction-set backend [`V`] (the intrinsics; see the module docs of [`crate::simd`]).

/// `W` lanes of `f64` in one register of an instruction set: the raw operations, one
/// implementation per register type (`f64`, and on x86-64 `__m128d`, `__m256d`, `__m512d`).
/// Each method is, lane by lane, the IEEE operation (or select, or comparison) named in its
/// documentation, so every type gives the same numbers as `f64`.
///
/// Kernels do not use this trait: they are written over [`F64s`], whose register types exist
/// only inside a dispatch that checked the CPU (so their methods are safe). `V` is public so
/// that tests can compare each register type's instructions with the scalar operations.
///
/// # Safety
/// Every method needs the CPU to have the type's instruction set, and runs at full speed
/// only in a caller compiled for it (`#[target_feature]`).
#[allow(clippy::missing_safety_doc)] // the trait's: the type's instruction set
pub trait V: Copy {
    /// Lanes per register.
    const W: usize;
    /// `x` in every lane.
    unsafe fn splat(x: f64) -> Self;
    /// The first `W` values of `p` (panics if `p` is shorter).
    unsafe fn load(p: &[f64]) -> Self;
    /// Into the first `W` values of `p` (panics if `p` is shorter).
    unsafe fn store(self, p: &mut [f64]);
    /// `self + o`.
    unsafe fn add(self, o: Self) -> Self;
    /// `self − o`.
    unsafe fn sub(self, o: Self) -> Self;
    /// `self · o`.
    unsafe fn mul(self, o: Self) -> Self;
    /// `√self`.
    unsafe fn sqrt(self) -> Self;
    /// `|self|` (the sign bit cleared, as `f64::abs`).
    unsafe fn abs(self) -> Self;
    /// `if self <= o { self } else { o }` (nalgebra's `inf`).
    unsafe fn inf(self, o: Self) -> Self;
    /// `if self >= o { self } else { o }` (nalgebra's `sup`).
    unsafe fn sup(self, o: Self) -> Self;
    /// `if self < o { self } else { o }`.
    unsafe fn lt_min(self, o: Self) -> Self;
    /// `f64::max` (the other operand where one is NaN; the sign of a zero result
    /// is unspecified, as `f64::max`'s).
    unsafe fn max(self, o: Self) -> Self;
    /// Bit `l`: `a ≤ b && c ≥ d` in lane `l` (false with a NaN).
    unsafe fn le_ge(a: Self, b: Self, c: Self, d: Self) -> u32;
    /// Bit `l`: `self < o` in lane `l` (false with a NaN).
    unsafe fn lt(self, o: Self) -> u32;
    /// Bit `l`: `self ≤ o` in lane `l` (false with a NaN).
    unsafe fn le(self, o: Self) -> u32;
    /// Bit `l`: `self > o` in lane `l` (false with a NaN).
    unsafe fn gt(self, o: Self) -> u32;
    /// Bit `l`: `self ≥ o` in lane `l` (false with a NaN).
    unsafe fn ge(self, o: Self) -> u32;
    /// `out[l · rows.len() + r] = rows[r][l]` for the 8 lanes of 12 rows, in 4 × 4 block
    /// transposes; `false` (nothing written) where the type has no such shuffles (the caller
    /// moves the values one by one). `out` holds at least `8 · 12` values.
    #[inline(always)]
    unsafe fn transpose_8x12(
        _rows: &[&[f64; 8]; 12],
        _out: &mut [std::mem::MaybeUninit<f64>],
    ) -> bool {
        false
    }
}

/// One lane: the scalar reference and the portable fall-back.
impl V for f64 {
    const W: usize = 1;
    #[inline(always)]
    unsafe fn splat(x: f64) -> Self {
        x
    }
    #[inline(always)]
    unsafe fn load(p: &[f64]) -> Self {
        p[0]
    }
    #[inline(always)]
    unsafe fn store(self, p: &mut [f64]) {
        p[0] = self
    }
    #[inline(always)]
    unsafe fn add(self, o: Self) -> Self {
        self + o
    }
    #[inline(always)]
    unsafe fn sub(self, o: Self) -> Self {
        self - o
    }
    #[inline(always)]
    unsafe fn mul(self, o: Self) -> Self {
        self * o
    }
    #[inline(always)]
    unsafe fn sqrt(self) -> Self {
        self.sqrt()
    }
    #[inline(always)]
    unsafe fn abs(self) -> Self {
        self.abs()
    }
    #[inline(always)]
    unsafe fn inf(self, o: Self) -> Self {
        if self <= o {
            self
        } else {
            o
        }
    }
    #[inline(always)]
    unsafe fn sup(self, o: Self) -> Self {
        if self >= o {
            self
        } else {
            o
        }
    }
    #[inline(always)]
    unsafe fn lt_min(self, o: Self) -> Self {
        if self < o {
            self
        } else {
            o
        }
    }
    #[inline(always)]
    unsafe fn max(self, o: Self) -> Self {
        f64::max(self, o)
    }
    #[inline(always)]
    unsafe fn le_ge(a: Self, b: Self, c: Self, d: Self) -> u32 {
        u32::from(a <= b && c >= d)
    }
    #[inline(always)]
    unsafe fn lt(self, o: Self) -> u32 {
        u32::from(self < o)
    }
    #[inline(always)]
    unsafe fn le(self, o: Self) -> u32 {
        u32::from(self <= o)
    }
    #[inline(always)]
    unsafe fn gt(self, o: Self) -> u32 {
        u32::from(self > o)
    }
    #[inline(always)]
    unsafe fn ge(self, o: Self) -> u32 {
        u32::from(self >= o)
    }
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    use super::V;
    use std::arch::x86_64::*;
    use std::mem::MaybeUninit;

    /// The AVX block transpose of [`V::transpose_8x12`].
    ///
    /// # Safety
    /// The CPU has AVX; `out` holds at least `8 · 12` values.
    #[inline(always)]
    unsafe fn transpose_8x12_avx(rows: &[&[f64; 8]; 12], out: &mut [MaybeUninit<f64>]) {
        assert!(out.len() >= 8 * 12);
        let o = out.as_mut_ptr() as *mut f64;
        // SAFETY: the caller's contract (AVX; `out` long enough: the asserted length); the
        // loads read 4 of a row's 8 lanes.
        unsafe {
            for h in [0, 4] {
                for g in 0..3 {
                    let r0 = _mm256_loadu_pd(rows[4 * g].as_ptr().add(h));
                    let r1 = _mm256_loadu_pd(rows[4 * g + 1].as_ptr().add(h));
                    let r2 = _mm256_loadu_pd(rows[4 * g + 2].as_ptr().add(h));
                    let r3 = _mm256_loadu_pd(rows[4 * g + 3].as_ptr().add(h));
                    let t0 = _mm256_unpacklo_pd(r0, r1);
                    let t1 = _mm256_unpackhi_pd(r0, r1);
                    let t2 = _mm256_unpacklo_pd(r2, r3);
                    let t3 = _mm256_unpackhi_pd(r2, r3);
                    let lanes = [
                        _mm256_permute2f128_pd::<0x20>(t0, t2),
                        _mm256_permute2f128_pd::<0x20>(t1, t3),
                        _mm256_permute2f128_pd::<0x31>(t0, t2),
                        _mm256_permute2f128_pd::<0x31>(t1, t3),
                    ];
                    for (i, v) in lanes.into_iter().enumerate() {
                        _mm256_storeu_pd(o.add((h + i) * 12 + 4 * g), v);
                    }
                }
            }
        }
    }

    impl V for __m128d {
        const W: usize = 2;
        #[inline(always)]
        unsafe fn splat(x: f64) -> Self {
            _mm_set1_pd(x)
        }
        #[inline(always)]
        unsafe fn load(p: &[f64]) -> Self {
            assert!(p.len() >= 2);
            _mm_loadu_pd(p.as_ptr())
        }
        #[inline(always)]
        unsafe fn store(self, p: &mut [f64]) {
            assert!(p.len() >= 2);
            _mm_storeu_pd(p.as_mut_ptr(), self)
        }
        #[inline(always)]
        unsafe fn add(self, o: Self) -> Self {
            _mm_add_pd(self, o)
        }
        #[inline(always)]
        unsafe fn sub(self, o: Self) -> Self {
            _mm_sub_pd(self, o)
        }
        #[inline(always)]
        unsafe fn mul(self, o: Self) -> Self {
            _mm_mul_pd(self, o)
        }
        #[inline(always)]
        unsafe fn sqrt(self) -> Self {
            _mm_sqrt_pd(self)
        }
        #[inline(always)]
        unsafe fn abs(self) -> Self {
            _mm_andnot_pd(_mm_set1_pd(-0.0), self)
        }
        #[inline(always)]
        unsafe fn inf(self, o: Self) -> Self {
            let m = _mm_cmple_pd(self, o);
            _mm_or_pd(_mm_and_pd(m, self), _mm_andnot_pd(m, o))
        }
        #[inline(always)]
        unsafe fn sup(self, o: Self) -> Self {
            let m = _mm_cmpge_pd(self, o);
            _mm_or_pd(_mm_and_pd(m, self), _mm_andnot_pd(m, o))
        }
        #[inline(always)]
        unsafe fn lt_min(self, o: Self) -> Self {
            // MINPD: the first operand where it is less, else the second.
            _mm_min_pd(self, o)
        }
        #[inline(always)]
        unsafe fn max(self, o: Self) -> Self {
            // MAXPD gives `o` where either is NaN: `self` where `o` is.
            let m = _mm_max_pd(self, o);
            let nan = _mm_cmpunord_pd(o, o);
            _mm_or_pd(_mm_and_pd(nan, self), _mm_andnot_pd(nan, m))
        }
        #[inline(always)]
        unsafe fn le_ge(a: Self, b: Self, c: Self, d: Self) -> u32 {
            _mm_movemask_pd(_mm_and_pd(_mm_cmple_pd(a, b), _mm_cmpge_pd(c, d))) as u32
        }
        #[inline(always)]
        unsafe fn lt(self, o: Self) -> u32 {
            _mm_movemask_pd(_mm_cmplt_pd(self, o)) as u32
        }
        #[inline(always)]
        unsafe fn le(self, o: Self) -> u32 {
            _mm_movemask_pd(_mm_cmple_pd(self, o)) as u32
        }
        #[inline(always)]
        unsafe fn gt(self, o: Self) -> u32 {
            _mm_movemask_pd(_mm_cmpgt_pd(self, o)) as u32
        }
        #[inline(always)]
        unsafe fn ge(self, o: Self) -> u32 {
            _mm_movemask_pd(_mm_cmpge_pd(self, o)) as u32
        }
    }

    impl V for __m256d {
        const W: usize = 4;
        #[inline(always)]
        unsafe fn splat(x: f64) -> Self {
            _mm256_set1_pd(x)
        }
        #[inline(always)]
        unsafe fn load(p: &[f64]) -> Self {
            assert!(p.len() >= 4);
            _mm256_loadu_pd(p.as_ptr())
        }
        #[inline(always)]
        unsafe fn store(self, p: &mut [f64]) {
            assert!(p.len() >= 4);
            _mm256_storeu_pd(p.as_mut_ptr(), self)
        }
        #[inline(always)]
        unsafe fn add(self, o: Self) -> Self {
            _mm256_add_pd(self, o)
        }
        #[inline(always)]
        unsafe fn sub(self, o: Self) -> Self {
            _mm256_sub_pd(self, o)
        }
        #[inline(always)]
        unsafe fn mul(self, o: Self) -> Self {
            _mm256_mul_pd(self, o)
        }
        #[inline(always)]
        unsafe fn sqrt(self) -> Self {
            _mm256_sqrt_pd(self)
        }
        #[inline(always)]
        unsafe fn abs(self) -> Self {
            _mm256_andnot_pd(_mm256_set1_pd(-0.0), self)
        }
        #[inline(always)]
        unsafe fn inf(self, o: Self) -> Self {
            _mm256_blendv_pd(o, self, _mm256_cmp_pd::<_CMP_LE_OQ>(self, o))
        }
        #[inline(always)]
        unsafe fn sup(self, o: Self) -> Self {
            _mm256_blendv_pd(o, self, _mm256_cmp_pd::<_CMP_GE_OQ>(self, o))
        }
        #[inline(always)]
        unsafe fn lt_min(self, o: Self) -> Self {
            _mm256_min_pd(self, o)
        }
        #[inline(always)]
        unsafe fn max(self, o: Self) -> Self {
            let m = _mm256_max_pd(self, o);
            _mm256_blendv_pd(m, self, _mm256_cmp_pd::<_CMP_UNORD_Q>(o, o))
        }
        #[inline(always)]
        unsafe fn le_ge(a: Self, b: Self, c: Self, d: Self) -> u32 {
            let m = _mm256_and_pd(
                _mm256_cmp_pd::<_CMP_LE_OQ>(a, b),
                _mm256_cmp_pd::<_CMP_GE_OQ>(c, d),
            );
            _mm256_movemask_pd(m) as u32
        }
        #[inline(always)]
        unsafe fn lt(self, o: Self) -> u32 {
            _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(self, o)) as u32
        }
        #[inline(always)]
        unsafe fn le(self, o: Self) -> u32 {
            _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LE_OQ>(self, o)) as u32
        }
        #[inline(always)]
        unsafe fn gt(self, o: Self) -> u32 {
            _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_GT_OQ>(self, o)) as u32
        }
        #[inline(always)]
        unsafe fn ge(self, o: Self) -> u32 {
            _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_GE_OQ>(self, o)) as u32
        }
        #[inline(always)]
        unsafe fn transpose_8x12(rows: &[&[f64; 8]; 12], out: &mut [MaybeUninit<f64>]) -> bool {
            // SAFETY: the caller's contract (AVX).
            unsafe { transpose_8x12_avx(rows, out) };
            true
        }
    }

    impl V for __m512d {
        const W: usize = 8;
        #[inline(always)]
        unsafe fn splat(x: f64) -> Self {
            _mm512_set1_pd(x)
        }
        #[inline(always)]
        unsafe fn load(p: &[f64]) -> Self {
            assert!(p.len() >= 8);
            _mm512_loadu_pd(p.as_ptr())
        }
        #[inline(always)]
        unsafe fn store(self, p: &mut [f64]) {
            assert!(p.len() >= 8);
            _mm512_storeu_pd(p.as_mut_ptr(), self)
        }
        #[inline(always)]
        unsafe fn add(self, o: Self) -> Self {
            _mm512_add_pd(self, o)
        }
        #[inline(always)]
        unsafe fn sub(self, o: Self) -> Self {
            _mm512_sub_pd(self, o)
        }
        #[inline(always)]
        unsafe fn mul(self, o: Self) -> Self {
            _mm512_mul_pd(self, o)
        }
        #[inline(always)]
        unsafe fn sqrt(self) -> Self {
            _mm512_sqrt_pd(self)
        }
        #[inline(always)]
        unsafe fn abs(self) -> Self {
            _mm512_abs_pd(self)
        }
        #[inline(always)]
        unsafe fn inf(self, o: Self) -> Self {
            _mm512_mask_blend_pd(_mm512_cmp_pd_mask::<_CMP_LE_OQ>(self, o), o, self)
        }
        #[inline(always)]
        unsafe fn sup(self, o: Self) -> Self {
            _mm512_mask_blend_pd(_mm512_cmp_pd_mask::<_CMP_GE_OQ>(self, o), o, self)
        }
        #[inline(always)]
        unsafe fn lt_min(self, o: Self) -> Self {
            _mm512_min_pd(self, o)
        }
        #[inline(always)]
        unsafe fn max(self, o: Self) -> Self {
            let m = _mm512_max_pd(self, o);
            _mm512_mask_blend_pd(_mm512_cmp_pd_mask::<_CMP_UNORD_Q>(o, o), m, self)
        }
        #[inline(always)]
        unsafe fn le_ge(a: Self, b: Self, c: Self, d: Self) -> u32 {
            let m = _mm512_cmp_pd_mask::<_CMP_LE_OQ>(a, b);
            _mm512_mask_cmp_pd_mask::<_CMP_GE_OQ>(m, c, d) as u32
        }
        #[inline(always)]
        unsafe fn lt(self, o: Self) -> u32 {
            _mm512_cmp_pd_mask::<_CMP_LT_OQ>(self, o) as u32
        }
        #[inline(always)]
        unsafe fn le(self, o: Self) -> u32 {
            _mm512_cmp_pd_mask::<_CMP_LE_OQ>(self, o) as u32
        }
        #[inline(always)]
        unsafe fn gt(self, o: Self) -> u32 {
            _mm512_cmp_pd_mask::<_CMP_GT_OQ>(self, o) as u32
        }
        #[inline(always)]
        unsafe fn ge(self, o: Self) -> u32 {
            _mm512_cmp_pd_mask::<_CMP_GE_OQ>(self, o) as u32
        }
        #[inline(always)]
        unsafe fn transpose_8x12(rows: &[&[f64; 8]; 12], out: &mut [MaybeUninit<f64>]) -> bool {
            // SAFETY: the caller's contract (AVX-512F implies AVX).
            unsafe { transpose_8x12_avx(rows, out) };
            true
        }
    }
}

/// Lanes of `f64` as the kernels see them: [`V`]'s operations, safe to call. A kernel is
/// generic over `R: F64s` and is handed its register type by [`crate::simd::dispatch`]
/// (which checked the CPU) or runs on `f64` (one lane, the scalar reference). See the module
/// docs of [`crate::simd`].
pub(crate) trait F64s: Copy {
    /// Lanes per register.
    const W: usize;
    /// `x` in every lane.
    fn splat(x: f64) -> Self;
    /// The first `W` values of `p` (panics if `p` is shorter).
    fn load(p: &[f64]) -> Self;
    /// Into the first `W` values of `p` (panics if `p` is shorter).
    fn store(self, p: &mut [f64]);
    /// `self + o`.
    fn add(self, o: Self) -> Self;
    /// `self − o`.
    fn sub(self, o: Self) -> Self;
    /// `self · o`.
    fn mul(self, o: Self) -> Self;
    /// `√self`.
    fn sqrt(self) -> Self;
    /// `|self|`.
    fn abs(self) -> Self;
    /// `if self <= o { self } else { o }`.
    fn inf(self, o: Self) -> Self;
    /// `if self >= o { self } else { o }`.
    fn sup(self, o: Self) -> Self;
    /// `if self < o { self } else { o }`.
    fn lt_min(self, o: Self) -> Self;
    /// `f64::max`.
    fn max(self, o: Self) -> Self;
    /// Bit `l`: `a ≤ b && c ≥ d` in lane `l`.
    fn le_ge(a: Self, b: Self, c: Self, d: Self) -> u32;
    /// Bit `l`: `self < o`.
    fn lt(self, o: Self) -> u32;
    /// Bit `l`: `self ≤ o`.
    fn le(self, o: Self) -> u32;
    /// Bit `l`: `self > o`.
    fn gt(self, o: Self) -> u32;
    /// Bit `l`: `self ≥ o`.
    fn ge(self, o: Self) -> u32;
    /// [`V::transpose_8x12`].
    fn transpose_8x12(rows: &[&[f64; 8]; 12], out: &mut [std::mem::MaybeUninit<f64>]) -> bool;
}

/// One lane: plain `f64` arithmetic, safe everywhere.
impl F64s for f64 {
    const W: usize = 1;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn load(p: &[f64]) -> Self {
        p[0]
    }
    #[inline(always)]
    fn store(self, p: &mut [f64]) {
        p[0] = self
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        self + o
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        self - o
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        self * o
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f64::abs(self)
    }
    #[inline(always)]
    fn inf(self, o: Self) -> Self {
        // SAFETY: `f64`'s implementation needs no instruction set.
        unsafe { V::inf(self, o) }
    }
    #[inline(always)]
    fn sup(self, o: Self) -> Self {
        // SAFETY: as above.
        unsafe { V::sup(self, o) }
    }
    #[inline(always)]
    fn lt_min(self, o: Self) -> Self {
        // SAFETY: as above.
        unsafe { V::lt_min(self, o) }
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        f64::max(self, o)
    }
    #[inline(always)]
    fn le_ge(a: Self, b: Self, c: Self, d: Self) -> u32 {
        u32::from(a <= b && c >= d)
    }
    #[inline(always)]
    fn lt(self, o: Self) -> u32 {
        u32::from(self < o)
    }
    #[inline(always)]
    fn le(self, o: Self) -> u32 {
        u32::from(self <= o)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> u32 {
        u32::from(self > o)
    }
    #[inline(always)]
    fn ge(self, o: Self) -> u32 {
        u32::from(self >= o)
    }
    #[inline(always)]
    fn transpose_8x12(_: &[&[f64; 8]; 12], _: &mut [std::mem::MaybeUninit<f64>]) -> bool {
        false
    }
}

/// A register of an instruction set, as [`F64s`]. Only [`crate::simd::dispatch`] makes
/// kernels over it, and only on a CPU that has the instruction set of `T`: the type is not
/// nameable outside this module, so no value of it exists anywhere else.
#[derive(Clone, Copy)]
pub(super) struct Reg<T>(T);

macro_rules! forward {
    ($($f:ident($($a:ident),*) -> $r:ident;)*) => {
        $(
            #[inline(always)]
            fn $f(self, $($a: Self),*) -> $r {
                // SAFETY: a `Reg<T>` exists only in a kernel that `dispatch` runs on a CPU
                // with `T`'s instruction set, compiled for it.
                wrap!(unsafe { V::$f(self.0, $($a.0),*) } => $r)
            }
        )*
    };
}

macro_rules! wrap {
    ($e:expr => Self) => {
        Reg($e)
    };
    ($e:expr => u32) => {
        $e
    };
}

impl<T: V> F64s for Reg<T> {
    const W: usize = T::W;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        // SAFETY: see `forward!`.
        Reg(unsafe { T::splat(x) })
    }
    #[inline(always)]
    fn load(p: &[f64]) -> Self {
        // SAFETY: see `forward!`.
        Reg(unsafe { T::load(p) })
    }
    #[inline(always)]
    fn store(self, p: &mut [f64]) {
        // SAFETY: see `forward!`.
        unsafe { self.0.store(p) }
    }
    forward! {
        add(o) -> Self;
        sub(o) -> Self;
        mul(o) -> Self;
        sqrt() -> Self;
        abs() -> Self;
        inf(o) -> Self;
        sup(o) -> Self;
        lt_min(o) -> Self;
        max(o) -> Self;
        lt(o) -> u32;
        le(o) -> u32;
        gt(o) -> u32;
        ge(o) -> u32;
    }
    #[inline(always)]
    fn le_ge(a: Self, b: Self, c: Self, d: Self) -> u32 {
        // SAFETY: see `forward!`.
        unsafe { T::le_ge(a.0, b.0, c.0, d.0) }
    }
    #[inline(always)]
    fn transpose_8x12(rows: &[&[f64; 8]; 12], out: &mut [std::mem::MaybeUninit<f64>]) -> bool {
        // SAFETY: see `forward!`.
        unsafe { T::transpose_8x12(rows, out) }
    }
}
