//! Simulation settings: Chipmunk's space parameters, sub-steps, and the
//! solver switches ("pay only for what you use", see `docs/tuning.md`).
//! They are part of the simulation state (snapshots, checksums) and are
//! checked by [`Settings::validate`] wherever they enter a space.
use serde::{Deserialize, Serialize};

use super::SpaceError;
use crate::math::{Real, Vect};

/// Simulation settings (Chipmunk's space parameters, with defaults for
/// metres, kilograms and seconds).
///
/// # Units and the defaults
///
/// Only [`collision_slop`](Self::collision_slop) has a unit (a length). Its
/// default is 0.005 m (Box2D v3's linear slop), not Chipmunk's 0.1, which
/// is a pixel-scale value: in metres it lets a player rest up to 10 cm inside
/// the ground after a fall. The other defaults have no unit and hold at any
/// scale: [`collision_bias`](Self::collision_bias) is a fraction of overlap
/// per second (Chipmunk's 10% per 1/60 s step), `iterations`, `damping` (a
/// fraction of velocity per second) and `collision_persistence` (steps) do
/// not depend on the length unit.
///
/// **Pixel units.** A world measured in pixels (or any unit `u` with `k` units
/// per metre) scales lengths by `k`: set `collision_slop` to `0.005 · k`
/// (e.g. 0.5 at 100 px/m; Chipmunk's own 0.1 assumes about 20 px/m), and
/// gravity to `(0, −9.8 · k)`. Keep in mind the numeric envelope of
/// `docs/numerics.md` is stated in metres: fixed point has the same absolute
/// resolution whatever the unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Settings {
    /// Solver iterations per step (Chipmunk default 10).
    pub iterations: u32,
    /// Gravity acceleration.
    pub gravity: Vect,
    /// Fraction of velocity kept after one second (1 = no damping), applied
    /// per step as `damping^dt`.
    pub damping: Real,
    /// Overlap allowed without correction, a length (default 0.005 m, Box2D
    /// v3's linear slop; Chipmunk's 0.1 is for pixels, see the type docs).
    pub collision_slop: Real,
    /// Fraction of overlap left uncorrected after one second (Chipmunk
    /// default `(1 − 0.1)^60`: 10% per 1/60 s step).
    pub collision_bias: Real,
    /// Steps an arbiter is kept after its shapes separate (default 3).
    /// Counted in sub-steps when [`substeps`](Self::substeps) > 1.
    pub collision_persistence: u32,
    /// Sub-steps per [`Space::step`](super::Space::step) (default 1, valid `1..=`[`MAX_SUBSTEPS`]).
    ///
    /// `step(dt)` with `substeps = k` runs the **whole** pipeline (integrate,
    /// collide, handlers, solve, post-step callbacks) `k` times, on sub-steps
    /// whose lengths sum to `dt` exactly, in raw bits: with `q = dt / k` (raw
    /// bits, truncated) and `r = dt mod k`, the first `r` sub-steps last
    /// `q + 1` ulp and the others `q` (see [`sub_step_dts`](super::sub_step_dts)). The result is
    /// bit-identical to `k` calls of `step` with those lengths on a world
    /// with `substeps = 1` when the forces and torques set on the bodies
    /// before the step are set again before each sub-step (the step keeps
    /// them for its later sub-steps: a force applied for a frame acts for
    /// the whole frame, as in Box2D). Collision handlers run in every sub-step,
    /// post-step callbacks after every sub-step, [`Space::stamp`](super::Space::stamp) and
    /// [`collision_persistence`](Self::collision_persistence) count
    /// sub-steps, warm starting scales by `min(sub-dt / previous sub-dt, 1)`, and
    /// [`Space::current_time_step`](super::Space::current_time_step) and [`Space::last_step_stats`](super::Space::last_step_stats) describe
    /// the last sub-step. What it buys: smaller steps (better stacking and
    /// trajectories) behind one call and one checksum per game frame.
    pub substeps: u32,
    /// Warm starting (default on): each step starts the solver from the
    /// impulses its contacts accumulated in the previous step (scaled by
    /// `min(dt / prev_dt, 1)`: a step longer than the last starts from the
    /// last step's impulses unscaled). Off: the solver starts from zero and the warm-start
    /// stage is skipped. Stacks then need many more iterations; worth
    /// switching off only for scenes without resting contact.
    pub warm_starting: bool,
    /// Friction (default on). Off: the solver runs a routine without the
    /// tangent impulse (no tangent effective mass in the pre-step, no
    /// friction row in the iterations); results are bit-identical to every
    /// shape having friction 0, at a lower cost.
    pub friction: bool,
    /// Restitution (default on). Off: the pre-step skips the bounce target;
    /// results are bit-identical to every shape having elasticity 0. The
    /// iterations cost the same either way (the target is one addition).
    pub restitution: bool,
    /// Bias impulses (default on): the pseudo-velocities that push
    /// overlapping shapes apart (see [`collision_bias`](Self::collision_bias)).
    /// Off: the solver runs a routine without the bias row; overlap is then
    /// never corrected (results are bit-identical to `collision_bias = 1`),
    /// so switch it off only for scenes whose contacts never sink in
    /// (bouncing, sliding on flat ground) or that correct overlap themselves.
    pub bias_impulses: bool,
    /// Block solver (default on): the two contacts of a face (a
    /// two-point manifold) are solved together, normal and bias impulses
    /// as one 2×2 complementarity problem and friction as one row for the
    /// face, instead of one contact after the other. It converges faster
    /// per iteration, and a face's two contacts no longer depend on which
    /// is solved first: a scene whose mirror image maps every arbiter to
    /// itself (a centred stack, a box tumbling or a ball rolling on the
    /// ground) and that mirror evolve as exact mirrors, bit for bit.
    /// Scenes where the mirror swaps bodies between arbiters (a pyramid, a
    /// pile) do not: the solver still visits the arbiters one after the
    /// other in canonical order, which a mirror does not map to itself, so
    /// such a scene and its mirror agree only to the solver's convergence.
    /// Off: Chipmunk's sequential contacts. See the `solver::block`
    /// module.
    pub block_solver: bool,
    /// Colored solver (default off): the iterations solve the contacts
    /// color by color, where no two contacts of a color share a body the
    /// solver moves (the `solver::graph` module), instead of in canonical
    /// order. A color's contacts are independent, so the `parallel`
    /// feature splits each color between threads and still gives the bits
    /// of one thread (and of a build without the feature). The price is
    /// quality: Gauss–Seidel converges by the order it sweeps in, and the
    /// canonical order (creation order, bottom-up in a stack built from the
    /// ground) carries a stack's weight down in one pass, a coloring does
    /// not. `docs/performance.md` ("The parallel step") measures both.
    /// Off, the contact iterations run on one thread.
    pub colored_solver: bool,
    /// Seconds every body of an island must stay idle before the island
    /// falls asleep (default 0.5 s, Box2D v3's `b2_timeToSleep`; Chipmunk's
    /// default is infinity, i.e. off). [`SLEEP_NEVER`] (`Real::MAX`) turns
    /// sleeping off: the sleep stage is skipped, no idle time is kept.
    /// A sleeping body costs nothing in the step: see the `space::sleep`
    /// module for when islands sleep and wake.
    pub sleep_time_threshold: Real,
    /// A body is idle while `|v|² + (I/m)·ω² ≤ idle_speed_threshold²` (a
    /// speed, default 0.05 m/s: Box2D v3's sleep threshold; Chipmunk's
    /// default derives it from gravity, `|g|·dt`, which is 0.16 m/s at
    /// 1/60 s in metres and changes with the step). Scale it with the
    /// length unit like [`collision_slop`](Self::collision_slop).
    pub idle_speed_threshold: Real,
    /// The solver a step runs (default [`Solver::Sequential`]): the MIS's
    /// sequential impulses, or the soft step ([`SoftStep`]). See
    /// `docs/tuning.md` for the trade between them.
    pub solver: Solver,
}

/// The derive's hash of every field in declaration order, except that the
/// sequential solver adds nothing: a world on the sequential solver keeps
/// the checksum it had before the solver was a setting (its committed
/// goldens stay valid), and any other solver is hashed.
impl core::hash::Hash for Settings {
    fn hash<H: core::hash::Hasher>(&self, h: &mut H) {
        // Every field named: a new one is a compile error until hashed.
        let Settings {
            iterations,
            gravity,
            damping,
            collision_slop,
            collision_bias,
            collision_persistence,
            substeps,
            warm_starting,
            friction,
            restitution,
            bias_impulses,
            block_solver,
            colored_solver,
            sleep_time_threshold,
            idle_speed_threshold,
            solver,
        } = self;
        iterations.hash(h);
        gravity.hash(h);
        damping.hash(h);
        collision_slop.hash(h);
        collision_bias.hash(h);
        collision_persistence.hash(h);
        substeps.hash(h);
        warm_starting.hash(h);
        friction.hash(h);
        restitution.hash(h);
        bias_impulses.hash(h);
        block_solver.hash(h);
        colored_solver.hash(h);
        sleep_time_threshold.hash(h);
        idle_speed_threshold.hash(h);
        if let Solver::Soft(soft) = solver {
            soft.hash(h);
        }
    }
}

/// The solver of a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
pub enum Solver {
    /// Sequential impulses with a velocity-level bias (the MIS's Collision
    /// Solver, Chipmunk's scheme): every sub-step collides, then runs
    /// [`Settings::iterations`] passes over the contacts and joints, and
    /// corrects overlap and joint drift by a fraction per step
    /// ([`Settings::collision_bias`], each joint's `error_bias`).
    #[default]
    Sequential,
    /// The soft step (Box2D v3's scheme, in fixed point): collide once per
    /// step, then [`SoftStep::substeps`] sub-steps of one solve with soft
    /// constraints, a position update and a relax pass without bias; a
    /// restitution pass at the end. It always solves in the colored order
    /// (which costs it no quality: `docs/solver.md`);
    /// [`Settings::iterations`], [`Settings::collision_bias`],
    /// [`Settings::collision_slop`], [`Settings::bias_impulses`],
    /// [`Settings::block_solver`] and [`Settings::colored_solver`] do not
    /// apply.
    Soft(SoftStep),
}

impl Solver {
    /// The soft step with its defaults ([`SoftStep::default`]).
    pub const SOFT: Solver = Solver::Soft(SoftStep::DEFAULT);

    /// True for the soft step.
    pub fn is_soft(&self) -> bool {
        matches!(self, Solver::Soft(_))
    }
}

/// The soft step's parameters. Stiffness is a frequency (hertz) and a
/// damping ratio, as a spring's: the solver corrects overlap and joint
/// drift like a damped spring of that frequency would, never faster than
/// [`push_out_speed`](Self::push_out_speed) for contacts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SoftStep {
    /// Sub-steps per step (default 4, valid `1..=`[`MAX_SUBSTEPS`]):
    /// velocities, the solve, positions and the relax pass run this many
    /// times on the contacts found once per step.
    pub substeps: u32,
    /// Contact stiffness in hertz (default 30), capped at a quarter of the
    /// sub-step rate; contacts with a static or kinematic body use twice it.
    pub contact_hertz: Real,
    /// Contact damping ratio (default 10: heavily over-damped, no bounce
    /// from the push-out).
    pub contact_damping_ratio: Real,
    /// Joint stiffness in hertz (default 60), capped at a quarter of the
    /// sub-step rate: stiff enough to behave rigid.
    pub joint_hertz: Real,
    /// Joint damping ratio (default 2).
    pub joint_damping_ratio: Real,
    /// Largest speed at which overlap is pushed out, a length per second
    /// (default 3 m/s; scale it with the length unit).
    pub push_out_speed: Real,
    /// Approach speed above which restitution applies, a length per second
    /// (default 1 m/s; scale it with the length unit).
    pub restitution_threshold: Real,
    /// Overlap left without push-out, a length (default 0, as Box2D v3:
    /// the contact's own softness keeps a loaded contact a hair deep, so
    /// the narrowphase still finds it). The soft step's own, apart from
    /// [`Settings::collision_slop`], whose Chipmunk value 0.1 in the
    /// built-in scenes would let stacks sink 10 cm. Measured: `pyramid_20`
    /// sinks 3.0 cm at 0, 5.0 cm at 0.001 m, 11.8 cm at 0.005 m.
    pub slop: Real,
    /// The arithmetic of the contact passes (default
    /// [`ContactPrecision::Full`]): exact I32F32, or the narrow kernels,
    /// faster, on coarser grids ([`ContactPrecision::Narrow`]).
    pub contact_precision: ContactPrecision,
}

/// The arithmetic of the soft step's contact passes. Both are
/// deterministic: the same bits on every platform, build and thread
/// count, whichever kernels run ([`Kernels`](crate::solver::Kernels));
/// they give different bits from each other.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ContactPrecision {
    /// Every product of the passes in exact I32F32 (64×64-bit products
    /// rounded once). The default.
    #[default]
    Full,
    /// Every value a pass multiplies held in 32 bits (velocities read on
    /// Q16.16, impulses on Q8.24, the normal and lever arms on Q8.24), so
    /// that each product is one 32×32→64-bit multiply: faster wide
    /// kernels, at a cost in accuracy `docs/numerics.md` measures ("The
    /// narrow contact kernels"). A contact whose values leave the grids'
    /// windows (heavy bodies, fast ones, pixel units) is solved exactly,
    /// so nothing saturates that the full kernels would not.
    Narrow,
}

/// The derive's hash of every field, except that the default
/// [`ContactPrecision::Full`] adds nothing: a world on the full kernels
/// keeps the checksum it had before the precision was a setting.
impl core::hash::Hash for SoftStep {
    fn hash<H: core::hash::Hasher>(&self, h: &mut H) {
        // Every field named: a new one is a compile error until hashed.
        let SoftStep {
            substeps,
            contact_hertz,
            contact_damping_ratio,
            joint_hertz,
            joint_damping_ratio,
            push_out_speed,
            restitution_threshold,
            slop,
            contact_precision,
        } = self;
        substeps.hash(h);
        contact_hertz.hash(h);
        contact_damping_ratio.hash(h);
        joint_hertz.hash(h);
        joint_damping_ratio.hash(h);
        push_out_speed.hash(h);
        restitution_threshold.hash(h);
        slop.hash(h);
        if *contact_precision != ContactPrecision::Full {
            contact_precision.hash(h);
        }
    }
}

impl SoftStep {
    /// The defaults, Box2D v3's: 4 sub-steps, contacts 30 Hz with damping
    /// ratio 10, joints 60 Hz with ratio 2, push-out 3 m/s, restitution
    /// from 1 m/s, no slop.
    pub const DEFAULT: SoftStep = SoftStep {
        substeps: 4,
        contact_hertz: Real::lit("30"),
        contact_damping_ratio: Real::lit("10"),
        joint_hertz: Real::lit("60"),
        joint_damping_ratio: Real::lit("2"),
        push_out_speed: Real::lit("3"),
        restitution_threshold: Real::lit("1"),
        slop: Real::ZERO,
        contact_precision: ContactPrecision::Full,
    };

    /// The defaults for a world measured in a unit with `units_per_metre`
    /// units per metre (pixels, centimetres): the push-out speed, the
    /// restitution threshold and the slop scaled by it; frequencies have
    /// no length unit.
    pub fn scaled(self, units_per_metre: Real) -> SoftStep {
        SoftStep {
            push_out_speed: self.push_out_speed * units_per_metre,
            restitution_threshold: self.restitution_threshold * units_per_metre,
            slop: self.slop * units_per_metre,
            ..self
        }
    }

    /// The ranges [`Settings::validate`] enforces: sub-steps in
    /// `1..=`[`MAX_SUBSTEPS`], every frequency and ratio in `[0, 10⁶]`, the
    /// speeds ≥ 0.
    pub fn validate(&self) -> Result<(), SpaceError> {
        if self.substeps == 0 || self.substeps > MAX_SUBSTEPS {
            return Err(SpaceError::InvalidSetting(
                "soft step substeps must be in 1..=64",
            ));
        }
        let bounded = |x: Real| !x.is_negative() && x <= MAX_SOFT_PARAMETER;
        if !(bounded(self.contact_hertz)
            && bounded(self.contact_damping_ratio)
            && bounded(self.joint_hertz)
            && bounded(self.joint_damping_ratio))
        {
            return Err(SpaceError::InvalidSetting(
                "soft step frequencies and damping ratios must be in [0, 1e6]",
            ));
        }
        if self.push_out_speed.is_negative()
            || self.restitution_threshold.is_negative()
            || self.slop.is_negative()
        {
            return Err(SpaceError::InvalidSetting(
                "soft step push-out speed, restitution threshold and slop must be ≥ 0",
            ));
        }
        Ok(())
    }
}

impl Default for SoftStep {
    fn default() -> Self {
        SoftStep::DEFAULT
    }
}

/// Largest soft-step frequency or damping ratio: far above any useful
/// value, low enough that the soft coefficients never saturate.
pub const MAX_SOFT_PARAMETER: Real = Real::lit("1000000");

/// [`Settings::sleep_time_threshold`] that turns sleeping off.
pub const SLEEP_NEVER: Real = Real::MAX;

/// The default sleep time threshold, 0.5 s (Box2D v3's): long enough that
/// a body at the top of its bounce (speed 0 for an instant) never sleeps,
/// short enough that a settled pile stops costing within a second.
pub const DEFAULT_SLEEP_TIME_THRESHOLD: Real = Real::lit("0.5");

/// The default idle speed, 0.05 m/s (Box2D v3's): a body slower than this
/// moves less than a millimetre per 1/60 s step.
pub const DEFAULT_IDLE_SPEED_THRESHOLD: Real = Real::lit("0.05");

/// The default collision slop, 0.005 m (see [`Settings`]): deep enough that
/// resting contacts keep their overlap (the standard stacks rest 4.4 mm
/// deep with any slop from 0.005 m up, and are as still as with 0.1), far
/// below the 1 cm a player may sink into the ground. A slop of 0.001 m
/// makes `stack_10` jitter (bodies at up to 0.6 m/s after 5 s).
pub const DEFAULT_COLLISION_SLOP: Real = Real::lit("0.005");

/// The collision slop of Chipmunk and of the built-in scenes, 0.1 (a pixel
/// scale value). Scene descriptions that omit the slop take this one, so
/// scene files and their checksums are unchanged by the metre default.
pub const CHIPMUNK_COLLISION_SLOP: Real = Real::lit("0.1");

/// `0.9^60`, Chipmunk's default collision bias, computed exactly in `Real`
/// arithmetic at compile time (no float `pow`).
pub const DEFAULT_COLLISION_BIAS: Real = {
    let base = Real::lit("0.9");
    let mut acc = Real::ONE;
    let mut i = 0;
    while i < 60 {
        acc = acc.mul_const(base);
        i += 1;
    }
    acc
};

impl Settings {
    /// Checks the ranges [`Space::set_settings`](super::Space::set_settings) enforces: iterations ≤
    /// [`MAX_ITERATIONS`], damping ≥ 0, collision bias in [0, 1], collision
    /// slop ≥ 0, substeps in `1..=`[`MAX_SUBSTEPS`].
    pub fn validate(&self) -> Result<(), SpaceError> {
        if self.iterations > MAX_ITERATIONS {
            return Err(SpaceError::InvalidSetting("iterations must be ≤ 1024"));
        }
        if self.damping.is_negative() {
            return Err(SpaceError::InvalidSetting("damping must be ≥ 0"));
        }
        if self.collision_bias.is_negative() || self.collision_bias > Real::ONE {
            return Err(SpaceError::InvalidSetting(
                "collision bias must be in [0, 1]",
            ));
        }
        if self.collision_slop.is_negative() {
            return Err(SpaceError::InvalidSetting("collision slop must be ≥ 0"));
        }
        if self.substeps == 0 || self.substeps > MAX_SUBSTEPS {
            return Err(SpaceError::InvalidSetting("substeps must be in 1..=64"));
        }
        if self.sleep_time_threshold.is_negative() {
            return Err(SpaceError::InvalidSetting(
                "sleep time threshold must be ≥ 0",
            ));
        }
        if self.idle_speed_threshold.is_negative() {
            return Err(SpaceError::InvalidSetting(
                "idle speed threshold must be ≥ 0",
            ));
        }
        if let Solver::Soft(soft) = &self.solver {
            soft.validate()?;
        }
        Ok(())
    }

    /// True unless [`sleep_time_threshold`](Self::sleep_time_threshold) is
    /// [`SLEEP_NEVER`].
    pub fn sleeping_enabled(&self) -> bool {
        self.sleep_time_threshold != SLEEP_NEVER
    }
}

/// Most sub-steps per step a space accepts: 64 sub-steps of a 1/60 s frame
/// are already steps of 1/3840 s, far below what any game scene needs, and
/// the cap bounds the work one `step` call (or a forged snapshot) can ask for.
pub const MAX_SUBSTEPS: u32 = 64;

/// Most solver iterations a space accepts: far above any useful value (the
/// trade-off flattens out by 30), low enough that a forged snapshot cannot
/// make one step run for hours.
pub const MAX_ITERATIONS: u32 = 1024;

impl Default for Settings {
    fn default() -> Self {
        Settings {
            iterations: 10,
            gravity: Vect::ZERO,
            damping: Real::ONE,
            collision_slop: DEFAULT_COLLISION_SLOP,
            collision_bias: DEFAULT_COLLISION_BIAS,
            collision_persistence: 3,
            substeps: 1,
            warm_starting: true,
            friction: true,
            restitution: true,
            bias_impulses: true,
            block_solver: true,
            colored_solver: false,
            sleep_time_threshold: DEFAULT_SLEEP_TIME_THRESHOLD,
            idle_speed_threshold: DEFAULT_IDLE_SPEED_THRESHOLD,
            solver: Solver::Sequential,
        }
    }
}
