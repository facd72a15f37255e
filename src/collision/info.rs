//! The narrow phase's answer and the limits every stage of it shares: a
//! [`CollisionInfo`] of up to [`MAX_CONTACTS_PER_ARBITER`] [`Contact`]s, the
//! [`WarmStartId`] that carries GJK's last edge from step to step, the
//! touching tolerance [`CONTACT_TOLERANCE`], and the public query answer
//! [`ContactPointSet`] of [`ContactPoint`]s.
//!
//! Plain data, below every algorithm of the narrow phase: the pair functions,
//! GJK, EPA and the clipping fill these in; [`collide`](super::collide)
//! returns them.
use serde::{Deserialize, Serialize};

use crate::math::{Real, Vect};

/// Contacts one pair can produce (Chipmunk `CP_MAX_CONTACTS_PER_ARBITER`).
pub const MAX_CONTACTS_PER_ARBITER: usize = 2;

/// Largest separation at which two shapes still count as touching (2^-20,
/// about 10^-6 m). A resting contact's separation hovers around zero by a few
/// ulp; with a strict `≤ 0` test a contact that rounds to +1 ulp vanishes for
/// a step and the body rocks on the remaining one (found by the sliding
/// incline test). A slightly separated contact gets no bias (its distance is
/// above `−slop`) and only stops approach.
pub const CONTACT_TOLERANCE: Real = Real::from_bits(1 << 12);

/// GJK warm-start id (MIS `CollisionID`; not a feature id): the vertex indices of the last
/// closest edge of the Minkowski difference, one byte each,
/// `a₀ << 24 | b₀ << 16 | a₁ << 8 | b₁` (indices on shape `a` and `b` of the
/// caller). 0 means "no cache". Store the id a [`collide`](super::collide) call returns and
/// pass it to the next call for the same pair; any value is safe (an id that
/// names missing vertices is ignored) and gives a correct answer.
///
/// The answer is not always bit-identical to a cold start's: when two
/// features of the Minkowski difference are equally deep (a box centred in a
/// wider one: pushed up or down) or equally deep to within EPA's ranking
/// precision (~2^-61 relative), GJK/EPA report the one their starting point
/// leads to, and a face made of collinear pieces gets the normal of the piece
/// GJK ends on (equal up to rounding). Either answer is right and the result
/// is still deterministic, since the id is part of the arbiter state.
/// Polygon pairs answered by separating axes (see [`poly_to_poly`](super::poly_to_poly)) neither
/// read nor change the id, so their answer is the same for every id.
pub type WarmStartId = u32;

/// One narrowphase contact: a pair of points on the two surfaces with its
/// feature id (an element of MIS `CollisionInfo`, per step). The arbiter
/// keeps it as an [`arbiter::ManifoldPoint`](crate::arbiter::ManifoldPoint),
/// the solver turns that into a
/// `solver::ContactConstraint`; the public
/// query type is [`ContactPoint`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Contact {
    /// World-space point on the surface of `a` (rounding radius included).
    pub point_a: Vect,
    /// World-space point on the surface of `b`.
    pub point_b: Vect,
    /// Signed separation `(point_b − point_a) · normal`: negative when the
    /// shapes overlap (Chipmunk's convention), 0 when they just touch; at
    /// most [`CONTACT_TOLERANCE`] above 0 for shapes a hair apart.
    pub distance: Real,
    /// Feature id, `(feature on a) << 16 | (feature on b)`, where a feature is
    /// a vertex / endpoint index (0 for a circle). The same touching features
    /// keep the same id from step to step.
    pub feature_id: u32,
}

/// The result of [`collide`](super::collide) (MIS `CollisionInfo`). A per-step value, not
/// snapshot state (it holds a `usize`); arbiters keep the [`Contact`]s (as
/// [`ManifoldPoint`](crate::arbiter::ManifoldPoint)s) and `warm_start_id`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct CollisionInfo {
    /// Unit normal from `a` toward `b` (zero when `count == 0`).
    pub normal: Vect,
    /// Number of valid entries of `contacts` (≤ [`MAX_CONTACTS_PER_ARBITER`]).
    pub count: usize,
    /// The contacts; entries past `count` are zero.
    pub contacts: [Contact; MAX_CONTACTS_PER_ARBITER],
    /// Warm-start id for the next call on this pair.
    pub warm_start_id: WarmStartId,
    /// True if GJK or EPA stopped at its iteration cap; the answer is then
    /// the best found, not necessarily the exact one.
    pub hit_iteration_cap: bool,
}

impl CollisionInfo {
    /// An empty info carrying the warm-start id `warm_start_id`.
    pub fn new(warm_start_id: WarmStartId) -> CollisionInfo {
        let mut info = EMPTY;
        info.warm_start_id = warm_start_id;
        info
    }

    /// The valid contacts.
    pub fn contacts(&self) -> &[Contact] {
        self.contacts.get(..self.count).unwrap_or(&[])
    }

    /// MIS `collisionInfoPushContact`. A third contact cannot be produced by
    /// the pair functions; it would be ignored rather than overflow.
    pub fn push_contact(&mut self, point_a: Vect, point_b: Vect, distance: Real, feature_id: u32) {
        if let Some(slot) = self.contacts.get_mut(self.count) {
            *slot = Contact {
                point_a,
                point_b,
                distance,
                feature_id,
            };
            // count < contacts.len() (the slot exists): never saturates.
            self.count = self.count.saturating_add(1);
        }
    }

    /// The answer of a pair computed near the origin, put back: every
    /// contact point moved by `offset`, the normal zero if there is no
    /// contact, and seen from the other shape if `mirror`
    /// ([`mirror`](Self::mirror)). Each contact is written once, whole:
    /// moving and mirroring in place edited parts of each contact that
    /// were then copied whole, and the copy waited on those stores (a
    /// failed store-to-load forward) on every narrowphase call.
    pub(super) fn placed(&self, offset: Vect, mirror: bool) -> CollisionInfo {
        let place = |c: &Contact| {
            let (a, b) = (c.point_a + offset, c.point_b + offset);
            if mirror {
                Contact {
                    point_a: b,
                    point_b: a,
                    distance: c.distance,
                    feature_id: c.feature_id.rotate_left(16),
                }
            } else {
                Contact {
                    point_a: a,
                    point_b: b,
                    distance: c.distance,
                    feature_id: c.feature_id,
                }
            }
        };
        let [c0, c1] = &self.contacts;
        let normal = match (self.count, mirror) {
            (0, _) => Vect::ZERO,
            (_, true) => -self.normal,
            (_, false) => self.normal,
        };
        CollisionInfo {
            normal,
            count: self.count,
            contacts: [
                if self.count > 0 { place(c0) } else { *c0 },
                if self.count > 1 { place(c1) } else { *c1 },
            ],
            warm_start_id: if mirror {
                swap_id_shapes(self.warm_start_id)
            } else {
                self.warm_start_id
            },
            hit_iteration_cap: self.hit_iteration_cap,
        }
    }

    /// The same collision seen from the other shape: normal negated, points
    /// and feature-id halves swapped, warm-start id converted.
    pub(super) fn mirrored(mut self) -> CollisionInfo {
        self.mirror();
        self
    }

    /// [`mirrored`](Self::mirrored) in place.
    pub(super) fn mirror(&mut self) {
        self.normal = -self.normal;
        for c in self.contacts.iter_mut().take(self.count) {
            core::mem::swap(&mut c.point_a, &mut c.point_b);
            c.feature_id = c.feature_id.rotate_left(16);
        }
        self.warm_start_id = swap_id_shapes(self.warm_start_id);
    }
}

/// An empty info (all zero), written whole.
const EMPTY: CollisionInfo = CollisionInfo {
    normal: Vect::ZERO,
    count: 0,
    contacts: [Contact {
        point_a: Vect::ZERO,
        point_b: Vect::ZERO,
        distance: Real::ZERO,
        feature_id: 0,
    }; MAX_CONTACTS_PER_ARBITER],
    warm_start_id: 0,
    hit_iteration_cap: false,
};

/// A warm-start id with the roles of the two shapes exchanged (the A and B
/// bytes of each Minkowski point swap places).
#[inline]
pub(super) fn swap_id_shapes(id: WarmStartId) -> WarmStartId {
    ((id & 0x00FF_00FF) << 8) | ((id >> 8) & 0x00FF_00FF)
}

/// One point pair of a [`ContactPointSet`]: the public query answer (MIS /
/// Chipmunk), without feature id. The engine's other contact types are
/// [`Contact`] (narrowphase), [`arbiter::ManifoldPoint`](crate::arbiter::ManifoldPoint)
/// (persistent) and `solver::ContactConstraint`
/// (solver row).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct ContactPoint {
    /// Point on the surface of `a`.
    pub point_a: Vect,
    /// Point on the surface of `b`.
    pub point_b: Vect,
    /// Signed separation along the normal (negative when overlapping).
    pub distance: Real,
}

/// Contacts between two shapes without ids (MIS/Chipmunk `ContactPointSet`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ContactPointSet {
    /// Number of valid points.
    pub count: usize,
    /// Unit normal from `a` toward `b` (zero when `count == 0`).
    pub normal: Vect,
    /// The points; entries past `count` are zero.
    pub points: [ContactPoint; MAX_CONTACTS_PER_ARBITER],
}
