//! Convex hull (placeholder: being written).
