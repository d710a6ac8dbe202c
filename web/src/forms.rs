//! Cycle forms: for each lathe controller, its threading cycle as program text with editable words.
//!
//! A form is the program the CLI would read, line by line, where some pieces are fields the page
//! lets the user edit. [`Form::program`] writes the text and remembers where each field landed, so
//! a diagnostic's span (line, column, length) names the field it points into.

use serde::Serialize;
use threadcut::thread::standard::lathe::{taper_cycle, Placement, TaperCycle};
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
    let p = Plan::new(controller, t, side);
    let units = if p.units == Units::Mm { "21" } else { "20" };
    let mut v = vec![
        ("units", units.to_string()),
        ("sx", p.n(p.sx)),
        ("sz", p.n(p.sz)),
        ("z", p.n(p.z)),
    ];
    match controller {
        "gsk980" => v.extend(gsk980_values(&p)),
        "fanuc" => v.extend(fanuc_values(&p)),
        "linuxcnc" => v.extend(linuxcnc_values(&p)),
        "ab9" => v.extend(ab9_values(&p)),
        _ => {}
    }
    v
}

/// The cycle [`fill`] proposes for a thread, in the thread's units (X on diameter): what every
/// controller's values are written from.
struct Plan {
    units: Units,
    /// Decimals of a position: 3 in mm, 4 in inches.
    decimals: i32,
    /// Radial infeed depth (thread height), rounded to the position's decimals.
    k: f64,
    /// Crest diameter: the major (external) or the minor (internal) one.
    crest: f64,
    /// Root diameter: the radial depth `k` beyond the crest, so that X and the height agree.
    root: f64,
    /// The start point: X clear of the crest, Z before the thread.
    sx: f64,
    sz: f64,
    /// Z of the thread's end.
    z: f64,
    /// Finishing allowance (radius).
    fin: f64,
    /// Minimum cut depth (radius).
    qmin: f64,
    /// First cut depth (radius).
    dd: f64,
    /// The tool's angle, two digits (`60`, `55`, `30`, `29`).
    angle: String,
    /// LinuxCNC's compound slide angle: half a degree under the flank.
    compound: String,
    /// A taper thread's cycle, placed with its small end (external) or opening (internal) at Z0.
    taper: Option<TaperCycle>,
    /// The lead, written to the controller's own lead resolution.
    lead_text: String,
}

impl Plan {
    /// The plan for `t` on `side`, its lead written for `controller`.
    fn new(controller: &str, t: &StandardThread, side: Surface) -> Plan {
        let u = t.units;
        let d = match u {
            Units::Mm => 3,
            Units::Inch => 4,
        };
        let lead = u.from_mm(t.pitch);
        let internal = side == Surface::Internal;
        let (k, crest, root) = depth_and_diameters(t, internal, d);
        let (sx, sz) = start_point(u, crest, lead, internal);
        let z = end_z(t, lead);
        let fin = if u == Units::Mm { 0.05 } else { 0.002 };
        let qmin = if u == Units::Mm { 0.1 } else { 0.004 };
        Plan {
            units: u,
            decimals: d,
            k,
            crest,
            root,
            sx,
            sz,
            z,
            fin,
            qmin,
            dd: first_cut(t, k, fin),
            // The tool's angle is the form's: 60° (ISO, Unified, NPT), 55° (Whitworth, pipe),
            // 30° (Tr), 29° (Acme); LinuxCNC's compound angle half a degree under the flank.
            angle: format!("{:02}", t.profile.angle_deg.round() as u32),
            compound: format!("{}", t.profile.flank_angle_deg - 0.5),
            taper: taper(t, side, sz, z),
            lead_text: lead_text(controller, lead, u, d),
        }
    }

    /// A position or depth as written in the program (the position's decimals).
    fn n(&self, v: f64) -> String {
        number(v, self.decimals as usize)
    }

    /// A depth in least input increments (a whole number of the position's last decimal).
    fn incr(&self, v: f64) -> String {
        format!("{}", (v * 10f64.powi(self.decimals)).round() as i64)
    }
}

/// The radial infeed depth k, the crest diameter and the root diameter: k and the crest rounded
/// to the program's resolution (`d` decimals), the root following from them so that X and the
/// height agree exactly.
fn depth_and_diameters(t: &StandardThread, internal: bool, d: i32) -> (f64, f64, f64) {
    let mm = |v: f64| t.units.from_mm(v);
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
    (k, crest, root)
}

/// Where the cycle starts: X clear of the crest (inside it for an internal thread, but never
/// below half the crest), Z three leads before the thread and at least 3 mm (0.12") away.
fn start_point(u: Units, crest: f64, lead: f64, internal: bool) -> (f64, f64) {
    let clear = if u == Units::Mm { 2.0 } else { 0.08 };
    let sx = if internal {
        (crest - clear).max(crest / 2.0)
    } else {
        crest + clear
    };
    let sz = (3.0 * lead).max(if u == Units::Mm { 3.0 } else { 0.12 });
    (sx, sz)
}

/// Where the thread ends: a taper thread is as long as its effective (useful) thread, others
/// 1.5 diameters (at least 4 leads); whole millimetres, or hundredths of an inch.
fn end_z(t: &StandardThread, lead: f64) -> f64 {
    let u = t.units;
    let length = match t.taper {
        Some(tp) => u.from_mm(tp.effective_length),
        None => (1.5 * u.from_mm(t.basic.major)).max(4.0 * lead),
    };
    -round(length, if u == Units::Mm { 0 } else { 2 })
}

/// The first cut depth Δd for a radial depth `k` and finishing allowance `fin`: about ten rough
/// passes for a 2.5 mm pitch, fewer for fine ones (Δd·√n = k − d), to 0.01 mm (0.001").
fn first_cut(t: &StandardThread, k: f64, fin: f64) -> f64 {
    let u = t.units;
    let passes = (4.0 * t.pitch).round().clamp(4.0, 16.0);
    to_step(
        (k - fin) / passes.sqrt(),
        if u == Units::Mm { 0.01 } else { 0.001 },
    )
}

/// A taper thread's cycle from the start Z `sz` to the end Z `z`, with the small end (external)
/// or the opening (internal) at Z0: the root at the cycle's end and its taper over the cycle, for
/// the forms that have a taper word (Allen-Bradley's I). `None` for a parallel thread.
fn taper(t: &StandardThread, side: Surface, sz: f64, z: f64) -> Option<TaperCycle> {
    let u = t.units;
    t.taper.and_then(|_| {
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
    })
}

/// The lead to the controller's own lead resolution (the decimals its lead word is written with:
/// 1/13" is F0.07692 on GSK and Fanuc, P0.0769231 on LinuxCNC), not the position's `d` decimals
/// (which a controller without a built-in profile keeps).
fn lead_text(controller: &str, lead: f64, u: Units, d: i32) -> String {
    let lead_decimals = threadcut::machine::Machine::built_in(controller)
        .and_then(|m| threadcut::dialect::open(&m).ok())
        .map_or(d as usize, |dialect| {
            dialect.format().lead_decimals[(u == Units::Inch) as usize] as usize
        });
    number(lead, lead_decimals)
}

/// GSK980's G78 values: depths as numbers (radius), two finishing passes, left-flank infeed.
fn gsk980_values(p: &Plan) -> Vec<(&'static str, String)> {
    vec![
        ("m", "02".into()),
        ("r", "01".into()),
        ("a", p.angle.clone()),
        ("qmin", p.n(p.qmin)),
        ("fin", p.n(p.fin)),
        ("x", p.n(p.root)),
        ("k", p.n(p.k)),
        ("dd", p.n(p.dd)),
        ("lead", p.lead_text.clone()),
        ("j", String::new()),
        ("kk", String::new()),
        ("starts", String::new()),
    ]
}

/// Fanuc's G76 values: the height and cut depths in least increments, two finishing passes,
/// no chamfer.
fn fanuc_values(p: &Plan) -> Vec<(&'static str, String)> {
    vec![
        ("m", "02".into()),
        ("r", "00".into()),
        ("a", p.angle.clone()),
        ("qmin", p.incr(p.qmin)),
        ("fin", p.n(p.fin)),
        ("x", p.n(p.root)),
        ("k", p.incr(p.k)),
        ("dd", p.incr(p.dd)),
        ("lead", p.lead_text.clone()),
    ]
}

/// LinuxCNC's G76 values. The form is in G7 (X on diameter), where LinuxCNC reads I, J and K as
/// diameters too (docs/dialects/linuxcnc-g76.md): each is twice its radial value.
fn linuxcnc_values(p: &Plan) -> Vec<(&'static str, String)> {
    vec![
        ("lead", p.lead_text.clone()),
        // The drive line is the start X; I is the crest's offset from it.
        ("i", p.n(p.crest - p.sx)),
        ("dd", p.n(2.0 * p.dd)),
        ("degression", "1.5".into()),
        ("k", p.n(2.0 * p.k)),
        ("q", p.compound.clone()),
        ("h", "2".into()),
        ("e", String::new()),
        ("l", String::new()),
    ]
}

/// Allen-Bradley's G78 values: radial infeed, and for a taper thread the root diameter at the
/// cycle's end and the taper word I.
fn ab9_values(p: &Plan) -> Vec<(&'static str, String)> {
    let mm = |v: f64| p.units.from_mm(v);
    vec![
        (
            "x",
            p.n(p
                .taper
                .map_or(p.root, |c| round(mm(2.0 * c.root_end_x), p.decimals))),
        ),
        ("k", p.n(p.k)),
        ("dd", p.n(p.dd)),
        ("lead", p.lead_text.clone()),
        ("a", p.angle.clone()),
        ("p", "1".into()),
        (
            "taper",
            p.taper.map_or(String::new(), |c| p.n(mm(c.radial_change))),
        ),
    ]
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
