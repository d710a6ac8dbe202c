//! G-code as written: a streaming line reader, the lexer, and the modal state shared by the lathe
//! dialects. This module knows no controller; each dialect tells it its conventions.

pub mod lexer;
pub mod modal;
pub mod reader;

pub use lexer::{lex_line, lex_line_syntax, LineShape, Syntax, Word, WordSummary};
pub use modal::{Conventions, Modal, MotionMode, PlainMove, Position, PositionCodes, Reference};
pub use reader::{Line, Reader};
