//! Mass helpers (placeholder: being written).
use super::{Geometry, MassInfo, MassSpec};

/// Mass properties of a geometry (placeholder).
pub fn shape_mass_info(_geometry: &Geometry, _spec: MassSpec) -> MassInfo {
    MassInfo::default()
}
