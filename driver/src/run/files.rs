//! The files a run names besides the program: read within their bounds, parsed, each error a
//! `Failure` with its exit code (a dialect profile, the parameters, the offsets, the probe points).

use std::path::Path;

use crate::exit::{Exit, Failure};
use crate::input::{ReadError, read_bounded};

/// The output dialect: a profile file (`--dialect-file FILE` over its base; the flag that named it
/// beside it), or the built-in `--dialect NAME`.
pub fn load_dialect(
    name: Option<&str>,
    file: Option<(&str, &Path)>,
    max: u64,
) -> Result<crate::dialects::Profile, Failure> {
    match file {
        Some((flag, path)) => {
            let bytes = read_file(flag, path, max)?;
            let Ok(text) = String::from_utf8(bytes) else {
                return Err(Failure::new(
                    Exit::MALFORMED_INPUT,
                    format!("{}: a dialect profile is UTF-8 text", path.display()),
                ));
            };
            crate::dialects::load(&path.display().to_string(), &text)
                .map_err(|e| Failure::new(Exit::MALFORMED_INPUT, e))
        }
        None => crate::dialects::builtin(name.unwrap_or("fanuc"))
            .map_err(|e| Failure::new(Exit::Usage, e)),
    }
}

/// The flags that name a settings file: a regular file of at most `MAX_SETTINGS`.
pub(super) const SETTINGS_FLAGS: [&str; 7] = [
    "--dialect-file",
    "--params",
    "--offsets",
    "--probe-points",
    "dialects --show",
    "dialects --cycles",
    "dialects --launcher",
];

/// Reads an input file of `flag` within the bound; the error says why, with its exit code. A
/// settings file is a regular file of at most `MAX_SETTINGS` bytes.
pub(super) fn read_file(flag: &str, path: &Path, max: u64) -> Result<Vec<u8>, Failure> {
    let settings = SETTINGS_FLAGS.contains(&flag);
    let read = if settings {
        crate::input::read_regular(path, max.min(crate::input::MAX_SETTINGS))
    } else {
        read_bounded(path, max)
    };
    read.map_err(|e| {
        let flag = if flag.is_empty() {
            String::new()
        } else {
            format!("{flag} ")
        };
        let what = match &e {
            ReadError::TooBig(_) if settings => format!(
                "it is larger than {}, the most a settings file may hold",
                crate::input::human(crate::input::MAX_SETTINGS)
            ),
            e => e.to_string(),
        };
        let exit = match e {
            ReadError::TooBig(_) => Exit::Limit,
            ReadError::Io(_) => Exit::Io,
        };
        Failure::new(
            exit,
            format!("cannot read {flag}{}: {what}", path.display()),
        )
    })
}

/// An input file a flag names, read (bounded) and parsed by `parse(name, text)`: a file that cannot
/// be read is `read_file`'s error, one that does not parse fails with `Exit::MALFORMED_INPUT`, the
/// code of every malformed input file.
pub(super) fn parse_input<T>(
    flag: &str,
    path: &Path,
    max: u64,
    parse: impl FnOnce(&str, &str) -> Result<T, String>,
) -> Result<T, Failure> {
    let bytes = read_file(flag, path, max)?;
    parse(
        &path.display().to_string(),
        &String::from_utf8_lossy(&bytes),
    )
    .map_err(|e| Failure::new(Exit::MALFORMED_INPUT, e))
}

/// Touch points: one `X… Y… Z…` line each (missing axes are 0); `(…)` comments and blank lines skipped.
pub fn parse_points(name: &str, text: &str) -> Result<Vec<[f64; 3]>, String> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let mut line = String::new();
        let mut depth = 0;
        for c in raw.chars() {
            match c {
                '(' => depth += 1,
                ')' => depth = 0.max(depth - 1),
                _ if depth == 0 => line.push(c.to_ascii_uppercase()),
                _ => {}
            }
        }
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let mut p = [0.0; 3];
        for word in line.split_whitespace() {
            let axis_len = word.chars().next().map_or(0, char::len_utf8);
            let (axis, value) = word.split_at(axis_len);
            let k = match axis {
                "X" => 0,
                "Y" => 1,
                "Z" => 2,
                _ => return Err(format!("{name}:{}: expected X Y Z words: `{raw}`", i + 1)),
            };
            p[k] = value
                .parse()
                .map_err(|_| format!("{name}:{}: `{word}` is not a number", i + 1))?;
        }
        out.push(p);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file a request names that cannot be read, or a dialect that does not exist, is a
    /// `Failure` carrying its exit code and message: nothing is printed (a front end renders it).
    #[test]
    fn what_cannot_be_loaded_is_a_typed_failure() {
        let missing = Path::new("/nonexistent-fmsvm/d.toml");
        let f = load_dialect(None, Some(("--dialect-file", missing)), 1 << 20).err();
        let f = f.unwrap_or_else(|| Failure::new(Exit::Success, ""));
        assert_eq!(f.exit, Exit::Io);
        assert!(
            f.message
                .starts_with("cannot read --dialect-file /nonexistent-fmsvm/d.toml: "),
            "{}",
            f.message
        );
        let f = load_dialect(Some("no-such-control"), None, 1 << 20).err();
        let f = f.unwrap_or_else(|| Failure::new(Exit::Success, ""));
        assert_eq!(f.exit, Exit::Usage);
        assert!(f.message.contains("no-such-control"), "{}", f.message);
        let f = super::super::load_params(None, Some(missing), 1 << 20).err();
        assert_eq!(f.map(|f| f.exit), Some(Exit::Io));
    }
}
