//! Pictures of what a program does. Everything here reads the model's results (the pass table,
//! the simulated section, the toolpath) and writes text; nothing computes motion.

pub mod svg;

pub use svg::{svg, CyclePlot};
