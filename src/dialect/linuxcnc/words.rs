//! LinuxCNC's rules for the words of one block, as its interpreter (rs274ngc, LinuxCNC 2.10) reads
//! a line: `read_items` (each letter once, `N` only first, one G and one M code per modal group,
//! H and L integers), `enhance_block` (which motion the block's axis words belong to) and
//! `check_other_codes` (a word that no G or M code of the block uses is an error). The messages are
//! LinuxCNC's own; each error points at the word it is about. `docs/dialects/linuxcnc-g76.md`
//! ("Reading rules") lists the rules and the places where threadcut differs.

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::gcode::reader::g_code;
use crate::gcode::{Line, Word};

/// G codes ×10, by name, for the rules below.
mod g {
    pub const G2: u16 = 20;
    pub const G3: u16 = 30;
    pub const G4: u16 = 40;
    pub const G5: u16 = 50;
    pub const G5_1: u16 = 51;
    pub const G5_2: u16 = 52;
    pub const G6: u16 = 60;
    pub const G6_1: u16 = 61;
    pub const G6_2: u16 = 62;
    pub const G10: u16 = 100;
    pub const G28: u16 = 280;
    pub const G30: u16 = 300;
    pub const G33: u16 = 330;
    pub const G33_1: u16 = 331;
    pub const G41: u16 = 410;
    pub const G41_1: u16 = 411;
    pub const G42: u16 = 420;
    pub const G42_1: u16 = 421;
    pub const G43: u16 = 430;
    pub const G43_2: u16 = 432;
    pub const G52: u16 = 520;
    pub const G64: u16 = 640;
    pub const G70: u16 = 700;
    pub const G71: u16 = 710;
    pub const G71_1: u16 = 711;
    pub const G71_2: u16 = 712;
    pub const G72: u16 = 720;
    pub const G72_1: u16 = 721;
    pub const G72_2: u16 = 722;
    pub const G73: u16 = 730;
    pub const G74: u16 = 740;
    pub const G76: u16 = 760;
    pub const G80: u16 = 800;
    pub const G81: u16 = 810;
    pub const G82: u16 = 820;
    pub const G83: u16 = 830;
    pub const G84: u16 = 840;
    pub const G86: u16 = 860;
    pub const G87: u16 = 870;
    pub const G88: u16 = 880;
    pub const G89: u16 = 890;
    pub const G92: u16 = 920;
    pub const G95: u16 = 950;
    pub const G96: u16 = 960;
    pub const G97: u16 = 970;
}

use g::*;

/// LinuxCNC's modal groups of G codes (its numbering): 0 non-modal, 1 motion, 2 plane, 3 distance,
/// 4 arc distance, 5 feed mode, 6 units, 7 cutter compensation, 8 tool length offset, 10 canned
/// return, 12 coordinate system, 13 path control, 14 spindle speed mode, 15 lathe diameter mode,
/// 16 G92 offsets applied.
fn g_group(code: u16) -> Option<usize> {
    Some(match code {
        40 | 53 | 63 | 100 | 280 | 281 | 300 | 301 | 520 | 530 | 920 => 0,
        0
        | 10
        | 20
        | 30
        | 50
        | 51
        | 52
        | 60
        | 61
        | 62
        | 330
        | 331
        | 382..=385
        | 700
        | 710
        | 711
        | 712
        | 720
        | 721
        | 722
        | 730
        | 740
        | 760
        | 800
        | 810
        | 820
        | 830
        | 840
        | 850
        | 860
        | 870
        | 880
        | 890 => 1,
        170 | 171 | 180 | 181 | 190 | 191 => 2,
        900 | 910 => 3,
        901 | 911 => 4,
        930 | 940 | 950 => 5,
        200 | 210 => 6,
        400 | 410 | 411 | 420 | 421 => 7,
        430 | 431 | 432 | 490 => 8,
        980 | 990 => 10,
        540 | 550 | 560 | 570 | 580 | 590 | 591 | 592 | 593 => 12,
        610 | 611 | 640 => 13,
        960 | 970 => 14,
        70 | 80 => 15,
        921..=923 => 16,
        _ => return None,
    })
}

/// LinuxCNC's modal groups of M codes: 4 stopping, 5 input/output, 6 tool change, 7 spindle,
/// 8 coolant, 9 override switches, 10 user-defined (M100–M199).
fn m_group(code: u16) -> Option<usize> {
    Some(match code {
        0 | 1 | 2 | 30 | 60 | 99 => 4,
        62..=68 => 5,
        6 | 61 => 6,
        3 | 4 | 5 | 19 | 70..=73 => 7,
        7..=9 => 8,
        48..=53 => 9,
        100..=199 => 10,
        _ => return None,
    })
}

/// What a block holds, sorted as LinuxCNC sorts it.
pub(super) struct Block<'l> {
    /// The G code of each modal group, with its word.
    g: [Option<(u16, &'l Word)>; 17],
    /// The M code of each modal group.
    m: [Option<u16>; 11],
    /// The first word of each letter (`A`–`Z` at 1–26, `$` at 0).
    first: [Option<&'l Word>; 32],
    /// An `M98` (LinuxCNC's Fanuc-style subprogram call, which takes P and L).
    m98: bool,
}

impl<'l> Block<'l> {
    fn word(&self, letter: u8) -> Option<&'l Word> {
        self.first[slot(letter)]
    }

    fn has(&self, letter: u8) -> bool {
        self.word(letter).is_some()
    }

    fn g(&self, group: usize) -> Option<u16> {
        self.g[group].map(|(c, _)| c)
    }

    fn m(&self, group: usize) -> Option<u16> {
        self.m[group]
    }

    /// The block's motion code (group 1), if it has one.
    pub(super) fn motion(&self) -> Option<u16> {
        self.g(1)
    }

    /// The first axis word (X Y Z A B C U V W).
    fn first_axis(&self) -> Option<&'l Word> {
        b"XYZABCUVW"
            .iter()
            .filter_map(|&l| self.word(l))
            .min_by_key(|w| w.span.start)
    }
}

fn slot(letter: u8) -> usize {
    if letter == b'$' {
        0
    } else {
        usize::from(letter & 31)
    }
}

fn error(span: Span, code: Code, message: impl Into<String>) -> Diagnostic {
    Diagnostic::error(code, span, message)
}

/// LinuxCNC's `read_integer_value`: a value within 0.0001 of an integer is that integer.
pub(super) fn integer(w: &Word) -> Result<i64> {
    let v = w.value;
    let floor = v.floor();
    if v - floor > 0.9999 {
        Ok(floor as i64 + 1)
    } else if v - floor > 0.0001 {
        Err(error(w.span, Code::Syntax, "Non integer value for integer"))
    } else {
        Ok(floor as i64)
    }
}

/// LinuxCNC's "Multiple … words on one line", in its words: the letter in lower case, but U, V
/// and W in upper case and `$` named.
fn multiple(letter: u8) -> String {
    match letter {
        b'$' => "Multiple spindle choice ($) words on one line".to_string(),
        b'U' | b'V' | b'W' => format!("Multiple {} words on one line", letter as char),
        _ => format!(
            "Multiple {} words on one line",
            letter.to_ascii_lowercase() as char
        ),
    }
}

/// `read_items`: the words in the order written. The first error in the line wins.
pub(super) fn read<'l>(line: &Line<'l>) -> Result<Block<'l>> {
    let mut block = Block {
        g: [None; 17],
        m: [None; 11],
        first: [None; 32],
        m98: false,
    };
    let mut m_count = 0;
    for (k, w) in line.words.iter().enumerate() {
        match w.letter {
            // A line number is read only at the start of a line.
            b'N' if k > 0 => {
                return Err(error(w.span, Code::Syntax, "Bad character 'n' used")
                    .with_hint("LinuxCNC reads N only as the first word of a line"))
            }
            b'G' => {
                // A code LinuxCNC does not have is its "Unknown g code used" where it is written
                // (the first error in the line wins); the modal groups are LinuxCNC's list of
                // codes, and the vocabulary the alarm and its hint (a test keeps the two alike).
                // A value that is no code at all is the modal reader's error.
                let group = match g_code(w.value) {
                    Some(c) => match g_group(c) {
                        Some(g) => Some((c, g)),
                        None => return Err(super::VOCABULARY.unknown(w, c, line)),
                    },
                    None => None,
                };
                if let Some((code, group)) = group {
                    if block.g[group].is_some() {
                        return Err(error(
                            w.span,
                            Code::Conflict,
                            "Two g codes used from same modal group",
                        ));
                    }
                    block.g[group] = Some((code, w));
                }
            }
            b'M' => {
                block.m98 |= g_code(w.value) == Some(980);
                let group = g_code(w.value)
                    .filter(|c| c % 10 == 0)
                    .and_then(|c| m_group(c / 10).map(|g| (c / 10, g)));
                if let Some((code, group)) = group {
                    if block.m[group].is_some() {
                        return Err(error(
                            w.span,
                            Code::Conflict,
                            "Two m codes used from same modal group",
                        ));
                    }
                    block.m[group] = Some(code);
                    m_count += 1;
                }
            }
            letter => {
                if block.word(letter).is_some() {
                    return Err(error(w.span, Code::Conflict, multiple(letter))
                        .with_hint("LinuxCNC allows each letter once on a line (G and M codes of different modal groups excepted)"));
                }
                block.first[slot(letter)] = Some(w);
                if letter == b'H' && integer(w)? < -1 {
                    return Err(error(w.span, Code::OutOfRange, "Negative h word used"));
                }
                if letter == b'L' && integer(w)? < 0 {
                    return Err(error(w.span, Code::OutOfRange, "Negative l word used"));
                }
            }
        }
    }
    if m_count > 4 {
        return Err(error(
            line.span(),
            Code::Conflict,
            "Too many m codes on line",
        ));
    }
    Ok(block)
}

/// `enhance_block`: the motion the block's axis words belong to (`motion_to_be`), given the motion
/// mode in force (`None` after G80 and at the start of a program).
pub(super) fn motion_to_be(block: &Block, modal: Option<u16>) -> Result<Option<u16>> {
    let axis = block.first_axis();
    let mode0 = block.g[0];
    let covets_axes = mode0.is_some_and(|(c, _)| matches!(c, G10 | G28 | G30 | G52 | G92));
    let needs_axes = mode0.filter(|(c, _)| matches!(*c, G52 | G92));
    match block.g[1] {
        Some((G80, g80)) => {
            if let (Some(a), false) = (axis, covets_axes) {
                return Err(error(a.span, Code::Conflict, "Cannot use axis values with g80")
                    .with_hint(format!("G80 at column {} cancels the motion mode", g80.span.column)));
            }
            if let (None, Some((_, w))) = (axis, needs_axes) {
                return Err(error(w.span, Code::MissingWord, "All axes missing with g52 or g92"));
            }
            Ok(None)
        }
        Some((code, w)) => {
            if let Some((_, other)) = mode0.filter(|_| covets_axes) {
                let later = if other.span.start > w.span.start { other } else { w };
                return Err(error(
                    later.span,
                    Code::Conflict,
                    "Cannot use two g codes that both use axis values",
                ));
            }
            let may_lack_axes = matches!(
                code,
                0 | 10 | G2 | G3 | G5_2 | G6_2 | G70 | G71 | G71_1 | G71_2 | G72 | G72_1 | G72_2
            );
            if axis.is_none() && !may_lack_axes {
                return Err(error(w.span, Code::MissingWord, "All axes missing with motion code"));
            }
            Ok(Some(code))
        }
        None if covets_axes => {
            if let (None, Some((_, w))) = (axis, needs_axes) {
                return Err(error(w.span, Code::MissingWord, "All axes missing with g52 or g92"));
            }
            Ok(None)
        }
        None => match (axis, modal) {
            (Some(a), None) => Err(error(
                a.span,
                Code::Conflict,
                "Cannot use axis values without a g code that uses them",
            )
            .with_hint("name the motion (G0, G1, …) on this line or an earlier one; G80 and the start of a program set none")),
            (Some(_), Some(m)) => Ok(Some(m)),
            // `I1` alone goes on an arc in G2/G3 mode.
            (None, Some(m @ (G2 | G3)))
                if block.has(b'I') || block.has(b'J') || block.has(b'K') =>
            {
                Ok(Some(m))
            }
            (None, _) => Ok(None),
        },
    }
}

/// One of `check_other_codes`' rules: a letter, LinuxCNC's message when no code of the block uses
/// it, and whether one does.
struct Use {
    letter: u8,
    message: &'static str,
    used: fn(&Block, Option<u16>) -> bool,
}

/// In LinuxCNC's order. Motion codes are the block's `motion_to_be`; the others must be on the
/// block itself.
const USES: &[Use] = &[
    Use {
        letter: b'D',
        message: "D word with no G41, G41.1, G42, G42.1, G71, G71.1, G71.2 G73, G83 or G96 to use it",
        used: |b, m| {
            matches!(b.g(7), Some(G41 | G41_1 | G42 | G42_1))
                || matches!(m, Some(G70 | G71 | G71_1 | G71_2 | G72 | G72_1 | G72_2 | G73 | G83))
                || b.g(14) == Some(G96)
        },
    },
    Use {
        letter: b'$',
        message: "$ (spindle selection) word with no M3, M4, M5, M19, M51, G33, G33.1, G76, G95, G96 or G97 to use it",
        used: |b, m| {
            matches!(m, Some(G76 | G33 | G33_1))
                || b.g(5) == Some(G95)
                || matches!(b.g(14), Some(G96 | G97))
                || matches!(b.m(7), Some(3 | 4 | 5 | 19))
                || b.m(9) == Some(51)
                || b.has(b'S')
        },
    },
    Use {
        letter: b'E',
        message: "E word with no G70, G76, M66, M67 or M68 to use it",
        used: |b, m| {
            matches!(m, Some(G76 | G33 | G33_1 | G70)) || matches!(b.m(5), Some(66..=68))
        },
    },
    Use {
        letter: b'H',
        message: "H word with no G43 or G76 to use it",
        used: |b, m| matches!(b.g(8), Some(G43 | G43_2)) || m == Some(G76),
    },
    Use {
        letter: b'I',
        message: "I word with no G2, G3, G5, G5.1, G6, G6.1, G10, G33.1, G76, or G87 to use it",
        used: |b, m| {
            matches!(
                m,
                Some(G2 | G3 | G5 | G5_1 | G6 | G6_1 | G71 | G71_1 | G71_2 | G72 | G72_1 | G72_2 | G76 | G87 | G33_1)
            ) || b.g(0) == Some(G10)
        },
    },
    Use {
        letter: b'J',
        message: "J word with no G2, G3, G5, G5.1, G6, G6.1, G10, G76 or G87 to use it",
        used: |b, m| {
            matches!(m, Some(G2 | G3 | G5 | G5_1 | G6 | G6_1 | G76 | G87)) || b.g(0) == Some(G10)
        },
    },
    Use {
        letter: b'K',
        message: "K word with no G2, G3, G6.2, G33, G33.1, G76, or G87 to use it",
        used: |_, m| matches!(m, Some(G2 | G3 | G6_2 | G33 | G33_1 | G76 | G87)),
    },
    Use {
        letter: b'L',
        message: "L word with no G10, cutter compensation, canned cycle, digital/analog input, M98 or NURBS code",
        used: |b, m| {
            matches!(m, Some(G81..=G89 | G76 | G5_2 | G6_2 | G73))
                || b.g(0) == Some(G10)
                || matches!(b.g(7), Some(G41 | G41_1 | G42 | G42_1))
                || b.m(5) == Some(66)
                || b.has_m98()
        },
    },
    Use {
        letter: b'P',
        message: "P word with no G2 G3 G4 G10 G64 G5 G5.2 G6, G6.2, G76 G82 G86 G88 G89 or M50 M51 M52 M53 M62 M63 M64 M65 M66 M98 or user M code to use it",
        used: |b, m| {
            matches!(b.g(0), Some(G10 | G4))
                || b.g(13) == Some(G64)
                || matches!(
                    m,
                    Some(G76 | G82 | G86 | G88 | G89 | G5 | G5_2 | G70 | G6 | G6_2 | G2 | G3 | G74 | G84)
                )
                || matches!(b.m(9), Some(50..=53))
                || matches!(b.m(5), Some(62..=66))
                || b.m(7) == Some(19)
                || b.m(10).is_some()
                || b.has_m98()
        },
    },
    Use {
        letter: b'Q',
        message: "Q word with no G5, G6, G10, G64, G73, G76, G83, M19, M66, M67, M68 or user M code that uses it",
        used: |b, m| {
            matches!(
                m,
                Some(G83 | G73 | G5 | G6 | G6_2 | G76 | G70 | G71 | G71_1 | G71_2 | G72 | G72_1 | G72_2)
            ) || b.m(10).is_some()
                || matches!(b.m(5), Some(66..=68))
                || b.g(0) == Some(G10)
                || b.m(6) == Some(61)
                || b.g(13) == Some(G64)
                || b.m(7) == Some(19)
        },
    },
    Use {
        letter: b'R',
        message: "R word with no g code that uses it",
        used: |b, m| {
            matches!(
                m,
                Some(G2 | G3 | G76 | G6_2 | G71 | G71_1 | G71_2 | G72 | G72_1 | G72_2 | G81..=G89 | G73 | G74)
            ) || matches!(b.g(7), Some(G41_1 | G42_1))
                || b.g(0) == Some(G10)
                || b.m(7) == Some(19)
                || b.g(13) == Some(G64)
        },
    },
];

impl Block<'_> {
    /// LinuxCNC's Fanuc-style subprogram call (`M98`), which takes P and L.
    fn has_m98(&self) -> bool {
        self.m98
    }

    /// The block ends the program (M2, M30): LinuxCNC's motion mode is G1 afterwards.
    pub(super) fn ends_program(&self) -> bool {
        matches!(self.m(4), Some(2 | 30))
    }

    /// The span of the block's motion code.
    pub(super) fn motion_span(&self) -> Option<Span> {
        self.g[1].map(|(_, w)| w.span)
    }
}

/// `check_other_codes`: a word that no code of the block uses, then the words G33 and G76 need.
/// `motion` is the block's [`motion_to_be`].
pub(super) fn check_other_codes(block: &Block, line: &Line, motion: Option<u16>) -> Result<()> {
    for rule in USES {
        if let Some(w) = block.word(rule.letter) {
            if !(rule.used)(block, motion) {
                return Err(error(w.span, Code::Unsupported, rule.message)
                    .with_hint(format!(
                        "LinuxCNC refuses a word that no G or M code of its line uses: remove {}, or add the code that uses it",
                        w.letter as char
                    )));
            }
        }
    }
    if block.g(14) == Some(G96) && !block.has(b'S') {
        let g96 = block.g[14].map_or(line.span(), |(_, w)| w.span);
        return Err(error(g96, Code::MissingWord, "S word missing with G96"));
    }
    if let Some(m @ (G33 | G33_1)) = motion {
        let at = block.g[1].map_or(line.span(), |(_, w)| w.span);
        if !block.has(b'K') {
            return Err(
                error(at, Code::MissingWord, "K word missing with g33/g33.1").with_hint(
                    if m == G33 {
                        "K is the distance per revolution along the path"
                    } else {
                        "K is the thread pitch"
                    },
                ),
            );
        }
        if let Some(f) = block.word(b'F') {
            return Err(error(
                f.span,
                Code::Conflict,
                "F word used with a g33/g33.1",
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The modal groups are LinuxCNC's list of G codes; the vocabulary (the alarm, the hint of
    /// other controllers' alarms) must know every one of them, and name no whole code that no
    /// group has in some form (`G38` stands for `G38.2`–`G38.5`).
    #[test]
    fn the_modal_groups_and_the_vocabulary_name_the_same_codes() {
        for code in 0..10_000u16 {
            if g_group(code).is_some() {
                assert!(
                    super::super::VOCABULARY.get(code).is_some(),
                    "G{} has a modal group but is not in the vocabulary",
                    f64::from(code) / 10.0
                );
            }
        }
        for entry in super::super::VOCABULARY.g_codes {
            let whole = entry.code / 10 * 10;
            assert!(
                (whole..whole + 10).any(|c| g_group(c).is_some()),
                "G{} is in the vocabulary but in no modal group",
                entry.code / 10
            );
        }
    }
}
