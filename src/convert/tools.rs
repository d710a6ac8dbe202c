//! Named tools and the numbers that call them: the command's `--tool NAME=T0101` entries over the
//! target profile's `[tools]` table. A program that calls a tool by its name (Sinumerik's
//! `T="THREAD_EXT_60"`) is converted for a controller that numbers tools through this table, and a
//! numbered tool is called by its name on a target that names tools when the table names it.
//!
//! A number is written `T` and digits, as the Fanuc family writes a tool call: with three digits
//! or more the last two are the offset number and the rest the tool (`T0101`: tool 1, offset 1;
//! `T1203`: tool 12, offset 3); with one or two digits it is the tool with its own offset (`T4`:
//! tool 4, offset 4, as the OmniTurn and LinuxCNC apply a tool's own offset). A named tool's
//! first cutting edge (`D1`) is the offset the number gives; `D0` is no offset
//! (docs/translation.md, "Tools by name").

use std::collections::BTreeMap;

/// One named tool: the tool number and the offset its first cutting edge (D1) applies.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Named {
    pub name: String,
    pub tool: u32,
    pub offset: u32,
}

/// Every named tool of a conversion.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ToolMap {
    entries: Vec<Named>,
}

/// The longest tool call read: eight digits (a tool number up to 999999 and its offset).
const MAX_DIGITS: usize = 8;

impl ToolMap {
    /// The command's entries (`(name, number)`, in order) over the profile's table: an entry of
    /// the command replaces the profile's of the same name. An error names the entry that is not
    /// a name and a number, a name given twice on the command, or a tool number given two names.
    pub fn new(
        command: &[(String, String)],
        profile: &BTreeMap<String, String>,
    ) -> Result<ToolMap, String> {
        let mut entries: Vec<Named> = Vec::new();
        for (i, (name, number)) in command.iter().enumerate() {
            if command[..i].iter().any(|(n, _)| n == name) {
                return Err(format!("--tool {name}=…: the tool {name} is given twice"));
            }
            entries.push(entry(name, number).map_err(|e| format!("--tool {name}={number}: {e}"))?);
        }
        for (name, number) in profile {
            if entries.iter().any(|e| &e.name == name) {
                continue;
            }
            entries.push(
                entry(name, number)
                    .map_err(|e| format!("the profile's [tools] {name} = \"{number}\": {e}"))?,
            );
        }
        for (i, e) in entries.iter().enumerate() {
            if let Some(other) = entries[..i].iter().find(|o| o.tool == e.tool) {
                return Err(format!(
                    "tool {} is named both {} and {}: one name per tool number",
                    e.tool, other.name, e.name
                ));
            }
        }
        Ok(ToolMap { entries })
    }

    /// The tool called by `name`.
    pub fn by_name(&self, name: &str) -> Option<&Named> {
        self.entries.iter().find(|e| e.name == name)
    }

    /// The name of tool number `tool`.
    pub fn by_tool(&self, tool: u32) -> Option<&Named> {
        self.entries.iter().find(|e| e.tool == tool)
    }
}

/// `NAME=T0101` (the command's `--tool`): the name and the number, split at the first `=`.
pub fn argument(spec: &str) -> Result<(String, String), String> {
    let (name, number) = spec
        .split_once('=')
        .ok_or_else(|| format!("{spec}: expected NAME=T0101 (the tool's name, its number)"))?;
    Ok((name.trim().to_string(), number.trim().to_string()))
}

fn entry(name: &str, number: &str) -> Result<Named, String> {
    if name.is_empty()
        || name
            .chars()
            .any(|c| c == '"' || c == '=' || c.is_control() || c.is_whitespace())
    {
        return Err(format!(
            "`{name}` is not a tool name (expected letters, digits and signs such as _, without quotes, blanks or =)"
        ));
    }
    let (tool, offset) = number_of(number)?;
    Ok(Named {
        name: name.to_string(),
        tool,
        offset,
    })
}

/// `T0101` → (1, 1), `T4` → (4, 4).
fn number_of(text: &str) -> Result<(u32, u32), String> {
    let digits = text
        .strip_prefix(['T', 't'])
        .filter(|d| !d.is_empty() && d.len() <= MAX_DIGITS && d.bytes().all(|b| b.is_ascii_digit()))
        .ok_or_else(|| {
            format!("`{text}`: expected T and the tool's number with its two-digit offset (T0101), or T and the tool alone (T4)")
        })?;
    let v: u32 = digits.parse().map_err(|_| format!("{text}: too long"))?;
    let (tool, offset) = if digits.len() <= 2 {
        (v, v)
    } else {
        (v / 100, v % 100)
    };
    if tool == 0 || offset == 0 {
        return Err(format!(
            "{text} calls {}: a named tool is a tool with an offset",
            if tool == 0 { "no tool" } else { "no offset" }
        ));
    }
    Ok((tool, offset))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(command: &[(&str, &str)], profile: &[(&str, &str)]) -> Result<ToolMap, String> {
        let c: Vec<(String, String)> = command
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect();
        let p: BTreeMap<String, String> = profile
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect();
        ToolMap::new(&c, &p)
    }

    #[test]
    fn numbers_read_as_the_fanuc_family_writes_a_tool_call() {
        // T0101: tool 1, offset 01; T1203: tool 12, offset 03; T4: tool 4 with its own offset.
        assert_eq!(number_of("T0101"), Ok((1, 1)));
        assert_eq!(number_of("T1203"), Ok((12, 3)));
        assert_eq!(number_of("T303"), Ok((3, 3)));
        assert_eq!(number_of("T4"), Ok((4, 4)));
        assert_eq!(number_of("T12"), Ok((12, 12)));
        assert!(number_of("T0100").unwrap_err().contains("no offset"));
        assert!(number_of("T0").unwrap_err().contains("no tool"));
        assert!(number_of("0101").is_err());
        assert!(number_of("T1.5").is_err());
        assert!(number_of("T123456789").is_err());
    }

    #[test]
    fn the_command_replaces_the_profiles_entry_and_one_name_per_number() {
        let m = map(
            &[("THREAD", "T0303")],
            &[("THREAD", "T0101"), ("GROOVE", "T0202")],
        )
        .unwrap();
        assert_eq!(
            m.by_name("THREAD").map(|n| (n.tool, n.offset)),
            Some((3, 3))
        );
        assert_eq!(m.by_tool(2).map(|n| n.name.as_str()), Some("GROOVE"));
        assert_eq!(m.by_tool(1), None);
        assert_eq!(m.by_name("thread"), None, "names compare exactly");
        let e = map(&[("A", "T0101"), ("B", "T0102")], &[]).unwrap_err();
        assert!(e.contains("tool 1 is named both A and B"), "{e}");
        let e = map(&[("A", "T0101"), ("A", "T0202")], &[]).unwrap_err();
        assert!(e.contains("given twice"), "{e}");
        let e = map(&[("A B", "T0101")], &[]).unwrap_err();
        assert!(e.contains("not a tool name"), "{e}");
        let e = map(&[], &[("A", "X1")]).unwrap_err();
        assert!(e.contains("[tools] A"), "{e}");
    }

    #[test]
    fn the_argument_splits_at_the_first_equals_sign() {
        assert_eq!(
            argument("THREAD_EXT_60=T0101"),
            Ok(("THREAD_EXT_60".into(), "T0101".into()))
        );
        assert!(argument("THREAD_EXT_60").is_err());
    }
}
