//! `threadcut thread` (standard thread data) and `threadcut mill` (thread-milling programs).

use std::io::{self, Write};

use serde_json::{json, Value};

use threadcut::diag::Diagnostic;
use threadcut::dialect::CycleTaper;
use threadcut::mill::Side;
use threadcut::thread::standard::{self, Limits, StandardThread};
use threadcut::units::Units;

use super::{output, render, Failure, MachineArgs};

/// A lookup or planning error as a usage failure: the message and the hint.
pub fn usage(d: Diagnostic) -> Failure {
    match d.hint {
        Some(h) => Failure::Usage(format!("{}\n  = help: {h}", d.message)),
        None => Failure::Usage(d.message),
    }
}

/// `thread --controller`: where a taper thread is cut (the thread's units).
pub struct CycleArgs {
    pub machine: MachineArgs,
    pub internal: bool,
    pub face_z: Option<f64>,
    pub start_z: Option<f64>,
    pub length: Option<f64>,
}

/// `threadcut thread NAME [--json]`, or `--list`.
pub fn thread(
    name: Option<&str>,
    json: bool,
    list: bool,
    cycle: Option<CycleArgs>,
    out: Option<&std::path::Path>,
    wire: Option<f64>,
) -> Result<(), Failure> {
    let stdin = std::path::Path::new("-");
    if list {
        return output::write(stdin, out, |w| {
            for n in standard::known_names() {
                writeln!(w, "{n}").map_err(write_failure)?;
            }
            Ok(())
        });
    }
    let Some(name) = name else {
        return Err(Failure::Usage(
            "name a thread (e.g. `threadcut thread M10x1.5` or `threadcut thread \"1/2-13 UNC-2A\"`), or use --list"
                .into(),
        ));
    };
    let t = standard::lookup(name).map_err(thread_usage)?;
    let wire = match wire {
        Some(w) if w.is_finite() && w > 0.0 => Some(t.units.to_mm(w)),
        Some(w) => {
            return Err(Failure::Usage(format!(
                "--wire {w}: a measuring wire's diameter is a positive length ({})",
                t.units.name()
            )))
        }
        None => None,
    };
    let wires = t.wires(wire);
    let taper = match cycle {
        Some(c) => Some(taper_word(&t, &c)?),
        None => None,
    };
    output::write(stdin, out, |w| {
        if json {
            let mut v = t.to_json();
            v["wires"] = wires.to_json(t.units);
            if let Some((_, j)) = &taper {
                v["cycle"] = j.clone();
            }
            serde_json::to_writer_pretty(&mut *w, &v)
                .map_err(|e| write_failure(io::Error::from(e)))?;
            writeln!(w).map_err(write_failure)?;
        } else {
            write_thread(w, &t).map_err(write_failure)?;
            write_wires(w, &t, &wires).map_err(write_failure)?;
            if let Some((text, _)) = &taper {
                w.write_all(text.as_bytes()).map_err(write_failure)?;
            }
        }
        Ok(())
    })
}

fn write_failure(e: io::Error) -> Failure {
    super::failure(std::path::Path::new("-"), e.into())
}

/// A thread name that names no thread: the library's message and nearest names, and where the
/// whole list is.
pub fn thread_usage(d: Diagnostic) -> Failure {
    match d.hint {
        Some(h) => Failure::Usage(format!(
            "{}\n  = help: {h} (`threadcut thread --list` lists them all)",
            d.message
        )),
        None => Failure::Usage(d.message),
    }
}

/// The taper word of a controller's cycle for a taper thread: the text lines and their JSON.
fn taper_word(t: &StandardThread, c: &CycleArgs) -> Result<(String, Value), Failure> {
    use threadcut::thread::standard::lathe::{taper_cycle, Placement};
    let machine = super::load_machine(&c.machine)?;
    let dialect = threadcut::dialect::open(&machine).map_err(Failure::Usage)?;
    let u = t.units;
    let tp = t.taper.ok_or_else(|| {
        Failure::Usage(format!(
            "--controller: {} is a parallel thread; its cycle has no taper word",
            t.name
        ))
    })?;
    let side = if c.internal {
        Side::Internal
    } else {
        Side::External
    };
    let face_z = u.to_mm(c.face_z.unwrap_or(0.0));
    let start_z = c.start_z.map_or(face_z + 3.0 * t.pitch, |z| u.to_mm(z));
    let length = c.length.map_or(tp.effective_length, |l| u.to_mm(l));
    let cycle = taper_cycle(
        t,
        &Placement {
            side,
            face_z,
            start_z,
            length,
        },
    )
    .map_err(usage)?;
    let d = decimals(u);
    let v = |mm: f64| u.from_mm(mm);
    let dia = |r: f64| format!("Ø{:.d$}", v(2.0 * r));
    let mut text = format!(
        "{} {} thread on {} ({}): Z{:.d$} → Z{:.d$}, crest {} → {}, root {} → {}, height {:.d$} {}\n",
        if side == Side::External { "external" } else { "internal" },
        t.name,
        machine.name,
        dialect.name(),
        v(cycle.start_z),
        v(cycle.end_z),
        dia(cycle.crest_start_x),
        dia(cycle.crest_end_x),
        dia(cycle.root_start_x),
        dia(cycle.root_end_x),
        v(cycle.depth),
        u.name()
    );
    let taper = dialect.cycle_taper();
    let word = match taper {
        Some(CycleTaper::Word(w)) => Some(w),
        _ => None,
    };
    let value = word.map(|w| w.value(&cycle, machine.diameter_x));
    let mut diameters = Value::Null;
    match (taper, value) {
        (Some(CycleTaper::Word(w)), Some(val)) => text.push_str(&format!(
            "  taper word {} = {}{:.d$} ({}: {}, {}, over the cycle's whole Z travel)\n",
            w.cycles,
            w.letter,
            v(val),
            u.name(),
            if w.start_minus_end {
                "X at the start minus X at the end"
            } else {
                "X at the end minus X at the start"
            },
            if w.radius || !machine.diameter_x {
                "a radius"
            } else {
                "a diameter, as X is written"
            }
        )),
        (Some(CycleTaper::Diameters(w)), _) => {
            // The thread proper runs from the face to the end of its length; the run-up before the
            // face is the cycle's run-in, on the same cone.
            let (spl, fpl) = (face_z, cycle.end_z);
            let (dm1, dm2) = (2.0 * cycle.crest_at(spl), 2.0 * cycle.crest_at(fpl));
            let app = (cycle.start_z - face_z).abs();
            text.push_str(&format!(
                "  taper {} = {} {:.d$} at {} Z{:.d$}, {} {:.d$} at {} Z{:.d$}, {} {:.d$} ({}: the crest diameters at the thread's start and end points, {}; the run-in on the same cone)\n",
                w.cycles,
                w.at_start,
                v(dm1),
                w.start_point,
                v(spl),
                w.at_end,
                v(dm2),
                w.end_point,
                v(fpl),
                w.run_in,
                v(app),
                u.name(),
                if side == Side::External {
                    "the major diameter"
                } else {
                    "the tap hole's (minor) diameter"
                }
            ));
            diameters = json!({
                "cycles": w.cycles,
                w.at_start: v(dm1),
                w.at_end: v(dm2),
                w.start_point: v(spl),
                w.end_point: v(fpl),
                w.run_in: v(app),
            });
        }
        _ => text.push_str(&format!(
            "  {} has no taper word in its threading cycle: cut this thread with synchronised moves (G33/G32) or a post-processed program\n",
            machine.name
        )),
    }
    let j = json!({
        "controller": machine.name,
        "side": if side == Side::External { "external" } else { "internal" },
        "start_z": v(cycle.start_z),
        "end_z": v(cycle.end_z),
        "crest": {"start": v(2.0 * cycle.crest_start_x), "end": v(2.0 * cycle.crest_end_x)},
        "root": {"start": v(2.0 * cycle.root_start_x), "end": v(2.0 * cycle.root_end_x)},
        "height": v(cycle.depth),
        "taper_word": word.map(|w| json!({"cycles": w.cycles, "letter": w.letter.to_string(), "value": value.map(v)})),
        "taper_diameters": diameters,
    });
    Ok((text, j))
}

fn decimals(units: Units) -> usize {
    match units {
        Units::Mm => 3,
        Units::Inch => 4,
    }
}

fn write_thread(out: &mut dyn Write, t: &StandardThread) -> io::Result<()> {
    let u = t.units;
    let d = decimals(u);
    let v = |mm: f64| u.from_mm(mm);
    let family = match t.family {
        standard::Family::Metric => "ISO metric",
        standard::Family::Unified => "Unified inch",
        _ => return write_form(out, t),
    };
    match t.tpi {
        Some(tpi) => writeln!(
            out,
            "{}  {family} {}, {tpi} threads per inch (pitch {:.6} in = {:.4} mm)",
            t.name,
            t.series.name(),
            v(t.pitch),
            t.pitch
        )?,
        None => writeln!(
            out,
            "{}  {family} {} pitch, pitch {} mm",
            t.name,
            t.series.name(),
            t.pitch
        )?,
    }
    let un = u.name();
    writeln!(
        out,
        "basic ({un}): major {:.d$}  pitch diameter {:.d$}  minor {:.d$}  H {:.d2$}",
        v(t.basic.major),
        v(t.basic.pitch_diameter),
        v(t.basic.minor),
        v(t.basic.fundamental_height),
        d2 = d + 2
    )?;
    writeln!(
        out,
        "thread height / turning infeed ({un}, radial): external {:.d2$} (17/24·H = 0.61343·P), internal {:.d2$} (5/8·H = 0.54127·P)",
        v(t.external_depth),
        v(t.internal_depth),
        d2 = d + 1
    )?;
    for side in [Side::External, Side::Internal] {
        let given = match side {
            Side::External => t.external,
            Side::Internal => t.internal,
        };
        let Some(l) = given else { continue };
        write_limits(out, &l, u)?;
        write_gauges(out, t, &l)?;
    }
    Ok(())
}

/// The GO / NOT GO gauges of a metric (ISO 1502) or Unified (ASME B1.2) class.
fn write_gauges(out: &mut dyn Write, t: &StandardThread, l: &Limits) -> io::Result<()> {
    let u = t.units;
    let d = decimals(u);
    let standard = match t.family {
        standard::Family::Metric => "ISO 1502",
        _ => "ASME B1.2",
    };
    let pairs = standard::gauges::gauges(l);
    let said: Vec<String> = pairs
        .iter()
        .map(|g| {
            format!(
                "{} ({}) GO {:.d$} / NOT GO {:.d$}",
                g.gauge,
                g.diameter,
                u.from_mm(g.go),
                u.from_mm(g.not_go)
            )
        })
        .collect();
    if said.is_empty() {
        return Ok(());
    }
    writeln!(
        out,
        "  gauges ({standard}, at the class limits; gauge tolerances not applied): {}",
        said.join("; ")
    )
}

fn edge_text(e: &standard::Edge, u: Units, d: usize) -> String {
    let v = |mm: f64| u.from_mm(mm);
    match *e {
        standard::Edge::Sharp => "sharp".into(),
        standard::Edge::Flat { width } => format!("flat {:.d$}", v(width)),
        standard::Edge::Round { radius } => format!("radius {:.d$}", v(radius)),
        standard::Edge::Truncated { min, max } => {
            format!("truncated {:.d$} to {:.d$}", v(min), v(max))
        }
    }
}

/// The pipe, trapezoidal, Acme and Whitworth forms: every quantity of the form, then the limits.
fn write_form(out: &mut dyn Write, t: &StandardThread) -> io::Result<()> {
    let u = t.units;
    let d = decimals(u);
    let d5 = d + 1;
    let un = u.name();
    let v = |mm: f64| u.from_mm(mm);
    match t.tpi {
        Some(tpi) => writeln!(
            out,
            "{}  {}, {tpi} threads per inch (pitch {:.6} {un} = {:.4} mm)",
            t.name,
            t.family.name(),
            v(t.pitch),
            t.pitch
        )?,
        None => writeln!(out, "{}  {}, pitch {} mm", t.name, t.family.name(), t.pitch)?,
    }
    let p = &t.profile;
    writeln!(
        out,
        "form: {}° (flanks {}° from the radial), fundamental triangle H {:.d5$} {un}",
        p.angle_deg,
        p.flank_angle_deg,
        v(p.fundamental_height)
    )?;
    writeln!(
        out,
        "  external crest {}, root {}; internal crest {}, root {} ({un})",
        edge_text(&p.external_crest, u, d5),
        edge_text(&p.external_root, u, d5),
        edge_text(&p.internal_crest, u, d5),
        edge_text(&p.internal_root, u, d5)
    )?;
    let at = if t.taper.is_some() {
        " at the gauge plane"
    } else {
        ""
    };
    if t.family == standard::Family::Trapezoidal {
        // ISO 2904 names the diameters by side: d and D4, d2 = D2, d3 and D1; a_c is the crest
        // clearance between d and D4 (and d3 and D1).
        let ac = standard::trapezoidal::crest_clearance(t.pitch);
        writeln!(
            out,
            "basic ({un}): major d {:.d5$} (internal D4 {:.d5$})  pitch diameter d2 = D2 {:.d5$}  minor d3 {:.d5$} (external), D1 {:.d5$} (internal); crest clearance ac {:.d5$}",
            v(t.basic.major),
            v(t.basic.major + 2.0 * ac),
            v(t.basic.pitch_diameter),
            v(t.basic.major - 2.0 * t.external_depth),
            v(t.basic.minor),
            v(ac),
        )?;
    } else {
        writeln!(
            out,
            "basic{at} ({un}): major {:.d5$}  pitch diameter {:.d5$}  minor {:.d5$}",
            v(t.basic.major),
            v(t.basic.pitch_diameter),
            v(t.basic.minor),
        )?;
    }
    writeln!(
        out,
        "thread height / turning infeed ({un}, radial): external {:.d5$}, internal {:.d5$}",
        v(t.external_depth),
        v(t.internal_depth),
    )?;
    if let Some(tp) = &t.taper {
        writeln!(
            out,
            "taper 1:{} on diameter; gauge plane {:.d$} {un} from the small end of the external thread (at the opening of the internal one)",
            1.0 / tp.diameter_per_length,
            v(tp.gauge_length)
        )?;
        writeln!(
            out,
            "  pitch diameter: small end {:.d5$}, gauge plane {:.d5$}, end of the effective thread {:.d5$} ({un})",
            v(tp.small_end_pitch_diameter),
            v(tp.gauge_pitch_diameter),
            v(tp.effective_end_pitch_diameter)
        )?;
        writeln!(
            out,
            "  effective (useful) thread {:.d$} {un}; gauge plane tolerance ±{:.d$} external, ±{:.d$} internal ({un}, {:.2} / {:.2} turns)",
            v(tp.effective_length),
            v(tp.external_position_tolerance),
            v(tp.internal_position_tolerance),
            tp.external_position_tolerance / t.pitch,
            tp.internal_position_tolerance / t.pitch
        )?;
        if tp.vanish_length > 0.0 {
            writeln!(
                out,
                "  vanish thread {:.d$}, overall external thread (L4) {:.d$}, wrench make-up {:.d$} ({un})",
                v(tp.vanish_length),
                v(tp.overall_length),
                v(tp.wrench_makeup)
            )?;
        }
    }
    for side in [Side::External, Side::Internal] {
        let given = match side {
            Side::External => t.external,
            Side::Internal => t.internal,
        };
        let Some(l) = given else { continue };
        write_limits(out, &l, u)?;
        if let Some(g) = standard::Groove::at_maximum_material(&l, t.pitch, &t.profile) {
            let tip = match g.root {
                standard::Edge::Flat { width } => {
                    format!("flat tip {:.d5$} (--tip-flat {:.d5$})", v(width), v(width))
                }
                standard::Edge::Round { radius } => {
                    format!(
                        "nose radius {:.d5$} (--nose-radius {:.d5$})",
                        v(radius),
                        v(radius)
                    )
                }
                _ => "sharp tip".into(),
            };
            writeln!(
                out,
                "  form tool: {}° {tip}, {:.d5$} deep to the maximum-material root ({un})",
                2.0 * g.flank_angle_deg,
                v(g.depth)
            )?;
        }
    }
    if t.taper.is_some() {
        writeln!(out, "  (limits at the gauge plane)")?;
    }
    Ok(())
}

/// The three-wire measurement: the wires that fit, and M over the wire at the basic pitch
/// diameter and at the external class's limits, by both formulas.
fn write_wires(
    out: &mut dyn Write,
    t: &StandardThread,
    w: &standard::wires::Wires,
) -> io::Result<()> {
    let u = t.units;
    let d = decimals(u) + 1;
    let un = u.name();
    let v = |mm: f64| u.from_mm(mm);
    let at = if t.taper.is_some() {
        ", at the gauge plane"
    } else {
        ""
    };
    writeln!(
        out,
        "three wires ({un}{at}): best wire {:.d$}; wires from {:.d$} to {:.d$} touch the flanks",
        v(w.best),
        v(w.min),
        v(w.max)
    )?;
    if !w.fits {
        writeln!(
            out,
            "  the {:.d$} wire does not touch both flanks below the crest: M over it does not measure the pitch diameter",
            v(w.wire)
        )?;
    }
    writeln!(
        out,
        "  M over {:.d$} wires: simple / with the lead angle",
        v(w.wire)
    )?;
    writeln!(
        out,
        "    basic E {:.d$}: {:.d$} / {:.d$}",
        v(w.basic.pitch_diameter),
        v(w.basic.simple),
        v(w.basic.corrected)
    )?;
    if let (Some((lo, hi)), Some(class)) = (&w.limits, &w.class) {
        for (name, o) in [("min", lo), ("max", hi)] {
            writeln!(
                out,
                "    {class} E {name} {:.d$}: {:.d$} / {:.d$}",
                v(o.pitch_diameter),
                v(o.simple),
                v(o.corrected)
            )?;
        }
    }
    writeln!(out, "  ({})", standard::wires::FORMULAS)
}

fn write_limits(out: &mut dyn Write, l: &Limits, u: Units) -> io::Result<()> {
    let d = decimals(u);
    let f =
        |x: Option<f64>| x.map_or_else(|| "—".to_string(), |mm| format!("{:.d$}", u.from_mm(mm)));
    let (side, dev) = match l.side {
        Side::External => ("external", "es"),
        Side::Internal => ("internal", "EI"),
    };
    // A pipe thread's one class is named by its side ("internal"): the side is said once.
    let class = l.class.to_string();
    let class = if class == side {
        String::new()
    } else {
        format!(" {class}")
    };
    writeln!(
        out,
        "{side}{class}: {dev} {:+.d$} {}",
        u.from_mm(l.deviation),
        u.name()
    )?;
    writeln!(out, "  {:<6} {:>10} {:>10}", "", "min", "max")?;
    let rows: [(&str, _); 3] = match l.side {
        Side::External => [("major", l.major), ("pitch", l.pitch), ("minor", l.minor)],
        Side::Internal => [("minor", l.minor), ("pitch", l.pitch), ("major", l.major)],
    };
    for (name, r) in rows {
        writeln!(out, "  {name:<6} {:>10} {:>10}", f(r.min), f(r.max))?;
    }
    if l.side == Side::External && l.minor.min.is_none() {
        writeln!(
            out,
            "  (minor: rounded-root d3 / UNR maximum; the standard sets no minimum)"
        )?;
    }
    Ok(())
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub enum CompArg {
    /// Controller compensation: G41 or G42 as TB029's table gives for the case.
    G41,
    /// None: the program is the tool-centre path.
    None,
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub enum LeadArg {
    /// A quarter-circle tangent to the helix, climbing with it.
    Arc,
    /// TB029 step 4: a straight radial move to the start point.
    Radial,
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub enum MillFormat {
    Gcode,
    /// One JSON object per move (a first `plan` object, then rapid/feed/arc).
    Jsonl,
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub enum UnitsArg {
    Mm,
    Inch,
}

#[derive(clap::Args)]
pub struct MillArgs {
    /// Standard thread name: `M10x1.5`, `M12-6H`, `"1/2-13 UNC-2B"`, `"1-8 UNC"`.
    #[arg(long)]
    thread: String,
    /// An internal thread (a nut): the bore is at the minor diameter.
    #[arg(long, conflicts_with = "external")]
    internal: bool,
    /// An external thread (a bolt): the cylinder is at the major diameter.
    #[arg(long)]
    external: bool,
    /// Left-hand thread (TB029 tip 4: compensation and arc directions reversed).
    #[arg(long)]
    left: bool,
    /// Thread length, down from --start-z (program units).
    #[arg(long, allow_hyphen_values = true)]
    length: f64,
    /// Cutting diameter of the thread mill (program units).
    #[arg(long, allow_hyphen_values = true)]
    tool_diameter: f64,
    /// Thread-form teeth on the tool, one pitch apart.
    #[arg(long, default_value_t = 1)]
    teeth: u32,
    /// Mill from the top down (default: the climb-milling direction).
    #[arg(long, conflicts_with = "bottom_up")]
    top_down: bool,
    /// Mill from the bottom up.
    #[arg(long)]
    bottom_up: bool,
    /// Radial passes of equal chip area.
    #[arg(long, default_value_t = 1)]
    passes: u32,
    /// Thread starts: each turn advances starts × pitch, each start turned 360°/starts.
    #[arg(long, default_value_t = 1)]
    starts: u32,
    /// Cutter compensation.
    #[arg(long, value_enum, default_value = "g41")]
    comp: CompArg,
    /// Thread axis `X,Y` (program units).
    #[arg(long, default_value = "0,0", allow_hyphen_values = true)]
    center: String,
    /// Top of the thread (program units).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    start_z: f64,
    /// Feed at the cutting edge (program units per minute); arc feeds are scaled from it.
    #[arg(long, allow_hyphen_values = true)]
    feed: f64,
    /// How the tool reaches the helix.
    #[arg(long, value_enum, default_value = "arc")]
    lead: LeadArg,
    /// Height above --start-z for rapid moves (program units; default 5 mm / 0.2 in).
    #[arg(long, allow_hyphen_values = true)]
    clearance: Option<f64>,
    /// Program units (default: the thread's own, mm for metric, inch for Unified).
    #[arg(long, value_enum)]
    units: Option<UnitsArg>,
    /// Offset register for G41/G42 (the D word).
    #[arg(long)]
    d_register: Option<u32>,
    /// Milling controller profile, any case: centroid, fanuc-mill, haas-mill, linuxcnc-mill.
    #[arg(
        long,
        short = 'c',
        value_name = "NAME",
        required_unless_present = "machine"
    )]
    controller: Option<String>,
    /// Milling profile (a TOML file like profiles/centroid.toml); used instead of --controller.
    #[arg(long, value_name = "FILE.toml")]
    machine: Option<std::path::PathBuf>,
    /// The program (gcode), or one JSON object per move (jsonl).
    #[arg(long, value_enum, default_value = "gcode")]
    format: MillFormat,
    /// Write to this file instead of standard output (`-` or absent: standard output). A file is
    /// written whole or not at all (a temporary file beside it, renamed at the end).
    #[arg(long, short = 'o', value_name = "OUT")]
    output: Option<std::path::PathBuf>,
}

/// The milling profile `mill` is given: a profile file, or a built-in one by name.
fn mill_profile(a: &MillArgs) -> Result<threadcut::mill::profile::MillProfile, Failure> {
    use threadcut::machine::{built_in_name, ProfileKind};
    use threadcut::mill::profile::MillProfile;
    if let Some(path) = &a.machine {
        let text = std::fs::read_to_string(path).map_err(|e| {
            Failure::Usage(format!(
                "cannot read {}: {}",
                path.display(),
                super::reason(&e)
            ))
        })?;
        return MillProfile::from_toml(&text).map_err(|e| {
            Failure::Usage(format!(
                "{} is not a milling profile: {}",
                path.display(),
                e.message().trim_end()
            ))
        });
    }
    let name = a.controller.as_deref().unwrap_or_default();
    built_in_name(name, ProfileKind::Mill)
        .map(|n| MillProfile::built_in(n).expect("built-in profiles parse"))
        .map_err(|e| Failure::Usage(super::name_error(name, e, ProfileKind::Mill)))
}

/// `--center X,Y`, in the program's units.
fn parse_center(text: &str) -> Result<(f64, f64), Failure> {
    let bad = || {
        Failure::Usage(format!(
            "--center: `{text}` is not `X,Y` (e.g. --center 10,-5.5)"
        ))
    };
    let (x, y) = text.split_once(',').ok_or_else(bad)?;
    let x: f64 = x.trim().parse().map_err(|_| bad())?;
    let y: f64 = y.trim().parse().map_err(|_| bad())?;
    Ok((x, y))
}

/// `threadcut mill …`: the flags as a [`threadcut::mill::Request`], which the Python package
/// fills from its keywords too.
pub fn mill(a: MillArgs) -> Result<(), Failure> {
    use threadcut::mill::{Comp, Direction, Hand, LeadIn, Request};

    let profile = mill_profile(&a)?;
    let side = match (a.internal, a.external) {
        (true, false) => Side::Internal,
        (false, true) => Side::External,
        _ => {
            return Err(Failure::Usage(
                "name the side: --internal (a nut) or --external (a bolt)".into(),
            ))
        }
    };
    let request = Request {
        hand: if a.left { Hand::Left } else { Hand::Right },
        teeth: a.teeth,
        direction: match (a.top_down, a.bottom_up) {
            (true, _) => Some(Direction::TopDown),
            (_, true) => Some(Direction::BottomUp),
            _ => None,
        },
        passes: a.passes,
        starts: a.starts,
        comp: match a.comp {
            CompArg::G41 => Comp::Controller,
            CompArg::None => Comp::Off,
        },
        center: parse_center(&a.center)?,
        start_z: a.start_z,
        lead_in: match a.lead {
            LeadArg::Arc => LeadIn::Arc,
            LeadArg::Radial => LeadIn::Radial,
        },
        clearance: a.clearance,
        units: a.units.map(|u| match u {
            UnitsArg::Mm => Units::Mm,
            UnitsArg::Inch => Units::Inch,
        }),
        d_register: a.d_register,
        ..Request::new(&a.thread, side, a.length, a.tool_diameter, a.feed, profile)
    };
    let milling = request.prepare().map_err(usage)?;
    for w in &milling.warnings {
        let text = match &w.hint {
            Some(h) => format!("{}\n  = help: {h}", w.message),
            None => w.message.clone(),
        };
        eprint!("{}", render::warning(&text));
    }
    super::output::write(std::path::Path::new("-"), a.output.as_deref(), |out| {
        match a.format {
            MillFormat::Gcode => milling.write_gcode(out),
            MillFormat::Jsonl => milling.write_jsonl(out),
        }
        .map_err(write_failure)
    })?;
    Ok(())
}
