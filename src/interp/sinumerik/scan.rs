//! Whether a line the dialect would read itself needs the interpreter: program flow, a label, a
//! call of a subprogram by name, or a computed value.

/// The words that begin program flow in Sinumerik's language.
pub(super) const FLOW: &[&str] = &[
    "IF", "ELSE", "ENDIF", "WHILE", "ENDWHILE", "FOR", "ENDFOR", "LOOP", "ENDLOOP", "REPEAT",
    "REPEATB", "UNTIL", "GOTO", "GOTOF", "GOTOB", "GOTOC", "PROC", "RET", "CALL",
];

/// Whether `text` (a line in Sinumerik's own syntax) holds program flow, a label, a call by name
/// or an expression. `plain` lists the names that are the dialect's own words.
pub fn looks_like_macro(text: &[u8], plain: &[&[&str]]) -> bool {
    let mut k = 0;
    let mut first = true;
    // Parentheses open: a call's arguments and an expression's parts are values, not calls (and
    // a `(` comment of another controller is no Sinumerik at all).
    let mut depth = 0usize;
    if text.iter().find(|c| !c.is_ascii_whitespace()) == Some(&b'%') {
        // The program's header, `%_N_NAME_MPF`.
        return false;
    }
    while k < text.len() {
        let c = text[k];
        match c {
            b';' => break,
            b'(' => {
                depth += 1;
                k += 1;
            }
            b')' => {
                depth = depth.saturating_sub(1);
                k += 1;
            }
            b'"' => {
                k += 1;
                while k < text.len() && text[k] != b'"' {
                    k += 1;
                }
                k += 1;
            }
            c if (c.is_ascii_alphabetic() || c == b'_')
                && !(k > 0 && (text[k - 1].is_ascii_alphanumeric() || text[k - 1] == b'.')) =>
            {
                let mut e = k;
                while e < text.len() && (text[e].is_ascii_alphanumeric() || text[e] == b'_') {
                    e += 1;
                }
                if depth == 0 && !is_value(text, k) && needs_interpreter(text, k, e, first, plain) {
                    return true;
                }
                // (The block number does not count: `N20 LABEL:`, `N30 NAME`.)
                let block_number = matches!(text[k], b'N' | b'n')
                    && e > k + 1
                    && text[k + 1..e].iter().all(u8::is_ascii_digit);
                first &= block_number;
                k = e;
            }
            _ => k += 1,
        }
    }
    false
}

/// A call of one of `names` (a cycle that turns a contour) whose first argument is text: the
/// text (the contour's subprogram, or `START:END`) and its span in the line (start, end).
pub fn profile_call(text: &[u8], names: &[&str]) -> Option<(String, usize, usize)> {
    if names.is_empty() {
        return None;
    }
    let upper = text.to_ascii_uppercase();
    for name in names {
        let mut from = 0;
        while let Some(at) = find(&upper[from..], name.as_bytes()).map(|i| i + from) {
            from = at + name.len();
            let starts_word =
                at == 0 || !(upper[at - 1].is_ascii_alphanumeric() || upper[at - 1] == b'_');
            let comment = upper[..at].contains(&b';');
            let rest = &text[from..];
            let mut k = 0;
            while k < rest.len() && matches!(rest[k], b' ' | b'\t') {
                k += 1;
            }
            if !starts_word || comment || rest.get(k) != Some(&b'(') {
                continue;
            }
            k += 1;
            while k < rest.len() && matches!(rest[k], b' ' | b'\t') {
                k += 1;
            }
            if rest.get(k) != Some(&b'"') {
                return None;
            }
            let open = from + k + 1;
            let close = text[open..].iter().position(|&c| c == b'"')? + open;
            let value = String::from_utf8_lossy(&text[open..close])
                .trim()
                .to_ascii_uppercase();
            return Some((value, open, close));
        }
    }
    None
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// Whether the name at `k` is a value (after `=`, `,` or an operator), not a word of its own.
fn is_value(text: &[u8], k: usize) -> bool {
    let before = text[..k].iter().rev().find(|c| !matches!(c, b' ' | b'\t'));
    matches!(
        before,
        Some(b'=' | b',' | b'+' | b'-' | b'*' | b'/' | b'<' | b'>' | b'[')
    )
}

/// Whether the name at `k..e` takes the interpreter.
fn needs_interpreter(text: &[u8], k: usize, e: usize, first: bool, plain: &[&[&str]]) -> bool {
    let name = String::from_utf8_lossy(&text[k..e]).to_ascii_uppercase();
    let mut n = e;
    while n < text.len() && matches!(text[n], b' ' | b'\t') {
        n += 1;
    }
    let next = text.get(n).copied().unwrap_or(0);
    if FLOW.contains(&name.as_str()) {
        return true;
    }
    if next == b':' && text.get(n + 1) != Some(&b'=') && first && name.len() >= 2 {
        // A jump label.
        return true;
    }
    if next == b'=' && text.get(n + 1) != Some(&b'=') {
        return computed(text, n + 1);
    }
    // `L100` alone in its block: the subprogram L100 (`L100.SPF`), called by its number.
    if is_l_number(&name) && first && alone(text, e) {
        return true;
    }
    // A letter and a number: an address word.
    let second = text.get(k + 1).copied().unwrap_or(0);
    if second.is_ascii_digit() || matches!(second, b'.' | b'-' | b'+') || e == k + 1 {
        return false;
    }
    const DECLARATIONS: &[&str] = &[
        "DEF", "EXTERN", "REAL", "INT", "BOOL", "CHAR", "STRING", "AXIS", "FRAME",
    ];
    let own = name.starts_with("CYCLE") || DECLARATIONS.contains(&name.as_str());
    // A call by name: the block's only word (Sinumerik calls a subprogram in a block of its
    // own), with its arguments and a repeat count.
    !own && first && alone(text, e) && !plain.iter().any(|list| list.contains(&name.as_str()))
}

/// Whether the name at `k..e` of `text` (the block's first word after its number and label)
/// is a call by name: the block's only word, with its arguments and repeat count, and neither an
/// address word, a cycle, a declaration nor one of the dialect's own names (`plain`).
pub(super) fn is_bare_call(text: &[u8], k: usize, e: usize, plain: &[&[&str]]) -> bool {
    let name = String::from_utf8_lossy(&text[k..e]).to_ascii_uppercase();
    if FLOW.contains(&name.as_str()) {
        return false;
    }
    needs_interpreter(text, k, e, true, plain)
        && !matches!(
            text.get(e..)
                .and_then(|r| r.iter().find(|c| !matches!(c, b' ' | b'\t'))),
            Some(b':' | b'=')
        )
}

/// `L` and one to seven digits: a subprogram called by its number (`L10`).
fn is_l_number(name: &str) -> bool {
    name.len() > 1
        && name.len() <= 8
        && name.starts_with('L')
        && name[1..].bytes().all(|b| b.is_ascii_digit())
}

/// Whether only a call's arguments `( … )` and a repeat count `P…` follow `e` in the block.
fn alone(text: &[u8], mut k: usize) -> bool {
    let blanks = |k: &mut usize| {
        while *k < text.len() && matches!(text[*k], b' ' | b'\t' | b'\r') {
            *k += 1;
        }
    };
    blanks(&mut k);
    if text.get(k) == Some(&b'(') {
        let mut depth = 0usize;
        while k < text.len() {
            match text[k] {
                b'(' => depth += 1,
                b')' => {
                    depth -= 1;
                    if depth == 0 {
                        k += 1;
                        break;
                    }
                }
                _ => {}
            }
            k += 1;
        }
        blanks(&mut k);
    }
    if matches!(text.get(k), Some(b'P' | b'p')) {
        k += 1;
        while k < text.len() && !matches!(text[k], b';') {
            k += 1;
        }
    }
    blanks(&mut k);
    k >= text.len() || text[k] == b';'
}

/// Whether the value after an `=` at `k` is an expression (more than a signed number or name).
fn computed(text: &[u8], mut k: usize) -> bool {
    while k < text.len() && matches!(text[k], b' ' | b'\t') {
        k += 1;
    }
    if matches!(text.get(k), Some(b'-' | b'+')) {
        k += 1;
    }
    if text.get(k) == Some(&b'"') {
        return false;
    }
    let start = k;
    while k < text.len() && (text[k].is_ascii_alphanumeric() || matches!(text[k], b'_' | b'.')) {
        k += 1;
    }
    if k == start || text[start..k].eq_ignore_ascii_case(b"NOT") {
        return true;
    }
    // An operator may follow after blanks (the interpreter reads on after them too).
    while k < text.len() && matches!(text[k], b' ' | b'\t') {
        k += 1;
    }
    let word = |w: &[u8]| {
        text.len() >= k + w.len()
            && text[k..k + w.len()].eq_ignore_ascii_case(w)
            && !text
                .get(k + w.len())
                .is_some_and(|c| c.is_ascii_alphanumeric() || *c == b'_')
    };
    matches!(
        text.get(k),
        Some(b'+' | b'-' | b'*' | b'/' | b'(' | b'[' | b'<' | b'>' | b'=')
    ) || [&b"MOD"[..], b"DIV", b"AND", b"OR", b"XOR"]
        .iter()
        .any(|w| word(w))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flow_labels_calls_and_expressions_take_the_interpreter() {
        let plain: &[&[&str]] = &[&["DIAMON", "STOPRE", "MSG"]];
        for yes in [
            "IF R1==R2 GOTOF END2",
            "PRAV: G0 X10",
            "N20 GOTOB PRAV",
            "BAR_CENTR",
            "THREAD_PASS(1.5, 2)",
            "G33 Z=R6+R3 K=R5",
            "X=(R1) Z0",
            "WHILE R1<5",
            "N20 MARKE: G1 X28",
            "N30 BAR_CENTR P3 ; eleven passes",
            "R9=7 MOD 3",
            "R9=NOT R1==0",
            "R9=R1 - 2",
        ] {
            assert!(looks_like_macro(yes.as_bytes(), plain), "{yes}");
        }
        for no in [
            "G0 X10 Z5",
            "DIAMON",
            "R1=2.5 R2=-3",
            "X=R1 Z=-R2",
            "CYCLE97(2,,0,-30,20,20,3,3,1.227,0.05,0,0,5,1,3,1)",
            "MSG(\"IF a GOTOF b\")",
            "T=\"THREAD\" D1 ; IF in a comment",
            "SF=90",
            "DEF REAL DEPTH=1.5",
            "%_N_SHAFT_M24_MPF",
            "N30 T=\"ROUGHING_80\" D1",
            "N50 CYCLE97(LEAD,,0,-25,38.376,38.376,6,2,DEPTH,0.04,0,0,8,1,4,2)",
            "G0 X=DEPTH Z=-LEAD",
            "(Allen-Bradley 9/Series G78: M10x1.5 external)",
            "$$ M20x2.5 external thread, 6 cuts at constant cross-section",
            "G0 X10 UNKNOWN_WORD",
        ] {
            assert!(!looks_like_macro(no.as_bytes(), plain), "{no}");
        }
    }
}
