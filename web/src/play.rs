//! The playground: one scene the page steps at 60 Hz, that the user drags
//! (a mouse joint) and drops bodies into.
use tamias2d::body::{Body, BodyHandle};
use tamias2d::constraint::{Constraint, ConstraintHandle, PivotJoint};
use tamias2d::shape::mass::{moment_for_box, moment_for_circle};
use tamias2d::shape::{Shape, ShapeFilter};
use tamias2d::snapshot;
use tamias2d::space::Space;
use tamias2d::{Real, Vect};
use tamias2d_scenes::{SceneDesc, ScriptedWorld};

/// What a dropped body looks like: sized and weighed like the scene's own
/// first dynamic body, so a drop fits a pile of 1 m boxes and a bowl of
/// 10-pixel balls alike.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Dropper {
    /// Width of a dropped box, diameter of a dropped ball.
    pub size: Real,
    /// Its mass.
    pub mass: Real,
}

/// The shape of a dropped body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DropKind {
    /// A ball.
    Ball,
    /// A square box.
    Box,
}

impl Dropper {
    /// Measured from `space`'s first dynamic body (slot order) and its
    /// first shape's box; 1 × 1 of mass 1 in a scene without one.
    pub fn of(space: &Space) -> Dropper {
        let fallback = Dropper {
            size: Real::ONE,
            mass: Real::ONE,
        };
        let Some((h, body)) = space.bodies().find(|(_, b)| b.is_dynamic()) else {
            return fallback;
        };
        let Some((_, shape)) = space.body_shapes(h).next() else {
            return fallback;
        };
        let bb = shape.local_bb();
        let size = (bb.r - bb.l).max(bb.t - bb.b);
        if !size.is_positive() || !body.mass().is_positive() {
            return fallback;
        }
        Dropper {
            size,
            mass: body.mass(),
        }
    }

    /// `k` times the size (and `k²` times the mass, the same density).
    pub fn scaled(self, k: i32) -> Dropper {
        let k = Real::from_int(k);
        Dropper {
            size: self.size * k,
            mass: self.mass * k * k,
        }
    }

    /// Adds a body of `kind` at `at`, at rest. Errors say what the space
    /// refused.
    pub fn drop(&self, space: &mut Space, kind: DropKind, at: Vect) -> Result<BodyHandle, String> {
        let half = self.size * Real::HALF;
        let moment = match kind {
            DropKind::Ball => moment_for_circle(self.mass, Real::ZERO, half, Vect::ZERO),
            DropKind::Box => moment_for_box(self.mass, self.size, self.size),
        };
        let mut body = Body::new(self.mass, moment).map_err(|e| e.to_string())?;
        body.set_position(at);
        let h = space.add_body(body).map_err(|e| e.to_string())?;
        let shape = match kind {
            DropKind::Ball => Shape::circle_shape_new(h, half, Vect::ZERO),
            DropKind::Box => Shape::box_shape_new(h, self.size, self.size, Real::ZERO),
        };
        let shape = shape
            .and_then(|s| s.with_material(Real::lit("0.7"), Real::lit("0.2")))
            .map_err(|e| e.to_string())?;
        space.add_shape(shape).map_err(|e| e.to_string())?;
        Ok(h)
    }
}

/// A point of the page (an `f64` pointer position in world units) as a
/// `Vect`: the one conversion from float input, exact and the same on every
/// machine (`Real::from_f64` rounds to the nearest 2⁻³²).
pub fn point(x: f64, y: f64) -> Result<Vect, String> {
    Vect::from_f64(x, y).map_err(|e| format!("({x}, {y}): {e}"))
}

/// A drag in progress: a kinematic body that follows the pointer, pinned
/// to the grabbed body by a pivot joint of bounded force (Chipmunk's demo
/// "mouse joint").
#[derive(Clone, Copy, Debug)]
struct Drag {
    mouse: BodyHandle,
    joint: ConstraintHandle,
    /// Where the pointer is: the mouse body gets there in one step.
    target: Vect,
}

/// The playground.
#[derive(Debug)]
pub struct Play {
    /// The scene (its script, if any, keeps running).
    pub world: ScriptedWorld,
    /// Its registry name, or the name in its JSON.
    pub name: String,
    dropper: Dropper,
    drag: Option<Drag>,
    /// The last saved frame snapshot ([`Play::save`]).
    saved: Vec<u8>,
}

impl Play {
    /// Builds `desc`.
    pub fn new(desc: &SceneDesc) -> Result<Play, String> {
        let world = desc.build().map_err(|e| format!("{}: {e}", desc.name))?;
        Ok(Play {
            dropper: Dropper::of(&world.space),
            name: desc.name.clone(),
            world,
            drag: None,
            saved: Vec::new(),
        })
    }

    /// A built-in scene by registry name.
    pub fn builtin(name: &str) -> Result<Play, String> {
        let desc = tamias2d_scenes::builtin(name).ok_or_else(|| format!("no scene {name:?}"))?;
        Play::new(&desc)
    }

    /// A scene from its JSON description (the format of `tamias scene save`).
    pub fn from_json(json: &str) -> Result<Play, String> {
        let desc: SceneDesc =
            serde_json::from_str(json).map_err(|e| format!("invalid scene JSON: {e}"))?;
        Play::new(&desc)
    }

    /// `n` steps of the scene. While a body is dragged, the mouse body is
    /// given, before each step, the velocity that takes it to the pointer in
    /// that step (and none once there): the joint sees a moving anchor,
    /// never a teleport.
    pub fn step(&mut self, n: u32) -> Result<(), String> {
        for _ in 0..n {
            if let Some(drag) = self.drag {
                let rate = self.world.dt.recip();
                if let Some(mouse) = self.world.space.body_mut(drag.mouse) {
                    mouse.set_velocity((drag.target - mouse.position()).mult(rate));
                }
            }
            self.world.step().map_err(|e| e.to_string())?;
        }
        Ok(())
    }

    /// Drops a body of `kind` at `at`.
    pub fn drop_body(&mut self, kind: DropKind, at: Vect) -> Result<BodyHandle, String> {
        self.dropper.drop(&mut self.world.space, kind, at)
    }

    /// Starts dragging the dynamic body under `at` (within `reach`); false
    /// if there is none.
    pub fn drag_begin(&mut self, at: Vect, reach: Real) -> Result<bool, String> {
        self.drag_end()?;
        let space = &mut self.world.space;
        let Some((shape, _)) = space.point_query_nearest(at, reach, ShapeFilter::ALL) else {
            return Ok(false);
        };
        let Some(target) = space.shape(shape).map(Shape::body) else {
            return Ok(false);
        };
        let Some(body) = space.body(target).filter(|b| b.is_dynamic()) else {
            return Ok(false);
        };
        let anchor = body.world_to_local(at);
        // Strong enough to lift the body against 60 g, soft enough that a
        // dragged box pushes a pile instead of tunnelling through it.
        let weight = body.mass() * space.gravity().length().max(Real::ONE);
        let mut mouse = Body::new_kinematic();
        mouse.set_position(at);
        let mouse = space.add_body(mouse).map_err(|e| e.to_string())?;
        let mut joint = Constraint::new(
            mouse,
            target,
            PivotJoint::new(Vect::ZERO, anchor).map_err(|e| e.to_string())?,
        )
        .map_err(|e| e.to_string())?;
        joint
            .set_max_force(weight * Real::from_int(60))
            .map_err(|e| e.to_string())?;
        // Chipmunk's demo value, 0.85^60: 85 % of the error left after one
        // second (15 % corrected per 1/60 s step).
        joint
            .set_error_bias(Real::lit("0.000058"))
            .map_err(|e| e.to_string())?;
        joint.set_collide_bodies(false);
        let joint = match space.add_constraint(joint) {
            Ok(j) => j,
            Err(e) => {
                space.remove_body(mouse).map_err(|e| e.to_string())?;
                return Err(e.to_string());
            }
        };
        self.drag = Some(Drag {
            mouse,
            joint,
            target: at,
        });
        Ok(true)
    }

    /// Moves the drag point to `at` (the mouse body follows on the next
    /// step).
    pub fn drag_move(&mut self, at: Vect) {
        if let Some(drag) = self.drag.as_mut() {
            drag.target = at;
        }
    }

    /// Ends the drag (removes the joint and the mouse body).
    pub fn drag_end(&mut self) -> Result<(), String> {
        let Some(drag) = self.drag.take() else {
            return Ok(());
        };
        let space = &mut self.world.space;
        space
            .remove_constraint(drag.joint)
            .map_err(|e| e.to_string())?;
        space.remove_body(drag.mouse).map_err(|e| e.to_string())?;
        Ok(())
    }

    /// True while a body is dragged.
    pub fn dragging(&self) -> bool {
        self.drag.is_some()
    }

    /// Saves the world's frame (frame snapshot bytes, kept here); returns
    /// their length.
    pub fn save(&mut self) -> usize {
        snapshot::save_frame_into(&self.world.space, &mut self.saved)
    }

    /// Loads the saved frame back (validated; on error the world is
    /// untouched). A drag in progress ends first: its joint and mouse body
    /// belong to the present, not to the saved frame.
    pub fn load(&mut self) -> Result<(), String> {
        if self.saved.is_empty() {
            return Err("no snapshot saved yet".into());
        }
        self.drag_end()?;
        self.world
            .space
            .load_frame_snapshot(&self.saved)
            .map_err(|e| e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dropped_box_falls_and_a_drag_lifts_it() -> Result<(), String> {
        let mut play = Play::builtin("pyramid_20")?;
        let before = play.world.space.bodies().count();
        let top = Vect::from_ints(0, 40);
        let h = play.drop_body(DropKind::Box, top)?;
        assert_eq!(play.world.space.bodies().count(), before + 1);
        play.step(10)?;
        let y = play.world.space.body(h).map(|b| b.position().y);
        assert!(y.is_some_and(|y| y < Real::from_int(40)), "{y:?}");
        // Grab it and pull it up 5 units: it follows.
        let at = play
            .world
            .space
            .body(h)
            .map(|b| b.position())
            .ok_or("body")?;
        assert!(play.drag_begin(at, Real::ONE)?);
        let goal = at + Vect::from_ints(0, 5);
        play.drag_move(goal);
        play.step(60)?;
        let now = play
            .world
            .space
            .body(h)
            .map(|b| b.position())
            .ok_or("body")?;
        assert!(now.dist(goal) < Real::ONE, "{now:?} vs {goal:?}");
        play.drag_end()?;
        assert!(!play.dragging());
        assert_eq!(play.world.space.bodies().count(), before + 1);
        Ok(())
    }

    #[test]
    fn a_sleeping_pile_wakes_when_a_box_is_dragged() -> Result<(), String> {
        let mut play = Play::builtin("pyramid_20")?;
        play.step(400)?;
        // The top box: the highest dynamic body.
        let (top, at) = play
            .world
            .space
            .bodies()
            .filter(|(_, b)| b.is_dynamic())
            .map(|(h, b)| (h, b.position()))
            .max_by_key(|&(_, p)| p.y)
            .ok_or("no box")?;
        assert!(play.world.space.body(top).is_some_and(|b| b.is_sleeping()));
        assert!(play.drag_begin(at, Real::HALF)?);
        let goal = at + Vect::from_ints(3, 2);
        play.drag_move(goal);
        play.step(60)?;
        let now = play
            .world
            .space
            .body(top)
            .map(|b| b.position())
            .ok_or("body")?;
        assert!(now.dist(goal) < Real::HALF, "{now:?} vs {goal:?}");
        Ok(())
    }

    #[test]
    fn nothing_under_the_pointer_is_no_drag() -> Result<(), String> {
        let mut play = Play::builtin("pyramid_20")?;
        assert!(!play.drag_begin(Vect::from_ints(0, 10_000), Real::ONE)?);
        assert!(!play.dragging());
        Ok(())
    }

    #[test]
    fn a_saved_frame_loads_back_to_the_same_checksum() -> Result<(), String> {
        let mut play = Play::builtin("pyramid_20")?;
        play.step(5)?;
        assert!(play.load().is_err());
        assert!(play.save() > 0);
        let saved = play.world.space.checksum();
        play.step(5)?;
        assert_ne!(play.world.space.checksum(), saved);
        play.load()?;
        assert_eq!(play.world.space.checksum(), saved);
        Ok(())
    }

    #[test]
    fn scene_json_loads_and_bad_json_is_an_error() -> Result<(), String> {
        let desc = tamias2d_scenes::builtin("stack_10").ok_or("stack_10")?;
        let json = serde_json::to_string(&desc).map_err(|e| e.to_string())?;
        let play = Play::from_json(&json)?;
        assert_eq!(play.world.space.bodies().count(), 11);
        assert!(Play::from_json("{").is_err_and(|e| e.contains("invalid scene JSON")));
        Ok(())
    }
}
