//! Run-time CPU feature detection for the hot loops (covariance propagation,
//! Joseph update). The portable build targets SSE2 (two `f64` lanes); where
//! the CPU has AVX the same loops run compiled for four lanes. Only the
//! vector width changes, never the operations or their order (no FMA
//! contraction), so results are bit-identical on every CPU (tested beside
//! each use). Without `std` there is no detection: the portable code runs,
//! vectorized for whatever `-C target-feature` the build enables.
//!
//! The opt-in `fma` feature fuses the kernels' multiply-adds
//! ([`crate::real::Real::plus_product`]) and compiles the fast path for
//! AVX and FMA. A fused multiply-add is exactly rounded, so the results are
//! still the same on every CPU (the portable path calls the exact software
//! `fma`), but they differ from the default build in the last bits.

/// Whether the kernels fuse their multiply-adds (the `fma` feature).
pub(crate) const FUSED: bool = cfg!(feature = "fma");

/// Whether the CPU executes AVX instructions (and, in the `fma` build,
/// FMA ones; std caches the answer).
#[cfg(all(feature = "std", target_arch = "x86_64"))]
#[inline(always)]
pub fn has_avx() -> bool {
    std::arch::is_x86_feature_detected!("avx")
        && (!cfg!(feature = "fma") || std::arch::is_x86_feature_detected!("fma"))
}

/// `fn name<const ..>(args) -> ret => portable;` defines `name`, which calls
/// `portable` (an `#[inline(always)]` function with the same signature and a
/// last `const AVX: bool`) compiled for AVX with `AVX = true` when the CPU has
/// it, and as built with `AVX = false` otherwise (the flag lets a kernel pick
/// block sizes for the register file it gets).
macro_rules! avx_dispatch {
    (
        $(#[$meta:meta])*
        $vis:vis fn $name:ident<$(const $c:ident: usize),*>($($arg:ident: $ty:ty),* $(,)?)
            $(-> $ret:ty)? => $portable:ident;
    ) => {
        $(#[$meta])*
        #[inline]
        $vis fn $name<$(const $c: usize),*>($($arg: $ty),*) $(-> $ret)? {
            #[cfg(all(feature = "std", target_arch = "x86_64"))]
            {
                #[target_feature(enable = "avx")]
                unsafe fn with_avx<$(const $c: usize),*>($($arg: $ty),*) $(-> $ret)? {
                    $portable::<$($c,)* true>($($arg),*)
                }
                if $crate::dispatch::has_avx() {
                    // SAFETY: the CPU executes AVX instructions (checked above).
                    return unsafe { with_avx::<$($c),*>($($arg),*) };
                }
            }
            $portable::<$($c,)* false>($($arg),*)
        }
    };
    // The same for a kernel generic over the scalar (`f32` or `f64`), whose
    // portable body also takes a last `const FUSED: bool` (see `FUSED`).
    (
        $(#[$meta:meta])*
        $vis:vis fn $name:ident<$t:ident: Real, $(const $c:ident: usize),*>($($arg:ident: $ty:ty),* $(,)?)
            $(-> $ret:ty)? => $portable:ident;
    ) => {
        $(#[$meta])*
        #[inline]
        $vis fn $name<$t: $crate::real::Real, $(const $c: usize),*>($($arg: $ty),*) $(-> $ret)? {
            #[cfg(all(feature = "std", target_arch = "x86_64"))]
            {
                #[cfg_attr(not(feature = "fma"), target_feature(enable = "avx"))]
                #[cfg_attr(feature = "fma", target_feature(enable = "avx,fma"))]
                unsafe fn with_avx<$t: $crate::real::Real, $(const $c: usize),*>($($arg: $ty),*) $(-> $ret)? {
                    $portable::<$t, $($c,)* true, { $crate::dispatch::FUSED }>($($arg),*)
                }
                if $crate::dispatch::has_avx() {
                    // SAFETY: the CPU executes AVX instructions (checked above).
                    return unsafe { with_avx::<$t, $($c),*>($($arg),*) };
                }
            }
            $portable::<$t, $($c,)* false, { $crate::dispatch::FUSED }>($($arg),*)
        }
    };
    // The same with a last type parameter `S` (a table known at compile time
    // through a trait's associated constant), written after a `;` and passed
    // on to the portable body before `AVX` and `FUSED`.
    (
        $(#[$meta:meta])*
        $vis:vis fn $name:ident<$t:ident: Real, $(const $c:ident: usize),*; $s:ident: $bound:path>($($arg:ident: $ty:ty),* $(,)?)
            $(-> $ret:ty)? => $portable:ident;
    ) => {
        $(#[$meta])*
        #[inline]
        $vis fn $name<$t: $crate::real::Real, $(const $c: usize,)* $s: $bound>($($arg: $ty),*) $(-> $ret)? {
            #[cfg(all(feature = "std", target_arch = "x86_64"))]
            {
                #[cfg_attr(not(feature = "fma"), target_feature(enable = "avx"))]
                #[cfg_attr(feature = "fma", target_feature(enable = "avx,fma"))]
                unsafe fn with_avx<$t: $crate::real::Real, $(const $c: usize,)* $s: $bound>($($arg: $ty),*) $(-> $ret)? {
                    $portable::<$t, $($c,)* $s, true, { $crate::dispatch::FUSED }>($($arg),*)
                }
                if $crate::dispatch::has_avx() {
                    // SAFETY: the CPU executes AVX instructions (checked above).
                    return unsafe { with_avx::<$t, $($c,)* $s>($($arg),*) };
                }
            }
            $portable::<$t, $($c,)* $s, false, { $crate::dispatch::FUSED }>($($arg),*)
        }
    };
}
pub(crate) use avx_dispatch;
