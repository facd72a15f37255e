//! Polygon constructors (placeholder: being written).
