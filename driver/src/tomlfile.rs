//! What the TOML input files (`--params`, `--offsets`, `--dialect-file`) share: reading one into its
//! typed sections with serde, and locating an error as `file:line:column`, the section it is in, and
//! the line itself with a caret under what is wrong.

use std::ops::Range;

use serde::de::DeserializeOwned;
use toml::Spanned;

/// `text` (the file `name`) as a `T`, whose sections refuse unknown keys and read each value as its
/// type; the error is located as [`located`] says.
pub fn read<T: DeserializeOwned>(name: &str, text: &str) -> Result<T, String> {
    toml::from_str(text).map_err(|e| {
        let span = e.span().unwrap_or(0..0);
        let what = match section(text, span.start) {
            Some(s) => format!("[{s}] {}", e.message().trim()),
            None => e.message().trim().to_string(),
        };
        located(name, text, span, &what)
    })
}

/// `name:line:column: what`, then the line at `span` with a caret under it.
pub fn located(name: &str, text: &str, span: Range<usize>, what: &str) -> String {
    let start = span.start.min(text.len());
    let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[start..].find('\n').map_or(text.len(), |i| start + i);
    let line = text[line_start..line_end].trim_end_matches('\r');
    let column = text[line_start..start].chars().count();
    let width = text[start..span.end.clamp(start, line_end)]
        .chars()
        .count()
        .max(1);
    format!(
        "{}: {what}\n  {line}\n  {}{}",
        at(name, text, start),
        " ".repeat(column),
        "^".repeat(width)
    )
}

/// `name:line:column` of byte `offset` of `text`, to begin an error about what stands there.
pub fn at(name: &str, text: &str, offset: usize) -> String {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    format!("{name}:{line}:{column}")
}

/// `name:line:column` of `key` in `text`.
pub fn key_at(name: &str, text: &str, key: &Spanned<String>) -> String {
    at(name, text, key.span().start)
}

/// The `[table]` header in force at byte `offset` (None before the first).
fn section(text: &str, offset: usize) -> Option<&str> {
    text[..offset.min(text.len())]
        .lines()
        .rev()
        .map(str::trim)
        .find(|l| l.starts_with('[') && !l.starts_with("[["))
        .and_then(|l| l.strip_prefix('['))
        .and_then(|l| l.split(']').next())
        .map(str::trim)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_error_names_its_place_section_and_line() {
        #[derive(serde::Deserialize, Debug)]
        #[serde(deny_unknown_fields)]
        #[allow(dead_code)]
        struct F {
            a: Option<A>,
        }
        #[derive(serde::Deserialize, Debug)]
        #[serde(deny_unknown_fields)]
        #[allow(dead_code)]
        struct A {
            x: Option<u32>,
        }
        let e = read::<F>("f.toml", "# c\n[a]\nx = \"five\"\n").unwrap_err();
        assert_eq!(
            e,
            "f.toml:3:5: [a] invalid type: string \"five\", expected u32\n  x = \"five\"\n      ^^^^^^"
        );
        let e = read::<F>("f.toml", "[a]\ny = 1\n").unwrap_err();
        assert!(e.starts_with("f.toml:2:1: [a] unknown field `y`"), "{e}");
        let e = read::<F>("f.toml", "b = 1\n").unwrap_err();
        assert!(e.starts_with("f.toml:1:1: unknown field `b`"), "{e}");
    }
}
