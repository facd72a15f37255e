//! `tamias2d-simd`'s AVX2 operations (the engine's one `unsafe` code)
//! against plain integer arithmetic on any lanes, and a kernel run through
//! `run_avx2` against the same kernel run directly. Nothing to check on a
//! processor without AVX2 but that `Avx2::new` says so.
#![no_main]

use libfuzzer_sys::fuzz_target;
use tamias2d_simd::{has_avx2, run_avx2, Avx2, Kernel, U64x4};

/// `f` lane by lane.
fn each(a: U64x4, b: U64x4, f: impl Fn(u64, u64) -> u64) -> U64x4 {
    let mut out = a;
    for (o, &y) in out.iter_mut().zip(&b) {
        *o = f(*o, y);
    }
    out
}

/// A kernel: products and sums of lanes, as the engine's lane arithmetic
/// makes them.
struct Mix(U64x4, U64x4, Option<Avx2>);

impl Kernel for Mix {
    type Output = U64x4;
    #[inline(always)]
    fn run(self) -> U64x4 {
        let Mix(a, b, v) = self;
        match v {
            Some(v) => v.add(v.mul_lo32(v.shr32(a), b), v.shl32(v.xor(a, b))),
            None => each(
                each(a.map(|x| x >> 32), b, |x, y| {
                    (x & 0xffff_ffff) * (y & 0xffff_ffff)
                }),
                each(a, b, |x, y| (x ^ y) << 32),
                u64::wrapping_add,
            ),
        }
    }
}

fuzz_target!(|lanes: [[u64; 4]; 3]| {
    let [a, b, m] = lanes;
    let Some(v) = Avx2::new() else {
        assert!(!has_avx2());
        return;
    };
    assert_eq!(v.add(a, b), each(a, b, u64::wrapping_add));
    assert_eq!(v.sub(a, b), each(a, b, u64::wrapping_sub));
    assert_eq!(v.xor(a, b), each(a, b, |x, y| x ^ y));
    assert_eq!(v.and(a, b), each(a, b, |x, y| x & y));
    assert_eq!(v.or(a, b), each(a, b, |x, y| x | y));
    assert_eq!(
        v.gt(a, b),
        each(a, b, |x, y| if (x as i64) > (y as i64) {
            u64::MAX
        } else {
            0
        })
    );
    assert_eq!(
        v.mul_lo32(a, b),
        each(a, b, |x, y| (x & 0xffff_ffff) * (y & 0xffff_ffff))
    );
    assert_eq!(v.shr32(a), a.map(|x| x >> 32));
    assert_eq!(v.shl32(a), a.map(|x| x << 32));
    // A mask of whole lanes (as the engine's comparisons make them).
    let mask = m.map(|x| if x & 1 == 1 { u64::MAX } else { 0 });
    assert_eq!(
        v.select(mask, a, b),
        each(
            each(a, mask, |x, k| x & k),
            each(b, mask, |y, k| y & !k),
            |x, y| x | y
        )
    );
    let direct = Mix(a, b, None).run();
    let wide = run_avx2(Mix(a, b, Some(v))).unwrap_or_else(Kernel::run);
    assert_eq!(wide, direct);
});
