//! Diagnostics are values: a stable code, a source span, the controller's wording and a hint.
//! The library never prints; the CLI renders them with the source line and a caret.

use std::fmt;

/// A place in the source: a byte range plus the 1-based line and column of its start.
///
/// Columns count bytes, like most compilers, so a caret lands under the word even in files that are
/// not UTF-8.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Span {
    /// Byte offset of the first byte in the whole input.
    pub start: u64,
    /// Length in bytes.
    pub len: u32,
    /// 1-based line number.
    pub line: u32,
    /// 1-based column (bytes) of the first byte.
    pub column: u32,
}

/// How far apart the offsets of two programs' texts lie: the main input's bytes from 0, those
/// of the `k`th program read from another file (a subprogram a call found in an include
/// directory) from `k × FILE_SPACING`, so that a span names its file by its offset alone, as a
/// compiler's source map places every file in one range of positions. 1 TiB: no input reaches it.
pub const FILE_SPACING: u64 = 1 << 40;

impl Span {
    /// The file the span lies in: 0 for the main input, `k` for the `k`th file a library gave
    /// (see [`FILE_SPACING`]).
    pub const fn file(&self) -> u32 {
        (self.start / FILE_SPACING) as u32
    }

    /// A place known only by its line (column 1, no extent): a finding about a move whose block
    /// is not at hand.
    pub fn at_line(line: u32) -> Span {
        Span {
            line,
            column: 1,
            ..Span::default()
        }
    }

    pub const fn new(start: u64, len: u32, line: u32, column: u32) -> Span {
        Span {
            start,
            len,
            line,
            column,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    Warning,
    Error,
}

/// Stable diagnostic codes: tests and users' scripts match on these, so never renumber them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub enum Code {
    /// A malformed number or word (`X1.2.3`, `X--1`, a letter with no value).
    Syntax,
    /// A number that is not finite or too large to be exact.
    BadNumber,
    /// A word the cycle requires is missing (the controller's alarm).
    MissingWord,
    /// A word's value lies outside the range the controller allows.
    OutOfRange,
    /// Two words or settings that cannot be used together.
    Conflict,
    /// The cycle needs a known start position and none is known.
    UnknownPosition,
    /// Geometry that cannot be cut (depth beyond the part, taper too steep, zero length...).
    Geometry,
    /// The plan would exceed a hard limit on passes or moves.
    TooManyPasses,
    /// A word or statement that this controller does not support.
    Unsupported,
    /// The input is not text the reader can handle (binary garbage, an over-long line).
    Input,
    /// A suspicious but executable value.
    Suspicious,
    /// A machine limit would be exceeded.
    MachineLimit,
    /// `check`: a rapid move enters the blank.
    Collision,
    /// `check`: the synchronised feed (lead × spindle speed) exceeds the machine's axis limit.
    FeedLimit,
    /// `check`: the groove does not reach the thread's depth.
    DepthNotReached,
    /// `check`: the lead exceeds the controller's maximum.
    LeadLimit,
    /// `check`: the run-up before the blank is shorter than the feed needs to settle.
    RunUp,
    /// `check`: the simulated groove departs from the target form (ridge, pitch diameter).
    Form,
    /// `check`: the spindle speed is unknown or not constant.
    Spindle,
    /// A G code the controller does not have (its alarm), e.g. G78 on a Fanuc control.
    UnknownCode,
    /// `check --thread`: the thread cut lies outside its class's limits (pitch diameter, root
    /// diameter, flank angle, lead).
    OutOfClass,
    /// `check`: an axis, lead or feed word without a decimal point on a control that reads it as
    /// least increments.
    DecimalPoint,
    /// `check`: a pull-out shorter than the run-out the synchronised feed needs to stop (δ2).
    RunOut,
    /// `check`: a rapid move enters the blank, which the program and the options do not give but
    /// `check` assumed (E011's twin for an assumed blank).
    CollisionAssumed,
    /// A thread's passes run into material the program left (a shoulder, a face).
    Shoulder,
    /// `check --thread`: outside the class's limits on an assumption — the tool's form, or a taper
    /// thread's face — or shorter than a taper thread's effective length (E016's twin).
    OutOfClassAssumed,
    /// `check`: the machine's state at a thread ruins it — the spindle stopped (M5, M19, the end
    /// of the program, a stop the manual says stops it), turned the other way, or another tool,
    /// between passes of one thread.
    MachineState,
    /// `check`: E017's twin where it rests on an assumption (a program stop that stops the
    /// spindle on most machines, the same tool restated between passes).
    MachineStateAssumed,
    /// `check` of a milled thread: its helix is not a thread — turns of unequal lead, passes
    /// about one axis advancing differently, compensation on the side that cuts the wall, an
    /// entry or exit arc that gouges the finished thread.
    Helix,
    /// `check` of a milled thread: an entry that leaves a mark (a straight move onto the finished
    /// thread's radius), or E019 on an assumption.
    HelixAssumed,
    /// `check` of a tapping cycle: the feed is not the tap's lead (F ≠ pitch × rpm per minute),
    /// the spindle turns against the tap's hand, or the cycle's words are not the control's.
    Tapping,
    /// `check` of a tapping cycle: E020 on an assumption (a floating holder's compensation, the
    /// pitch taken from the program rather than named).
    TappingAssumed,
}

impl Code {
    /// Every code, in the order of their numbers' introduction.
    pub const ALL: [Code; 32] = [
        Code::Syntax,
        Code::BadNumber,
        Code::MissingWord,
        Code::OutOfRange,
        Code::Conflict,
        Code::UnknownPosition,
        Code::Geometry,
        Code::TooManyPasses,
        Code::Unsupported,
        Code::Input,
        Code::Suspicious,
        Code::MachineLimit,
        Code::Collision,
        Code::FeedLimit,
        Code::DepthNotReached,
        Code::LeadLimit,
        Code::RunUp,
        Code::Form,
        Code::Spindle,
        Code::UnknownCode,
        Code::OutOfClass,
        Code::DecimalPoint,
        Code::RunOut,
        Code::CollisionAssumed,
        Code::Shoulder,
        Code::OutOfClassAssumed,
        Code::MachineState,
        Code::MachineStateAssumed,
        Code::Helix,
        Code::HelixAssumed,
        Code::Tapping,
        Code::TappingAssumed,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            Code::Syntax => "E001",
            Code::BadNumber => "E002",
            Code::MissingWord => "E003",
            Code::OutOfRange => "E004",
            Code::Conflict => "E005",
            Code::UnknownPosition => "E006",
            Code::Geometry => "E007",
            Code::TooManyPasses => "E008",
            Code::Unsupported => "E009",
            Code::Input => "E010",
            Code::Suspicious => "W001",
            Code::MachineLimit => "W002",
            Code::Collision => "E011",
            Code::FeedLimit => "E012",
            Code::DepthNotReached => "E013",
            Code::LeadLimit => "E014",
            Code::RunUp => "W003",
            Code::Form => "W004",
            Code::Spindle => "W005",
            Code::UnknownCode => "E015",
            Code::OutOfClass => "E016",
            Code::DecimalPoint => "W006",
            Code::RunOut => "W007",
            Code::CollisionAssumed => "W008",
            Code::OutOfClassAssumed => "W009",
            Code::MachineState => "E017",
            Code::MachineStateAssumed => "W010",
            Code::Shoulder => "E018",
            Code::Helix => "E019",
            Code::HelixAssumed => "W011",
            Code::Tapping => "E020",
            Code::TappingAssumed => "W012",
        }
    }
}

impl fmt::Display for Code {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Diagnostic {
    pub code: Code,
    pub severity: Severity,
    #[serde(skip)]
    pub span: Span,
    pub message: String,
    pub hint: Option<String>,
    /// Where the program ran when the finding was raised inside a called program: each call's
    /// line, outermost first (empty in the main program). A span's file is its offset's
    /// ([`Span::file`]).
    #[serde(skip)]
    pub calls: Vec<Span>,
}

impl Diagnostic {
    pub fn error(code: Code, span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            code,
            severity: Severity::Error,
            span,
            message: message.into(),
            hint: None,
            calls: Vec::new(),
        }
    }

    pub fn warning(code: Code, span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            code,
            severity: Severity::Warning,
            span,
            message: message.into(),
            hint: None,
            calls: Vec::new(),
        }
    }

    pub fn with_hint(mut self, hint: impl Into<String>) -> Diagnostic {
        self.hint = Some(hint.into());
        self
    }

    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// The one-line form of the command line's diagnostics: `file:line:column: error[E004]:
    /// message`. Without a place (line 0: a thread name, an option) the place is left out
    /// (`file: error[E004]: message`, or `error[E004]: message` without a file); the hint is not
    /// part of it.
    pub fn headline(&self, file: Option<&str>) -> String {
        let kind = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        let place = match (file, self.span.line) {
            (Some(f), 0) => format!("{f}: "),
            (Some(f), line) => format!("{f}:{line}:{}: ", self.span.column),
            (None, 0) => String::new(),
            (None, line) => format!("{line}:{}: ", self.span.column),
        };
        format!("{place}{kind}[{}]: {}", self.code, self.message)
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        write!(
            f,
            "{}:{}: {kind}[{}]: {}",
            self.span.line, self.span.column, self.code, self.message
        )?;
        if let Some(hint) = &self.hint {
            write!(f, " (hint: {hint})")?;
        }
        Ok(())
    }
}

impl std::error::Error for Diagnostic {}

pub type Result<T> = std::result::Result<T, Diagnostic>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headline_is_the_one_line_form() {
        let d = Diagnostic::error(Code::OutOfRange, Span::new(20, 2, 2, 8), "P(r)=05: bad")
            .with_hint("0 to 4");
        assert_eq!(
            d.headline(Some("<string>")),
            "<string>:2:8: error[E004]: P(r)=05: bad"
        );
        assert_eq!(d.headline(None), "2:8: error[E004]: P(r)=05: bad");
        let w = Diagnostic::warning(Code::Suspicious, Span::default(), "odd");
        assert_eq!(w.headline(Some("a.nc")), "a.nc: warning[W001]: odd");
        assert_eq!(w.headline(None), "warning[W001]: odd");
    }

    /// Codes are stable and unique: branches merged side by side must not reuse a number. `ALL`
    /// lists every variant (the match below fails to compile when a variant is added, and the
    /// count then fails here until `ALL` has it too).
    #[test]
    fn every_code_has_its_own_number() {
        let listed = |c: Code| match c {
            Code::Syntax
            | Code::BadNumber
            | Code::MissingWord
            | Code::OutOfRange
            | Code::Conflict
            | Code::UnknownPosition
            | Code::Geometry
            | Code::TooManyPasses
            | Code::Unsupported
            | Code::Input
            | Code::Suspicious
            | Code::MachineLimit
            | Code::Collision
            | Code::FeedLimit
            | Code::DepthNotReached
            | Code::LeadLimit
            | Code::RunUp
            | Code::Form
            | Code::Spindle
            | Code::UnknownCode
            | Code::OutOfClass
            | Code::DecimalPoint
            | Code::RunOut
            | Code::CollisionAssumed
            | Code::Shoulder
            | Code::OutOfClassAssumed
            | Code::MachineState
            | Code::MachineStateAssumed
            | Code::Helix
            | Code::HelixAssumed
            | Code::Tapping
            | Code::TappingAssumed => Code::ALL.contains(&c),
        };
        assert!(Code::ALL.iter().all(|&c| listed(c)));
        let mut names: Vec<&str> = Code::ALL.iter().map(|c| c.as_str()).collect();
        names.sort_unstable();
        let n = names.len();
        names.dedup();
        assert_eq!(names.len(), n, "a code number is used twice");
        for name in names {
            assert!(
                (name.starts_with('E') || name.starts_with('W'))
                    && name.len() == 4
                    && name[1..].bytes().all(|b| b.is_ascii_digit()),
                "{name}"
            );
        }
    }
}
