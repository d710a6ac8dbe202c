//! Cycle forms: for each lathe controller, its threading cycle as program text with editable words.
//!
//! A form is the program the CLI would read, line by line, where some pieces are fields the page
//! lets the user edit. [`Form::program`] writes the text and remembers where each field landed, so
//! a diagnostic's span (line, column, length) names the field it points into.

use serde::Serialize;
use threadcut::thread::standard::{StandardThread, Surface};
use threadcut::units::Units;

/// How a field's value is written into the program.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A number as typed (lengths, leads, angles).
    Number,
    /// A whole number in least input increments (Fanuc's G76 P(k), Q(Δd), Q(Δdmin)).
    Increments,
    /// Two digits of a packed word (P(m)(r)(a)): a one-digit value gets its leading zero.
    Digits2,
}

#[derive(Clone, Debug, Serialize)]
pub struct Field {
    pub id: &'static str,
    /// The word's letter as written before the value; empty for the later parts of a packed word.
    pub letter: &'static str,
    pub label: &'static str,
    pub kind: Kind,
    /// An optional word is left out of the program when its value is empty.
    pub optional: bool,
}

#[derive(Clone, Debug, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Piece {
    Text(&'static str),
    Field(Field),
}

/// One controller's cycle form.
#[derive(Clone, Debug, Serialize)]
pub struct Form {
    pub controller: &'static str,
    pub cycle: &'static str,
    pub lines: Vec<Vec<Piece>>,
}

/// Where a field landed in the generated program (1-based line, 1-based byte columns, end exclusive).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Placed {
    pub id: &'static str,
    pub line: u32,
    pub column: u32,
    pub end: u32,
}

fn f(
    id: &'static str,
    letter: &'static str,
    label: &'static str,
    kind: Kind,
    optional: bool,
) -> Piece {
    Piece::Field(Field {
        id,
        letter,
        label,
        kind,
        optional,
    })
}

fn num(id: &'static str, letter: &'static str, label: &'static str) -> Piece {
    f(id, letter, label, Kind::Number, false)
}

fn opt(id: &'static str, letter: &'static str, label: &'static str) -> Piece {
    f(id, letter, label, Kind::Number, true)
}

fn t(text: &'static str) -> Piece {
    Piece::Text(text)
}

/// The controllers with a form, in the order the page lists them.
pub const CONTROLLERS: &[&str] = &["gsk980", "fanuc", "linuxcnc", "ab9"];

/// One controller's cycle form, or `None` for a controller without one.
pub fn form(controller: &str) -> Option<Form> {
    Some(match controller {
        "gsk980" => gsk980_form(),
        "fanuc" => fanuc_form(),
        "linuxcnc" => linuxcnc_form(),
        "ab9" => ab9_form(),
        _ => return None,
    })
}

/// The units word (G21 or G20): a field, so that the page can switch units.
fn units() -> Piece {
    f("units", "G", "units: 21 mm, 20 inch", Kind::Number, false)
}

/// The rapid to the cycle's start point: X clear of the part, Z before the thread.
fn start() -> Vec<Piece> {
    vec![
        t("G00 "),
        num("sx", "X", "start X (diameter), clear of the part"),
        t(" "),
        num("sz", "Z", "start Z, before the thread"),
    ]
}

/// The packed P(m)(r)(a) word of a two-block cycle's first block: finishing passes, the
/// controller's own second pair (labelled `r_label`), tool angle.
fn packed(r_label: &'static str) -> Vec<Piece> {
    vec![
        f(
            "m",
            "P",
            "P(m): finishing passes (01-99)",
            Kind::Digits2,
            false,
        ),
        f("r", "", r_label, Kind::Digits2, false),
        f("a", "", "P(a): tool angle (degrees)", Kind::Digits2, false),
    ]
}

/// GSK980's form: the two-block G78, whose second pair of P is the infeed mode, and whose depths
/// are written as numbers (radius).
fn gsk980_form() -> Form {
    Form {
        controller: "gsk980",
        cycle: "G78 enhanced multiple thread-cutting cycle",
        lines: vec![
            vec![units()],
            vec![t("G97 S500 M03")],
            start(),
            [
                vec![t("G78 ")],
                packed("P(r): infeed mode (0 centre, 1 left flank, 2 right flank, 3 right/centre, 4 left/right)"),
                vec![
                    t(" "),
                    num("qmin", "Q", "Q(Δdmin): minimum cut depth (radius)"),
                    t(" "),
                    num("fin", "R", "R(d): finishing allowance (radius)"),
                ],
            ]
            .concat(),
            vec![
                t("G78 "),
                num("x", "X", "X: root diameter at the end"),
                t(" "),
                num("z", "Z", "Z: end of the thread"),
                t(" "),
                num("k", "P", "P(k): thread height (radius)"),
                t(" "),
                num("dd", "Q", "Q(Δd): first cut depth (radius)"),
                t(" "),
                num("lead", "F", "F: lead"),
                t(" "),
                opt("j", "J", "J: tail-out along X (optional)"),
                t(" "),
                opt("kk", "K", "K: tail-out along Z (optional)"),
                t(" "),
                opt("starts", "L", "L: number of starts (optional)"),
            ],
        ],
    }
}

/// Fanuc's form: the two-block G76, whose second pair of P is the chamfer, and whose thread height
/// and cut depths (P and Q) are written in least input increments.
fn fanuc_form() -> Form {
    Form {
        controller: "fanuc",
        cycle: "G76 two-block multiple threading cycle",
        lines: vec![
            vec![units()],
            vec![t("G97 S500 M03")],
            start(),
            [
                vec![t("G76 ")],
                packed("P(r): chamfer (0.1 lead, 00-99)"),
                vec![
                    t(" "),
                    f(
                        "qmin",
                        "Q",
                        "Q(Δdmin): minimum cut depth (least increments, radius)",
                        Kind::Increments,
                        false,
                    ),
                    t(" "),
                    num("fin", "R", "R(d): finishing allowance (radius)"),
                ],
            ]
            .concat(),
            vec![
                t("G76 "),
                num("x", "X", "X: root diameter"),
                t(" "),
                num("z", "Z", "Z: end of the thread"),
                t(" "),
                f(
                    "k",
                    "P",
                    "P(k): thread height (least increments, radius)",
                    Kind::Increments,
                    false,
                ),
                t(" "),
                f(
                    "dd",
                    "Q",
                    "Q(Δd): first cut depth (least increments, radius)",
                    Kind::Increments,
                    false,
                ),
                t(" "),
                num("lead", "F", "F: lead"),
            ],
        ],
    }
}

/// LinuxCNC's form: the one-block G76 in G7 (diameter mode), its depths as diameters.
fn linuxcnc_form() -> Form {
    Form {
        controller: "linuxcnc",
        cycle: "G76 threading cycle",
        lines: vec![
            vec![t("G7 "), units(), t(" G18")],
            vec![t("S500 M3")],
            start(),
            vec![
                t("G76 "),
                num("lead", "P", "P: pitch (lead per revolution)"),
                t(" "),
                num("z", "Z", "Z: end of the thread"),
                t(" "),
                num(
                    "i",
                    "I",
                    "I: crest offset from the drive line (a diameter in G7; negative outside)",
                ),
                t(" "),
                num("dd", "J", "J: first cut depth (a diameter in G7)"),
                t(" "),
                num(
                    "degression",
                    "R",
                    "R: depth degression (1 constant depth, 2 constant area)",
                ),
                t(" "),
                num("k", "K", "K: full thread depth (a diameter in G7)"),
                t(" "),
                opt("q", "Q", "Q: compound slide angle (degrees, optional)"),
                t(" "),
                opt("h", "H", "H: spring passes (optional)"),
                t(" "),
                opt("e", "E", "E: taper distance along Z (optional)"),
                t(" "),
                opt(
                    "l",
                    "L",
                    "L: taper ends (0 none, 1 entry, 2 exit, 3 both; optional)",
                ),
            ],
        ],
    }
}

/// Allen-Bradley's form: the one-block G78 after a G90 start, with its taper word I.
fn ab9_form() -> Form {
    Form {
        controller: "ab9",
        cycle: "G78 multipass threading cycle",
        lines: vec![
            vec![units()],
            vec![t("G97 S500 M03")],
            [vec![t("G90 ")], start()].concat(),
            vec![
                t("G78 "),
                num("x", "X", "X: root diameter"),
                t(" "),
                num("z", "Z", "Z: end of the thread"),
                t(" "),
                num("k", "K", "K: thread height (radius)"),
                t(" "),
                num("dd", "D", "D: first cut depth (radius)"),
                t(" "),
                num("lead", "F", "F: lead"),
                t(" "),
                num("a", "A", "A: tool angle (degrees)"),
                t(" "),
                num("p", "P", "P: infeed (1-4)"),
                t(" "),
                opt(
                    "taper",
                    "I",
                    "I: taper, radius change start to end (optional)",
                ),
            ],
        ],
    }
}

/// A number written with at most `decimals` places and always a decimal point (`32.`, `27.546`):
/// Fanuc-style controls read `X32` as 32 least increments.
pub fn number(v: f64, decimals: usize) -> String {
    let s = format!("{:.*}", decimals, v);
    let s = if s.contains('.') {
        s.trim_end_matches('0').to_string()
    } else {
        s
    };
    let s = if s == "-0." { "0.".to_string() } else { s };
    if s.contains('.') {
        s
    } else {
        format!("{s}.")
    }
}

/// A value rounded to a step (for the first cut depth): nearest multiple, never zero.
fn to_step(v: f64, step: f64) -> f64 {
    ((v / step).round() * step).max(step)
}

/// Values for a form from a standard thread: a plain, conservative cycle a programmer would start
/// from. Returns (field id, value) pairs; fields not named keep the form's empty value.
pub fn fill(controller: &str, t: &StandardThread, side: Surface) -> Vec<(&'static str, String)> {
    let u = t.units;
    let d = match u {
        Units::Mm => 3,
        Units::Inch => 4,
    };
    let mm = |v: f64| u.from_mm(v);
    let lead = mm(t.pitch);
    let internal = side == Surface::Internal;
    // Radial infeed depth, rounded to the program's resolution; the root diameter follows from it
    // so that X and the height agree exactly.
    let k = round(
        mm(if internal {
            t.internal_depth
        } else {
            t.external_depth
        }),
        d,
    );
    // External: the crest is the major diameter and the root lies k below it. Internal: the crest
    // is the minor diameter D1 and the root k above it.
    let crest = round(
        mm(if internal {
            t.basic.minor
        } else {
            t.basic.major
        }),
        d,
    );
    let root = if internal {
        crest + 2.0 * k
    } else {
        crest - 2.0 * k
    };
    let clear = if u == Units::Mm { 2.0 } else { 0.08 };
    let sx = if internal {
        (crest - clear).max(crest / 2.0)
    } else {
        crest + clear
    };
    let sz = (3.0 * lead).max(if u == Units::Mm { 3.0 } else { 0.12 });
    // A taper thread is as long as its effective (useful) thread; others 1.5 diameters.
    let length = match t.taper {
        Some(tp) => mm(tp.effective_length),
        None => (1.5 * mm(t.basic.major)).max(4.0 * lead),
    };
    let z = -round(length, if u == Units::Mm { 0 } else { 2 });
    let fin = if u == Units::Mm { 0.05 } else { 0.002 };
    let qmin = if u == Units::Mm { 0.1 } else { 0.004 };
    // About ten rough passes for a 2.5 mm pitch, fewer for fine ones: Δd·√n = k − d.
    let passes = (4.0 * t.pitch).round().clamp(4.0, 16.0);
    let dd = to_step(
        (k - fin) / passes.sqrt(),
        if u == Units::Mm { 0.01 } else { 0.001 },
    );
    let units = if u == Units::Mm { "21" } else { "20" };
    // The tool's angle is the form's: 60° (ISO, Unified, NPT), 55° (Whitworth, pipe), 30° (Tr),
    // 29° (Acme); LinuxCNC's compound angle half a degree under the flank.
    let angle = format!("{:02}", t.profile.angle_deg.round() as u32);
    let compound = format!("{}", t.profile.flank_angle_deg - 0.5);
    // A taper thread: the root at the cycle's end and its taper over the cycle, for the forms that
    // have a taper word (Allen-Bradley's I); the small end (external) or the opening (internal)
    // at Z0.
    let taper = t.taper.and_then(|_| {
        use threadcut::thread::standard::lathe::{taper_cycle, Placement};
        taper_cycle(
            t,
            &Placement {
                side,
                face_z: 0.0,
                start_z: u.to_mm(sz),
                length: u.to_mm(-z),
            },
        )
        .ok()
    });
    let n = |v: f64| number(v, d as usize);
    // The lead to the controller's own lead resolution (the decimals its lead word is written
    // with: 1/13" is F0.07692 on GSK and Fanuc, P0.0769231 on LinuxCNC), not the position's.
    let lead_decimals = threadcut::machine::Machine::built_in(controller)
        .and_then(|m| threadcut::dialect::open(&m).ok())
        .map_or(d as usize, |dialect| {
            dialect.format().lead_decimals[(u == Units::Inch) as usize] as usize
        });
    let lead_text = number(lead, lead_decimals);
    let incr = |v: f64| format!("{}", (v * 10f64.powi(d)).round() as i64);
    let mut v = vec![
        ("units", units.to_string()),
        ("sx", n(sx)),
        ("sz", n(sz)),
        ("z", n(z)),
    ];
    match controller {
        "gsk980" => v.extend([
            ("m", "02".into()),
            ("r", "01".into()),
            ("a", angle.clone()),
            ("qmin", n(qmin)),
            ("fin", n(fin)),
            ("x", n(root)),
            ("k", n(k)),
            ("dd", n(dd)),
            ("lead", lead_text.clone()),
            ("j", String::new()),
            ("kk", String::new()),
            ("starts", String::new()),
        ]),
        "fanuc" => v.extend([
            ("m", "02".into()),
            ("r", "00".into()),
            ("a", angle.clone()),
            ("qmin", incr(qmin)),
            ("fin", n(fin)),
            ("x", n(root)),
            ("k", incr(k)),
            ("dd", incr(dd)),
            ("lead", lead_text.clone()),
        ]),
        // The form is in G7 (X on diameter), where LinuxCNC reads I, J and K as diameters too
        // (docs/dialects/linuxcnc-g76.md): each is twice its radial value.
        "linuxcnc" => v.extend([
            ("lead", lead_text.clone()),
            // The drive line is the start X; I is the crest's offset from it.
            ("i", n(crest - sx)),
            ("dd", n(2.0 * dd)),
            ("degression", "1.5".into()),
            ("k", n(2.0 * k)),
            ("q", compound),
            ("h", "2".into()),
            ("e", String::new()),
            ("l", String::new()),
        ]),
        "ab9" => v.extend([
            (
                "x",
                n(taper.map_or(root, |c| round(mm(2.0 * c.root_end_x), d))),
            ),
            ("k", n(k)),
            ("dd", n(dd)),
            ("lead", lead_text.clone()),
            ("a", angle),
            ("p", "1".into()),
            (
                "taper",
                taper.map_or(String::new(), |c| n(mm(c.radial_change))),
            ),
        ]),
        _ => {}
    }
    v
}

fn round(v: f64, decimals: i32) -> f64 {
    let s = 10f64.powi(decimals);
    (v * s).round() / s
}

impl Form {
    pub fn fields(&self) -> impl Iterator<Item = &Field> {
        self.lines.iter().flatten().filter_map(|p| match p {
            Piece::Field(f) => Some(f),
            Piece::Text(_) => None,
        })
    }

    /// The program text for `values` (field id → value as typed) and where each field landed.
    /// Unknown ids are ignored; a missing or empty optional field is left out, a missing or empty
    /// required one is written as its bare letter, so the controller's reader reports it.
    pub fn program(&self, value: impl Fn(&str) -> Option<String>) -> (String, Vec<Placed>) {
        let mut text = String::new();
        let mut placed = Vec::new();
        for (i, line) in self.lines.iter().enumerate() {
            let start = text.len();
            for piece in line {
                match piece {
                    Piece::Text(s) => text.push_str(s),
                    Piece::Field(field) => {
                        let raw = value(field.id).unwrap_or_default();
                        let raw = raw.trim();
                        if raw.is_empty() && field.optional {
                            continue;
                        }
                        let col = (text.len() - start) as u32 + 1;
                        text.push_str(field.letter);
                        match field.kind {
                            Kind::Digits2
                                if raw.len() == 1 && raw.as_bytes()[0].is_ascii_digit() =>
                            {
                                text.push('0');
                                text.push_str(raw);
                            }
                            _ => text.push_str(raw),
                        }
                        placed.push(Placed {
                            id: field.id,
                            line: i as u32 + 1,
                            column: col,
                            end: (text.len() - start) as u32 + 1,
                        });
                    }
                }
            }
            // Optional words left out leave doubled or trailing blanks: tidy them, keeping the
            // columns recorded so far right (only trailing blanks are trimmed).
            while text.ends_with(' ') && text.len() > start {
                text.pop();
            }
            text.push('\n');
        }
        (text, placed)
    }
}

/// The field a diagnostic at (line, column, len) points into: the one its span overlaps most.
pub fn field_at(placed: &[Placed], line: u32, column: u32, len: u32) -> Option<&'static str> {
    let (a, b) = (column, column + len.max(1));
    placed
        .iter()
        .filter(|p| p.line == line)
        .map(|p| (p.id, b.min(p.end).saturating_sub(a.max(p.column))))
        .filter(|(_, overlap)| *overlap > 0)
        .max_by_key(|(_, overlap)| *overlap)
        .map(|(id, _)| id)
}
