//! `threadcut thread` (standard thread data) and `threadcut mill` (thread-milling programs).

use std::io::{self, Write};

use serde_json::{json, Value};

use threadcut::diag::Diagnostic;
use threadcut::thread::standard::{self, Limits, StandardThread};
use threadcut::thread::Side;
use threadcut::units::Units;

use super::{io_failure, Failure};

/// A lookup or planning error as a usage failure: the message and the hint.
pub fn usage(d: Diagnostic) -> Failure {
    match d.hint {
        Some(h) => Failure::Usage(format!("{}\n  = help: {h}", d.message)),
        None => Failure::Usage(d.message),
    }
}

/// `threadcut thread NAME [--json]`, or `--list`.
pub fn thread(name: Option<&str>, json: bool, list: bool) -> Result<(), Failure> {
    let mut out = io::stdout().lock();
    if list {
        for n in standard::known_names() {
            writeln!(out, "{n}").map_err(io_failure)?;
        }
        return Ok(());
    }
    let Some(name) = name else {
        return Err(Failure::Usage(
            "name a thread (e.g. `threadcut thread M10x1.5` or `threadcut thread \"1/2-13 UNC-2A\"`), or use --list"
                .into(),
        ));
    };
    let t = standard::lookup(name).map_err(usage)?;
    if json {
        let v = thread_json(&t);
        serde_json::to_writer_pretty(&mut out, &v).map_err(|e| io_failure(e.into()))?;
        writeln!(out).map_err(io_failure)?;
    } else {
        write_thread(&mut out, &t).map_err(io_failure)?;
    }
    Ok(())
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
    }
    Ok(())
}

fn write_limits(out: &mut dyn Write, l: &Limits, u: Units) -> io::Result<()> {
    let d = decimals(u);
    let f =
        |x: Option<f64>| x.map_or_else(|| "—".to_string(), |mm| format!("{:.d$}", u.from_mm(mm)));
    let (side, dev) = match l.side {
        Side::External => ("external", "es"),
        Side::Internal => ("internal", "EI"),
    };
    writeln!(
        out,
        "{side} {}: {dev} {:+.d$} {}",
        l.class,
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
    if l.side == Side::External {
        writeln!(
            out,
            "  (minor: rounded-root d3 / UNR maximum; the standard sets no minimum)"
        )?;
    }
    Ok(())
}

fn thread_json(t: &StandardThread) -> Value {
    let u = t.units;
    let n = |mm: f64| json!(u.from_mm(mm));
    // Limits are tabulated values (0.001 mm, 0.0001 in): strip the mm → inch conversion noise.
    let o = |mm: Option<f64>| mm.map_or(Value::Null, |x| json!((u.from_mm(x) * 1e6).round() / 1e6));
    let limits = |l: &Limits| {
        json!({
            "class": l.class.to_string(),
            "deviation": (u.from_mm(l.deviation) * 1e6).round() / 1e6,
            "major": {"min": o(l.major.min), "max": o(l.major.max)},
            "pitch": {"min": o(l.pitch.min), "max": o(l.pitch.max)},
            "minor": {"min": o(l.minor.min), "max": o(l.minor.max)},
        })
    };
    json!({
        "name": t.name,
        "family": t.family,
        "series": t.series,
        "units": u,
        "pitch": n(t.pitch),
        "pitch_mm": t.pitch,
        "tpi": t.tpi,
        "basic": {
            "major": n(t.basic.major),
            "pitch_diameter": n(t.basic.pitch_diameter),
            "minor": n(t.basic.minor),
            "fundamental_height": n(t.basic.fundamental_height),
        },
        "thread_height": {"external": n(t.external_depth), "internal": n(t.internal_depth)},
        "turning_infeed": {"external": n(t.external_depth), "internal": n(t.internal_depth)},
        "external": t.external.as_ref().map(limits),
        "internal": t.internal.as_ref().map(limits),
    })
}
