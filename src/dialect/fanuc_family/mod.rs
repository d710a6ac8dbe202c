//! The Fanuc family's threading cycles, shared by every controller that copies them (Fanuc 0i/30i in
//! G-code systems A, B and C, Fanuc's FS15 program format, Haas, GSK 980TDi): the single-pass box
//! cycle G92 and the multiple-pass cycle G76 (`shared/reference/threading-notes.md` §c.1, §c.3, §e).
//! G numbers are system A's; [`GCodes`] gives the others (G78/G21 for G92, G78 for G76 in C).
//!
//! ```text
//! G92 X(U) Z(W) [R(i)] F(L) [Q] ;                  one pass; modal: a following `X..` repeats it
//! G76 P(m)(r)(a) Q(Δdmin) R(d) ;                   first block: rewrites parameters 5142/5130/5143, 5140, 5141
//! G76 X(U) Z(W) R(i) P(k) Q(Δd) F(L) ;             second block: the cycle
//! G76 X(U) Z(W) I K D F A P Q ;                    or in one block (FS15 format, Haas: `crate::dialect::one_block`)
//! ```
//! P(k), Q(Δd) and Q(Δdmin) are counts of least input increments, written without a decimal point,
//! whatever the machine's decimal-point setting. Q on G32/G92 (and the one-block G76) shifts the
//! thread's start angle, in 0.001°. Each member's words are its own dialect's ([`Flavour`]); each
//! decision is a row of `docs/dialects/fanuc.md` (or `haas.md`).

mod codes;
pub mod contour;
mod family;
mod g76;
mod g92;
pub mod start_angle;
mod turning;

use crate::diag::{Code, Diagnostic, Result};
use crate::gcode::reader::g_code;
use crate::gcode::{Conventions, Line, Modal, MotionMode};

use crate::dialect::{one_block, Read};

pub use codes::*;
pub use family::*;
pub use g76::*;
pub use g92::*;
pub use start_angle::START_ANGLE_Q;

impl FanucFamily {
    /// Reads `line` if it is a G76 or G92 block (or a block repeating a modal G92); `None` otherwise.
    pub fn read(
        &mut self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Option<Read>> {
        // A turning cycle's block, a block of the contour it reads, a repeat of a box cycle.
        if let Some(read) = self.read_turning(conv, line, modal, warnings)? {
            return Ok(Some(read));
        }
        let codes = self.codes;
        // No allocation: this runs on every line offered.
        let gs = || {
            line.words
                .iter()
                .filter(|w| w.letter == b'G')
                .map(|w| (w, g_code(w.value)))
        };
        let cycle = gs()
            .find(|(_, c)| *c == Some(codes.multiple) || *c == Some(codes.single))
            .map(|(w, c)| (w, c.expect("matched")));
        let Some((gword, code)) = cycle else {
            if gs().any(|(_, c)| c.is_some_and(|c| codes.ends_single.contains(&c))) {
                self.g92 = None;
            }
            // A repeat is a block of axis words alone: any G code (a dwell `G4 X1.`, `G50 X..`) makes
            // the block something else.
            let moves = gs().next().is_none()
                && line
                    .words
                    .iter()
                    .any(|w| matches!(w.letter, b'X' | b'Z' | b'U' | b'W'));
            return match self.g92 {
                Some(m) if moves => {
                    let job = self.read_g92(conv, line, modal, line.span(), Some(m), warnings)?;
                    Ok(Some(Read::Cycle(Box::new(job))))
                }
                _ => self.thread_move(conv, line, modal),
            };
        };
        self.run_phase = None;
        self.turning.box_modal = None;
        let name = g_name(code);
        // In systems B and C a G90/G91 may share the cycle's block: it applies to the block's own
        // words (and stays in force), as on the modal reader's blocks.
        let distance: &[u16] = if codes.g90_g91 { &[900, 910] } else { &[] };
        crate::dialect::alone_in_block(line, gword.span, &name, distance)?;
        for (_, c) in gs() {
            match c {
                Some(900) if codes.g90_g91 => modal.absolute = true,
                Some(910) if codes.g90_g91 => modal.absolute = false,
                _ => {}
            }
        }
        let second = line
            .words
            .iter()
            .any(|w| matches!(w.letter, b'X' | b'Z' | b'U' | b'W'));
        if code == codes.single {
            if !second {
                return Err(Diagnostic::error(
                    Code::MissingWord,
                    gword.span,
                    format!("{name} needs the thread end point: X (or U) and Z (or W)"),
                )
                .with_hint(format!(
                    "this dialect reads {name} as the thread-cutting cycle (G-code system {:?})",
                    codes.system
                )));
            }
            let job = self.read_g92(conv, line, modal, gword.span, None, warnings)?;
            return Ok(Some(Read::Cycle(Box::new(job))));
        }
        self.g92 = None;
        if let G76Form::OneBlock(words) = self.flavour.g76 {
            let setup = self.one_block_setup();
            let job = one_block::read_g76(
                conv, line, modal, gword.span, &name, &words, &setup, warnings,
            )?;
            return Ok(Some(Read::Cycle(Box::new(job))));
        }
        one_block_words_on_two_block(line, self.vocabulary, code, &name)?;
        if second {
            let job = self.read_g76_second(conv, line, modal, gword.span, warnings)?;
            Ok(Some(Read::Cycle(Box::new(job))))
        } else {
            self.read_g76_first(line, modal)?;
            Ok(Some(Read::Settings))
        }
    }

    /// Ends a modal single-pass cycle (a dialect that reads a block itself calls this).
    pub fn end_single(&mut self) {
        self.g92 = None;
    }

    /// A plain block's start angle. `Q` on a thread move (`G32 … Q`, or a block of axis words while
    /// the thread move is modal) begins a run of thread moves at that angle: the move carries it
    /// ([`PlainMove::phase_deg`](crate::gcode::PlainMove::phase_deg)), and so do the thread moves
    /// that continue the run without a Q (only a run's first move waits for the one-revolution
    /// signal), until a move of another kind. `None`: the modal reader applies the block as it is.
    pub(super) fn thread_move(
        &mut self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
    ) -> Result<Option<Read>> {
        let q = self.thread_move_start_angle(line, modal)?;
        if q.is_none() && self.run_phase.is_none() {
            return Ok(None);
        }
        let mut mv = modal.apply(conv, line)?;
        match mv.as_mut() {
            Some(m) if m.mode == MotionMode::Thread => {
                let phase = q.or(self.run_phase).unwrap_or(0.0);
                m.phase_deg = phase;
                self.run_phase = (phase != 0.0).then_some(phase);
            }
            // A block that does not move while G32 stays modal (M8) leaves the run as it is.
            None if modal.motion == MotionMode::Thread => {}
            _ => self.run_phase = None,
        }
        Ok(Some(Read::Applied(mv)))
    }

    /// `Q` on a thread move, checked: its start angle in degrees.
    pub(super) fn thread_move_start_angle(
        &self,
        line: &Line,
        modal: &Modal,
    ) -> Result<Option<f64>> {
        if !self.flavour.start_angle {
            return Ok(None);
        }
        let Some(q) = line.word(b'Q') else {
            return Ok(None);
        };
        let no_g = !line.words.iter().any(|w| w.letter == b'G');
        if line.has_g(self.codes.thread_move) || (no_g && modal.motion == MotionMode::Thread) {
            return start_angle::read(q).map(Some);
        }
        Ok(None)
    }
}

/// The files that may hold program `O{n}` a call (`M98 P…`, `G65 P…`) wants, as the Fanuc-style
/// controls and DNC software store programs: the program's name `O9010` (zero-filled to four
/// digits, as the control lists it, to five as Haas's does, and as written when different: `O10`
/// for `O0010`), or its
/// digits alone, each bare or with the extensions DNC software gives (`.nc`, `.cnc`, `.txt`,
/// `.tap`),
/// in any case (`o9010.NC`; file names on the PCs that hold them ignore case). Decisions:
/// docs/dialects/fanuc.md, "Programs in other files".
pub(crate) fn program_files(
    wanted: &crate::interp::library::Wanted,
) -> crate::interp::library::FileNames {
    use crate::interp::library::{FileNames, Wanted};
    let Wanted::Number(n) = wanted else {
        return FileNames::default();
    };
    // Haas's NGC control names its programs with five digits (`O01234`).
    let mut stems = vec![format!("O{n:04}"), format!("O{n:05}"), format!("O{n}")];
    stems.push(format!("{n:04}"));
    stems.push(format!("{n}"));
    let mut names = Vec::new();
    for stem in &stems {
        for ext in ["", ".nc", ".cnc", ".txt", ".tap"] {
            // Digits alone without an extension are no program file's name.
            if ext.is_empty() && !stem.starts_with('O') {
                continue;
            }
            let name = format!("{stem}{ext}");
            if !names.contains(&name) {
                names.push(name);
            }
        }
    }
    FileNames {
        names,
        any_case: true,
    }
}
