//! The MIS Rigid Body module (placeholder: being written).
use crate::arena::Handle;

/// A rigid body.
#[derive(Clone, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub struct Body {}

/// Handle of a body in a space.
pub type BodyHandle = Handle<Body>;
