//! Exact I32F32 arithmetic four values at a time, in the form integer SIMD
//! computes it: the wide kernels' arithmetic.
//!
//! A [`Lane`] holds the raw bits of four [`Real`](super::Real)s. Every
//! product rounds as `Real`'s (to nearest, ties away from zero), from
//! 32×32→64-bit partial products: with `|a| = a_h·2^32 + a_l` and `|b| =
//! b_h·2^32 + b_l`, `|a·b| = a_h·b_h·2^64 + (a_h·b_l + a_l·b_h)·2^32 +
//! a_l·b_l`, four unsigned products each below `2^64` (AVX2's `vpmuludq`,
//! four lanes an instruction), summed in 64 bits and the sign put back.
//! Sums of products (`a·b + c·d`, 4-term dot products) round once, as
//! `Real::mul_add2` and `Real::dot4`: the high parts and the low 32-bit
//! remainders are summed apart, then rounded together.
//!
//! The sums may wrap where the result leaves the window; each lane keeps a
//! **record** instead, nonzero once anything in that lane left the window:
//! a partial product too large for its sum, a result of `2^60` or more
//! (the bound [`Ranged`](super::Ranged)'s proofs assume for every rounded
//! product), or an input that [`LaneArith::check_inputs`] found at or
//! above `RANGED_INPUT` (`2^58`). Additions and subtractions wrap without
//! a record, as `Ranged`'s: the caller proves its kernel's depth bound
//! (the soft contacts' is in `solver::soft_contact::row`). A lane whose record
//! is clear computed exactly the bits of the scalar kernels; a lane whose
//! record is set is recomputed by the scalar kernel (a false alarm costs
//! only that, never a bit).
//!
//! The arithmetic is written once over [`Ops`], the lane operations it is
//! built from: [`Portable`] in plain Rust, `tamias2d_simd::Avx2`, one
//! AVX2 instruction each (left to itself, the compiler's vectoriser turns
//! some lane products back into scalar ones), and, in a wasm build with
//! `simd128`, `Wasm128`, one or two `i64x2` instructions each. All give
//! the same bits (integer operations; the AVX2 ones are proptested
//! against the portable ones, the `simd128` ones are checked by the
//! browser test's narrow goldens, which run in them).
//! Code the AVX2 kernel runs calls lane operations only from functions
//! marked `#[inline(always)]`, never from a closure: a closure is not
//! always inlined into the kernel, and outside it each AVX2 operation is
//! a function call (a closure in `dot` once made the step 2× slower).
use super::unsaturated::RANGED_INPUT;

/// Values per lane group.
pub(crate) const LANES: usize = 4;

/// The raw bits of four `Real`s.
pub(crate) type Lane = [i64; LANES];

/// The low 32 bits.
const LOW: i64 = 0xffff_ffff;
/// `2^31`: the rounding half, and the sign bit of a 32-bit value.
const HALF: i64 = 1 << 31;
/// Results at or above `2^60` in magnitude are recorded.
const RESULT_BITS: u32 = 60;
/// High partial products at or above `2^28` are recorded.
const HIGH_BITS: u32 = 28;
/// Inputs at or above [`RANGED_INPUT`] (`2^58`) are recorded.
const INPUT_BITS: u32 = RANGED_INPUT.trailing_zeros();

/// `x` in every lane.
#[inline(always)]
pub(crate) const fn splat(x: i64) -> Lane {
    [x; LANES]
}

/// `f` lane by lane on two groups.
#[inline(always)]
#[cfg_attr(
    all(target_arch = "wasm32", target_feature = "simd128", not(test)),
    allow(dead_code, reason = "the simd128 build's passes run `Wasm128`")
)]
fn zip(a: Lane, b: Lane, f: impl Fn(i64, i64) -> i64) -> Lane {
    let mut out = a;
    for (o, &y) in out.iter_mut().zip(&b) {
        *o = f(*o, y);
    }
    out
}

/// The lane operations the arithmetic is built from, each one instruction
/// on a processor with 64-bit integer lanes: [`Portable`] (plain Rust, for
/// any processor) and [`tamias2d_simd::Avx2`] (AVX2 instructions, which
/// the compiler does not reliably choose by itself). Both give the same
/// bits: the operations are integer ones.
pub(crate) trait Ops: Copy {
    /// `a + b`, wrapping.
    fn add(self, a: Lane, b: Lane) -> Lane;
    /// `a − b`, wrapping.
    fn sub(self, a: Lane, b: Lane) -> Lane;
    /// `a ^ b`.
    fn xor(self, a: Lane, b: Lane) -> Lane;
    /// `a & b`.
    fn and(self, a: Lane, b: Lane) -> Lane;
    /// `a | b`.
    fn or(self, a: Lane, b: Lane) -> Lane;
    /// All ones where `a > b`, else 0.
    fn gt(self, a: Lane, b: Lane) -> Lane;
    /// The low 32 bits of `a` times those of `b` (unsigned, 64-bit
    /// products).
    fn mul_lo32(self, a: Lane, b: Lane) -> Lane;
    /// The low 32 bits of `a` times those of `b`, both read as signed
    /// 32-bit integers (signed 64-bit products, never wrapping).
    fn mul_i32(self, a: Lane, b: Lane) -> Lane;
    /// `a >> N`, logical (`N` in `0..64`).
    fn shr_n<const N: i32>(self, a: Lane) -> Lane;
    /// `a << N` (`N` in `0..64`).
    fn shl_n<const N: i32>(self, a: Lane) -> Lane;
    /// `a >> 32`, logical.
    fn shr32(self, a: Lane) -> Lane;
    /// `a << 32`.
    fn shl32(self, a: Lane) -> Lane;
    /// `mask ? a : b` (`mask` all ones or 0).
    fn select(self, mask: Lane, a: Lane, b: Lane) -> Lane;
    /// `kernel.run()` in a function of its own, never inlined (for
    /// `Avx2`, compiled for AVX2): a part of a larger kernel, which then
    /// compiles as parts instead of one function.
    fn run_part<K: tamias2d_simd::Kernel>(self, kernel: K) -> K::Output;

    /// All ones where `a < 0`, else 0.
    #[inline(always)]
    fn sign(self, a: Lane) -> Lane {
        self.gt(splat(0), a)
    }

    /// `−a`, wrapping.
    #[inline(always)]
    fn neg(self, a: Lane) -> Lane {
        self.sub(splat(0), a)
    }

    /// `Real::min`.
    #[inline(always)]
    fn min(self, a: Lane, b: Lane) -> Lane {
        self.select(self.gt(a, b), b, a)
    }

    /// `Real::max`.
    #[inline(always)]
    fn max(self, a: Lane, b: Lane) -> Lane {
        self.select(self.gt(b, a), b, a)
    }

    /// All ones where `a > 0`, else 0.
    #[inline(always)]
    fn positive(self, a: Lane) -> Lane {
        self.gt(a, splat(0))
    }
}

/// [`Ops`] in plain Rust.
#[derive(Clone, Copy, Debug, Default)]
#[cfg_attr(
    all(target_arch = "wasm32", target_feature = "simd128", not(test)),
    allow(dead_code, reason = "the simd128 build's passes run `Wasm128`")
)]
pub(crate) struct Portable;

impl Ops for Portable {
    #[inline(always)]
    fn run_part<K: tamias2d_simd::Kernel>(self, kernel: K) -> K::Output {
        portable_part(kernel)
    }
    #[inline(always)]
    fn add(self, a: Lane, b: Lane) -> Lane {
        zip(a, b, i64::wrapping_add)
    }
    #[inline(always)]
    fn sub(self, a: Lane, b: Lane) -> Lane {
        zip(a, b, i64::wrapping_sub)
    }
    #[inline(always)]
    fn xor(self, a: Lane, b: Lane) -> Lane {
        zip(a, b, |x, y| x ^ y)
    }
    #[inline(always)]
    fn and(self, a: Lane, b: Lane) -> Lane {
        zip(a, b, |x, y| x & y)
    }
    #[inline(always)]
    fn or(self, a: Lane, b: Lane) -> Lane {
        zip(a, b, |x, y| x | y)
    }
    #[inline(always)]
    fn gt(self, a: Lane, b: Lane) -> Lane {
        zip(a, b, |x, y| i64::from(x > y).wrapping_neg())
    }
    #[inline(always)]
    fn mul_lo32(self, a: Lane, b: Lane) -> Lane {
        zip(a, b, |x, y| (x & LOW).wrapping_mul(y & LOW))
    }
    #[inline(always)]
    fn mul_i32(self, a: Lane, b: Lane) -> Lane {
        zip(a, b, |x, y| {
            i64::from(x as i32).wrapping_mul(i64::from(y as i32))
        })
    }
    #[inline(always)]
    fn shr_n<const N: i32>(self, a: Lane) -> Lane {
        a.map(|x| ((x as u64).wrapping_shr(N as u32)) as i64)
    }
    #[inline(always)]
    fn shl_n<const N: i32>(self, a: Lane) -> Lane {
        a.map(|x| x.wrapping_shl(N as u32))
    }
    #[inline(always)]
    fn shr32(self, a: Lane) -> Lane {
        a.map(|x| ((x as u64) >> 32) as i64)
    }
    #[inline(always)]
    fn shl32(self, a: Lane) -> Lane {
        a.map(|x| x << 32)
    }
    #[inline(always)]
    fn select(self, mask: Lane, a: Lane, b: Lane) -> Lane {
        zip(
            zip(a, mask, |x, m| x & m),
            zip(b, mask, |y, m| y & !m),
            |x, y| x | y,
        )
    }
}

/// The lane operations in wasm's 128-bit SIMD, two `i64x2` halves a lane
/// group, each operation one or two instructions. Left to itself the
/// compiler vectorises the portable operations, but it rewrites the
/// widening products (`i64x2.extmul_low_i32x4`) as sign or zero
/// extensions and a full 64-bit `i64x2.mul`, which wasm engines emulate
/// in many instructions on x86_64. The products here first gather each
/// 64-bit lane's low half with an `i8x16.swizzle` whose index vector the
/// compiler cannot see through (made opaque once, in [`Wasm128::new`]),
/// so it keeps the one widening multiply where both factors are gathered
/// in the product's block of code (a factor gathered once for products
/// in several blocks still becomes `i64x2.mul`: making every index depend
/// on the other factor too, to prevent that, was slower in Chromium).
/// Integer operations: the bits of [`Portable`].
#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
mod wasm128 {
    use super::{Lane, Ops};
    use core::arch::wasm32::{
        i64x2, i64x2_add, i64x2_extmul_low_i32x4, i64x2_extract_lane, i64x2_gt, i64x2_shl,
        i64x2_sub, i8x16, i8x16_swizzle, u64x2_extmul_low_u32x4, u64x2_shr, v128, v128_and,
        v128_bitselect, v128_or, v128_xor,
    };

    /// The wasm `simd128` lane operations.
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct Wasm128 {
        /// The byte indices of each 64-bit lane's low 32 bits, side by
        /// side in the low 64 bits (and again above).
        lows: v128,
        /// Zero, opaque: `0 > a` stays one comparison instead of the
        /// arithmetic shift by 63 the compiler prefers (which wasm
        /// engines emulate on x86_64).
        zero: v128,
    }

    impl Wasm128 {
        /// The operations, with their swizzle index made opaque.
        #[inline(always)]
        pub(crate) fn new() -> Wasm128 {
            Wasm128 {
                lows: core::hint::black_box(i8x16(
                    0, 1, 2, 3, 8, 9, 10, 11, 0, 1, 2, 3, 8, 9, 10, 11,
                )),
                zero: core::hint::black_box(i64x2(0, 0)),
            }
        }

        /// The low 32 bits of each 64-bit lane of `x` and of `y`, side by
        /// side in the low 64 bits: the operands of a widening product.
        #[inline(always)]
        fn lows_of(self, x: v128, y: v128) -> (v128, v128) {
            (i8x16_swizzle(x, self.lows), i8x16_swizzle(y, self.lows))
        }
    }

    /// A lane group as two `i64x2`.
    #[inline(always)]
    fn halves(a: Lane) -> [v128; 2] {
        [i64x2(a[0], a[1]), i64x2(a[2], a[3])]
    }

    /// Two `i64x2` as a lane group.
    #[inline(always)]
    fn join([lo, hi]: [v128; 2]) -> Lane {
        [
            i64x2_extract_lane::<0>(lo),
            i64x2_extract_lane::<1>(lo),
            i64x2_extract_lane::<0>(hi),
            i64x2_extract_lane::<1>(hi),
        ]
    }

    /// One `simd128` operation on both halves of two lane groups.
    macro_rules! both {
        ($a:expr, $b:expr, $op:expr) => {{
            let ([a0, a1], [b0, b1]) = (halves($a), halves($b));
            join([$op(a0, b0), $op(a1, b1)])
        }};
    }

    impl Ops for Wasm128 {
        #[inline(always)]
        fn run_part<K: tamias2d_simd::Kernel>(self, kernel: K) -> K::Output {
            super::portable_part(kernel)
        }
        #[inline(always)]
        fn add(self, a: Lane, b: Lane) -> Lane {
            both!(a, b, i64x2_add)
        }
        #[inline(always)]
        fn sub(self, a: Lane, b: Lane) -> Lane {
            both!(a, b, i64x2_sub)
        }
        #[inline(always)]
        fn xor(self, a: Lane, b: Lane) -> Lane {
            both!(a, b, v128_xor)
        }
        #[inline(always)]
        fn and(self, a: Lane, b: Lane) -> Lane {
            both!(a, b, v128_and)
        }
        #[inline(always)]
        fn or(self, a: Lane, b: Lane) -> Lane {
            both!(a, b, v128_or)
        }
        #[inline(always)]
        fn gt(self, a: Lane, b: Lane) -> Lane {
            both!(a, b, i64x2_gt)
        }
        #[inline(always)]
        fn sign(self, a: Lane) -> Lane {
            let [lo, hi] = halves(a);
            join([i64x2_gt(self.zero, lo), i64x2_gt(self.zero, hi)])
        }
        #[inline(always)]
        fn mul_lo32(self, a: Lane, b: Lane) -> Lane {
            both!(a, b, |x, y| {
                let (x, y) = self.lows_of(x, y);
                u64x2_extmul_low_u32x4(x, y)
            })
        }
        #[inline(always)]
        fn mul_i32(self, a: Lane, b: Lane) -> Lane {
            both!(a, b, |x, y| {
                let (x, y) = self.lows_of(x, y);
                i64x2_extmul_low_i32x4(x, y)
            })
        }
        #[inline(always)]
        fn shr_n<const N: i32>(self, a: Lane) -> Lane {
            let [lo, hi] = halves(a);
            join([u64x2_shr(lo, N as u32), u64x2_shr(hi, N as u32)])
        }
        #[inline(always)]
        fn shl_n<const N: i32>(self, a: Lane) -> Lane {
            let [lo, hi] = halves(a);
            join([i64x2_shl(lo, N as u32), i64x2_shl(hi, N as u32)])
        }
        #[inline(always)]
        fn shr32(self, a: Lane) -> Lane {
            self.shr_n::<32>(a)
        }
        #[inline(always)]
        fn shl32(self, a: Lane) -> Lane {
            self.shl_n::<32>(a)
        }
        #[inline(always)]
        fn select(self, mask: Lane, a: Lane, b: Lane) -> Lane {
            let ([m0, m1], [a0, a1], [b0, b1]) = (halves(mask), halves(a), halves(b));
            join([v128_bitselect(a0, b0, m0), v128_bitselect(a1, b1, m1)])
        }
    }
}

#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
pub(crate) use wasm128::Wasm128;

/// `[i64; 4]` as the unsigned lanes `tamias2d_simd` takes, and back (the
/// same bits).
#[inline(always)]
fn u(a: Lane) -> [u64; LANES] {
    a.map(|x| x as u64)
}
#[inline(always)]
fn i(a: [u64; LANES]) -> Lane {
    a.map(|x| x as i64)
}

/// [`Portable`]'s [`Ops::run_part`].
#[inline(never)]
fn portable_part<K: tamias2d_simd::Kernel>(kernel: K) -> K::Output {
    kernel.run()
}

impl Ops for tamias2d_simd::Avx2 {
    #[inline(always)]
    fn run_part<K: tamias2d_simd::Kernel>(self, kernel: K) -> K::Output {
        tamias2d_simd::Avx2::run_in_part(self, kernel)
    }
    #[inline(always)]
    fn add(self, a: Lane, b: Lane) -> Lane {
        i(tamias2d_simd::Avx2::add(self, u(a), u(b)))
    }
    #[inline(always)]
    fn sub(self, a: Lane, b: Lane) -> Lane {
        i(tamias2d_simd::Avx2::sub(self, u(a), u(b)))
    }
    #[inline(always)]
    fn xor(self, a: Lane, b: Lane) -> Lane {
        i(tamias2d_simd::Avx2::xor(self, u(a), u(b)))
    }
    #[inline(always)]
    fn and(self, a: Lane, b: Lane) -> Lane {
        i(tamias2d_simd::Avx2::and(self, u(a), u(b)))
    }
    #[inline(always)]
    fn or(self, a: Lane, b: Lane) -> Lane {
        i(tamias2d_simd::Avx2::or(self, u(a), u(b)))
    }
    #[inline(always)]
    fn gt(self, a: Lane, b: Lane) -> Lane {
        i(tamias2d_simd::Avx2::gt(self, u(a), u(b)))
    }
    #[inline(always)]
    fn mul_lo32(self, a: Lane, b: Lane) -> Lane {
        i(tamias2d_simd::Avx2::mul_lo32(self, u(a), u(b)))
    }
    #[inline(always)]
    fn mul_i32(self, a: Lane, b: Lane) -> Lane {
        i(tamias2d_simd::Avx2::mul_i32(self, u(a), u(b)))
    }
    #[inline(always)]
    fn shr_n<const N: i32>(self, a: Lane) -> Lane {
        i(tamias2d_simd::Avx2::shr_n::<N>(self, u(a)))
    }
    #[inline(always)]
    fn shl_n<const N: i32>(self, a: Lane) -> Lane {
        i(tamias2d_simd::Avx2::shl_n::<N>(self, u(a)))
    }
    #[inline(always)]
    fn shr32(self, a: Lane) -> Lane {
        i(tamias2d_simd::Avx2::shr32(self, u(a)))
    }
    #[inline(always)]
    fn shl32(self, a: Lane) -> Lane {
        i(tamias2d_simd::Avx2::shl32(self, u(a)))
    }
    #[inline(always)]
    fn select(self, mask: Lane, a: Lane, b: Lane) -> Lane {
        i(tamias2d_simd::Avx2::select(self, u(mask), u(a), u(b)))
    }
}

/// `|x|` in one's complement (`|x|` for `x ≥ 0`, `|x| − 1` below): the
/// magnitude a record compares, without the edge case of `i64::MIN`.
#[inline(always)]
fn magnitude(x: i64) -> u64 {
    (x ^ (x >> 63)) as u64
}

/// One factor of lane products as the partial products take it: its
/// magnitude, the magnitude's high half, and its sign (all ones where
/// negative). A factor that several products share (the impulse a row
/// applies through four terms, a momentum shared by two bodies) is split
/// once ([`LaneArith::factor`]); the products' bits do not depend on it.
///
/// A **short** factor (`SHORT`) is below `2^32` in magnitude in every
/// lane (most row constants: unit normals, lever arms under a metre,
/// effective masses and friction under 1): its high half is 0, so two of
/// a product's four partial products are 0 and are not computed, nor is
/// the high half ([`LaneArith::split`]). The sums and the record are those
/// of the four partial products (a 0 adds nothing to a sum and nothing to
/// an OR), so the bits are the same. Shortness is part of the type, so
/// that the kernels are compiled once for short and once for long
/// constants, with no test per product (a test per product cost more
/// instructions than the products it saved).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Factor<const SHORT: bool = false> {
    mag: Lane,
    high: Lane,
    sign: Lane,
}

/// True if every lane of `a` is below `2^32` in magnitude: a short
/// [`Factor`].
#[inline(always)]
pub(crate) fn is_short(a: &Lane) -> bool {
    a.iter().all(|&x| x.unsigned_abs() < 1 << 32)
}

/// A product's partial products as the quotient sums them: the high one
/// (`None` when a factor is short: it is 0), the middle sum `hl + lh`,
/// and the low one.
#[derive(Clone, Copy)]
struct Partials {
    hh: Option<Lane>,
    mid: Lane,
    ll: Lane,
}

/// Lane arithmetic with a record per lane (see the module docs), on the
/// operations `O`.
///
/// The record is two OR-accumulated words per lane, tested once by
/// [`left`](Self::left): `high`, the high partial products `a_h·b_h`
/// (a lane left the window if one reached `2^28`), and `quotient`, the
/// magnitudes of the rounded products and of a dot product's terms and
/// result (left if one reached `2^60`). Below both no sum of partial
/// products wrapped (see [`mul`](Self::mul)), a dot product's four terms
/// (each below `2^60`) summed without wrapping, and every result is below
/// `2^60`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LaneArith<O: Ops> {
    ops: O,
    high: Lane,
    quotient: Lane,
}

impl<O: Ops> LaneArith<O> {
    /// Clear records.
    #[inline(always)]
    pub(crate) const fn new(ops: O) -> LaneArith<O> {
        LaneArith {
            ops,
            high: [0; LANES],
            quotient: [0; LANES],
        }
    }

    /// The operations (the ones that record nothing: additions, choices).
    #[inline(always)]
    pub(crate) fn ops(&self) -> O {
        self.ops
    }

    /// Per lane: true if the lane left the window (its results are
    /// meaningless and the scalar kernel must recompute it).
    #[inline(always)]
    pub(crate) fn left(&self) -> [bool; LANES] {
        let mut out = [false; LANES];
        for ((o, &h), &q) in out.iter_mut().zip(&self.high).zip(&self.quotient) {
            *o = ((h as u64) >> HIGH_BITS) | ((q as u64) >> RESULT_BITS) != 0;
        }
        out
    }

    /// Records every lane of `values` at or above `RANGED_INPUT` in
    /// magnitude: the inputs a kernel's depth bound assumes.
    #[inline(always)]
    pub(crate) fn check_inputs(&mut self, values: &[Lane]) {
        for v in values {
            for (r, &x) in self.high.iter_mut().zip(v) {
                *r |= ((magnitude(x) >> INPUT_BITS) << HIGH_BITS) as i64;
            }
        }
    }

    /// Records lanes where an input record (such as a row's precomputed
    /// `constant_record`) is at or above `RANGED_INPUT`.
    #[inline(always)]
    pub(crate) fn check_records(&mut self, records: &[u64; LANES]) {
        for (r, &x) in self.high.iter_mut().zip(records) {
            *r |= ((x >> INPUT_BITS) << HIGH_BITS) as i64;
        }
    }

    /// `a` split for products ([`Factor`]): `|a|` as unsigned bits
    /// (`i64::MIN` gives `2^63`), its high half, its sign.
    #[inline(always)]
    pub(crate) fn factor(&self, a: Lane) -> Factor {
        self.split(a)
    }

    /// [`factor`](Self::factor) of a value the caller knows to be short
    /// ([`is_short`]) in every lane when `SHORT` (else the same as
    /// `factor`): the high half is not computed.
    #[inline(always)]
    pub(crate) fn split<const SHORT: bool>(&self, a: Lane) -> Factor<SHORT> {
        let o = self.ops;
        let sign = o.sign(a);
        let mag = o.sub(o.xor(a, sign), sign);
        Factor {
            mag,
            high: if SHORT { splat(0) } else { o.shr32(mag) },
            sign,
        }
    }

    /// The partial products of `|a|·|b|` (each a 32×32→64 product, no
    /// masks needed: the instruction reads only the low halves) and the
    /// product's sign (all ones if negative), recording `hh`. With a
    /// short factor `hh` and one middle product are 0 (not computed).
    #[inline(always)]
    fn partials<const A: bool, const B: bool>(
        &mut self,
        a: &Factor<A>,
        b: &Factor<B>,
    ) -> (Partials, Lane) {
        let o = self.ops;
        let sign = o.xor(a.sign, b.sign);
        let ll = o.mul_lo32(a.mag, b.mag);
        let p = match (A, B) {
            (true, true) => Partials {
                hh: None,
                mid: splat(0),
                ll,
            },
            (false, true) => Partials {
                hh: None,
                mid: o.mul_lo32(a.high, b.mag),
                ll,
            },
            (true, false) => Partials {
                hh: None,
                mid: o.mul_lo32(a.mag, b.high),
                ll,
            },
            (false, false) => {
                let hh = o.mul_lo32(a.high, b.high);
                self.high = o.or(self.high, hh);
                Partials {
                    hh: Some(hh),
                    mid: o.add(o.mul_lo32(a.high, b.mag), o.mul_lo32(a.mag, b.high)),
                    ll,
                }
            }
        };
        (p, sign)
    }

    /// `|a·b| >> 32` truncated, from the partial products:
    /// `hh·2^32 + hl + lh + (ll + round)/2^32` (`round`: `2^31` to round,
    /// 0 to truncate), recorded. Exact (the sum does not wrap) whenever
    /// `hh < 2^28`: then one of `a_h`, `b_h` is below `2^14`, so one of
    /// `hl`, `lh` is below `2^46`, the other below `2^63` (`a_h ≤ 2^31`,
    /// `b_l < 2^32`), and the sum below `2^60 + 2^46 + 2^63 + 2^32 <
    /// 2^64`. With a short factor `hh = 0` and the middle sum is one
    /// product below `2^63`: exact too.
    #[inline(always)]
    fn quotient(&mut self, p: &Partials, round: i64) -> Lane {
        let o = self.ops;
        let carry = if round == 0 {
            o.shr32(p.ll)
        } else {
            o.shr32(o.add(p.ll, splat(round)))
        };
        let mid = match p.hh {
            Some(hh) => o.add(o.shl32(hh), p.mid),
            None => p.mid,
        };
        let q = o.add(mid, carry);
        self.quotient = o.or(self.quotient, q);
        q
    }

    /// `(x ^ s) − s`: `x` negated where `s` is all ones.
    #[inline(always)]
    fn signed(&self, x: Lane, s: Lane) -> Lane {
        let o = self.ops;
        o.sub(o.xor(x, s), s)
    }

    /// `a·b`, rounded as `Real`'s `*`.
    #[inline(always)]
    pub(crate) fn mul(&mut self, a: Lane, b: Lane) -> Lane {
        let (a, b) = (self.factor(a), self.factor(b));
        self.mul_factors(&a, &b)
    }

    /// `a·b` of a value and a split factor.
    #[inline(always)]
    pub(crate) fn mul_by<const B: bool>(&mut self, a: Lane, b: &Factor<B>) -> Lane {
        let a = self.factor(a);
        self.mul_factors(&a, b)
    }

    /// `a·b` of two split factors.
    #[inline(always)]
    pub(crate) fn mul_factors<const A: bool, const B: bool>(
        &mut self,
        a: &Factor<A>,
        b: &Factor<B>,
    ) -> Lane {
        let (p, sign) = self.partials(a, b);
        let q = self.quotient(&p, HALF);
        self.signed(q, sign)
    }

    /// `Σ xᵢ·yᵢ` over `N ≤ 4` terms with one rounding, as `Real::mul_add2`
    /// (`N = 2`) and `Real::dot4` (`N = 4`).
    #[cfg(test)]
    #[inline(always)]
    pub(crate) fn dot<const N: usize>(&mut self, x: [Lane; N], y: [Lane; N]) -> Lane {
        let mut sum = Sum::default();
        for (&a, &b) in x.iter().zip(&y) {
            let (a, b) = (self.factor(a), self.factor(b));
            self.add_term(&mut sum, &a, &b);
        }
        self.round_sum(sum)
    }

    /// [`dot`](Self::dot) with the second factors split.
    #[inline(always)]
    pub(crate) fn dot_by<const N: usize, const B: bool>(
        &mut self,
        x: [Lane; N],
        y: &[Factor<B>; N],
    ) -> Lane {
        let mut sum = Sum::default();
        for (&a, b) in x.iter().zip(y) {
            let a = self.factor(a);
            self.add_term(&mut sum, &a, b);
        }
        self.round_sum(sum)
    }

    /// [`dot`](Self::dot) of split factors.
    #[inline(always)]
    pub(crate) fn dot_factors<const N: usize, const A: bool, const B: bool>(
        &mut self,
        x: &[Factor<A>; N],
        y: &[Factor<B>; N],
    ) -> Lane {
        let mut sum = Sum::default();
        for (a, b) in x.iter().zip(y) {
            self.add_term(&mut sum, a, b);
        }
        self.round_sum(sum)
    }

    /// One term `a·b` of a dot product, unrounded.
    #[inline(always)]
    fn add_term<const A: bool, const B: bool>(
        &mut self,
        sum: &mut Sum,
        a: &Factor<A>,
        b: &Factor<B>,
    ) {
        let o = self.ops;
        let (p, sign) = self.partials(a, b);
        // Each term's quotient below 2^60 (recorded), so a sum of four
        // stays below 2^62.
        let q = self.quotient(&p, 0);
        sum.high = o.add(sum.high, self.signed(q, sign));
        sum.low = o.add(sum.low, self.signed(o.and(p.ll, splat(LOW)), sign));
    }

    /// A dot product's terms rounded once.
    #[inline(always)]
    fn round_sum(&mut self, Sum { high, low }: Sum) -> Lane {
        let o = self.ops;
        // |low| < 4·2^32: its carry (or borrow) into the high part (the
        // top half sign-extended from 32 bits), then `h·2^32 + l` rounded
        // with `l` in [0, 2^32); the total is negative exactly when `h`
        // is, and rounds away from zero with `l + 2^31 − 1` there.
        let carry = o.sub(o.xor(o.shr32(low), splat(HALF)), splat(HALF));
        let h = o.add(high, carry);
        let l = o.and(low, splat(LOW));
        let up = o.shr32(o.add(o.add(l, splat(HALF)), o.sign(h)));
        let q = o.add(h, up);
        self.quotient = o.or(self.quotient, o.xor(q, o.sign(q)));
        q
    }
}

/// A dot product's terms before the rounding: the truncated quotients
/// and the 32-bit remainders, each signed, summed apart.
#[derive(Clone, Copy, Default)]
struct Sum {
    high: Lane,
    low: Lane,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Ranged, Real};
    use proptest::prelude::*;

    /// Values that reach every branch: any bits, any magnitude, small,
    /// ties (odd multiples of 2^31), the extremes.
    fn any_bits() -> impl Strategy<Value = i64> {
        prop_oneof![
            any::<i64>(),
            (any::<i64>(), 0u32..63).prop_map(|(v, s)| v >> s),
            (-64i64..64),
            (-(1i64 << 20)..(1 << 20)).prop_map(|k| k.wrapping_mul(2).wrapping_add(1) << 31),
            Just(i64::MIN),
            Just(i64::MAX),
            Just(1i64 << 60),
            Just(-(1i64 << 60)),
            Just((1i64 << 58) - 1),
            Just(1i64 << 58),
        ]
    }

    const EDGES: [i64; 24] = [
        0,
        1,
        -1,
        2,
        -3,
        1 << 31,
        -(1 << 31),
        (1 << 31) + 1,
        -(1 << 31) - 1,
        1 << 32,
        -(1 << 32),
        (1 << 32) + 1,
        -(1 << 32) - 1,
        (1 << 33) + 1,
        i64::MAX,
        i64::MIN,
        i64::MIN + 1,
        1 << 59,
        -(1 << 59),
        (1 << 61) - 1,
        1 << 62,
        u32::MAX as i64,
        -(u32::MAX as i64),
        (1 << 44) + (1 << 31),
    ];

    /// A clear record gives `Real`'s bits; a set one only where the scalar
    /// fast path could not promise its bound either (`|a·b| ≥ 2^91`, a
    /// result near `2^59` or more).
    fn check_mul(a: i64, b: i64) -> Result<(), TestCaseError> {
        let mut ar = LaneArith::new(Portable);
        let [got, ..] = ar.mul([a, 0, 0, 0], [b, 0, 0, 0]);
        let [left, ..] = ar.left();
        let want = Real::from_bits(a) * Real::from_bits(b);
        let p = (i128::from(a) * i128::from(b)).unsigned_abs();
        if left {
            prop_assert!(p >= 1u128 << 91, "false alarm {} * {}", a, b);
        } else {
            prop_assert_eq!(got, want.to_bits(), "{} * {}", a, b);
            prop_assert!(want.to_bits().unsigned_abs() <= 1 << 60);
            // And the scalar fast path agrees.
            let mut fast = Ranged::new();
            use crate::math::FixedArith;
            prop_assert_eq!(fast.mul(Real::from_bits(a), Real::from_bits(b)), want);
        }
        Ok(())
    }

    fn check_dot(x: [i64; 4], y: [i64; 4]) -> Result<(), TestCaseError> {
        let r = Real::from_bits;
        let col = |v: [i64; 4]| v.map(|e| [e, 0, 0, 0]);
        let mut ar4 = LaneArith::new(Portable);
        let [got4, ..] = ar4.dot(col(x), col(y));
        let want4 = Real::dot4(x.map(r), y.map(r));
        let mut ar2 = LaneArith::new(Portable);
        let [got2, ..] = ar2.dot(
            [[x[0], 0, 0, 0], [x[1], 0, 0, 0]],
            [[y[0], 0, 0, 0], [y[1], 0, 0, 0]],
        );
        let want2 = Real::mul_add2(r(x[0]), r(y[0]), r(x[1]), r(y[1]));
        // The exact sum (None if it leaves i128: four products of 2^126).
        let sum = x.iter().zip(&y).try_fold(0i128, |s, (&a, &b)| {
            s.checked_add(i128::from(a) * i128::from(b))
        });
        let big = x
            .iter()
            .zip(&y)
            .any(|(&a, &b)| (i128::from(a) * i128::from(b)).unsigned_abs() >= 1u128 << 89)
            || sum.is_none_or(|s| s.unsigned_abs() >= (1u128 << 92) - (1 << 31));
        let [left4, ..] = ar4.left();
        prop_assert!(big || !left4, "false alarm {:?} {:?}", x, y);
        if !left4 {
            prop_assert_eq!(got4, want4.to_bits(), "dot4 {:?} {:?}", x, y);
        }
        if !ar2.left()[0] {
            prop_assert_eq!(got2, want2.to_bits(), "mul_add2 {:?} {:?}", x, y);
        }
        Ok(())
    }

    #[test]
    fn products_at_ties_and_edges() {
        for a in EDGES {
            for b in EDGES {
                check_mul(a, b).unwrap();
            }
        }
    }

    #[test]
    fn dots_at_ties() {
        // Sums landing on ties of either sign, and remainders that borrow.
        let h = 1i64 << 31;
        for (x, y) in [
            ([h, h, 0, 0], [1, 0, 0, 0]),
            ([h, -h, h, 0], [1, 1, 1, 0]),
            ([-h, 0, 0, 0], [1, 0, 0, 0]),
            ([3 * h, -1, 0, 0], [1, 1, 0, 0]),
            ([-3 * h, 1, 0, 0], [1, 1, 0, 0]),
            ([1 << 32, -1, 0, 0], [1 << 32, 1, 0, 0]),
            (
                [i64::MAX >> 20, -(i64::MAX >> 20), 5, -7],
                [1 << 20, 1 << 20, 3, 11],
            ),
        ] {
            check_dot(x, y).unwrap();
        }
        for a in EDGES {
            for b in EDGES {
                check_dot([a, b, a.wrapping_neg(), 1], [b, a, 1 << 31, b]).unwrap();
            }
        }
    }

    #[test]
    fn inputs_at_the_window_edge() {
        let mut ar = LaneArith::new(Portable);
        let edge = RANGED_INPUT as i64;
        ar.check_inputs(&[[edge - 1, -edge, edge, -edge - 1]]);
        assert_eq!(ar.left(), [false, false, true, true]);
        let mut ar = LaneArith::new(Portable);
        ar.check_records(&[0, RANGED_INPUT - 1, RANGED_INPUT, u64::MAX]);
        assert_eq!(ar.left(), [false, false, true, true]);
    }

    #[test]
    fn selections() {
        let a = [3, -1, 0, i64::MIN];
        let b = [-3, 1, 0, i64::MAX];
        let o = Portable;
        assert_eq!(o.min(a, b), [-3, -1, 0, i64::MIN]);
        assert_eq!(o.max(a, b), [3, 1, 0, i64::MAX]);
        assert_eq!(o.positive(a), [-1, 0, 0, 0]);
        assert_eq!(o.select(o.positive(a), a, b), [3, 1, 0, i64::MAX]);
        let f = LaneArith::new(o).factor([i64::MIN, -5, 5, 0]);
        assert_eq!(f.mag, [i64::MIN, 5, 5, 0]);
        assert_eq!(f.high, [1 << 31, 0, 0, 0]);
        assert_eq!(f.sign, [-1, -1, 0, 0]);
        assert_eq!(o.neg([i64::MIN, -5, 5, 0]), [i64::MIN, 5, -5, 0]);
    }

    /// Every operation of `v`, and the arithmetic built on them, gives
    /// [`Portable`]'s bits and records on the lanes `[a, b, c, d]`.
    fn same_as_portable<V: Ops>(v: V, [a, b, c, d]: [Lane; 4]) -> Result<(), TestCaseError> {
        let o = Portable;
        prop_assert_eq!(o.add(a, b), v.add(a, b));
        prop_assert_eq!(o.sub(a, b), v.sub(a, b));
        prop_assert_eq!(o.xor(a, b), v.xor(a, b));
        prop_assert_eq!(o.and(a, b), v.and(a, b));
        prop_assert_eq!(o.or(a, b), v.or(a, b));
        prop_assert_eq!(o.gt(a, b), v.gt(a, b));
        prop_assert_eq!(o.gt(a, a), v.gt(a, a));
        prop_assert_eq!(o.sign(c), v.sign(c));
        prop_assert_eq!(o.mul_lo32(a, b), v.mul_lo32(a, b));
        prop_assert_eq!(o.mul_i32(c, d), v.mul_i32(c, d));
        prop_assert_eq!(o.shr_n::<7>(a), v.shr_n::<7>(a));
        prop_assert_eq!(o.shl_n::<24>(a), v.shl_n::<24>(a));
        prop_assert_eq!(o.shr32(b), v.shr32(b));
        prop_assert_eq!(o.shl32(b), v.shl32(b));
        let (mut p, mut w) = (LaneArith::new(o), LaneArith::new(v));
        prop_assert_eq!(p.mul(a, b), w.mul(a, b));
        prop_assert_eq!(
            p.dot([a, b, c, d], [d, c, b, a]),
            w.dot([a, b, c, d], [d, c, b, a])
        );
        prop_assert_eq!(p.dot([a, c], [b, d]), w.dot([a, c], [b, d]));
        prop_assert_eq!(p.left(), w.left());
        prop_assert_eq!(o.min(a, b), v.min(a, b));
        prop_assert_eq!(o.max(a, b), v.max(a, b));
        prop_assert_eq!(o.select(o.positive(c), a, b), v.select(v.positive(c), a, b));
        prop_assert_eq!(o.neg(d), v.neg(d));
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(5_000))]
        #[test]
        fn products_equal_reals(a in any_bits(), b in any_bits()) {
            check_mul(a, b)?;
        }

        #[test]
        fn dots_equal_reals(x in prop::array::uniform4(any_bits()), y in prop::array::uniform4(any_bits())) {
            check_dot(x, y)?;
        }

        /// The AVX2 operations give the portable ones' bits and records
        /// (where the processor has AVX2; elsewhere there is nothing to
        /// compare).
        #[test]
        fn avx2_equals_portable(
            a in prop::array::uniform4(any_bits()),
            b in prop::array::uniform4(any_bits()),
            c in prop::array::uniform4(any_bits()),
            d in prop::array::uniform4(any_bits()),
        ) {
            let Some(v) = tamias2d_simd::Avx2::new() else {
                return Ok(());
            };
            same_as_portable(v, [a, b, c, d])?;
        }

        /// Short factors skip the partial products that are 0: the bits
        /// and the records of the full products (either factor short, or
        /// both; and in dot products).
        #[test]
        fn short_factors_give_the_full_bits(
            a in prop::array::uniform4(any_bits()),
            b in prop::array::uniform4(-(1i64 << 32) + 1..(1i64 << 32)),
            c in prop::array::uniform4(-(1i64 << 32) + 1..(1i64 << 32)),
            d in prop::array::uniform4(any_bits()),
        ) {
            let (mut full, mut short) = (LaneArith::new(Portable), LaneArith::new(Portable));
            prop_assert!(is_short(&b) && is_short(&c));
            let (sb, sc) = (short.split::<true>(b), short.split::<true>(c));
            let (fa, fd) = (short.factor(a), short.factor(d));
            prop_assert_eq!(full.mul(a, b), short.mul_factors(&fa, &sb));
            prop_assert_eq!(full.mul(b, a), short.mul_factors(&sb, &fa));
            prop_assert_eq!(full.mul(b, c), short.mul_factors(&sb, &sc));
            prop_assert_eq!(
                full.dot([a, d, a, d], [b, c, c, b]),
                short.dot_factors(&[fa, fd, fa, fd], &[sb, sc, sc, sb])
            );
            prop_assert_eq!(full.dot([b, c], [c, b]), short.dot_factors(&[sb, sc], &[sc, sb]));
            prop_assert_eq!(full.left(), short.left());
            prop_assert_eq!((full.high, full.quotient), (short.high, short.quotient));
        }

        #[test]
        fn lanes_are_independent(a in prop::array::uniform4(any_bits()), b in prop::array::uniform4(any_bits())) {
            let mut ar = LaneArith::new(Portable);
            let got = ar.mul(a, b);
            let left = ar.left();
            for (((&x, &y), &g), &l) in a.iter().zip(&b).zip(&got).zip(&left) {
                let mut one = LaneArith::new(Portable);
                let [alone, ..] = one.mul([x, 0, 0, 0], [y, 0, 0, 0]);
                prop_assert_eq!(l, one.left()[0]);
                if !l {
                    prop_assert_eq!(g, alone);
                }
            }
        }
    }
}
