//! Diagnostics printed like a compiler's: `file:line:column`, the source line, a caret, a hint.

use std::fs::File;
use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use annotate_snippets::{AnnotationKind, Level, Renderer, Snippet};

use threadcut::diag::{Diagnostic, Severity, Span};
use threadcut::interp::library::{Dirs, Library};

/// The library of the command's include directories (one a process: the files it numbered
/// are the ones the messages show).
static LIBRARY: std::sync::OnceLock<Library> = std::sync::OnceLock::new();

/// The library that searches `dirs`, made once.
pub fn library(dirs: &[std::path::PathBuf]) -> Library {
    LIBRARY
        .get_or_init(|| Library::new(Dirs::new(dirs.to_vec())))
        .clone()
}

/// The name and text of the file a span lies in, when it is a file a call read.
fn called_file(span: &Span) -> Option<(String, std::sync::Arc<[u8]>)> {
    match span.file() {
        0 => None,
        k => LIBRARY.get()?.0.source(k),
    }
}

/// Line `line` of a text held in memory.
fn line_of(text: &[u8], line: u32) -> Option<Vec<u8>> {
    let mut l = text
        .split(|&b| b == b'\n')
        .nth(line.checked_sub(1)? as usize)?
        .to_vec();
    while matches!(l.last(), Some(b'\r')) {
        l.pop();
    }
    Some(l)
}

/// Where a span is, for a "called from" line: `line 11 of MAIN.MPF`.
fn place(main: &Path, span: &Span) -> String {
    let name = match called_file(span) {
        Some((name, _)) => name,
        None if main.as_os_str() == "-" => "<stdin>".to_string(),
        None => main.display().to_string(),
    };
    format!("line {} of {name}", span.line)
}

/// The file a span lies in, as messages name it: the called file's name, else the program's.
pub fn file_of(main: &Path, span: &Span) -> String {
    match called_file(span) {
        Some((name, _)) => name,
        None => main.display().to_string(),
    }
}

/// At most this much of a long line is shown around the caret.
const WINDOW: usize = 100;

pub fn diagnostic(main: &Path, d: &Diagnostic) -> String {
    let called = called_file(&d.span);
    let path_buf;
    let file = match &called {
        Some((name, _)) => {
            path_buf = std::path::PathBuf::from(name);
            path_buf.as_path()
        }
        None => main,
    };
    let level = match d.severity {
        Severity::Error => Level::ERROR,
        Severity::Warning => Level::WARNING,
    };
    let origin = format!(
        "{}:{}:{}",
        if file.as_os_str() == "-" {
            "<stdin>".into()
        } else {
            file.display().to_string()
        },
        d.span.line,
        d.span.column
    );
    let title = level.primary_title(d.message.as_str()).id(d.code.as_str());
    let source = match &called {
        Some((_, text)) => line_of(text, d.span.line),
        None => source_line(file, &d.span),
    };
    // The calls it ran inside, innermost first.
    let chain: Vec<String> = d
        .calls
        .iter()
        .rev()
        .map(|c| format!("called from {}", place(main, c)))
        .collect();
    let mut out = match &source {
        Some(line) if d.span.line > 0 => {
            let (text, start, end) = window(line, d.span.column as usize, d.span.len as usize);
            let snippet = Snippet::source(text.as_str())
                .line_start(d.span.line as usize)
                .path(file.display().to_string())
                .annotation(AnnotationKind::Primary.span(start..end));
            let mut group = title.element(snippet);
            for c in &chain {
                group = group.element(Level::NOTE.message(c.as_str()));
            }
            if let Some(hint) = &d.hint {
                group = group.element(Level::HELP.message(hint.as_str()));
            }
            Renderer::plain().render(&[group])
        }
        _ => {
            // No source line to show (standard input): the same head and place, then the hint.
            let mut text = format!("{}[{}]: {}", level_name(d), d.code, d.message);
            if d.span.line > 0 {
                text.push_str(&format!("\n --> {origin}"));
            }
            for c in &chain {
                text.push_str(&format!("\n  = note: {c}"));
            }
            if let Some(hint) = &d.hint {
                text.push_str(&format!("\n  = help: {hint}"));
            }
            text
        }
    };
    out.push('\n');
    out
}

fn level_name(d: &Diagnostic) -> &'static str {
    match d.severity {
        Severity::Error => "error",
        Severity::Warning => "warning",
    }
}

/// The span's line, read again from the file; `None` for standard input. Read where the span says
/// it begins (its offset less its column), so that a program with a finding on each of thousands
/// of lines is not read from its start for each; from the start when the span's offset does not
/// fall at a line's start.
fn source_line(file: &Path, span: &Span) -> Option<Vec<u8>> {
    if file.as_os_str() == "-" || span.line == 0 {
        return None;
    }
    let mut reader = BufReader::new(File::open(file).ok()?);
    let mut buf = Vec::new();
    let at = span.start.checked_sub(u64::from(span.column.max(1) - 1));
    let seeked = match at {
        Some(0) => span.line == 1,
        // The byte before the line is the end of the line before it.
        Some(at) => {
            reader.seek(SeekFrom::Start(at - 1)).ok()?;
            let mut before = [0u8];
            reader.read_exact(&mut before).is_ok() && before[0] == b'\n'
        }
        None => false,
    };
    if !seeked {
        reader.rewind().ok()?;
        for _ in 1..span.line {
            buf.clear();
            if read_line(&mut reader, &mut buf)? == 0 {
                return None;
            }
        }
    }
    buf.clear();
    if read_line(&mut reader, &mut buf)? == 0 {
        return None;
    }
    while matches!(buf.last(), Some(b'\n' | b'\r')) {
        buf.pop();
    }
    Some(buf)
}

/// One line into `buf` (at most 2 MiB of it): the bytes read, `None` on a read error.
fn read_line(reader: &mut BufReader<File>, buf: &mut Vec<u8>) -> Option<usize> {
    reader.take(1 << 21).read_until(b'\n', buf).ok()
}

/// Cuts a long line down to a window around the span and converts it to printable text, returning
/// the text and the span's byte range within it.
fn window(line: &[u8], column: usize, len: usize) -> (String, usize, usize) {
    let start = column.saturating_sub(1).min(line.len());
    let end = (start + len.max(1)).min(line.len());
    let from = start.saturating_sub(WINDOW / 2);
    let to = (end + WINDOW / 2).min(line.len());
    let printable = |bytes: &[u8]| -> String {
        String::from_utf8_lossy(bytes)
            .chars()
            .map(|c| if c.is_control() && c != '\t' { '?' } else { c })
            .collect()
    };
    let mut text = String::from(if from > 0 { "…" } else { "" });
    text.push_str(&printable(&line[from..start]));
    let a = text.len();
    text.push_str(&printable(&line[start..end]));
    let b = text.len();
    text.push_str(&printable(&line[end..to]));
    if to < line.len() {
        text.push('…');
    }
    (text, a, b)
}

/// A message without a place in the program: `error: message`, and its `  = help:` lines.
pub fn error(message: &str) -> String {
    format!("error: {}\n", message.trim_end())
}

/// A warning without a place in the program: `warning: message`, and its `  = help:` lines.
pub fn warning(message: &str) -> String {
    format!("warning: {}\n", message.trim_end())
}

/// clap's error text in the one form: its first line `error: …` (a list of missing arguments
/// joined onto it), then each tip, the usage and the pointer to `--help` as `  = help:` and
/// `  = note:` lines.
pub fn clap_error(rendered: &str) -> String {
    let mut lines = rendered.lines().map(str::trim_end).peekable();
    let mut head = lines.next().unwrap_or("error: bad usage").to_string();
    if !head.starts_with("error:") {
        head = format!("error: {}", head.trim());
    }
    // `the following required arguments were not provided:` and the indented list after it.
    if head.ends_with(':') {
        let mut items = Vec::new();
        while let Some(l) = lines.next_if(|l| l.starts_with("  ") && !l.trim().is_empty()) {
            items.push(l.trim().to_string());
        }
        if !items.is_empty() {
            head = format!("{} {}", head, items.join(", "));
        }
    }
    let mut out = head;
    out.push('\n');
    for l in lines {
        let t = l.trim();
        if t.is_empty() {
            continue;
        }
        let line = if let Some(tip) = t.strip_prefix("tip: ") {
            format!("  = help: {tip}")
        } else if let Some(values) = t
            .strip_prefix("[possible values: ")
            .and_then(|v| v.strip_suffix(']'))
        {
            format!("  = help: possible values: {values}")
        } else if let Some(usage) = t.strip_prefix("Usage: ") {
            format!("  = note: usage: {usage}")
        } else if t.starts_with("For more information, try") {
            let rest = t.trim_start_matches("For more information, try ");
            format!(
                "  = help: for more information, try {}",
                rest.trim_end_matches('.')
            )
        } else if l.starts_with(' ') {
            // A further usage line.
            format!("  = note: usage: {t}")
        } else {
            format!("  = note: {t}")
        };
        out.push_str(&line);
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clap_errors_take_the_one_form() {
        let clap = "error: unexpected argument '--frmat' found\n\n  tip: a similar argument exists: '--format'\n\nUsage: threadcut passes [OPTIONS] <FILE>\n\nFor more information, try '--help'.\n";
        assert_eq!(
            clap_error(clap),
            "error: unexpected argument '--frmat' found\n  = help: a similar argument exists: '--format'\n  = note: usage: threadcut passes [OPTIONS] <FILE>\n  = help: for more information, try '--help'\n"
        );
        let clap = "error: the following required arguments were not provided:\n  --length <LENGTH>\n  --feed <FEED>\n\nUsage: threadcut mill --length <LENGTH>\n";
        assert_eq!(
            clap_error(clap),
            "error: the following required arguments were not provided: --length <LENGTH>, --feed <FEED>\n  = note: usage: threadcut mill --length <LENGTH>\n"
        );
        let clap =
            "error: invalid value 'xml' for '--format <FORMAT>'\n  [possible values: text, json]\n";
        assert_eq!(
            clap_error(clap),
            "error: invalid value 'xml' for '--format <FORMAT>'\n  = help: possible values: text, json\n"
        );
    }
}
