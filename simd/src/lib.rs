#![doc = include_str!("../README.md")]
#![no_std]

#[cfg(target_arch = "x86_64")]
extern crate std;

/// A computation to compile for AVX2. Mark `run` `#[inline(always)]`, and
/// what it calls: only code inlined into the AVX2 function is compiled
/// for AVX2.
pub trait Kernel {
    /// What the kernel returns.
    type Output;
    /// The computation.
    fn run(self) -> Self::Output;
}

/// True when [`run_avx2`] would run its kernel: an x86_64 processor with
/// AVX2.
#[inline]
pub fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Runs `kernel` compiled for AVX2 if the processor has it; otherwise
/// returns it unrun (`Err`), for the caller to run the usual way.
#[inline]
pub fn run_avx2<K: Kernel>(kernel: K) -> Result<K::Output, K> {
    #[cfg(target_arch = "x86_64")]
    {
        if has_avx2() {
            // SAFETY: the processor has AVX2 (checked just above), the only
            // requirement of a `#[target_feature(enable = "avx2")]` function.
            return Ok(unsafe { avx2(kernel) });
        }
    }
    Err(kernel)
}

/// `kernel.run()` with AVX2 enabled for everything inlined into it.
///
/// # Safety
/// The processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn avx2<K: Kernel>(kernel: K) -> K::Output {
    kernel.run()
}

/// `kernel.run()` in a function of its own, compiled for AVX2 and never
/// inlined: [`Avx2::run_in_part`].
///
/// # Safety
/// The processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline(never)]
unsafe fn avx2_part<K: Kernel>(kernel: K) -> K::Output {
    kernel.run()
}

/// Four 64-bit lanes, as the engine's lane arithmetic holds them.
pub type U64x4 = [u64; 4];

/// Proof that the processor has AVX2, and the AVX2 operations on
/// [`U64x4`] that the compiler does not reliably choose by itself (it
/// turns some lane products into scalar ones). Each method is one
/// instruction: call them from a [`Kernel`] run by [`run_avx2`], where
/// they inline into the AVX2 code (called elsewhere they still compute
/// the same, through a call).
#[derive(Clone, Copy, Debug)]
pub struct Avx2 {
    _proof: (),
}

impl Avx2 {
    /// The proof, if the processor has AVX2.
    #[inline]
    pub fn new() -> Option<Avx2> {
        has_avx2().then_some(Avx2 { _proof: () })
    }

    /// Runs `kernel` compiled for AVX2 in a function of its own, never
    /// inlined into its caller: a part of a kernel. Everything inlined
    /// into one function is compiled as one, and the optimiser's time
    /// grows faster than the function; a kernel whose inlined code would
    /// be large compiles much faster cut into parts, at the cost of a
    /// call (the part's data passes through memory).
    #[inline(always)]
    pub fn run_in_part<K: Kernel>(self, kernel: K) -> K::Output {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: an `Avx2` exists only where `has_avx2()` held
            // (`Avx2::new`), the only requirement of the AVX2 function.
            unsafe { avx2_part(kernel) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = self;
            kernel.run()
        }
    }
}

/// Defines a method of [`Avx2`] as one intrinsic on two lanes.
macro_rules! binary {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[inline(always)]
        pub fn $name(self, a: U64x4, b: U64x4) -> U64x4 {
            #[cfg(target_arch = "x86_64")]
            {
                // SAFETY: `self` proves the processor has AVX2.
                unsafe { x86::$name(a, b) }
            }
            #[cfg(not(target_arch = "x86_64"))]
            {
                // `Avx2::new` returns `None` here: no value exists.
                let _ = (self, b);
                a
            }
        }
    };
}

impl Avx2 {
    binary!(
        /// `a + b` lane by lane, wrapping (`vpaddq`).
        add
    );
    binary!(
        /// `a − b` lane by lane, wrapping (`vpsubq`).
        sub
    );
    binary!(
        /// `a ^ b` (`vpxor`).
        xor
    );
    binary!(
        /// `a & b` (`vpand`).
        and
    );
    binary!(
        /// `a | b` (`vpor`).
        or
    );
    binary!(
        /// All ones where `a > b` as signed 64-bit integers, else 0
        /// (`vpcmpgtq`).
        gt
    );
    binary!(
        /// The low 32 bits of `a` times the low 32 bits of `b`, 64-bit
        /// products (`vpmuludq`).
        mul_lo32
    );
    binary!(
        /// The low 32 bits of `a` times the low 32 bits of `b`, both read
        /// as signed 32-bit integers: signed 64-bit products (`vpmuldq`).
        mul_i32
    );

    /// `mask ? a : b` lane by lane, `mask` all ones or 0 (`vpblendvb`).
    #[inline(always)]
    pub fn select(self, mask: U64x4, a: U64x4, b: U64x4) -> U64x4 {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: `self` proves the processor has AVX2.
            unsafe { x86::select(mask, a, b) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = (self, mask, b);
            a
        }
    }

    /// `a >> 32` lane by lane, logical (`vpsrlq`).
    #[inline(always)]
    pub fn shr32(self, a: U64x4) -> U64x4 {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: `self` proves the processor has AVX2.
            unsafe { x86::shr32(a) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = self;
            a
        }
    }

    /// `a >> N` lane by lane, logical (`vpsrlq`; `N` in `0..64`).
    #[inline(always)]
    pub fn shr_n<const N: i32>(self, a: U64x4) -> U64x4 {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: `self` proves the processor has AVX2.
            unsafe { x86::shr::<N>(a) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = self;
            a
        }
    }

    /// `a << N` lane by lane (`vpsllq`; `N` in `0..64`).
    #[inline(always)]
    pub fn shl_n<const N: i32>(self, a: U64x4) -> U64x4 {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: `self` proves the processor has AVX2.
            unsafe { x86::shl::<N>(a) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = self;
            a
        }
    }

    /// `a << 32` lane by lane (`vpsllq`).
    #[inline(always)]
    pub fn shl32(self, a: U64x4) -> U64x4 {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: `self` proves the processor has AVX2.
            unsafe { x86::shl32(a) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = self;
            a
        }
    }
}

/// The intrinsics. Every function needs AVX2 (its only safety
/// requirement); `[u64; 4]` and `__m256i` are both 32 plain bytes, so the
/// conversions between them are bit copies.
#[cfg(target_arch = "x86_64")]
mod x86 {
    use super::U64x4;
    use core::arch::x86_64::*;

    #[inline(always)]
    fn to(a: U64x4) -> __m256i {
        // SAFETY: both types are 32 bytes of plain integer data.
        unsafe { core::mem::transmute::<U64x4, __m256i>(a) }
    }

    #[inline(always)]
    fn from(a: __m256i) -> U64x4 {
        // SAFETY: both types are 32 bytes of plain integer data.
        unsafe { core::mem::transmute::<__m256i, U64x4>(a) }
    }

    macro_rules! avx2_binary {
        ($name:ident, $intrinsic:ident) => {
            #[target_feature(enable = "avx2")]
            #[inline]
            pub(super) unsafe fn $name(a: U64x4, b: U64x4) -> U64x4 {
                from($intrinsic(to(a), to(b)))
            }
        };
    }

    avx2_binary!(add, _mm256_add_epi64);
    avx2_binary!(sub, _mm256_sub_epi64);
    avx2_binary!(xor, _mm256_xor_si256);
    avx2_binary!(and, _mm256_and_si256);
    avx2_binary!(or, _mm256_or_si256);
    avx2_binary!(gt, _mm256_cmpgt_epi64);
    avx2_binary!(mul_lo32, _mm256_mul_epu32);
    avx2_binary!(mul_i32, _mm256_mul_epi32);

    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn shr<const N: i32>(a: U64x4) -> U64x4 {
        from(_mm256_srli_epi64::<N>(to(a)))
    }

    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn shl<const N: i32>(a: U64x4) -> U64x4 {
        from(_mm256_slli_epi64::<N>(to(a)))
    }

    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn select(mask: U64x4, a: U64x4, b: U64x4) -> U64x4 {
        from(_mm256_blendv_epi8(to(b), to(a), to(mask)))
    }

    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn shr32(a: U64x4) -> U64x4 {
        from(_mm256_srli_epi64::<32>(to(a)))
    }

    #[target_feature(enable = "avx2")]
    #[inline]
    pub(super) unsafe fn shl32(a: U64x4) -> U64x4 {
        from(_mm256_slli_epi64::<32>(to(a)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Dot<'a>(&'a [i64], &'a [i64]);

    impl Kernel for Dot<'_> {
        type Output = i64;
        #[inline(always)]
        fn run(self) -> i64 {
            self.0
                .iter()
                .zip(self.1)
                .fold(0i64, |acc, (&a, &b)| acc.wrapping_add(a.wrapping_mul(b)))
        }
    }

    #[test]
    fn the_operations_compute_what_they_say() {
        let Some(v) = Avx2::new() else {
            assert!(!has_avx2());
            return;
        };
        let a: U64x4 = [1, u64::MAX, 1 << 63, 0x1234_5678_9abc_def0];
        let b: U64x4 = [3, 2, 1 << 63, 0xffff_ffff_0000_0002];
        let each = |f: fn(u64, u64) -> u64| {
            let mut out = a;
            for (o, &y) in out.iter_mut().zip(&b) {
                *o = f(*o, y);
            }
            out
        };
        assert_eq!(v.add(a, b), each(u64::wrapping_add));
        assert_eq!(v.sub(a, b), each(u64::wrapping_sub));
        assert_eq!(v.xor(a, b), each(|x, y| x ^ y));
        assert_eq!(v.and(a, b), each(|x, y| x & y));
        assert_eq!(v.or(a, b), each(|x, y| x | y));
        assert_eq!(
            v.gt(a, b),
            each(|x, y| if (x as i64) > (y as i64) { u64::MAX } else { 0 })
        );
        assert_eq!(
            v.mul_lo32(a, b),
            each(|x, y| (x & 0xffff_ffff) * (y & 0xffff_ffff))
        );
        assert_eq!(
            v.mul_i32(a, b),
            each(|x, y| (i64::from(x as u32 as i32) * i64::from(y as u32 as i32)) as u64)
        );
        assert_eq!(v.shr32(a), a.map(|x| x >> 32));
        assert_eq!(v.shl32(a), a.map(|x| x << 32));
        assert_eq!(v.shr_n::<24>(a), a.map(|x| x >> 24));
        assert_eq!(v.shl_n::<16>(a), a.map(|x| x << 16));
        let mask = [u64::MAX, 0, u64::MAX, 0];
        assert_eq!(v.select(mask, a, b), [a[0], b[1], a[2], b[3]]);
    }

    #[test]
    fn avx2_runs_exactly_when_detected_and_gives_the_same_result() {
        let a: [i64; 9] = [1, -2, 3, i64::MAX, i64::MIN, 7, 0, -1, 1 << 40];
        let b: [i64; 9] = [5, 6, -7, 3, -1, 1 << 33, 9, i64::MIN, 1 << 30];
        let plain = Dot(&a, &b).run();
        match run_avx2(Dot(&a, &b)) {
            Ok(wide) => {
                assert!(has_avx2());
                assert_eq!(wide, plain);
            }
            Err(unrun) => {
                assert!(!has_avx2());
                assert_eq!(unrun.run(), plain);
            }
        }
    }

    #[test]
    fn a_part_gives_the_kernels_result() {
        let a: [i64; 9] = [1, -2, 3, i64::MAX, i64::MIN, 7, 0, -1, 1 << 40];
        let b: [i64; 9] = [5, 6, -7, 3, -1, 1 << 33, 9, i64::MIN, 1 << 30];
        let plain = Dot(&a, &b).run();
        match Avx2::new() {
            Some(v) => assert_eq!(v.run_in_part(Dot(&a, &b)), plain),
            None => assert!(!has_avx2()),
        }
    }
}
