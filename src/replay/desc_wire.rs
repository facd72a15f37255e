//! A [`SceneDesc`] in a form bincode can hold.
//!
//! `SceneDesc` is written for people and other engines: every `Real` is a
//! decimal string read with `deserialize_any` (it also accepts JSON
//! integers), default fields are skipped and `GeometryDesc` is an internally
//! tagged enum. None of that works in a non-self-describing format such as
//! bincode, so a replay stores this mirror instead: the same fields, every
//! `Real` as its raw bits, nothing skipped, externally tagged enums.
//!
//! The conversions destructure every struct and match every enum without a
//! wildcard, so a field or variant added to the scene description is a
//! compile error here rather than a field silently dropped from replays.
use serde::{Deserialize, Serialize};

use crate::math::{Real, Vect};
use crate::scenes::{
    BodyDesc, BodyKind, CounterDesc, ForceDesc, GeometryDesc, MassDesc, Neighbors, SceneDesc,
    ShapeDesc, ShapeMassDesc, SpawnDesc,
};
use crate::shape::{CollisionType, ShapeFilter};
use crate::space::Settings;

/// Mirror of [`SceneDesc`].
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub(crate) struct WireScene {
    name: String,
    settings: Settings,
    dt: Real,
    steps: u32,
    bodies: Vec<WireBody>,
    forces: Vec<WireForce>,
    spawns: Vec<WireSpawn>,
    begin_counters: Vec<(CollisionType, CollisionType)>,
}

#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
struct WireBody {
    label: Option<String>,
    kind: WireKind,
    position: Vect,
    angle: Real,
    velocity: Vect,
    angular_velocity: Real,
    /// `None`: mass from shapes; `Some((mass, moment))`: explicit.
    mass: Option<(Real, Real)>,
    shapes: Vec<WireShape>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
enum WireKind {
    Dynamic,
    Kinematic,
    Static,
}

#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
enum WireGeometry {
    Circle {
        radius: Real,
        offset: Vect,
    },
    Segment {
        a: Vect,
        b: Vect,
        radius: Real,
        /// `(prev, next)`.
        neighbors: Option<(Vect, Vect)>,
    },
    Poly {
        verts: Vec<Vect>,
        radius: Real,
    },
    RawPoly {
        verts: Vec<Vect>,
        radius: Real,
    },
    Box {
        width: Real,
        height: Real,
        radius: Real,
        offset: Vect,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
enum WireShapeMass {
    None,
    Mass(Real),
    Density(Real),
}

#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
struct WireShape {
    geometry: WireGeometry,
    friction: Real,
    elasticity: Real,
    surface_velocity: Vect,
    collision_type: CollisionType,
    filter: ShapeFilter,
    sensor: bool,
    mass: WireShapeMass,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
struct WireForce {
    body: u32,
    force: Vect,
    torque: Real,
}

#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
struct WireSpawn {
    at_step: u32,
    bodies: Vec<WireBody>,
}

impl From<&SceneDesc> for WireScene {
    fn from(d: &SceneDesc) -> WireScene {
        let SceneDesc {
            name,
            settings,
            dt,
            steps,
            bodies,
            forces,
            spawns,
            begin_counters,
        } = d;
        WireScene {
            name: name.clone(),
            settings: Settings::from(settings),
            dt: *dt,
            steps: *steps,
            bodies: bodies.iter().map(WireBody::from).collect(),
            forces: forces
                .iter()
                .map(
                    |&ForceDesc {
                         body,
                         force,
                         torque,
                     }| WireForce {
                        body,
                        force,
                        torque,
                    },
                )
                .collect(),
            spawns: spawns
                .iter()
                .map(|SpawnDesc { at_step, bodies }| WireSpawn {
                    at_step: *at_step,
                    bodies: bodies.iter().map(WireBody::from).collect(),
                })
                .collect(),
            begin_counters: begin_counters
                .iter()
                .map(|&CounterDesc { type_a, type_b }| (type_a, type_b))
                .collect(),
        }
    }
}

impl From<WireScene> for SceneDesc {
    fn from(w: WireScene) -> SceneDesc {
        SceneDesc {
            name: w.name,
            settings: (&w.settings).into(),
            dt: w.dt,
            steps: w.steps,
            bodies: w.bodies.into_iter().map(BodyDesc::from).collect(),
            forces: w
                .forces
                .into_iter()
                .map(|f| ForceDesc {
                    body: f.body,
                    force: f.force,
                    torque: f.torque,
                })
                .collect(),
            spawns: w
                .spawns
                .into_iter()
                .map(|s| SpawnDesc {
                    at_step: s.at_step,
                    bodies: s.bodies.into_iter().map(BodyDesc::from).collect(),
                })
                .collect(),
            begin_counters: w
                .begin_counters
                .into_iter()
                .map(|(type_a, type_b)| CounterDesc { type_a, type_b })
                .collect(),
        }
    }
}

impl From<&BodyDesc> for WireBody {
    fn from(b: &BodyDesc) -> WireBody {
        let BodyDesc {
            label,
            kind,
            position,
            angle,
            velocity,
            angular_velocity,
            mass,
            shapes,
        } = b;
        WireBody {
            label: label.clone(),
            kind: match kind {
                BodyKind::Dynamic => WireKind::Dynamic,
                BodyKind::Kinematic => WireKind::Kinematic,
                BodyKind::Static => WireKind::Static,
            },
            position: *position,
            angle: *angle,
            velocity: *velocity,
            angular_velocity: *angular_velocity,
            mass: match *mass {
                MassDesc::FromShapes => None,
                MassDesc::Explicit { mass, moment } => Some((mass, moment)),
            },
            shapes: shapes.iter().map(WireShape::from).collect(),
        }
    }
}

impl From<WireBody> for BodyDesc {
    fn from(w: WireBody) -> BodyDesc {
        BodyDesc {
            label: w.label,
            kind: match w.kind {
                WireKind::Dynamic => BodyKind::Dynamic,
                WireKind::Kinematic => BodyKind::Kinematic,
                WireKind::Static => BodyKind::Static,
            },
            position: w.position,
            angle: w.angle,
            velocity: w.velocity,
            angular_velocity: w.angular_velocity,
            mass: match w.mass {
                None => MassDesc::FromShapes,
                Some((mass, moment)) => MassDesc::Explicit { mass, moment },
            },
            shapes: w.shapes.into_iter().map(ShapeDesc::from).collect(),
        }
    }
}

impl From<&ShapeDesc> for WireShape {
    fn from(s: &ShapeDesc) -> WireShape {
        let ShapeDesc {
            geometry,
            friction,
            elasticity,
            surface_velocity,
            collision_type,
            filter,
            sensor,
            mass,
        } = s;
        WireShape {
            geometry: match geometry {
                GeometryDesc::Circle { radius, offset } => WireGeometry::Circle {
                    radius: *radius,
                    offset: *offset,
                },
                GeometryDesc::Segment {
                    a,
                    b,
                    radius,
                    neighbors,
                } => WireGeometry::Segment {
                    a: *a,
                    b: *b,
                    radius: *radius,
                    neighbors: neighbors.map(|Neighbors { prev, next }| (prev, next)),
                },
                GeometryDesc::Poly { verts, radius } => WireGeometry::Poly {
                    verts: verts.clone(),
                    radius: *radius,
                },
                GeometryDesc::RawPoly { verts, radius } => WireGeometry::RawPoly {
                    verts: verts.clone(),
                    radius: *radius,
                },
                GeometryDesc::Box {
                    width,
                    height,
                    radius,
                    offset,
                } => WireGeometry::Box {
                    width: *width,
                    height: *height,
                    radius: *radius,
                    offset: *offset,
                },
            },
            friction: *friction,
            elasticity: *elasticity,
            surface_velocity: *surface_velocity,
            collision_type: *collision_type,
            filter: *filter,
            sensor: *sensor,
            mass: match *mass {
                ShapeMassDesc::None => WireShapeMass::None,
                ShapeMassDesc::Mass(m) => WireShapeMass::Mass(m),
                ShapeMassDesc::Density(d) => WireShapeMass::Density(d),
            },
        }
    }
}

impl From<WireShape> for ShapeDesc {
    fn from(w: WireShape) -> ShapeDesc {
        ShapeDesc {
            geometry: match w.geometry {
                WireGeometry::Circle { radius, offset } => GeometryDesc::Circle { radius, offset },
                WireGeometry::Segment {
                    a,
                    b,
                    radius,
                    neighbors,
                } => GeometryDesc::Segment {
                    a,
                    b,
                    radius,
                    neighbors: neighbors.map(|(prev, next)| Neighbors { prev, next }),
                },
                WireGeometry::Poly { verts, radius } => GeometryDesc::Poly { verts, radius },
                WireGeometry::RawPoly { verts, radius } => GeometryDesc::RawPoly { verts, radius },
                WireGeometry::Box {
                    width,
                    height,
                    radius,
                    offset,
                } => GeometryDesc::Box {
                    width,
                    height,
                    radius,
                    offset,
                },
            },
            friction: w.friction,
            elasticity: w.elasticity,
            surface_velocity: w.surface_velocity,
            collision_type: w.collision_type,
            filter: w.filter,
            sensor: w.sensor,
            mass: match w.mass {
                WireShapeMass::None => ShapeMassDesc::None,
                WireShapeMass::Mass(m) => ShapeMassDesc::Mass(m),
                WireShapeMass::Density(d) => ShapeMassDesc::Density(d),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes;

    #[test]
    fn every_builtin_scene_round_trips_through_the_mirror() {
        for (name, _) in scenes::list() {
            let Some(desc) = scenes::builtin(name) else {
                continue;
            };
            let back = SceneDesc::from(WireScene::from(&desc));
            assert_eq!(back, desc, "{name}");
        }
    }
}
