//! The library search path (`--lib DIR`): finds the file that holds program `Onnnn` when the main file
//! calls it and does not hold it. A file named `O1234` (any extension) holds O1234; any other file with a
//! part-program extension holds the program of its first `O` line. Folders are indexed on first use.
//! A number two files hold (in one folder or in two) is found in neither: the run names both.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use fmsvm_compiler::Library;

use crate::input::{Charset, decode, read_regular};

/// Extensions read as part programs when the name does not say the number.
const EXTENSIONS: [&str; 8] = ["nc", "tap", "txt", "min", "cnc", "mpf", "spf", "eia"];

/// Library folders, indexed lazily.
pub struct Folders {
    dirs: Vec<PathBuf>,
    index: Option<HashMap<u32, PathBuf>>,
    /// Program numbers more than one file holds: fmsvm does not choose between them.
    twins: HashMap<u32, Vec<PathBuf>>,
    charset: Option<Charset>,
    max_input: u64,
    /// Files that could not be read while indexing (reported, not fatal).
    pub skipped: Vec<String>,
    /// Warnings about files read (a guessed character set).
    pub warnings: Vec<String>,
}

impl Folders {
    /// The folders in search order; files are read in `charset` (None: UTF-8 or a guess), at most
    /// `max_input` bytes each.
    pub fn new(dirs: Vec<PathBuf>, charset: Option<Charset>, max_input: u64) -> Self {
        Folders {
            dirs,
            index: None,
            twins: HashMap::new(),
            charset,
            max_input,
            skipped: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// Checks that every folder can be listed (before anything runs).
    pub fn check(dirs: &[PathBuf]) -> Result<(), String> {
        for dir in dirs {
            if let Err(e) = std::fs::read_dir(dir) {
                return Err(format!("--lib {}: {e}", dir.display()));
            }
        }
        Ok(())
    }

    /// Every file in the folders (for the check that no output overwrites one).
    pub fn files(dirs: &[PathBuf]) -> Vec<PathBuf> {
        dirs.iter()
            .filter_map(|d| std::fs::read_dir(d).ok())
            .flat_map(|entries| entries.filter_map(|e| e.ok().map(|e| e.path())))
            .filter(|p| p.is_file())
            .collect()
    }

    fn build(&mut self) -> HashMap<u32, PathBuf> {
        let mut index = HashMap::new();
        for dir in &self.dirs {
            let Ok(entries) = std::fs::read_dir(dir) else {
                self.skipped
                    .push(format!("{}: not a readable folder", dir.display()));
                continue;
            };
            let mut files: Vec<PathBuf> =
                entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
            files.sort();
            for path in files {
                if let Some(n) = number_of(&path) {
                    match index.get(&n) {
                        Some(first) => {
                            let first: &PathBuf = first;
                            self.twins
                                .entry(n)
                                .or_insert_with(|| vec![first.clone()])
                                .push(path);
                        }
                        None => {
                            index.insert(n, path);
                        }
                    }
                }
            }
        }
        index
    }
}

/// The program number a file holds, from its name (`O1234.nc`) or its first `O` line.
fn number_of(path: &Path) -> Option<u32> {
    let stem = path.file_stem()?.to_string_lossy().to_ascii_uppercase();
    if let Some(digits) = stem.strip_prefix('O')
        && !digits.is_empty()
        && digits.bytes().all(|b| b.is_ascii_digit())
    {
        return digits.parse().ok();
    }
    let ext = path.extension()?.to_string_lossy().to_ascii_lowercase();
    if !EXTENSIONS.contains(&ext.as_str()) || !path.is_file() {
        return None;
    }
    let mut head = Vec::new();
    std::io::Read::read_to_end(
        &mut std::io::Read::take(std::fs::File::open(path).ok()?, 4096),
        &mut head,
    )
    .ok()?;
    let text = String::from_utf8_lossy(&head).into_owned();
    for line in text.lines() {
        let t = line.trim();
        if t.is_empty() || t.starts_with('%') || t.starts_with('(') {
            continue;
        }
        let rest = t.strip_prefix(['O', 'o', ':'])?;
        let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
        let after = rest[digits.len()..].trim_start();
        if digits.is_empty() || !(after.is_empty() || after.starts_with('(')) {
            return None;
        }
        return digits.parse().ok();
    }
    None
}

impl Library for Folders {
    fn find(&mut self, number: u32) -> Option<(String, String)> {
        if self.index.is_none() {
            self.index = Some(self.build());
        }
        if let Some(files) = self.twins.get(&number) {
            // Two files hold the program: the one a control has is not known, so none is taken.
            self.skipped.push(format!(
                "O{number:04} is held by {}: remove or rename all but one (fmsvm does not choose)",
                files
                    .iter()
                    .map(|f| f.display().to_string())
                    .collect::<Vec<_>>()
                    .join(" and ")
            ));
            return None;
        }
        let path = self.index.as_ref()?.get(&number)?.clone();
        let name = path.display().to_string();
        match read_regular(&path, self.max_input) {
            Ok(bytes) => match decode(bytes, self.charset) {
                Ok(d) => {
                    if let Some(w) = d.guessed {
                        self.warnings.push(format!("{name}: {w}"));
                    }
                    Some((name, d.text))
                }
                Err(e) => {
                    self.skipped
                        .push(format!("{name}:{}:{}: {}", e.line, e.column, e.message));
                    None
                }
            },
            Err(e) => {
                self.skipped.push(format!("{name}: {e}"));
                None
            }
        }
    }
}
