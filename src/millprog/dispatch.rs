//! One block's motion: the modal G0/G1/G2/G3, a canned cycle, G33.1 — handed to the straight
//! moves of the modal state ([`super::state`]), the arcs ([`super::arc`]) and the canned cycles
//! ([`super::cycles`]), which all build on the state and not on each other.

use crate::diag::{Code, Diagnostic};
use crate::gcode::{Line, Word};
use crate::mill::motion::MillKind;

use super::state::{g_name, Mill, Motion, Out, Result, AXES};
use super::{arc, cycles};

impl Mill {
    /// The motion of the block: the modal G0/G1/G2/G3, a canned cycle, G33.1.
    pub(crate) fn motion(
        &mut self,
        line: &Line,
        codes: &[(u16, &Word)],
        out: &mut dyn Out,
    ) -> Result<()> {
        if let Some(w) = line
            .words
            .iter()
            .find(|w| matches!(w.letter, b'A' | b'B' | b'C' | b'U' | b'V' | b'W'))
        {
            return Err(Diagnostic::error(
                Code::Unsupported,
                w.span,
                format!(
                    "{}{}: threadcut reads the X, Y and Z axes of a machining centre, not rotary or parallel axes",
                    w.letter as char, w.value
                ),
            )
            .with_hint("a move of a rotary axis turns the part under the program's later moves"));
        }
        let mut given = None;
        for (c, w) in codes {
            let m = match c {
                0 => Motion::Rapid,
                10 => Motion::Feed,
                20 => Motion::Arc { clockwise: true },
                30 => Motion::Arc { clockwise: false },
                331 => {
                    return cycles::g33_1(self, line, w, out);
                }
                800 if !self.lang.g80_in_motion_group => {
                    self.cycle.end();
                    self.m29 = false;
                    self.motion = self.group1;
                    continue;
                }
                800 => Motion::None,
                730 | 740 | 760 | 810..=890 => Motion::Cycle(*c),
                _ => continue,
            };
            if matches!(m, Motion::Rapid | Motion::Feed | Motion::Arc { .. }) {
                self.group1 = m;
            }
            if let Some((g, _)) = given {
                return Err(Diagnostic::error(
                    Code::Conflict,
                    w.span,
                    format!(
                        "{} and {} in one block: two motion codes",
                        g_name(g),
                        g_name(*c)
                    ),
                ));
            }
            given = Some((*c, *w));
            // Rigid tapping (M29) lasts while the tapping cycle is modal, for every hole it taps:
            // G80, a motion code or another canned cycle ends it (as Fanuc's manual describes
            // the rigid tapping mode's cancel; recalled, docs/milling.md).
            let taps = |c: u16| self.lang.cycles.taps.iter().any(|t| t.code == c);
            if !matches!(m, Motion::Cycle(c) if taps(c)) {
                self.m29 = false;
            }
            if !matches!(m, Motion::Cycle(_)) {
                self.cycle.end();
            }
            self.motion = m;
        }
        let moves = AXES.iter().any(|l| line.word(*l).is_some())
            || (matches!(self.motion, Motion::Arc { .. })
                && [b'I', b'J', b'K', b'R']
                    .iter()
                    .any(|l| line.word(*l).is_some()));
        match self.motion {
            Motion::Rapid | Motion::Feed if moves => {
                let to = self.end_point(line)?;
                let kind = if self.motion == Motion::Rapid {
                    MillKind::Rapid
                } else {
                    self.feed_needed(line, given.map(|g| g.1), false)?;
                    MillKind::Feed
                };
                self.straight(kind, to, line.number, out)
            }
            Motion::Arc { clockwise } if moves => {
                let g = given.map(|g| g.1);
                self.feed_needed(line, g, true)?;
                arc::arc(self, line, clockwise, g, out)
            }
            Motion::Cycle(code) => {
                let cycle_words = moves || given.is_some();
                if cycle_words {
                    cycles::cycle(self, line, code, given.map(|g| g.1), out)
                } else {
                    Ok(())
                }
            }
            _ => Ok(()),
        }
    }
}
