//! From a [`SceneDesc`] to a running [`ScriptedWorld`], and a scripted world
//! to bytes and back.
//!
//! Building validates everything (settings, every body and shape, force
//! targets, labels, and the bodies of future spawns) and returns a
//! [`SceneError`] naming what is wrong; it never panics. Spawned bodies are
//! validated at build time by building them into a scratch space, so that
//! [`ScriptedWorld::step`] cannot fail on bad data halfway through a run.
//!
//! A scripted world's script is state: [`ScriptedWorld::save`] writes the
//! engine snapshot together with the script (forces, the spawns and which
//! of them have happened, the `begin` counters), and
//! [`ScriptedWorld::load`] brings back a world that continues exactly as the
//! one saved, scripted forces and spawns included.
//!
//! Bodies are created in description order and each body's shapes right
//! after it, so handles (and therefore the state bytes) depend only on the
//! description.
mod save;

pub use save::LoadError;

use core::fmt;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use super::desc::{
    BodyDesc, BodyKind, GeometryDesc, MassDesc, SceneDesc, ShapeDesc, ShapeMassDesc, SpawnDesc,
};
use tamias2d::body::{Body, BodyHandle};
use tamias2d::math::{Real, Transform, Vect, BB};
use tamias2d::shape::{CollisionType, Shape, ShapeError};
use tamias2d::space::{Settings, Space, SpaceError};

/// Which body of a description an error is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyPath {
    /// `SceneDesc::bodies[index]`.
    Initial(usize),
    /// `SceneDesc::spawns[spawn].bodies[index]`.
    Spawn {
        /// Index of the spawn event.
        spawn: usize,
        /// Index of the body in it.
        index: usize,
    },
}

impl fmt::Display for BodyPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BodyPath::Initial(i) => write!(f, "bodies[{i}]"),
            BodyPath::Spawn { spawn, index } => write!(f, "spawns[{spawn}].bodies[{index}]"),
        }
    }
}

/// Why a scene could not be built or stepped.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SceneError {
    /// `dt` must be > 0.
    TimeStep,
    /// The settings were rejected.
    Settings(SpaceError),
    /// A body was rejected (illegal mass or moment, space full).
    Body {
        /// The body.
        at: BodyPath,
        /// Why.
        error: SpaceError,
    },
    /// A shape was rejected (negative radius, concave raw polygon …).
    Shape {
        /// The body.
        at: BodyPath,
        /// Index into the body's shapes.
        shape: usize,
        /// Why.
        error: SpaceError,
    },
    /// A dynamic body ended with zero mass or moment (no explicit mass and
    /// no shape with mass or density).
    Massless(BodyPath),
    /// `forces[force]` names a body index that does not exist.
    ForceTarget {
        /// Index into `forces`.
        force: usize,
        /// The bad body index.
        body: u32,
    },
    /// Two bodies share a label.
    DuplicateLabel(String),
    /// `constraints[constraint]` was rejected (a body index that does not
    /// exist, a missing or foreign parameter, a bad value).
    Constraint {
        /// Index into `constraints`.
        constraint: usize,
        /// Why.
        why: String,
    },
    /// The space rejected a step.
    Step(SpaceError),
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::TimeStep => f.write_str("time step must be > 0"),
            SceneError::Settings(e) => write!(f, "settings: {e}"),
            SceneError::Body { at, error } => write!(f, "{at}: {error}"),
            SceneError::Shape { at, shape, error } => write!(f, "{at}.shapes[{shape}]: {error}"),
            SceneError::Massless(at) => write!(
                f,
                "{at}: dynamic body has no mass (set an explicit mass or give a shape mass or density)"
            ),
            SceneError::ForceTarget { force, body } => {
                write!(f, "forces[{force}] names body {body}, which does not exist")
            }
            SceneError::DuplicateLabel(l) => write!(f, "label {l:?} is used by two bodies"),
            SceneError::Constraint { constraint, why } => {
                write!(f, "constraints[{constraint}]: {why}")
            }
            SceneError::Step(e) => write!(f, "step: {e}"),
        }
    }
}

impl std::error::Error for SceneError {}

/// A `begin` counter registered for a collision type pair.
#[derive(Clone, Debug)]
struct BeginCounter {
    types: (CollisionType, CollisionType),
    count: Arc<AtomicU64>,
}

/// A built scene: the space plus what the description scripts around it.
#[derive(Debug)]
pub struct ScriptedWorld {
    /// The world.
    pub space: Space,
    /// Time step of every step.
    pub dt: Real,
    /// Default number of steps of a run.
    pub steps: u32,
    /// Handles in creation order: initial bodies, then spawned ones.
    bodies: Vec<BodyHandle>,
    labels: BTreeMap<String, BodyHandle>,
    forces: Vec<(BodyHandle, Vect, Real)>,
    /// Spawn events sorted by `at_step` (stable), and the next one due.
    spawns: Vec<SpawnDesc>,
    next_spawn: usize,
    /// Number of initial (not spawned) bodies.
    initial_bodies: usize,
    counters: Vec<BeginCounter>,
    steps_taken: u64,
}

impl SceneDesc {
    /// Builds the scene: a new [`Space`] with the settings, bodies and
    /// shapes, the scripted forces and spawns, and the `begin` counters.
    /// Spawns due at step 0 are added at once.
    pub fn build(&self) -> Result<ScriptedWorld, SceneError> {
        if !self.dt.is_positive() {
            return Err(SceneError::TimeStep);
        }
        let mut space = Space::new();
        space
            .set_settings(Settings::from(&self.settings))
            .map_err(SceneError::Settings)?;
        let mut scene = ScriptedWorld {
            space,
            dt: self.dt,
            steps: self.steps,
            bodies: Vec::with_capacity(self.total_bodies()),
            labels: BTreeMap::new(),
            forces: Vec::with_capacity(self.forces.len()),
            spawns: Vec::new(),
            next_spawn: 0,
            initial_bodies: self.bodies.len(),
            counters: Vec::with_capacity(self.begin_counters.len()),
            steps_taken: 0,
        };
        for (i, desc) in self.bodies.iter().enumerate() {
            scene.add(desc, BodyPath::Initial(i))?;
        }
        for (i, f) in self.forces.iter().enumerate() {
            let h = usize::try_from(f.body)
                .ok()
                .and_then(|b| scene.bodies.get(b).copied())
                .ok_or(SceneError::ForceTarget {
                    force: i,
                    body: f.body,
                })?;
            scene.forces.push((h, f.force, f.torque));
        }
        for (i, c) in self.constraints.iter().enumerate() {
            let body = |index: u32| {
                usize::try_from(index)
                    .ok()
                    .and_then(|b| scene.bodies.get(b).copied())
                    .ok_or_else(|| SceneError::Constraint {
                        constraint: i,
                        why: format!("body {index} does not exist"),
                    })
            };
            let (a, b) = (body(c.a)?, body(c.b)?);
            let built = c
                .build(&scene.space, a, b)
                .and_then(|c| scene.space.add_constraint(c).map_err(|e| e.to_string()));
            built.map_err(|why| SceneError::Constraint { constraint: i, why })?;
        }
        validate_spawns(self)?;
        let mut spawns = self.spawns.clone();
        spawns.sort_by_key(|s| s.at_step);
        scene.spawns = spawns;
        for c in &self.begin_counters {
            scene.add_counter(c.type_a, c.type_b);
        }
        scene.spawn_due()?;
        Ok(scene)
    }
}

/// Builds every spawned body into a scratch space (same settings are not
/// needed: only body and shape validity is checked) and checks labels.
fn validate_spawns(desc: &SceneDesc) -> Result<(), SceneError> {
    let mut labels: Vec<&str> = desc
        .bodies
        .iter()
        .filter_map(|b| b.label.as_deref())
        .collect();
    for (s, spawn) in desc.spawns.iter().enumerate() {
        let mut scratch = Space::new();
        for (i, body) in spawn.bodies.iter().enumerate() {
            add_body(&mut scratch, body, BodyPath::Spawn { spawn: s, index: i })?;
            labels.extend(body.label.as_deref());
        }
    }
    labels.sort_unstable();
    match labels.windows(2).find(|w| w.first() == w.get(1)) {
        Some(w) => Err(SceneError::DuplicateLabel(
            w.first().map_or_else(String::new, |l| (*l).to_owned()),
        )),
        None => Ok(()),
    }
}

impl ScriptedWorld {
    /// One step: apply the scripted forces, step the space by `dt`, then add
    /// the bodies whose spawn is due after this many steps.
    pub fn step(&mut self) -> Result<(), SceneError> {
        self.step_by(self.dt)
    }

    /// [`ScriptedWorld::step`] by `dt` instead of the world's own step.
    fn step_by(&mut self, dt: Real) -> Result<(), SceneError> {
        for (i, &(h, force, torque)) in self.forces.iter().enumerate() {
            // A scripted body that no longer resolves (removed, or the space
            // was replaced by one with other handles) is an error, not a
            // silently skipped force.
            let body = self.space.body_mut(h).ok_or(SceneError::ForceTarget {
                force: i,
                body: h.index(),
            })?;
            body.apply_force(force);
            body.apply_torque(torque);
        }
        self.space.step(dt).map_err(SceneError::Step)?;
        // 2^64 steps never happen: never saturates.
        self.steps_taken = self.steps_taken.saturating_add(1);
        self.spawn_due()
    }

    /// Rolls the scene's space back (or forward) to `state` in place, keeping
    /// handlers and every handle the scene holds valid (the in-memory
    /// rollback path). `steps_taken` is set to the state's step count
    /// ([`WorldState::steps`](tamias2d::space::WorldState::steps), not the
    /// sub-step `stamp`) so spawns stay on schedule.
    pub fn restore_state(&mut self, state: &tamias2d::space::WorldState) {
        self.space.restore_state(state);
        self.steps_taken = state.steps;
        // Spawns after the restored step have not happened yet.
        self.next_spawn = self
            .spawns
            .iter()
            .take_while(|s| u64::from(s.at_step) <= state.steps)
            .count();
        let spawned: usize = self
            .spawns
            .iter()
            .take(self.next_spawn)
            .map(|s| s.bodies.len())
            .fold(0, usize::saturating_add);
        // Both count bodies in memory: the sum never saturates.
        self.bodies
            .truncate(self.initial_bodies.saturating_add(spawned));
        let live = &self.bodies;
        self.labels.retain(|_, h| live.contains(h));
    }

    /// A world with no script around `space` (a bare engine snapshot, say):
    /// each step is the space's step by `dt`. Its bodies, in slot order,
    /// are its creation-order bodies.
    pub fn unscripted(space: Space, dt: Real) -> ScriptedWorld {
        let bodies: Vec<BodyHandle> = space.bodies().map(|(h, _)| h).collect();
        ScriptedWorld {
            initial_bodies: bodies.len(),
            bodies,
            labels: BTreeMap::new(),
            forces: Vec::new(),
            spawns: Vec::new(),
            next_spawn: 0,
            counters: Vec::new(),
            steps_taken: space.steps(),
            steps: 0,
            dt,
            space,
        }
    }

    /// Takes `n` steps.
    pub fn step_n(&mut self, n: u32) -> Result<(), SceneError> {
        (0..n).try_for_each(|_| self.step())
    }

    /// Takes the scene's default number of steps ([`ScriptedWorld::steps`]).
    pub fn run(&mut self) -> Result<(), SceneError> {
        self.step_n(self.steps)
    }

    /// Steps taken since the scene was built.
    pub fn steps_taken(&self) -> u64 {
        self.steps_taken
    }

    /// The handle of the body labelled `label`.
    pub fn body(&self, label: &str) -> Option<BodyHandle> {
        self.labels.get(label).copied()
    }

    /// Handles of all bodies added so far, in creation order (initial bodies
    /// in description order, then spawned ones).
    pub fn bodies(&self) -> &[BodyHandle] {
        &self.bodies
    }

    /// Number of `begin` callbacks so far for the type pair `(a, b)` (either
    /// order), or `None` if the description has no such counter.
    pub fn begin_count(&self, a: CollisionType, b: CollisionType) -> Option<u64> {
        self.counters
            .iter()
            .find(|c| c.types == (a, b) || c.types == (b, a))
            .map(|c| c.count.load(Ordering::Relaxed))
    }

    /// Adds a body (validated) and records its handle and label.
    fn add(&mut self, desc: &BodyDesc, at: BodyPath) -> Result<BodyHandle, SceneError> {
        let h = add_body(&mut self.space, desc, at)?;
        self.bodies.push(h);
        if let Some(label) = &desc.label {
            if self.labels.insert(label.clone(), h).is_some() {
                return Err(SceneError::DuplicateLabel(label.clone()));
            }
        }
        Ok(h)
    }

    /// Adds the bodies of every spawn due at the current step count.
    fn spawn_due(&mut self) -> Result<(), SceneError> {
        while let Some(spawn) = self.spawns.get_mut(self.next_spawn) {
            if u64::from(spawn.at_step) > self.steps_taken {
                break;
            }
            // Cloned, not moved out: a rollback to before this step spawns
            // the same bodies again.
            let bodies = spawn.bodies.clone();
            let s = self.next_spawn;
            // `next_spawn` indexes `spawns` (checked above): never saturates.
            self.next_spawn = self.next_spawn.saturating_add(1);
            for (i, desc) in bodies.iter().enumerate() {
                self.add(desc, BodyPath::Spawn { spawn: s, index: i })?;
            }
        }
        Ok(())
    }

    /// Registers a counting `begin` handler for the pair (it accepts the pair).
    fn add_counter(&mut self, a: CollisionType, b: CollisionType) {
        if self.begin_count(a, b).is_some() {
            return;
        }
        let count = Arc::new(AtomicU64::new(0));
        let inner = Arc::clone(&count);
        self.space.add_collision_handler(a, b).begin = Some(Box::new(move |_| {
            inner.fetch_add(1, Ordering::Relaxed);
            true
        }));
        self.counters.push(BeginCounter {
            types: (a, b),
            count,
        });
    }
}

/// Creates the body, adds it and its shapes to `space`.
fn add_body(space: &mut Space, desc: &BodyDesc, at: BodyPath) -> Result<BodyHandle, SceneError> {
    let body_err = |error: SpaceError| SceneError::Body { at, error };
    let mut body = match desc.kind {
        BodyKind::Dynamic => Body::new(Real::ZERO, Real::ZERO).map_err(|e| body_err(e.into()))?,
        BodyKind::Kinematic => Body::new_kinematic(),
        BodyKind::Static => Body::new_static(),
    };
    if let MassDesc::Explicit { mass, moment } = desc.mass {
        body.set_mass(mass).map_err(|e| body_err(e.into()))?;
        body.set_moment(moment).map_err(|e| body_err(e.into()))?;
    }
    body.set_angle(desc.angle);
    body.set_position(desc.position);
    body.set_velocity(desc.velocity);
    body.set_angular_velocity(desc.angular_velocity);
    body.set_bullet(desc.bullet);
    let h = space.add_body(body).map_err(body_err)?;
    for (i, shape) in desc.shapes.iter().enumerate() {
        let shape_err = |error: SpaceError| SceneError::Shape {
            at,
            shape: i,
            error,
        };
        let s = make_shape(h, shape).map_err(|e| shape_err(e.into()))?;
        space.add_shape(s).map_err(shape_err)?;
    }
    if desc.kind == BodyKind::Dynamic {
        let massive = space
            .body(h)
            .is_some_and(|b| b.mass().is_positive() && b.moment().is_positive());
        if !massive {
            return Err(SceneError::Massless(at));
        }
    }
    Ok(h)
}

/// The shape a description stands for, attached to `body`.
fn make_shape(body: BodyHandle, d: &ShapeDesc) -> Result<Shape, ShapeError> {
    let shape = match &d.geometry {
        GeometryDesc::Circle { radius, offset } => Shape::circle_shape_new(body, *radius, *offset)?,
        GeometryDesc::Segment {
            a,
            b,
            radius,
            neighbors,
        } => {
            let mut s = Shape::segment_shape_new(body, *a, *b, *radius)?;
            if let Some(n) = neighbors {
                s.set_segment_neighbors(n.prev, n.next)?;
            }
            s
        }
        GeometryDesc::Poly { verts, radius } => {
            Shape::poly_shape_new(body, verts, &Transform::IDENTITY, *radius)?
        }
        GeometryDesc::RawPoly { verts, radius } => Shape::poly_shape_new_raw(body, verts, *radius)?,
        GeometryDesc::Box {
            width,
            height,
            radius,
            offset,
        } => {
            if width.is_negative() || height.is_negative() {
                return Err(ShapeError::Negative("box size"));
            }
            if *offset == Vect::ZERO {
                Shape::box_shape_new(body, *width, *height, *radius)?
            } else {
                let bb = BB::for_extents(*offset, *width * Real::HALF, *height * Real::HALF);
                Shape::box_shape_new2(body, bb, *radius)?
            }
        }
    };
    let mut shape = shape.with_material(d.friction, d.elasticity)?;
    shape.material.surface_velocity = d.surface_velocity;
    shape.filter = d.filter;
    shape.collision_type = d.collision_type;
    shape.sensor = d.sensor;
    match d.mass {
        ShapeMassDesc::None => {}
        ShapeMassDesc::Mass(m) => shape.set_mass(m)?,
        ShapeMassDesc::Density(rho) => shape.set_density(rho)?,
    }
    Ok(shape)
}
