//! What every contact pass kernel shares: which pass runs, how the lane
//! kernels are compiled, and where a pass reads and writes the bodies (in
//! place, or shared between threads).
#[cfg(not(all(target_arch = "wasm32", target_feature = "simd128")))]
use crate::math::lanes::Portable;
use crate::math::lanes::{Lane, Ops, LANES};
use crate::math::Real;
use crate::solver::{sweep, SolverBody};

use super::row::{Motion, SoftContact, SoftContactParams};

/// How the wide kernels are compiled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Compiled {
    /// For the build's instruction set.
    Portable,
    /// For AVX2 (the processor has it).
    Avx2,
}

/// Where a pass reads and writes the bodies: in place, or shared between
/// threads.
pub(super) trait BodyStore {
    /// The body in `slot` (`None` past the end).
    fn load(&self, slot: u32) -> Option<SolverBody>;
    /// Its new velocities.
    fn store(&mut self, slot: u32, body: &SolverBody);
    /// The raw bits of its velocities `[v.x, v.y, ω]` (`None` past the
    /// end): what the narrow kernels read, nothing more.
    fn velocities(&self, slot: u32) -> Option<[i64; 3]>;
    /// Its new velocities `[v.x, v.y, ω]`, raw bits.
    fn set_velocities(&mut self, slot: u32, v: [i64; 3]);
}

/// The bodies in place (one thread).
pub(super) struct InPlace<'a>(pub(super) &'a mut [SolverBody]);

impl BodyStore for InPlace<'_> {
    #[inline(always)]
    fn load(&self, slot: u32) -> Option<SolverBody> {
        self.0.get(slot as usize).copied()
    }
    #[inline(always)]
    fn store(&mut self, slot: u32, body: &SolverBody) {
        if let Some(b) = self.0.get_mut(slot as usize) {
            (b.v, b.w) = (body.v, body.w);
        }
    }
    #[inline(always)]
    fn velocities(&self, slot: u32) -> Option<[i64; 3]> {
        let b = self.0.get(slot as usize)?;
        Some([b.v.x.to_bits(), b.v.y.to_bits(), b.w.to_bits()])
    }
    #[inline(always)]
    fn set_velocities(&mut self, slot: u32, [x, y, w]: [i64; 3]) {
        if let Some(b) = self.0.get_mut(slot as usize) {
            b.v = crate::math::Vect::new(Real::from_bits(x), Real::from_bits(y));
            b.w = Real::from_bits(w);
        }
    }
}

/// The bodies threads share ([`sweep::SharedBody`]).
#[derive(Clone, Copy)]
pub(super) struct Shared<'a>(pub(super) &'a [sweep::SharedBody]);

impl BodyStore for Shared<'_> {
    #[inline(always)]
    fn load(&self, slot: u32) -> Option<SolverBody> {
        self.0.get(slot as usize).map(sweep::SharedBody::load)
    }
    #[inline(always)]
    fn store(&mut self, slot: u32, body: &SolverBody) {
        if let Some(b) = self.0.get(slot as usize) {
            b.store_velocities(body);
        }
    }
    #[inline(always)]
    fn velocities(&self, slot: u32) -> Option<[i64; 3]> {
        self.0
            .get(slot as usize)
            .map(sweep::SharedBody::velocity_bits)
    }
    #[inline(always)]
    fn set_velocities(&mut self, slot: u32, v: [i64; 3]) {
        if let Some(b) = self.0.get(slot as usize) {
            b.set_velocity_bits(v);
        }
    }
}

/// True for a body the solver moves (a nonzero inverse mass or moment);
/// the others come out of a pass unchanged and are not stored, so that
/// threads sharing one never write its cache line.
#[inline(always)]
pub(super) fn movable(b: &SolverBody) -> bool {
    !b.m_inv.is_zero() || !b.i_inv.is_zero()
}

/// Runs `f` on one manifold's rows with a copy of its two bodies from
/// `store`, and stores the movable ones back (nothing for a body paired
/// with itself, or a slot out of range): the in-place kernel's bits.
#[inline(always)]
pub(super) fn on_store<S: BodyStore>(
    rows: &mut [SoftContact],
    store: &mut S,
    f: impl FnOnce(&mut [SoftContact], &mut [SolverBody; 2]),
) {
    let Some(first) = rows.first() else {
        return;
    };
    let (ia, ib) = (first.a, first.b);
    if ia == ib {
        return;
    }
    let (Some(a), Some(b)) = (store.load(ia), store.load(ib)) else {
        return;
    };
    let mut copy = [a, b];
    f(rows, &mut copy);
    for (slot, body) in [ia, ib].into_iter().zip(&copy) {
        if movable(body) {
            store.store(slot, body);
        }
    }
}

/// Which pass.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Pass {
    WarmStart(Real),
    Solve(SoftContactParams, bool),
}

/// `values[lane] = v` (nothing past the end).
#[inline(always)]
pub(super) fn set<T>(values: &mut [T; LANES], lane: usize, v: T) {
    if let Some(slot) = values.get_mut(lane) {
        *slot = v;
    }
}

/// What a pass changes in a point's lanes: the separation, the
/// accumulated impulses and the largest normal impulse of the step (each
/// batch kind's own grid).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct PointState {
    pub(super) sep: Lane,
    pub(super) jn: Lane,
    pub(super) jt: Lane,
    pub(super) max_jn: Lane,
}

/// `new` where the lane did not leave, `old` where it did.
#[inline(always)]
pub(super) fn keep_left(old: PointState, new: PointState, left: &[bool; LANES]) -> PointState {
    let pick = |o: Lane, n: Lane| {
        let mut out = n;
        for ((x, &o), &l) in out.iter_mut().zip(&o).zip(left) {
            if l {
                *x = o;
            }
        }
        out
    };
    PointState {
        sep: pick(old.sep, new.sep),
        jn: pick(old.jn, new.jn),
        jt: pick(old.jt, new.jt),
        max_jn: pick(old.max_jn, new.max_jn),
    }
}

/// A batch of four manifolds the lane kernels run: the exact wide
/// kernels' or the narrow ones'.
pub(super) trait LaneBatch: Send {
    /// What every batch of a pass reads, computed once per pass (the
    /// pass's parameters on the batch kind's grids).
    type PassConstants: Copy;

    /// The [`PassConstants`](Self::PassConstants) of `pass`.
    fn pass_constants(pass: &Pass) -> Self::PassConstants;

    /// `pass` on this batch's manifolds on the lane operations `ops`,
    /// their bodies in `store` (`rows`: the step's rows, which a lane
    /// that leaves its window reruns from; `constants`: the pass's).
    #[allow(clippy::too_many_arguments)]
    fn run_pass<O: Ops, S: BodyStore>(
        &mut self,
        ops: O,
        pass: Pass,
        constants: Self::PassConstants,
        store: &mut S,
        rows: &[SoftContact],
        motion: &[Motion],
    );
}

/// `pass` on `batches`, in AVX2 instructions when the step chose them.
#[inline(always)]
pub(super) fn dispatch<S: BodyStore, B: LaneBatch>(
    compiled: Option<Compiled>,
    pass: Pass,
    batches: &mut [B],
    store: S,
    rows: &[SoftContact],
    motion: &[Motion],
) {
    use tamias2d_simd::Kernel;
    if batches.is_empty() {
        return;
    }
    let avx2 = match compiled {
        Some(Compiled::Avx2) => tamias2d_simd::Avx2::new(),
        Some(Compiled::Portable) | None => None,
    };
    match avx2 {
        // The same bits either way: `run_avx2` hands the job back only if
        // the processor lost AVX2 since the check, which it cannot.
        Some(ops) => {
            let job = BatchPass {
                ops,
                pass,
                batches,
                store,
                rows,
                motion,
            };
            tamias2d_simd::run_avx2(job).unwrap_or_else(Kernel::run);
        }
        None => BatchPass {
            ops: portable_ops(),
            pass,
            batches,
            store,
            rows,
            motion,
        }
        .run(),
    }
}

/// The lane operations of the build's instruction set: wasm's `simd128`
/// ones where the build has it (the compiler does not find its widening
/// products by itself), plain Rust elsewhere. The same bits.
#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
#[inline(always)]
fn portable_ops() -> crate::math::lanes::Wasm128 {
    crate::math::lanes::Wasm128::new()
}

/// [`portable_ops`] without `simd128`: the plain Rust lanes.
#[cfg(not(all(target_arch = "wasm32", target_feature = "simd128")))]
#[inline(always)]
fn portable_ops() -> Portable {
    Portable
}

/// One pass over batches on the lane operations `O`: the kernel
/// `tamias2d_simd` compiles for AVX2.
struct BatchPass<'a, O: Ops, S: BodyStore, B: LaneBatch> {
    ops: O,
    pass: Pass,
    batches: &'a mut [B],
    store: S,
    rows: &'a [SoftContact],
    motion: &'a [Motion],
}

impl<O: Ops, S: BodyStore, B: LaneBatch> tamias2d_simd::Kernel for BatchPass<'_, O, S, B> {
    type Output = ();

    #[inline(always)]
    fn run(self) {
        let BatchPass {
            ops,
            pass,
            batches,
            mut store,
            rows,
            motion,
        } = self;
        let constants = B::pass_constants(&pass);
        for batch in batches {
            batch.run_pass(ops, pass, constants, &mut store, rows, motion);
        }
    }
}
