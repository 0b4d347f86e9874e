//! The library search path (`--lib DIR`): finds the file that holds program `Onnnn` when the main file
//! calls it and does not hold it. A file named `O1234` (any extension) holds O1234; any other file with a
//! part-program extension holds the program of its first `O` line. Folders are indexed on first use.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use fmsvm_compiler::Library;

/// Extensions read as part programs when the name does not say the number.
const EXTENSIONS: [&str; 8] = ["nc", "tap", "txt", "min", "cnc", "mpf", "spf", "eia"];

/// Library folders, indexed lazily.
pub struct Folders {
    dirs: Vec<PathBuf>,
    index: Option<HashMap<u32, PathBuf>>,
    /// Files that could not be read while indexing (reported, not fatal).
    pub skipped: Vec<String>,
}

impl Folders {
    /// The folders in search order.
    pub fn new(dirs: Vec<PathBuf>) -> Self {
        Folders {
            dirs,
            index: None,
            skipped: Vec::new(),
        }
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
                    index.entry(n).or_insert(path);
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
    let text = std::fs::read(path).ok()?;
    let text = String::from_utf8_lossy(&text[..text.len().min(4096)]).into_owned();
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
        let path = self.index.as_ref()?.get(&number)?.clone();
        match std::fs::read(&path) {
            Ok(bytes) => match String::from_utf8(bytes) {
                Ok(text) => Some((path.display().to_string(), text)),
                Err(_) => {
                    self.skipped
                        .push(format!("{}: not a text file", path.display()));
                    None
                }
            },
            Err(e) => {
                self.skipped.push(format!("{}: {e}", path.display()));
                None
            }
        }
    }
}
