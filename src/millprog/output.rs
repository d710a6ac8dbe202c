//! What `expand` writes for a milling program: JSON lines (one object per move, and one per
//! tapping cycle), or the program flattened into plain moves in the profile's format.

use std::io::Write;

use serde_json::json;

use super::state::g_name;
use super::Sink;
use crate::diag::{Code, Diagnostic, Span};
use crate::mill::motion::{Comp, Feed, MillKind, MillMotion, Plane, Rotation, State, TapCycle};
use crate::mill::profile::MillProfile;
use crate::post::number;

fn io(e: std::io::Error) -> Diagnostic {
    Diagnostic::error(
        Code::Input,
        Span::new(0, 0, 0, 0),
        format!("cannot write: {e}"),
    )
}

/// A number as JSON (−0 as 0; not finite: null).
fn json_num(v: f64) -> serde_json::Value {
    let v = if v == 0.0 { 0.0 } else { v };
    serde_json::Number::from_f64(v).map_or(serde_json::Value::Null, serde_json::Value::Number)
}

fn work_name(work: u16) -> String {
    g_name(work)
}

/// One JSON object per move: `kind`, `x` `y` `z` (mm), the arc's `centre`, `plane`, `clockwise`,
/// `turns`, a synchronised move's `lead`, `line`, `work` and the `state`.
pub struct Jsonl<W: Write>(pub W);

impl<W: Write> Sink for Jsonl<W> {
    fn motion(&mut self, m: &MillMotion, work: u16) -> Result<(), Diagnostic> {
        let mut o = json!({
            "kind": match m.kind {
                MillKind::Rapid => "rapid",
                MillKind::Feed => "feed",
                MillKind::Arc { .. } => "arc",
                MillKind::Sync { .. } => "sync",
            },
            "x": json_num(m.to[0]),
            "y": json_num(m.to[1]),
            "z": json_num(m.to[2]),
        });
        match m.kind {
            MillKind::Arc {
                centre,
                plane,
                clockwise,
                turns,
            } => {
                o["centre"] = json!(centre.map(json_num));
                o["plane"] = json!(plane);
                o["clockwise"] = json!(clockwise);
                o["turns"] = json!(turns);
            }
            MillKind::Sync { lead } => o["lead"] = json_num(lead),
            _ => {}
        }
        o["line"] = json!(m.line);
        o["work"] = json!(work_name(work));
        o["state"] = json!(m.state);
        writeln!(self.0, "{o}").map_err(io)
    }

    fn tap(&mut self, t: &TapCycle) -> Result<(), Diagnostic> {
        let mut o = json!({ "kind": "tap" });
        o["x"] = json_num(t.position[0]);
        o["y"] = json_num(t.position[1]);
        o["r"] = json_num(t.r);
        o["bottom"] = json_num(t.bottom);
        o["feed"] = json!(t.feed);
        o["rpm"] = json!(t.rpm);
        o["rotation"] = json!(t.rotation);
        o["rigid"] = json!(t.rigid);
        o["peck"] = json!(t.peck);
        o["dwell"] = json!(t.dwell);
        o["code"] = json!(g_name(t.code));
        o["line"] = json!(t.line);
        writeln!(self.0, "{o}").map_err(io)
    }
}

/// The program flattened: plain G0/G1/G2/G3 moves in mm, each state change written before the
/// move it applies to, in the profile's number format. LinuxCNC writes a rigid tap as G33.1
/// (its return is the same block's); a control without a plain synchronised move refuses one.
pub struct Flat<'p, W: Write> {
    out: W,
    profile: &'p MillProfile,
    /// The state the output has set so far.
    state: Option<State>,
    /// A G33.1 was written: the next synchronised move is its return.
    tapping: bool,
    /// The control has a plain synchronised tap (G33.1).
    sync_block: bool,
    /// The plane written last (the preamble's G17).
    plane: Plane,
    /// The control's program end.
    end: &'static str,
}

impl<'p, W: Write> Flat<'p, W> {
    /// Writes the header (units, the profile's preamble).
    pub fn new(mut out: W, profile: &'p MillProfile) -> Result<Flat<'p, W>, Diagnostic> {
        writeln!(out, "G21").map_err(io)?;
        for p in &profile.preamble {
            writeln!(out, "{p}").map_err(io)?;
        }
        Ok(Flat {
            out,
            profile,
            // The power-on state (the preamble cancels compensation and length offsets).
            state: Some(State {
                feed: Feed::Unknown,
                rpm: None,
                rotation: Rotation::Stopped,
                tool: None,
                length_offset: None,
                comp: Comp::Off,
                units: crate::units::Units::Mm,
            }),
            tapping: false,
            sync_block: super::language_of(profile)?.g33_1,
            plane: Plane::Xy,
            end: super::language_of(profile)?.program_end,
        })
    }

    /// Ends the program (the control's M30 or M2).
    pub fn finish(mut self) -> Result<(), Diagnostic> {
        writeln!(self.out, "{}", self.end).map_err(io)
    }

    fn num(&self, v: f64) -> String {
        number(v, self.profile.decimals_mm, self.profile.trailing_zeros)
    }

    /// The words that bring the output's state to `s`.
    fn state_words(&self, s: &State) -> Vec<String> {
        let old = self.state;
        let mut w = Vec::new();
        let changed = |f: fn(&State) -> String| old.as_ref().map(f) != Some(f(s));
        if changed(|s| format!("{:?}", s.tool)) {
            if let Some(t) = s.tool {
                w.push(format!("T{t} M6"));
            }
        }
        if changed(|s| format!("{:?}", s.length_offset)) {
            w.push(match s.length_offset {
                Some(h) => format!("G43 H{h}"),
                None => "G49".into(),
            });
        }
        if changed(|s| format!("{:?}{:?}", s.rpm, s.rotation)) {
            let speed = s.rpm.map(|r| format!("S{}", r.round() as i64));
            let m = match s.rotation {
                Rotation::Cw => "M3",
                Rotation::Ccw => "M4",
                Rotation::Stopped => "M5",
            };
            w.push(speed.map_or(m.to_string(), |sp| format!("{sp} {m}")));
        }
        if changed(|s| format!("{:?}", s.comp)) {
            w.push(match s.comp {
                Comp::Off => "G40".into(),
                Comp::Left { d } => d.map_or("G41".into(), |d| format!("G41 D{d}")),
                Comp::Right { d } => d.map_or("G42".into(), |d| format!("G42 D{d}")),
            });
        }
        w
    }

    /// F when it changes, with G94/G95 when the mode does (G94 is the preamble's).
    fn feed_words(&self, s: &State) -> String {
        let old = self.state.map_or(Feed::Unknown, |o| o.feed);
        let tz = self.profile.trailing_zeros;
        let per_min = |f: f64| number(f, self.profile.feed_decimals_mm, tz);
        match (old, s.feed) {
            (o, f) if o == f => String::new(),
            (Feed::PerRev(_), Feed::PerMinute(f)) => format!(" G94 F{}", per_min(f)),
            (_, Feed::PerMinute(f)) => format!(" F{}", per_min(f)),
            (Feed::PerRev(_), Feed::PerRev(f)) => format!(" F{}", number(f, 4, tz)),
            (_, Feed::PerRev(f)) => format!(" G95 F{}", number(f, 4, tz)),
            (_, Feed::Unknown) => String::new(),
        }
    }
}

impl<W: Write> Sink for Flat<'_, W> {
    fn motion(&mut self, m: &MillMotion, _work: u16) -> Result<(), Diagnostic> {
        for words in self.state_words(&m.state) {
            writeln!(self.out, "{words}").map_err(io)?;
        }
        let xyz = format!(
            "X{} Y{} Z{}",
            self.num(m.to[0]),
            self.num(m.to[1]),
            self.num(m.to[2])
        );
        let feed = self.feed_words(&m.state);
        let block = match m.kind {
            MillKind::Rapid => format!("G0 {xyz}"),
            MillKind::Feed => format!("G1 {xyz}{feed}"),
            MillKind::Arc {
                centre,
                plane,
                clockwise,
                turns,
            } => {
                let (a, b, _) = plane.axes();
                let l = [b'I', b'J', b'K'];
                let plane_code = match plane {
                    _ if plane == self.plane => "",
                    Plane::Xy => "G17 ",
                    Plane::Zx => "G18 ",
                    Plane::Yz => "G19 ",
                };
                self.plane = plane;
                let mut s = format!(
                    "{plane_code}{} {xyz} {}{} {}{}",
                    if clockwise { "G2" } else { "G3" },
                    l[a] as char,
                    self.num(centre[a] - m.from[a]),
                    l[b] as char,
                    self.num(centre[b] - m.from[b]),
                );
                if turns > 0 {
                    s.push_str(&format!(" P{}", turns + 1));
                }
                s.push_str(&feed);
                s
            }
            MillKind::Sync { lead } => {
                if !self.sync_block {
                    return Err(Diagnostic::error(
                        Code::Unsupported,
                        Span::new(0, 0, m.line, 1),
                        format!(
                            "line {}: a rigid tap's synchronised moves have no plain block on `{}`",
                            m.line, self.profile.name
                        ),
                    )
                    .with_hint("read the program with --format jsonl"));
                }
                self.tapping = !self.tapping;
                if !self.tapping {
                    self.state = Some(m.state);
                    return Ok(());
                }
                format!("G33.1 {xyz} K{}", number(lead, 4, false))
            }
        };
        // A rapid writes no F: the feed the output has set stays what it was.
        let feed = match (m.kind, self.state) {
            (MillKind::Rapid, Some(old)) => old.feed,
            _ => m.state.feed,
        };
        self.state = Some(State { feed, ..m.state });
        writeln!(self.out, "{block}").map_err(io)
    }

    fn tap(&mut self, _t: &TapCycle) -> Result<(), Diagnostic> {
        Ok(())
    }
}
