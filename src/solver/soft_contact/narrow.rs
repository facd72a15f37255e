//! The narrow contact kernels: the soft contact passes with every lane
//! value in 32 bits, so that each product is one signed 32×32→64-bit
//! multiply (`vpmuldq`, four lanes an instruction) instead of the exact
//! kernels' four partial products: the
//! [`ContactPrecision::Narrow`](crate::space::ContactPrecision::Narrow)
//! setting, whose grids `docs/numerics.md` states ("The narrow contact
//! kernels").
//!
//! The grids (fraction bits): velocities read by a row on Q16.16 (from
//! the bodies' velocities, which a pass keeps on 48 fraction bits so that
//! an impulse times a gain adds to them exactly); the normal, lever arms,
//! `n·r` and the separation a bias reads on Q8.24; a manifold's impulses
//! on Q(8+k).(24−k) and its gains (`m⁻¹·n`, `I⁻¹ (r × d)`) on
//! Q(8−k).(24+k), for its impulse shift `k` (0 but in heavy piles,
//! [`impulse_shift`], and for small light bodies, [`light_shift`]);
//! effective masses (divided by `2^k`), the bias rate
//! and `1/h` on Q16.16; friction and the impulse scale on Q2.30. Sums of
//! products are exact in 64 bits and round once, to nearest with ties
//! away from zero, as every rounding of the engine (symmetric under
//! negation). Between passes the accumulated impulses stay on their grid.
//!
//! Every value the proofs bound is checked: a manifold whose constants
//! leave their windows runs the exact kernel for the whole step, and one
//! whose velocities, impulses or separations leave theirs in a pass is
//! run again by the exact kernel from its state before that pass (as the
//! exact wide kernels do), then gathered again on a coarser impulse grid
//! if its impulses outgrew its own ([`widen_impulse_grid`]). The windows:
//! body velocities below 1,024 m/s (and rad/s) at a pass's start,
//! separations a bias reads below 64 m, and each manifold's impulses below
//! `min(2^29, 2^59/G)` grid units, where `G` is its largest gain in grid
//! units (for `k = 0`: `min(32, 2^11/G)` N·s, `G` in 1/kg): then a pass
//! changes a velocity by under `2^13` m/s in all, the 48-bit velocities
//! stay below `2^62` and every Q16.16 read fits 32 bits.
//!
//! The kernel is written once over [`Ops`]: the portable lanes are the
//! reference, the AVX2 lanes give their bits (the operations are integer
//! ones), and every manifold that can join a batch runs in lanes (a
//! color's last batch and the overflow color's manifolds with empty
//! lanes), so the bits do not depend on which instructions run.
use crate::math::exact::wide_mul;
use crate::math::lanes::{splat, Lane, Ops, LANES};
use crate::math::Real;
use crate::solver::SolverBody;

use super::pass::{keep_left, movable, on_store, set, BodyStore, LaneBatch, Pass, PointState};
use super::row::{solve_manifold, warm_start_manifold, Motion, SoftContact, SoftContactParams};

/// One point of four manifolds on the narrow grids.
#[derive(Clone, Copy, Debug, Default)]
struct NarrowPoint {
    /// The normal, the lever arms across it and the tangent (`r × n`,
    /// `r × t`) and `n·r` on Q8.24; `I⁻¹ (r × d)` on the gains' grid.
    n_x: Lane,
    n_y: Lane,
    rn_a: Lane,
    rn_b: Lane,
    rt_a: Lane,
    rt_b: Lane,
    nr_a: Lane,
    nr_b: Lane,
    kn_a: Lane,
    kn_b: Lane,
    kt_a: Lane,
    kt_b: Lane,
    /// The effective masses, and the normal's times the soft mass scale:
    /// Q16.16.
    n_mass: Lane,
    n_mass_soft: Lane,
    t_mass: Lane,
    /// Q2.30.
    friction: Lane,
    /// The tangential surface speed, on 40 fraction bits (a sum's).
    surface_t: Lane,
    /// The separation at the collide (`Real` bits).
    dist: Lane,
    state: PointState,
}

/// Four manifolds of one color on the narrow grids.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct NarrowBatch {
    a: [u32; LANES],
    b: [u32; LANES],
    first: [u32; LANES],
    count: [u32; LANES],
    points_used: usize,
    /// The gains `m⁻¹·n` of both bodies (Q(8−k).(24+k) for each lane's
    /// impulse shift `k`); the tangent's are the
    /// same values, swapped and one negated.
    ga_x: Lane,
    ga_y: Lane,
    gb_x: Lane,
    gb_y: Lane,
    /// Every lane's two gains are equal (a pile of like bodies).
    same_gains: bool,
    /// Each lane's impulse shift `k`: its impulses on Q(8+k).(24−k)
    /// (heavy piles: [`impulse_shift`]; small light bodies:
    /// [`light_shift`]).
    impulse_shift: [i32; LANES],
    /// Q2.30 and Q16.16.
    impulse_scale: Lane,
    bias_rate: Lane,
    /// The impulse window (on the lane's impulse grid): a normal impulse below it, a friction
    /// bound at most half of it.
    limit: Lane,
    /// Lanes whose constants left their windows: the exact kernel runs
    /// them in every pass.
    exact: [bool; LANES],
    /// Each lane's bodies the solver moves (a nonzero inverse mass or
    /// moment, for the step): only those are stored back.
    moves_a: [bool; LANES],
    moves_b: [bool; LANES],
    points: [NarrowPoint; 2],
}

/// `x / 2^s` rounded to nearest, ties away from zero (`s` in `1..=63`).
#[cfg(test)]
fn round_bits(x: i128, s: u32) -> i128 {
    let half = 1u128.checked_shl(s.saturating_sub(1)).unwrap_or(0);
    let m = x
        .unsigned_abs()
        .saturating_add(half)
        .checked_shr(s)
        .unwrap_or(0);
    let m = i128::try_from(m).unwrap_or(i128::MAX);
    if x < 0 {
        m.saturating_neg()
    } else {
        m
    }
}

/// Builds lane values and remembers whether one left its window.
struct Fit {
    ok: bool,
}

impl Fit {
    /// `x` (raw bits) rounded by `s` bits (in `1..=32`), if the result is
    /// a 32-bit lane value: [`round_bits`] in 64 bits.
    #[inline(always)]
    fn narrow(&mut self, x: i64, s: u32) -> i64 {
        let half = 1u64.wrapping_shl(s.wrapping_sub(1));
        let m = x.unsigned_abs().saturating_add(half).wrapping_shr(s);
        self.signed_lane(m, x < 0)
    }

    /// The magnitude `m` with the sign `negative`, if below `2^31`.
    #[inline(always)]
    fn signed_lane(&mut self, m: u64, negative: bool) -> i64 {
        if m >> 31 != 0 {
            self.ok = false;
            return 0;
        }
        // m < 2^31: the cast and the negation are exact.
        let m = m as i64;
        if negative {
            m.wrapping_neg()
        } else {
            m
        }
    }

    /// The product of two `Real`s' raw bits (64 fraction bits) rounded
    /// by `s` bits (in `1..=63`), if a 32-bit lane value: [`round_bits`]
    /// of the exact product, whose magnitude (at most `2^126`) leaves
    /// room for the half.
    #[inline(always)]
    fn product(&mut self, a: Real, b: Real, s: u32) -> i64 {
        let p = wide_mul(a.to_bits(), b.to_bits());
        let half = 1u128.wrapping_shl(s.wrapping_sub(1));
        let m = p.unsigned_abs().wrapping_add(half).wrapping_shr(s);
        if m >> 31 != 0 {
            self.ok = false;
            return 0;
        }
        // m < 2^31: the cast and the negation are exact.
        let m = m as i64;
        if p < 0 {
            m.wrapping_neg()
        } else {
            m
        }
    }

    /// `v` if its magnitude is below `2^31`.
    #[cfg(test)]
    fn fits(&mut self, v: i128) -> i64 {
        self.within(v, 31)
    }

    /// `v` if its magnitude is below `2^bits`.
    #[inline(always)]
    fn within(&mut self, v: i128, bits: u32) -> i64 {
        let limit = 1u128.checked_shl(bits).unwrap_or(0);
        if v.unsigned_abs() >= limit {
            self.ok = false;
            return 0;
        }
        i64::try_from(v).unwrap_or(0)
    }
}

/// The largest impulse window (Q8.24, 32 N·s).
const LIMIT_MAX: i64 = 1 << 29;
/// The velocity change a manifold's impulse window allows per product
/// (48 fraction bits): four such changes and the velocities' window keep
/// every 48-bit velocity below `2^62`.
const CHANGE_MAX: i64 = 1 << 59;

/// The largest gain whose window is [`LIMIT_MAX`] (`2^30`, Q8.24).
const FULL_WINDOW_GAIN: i64 = CHANGE_MAX / LIMIT_MAX;

/// A manifold's impulse window from its largest gain (Q8.24 both). A
/// gain of at most `2^30` (64 /kg) gets the largest window without the
/// division (`2^59 / 2^30` is that window already): the division's
/// latency was a tenth of the gather's time.
#[inline(always)]
fn impulse_limit(gain: i64) -> i64 {
    if gain <= FULL_WINDOW_GAIN {
        return LIMIT_MAX;
    }
    CHANGE_MAX
        .checked_div(gain.max(1))
        .unwrap_or(LIMIT_MAX)
        .min(LIMIT_MAX)
}

/// An impulse (`Real` bits) on the lane grid of impulse shift `k` (in
/// `MIN_IMPULSE_SHIFT..=MAX_IMPULSE_SHIFT`), Q(8+k).(24−k): [`round_bits`]
/// by `8 + k` bits (at least 1), in 64 bits (a magnitude of at most
/// `2^63` leaves room for the half).
#[inline(always)]
fn impulse_bits(j: Real, k: i32) -> i64 {
    let x = j.to_bits();
    let s = 8i32.wrapping_add(k) as u32;
    let half = 1u64.wrapping_shl(s.wrapping_sub(1));
    let m = x.unsigned_abs().wrapping_add(half).wrapping_shr(s);
    // m ≤ 2^55: the cast and the negation are exact.
    let m = m as i64;
    if x < 0 {
        m.wrapping_neg()
    } else {
        m
    }
}

/// An impulse on the lane grid of impulse shift `k` as a `Real`.
fn impulse_real(j: i64, k: i32) -> Real {
    let unit = 1i64.wrapping_shl(8i32.wrapping_add(k) as u32);
    Real::from_bits(j.saturating_mul(unit))
}

/// The largest impulse shift: impulses up to `2^7` times the window of
/// Q8.24 (4,096 N·s), the gains `I⁻¹ (r × d)` then on Q1.31 (each at
/// most `2^30` for a full window, so they fit).
const MAX_IMPULSE_SHIFT: i32 = 7;

/// The least impulse shift: gains up to `2^14` (`I⁻¹ (r × d)` of a
/// 2.5 cm box of 10 g), then on Q15.17, the impulses on Q1.31.
const MIN_IMPULSE_SHIFT: i32 = -7;

/// The impulse shift of a manifold from its warm-start impulses (the
/// largest one's complement magnitudes of the normal and the tangent
/// ones, on Q8.24) and its largest gain `gain` (Q8.24): the least `k`
/// whose grid holds them at half the window and the tangent at a quarter
/// (room for the step's growth, as a pass checks them against the window
/// and half of it: [`check_state`]); [`MAX_IMPULSE_SHIFT`] if none does.
/// Given on the grids of a shift `j` instead, the shift to add to `j`.
/// A shift gains only while the gains times `2^k` stay at most
/// [`FULL_WINDOW_GAIN`]: past that the window in newtons·seconds is the
/// gain's, whatever `k`.
fn impulse_shift(jn: i64, jt: i64, gain: i64) -> i32 {
    (0..=MAX_IMPULSE_SHIFT)
        .find(|&k| {
            let limit = impulse_limit(gain.saturating_mul(1i64.wrapping_shl(k as u32)));
            let fits = |j: i64, room: u32| {
                j.unsigned_abs().wrapping_shr(k as u32) < (limit >> room) as u64
            };
            fits(jn, 1) && fits(jt, 2)
        })
        .unwrap_or(MAX_IMPULSE_SHIFT)
}

/// The impulse shift of a manifold whose gains leave Q8.24 (`m⁻¹` or
/// `I⁻¹ (r × d)` of 128 or more: small light bodies, as a 25 cm box of
/// 62.5 g): the negative `k` nearest 0 whose grid Q(8−k).(24+k) holds its
/// largest gain, its impulses then on the finer Q(8+k).(24−k) (they are
/// small: the bodies are light); `None` if the gains fit Q8.24 (the
/// manifold left its window for another reason) or no shift down to
/// [`MIN_IMPULSE_SHIFT`] holds them.
fn light_shift(first: &SoftContact, points: &[SoftContact]) -> Option<i32> {
    let mut gain = first.m_inv_a.abs().max(first.m_inv_b.abs());
    for row in points {
        for g in [row.kn_a, row.kn_b, row.kt_a, row.kt_b] {
            gain = gain.max(g.abs());
        }
    }
    // `2^(7+j)`: the gains below it are below 2^31 units of
    // Q(8+j).(24−j), the grid of shift −j.
    let bound = |j: u32| Real::from_bits(1i64.wrapping_shl(39u32.wrapping_add(j)));
    if gain < bound(0) {
        return None;
    }
    (1..=MIN_IMPULSE_SHIFT.unsigned_abs())
        .find(|&j| gain < bound(j))
        .map(|j| (j as i32).wrapping_neg())
}

/// The lanes of four manifolds' rows (`(start, end)` each; an empty lane,
/// `start` past the rows, has no bodies and applies nothing) into
/// `batch`, which holds `NarrowBatch::default()`.
pub(super) fn gather_narrow(
    batch: &mut NarrowBatch,
    manifolds: [(u32, u32); LANES],
    rows: &[SoftContact],
    bodies: &[SolverBody],
) {
    batch.a = [u32::MAX; LANES];
    batch.b = [u32::MAX; LANES];
    batch.limit = splat(LIMIT_MAX);
    // Whether a body moves under the solver, and whether it is still: it
    // cannot move and does not turn (the ground, a kinematic body without
    // spin). A still body's lever arms only ever multiply its zero angular
    // velocity, its zero turn since the collide and its zero `I⁻¹`, so its
    // lanes hold 0 for them, the products' exact value, and a far anchor
    // (a large static body's) does not leave the window.
    let motion = |slot: u32| match bodies.get(slot as usize) {
        Some(b) if movable(b) => (true, false),
        Some(b) => (false, b.w.is_zero() && b.w_bias.is_zero()),
        None => (false, true),
    };
    for (lane, &(start, end)) in manifolds.iter().enumerate() {
        let Some(first) = rows.get(start as usize) else {
            continue;
        };
        let count = end.wrapping_sub(start);
        let ((moves_a, still_a), (moves_b, still_b)) = (motion(first.a), motion(first.b));
        set(&mut batch.a, lane, first.a);
        set(&mut batch.b, lane, first.b);
        set(&mut batch.moves_a, lane, moves_a);
        set(&mut batch.moves_b, lane, moves_b);
        set(&mut batch.first, lane, start);
        set(&mut batch.count, lane, count);
        batch.points_used = batch.points_used.max(count as usize).min(2);
        let points = rows.get(start as usize..end as usize).unwrap_or(&[]);
        let still = [still_a, still_b];
        let lane_fit = gather_lane(batch, lane, (first, points), 0, still);
        // Warm-start impulses past half the Q8.24 window: the manifold's
        // impulses go to a coarser grid, its gains to a finer one.
        let ok = match lane_fit {
            LaneFit::Heavy { gain, jn, jt } => {
                let k = impulse_shift(jn, jt, gain);
                !matches!(
                    gather_lane(batch, lane, (first, points), k, still),
                    LaneFit::Out
                )
            }
            LaneFit::Fits => true,
            // Gains past Q8.24 (small light bodies): a finer grid for the
            // impulses, a coarser one for the gains. A manifold that
            // leaves its windows there too runs the exact kernel from
            // the Q8.24 grid, as any other.
            LaneFit::Out => match light_shift(first, points) {
                Some(k) => {
                    let shifted = gather_lane(batch, lane, (first, points), k, still);
                    let fits = !matches!(shifted, LaneFit::Out);
                    if !fits {
                        gather_lane(batch, lane, (first, points), 0, still);
                    }
                    fits
                }
                None => false,
            },
        };
        set(&mut batch.exact, lane, !ok);
    }
    batch.same_gains = batch.ga_x == batch.gb_x && batch.ga_y == batch.gb_y;
}

/// What [`gather_lane`] found of a lane's values.
enum LaneFit {
    /// Every value in its window, the warm-start impulses within half of
    /// it (the tangent one within a quarter).
    Fits,
    /// Every value in its window but the warm-start impulses, which are
    /// past half of it: the largest gain and the largest one's complement
    /// magnitudes of the normal and the tangent impulses, on their grids
    /// ([`impulse_shift`]'s inputs).
    Heavy { gain: i64, jn: i64, jt: i64 },
    /// A constant out of its window: the exact kernel's lane.
    Out,
}

/// One lane's values from its manifold's rows (`first` is `points[0]`)
/// with impulse shift `k`: the impulses on Q(8+k).(24−k), the gains and
/// `I⁻¹ (r × d)` on Q(8−k).(24+k), the effective masses divided by `2^k`
/// on Q16.16, so that every product of an impulse keeps its grid. The
/// lever arms of a body `still` (a and b) are 0.
#[inline(always)]
fn gather_lane(
    batch: &mut NarrowBatch,
    lane: usize,
    (first, points): (&SoftContact, &[SoftContact]),
    k: i32,
    [still_a, still_b]: [bool; 2],
) -> LaneFit {
    set(&mut batch.impulse_shift, lane, k);
    let mut fit = Fit { ok: true };
    let n = first.n;
    // A pile's bodies often share their inverse mass, and a static
    // body's is 0 (exact zero gains): those products are not redone.
    let gain = |m_inv: Real, fit: &mut Fit| {
        if m_inv.is_zero() {
            [0, 0]
        } else {
            let s = 40i32.wrapping_sub(k) as u32;
            [fit.product(n.x, m_inv, s), fit.product(n.y, m_inv, s)]
        }
    };
    let [ga_x, ga_y] = gain(first.m_inv_a, &mut fit);
    let [gb_x, gb_y] = if first.m_inv_b == first.m_inv_a {
        [ga_x, ga_y]
    } else {
        gain(first.m_inv_b, &mut fit)
    };
    let gains = [ga_x, ga_y, gb_x, gb_y];
    set(&mut batch.ga_x, lane, ga_x);
    set(&mut batch.ga_y, lane, ga_y);
    set(&mut batch.gb_x, lane, gb_x);
    set(&mut batch.gb_y, lane, gb_y);
    let soft = first.soft;
    let impulse_scale = fit.narrow(soft.impulse_scale.to_bits(), 2);
    set(&mut batch.impulse_scale, lane, impulse_scale);
    // Below 2^12 /s: a bias of at most 2^58 (40 fraction bits).
    let bias_rate = fit.narrow(soft.bias_rate.to_bits(), 16);
    fit.within(i128::from(bias_rate), 28);
    set(&mut batch.bias_rate, lane, bias_rate);
    let mut gain = gains.iter().map(|g| g.saturating_abs()).max().unwrap_or(0);
    let mass_shift = 16i32.wrapping_add(k) as u32;
    let (mut jn_max, mut jt_max) = (0i64, 0i64);
    for (point, row) in batch.points.iter_mut().zip(points) {
        let arm = |v: Real, fit: &mut Fit| fit.narrow(v.to_bits(), 8);
        set(&mut point.n_x, lane, arm(row.n.x, &mut fit));
        set(&mut point.n_y, lane, arm(row.n.y, &mut fit));
        let arms = |r: [Real; 3], still: bool, fit: &mut Fit| {
            if still {
                [0; 3]
            } else {
                r.map(|v| arm(v, fit))
            }
        };
        let [rn_a, rt_a, nr_a] = arms([row.rn_a, row.rt_a, row.nr_a], still_a, &mut fit);
        let [rn_b, rt_b, nr_b] = arms([row.rn_b, row.rt_b, row.nr_b], still_b, &mut fit);
        set(&mut point.rn_a, lane, rn_a);
        set(&mut point.rn_b, lane, rn_b);
        set(&mut point.rt_a, lane, rt_a);
        set(&mut point.rt_b, lane, rt_b);
        set(&mut point.nr_a, lane, nr_a);
        set(&mut point.nr_b, lane, nr_b);
        let ks = [row.kn_a, row.kn_b, row.kt_a, row.kt_b]
            .map(|v| fit.narrow(v.to_bits(), 8i32.wrapping_sub(k) as u32));
        for k in ks {
            gain = gain.max(k.saturating_abs());
        }
        let [kn_a, kn_b, kt_a, kt_b] = ks;
        set(&mut point.kn_a, lane, kn_a);
        set(&mut point.kn_b, lane, kn_b);
        set(&mut point.kt_a, lane, kt_a);
        set(&mut point.kt_b, lane, kt_b);
        set(
            &mut point.n_mass,
            lane,
            fit.narrow(row.n_mass.to_bits(), mass_shift),
        );
        let soft_mass = fit.product(row.n_mass, soft.mass_scale, 48i32.wrapping_add(k) as u32);
        set(&mut point.n_mass_soft, lane, soft_mass);
        set(
            &mut point.t_mass,
            lane,
            fit.narrow(row.t_mass.to_bits(), mass_shift),
        );
        set(
            &mut point.friction,
            lane,
            fit.narrow(row.friction.to_bits(), 2),
        );
        // Below 2^52 raw: 2^60 on 40 fraction bits.
        let surface = fit.within(i128::from(row.surface_t.to_bits()), 52);
        set(&mut point.surface_t, lane, surface.wrapping_shl(8));
        set(
            &mut point.dist,
            lane,
            fit.within(i128::from(row.dist.to_bits()), 61),
        );
        let s = &mut point.state;
        let (jn, jt) = (impulse_bits(row.jn, k), impulse_bits(row.jt, k));
        let oc = |x: i64| x ^ (x >> 63);
        (jn_max, jt_max) = (jn_max.max(oc(jn)), jt_max.max(oc(jt)));
        set(&mut s.sep, lane, row.sep.to_bits());
        set(&mut s.jn, lane, jn);
        set(&mut s.jt, lane, jt);
        set(&mut s.max_jn, lane, impulse_bits(row.max_jn, k));
    }
    let limit = impulse_limit(gain);
    set(&mut batch.limit, lane, limit);
    if !fit.ok {
        LaneFit::Out
    } else if jn_max < limit >> 1 && jt_max < limit >> 2 {
        LaneFit::Fits
    } else {
        LaneFit::Heavy {
            gain,
            jn: jn_max,
            jt: jt_max,
        }
    }
}

/// The batch's state back into its rows, `rows` beginning at row `base`.
pub(super) fn put_narrow(batch: &NarrowBatch, rows: &mut [SoftContact], base: u32) {
    for lane in 0..LANES {
        let start = batch.first.get(lane).copied().unwrap_or(0);
        let start = start.wrapping_sub(base) as usize;
        let count = batch.count.get(lane).copied().unwrap_or(0) as usize;
        let Some(out) = rows.get_mut(start..start.saturating_add(count)) else {
            continue;
        };
        let k = batch.impulse_shift.get(lane).copied().unwrap_or(0);
        for (row, point) in out.iter_mut().zip(&batch.points) {
            let s = &point.state;
            let at = |v: &Lane| v.get(lane).copied().unwrap_or(0);
            row.sep = Real::from_bits(at(&s.sep));
            row.jn = impulse_real(at(&s.jn), k);
            row.jt = impulse_real(at(&s.jt), k);
            row.max_jn = impulse_real(at(&s.max_jn), k);
        }
    }
}

/// Warm starting off: every accumulated impulse starts from 0.
pub(super) fn zero_narrow(batch: &mut NarrowBatch) {
    for point in &mut batch.points {
        point.state.jn = splat(0);
        point.state.jt = splat(0);
    }
}

/// `x / 2^S` to nearest, ties away from zero, in every lane: the floor
/// of `(x + 2^(S−1) − [x < 0]) / 2^S`, the arithmetic shift made of a
/// logical one on `x + 2^63`. Exact where `|x| < 2^63 − 2^S`.
#[inline(always)]
fn round_full<O: Ops, const S: i32>(o: O, x: Lane) -> Lane {
    let half = 1i64.wrapping_shl((S as u32).wrapping_sub(1));
    let t = o.add(o.add(x, splat(half.wrapping_add(i64::MIN))), o.sign(x));
    let offset = 1i64.wrapping_shl(63u32.wrapping_sub(S as u32));
    o.sub(o.shr_n::<S>(t), splat(offset))
}

/// [`round_full`]'s low 32 bits (all a product reads), for `S ≤ 32` and
/// a result that fits 32 bits: one operation fewer.
#[inline(always)]
fn round_low<O: Ops, const S: i32>(o: O, x: Lane) -> Lane {
    let half = 1i64.wrapping_shl((S as u32).wrapping_sub(1));
    o.shr_n::<S>(o.add(o.add(x, splat(half)), o.sign(x)))
}

/// Four bodies' velocities on 48 fraction bits.
#[derive(Clone, Copy, Debug)]
struct Velocities {
    vx: Lane,
    vy: Lane,
    w: Lane,
}

/// Velocities at a pass's start below `2^42` raw (1,024 m/s).
const VELOCITY_BITS: i32 = 42;

impl Velocities {
    /// The bodies of `slots` from `store`; `rec` records every lane whose
    /// velocities leave the window.
    #[inline(always)]
    fn gather<O: Ops, S: BodyStore>(
        o: O,
        store: &S,
        slots: &[u32; LANES],
        rec: &mut Lane,
    ) -> Velocities {
        let v = slots.map(|slot| store.velocities(slot).unwrap_or([0; 3]));
        let vx = v.map(|[x, _, _]| x);
        let vy = v.map(|[_, y, _]| y);
        let w = v.map(|[_, _, r]| r);
        for v in [vx, vy, w] {
            *rec = record::<O, VELOCITY_BITS>(o, *rec, v, o.sign(v));
        }
        Velocities {
            vx: o.shl_n::<16>(vx),
            vy: o.shl_n::<16>(vy),
            w: o.shl_n::<16>(w),
        }
    }

    /// The bodies of the lanes not `left` that `moves` back into `store`.
    #[inline(always)]
    fn scatter<O: Ops, S: BodyStore>(
        &self,
        o: O,
        store: &mut S,
        slots: &[u32; LANES],
        moves: &[bool; LANES],
        left: &[bool; LANES],
    ) {
        let vx = round_full::<O, 16>(o, self.vx);
        let vy = round_full::<O, 16>(o, self.vy);
        let w = round_full::<O, 16>(o, self.w);
        let lanes = slots.iter().zip(moves).zip(left).zip(vx).zip(vy).zip(w);
        for (((((&slot, &m), &l), x), y), r) in lanes {
            if m && !l {
                store.set_velocities(slot, [x, y, r]);
            }
        }
    }

    /// The Q16.16 reads of a row: `(Δv_x, Δv_y, ω_b, ω_a)` of b against a.
    #[inline(always)]
    fn reads<O: Ops>(o: O, a: &Velocities, b: &Velocities) -> [Lane; 4] {
        [
            round_low::<O, 32>(o, o.sub(b.vx, a.vx)),
            round_low::<O, 32>(o, o.sub(b.vy, a.vy)),
            round_low::<O, 32>(o, b.w),
            round_low::<O, 32>(o, a.w),
        ]
    }
}

/// An impulse `j` (Q(8+k).(24−k)) on both bodies along the gains `(g_x, g_y)`
/// and angular terms `k` of each: b gains, a loses.
#[inline(always)]
fn apply<O: Ops>(
    o: O,
    [a, b]: &mut [Velocities; 2],
    j: Lane,
    ga: [Lane; 2],
    gb: [Lane; 2],
    k: [Lane; 2],
    same: bool,
) {
    let [ga_x, ga_y] = ga;
    let [gb_x, gb_y] = gb;
    let [ka, kb] = k;
    let dax = o.mul_i32(j, ga_x);
    let day = o.mul_i32(j, ga_y);
    let (dbx, dby) = if same {
        (dax, day)
    } else {
        (o.mul_i32(j, gb_x), o.mul_i32(j, gb_y))
    };
    a.vx = o.sub(a.vx, dax);
    a.vy = o.sub(a.vy, day);
    a.w = o.sub(a.w, o.mul_i32(j, ka));
    b.vx = o.add(b.vx, dbx);
    b.vy = o.add(b.vy, dby);
    b.w = o.add(b.w, o.mul_i32(j, kb));
}

/// A lane of `rec` nonzero where `|x| ≥ 2^N` (one's complement: the
/// magnitude check of every window in the engine).
#[inline(always)]
fn record<O: Ops, const N: i32>(o: O, rec: Lane, x: Lane, sign: Lane) -> Lane {
    o.or(rec, o.shr_n::<N>(o.xor(x, sign)))
}

/// A velocity sum (40 fraction bits) as a Q16.16 read, recorded in `rec`
/// unless below `2^54` (the read then below `2^30`).
#[inline(always)]
fn velocity_read<O: Ops>(o: O, x: Lane, rec: &mut Lane) -> Lane {
    let sign = o.sign(x);
    *rec = record::<O, 54>(o, *rec, x, sign);
    o.shr_n::<24>(o.add(o.add(x, splat(1 << 23)), sign))
}

/// The per-pass values every lane shares, on their grids: `1/h`
/// (Q16.16, below `2^12`), the slop (Q8.24, below 64 m) and the push-out
/// speed's negation (40 fraction bits, below `2^55` raw).
type Uniform = (Lane, Lane, Lane);

/// A solve's [`Uniform`] values, if they fit their grids.
fn uniform(p: &SoftContactParams) -> Option<Uniform> {
    let mut fit = Fit { ok: true };
    let h_inv = fit.narrow(p.h_inv.to_bits(), 16);
    fit.within(i128::from(h_inv), 28);
    let slop = fit.narrow(p.slop.to_bits(), 8);
    fit.within(i128::from(slop), 30);
    let push = fit.within(i128::from(p.push_out.to_bits()), 55);
    fit.ok.then(|| {
        (
            splat(h_inv),
            splat(slop),
            splat(push.wrapping_shl(8).wrapping_neg()),
        )
    })
}

/// Lanes whose accumulated impulses leave the window (`|jn|` at or above
/// the limit, `|jt|` above half of it) in `rec`.
#[inline(always)]
fn check_state<O: Ops>(o: O, batch: &NarrowBatch, state: &[PointState; 2], rec: &mut Lane) {
    let below = o.sub(batch.limit, splat(1));
    let half = o.shr_n::<1>(batch.limit);
    for s in state.iter().take(batch.points_used) {
        let jn = o.xor(s.jn, o.sign(s.jn));
        let jt = o.xor(s.jt, o.sign(s.jt));
        *rec = o.or(*rec, o.or(o.gt(jn, below), o.gt(jt, half)));
    }
}

/// The warm start of a batch; returns how many lanes ran the exact kernel.
#[inline(always)]
fn warm_start_narrow<O: Ops, S: BodyStore>(
    o: O,
    batch: &mut NarrowBatch,
    store: &mut S,
    rows: &[SoftContact],
    dt_coef: Real,
) -> usize {
    if dt_coef != Real::ONE {
        // The first sub-step after a change of time step (rare): the
        // products of `Real`, back on the grid.
        for pt in &mut batch.points {
            let (jn, jt) = (&mut pt.state.jn, &mut pt.state.jt);
            for ((n, t), &k) in jn.iter_mut().zip(jt).zip(&batch.impulse_shift) {
                for v in [n, t] {
                    *v = impulse_bits(impulse_real(*v, k) * dt_coef, k);
                }
            }
        }
    }
    let bad = batch.exact;
    let mut rec = splat(0);
    let a = Velocities::gather(o, store, &batch.a, &mut rec);
    let b = Velocities::gather(o, store, &batch.b, &mut rec);
    let state = batch.points.map(|p| p.state);
    check_state(o, batch, &state, &mut rec);
    let mut v = [a, b];
    let same = batch.same_gains;
    for pt in batch.points.iter().take(batch.points_used) {
        let (jn, jt) = (pt.state.jn, pt.state.jt);
        apply(
            o,
            &mut v,
            jn,
            [batch.ga_x, batch.ga_y],
            [batch.gb_x, batch.gb_y],
            [pt.kn_a, pt.kn_b],
            same,
        );
        // Along the tangent `(−n_y, n_x)`: the gains swapped, one negated.
        apply(
            o,
            &mut v,
            jt,
            [o.neg(batch.ga_y), batch.ga_x],
            [o.neg(batch.gb_y), batch.gb_x],
            [pt.kt_a, pt.kt_b],
            same,
        );
    }
    finish(
        o,
        batch,
        store,
        v,
        left_of(bad, &rec),
        |m, copy| {
            warm_start_manifold(m, copy);
        },
        rows,
    )
}

/// The lanes `bad` or whose record `rec` is set.
#[inline(always)]
fn left_of(mut bad: [bool; LANES], rec: &Lane) -> [bool; LANES] {
    for (l, &r) in bad.iter_mut().zip(rec) {
        *l |= r != 0;
    }
    bad
}

/// The end of a batch's pass: the lanes not `left` stored, the others run
/// again by the exact kernel `f` from their state before the pass;
/// returns how many.
#[inline(always)]
fn finish<O: Ops, S: BodyStore>(
    o: O,
    batch: &mut NarrowBatch,
    store: &mut S,
    [a, b]: [Velocities; 2],
    left: [bool; LANES],
    f: impl FnMut(&mut [SoftContact], &mut [SolverBody; 2]),
    rows: &[SoftContact],
) -> usize {
    a.scatter(o, store, &batch.a, &batch.moves_a, &left);
    b.scatter(o, store, &batch.b, &batch.moves_b, &left);
    if left.contains(&true) {
        rerun_exact(batch, store, &left, f, rows)
    } else {
        0
    }
}

/// The lanes `left`, run by the exact kernel `f` on their rows with the
/// batch's state (from before the pass), which takes theirs back.
#[cold]
#[inline(never)]
fn rerun_exact<S: BodyStore>(
    batch: &mut NarrowBatch,
    store: &mut S,
    left: &[bool; LANES],
    mut f: impl FnMut(&mut [SoftContact], &mut [SolverBody; 2]),
    rows: &[SoftContact],
) -> usize {
    let mut count = 0usize;
    for (lane, _) in left.iter().enumerate().filter(|(_, &l)| l) {
        let start = batch.first.get(lane).copied().unwrap_or(0) as usize;
        let n = batch.count.get(lane).copied().unwrap_or(0) as usize;
        let Some(src) = rows.get(start..start.saturating_add(n)) else {
            continue;
        };
        count = count.saturating_add(1);
        let k = batch.impulse_shift.get(lane).copied().unwrap_or(0);
        let mut m = [SoftContact::default(); 2];
        for ((row, src), pt) in m.iter_mut().zip(src).zip(&batch.points) {
            let at = |v: &Lane| v.get(lane).copied().unwrap_or(0);
            let s = &pt.state;
            *row = SoftContact {
                sep: Real::from_bits(at(&s.sep)),
                jn: impulse_real(at(&s.jn), k),
                jt: impulse_real(at(&s.jt), k),
                max_jn: impulse_real(at(&s.max_jn), k),
                ..*src
            };
        }
        let m = m.get_mut(..n.min(2)).unwrap_or(&mut []);
        on_store(m, store, &mut f);
        for (row, pt) in m.iter().zip(&mut batch.points) {
            let s = &mut pt.state;
            set(&mut s.sep, lane, row.sep.to_bits());
            set(&mut s.jn, lane, impulse_bits(row.jn, k));
            set(&mut s.jt, lane, impulse_bits(row.jt, k));
            set(&mut s.max_jn, lane, impulse_bits(row.max_jn, k));
        }
        if !batch.exact.get(lane).copied().unwrap_or(true) {
            widen_impulse_grid(batch, lane, m);
        }
    }
    count
}

/// After the exact kernel ran a lane's pass: if the lane's impulses have
/// outgrown its grid (past half the window, the tangent's past a quarter:
/// what the gather calls heavy), the lane is regathered from `rows` (its
/// rows, with the state after that pass) at the impulse shift that holds
/// them, so that the step's next passes run it in lanes again instead of
/// in the exact kernel. A new contact in a heavy pile starts at shift 0
/// (it has no warm-start impulse) and its first impulses pass the
/// window; so do a resting contact's under an impact. A lane that does
/// not fit at a coarser grid either keeps its shift.
#[cold]
#[inline(never)]
fn widen_impulse_grid(batch: &mut NarrowBatch, lane: usize, rows: &[SoftContact]) {
    let (Some(first), Some(&k)) = (rows.first(), batch.impulse_shift.get(lane)) else {
        return;
    };
    if k >= MAX_IMPULSE_SHIFT {
        return;
    }
    // A body the solver does not move whose lever arms the lane holds as
    // 0 is regathered as still: its arms are 0 again, whether the gather
    // found it still or they were 0 anyway.
    let at = |v: &Lane| v.get(lane).copied().unwrap_or(0);
    let used = batch.points.get(..rows.len()).unwrap_or(&[]);
    let still = |moves: &[bool; LANES], arms: fn(&NarrowPoint) -> [&Lane; 3]| {
        !moves.get(lane).copied().unwrap_or(true)
            && used.iter().all(|pt| arms(pt).iter().all(|&v| at(v) == 0))
    };
    let still = [
        still(&batch.moves_a, |pt| [&pt.rn_a, &pt.rt_a, &pt.nr_a]),
        still(&batch.moves_b, |pt| [&pt.rn_b, &pt.rt_b, &pt.nr_b]),
    ];
    // What a gather at the lane's own shift would find (its values come
    // from the same rows, its state rounds as the one just stored): the
    // largest gain and impulses, and whether the impulses are heavy.
    let oc = |x: i64| x ^ (x >> 63);
    let mut gain = [&batch.ga_x, &batch.ga_y, &batch.gb_x, &batch.gb_y]
        .iter()
        .map(|&g| at(g).saturating_abs())
        .max()
        .unwrap_or(0);
    let (mut jn, mut jt) = (0i64, 0i64);
    for pt in used {
        for g in [&pt.kn_a, &pt.kn_b, &pt.kt_a, &pt.kt_b] {
            gain = gain.max(at(g).saturating_abs());
        }
        (jn, jt) = (jn.max(oc(at(&pt.state.jn))), jt.max(oc(at(&pt.state.jt))));
    }
    let limit = at(&batch.limit);
    if jn < limit >> 1 && jt < limit >> 2 {
        return;
    }
    let wider = k
        .saturating_add(impulse_shift(jn, jt, gain))
        .min(MAX_IMPULSE_SHIFT);
    if wider > k
        && !matches!(
            gather_lane(batch, lane, (first, rows), wider, still),
            LaneFit::Out
        )
    {
        batch.same_gains = batch.ga_x == batch.gb_x && batch.ga_y == batch.gb_y;
        return;
    }
    gather_lane(batch, lane, (first, rows), k, still);
}

/// The solve (`BIAS`) or relax pass of a batch; returns how many lanes
/// ran the exact kernel.
#[inline(always)]
fn solve_narrow<O: Ops, S: BodyStore, const BIAS: bool>(
    o: O,
    batch: &mut NarrowBatch,
    store: &mut S,
    (rows, motion): (&[SoftContact], &[Motion]),
    p: &SoftContactParams,
    constants: Option<Uniform>,
) -> usize {
    let mut bad = batch.exact;
    let Some((h_inv, slop, neg_push)) = constants else {
        bad = [true; LANES];
        let v = [batch.a, batch.b].map(|_| Velocities {
            vx: splat(0),
            vy: splat(0),
            w: splat(0),
        });
        return finish(
            o,
            batch,
            store,
            v,
            bad,
            |m, copy| {
                solve_manifold(m, copy, motion, p, BIAS);
            },
            rows,
        );
    };
    let mut rec = splat(0);
    let a = Velocities::gather(o, store, &batch.a, &mut rec);
    let b = Velocities::gather(o, store, &batch.b, &mut rec);
    let mut state = batch.points.map(|pt| pt.state);
    check_state(o, batch, &state, &mut rec);
    // The motion since the collide (relax pass only): b's translation
    // against a's and both turns, Q8.24.
    let moved = if BIAS {
        [splat(0); 6]
    } else {
        narrow_motion(o, batch, motion, &mut rec)
    };
    let mut v = [a, b];
    let same = batch.same_gains;
    let used = batch.points_used;
    for (pt, st) in batch.points.iter().zip(&mut state).take(used) {
        let s = if BIAS {
            st.sep
        } else {
            let [dx, dy, c1a, sa, c1b, sb] = moved;
            let along = o.add(o.mul_i32(dx, pt.n_x), o.mul_i32(dy, pt.n_y));
            let turned_b = o.add(o.mul_i32(c1b, pt.nr_b), o.mul_i32(sb, pt.rn_b));
            let turned_a = o.add(o.mul_i32(c1a, pt.nr_a), o.mul_i32(sa, pt.rn_a));
            let sum = o.sub(o.add(along, turned_b), turned_a);
            let s = o.add(pt.dist, round_full::<O, 16>(o, sum));
            st.sep = s;
            s
        };
        // The bias reads the separation on Q8.24 (below 64 m).
        let sign = o.sign(s);
        rec = record::<O, 38>(o, rec, s, sign);
        let s24 = round_full::<O, 8>(o, s);
        let apart = o.positive(s);
        let close = o.mul_i32(s24, h_inv);
        let zero = splat(0);
        let (bias, n_mass, back) = if BIAS {
            let overlap = o.min(o.add(s24, slop), zero);
            let push = o.max(o.mul_i32(overlap, batch.bias_rate), neg_push);
            let scale = o.select(apart, zero, batch.impulse_scale);
            (
                o.select(apart, close, push),
                o.select(apart, pt.n_mass, pt.n_mass_soft),
                round_full::<O, 30>(o, o.mul_i32(scale, st.jn)),
            )
        } else {
            (o.and(apart, close), pt.n_mass, zero)
        };
        let [dvx, dvy, wb, wa] = Velocities::reads(o, &v[0], &v[1]);
        let vn = o.add(
            o.add(o.mul_i32(dvx, pt.n_x), o.mul_i32(dvy, pt.n_y)),
            o.sub(o.mul_i32(wb, pt.rn_b), o.mul_i32(wa, pt.rn_a)),
        );
        let err = velocity_read(o, o.add(vn, bias), &mut rec);
        let jn = o.add(round_full::<O, 8>(o, o.mul_i32(err, n_mass)), back);
        let old = st.jn;
        st.jn = o.max(o.sub(old, jn), zero);
        rec = o.or(rec, o.gt(st.jn, o.sub(batch.limit, splat(1))));
        let djn = o.sub(st.jn, old);
        st.max_jn = o.max(st.max_jn, djn);
        apply(
            o,
            &mut v,
            djn,
            [batch.ga_x, batch.ga_y],
            [batch.gb_x, batch.gb_y],
            [pt.kn_a, pt.kn_b],
            same,
        );
    }
    if p.friction {
        let half = o.shr_n::<1>(batch.limit);
        for (pt, st) in batch.points.iter().zip(&mut state).take(used) {
            let [dvx, dvy, wb, wa] = Velocities::reads(o, &v[0], &v[1]);
            let vt = o.add(
                o.sub(o.mul_i32(dvy, pt.n_x), o.mul_i32(dvx, pt.n_y)),
                o.sub(o.mul_i32(wb, pt.rt_b), o.mul_i32(wa, pt.rt_a)),
            );
            let vt = velocity_read(o, o.add(vt, pt.surface_t), &mut rec);
            let djt = round_full::<O, 8>(o, o.mul_i32(vt, pt.t_mass));
            let jt_max = round_full::<O, 30>(o, o.mul_i32(pt.friction, st.jn));
            rec = o.or(rec, o.gt(jt_max, half));
            let old = st.jt;
            st.jt = o.min(o.max(o.sub(old, djt), o.neg(jt_max)), jt_max);
            let djt = o.sub(st.jt, old);
            apply(
                o,
                &mut v,
                djt,
                [o.neg(batch.ga_y), batch.ga_x],
                [o.neg(batch.gb_y), batch.gb_x],
                [pt.kt_a, pt.kt_b],
                same,
            );
        }
    }
    let left = left_of(bad, &rec);
    if left.contains(&true) {
        for (pt, st) in batch.points.iter_mut().zip(&state) {
            pt.state = keep_left(pt.state, *st, &left);
        }
    } else {
        for (pt, st) in batch.points.iter_mut().zip(&state) {
            pt.state = *st;
        }
    }
    finish(
        o,
        batch,
        store,
        v,
        left,
        |m, copy| {
            solve_manifold(m, copy, motion, p, BIAS);
        },
        rows,
    )
}

/// The motion of a batch's bodies since the collide on Q8.24: `[Δp_b −
/// Δp_a (x, y), cos − 1 and sin of a's turn, of b's]`, recorded in `rec`
/// unless every value is below 64 (a translation of 64 m, any turn).
#[inline(always)]
fn narrow_motion<O: Ops>(
    o: O,
    batch: &NarrowBatch,
    motion: &[Motion],
    rec: &mut Lane,
) -> [Lane; 6] {
    let none = Motion::default();
    let mut raw = [[splat(0); 4]; 2];
    for (out, slots) in raw.iter_mut().zip([&batch.a, &batch.b]) {
        for (lane, &slot) in slots.iter().enumerate() {
            let m = motion.get(slot as usize).unwrap_or(&none);
            let [dx, dy, c1, s1] = out;
            set(dx, lane, m.dp.x.to_bits());
            set(dy, lane, m.dp.y.to_bits());
            set(c1, lane, m.dq_c1.to_bits());
            set(s1, lane, m.dq_s.to_bits());
        }
    }
    let [[ax, ay, ac, as1], [bx, by, bc, bs]] = raw;
    // Each translation below 2^37 raw first, so that the differences
    // neither wrap nor leave 2^38.
    for v in [ax, ay, bx, by] {
        *rec = record::<O, 37>(o, *rec, v, o.sign(v));
    }
    // No closure: each lane operation must inline into the kernel.
    let mut out = [o.sub(bx, ax), o.sub(by, ay), ac, as1, bc, bs];
    for v in &mut out {
        let sign = o.sign(*v);
        *rec = record::<O, 38>(o, *rec, *v, sign);
        *v = o.shr_n::<8>(o.add(o.add(*v, splat(1 << 7)), sign));
    }
    out
}

impl LaneBatch for NarrowBatch {
    /// A solve's [`Uniform`] values (`None` for a warm start, or where
    /// they do not fit their grids).
    type PassConstants = Option<Uniform>;

    fn pass_constants(pass: &Pass) -> Option<Uniform> {
        match pass {
            Pass::Solve(p, _) => uniform(p),
            Pass::WarmStart(_) => None,
        }
    }

    #[inline(always)]
    fn run_pass<O: Ops, S: BodyStore>(
        &mut self,
        ops: O,
        pass: Pass,
        constants: Option<Uniform>,
        store: &mut S,
        rows: &[SoftContact],
        motion: &[Motion],
    ) {
        let inputs = (rows, motion);
        match pass {
            Pass::WarmStart(dt_coef) => {
                warm_start_narrow(ops, self, store, rows, dt_coef);
            }
            Pass::Solve(p, true) => {
                solve_narrow::<O, S, true>(ops, self, store, inputs, &p, constants);
            }
            Pass::Solve(p, false) => {
                solve_narrow::<O, S, false>(ops, self, store, inputs, &p, constants);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::lanes::Portable;
    use crate::solver::soft_contact::pass::InPlace;
    use crate::solver::soft_contact::row::tests::{case, values, Counting};
    use proptest::prelude::*;

    /// `pass` on a batch of `manifolds` gathered from `rows`, on `ops`:
    /// the rows (state written back), the bodies and how many lanes ran
    /// the exact kernel.
    fn run<O: Ops>(
        ops: O,
        (rows, bodies, motion, p): (&[SoftContact], &[SolverBody], &[Motion], &SoftContactParams),
        manifolds: [(u32, u32); LANES],
        pass: Option<bool>,
    ) -> (Vec<SoftContact>, Vec<SolverBody>, usize) {
        run_shifted(ops, (rows, bodies, motion, p), manifolds, pass, None)
    }

    /// [`run`], every lane regathered with impulse shift `shift` if given.
    fn run_shifted<O: Ops>(
        ops: O,
        (rows, bodies, motion, p): (&[SoftContact], &[SolverBody], &[Motion], &SoftContactParams),
        manifolds: [(u32, u32); LANES],
        pass: Option<bool>,
        shift: Option<i32>,
    ) -> (Vec<SoftContact>, Vec<SolverBody>, usize) {
        let regather = |batch: &mut NarrowBatch, rows: &[SoftContact]| {
            let Some(k) = shift else { return };
            for (lane, &(start, end)) in manifolds.iter().enumerate() {
                let points = &rows[start as usize..end as usize];
                let still = [false; 2];
                let fit = gather_lane(batch, lane, (&points[0], points), k, still);
                assert!(!matches!(fit, LaneFit::Out));
            }
        };
        let (rows, bodies, left, _) =
            run_adjusted(ops, (rows, bodies, motion, p), manifolds, pass, regather);
        (rows, bodies, left)
    }

    /// [`run`], the batch changed by `adjust` after its gather; also the
    /// lanes' impulse shifts after the pass.
    fn run_adjusted<O: Ops>(
        ops: O,
        (rows, bodies, motion, p): (&[SoftContact], &[SolverBody], &[Motion], &SoftContactParams),
        manifolds: [(u32, u32); LANES],
        pass: Option<bool>,
        adjust: impl FnOnce(&mut NarrowBatch, &[SoftContact]),
    ) -> (Vec<SoftContact>, Vec<SolverBody>, usize, [i32; LANES]) {
        let (mut rows, mut bodies) = (rows.to_vec(), bodies.to_vec());
        let mut batch = NarrowBatch::default();
        gather_narrow(&mut batch, manifolds, &rows, &bodies);
        adjust(&mut batch, &rows);
        let mut store = InPlace(&mut bodies);
        let (inputs, constants) = ((rows.as_slice(), motion), uniform(p));
        let left = match pass {
            None => warm_start_narrow(ops, &mut batch, &mut store, &rows, Real::ONE),
            Some(true) => {
                solve_narrow::<O, _, true>(ops, &mut batch, &mut store, inputs, p, constants)
            }
            Some(false) => {
                solve_narrow::<O, _, false>(ops, &mut batch, &mut store, inputs, p, constants)
            }
        };
        put_narrow(&batch, &mut rows, 0);
        (rows, bodies, left, batch.impulse_shift)
    }

    /// Scene-like parameters: `1/h` of a 240 Hz sub-step, no slop, a
    /// push-out of 3 m/s (the generated ones are mostly out of the
    /// window, which would send every lane to the exact kernel).
    fn scene_params(p: &mut SoftContactParams) {
        p.h_inv = Real::from_int(240);
        p.slop = Real::ZERO;
        p.push_out = Real::from_int(3);
    }

    /// The window without the division is the division's, across the
    /// edge of the shortcut and at the extremes.
    #[test]
    fn impulse_limit_shortcut_is_the_division() {
        let edge = FULL_WINDOW_GAIN;
        for gain in [
            i64::MIN,
            -1,
            0,
            1,
            2,
            1 << 24,
            edge - 1,
            edge,
            edge + 1,
            2 * edge - 1,
            2 * edge,
            1 << 40,
            i64::MAX,
        ] {
            let want = CHANGE_MAX
                .checked_div(gain.max(1))
                .unwrap_or(LIMIT_MAX)
                .min(LIMIT_MAX);
            assert_eq!(impulse_limit(gain), want, "gain {gain}");
        }
    }

    /// A raw value of any magnitude: uniform bits shifted right by 0 to 63,
    /// so that small values (the lane windows) and the extremes are drawn.
    fn any_raw() -> impl Strategy<Value = i64> {
        prop_oneof![
            (any::<i64>(), 0u32..64).prop_map(|(v, k)| v >> k),
            prop::sample::select(vec![i64::MIN, i64::MIN + 1, i64::MAX, -1, 0, 1]),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(5_000))]
        /// The gather's 64-bit roundings give [`round_bits`]' answers and
        /// windows: an impulse on Q8.24, and a product rounded by `s` bits
        /// (lane value, or out of its window).
        #[test]
        fn gather_roundings_are_round_bits(x in any_raw(), a in any_raw(), b in any_raw(), s in 1u32..64) {
            let want = i64::try_from(round_bits(i128::from(x), 8)).unwrap();
            prop_assert_eq!(impulse_bits(Real::from_bits(x), 0), want);
            let (mut got, mut reference) = (Fit { ok: true }, Fit { ok: true });
            let product = got.product(Real::from_bits(a), Real::from_bits(b), s);
            let exact = i128::from(a) * i128::from(b);
            let want = reference.fits(round_bits(exact, s));
            prop_assert_eq!((product, got.ok), (want, reference.ok));
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(1_000))]
        /// The lanes' rounding is the reference's: to nearest, ties away
        /// from zero, on both lane implementations.
        #[test]
        fn lane_rounding_is_the_reference(x in prop::array::uniform4(-(1i64 << 61)..(1i64 << 61))) {
            fn check<O: Ops>(o: O, x: Lane) -> Result<(), TestCaseError> {
                let want = |s: u32| x.map(|v| i64::try_from(round_bits(i128::from(v), s)).unwrap());
                prop_assert_eq!(round_full::<O, 8>(o, x), want(8));
                prop_assert_eq!(round_full::<O, 16>(o, x), want(16));
                prop_assert_eq!(round_full::<O, 30>(o, x), want(30));
                let low = |v: Lane| v.map(|y| y as u32);
                prop_assert_eq!(low(round_low::<O, 32>(o, x)), low(want(32)));
                Ok(())
            }
            check(Portable, x)?;
            if let Some(avx2) = tamias2d_simd::Avx2::new() {
                check(avx2, x)?;
            }
            // Ties go away from zero, symmetrically.
            let ties = [1i64 << 7, -(1i64 << 7), 3 << 7, -(3 << 7)];
            prop_assert_eq!(round_full::<Portable, 8>(Portable, ties), [1, -1, 2, -2]);
        }

        /// The AVX2 lanes give the portable lanes' bits, and a manifold
        /// gives in a batch the bits it gives alone (no lane reads
        /// another's), on any input: in the windows, at their edges and
        /// past them (where lanes run the exact kernel).
        #[test]
        fn lanes_agree_and_are_independent(
            vals in values(),
            points in prop::array::uniform4(any::<bool>()),
            friction in any::<bool>(),
            like in any::<bool>(),
            scene in any::<bool>(),
            pass in prop_oneof![Just(None), Just(Some(true)), Just(Some(false))],
        ) {
            let (rows, manifolds, bodies, motion, mut p) = case(vals, points, friction, like);
            if scene {
                scene_params(&mut p);
            }
            let input = (rows.as_slice(), bodies.as_slice(), motion.as_slice(), &p);
            let (p_rows, p_bodies, _) = run(Portable, input, manifolds, pass);
            if let Some(avx2) = tamias2d_simd::Avx2::new() {
                let (a_rows, a_bodies, _) = run(avx2, input, manifolds, pass);
                prop_assert_eq!(&a_rows, &p_rows);
                prop_assert_eq!(&a_bodies, &p_bodies);
            }
            for (lane, &m) in manifolds.iter().enumerate() {
                let mut alone = [(u32::MAX, u32::MAX); LANES];
                alone[0] = m;
                let (l_rows, l_bodies, _) = run(Portable, input, alone, pass);
                let (start, end) = (m.0 as usize, m.1 as usize);
                prop_assert_eq!(&l_rows[start..end], &p_rows[start..end], "lane {}", lane);
                for body in [2 * lane, 2 * lane + 1] {
                    prop_assert_eq!(l_bodies[body], p_bodies[body], "lane {}", lane);
                }
            }
        }
    }

    /// Lanes whose velocities leave the window run the exact kernel, from
    /// the state on its grid: the exact kernel's bits, its impulses back
    /// on Q8.24.
    #[test]
    fn lanes_out_of_the_window_run_the_exact_kernel() {
        let vals: Vec<i64> = (1..200i64)
            .map(|k| k.wrapping_mul(0x9e37_79b9_7f4a_7c15_u64 as i64) >> 31)
            .collect();
        let (rows, manifolds, mut bodies, motion, mut p) = case(vals, [true; LANES], true, false);
        scene_params(&mut p);
        for b in &mut bodies {
            b.v.x = Real::from_int(5_000); // above 1,024 m/s
        }
        for pass in [None, Some(true), Some(false)] {
            let input = (rows.as_slice(), bodies.as_slice(), &motion[..], &p);
            let (n_rows, n_bodies, left, shifts) =
                run_adjusted(Portable, input, manifolds, pass, |_, _| {});
            assert_eq!(left, LANES);
            let (mut e_rows, mut e_bodies) = (rows.clone(), bodies.clone());
            for r in &mut e_rows {
                r.jn = impulse_real(impulse_bits(r.jn, 0), 0);
                r.jt = impulse_real(impulse_bits(r.jt, 0), 0);
                r.max_jn = impulse_real(impulse_bits(r.max_jn, 0), 0);
            }
            // The exact kernel's result on the grid each lane holds after
            // the pass (a coarser one where its impulses outgrew Q8.24).
            for (&(start, end), &k) in manifolds.iter().zip(&shifts) {
                let m = &mut e_rows[start as usize..end as usize];
                on_store(m, &mut InPlace(&mut e_bodies), |m, copy| match pass {
                    None => warm_start_manifold(m, copy),
                    Some(bias) => solve_manifold(m, copy, &motion, &p, bias),
                });
                for r in m.iter_mut() {
                    r.jn = impulse_real(impulse_bits(r.jn, k), k);
                    r.jt = impulse_real(impulse_bits(r.jt, k), k);
                    r.max_jn = impulse_real(impulse_bits(r.max_jn, k), k);
                }
            }
            assert_eq!(n_rows, e_rows, "{pass:?}");
            assert_eq!(n_bodies, e_bodies, "{pass:?}");
        }
    }

    /// A lane whose pass the exact kernel ran because its impulses
    /// outgrew Q8.24 takes the shift a gather of its new impulses would
    /// choose, and its next pass runs in lanes.
    #[test]
    fn grown_impulses_widen_the_lane_grid() {
        let vals: Vec<i64> = (1..200i64)
            .map(|k| k.wrapping_mul(0x9e37_79b9_7f4a_7c15_u64 as i64) >> 31)
            .collect();
        let (rows, manifolds, mut bodies, motion, mut p) = case(vals, [true; LANES], true, false);
        scene_params(&mut p);
        let mut batch = NarrowBatch::default();
        gather_narrow(&mut batch, manifolds, &rows, &bodies);
        assert_eq!(
            (batch.exact, batch.impulse_shift),
            ([false; LANES], [0; LANES])
        );
        let (inputs, constants) = ((rows.as_slice(), &motion[..]), uniform(&p));
        // A solve with the bodies past the velocity window runs the exact
        // kernel, whose impulses outgrow Q8.24's window (32 N·s).
        let mut fast = bodies.clone();
        for b in &mut fast {
            b.v.x = Real::from_int(5_000);
        }
        let mut store = InPlace(&mut fast);
        let left =
            solve_narrow::<_, _, true>(Portable, &mut batch, &mut store, inputs, &p, constants);
        assert_eq!(left, LANES);
        // Each lane now holds the grid that holds its impulses, as a gather
        // of those impulses would choose it.
        let mut after = rows.clone();
        put_narrow(&batch, &mut after, 0);
        let mut regathered = NarrowBatch::default();
        gather_narrow(&mut regathered, manifolds, &after, &bodies);
        assert_eq!(batch.impulse_shift, regathered.impulse_shift);
        assert!(batch.impulse_shift.iter().filter(|&&k| k > 0).count() >= 2);
        // The next pass, the bodies back in the window, runs in lanes.
        let mut store = InPlace(&mut bodies);
        let left =
            solve_narrow::<_, _, false>(Portable, &mut batch, &mut store, inputs, &p, constants);
        assert_eq!(left, 0);
    }

    /// A heavy pile's warm-start impulses (100 N·s, past Q8.24's 32 N·s)
    /// put the manifold on a coarser impulse grid instead of the exact
    /// kernel: the least shift that holds them at half the window, and no
    /// lane left to the exact kernel in any pass. On impulses that fit
    /// Q8.24 (10 N·s), the coarser grid moves no velocity by more than a
    /// step of the Q16.16 grid the passes read velocities on.
    #[test]
    fn heavy_impulses_take_a_coarser_grid() {
        let vals: Vec<i64> = (1..200i64)
            .map(|k| k.wrapping_mul(0x9e37_79b9_7f4a_7c15_u64 as i64) >> 35)
            .collect();
        let (mut rows, manifolds, bodies, motion, mut p) = case(vals, [true; LANES], true, false);
        scene_params(&mut p);
        let passes = [None, Some(true), Some(false)];
        for r in &mut rows {
            (r.jn, r.jt) = (Real::from_int(100), Real::from_int(-20));
        }
        let mut batch = NarrowBatch::default();
        gather_narrow(&mut batch, manifolds, &rows, &bodies);
        assert_eq!(batch.exact, [false; LANES]);
        // 100 / 2^3 is below 16 N·s, half the window; 100 / 2^2 is not.
        assert_eq!(batch.impulse_shift, [3; LANES]);
        for pass in passes {
            let input = (rows.as_slice(), bodies.as_slice(), &motion[..], &p);
            assert_eq!(run(Portable, input, manifolds, pass).2, 0, "{pass:?}");
        }
        for r in &mut rows {
            (r.jn, r.jt) = (Real::from_int(10), Real::from_int(-2));
        }
        let step = Real::from_bits(1 << 16);
        for pass in passes {
            let input = (rows.as_slice(), bodies.as_slice(), &motion[..], &p);
            let (_, fine, left) = run_shifted(Portable, input, manifolds, pass, None);
            let (_, coarse, left_coarse) = run_shifted(Portable, input, manifolds, pass, Some(3));
            assert_eq!((left, left_coarse), (0, 0), "{pass:?}");
            for (f, c) in fine.iter().zip(&coarse) {
                for d in [f.v.x - c.v.x, f.v.y - c.v.y, f.w - c.w] {
                    assert!(d.abs() <= step, "{pass:?}: {d:?}");
                }
            }
        }
    }

    /// Small light bodies (a 25 cm box of 62.5 g: `m⁻¹` 16 /kg,
    /// `I⁻¹ (r × d)` of some 300, past the 128 of Q8.24) take a negative
    /// impulse shift and stay in lanes, where they ran the exact kernel.
    /// On resting contacts (separation 0: the bias path rounds the
    /// separation and the bias rate alike at every shift) each pass
    /// leaves every velocity within two steps of the Q16.16 grid the
    /// passes read velocities on of the exact kernel's: a row reads its
    /// relative velocity within `2^-17 (2 + |r_a| + |r_b|)`, and a gain
    /// times an effective mass is about 1. Past the least shift the
    /// manifold runs the exact kernel.
    #[test]
    fn light_bodies_take_a_finer_impulse_grid() {
        let vals: Vec<i64> = (1..200i64)
            .map(|k| k.wrapping_mul(0x9e37_79b9_7f4a_7c15_u64 as i64) >> 35)
            .collect();
        let (rows, manifolds, bodies, motion, mut p) = case(vals, [true; LANES], true, false);
        scene_params(&mut p);
        let light = |gain: i32| {
            let mut rows = rows.clone();
            for (i, r) in rows.iter_mut().enumerate() {
                // A manifold's points share its normal.
                r.n = crate::math::Vect::new(Real::lit("0.6"), Real::lit("-0.8"));
                (r.m_inv_a, r.m_inv_b) = (Real::from_int(16), Real::from_int(16));
                let g = Real::from_int(gain - gain / 16 * (i as i32 % 3));
                (r.kn_a, r.kn_b, r.kt_a, r.kt_b) = (g, -g, g * Real::HALF, -g);
                let mass = Real::ONE / (Real::from_int(32) + g * Real::lit("0.36"));
                (r.n_mass, r.t_mass) = (mass, mass);
                (r.jn, r.jt) = (Real::lit("0.01"), Real::lit("-0.002"));
                (r.dist, r.sep) = (Real::ZERO, Real::ZERO);
            }
            rows
        };
        let step = Real::from_bits(1 << 16);
        for (gain, shift) in [(300, -2), (1000, -3)] {
            let rows = light(gain);
            let mut batch = NarrowBatch::default();
            gather_narrow(&mut batch, manifolds, &rows, &bodies);
            assert_eq!(batch.exact, [false; LANES], "{gain}");
            // Below 2^(7−k), not 2^(8−k).
            assert_eq!(batch.impulse_shift, [shift; LANES], "{gain}");
            for pass in [None, Some(true), Some(false)] {
                let input = (rows.as_slice(), bodies.as_slice(), &motion[..], &p);
                let (_, lanes, left) = run(Portable, input, manifolds, pass);
                assert_eq!(left, 0, "{gain} {pass:?}");
                let all_exact = |b: &mut NarrowBatch, _: &[SoftContact]| b.exact = [true; LANES];
                let (_, exact, left, _) = run_adjusted(Portable, input, manifolds, pass, all_exact);
                assert_eq!(left, LANES, "{gain} {pass:?}");
                for (l, e) in lanes.iter().zip(&exact) {
                    for d in [l.v.x - e.v.x, l.v.y - e.v.y, l.w - e.w] {
                        assert!(
                            d.abs() <= step * Real::from_int(2),
                            "{gain} {pass:?}: {d:?}"
                        );
                    }
                }
            }
        }
        // Gains of 2^15 (2^14 and more): past the least shift, the exact
        // kernel.
        let rows = light(1 << 15);
        let mut batch = NarrowBatch::default();
        gather_narrow(&mut batch, manifolds, &rows, &bodies);
        assert_eq!(batch.exact, [true; LANES]);
        assert_eq!(batch.impulse_shift, [0; LANES]);
    }

    /// The lever arms of a body that neither moves under the solver nor
    /// turns (the ground) only multiply zeros: a far anchor (200 m, past
    /// the 128 m window) keeps the manifold in lanes, with the bits of a
    /// near one. The same anchor on a spinning kinematic body leaves the
    /// window: that manifold runs the exact kernel.
    #[test]
    fn a_still_body_s_far_arms_stay_in_lanes() {
        let vals: Vec<i64> = (1..200i64)
            .map(|k| k.wrapping_mul(0x9e37_79b9_7f4a_7c15_u64 as i64) >> 35)
            .collect();
        let (rows, manifolds, mut bodies, mut motion, mut p) =
            case(vals, [true; LANES], true, false);
        scene_params(&mut p);
        for lane in 0..LANES {
            bodies[2 * lane] = SolverBody::default();
            motion[2 * lane].dq_c1 = Real::ZERO;
            motion[2 * lane].dq_s = Real::ZERO;
        }
        let anchored = |arm: i32| {
            let mut rows = rows.clone();
            for r in &mut rows {
                r.m_inv_a = Real::ZERO;
                (r.kn_a, r.kt_a) = (Real::ZERO, Real::ZERO);
                (r.rn_a, r.rt_a, r.nr_a) = (
                    Real::from_int(arm),
                    Real::from_int(-arm),
                    Real::from_int(arm),
                );
            }
            rows
        };
        let (far, near) = (anchored(200), anchored(3));
        for pass in [None, Some(true), Some(false)] {
            let run_on = |rows: &[SoftContact], bodies: &[SolverBody]| {
                run(Portable, (rows, bodies, &motion[..], &p), manifolds, pass)
            };
            let (far_rows, far_bodies, left) = run_on(&far, &bodies);
            let (near_rows, near_bodies, _) = run_on(&near, &bodies);
            assert_eq!(left, 0, "{pass:?}");
            assert_eq!(far_bodies, near_bodies, "{pass:?}");
            let impulses =
                |rows: &[SoftContact]| rows.iter().map(|r| (r.jn, r.jt)).collect::<Vec<_>>();
            assert_eq!(impulses(&far_rows), impulses(&near_rows), "{pass:?}");
            let mut spinning = bodies.clone();
            for lane in 0..LANES {
                spinning[2 * lane].w = Real::ONE;
            }
            assert_eq!(run_on(&far, &spinning).2, LANES, "{pass:?}");
        }
    }

    /// The lane operations of each pass over a batch of four two-point
    /// manifolds with friction (scene-like values: below 1/8, impulses
    /// in the window), per row: the figure `docs/performance.md`
    /// reports beside the exact kernels' (their test
    /// `lane_operations_per_row_and_pass`), and a bound a change that adds
    /// operations has to move.
    #[test]
    fn narrow_lane_operations_per_row_and_pass() {
        let vals: Vec<i64> = (1..200i64)
            .map(|k| k.wrapping_mul(0x9e37_79b9_7f4a_7c15_u64 as i64) >> 35)
            .collect();
        let (mut rows, manifolds, bodies, motion, mut p) = case(vals, [true; LANES], true, false);
        scene_params(&mut p);
        // The accumulated normal impulses as a pass leaves them (≥ 0).
        for r in &mut rows {
            r.jn = r.jn.abs();
        }
        let count = |pass: Option<bool>| {
            let ops = core::cell::Cell::new(0);
            let input = (rows.as_slice(), bodies.as_slice(), &motion[..], &p);
            let (_, _, left) = run(Counting(&ops), input, manifolds, pass);
            assert_eq!(
                left, 0,
                "{pass:?}: a lane left: the count would include a rerun"
            );
            ops.get() as f64 / (2 * LANES) as f64
        };
        let (warm, solve, relax) = (count(None), count(Some(true)), count(Some(false)));
        eprintln!(
            "narrow lane operations per row: warm start {warm}, solve {solve}, relax {relax}"
        );
        // 5 % above today's counts.
        assert!(
            warm <= 17.1 && solve <= 51.1 && relax <= 59.8,
            "{warm} {solve} {relax}"
        );
    }
}
