//! The mesh layer: scenes, springs, Voronoi masses, procedural scenes.

mod scenes;
