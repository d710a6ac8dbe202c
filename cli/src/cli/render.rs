//! Diagnostics printed like a compiler's: `file:line:column`, the source line, a caret, a hint.

use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;

use annotate_snippets::{AnnotationKind, Level, Renderer, Snippet};

use threadcut::diag::{Diagnostic, Severity};

/// At most this much of a long line is shown around the caret.
const WINDOW: usize = 100;

pub fn diagnostic(file: &Path, d: &Diagnostic) -> String {
    let level = match d.severity {
        Severity::Error => Level::ERROR,
        Severity::Warning => Level::WARNING,
    };
    let origin = format!("{}:{}:{}", file.display(), d.span.line, d.span.column);
    let title = level.primary_title(d.message.as_str()).id(d.code.as_str());
    let source = source_line(file, d.span.line);
    let mut out = match &source {
        Some(line) if d.span.line > 0 => {
            let (text, start, end) = window(line, d.span.column as usize, d.span.len as usize);
            let snippet = Snippet::source(text.as_str())
                .line_start(d.span.line as usize)
                .path(file.display().to_string())
                .annotation(AnnotationKind::Primary.span(start..end));
            let mut group = title.element(snippet);
            if let Some(hint) = &d.hint {
                group = group.element(Level::HELP.message(hint.as_str()));
            }
            Renderer::plain().render(&[group])
        }
        _ => {
            let mut text = format!("{origin}: {}[{}]: {}", level_name(d), d.code, d.message);
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

/// The line's text (lossy UTF-8), read again from the file; `None` for standard input.
fn source_line(file: &Path, line: u32) -> Option<Vec<u8>> {
    if file.as_os_str() == "-" || line == 0 {
        return None;
    }
    let mut reader = BufReader::new(File::open(file).ok()?);
    let mut buf = Vec::new();
    for _ in 0..line {
        buf.clear();
        let n = (&mut reader)
            .take(1 << 21)
            .read_until(b'\n', &mut buf)
            .ok()?;
        if n == 0 {
            return None;
        }
    }
    while matches!(buf.last(), Some(b'\n' | b'\r')) {
        buf.pop();
    }
    Some(buf)
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
