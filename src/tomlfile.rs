//! What the TOML input files (`--offsets`, `--params`) share: reading one, and naming the line of an
//! error as `file:line`.

use serde::de::DeserializeOwned;
use toml::Spanned;

/// Line (1-based) of byte `offset` in `text`.
fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

/// `text` (the file `name`) as a `T`; the error says `name:line: what`.
pub fn read<T: DeserializeOwned>(name: &str, text: &str) -> Result<T, String> {
    toml::from_str(text).map_err(|e| {
        let line = e.span().map_or(1, |s| line_of(text, s.start));
        format!("{name}:{line}: {}", e.message())
    })
}

/// `name:line` of `key` in `text`, to begin an error about it.
pub fn at(name: &str, text: &str, key: &Spanned<String>) -> String {
    format!("{name}:{}", line_of(text, key.span().start))
}
