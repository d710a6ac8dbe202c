//! `check`, `passes` and `plot_svg` on a milling profile: the library's milling check over the
//! keywords the lathe's functions take, plus the milling ones (`internal`, `tool_diameter`,
//! `teeth`, `tools`).

use std::collections::HashMap;

use pyo3::prelude::*;

use threadcut::check::milling::{self, ToolSize};
use threadcut::commands::milled;
use threadcut::machine::{built_in_name, ProfileKind};
use threadcut::mill::profile::MillProfile;
use threadcut::mill::Side;

use super::Problem;

/// The milling keywords.
pub struct Keywords {
    pub internal: Option<bool>,
    pub tool_diameter: Option<f64>,
    pub teeth: Option<u32>,
    pub tools: Option<HashMap<String, f64>>,
}

impl Keywords {
    /// Whether any is given (a lathe controller then refuses them).
    pub fn any(&self) -> bool {
        self.internal.is_some()
            || self.tool_diameter.is_some()
            || self.teeth.is_some()
            || self.tools.is_some()
    }
}

/// The milling profile a controller's name gives (no `machine=` file: milling profiles are the
/// built-in ones here).
pub fn profile(controller: &str, machine_given: bool) -> Option<MillProfile> {
    if machine_given {
        return None;
    }
    let name = built_in_name(controller, ProfileKind::Mill).ok()?;
    MillProfile::built_in(name)
}

/// The milling profile and the check's options, when `controller` names a milling profile (no
/// `machine=`); the thread and the wire are `check`'s keywords.
pub fn call(
    py: Python<'_>,
    controller: &str,
    machine: Option<&Bound<'_, PyAny>>,
    (thread, wire): (Option<&str>, Option<f64>),
    k: &Keywords,
) -> PyResult<Option<(MillProfile, milling::Options)>> {
    let Some(profile) = profile(controller, machine.is_some_and(|m| !m.is_none())) else {
        return Ok(None);
    };
    let max_blocks = threadcut::program::Options::default().max_blocks;
    Ok(Some((profile, options(py, thread, wire, k, max_blocks)?)))
}

/// A lathe controller given milling keywords.
pub fn refuse_on_a_lathe(py: Python<'_>, k: &Keywords) -> PyResult<()> {
    if k.any() {
        return Err(Problem::usage(
            "internal=, tool_diameter=, teeth= and tools= read a milling program: name a milling controller (fanuc-mill, haas-mill, linuxcnc-mill, centroid)",
        )
        .error(py));
    }
    Ok(())
}

/// The milling check's options from the keywords.
pub fn options(
    py: Python<'_>,
    thread: Option<&str>,
    wire: Option<f64>,
    k: &Keywords,
    max_blocks: u64,
) -> PyResult<milling::Options> {
    let thread = thread
        .map(milling::named_thread)
        .transpose()
        .map_err(|d| Problem::diagnostic(&d, None).error(py))?;
    let wire = match (super::wire_keyword(py, wire, thread.is_some())?, &thread) {
        (Some(w), Some((t, _))) => Some(t.units.to_mm(w)),
        (w, _) => w,
    };
    if let Some(d) = k.tool_diameter.filter(|d| !(d.is_finite() && *d > 0.0)) {
        return Err(Problem::usage(format!(
            "tool_diameter={d}: a cutter's diameter is a positive length (program units)"
        ))
        .error(py));
    }
    if k.teeth == Some(0) {
        return Err(Problem::usage("teeth=0: a thread mill has at least one tooth").error(py));
    }
    let mut tools = Vec::new();
    for (key, value) in k.tools.iter().flatten() {
        tools.push(ToolSize::of(key, *value).ok_or_else(|| {
            Problem::usage(format!(
                "tools={{{key:?}: {value}}}: expected a register or tool number (\"D16\", \"T5\") and the cutter's diameter (program units)"
            ))
            .error(py)
        })?);
    }
    Ok(milling::Options {
        thread,
        tip: None,
        wire,
        side: k
            .internal
            .map(|i| if i { Side::Internal } else { Side::External }),
        tool_diameter: k.tool_diameter,
        tools,
        teeth: k.teeth,
        max_blocks: Some(max_blocks),
    })
}

/// `passes` on a milling program: `{"milled": [...], "taps": [...]}` as
/// `threadcut passes --format json` writes it.
pub fn passes_json(
    py: Python<'_>,
    program: &str,
    profile: &MillProfile,
    o: &milling::Options,
) -> PyResult<String> {
    let m = read(py, program, profile, o)?;
    let threads: Vec<_> = m.threads.iter().map(|t| milled::json(t, None)).collect();
    Ok(serde_json::json!({ "milled": threads, "taps": m.taps }).to_string())
}

/// `plot_svg` on a milling program.
pub fn svg(
    py: Python<'_>,
    program: &str,
    profile: &MillProfile,
    o: &milling::Options,
) -> PyResult<String> {
    let m = read(py, program, profile, o)?;
    let angle = o.thread.as_ref().map_or(60.0, |(t, _)| t.profile.angle_deg);
    Ok(threadcut::render::milled::svg(&m.threads, angle))
}

fn read(
    py: Python<'_>,
    program: &str,
    profile: &MillProfile,
    o: &milling::Options,
) -> PyResult<milling::Milled> {
    let m = py
        .detach(|| milling::read(program.as_bytes(), profile, o))
        .map_err(|d| Problem::diagnostic(&d, Some(super::PROGRAM)).error(py))?;
    if m.threads.is_empty() && m.taps.is_empty() {
        Problem::plain_warning(
            "no thread found: no helix about one axis and no tapping cycle (G84, G74, G33.1)",
        )
        .warn(py)?;
    }
    Ok(m)
}
