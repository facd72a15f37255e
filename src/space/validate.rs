//! The invariants of a [`WorldState`](super::WorldState), checked: inside every snapshot
//! load (untrusted input), after every step in validation builds, and by
//! [`Space::validate`](super::Space::validate).
use crate::arbiter::Arbiter;
use crate::body::{Body, BodyType};
use crate::shape::{Geometry, MassSpec};

use super::{level, WorldState};

/// Checks a [`WorldState`](super::WorldState)'s invariants (see [`Space::validate`](super::Space::validate)): settings
/// in range; step counters consistent (no `dt` before the first step, a
/// positive one after it); arenas (free lists, lengths); every body's
/// invariants and cached inverses; every shape's body link, geometry and
/// mass specification; constraints (parameters, two different live
/// bodies); arbiter order, references, contact counts (cleared slots past
/// the count), states and stamps. Returns a description of the
/// first violation. What it checks of each field of the state, or why it
/// checks nothing, is listed in the field ledger (`space/ledger.rs`), which
/// the compiler keeps complete.
pub fn validate_state(state: &WorldState) -> Result<(), String> {
    validate_state_with(state, None)
}

/// [`validate_state`](super::validate_state) for a world whose level (static bodies and their
/// shapes, in `level`'s slots) is known valid: a frame installed around
/// this world's own level. The level objects' own checks and the arenas'
/// free lists (checked on the frame's parts before installing,
/// `ArenaPart::check_bookkeeping`) are skipped; a static body or a static
/// body's shape outside the level's slots is an error; everything that
/// refers to the level is checked as usual.
pub(crate) fn validate_state_trusting_level(
    state: &WorldState,
    level: &level::LevelIndex,
) -> Result<(), String> {
    validate_state_with(state, Some(level))
}

fn validate_state_with(
    state: &WorldState,
    level: Option<&level::LevelIndex>,
) -> Result<(), String> {
    state
        .settings
        .validate()
        .map_err(|e| format!("settings: {e}"))?;
    validate_counters(state)?;
    if level.is_none() {
        state
            .bodies
            .validate()
            .map_err(|e| format!("bodies: {e}"))?;
        state
            .shapes
            .validate()
            .map_err(|e| format!("shapes: {e}"))?;
    }
    // With a trusted level, its slots are skipped, and a frame slot may not
    // add to the level (its digest would no longer be the world's).
    let (body_runs, shape_runs) = level.map_or((&[][..], &[][..]), |l| {
        (l.body_runs.as_slice(), l.shape_runs.as_slice())
    });
    let bodies = crate::arena::outside_runs(body_runs, state.bodies.capacity_slots() as u32)
        .filter_map(|i| state.bodies.get_by_index(i));
    for (h, b) in bodies {
        if level.is_some() && b.body_type() == BodyType::Static {
            return Err(format!(
                "body {h:?}: a frame holds no static body (static bodies are the level)"
            ));
        }
        b.validate_derived()
            .map_err(|e| format!("body {h:?}: {e}"))?;
        if !b.can_step() {
            return Err(format!(
                "body {h:?}: a dynamic body without mass (inverse mass 0) cannot step"
            ));
        }
    }
    // Piles repeat one local geometry; checking each distinct run once
    // spares the polygon checks' square roots (exact either way).
    let mut checked: Option<&Geometry> = None;
    let shapes = crate::arena::outside_runs(shape_runs, state.shapes.capacity_slots() as u32)
        .filter_map(|i| state.shapes.get_by_index(i));
    for (h, s) in shapes {
        let Some(body) = state.bodies.get(s.body) else {
            return Err(format!("shape {h:?} names missing body {:?}", s.body));
        };
        if level.is_some() && body.body_type() == BodyType::Static {
            return Err(format!(
                "shape {h:?}: a frame holds no shape of a static body (they are the level)"
            ));
        }
        if checked != Some(&s.geometry) {
            s.geometry
                .validate()
                .map_err(|e| format!("shape {h:?}: {e}"))?;
            checked = Some(&s.geometry);
        }
        s.material
            .validate()
            .map_err(|e| format!("shape {h:?}: {e}"))?;
        if let MassSpec::Mass(v) | MassSpec::Density(v) = s.mass_spec {
            if v.is_negative() {
                return Err(format!("shape {h:?}: negative mass or density"));
            }
        }
    }
    crate::constraint::validate_constraints(&state.constraints, &state.bodies)?;
    let mut prev: Option<(u32, u32)> = None;
    for arb in &state.arbiters {
        let key = arb.key();
        if key.0 >= key.1 || prev.is_some_and(|p| p >= key) {
            return Err(format!("arbiter {key:?} out of canonical order"));
        }
        prev = Some(key);
        validate_arbiter(state, arb)?;
    }
    validate_sleep(state)
}

/// One arbiter's references, contact count, unused slots, state and
/// stamp (live arbiters, and dormant ones with their age made a stamp).
pub(super) fn validate_arbiter(state: &WorldState, arb: &Arbiter) -> Result<(), String> {
    let key = arb.key();
    let (Some(a), Some(b)) = (state.shapes.get(arb.shape_a), state.shapes.get(arb.shape_b)) else {
        return Err(format!("arbiter {key:?} names a missing shape"));
    };
    if a.body != arb.body_a || b.body != arb.body_b {
        return Err(format!("arbiter {key:?} bodies do not match its shapes"));
    }
    if arb.count() != usize::from(arb.count) {
        return Err(format!("arbiter {key:?} has too many contacts"));
    }
    // The narrowphase never pairs a body with itself or two bodies that
    // cannot move, and neither a shape's body nor a body's type changes.
    let dynamic = |h| state.bodies.get(h).is_some_and(Body::is_dynamic);
    if arb.body_a == arb.body_b || !(dynamic(arb.body_a) || dynamic(arb.body_b)) {
        return Err(format!("arbiter {key:?} pairs bodies that never collide"));
    }
    arb.validate(state.stamp)
        .map_err(|e| format!("arbiter {key:?}: {e}"))?;
    // The narrowphase clears the slots past the count, so that the state
    // (and its checksum) does not depend on earlier contacts.
    let unused = arb.contacts.get(arb.count()..).unwrap_or(&[]);
    if unused.iter().any(|c| *c != Default::default()) {
        return Err(format!("arbiter {key:?} has data past its contact count"));
    }
    Ok(())
}

/// Step counter and time steps: a step with `dt > 0` is the only thing that
/// advances `stamp`, and it shifts `current_dt` into `prev_dt`.
fn validate_counters(state: &WorldState) -> Result<(), String> {
    let (cur, prev) = (state.current_dt, state.prev_dt);
    let ok = match state.stamp {
        0 => cur.is_zero() && prev.is_zero(),
        1 => cur.is_positive() && prev.is_zero(),
        _ => cur.is_positive() && prev.is_positive(),
    };
    if !ok {
        return Err(format!(
            "stamp {} with current dt {cur} and previous dt {prev}",
            state.stamp
        ));
    }
    // Every step has at least one sub-step (a positive dt has at least one
    // non-empty sub-step), so there are never more steps than sub-steps.
    if state.steps > state.stamp {
        return Err(format!(
            "{} steps but only {} sub-steps",
            state.steps, state.stamp
        ));
    }
    Ok(())
}

/// The sleep part of [`validate_state`](super::validate_state): every
/// sleeping body's root is a sleeping body whose root is itself; dormant
/// arbiters are sorted, share no pair with a live one, have no awake
/// dynamic body, pass the arbiter checks with their age (`stamp`) at most
/// the world's stamp, and are never mid-step first collisions.
fn validate_sleep(state: &WorldState) -> Result<(), String> {
    for (h, b) in state.bodies.iter() {
        let Some(root) = b.sleep.island else {
            continue;
        };
        let root_ok = state
            .bodies
            .get_by_index(root)
            .is_some_and(|(_, r)| r.sleep.island == Some(root));
        if !root_ok {
            return Err(format!(
                "body {h:?} sleeps in island {root}, which is not a sleeping root"
            ));
        }
    }
    let mut prev: Option<(u32, u32)> = None;
    for arb in &state.dormant_arbiters {
        let key = arb.key();
        if key.0 >= key.1 || prev.is_some_and(|p| p >= key) {
            return Err(format!("dormant arbiter {key:?} out of canonical order"));
        }
        prev = Some(key);
        if state
            .arbiters
            .binary_search_by_key(&key, Arbiter::key)
            .is_ok()
        {
            return Err(format!("dormant arbiter {key:?} is also live"));
        }
        let awake = |h| {
            state
                .bodies
                .get(h)
                .is_some_and(|b| b.body_type() == BodyType::Dynamic && !b.is_sleeping())
        };
        let asleep = |h| state.bodies.get(h).is_some_and(Body::is_sleeping);
        if awake(arb.body_a) || awake(arb.body_b) || !(asleep(arb.body_a) || asleep(arb.body_b)) {
            return Err(format!(
                "dormant arbiter {key:?} does not rest between sleeping bodies"
            ));
        }
        // Checked as if it touched `age` steps before the world's stamp.
        let age = arb.stamp;
        if age >= state.stamp {
            return Err(format!("dormant arbiter {key:?} is older than the world"));
        }
        let mut as_live = arb.clone();
        as_live.stamp = state.stamp.saturating_sub(age);
        validate_arbiter(state, &as_live)?;
    }
    Ok(())
}
