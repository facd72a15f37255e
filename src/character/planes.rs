//! The least translation that clears a set of planes: how a character is
//! pushed out of the shapes that moved into it.
//!
//! Each plane is a unit normal `n` (out of the surface) and the signed
//! separation `s` of the character from it (negative: overlapping). A
//! translation `d` changes it to `s + d·n`. The solver is projected
//! Gauss–Seidel over the planes, as a contact solver is over contacts:
//! each plane's accumulated push along its normal is raised to clear the
//! plane (to `target`) and never goes below zero, so a plane is only ever
//! pushed away from, and two opposite planes (squeezed between a floor and
//! a ceiling) settle on the push between them instead of fighting. At most
//! [`MAX_PLANE_ITERATIONS`] sweeps; it stops early when a sweep moves less
//! than one ulp per plane.
use serde::{Deserialize, Serialize};

use crate::math::{Real, Vect};

/// Sweeps of the plane solver at most.
pub const MAX_PLANE_ITERATIONS: u32 = 20;

/// A surface near the character.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Plane {
    /// Unit normal out of the surface, toward the character.
    pub normal: Vect,
    /// The character's signed distance from it (negative: overlapping).
    pub separation: Real,
}

/// The translation that moves the character to at least `target` from
/// every plane it can (see the module docs). The planes' separations are
/// left as they were; the result is the sum of the pushes.
pub fn solve_planes(planes: &mut [Plane], target: Real) -> Vect {
    let mut pushes = vec![Real::ZERO; planes.len()];
    let mut d = Vect::ZERO;
    for _ in 0..MAX_PLANE_ITERATIONS {
        let mut moved = Real::ZERO;
        for (plane, push) in planes.iter().zip(pushes.iter_mut()) {
            let gap = plane.separation + d.dot(plane.normal) - target;
            let before = *push;
            *push = (before - gap).max(Real::ZERO);
            let step = *push - before;
            d += plane.normal * step;
            moved += step.abs();
        }
        if moved <= Real::from_bits(planes.len() as i64) {
            break;
        }
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane(nx: i32, ny: i32, s: Real) -> Plane {
        Plane {
            normal: Vect::from_ints(nx, ny).normalize(),
            separation: s,
        }
    }

    #[test]
    fn one_plane_is_cleared_exactly() {
        let mut p = [plane(0, 1, Real::ratio(-1, 4))];
        let d = solve_planes(&mut p, Real::ZERO);
        assert_eq!(d, Vect::new(Real::ZERO, Real::ratio(1, 4)));
    }

    #[test]
    fn a_corner_clears_both_walls() {
        let mut p = [
            plane(0, 1, Real::ratio(-1, 8)),
            plane(1, 0, Real::ratio(-1, 4)),
        ];
        let d = solve_planes(&mut p, Real::ZERO);
        assert_eq!(d, Vect::new(Real::ratio(1, 4), Real::ratio(1, 8)));
    }

    #[test]
    fn planes_already_clear_do_not_pull() {
        let mut p = [plane(0, 1, Real::ONE)];
        assert_eq!(solve_planes(&mut p, Real::ZERO), Vect::ZERO);
    }

    #[test]
    fn a_wedge_converges_to_clear_both() {
        // Floor and a 45° wall, both overlapped.
        let mut p = [plane(0, 1, -Real::HALF), plane(-1, 1, -Real::HALF)];
        let d = solve_planes(&mut p, Real::ZERO);
        for pl in p {
            let s = pl.separation + d.dot(pl.normal);
            assert!(s >= -Real::from_bits(64), "{s:?}");
        }
    }
}
