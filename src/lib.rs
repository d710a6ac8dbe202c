//! threadcut turns CNC thread-cutting cycles into exact pass-by-pass machine motion.
//!
//! Data flows one way:
//!
//! ```text
//! text ──gcode::Reader──► Line (words with spans) ──dialect::<controller>──► thread::Job
//!      ──toolpath::build──► Toolpath ──► post (plain G-code, JSON lines) / passes / checks
//! ```
//!
//! * [`gcode`] lexes lines and keeps the modal state (units, positions, lead); it knows no controller.
//! * [`dialect`] holds one module per controller: it validates the cycle in the controller's own words
//!   (raising the controller's alarms as [`diag::Diagnostic`]s) and lowers it into a [`thread::Job`].
//! * [`thread`] is the machine-neutral model: geometry, lead, depth law, infeed law, entry and exit.
//! * [`toolpath`] is the only place that creates motion.
//! * [`program`] streams a whole program through a dialect; [`post`] writes the results.
//! * [`commands`] is each `threadcut` command as one function, for the command line and bindings.
//!
//! ```
//! use threadcut::{dialect, machine::Machine, program};
//! let src = "G00 X80 Z10\nG78 P010060 Q0.1 R0.05\nG78 X60 Z-30 P1.2 Q0.4 F2\n";
//! let machine = Machine::built_in("gsk980").unwrap();
//! let jobs = program::jobs(src.as_bytes(), &machine).unwrap();
//! let passes = jobs[0].passes().unwrap();
//! assert_eq!(passes.last().unwrap().depth, 1.2);
//! ```

pub mod apt;
pub mod check;
pub mod commands;
pub mod convert;
pub mod diag;
pub mod dialect;
pub mod eol;
pub mod gcode;
pub mod interp;
pub mod machine;
pub mod mill;
pub mod millprog;
pub mod part;
pub mod post;
pub mod program;
pub mod render;
pub mod sim;
pub mod source;
pub mod text;
pub mod thread;
pub mod threads;
pub mod toolpath;
pub mod translate;
pub mod turning;
pub mod units;
