//! The constraints' part of the solver stages (the caches of a space, not
//! state): one row per constraint per sub-step, built after the contacts'
//! pre-step, warm started after the contacts, and iterated after the
//! contacts in each solver iteration, in constraint slot order. Also the
//! pair filter of `collide_bodies = false`.
use super::axis::{PinRow, SlideRow};
use super::damped_rotary_spring::RotarySpringRow;
use super::damped_spring::SpringRow;
use super::gear::GearRow;
use super::groove::GrooveRow;
use super::kernel::{self, Accumulated};
use super::pivot::PivotRow;
use super::prep::Prep;
use super::rotary_limit::AngularLimitRow;
use super::simple_motor::MotorRow;
use super::{Constraint, JointKind, JointSoftness};
use crate::arena::Arena;
use crate::body::{Body, BodyHandle};
use crate::math::{exp, Real, Vect};
use crate::solver::softness::Softness;
use crate::solver::SolverBody;

/// A kind's solver row and its accumulated impulse.
#[derive(Clone, Copy, Debug)]
enum RowKind {
    Pin(Accumulated<PinRow>),
    Pivot(Accumulated<PivotRow>),
    Spring(Accumulated<SpringRow>),
    Motor(Accumulated<MotorRow>),
    Gear(Accumulated<GearRow>),
    Slide(Accumulated<SlideRow>),
    RotaryLimit(Accumulated<AngularLimitRow>),
    RotarySpring(Accumulated<RotarySpringRow>),
    Groove(Accumulated<GrooveRow>),
    /// The row and the tooth angle the pre-step moved the ratchet to.
    Ratchet(Accumulated<AngularLimitRow>, Real),
}

/// One constraint's row for this sub-step.
#[derive(Clone, Copy, Debug)]
struct Row {
    /// Constraint slot (where the accumulated impulse goes back).
    slot: u32,
    /// Solver-body slots of a and b (different: validated).
    a: u32,
    b: u32,
    /// `max_force·dt`.
    j_max: Real,
    /// The softness its iterations apply ([`Softness::RIGID`] on the
    /// sequential solver and in the soft step's relax pass).
    soft: Softness,
    /// Last step's accumulated impulse, for the warm start.
    cached: Cached,
    kind: RowKind,
}

/// An accumulated impulse as stored in the state.
#[derive(Clone, Copy, Debug)]
enum Cached {
    Scalar(Real),
    Vector(Vect),
}

/// The constraints' solver caches of a space.
#[derive(Clone, Debug, Default)]
pub(crate) struct ConstraintScratch {
    rows: Vec<Row>,
    /// Body slot pairs `(low, high)` of constraints with `collide_bodies`
    /// false, sorted (rebuilt every sub-step from the state).
    no_collide: Vec<(u32, u32)>,
    /// The last `(error_bias, dt) → 1 − error_bias^dt`: constraints mostly
    /// share the default error bias, and `pow` is the pre-step's costliest
    /// operation.
    bias_memo: Option<(Real, Real, Real)>,
    /// The last joint's own softness and sub-step, and its coefficients
    /// (joints with their own stiffness mostly share it).
    soft_memo: Option<(JointSoftness, Real, Softness)>,
}

impl ConstraintScratch {
    /// The joint-filter stage's list: the body pairs whose shapes must not collide.
    pub(crate) fn update_filter(&mut self, constraints: &Arena<Constraint>) {
        self.no_collide.clear();
        self.no_collide
            .extend(
                constraints
                    .iter()
                    .filter(|(_, c)| !c.collide_bodies)
                    .map(|(_, c)| {
                        let (i, j) = (c.a.index(), c.b.index());
                        (i.min(j), i.max(j))
                    }),
            );
        self.no_collide.sort_unstable();
    }

    /// True if a constraint with `collide_bodies = false` joins `a` and `b`.
    pub(crate) fn rejects(&self, a: BodyHandle, b: BodyHandle) -> bool {
        if self.no_collide.is_empty() {
            return false;
        }
        let (i, j) = (a.index(), b.index());
        self.no_collide.binary_search(&(i.min(j), i.max(j))).is_ok()
    }

    /// The pre-step: one row per constraint, in slot order. Constraints
    /// whose bodies are missing (never, in a valid state) are skipped.
    /// With `soft` (the soft step) every row's bias is `−bias_rate·error`
    /// (capped at `max_bias`) and the iterations apply that softness;
    /// without it, Chipmunk's `−(1 − error_bias^dt)·error/dt`, rigid.
    pub(crate) fn pre_step(
        &mut self,
        constraints: &Arena<Constraint>,
        bodies: &Arena<Body>,
        solver_bodies: &[SolverBody],
        dt: Real,
        dt_inv: Real,
        soft: Option<Softness>,
    ) {
        self.rows.clear();
        for (h, c) in constraints.iter() {
            let (Some(body_a), Some(body_b)) = (bodies.get(c.a), bodies.get(c.b)) else {
                continue;
            };
            let (ia, ib) = (c.a.index(), c.b.index());
            let (Some(sa), Some(sb)) = (
                solver_bodies.get(ia as usize),
                solver_bodies.get(ib as usize),
            ) else {
                continue;
            };
            // A sleeping island's joints rest with it (their impulses stay).
            if ia == ib || body_a.is_sleeping() || body_b.is_sleeping() {
                continue;
            }
            let row_soft = match (soft, c.softness) {
                (Some(_), Some(own)) => Some(self.own_softness(own, dt, dt_inv)),
                (world, _) => world,
            };
            let bias_coef = match row_soft {
                Some(_) => Real::ZERO,
                None => self.bias_coef(c.error_bias, dt),
            };
            let p = Prep {
                body_a,
                body_b,
                sa,
                sb,
                dt,
                dt_inv,
                bias_coef,
                max_bias: c.max_bias,
                soft_rate: row_soft.map(|s| s.bias_rate),
            };
            let (kind, cached) = match &c.kind {
                JointKind::Pin(j) => (
                    RowKind::Pin(Accumulated::new(PinRow::new(j, &p))),
                    Cached::Scalar(j.jn_acc),
                ),
                JointKind::Pivot(j) => (
                    RowKind::Pivot(Accumulated::new(PivotRow::new(j, &p))),
                    Cached::Vector(j.j_acc),
                ),
                JointKind::DampedSpring(j) => (
                    RowKind::Spring(Accumulated::new(SpringRow::new(j, &p))),
                    Cached::Scalar(j.j_acc),
                ),
                JointKind::SimpleMotor(j) => (
                    RowKind::Motor(Accumulated::new(MotorRow::new(j, &p))),
                    Cached::Scalar(j.j_acc),
                ),
                JointKind::Gear(j) => (
                    RowKind::Gear(Accumulated::new(GearRow::new(j, &p))),
                    Cached::Scalar(j.j_acc),
                ),
                JointKind::Slide(j) => (
                    RowKind::Slide(Accumulated::new(SlideRow::new(j, &p))),
                    Cached::Scalar(j.jn_acc),
                ),
                JointKind::RotaryLimit(j) => (
                    RowKind::RotaryLimit(Accumulated::new(AngularLimitRow::new(j.error(&p), &p))),
                    Cached::Scalar(j.j_acc),
                ),
                JointKind::DampedRotarySpring(j) => (
                    RowKind::RotarySpring(Accumulated::new(RotarySpringRow::new(j, &p))),
                    Cached::Scalar(j.j_acc),
                ),
                JointKind::Groove(j) => (
                    RowKind::Groove(Accumulated::new(GrooveRow::new(j, &p))),
                    Cached::Vector(j.j_acc),
                ),
                JointKind::Ratchet(j) => {
                    let (row, tooth) = j.row(&p);
                    (
                        RowKind::Ratchet(Accumulated::new(row), tooth),
                        Cached::Scalar(j.j_acc),
                    )
                }
            };
            self.rows.push(Row {
                slot: h.index(),
                a: ia,
                b: ib,
                j_max: c.max_force * dt,
                soft: row_soft.unwrap_or(Softness::RIGID),
                cached,
                kind,
            });
        }
    }

    /// The coefficients of a joint's own softness on a sub-step of `dt`
    /// (frequency capped at a quarter of the sub-step rate, as the
    /// world's), remembered for the last arguments.
    fn own_softness(&mut self, own: JointSoftness, dt: Real, dt_inv: Real) -> Softness {
        if let Some((o, d, s)) = self.soft_memo {
            if o == own && d == dt {
                return s;
            }
        }
        let hertz = own.hertz.min(dt_inv * Real::lit("0.25"));
        let s = Softness::new(hertz, own.damping_ratio, dt);
        self.soft_memo = Some((own, dt, s));
        s
    }

    /// `1 − error_bias^dt`, remembered for the last pair of arguments.
    fn bias_coef(&mut self, error_bias: Real, dt: Real) -> Real {
        if let Some((e, d, coef)) = self.bias_memo {
            if e == error_bias && d == dt {
                return coef;
            }
        }
        let coef = Real::ONE - exp::pow(error_bias, dt);
        self.bias_memo = Some((error_bias, dt, coef));
        coef
    }

    /// Warm start: each row re-applies last step's accumulated impulse
    /// scaled by `dt_coef = min(dt / prev_dt, 1)` (as the contacts do, see
    /// the space's warm-start stage), which becomes the accumulator the iterations
    /// start from. Without this call (warm starting off) they start from 0.
    /// The cached impulse's scaling is saturating; its application runs on
    /// the fast path (module `kernel`).
    pub(crate) fn warm_start(&mut self, solver_bodies: &mut [SolverBody], dt_coef: Real) {
        use kernel::warm_start as ws;
        let bodies = solver_bodies;
        for row in &mut self.rows {
            let (a, b) = (row.a, row.b);
            match (&mut row.kind, row.cached) {
                (RowKind::Pin(r), Cached::Scalar(j)) => ws(r, bodies, a, b, j * dt_coef),
                (RowKind::Pivot(r), Cached::Vector(j)) => ws(r, bodies, a, b, j * dt_coef),
                (RowKind::Spring(r), Cached::Scalar(j)) => ws(r, bodies, a, b, j * dt_coef),
                (RowKind::Motor(r), Cached::Scalar(j)) => ws(r, bodies, a, b, j * dt_coef),
                (RowKind::Gear(r), Cached::Scalar(j)) => ws(r, bodies, a, b, j * dt_coef),
                (RowKind::Slide(r), Cached::Scalar(j)) => ws(r, bodies, a, b, j * dt_coef),
                (RowKind::RotaryLimit(r) | RowKind::Ratchet(r, _), Cached::Scalar(j)) => {
                    ws(r, bodies, a, b, j * dt_coef)
                }
                (RowKind::RotarySpring(r), Cached::Scalar(j)) => ws(r, bodies, a, b, j * dt_coef),
                (RowKind::Groove(r), Cached::Vector(j)) => ws(r, bodies, a, b, j * dt_coef),
                // A row and its cache come from the same kind.
                (_, _) => {}
            }
        }
    }

    /// The soft step's relax pass from here on: every row without its
    /// position bias, rigid.
    pub(crate) fn relax(&mut self) {
        use kernel::JointKernel;
        for row in &mut self.rows {
            row.soft = Softness::RIGID;
            match &mut row.kind {
                RowKind::Pin(r) => r.row.relax(),
                RowKind::Pivot(r) => r.row.relax(),
                RowKind::Spring(r) => r.row.relax(),
                RowKind::Motor(r) => r.row.relax(),
                RowKind::Gear(r) => r.row.relax(),
                RowKind::Slide(r) => r.row.relax(),
                RowKind::RotaryLimit(r) | RowKind::Ratchet(r, _) => r.row.relax(),
                RowKind::RotarySpring(r) => r.row.relax(),
                RowKind::Groove(r) => r.row.relax(),
            }
        }
    }

    /// One solver iteration over the rows, in slot order, each on the fast
    /// path with the saturating fallback (module `kernel`).
    pub(crate) fn iterate(&mut self, solver_bodies: &mut [SolverBody]) {
        let bodies = solver_bodies;
        use kernel::solve;
        for row in &mut self.rows {
            let (a, b, j_max, soft) = (row.a, row.b, row.j_max, row.soft);
            match &mut row.kind {
                RowKind::Pin(r) => solve(r, bodies, a, b, j_max, soft),
                RowKind::Pivot(r) => solve(r, bodies, a, b, j_max, soft),
                RowKind::Spring(r) => solve(r, bodies, a, b, j_max, soft),
                RowKind::Motor(r) => solve(r, bodies, a, b, j_max, soft),
                RowKind::Gear(r) => solve(r, bodies, a, b, j_max, soft),
                RowKind::Slide(r) => solve(r, bodies, a, b, j_max, soft),
                RowKind::RotaryLimit(r) | RowKind::Ratchet(r, _) => {
                    solve(r, bodies, a, b, j_max, soft)
                }
                RowKind::RotarySpring(r) => solve(r, bodies, a, b, j_max, soft),
                RowKind::Groove(r) => solve(r, bodies, a, b, j_max, soft),
            }
        }
    }

    /// True if there is nothing to solve (the stages are then skipped).
    pub(crate) fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// The store stage: the accumulated impulses back into the constraints.
    pub(crate) fn store(&self, constraints: &mut Arena<Constraint>) {
        for row in &self.rows {
            let Some((h, _)) = constraints.get_by_index(row.slot) else {
                continue;
            };
            let Some(c) = constraints.get_mut(h) else {
                continue;
            };
            match (&mut c.kind, &row.kind) {
                (JointKind::Pin(j), RowKind::Pin(r)) => j.jn_acc = r.acc,
                (JointKind::Pivot(j), RowKind::Pivot(r)) => j.j_acc = r.acc,
                (JointKind::DampedSpring(j), RowKind::Spring(r)) => j.j_acc = r.acc,
                (JointKind::SimpleMotor(j), RowKind::Motor(r)) => j.j_acc = r.acc,
                (JointKind::Gear(j), RowKind::Gear(r)) => j.j_acc = r.acc,
                (JointKind::Slide(j), RowKind::Slide(r)) => j.jn_acc = r.acc,
                (JointKind::RotaryLimit(j), RowKind::RotaryLimit(r)) => j.j_acc = r.acc,
                (JointKind::DampedRotarySpring(j), RowKind::RotarySpring(r)) => j.j_acc = r.acc,
                (JointKind::Groove(j), RowKind::Groove(r)) => j.j_acc = r.acc,
                (JointKind::Ratchet(j), RowKind::Ratchet(r, tooth)) => {
                    j.j_acc = r.acc;
                    j.angle = *tooth;
                }
                // A row is built from its constraint's kind.
                (_, _) => {}
            }
        }
    }
}

/// The joints' rows, as the contact solver interleaves them with its own
/// in every pass.
impl crate::solver::contact_solver::JointRows for ConstraintScratch {
    fn is_empty(&self) -> bool {
        ConstraintScratch::is_empty(self)
    }

    fn warm_start(&mut self, bodies: &mut [SolverBody], dt_coef: Real) {
        ConstraintScratch::warm_start(self, bodies, dt_coef);
    }

    fn iterate(&mut self, bodies: &mut [SolverBody]) {
        ConstraintScratch::iterate(self, bodies);
    }
}
