//! Approximate minimum degree ordering (placeholder, being written).
