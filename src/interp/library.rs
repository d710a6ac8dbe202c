//! Programs in other files: a call to a program the running text does not hold (a Fanuc
//! `M98 P9010` or `G65 P9010` whose `O9010` is not in the file, a LinuxCNC `o<thread_pass> call`
//! without `o<thread_pass> sub`) asks a [`Library`] for it, as the control looks in its memory or
//! LinuxCNC in the directories of `SUBROUTINE_PATH`.
//!
//! The interpreter says what it wants ([`Wanted`]: a number or a name); the dialect says which
//! file names hold it ([`FileNames`], `Dialect::program_files`); the library looks for those
//! names and gives the text. The library is a trait ([`Lookup`]) so that the core never touches
//! a file system where it runs without one (the page's WebAssembly module): [`Provided`] is a map
//! of texts given by the caller, and [`Dirs`] (not on wasm32) searches directories, as
//! `--include DIR` asks.

use std::sync::Arc;

/// A program a call names.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Wanted {
    /// A program number (Fanuc's `P9010`).
    Number(u32),
    /// A program's name (LinuxCNC's `o<thread_pass>`, lower case as LinuxCNC reads it).
    Name(String),
}

impl std::fmt::Display for Wanted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Wanted::Number(n) => write!(f, "{n}"),
            Wanted::Name(s) => f.write_str(s),
        }
    }
}

/// The names of the files that may hold a wanted program, in the order they are tried in each
/// directory.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FileNames {
    pub names: Vec<String>,
    /// A name matches a file whose name differs in case only (controls' and DNC software's
    /// names: `o9010.NC` is `O9010.nc`).
    pub any_case: bool,
}

/// A program found: its file's number (1 for the first file the library gave, and the same
/// number each time the same file is given again), its name as shown to the user, its text.
pub struct Found {
    pub file: u32,
    pub name: String,
    pub text: Vec<u8>,
}

/// A program not found: every place looked at, and what was wrong with a file found there (too
/// large, unreadable), if anything.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Missing {
    pub tried: Vec<String>,
    pub problem: Option<String>,
}

/// Where called programs are looked for.
pub trait Lookup: Send + Sync {
    /// The first file of `names` there is.
    fn find(&self, names: &FileNames) -> Result<Found, Missing>;
    /// The name and text of file `file` (a number [`Lookup::find`] gave), for showing a line of it.
    fn source(&self, file: u32) -> Option<(String, Arc<[u8]>)>;
}

/// A library, shared by the runs of one command (a cheap handle).
#[derive(Clone)]
pub struct Library(pub Arc<dyn Lookup>);

impl std::fmt::Debug for Library {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Library")
    }
}

impl PartialEq for Library {
    fn eq(&self, other: &Library) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

impl Eq for Library {}

impl Library {
    pub fn new(lookup: impl Lookup + 'static) -> Library {
        Library(Arc::new(lookup))
    }
}

fn matches(file: &str, wanted: &str, any_case: bool) -> bool {
    if any_case {
        file.eq_ignore_ascii_case(wanted)
    } else {
        file == wanted
    }
}

/// Programs given as texts by name (the page, Python, tests).
#[derive(Default)]
pub struct Provided {
    files: Vec<(String, Arc<[u8]>)>,
}

impl Provided {
    pub fn new(files: impl IntoIterator<Item = (String, Vec<u8>)>) -> Provided {
        Provided {
            files: files.into_iter().map(|(n, t)| (n, t.into())).collect(),
        }
    }
}

impl Lookup for Provided {
    fn find(&self, names: &FileNames) -> Result<Found, Missing> {
        for want in &names.names {
            if let Some(i) = self
                .files
                .iter()
                .position(|(n, _)| matches(n, want, names.any_case))
            {
                let (name, text) = &self.files[i];
                return Ok(Found {
                    file: i as u32 + 1,
                    name: name.clone(),
                    text: text.to_vec(),
                });
            }
        }
        Err(Missing {
            tried: names.names.clone(),
            problem: None,
        })
    }

    fn source(&self, file: u32) -> Option<(String, Arc<[u8]>)> {
        let (n, t) = self.files.get((file as usize).checked_sub(1)?)?;
        Some((n.clone(), t.clone()))
    }
}

/// Directories searched in order, each for every candidate name in order (as LinuxCNC searches
/// the directories of `SUBROUTINE_PATH` for `name.ngc`). Each file is read once and numbered in
/// the order it was first found.
#[cfg(not(target_arch = "wasm32"))]
pub struct Dirs {
    dirs: Vec<std::path::PathBuf>,
    loaded: std::sync::Mutex<Vec<(std::path::PathBuf, Arc<[u8]>)>>,
}

#[cfg(not(target_arch = "wasm32"))]
impl Dirs {
    pub fn new(dirs: Vec<std::path::PathBuf>) -> Dirs {
        Dirs {
            dirs,
            loaded: std::sync::Mutex::new(Vec::new()),
        }
    }

    /// The file in `dir` called `name`, or (with `any_case`) whose name differs from it in case
    /// only.
    fn in_dir(dir: &std::path::Path, name: &str, any_case: bool) -> Option<std::path::PathBuf> {
        let exact = dir.join(name);
        if exact.is_file() {
            return Some(exact);
        }
        if !any_case {
            return None;
        }
        std::fs::read_dir(dir).ok()?.flatten().find_map(|e| {
            let n = e.file_name();
            let p = e.path();
            (matches(n.to_str()?, name, true) && p.is_file()).then_some(p)
        })
    }

    fn load(&self, path: std::path::PathBuf) -> Result<Found, String> {
        let shown = path.display().to_string();
        let mut loaded = self
            .loaded
            .lock()
            .map_err(|_| "the library failed".to_string())?;
        if let Some(i) = loaded.iter().position(|(p, _)| *p == path) {
            return Ok(Found {
                file: i as u32 + 1,
                name: shown,
                text: loaded[i].1.to_vec(),
            });
        }
        let size = std::fs::metadata(&path)
            .map_err(|e| format!("{shown}: {e}"))?
            .len();
        if size > super::MAX_PROGRAM_BYTES as u64 {
            return Err(format!(
                "{shown} is longer than {} MiB, the largest program threadcut holds",
                super::MAX_PROGRAM_BYTES >> 20
            ));
        }
        let text = std::fs::read(&path).map_err(|e| format!("{shown}: {e}"))?;
        loaded.push((path, text.clone().into()));
        Ok(Found {
            file: loaded.len() as u32,
            name: shown,
            text,
        })
    }
}

#[cfg(not(target_arch = "wasm32"))]
impl Lookup for Dirs {
    fn find(&self, names: &FileNames) -> Result<Found, Missing> {
        let mut tried = Vec::new();
        for dir in &self.dirs {
            for name in &names.names {
                tried.push(dir.join(name).display().to_string());
                if let Some(path) = Dirs::in_dir(dir, name, names.any_case) {
                    return self.load(path).map_err(|problem| Missing {
                        tried,
                        problem: Some(problem),
                    });
                }
            }
        }
        Err(Missing {
            tried,
            problem: None,
        })
    }

    fn source(&self, file: u32) -> Option<(String, Arc<[u8]>)> {
        let loaded = self.loaded.lock().ok()?;
        let (p, t) = loaded.get((file as usize).checked_sub(1)?)?;
        Some((p.display().to_string(), t.clone()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn provided_names_in_order_and_case() {
        let lib = Provided::new([
            ("o9010.NC".to_string(), b"O9010\nM99\n".to_vec()),
            ("thread.ngc".to_string(), b"o<thread> sub\n".to_vec()),
        ]);
        let fanuc = FileNames {
            names: vec!["O9010".into(), "O9010.nc".into()],
            any_case: true,
        };
        let f = lib.find(&fanuc).ok().unwrap();
        assert_eq!((f.file, f.name.as_str()), (1, "o9010.NC"));
        let exact = FileNames {
            names: vec!["THREAD.ngc".into()],
            any_case: false,
        };
        let m = lib.find(&exact).err().unwrap();
        assert_eq!(m.tried, vec!["THREAD.ngc".to_string()]);
        assert_eq!(lib.source(2).unwrap().0, "thread.ngc");
    }
}
