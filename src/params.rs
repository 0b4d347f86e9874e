//! `--params FILE`: the control's parameters as a TOML file. Today the code-call tables (docs/params.md):
//! which G, M and T codes call macros and subprograms. Every error names its line.
//!
//! ```toml
//! [calls]
//! 6050 = 100     # G100 calls O9010 as G65 does (6050–6059: O9010–O9019)
//! 6071 = 6       # M6 calls O9001 as M98 does (6071–6079: O9001–O9009)
//! 6080 = 123     # M123 calls O9020 as a macro (6080–6089: O9020–O9029)
//! t_code = true  # 6001#5: a T code calls O9000, the T value in #149
//! ```

use std::collections::BTreeMap;

use fmsvm_compiler::CodeCalls;
use serde::Deserialize;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    #[serde(default)]
    calls: BTreeMap<Spanned<String>, Spanned<toml::Value>>,
}

fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

/// Reads a parameter file; the error says `name:line: what`.
pub fn parse(name: &str, text: &str) -> Result<CodeCalls, String> {
    let file: File = toml::from_str(text).map_err(|e| {
        let line = e.span().map_or(1, |s| line_of(text, s.start));
        format!("{name}:{line}: {}", e.message())
    })?;
    let mut calls = CodeCalls::default();
    for (key, value) in &file.calls {
        let at = format!("{name}:{}", line_of(text, key.span().start));
        if key.get_ref() == "t_code" {
            calls.t_sub = value
                .get_ref()
                .as_bool()
                .ok_or_else(|| format!("{at}: [calls] t_code is true or false"))?;
            continue;
        }
        let v = value
            .get_ref()
            .as_integer()
            .and_then(|v| u32::try_from(v).ok())
            .ok_or_else(|| {
                format!(
                    "{at}: [calls] {}: the value is a code number",
                    key.get_ref()
                )
            })?;
        let n: u32 = key.get_ref().parse().map_err(|_| {
            format!(
                "{at}: [calls] {}: a parameter number (6050–6059, 6071–6079, 6080–6089) or t_code",
                key.get_ref()
            )
        })?;
        match n {
            6050..=6059 => {
                if !(1..=9999).contains(&v) || matches!(v, 65..=67) {
                    return Err(format!(
                        "{at}: parameter {n} = {v}: a G code 1 to 9999 other than G65, G66, G67"
                    ));
                }
                calls.g_macro[(n - 6050) as usize] = Some((v * 10) as u16);
            }
            6071..=6089 => {
                if v == 0 || v > 99_999_999 || matches!(v, 2 | 30 | 98 | 99) {
                    return Err(format!(
                        "{at}: parameter {n} = {v}: an M code other than M2, M30, M98, M99"
                    ));
                }
                if n >= 6080 {
                    calls.m_macro[(n - 6080) as usize] = Some(v);
                } else {
                    calls.m_sub[(n - 6071) as usize] = Some(v);
                }
            }
            _ => {
                return Err(format!(
                    "{at}: [calls] {n}: the call parameters are 6050–6059, 6071–6079 and 6080–6089"
                ));
            }
        }
    }
    Ok(calls)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_key_and_its_errors() {
        let c = parse(
            "p.toml",
            "[calls]\n6050 = 100\n6059 = 966\n6071 = 6\n6089 = 123\nt_code = true\n",
        )
        .expect("parses");
        assert_eq!(c.g_macro[0], Some(1000));
        assert_eq!(c.g_macro[9], Some(9660));
        assert_eq!(c.m_sub[0], Some(6));
        assert_eq!(c.m_macro[9], Some(123));
        assert!(c.t_sub);
        let e = parse("p.toml", "[calls]\n6050 = 100\n6060 = 5\n").unwrap_err();
        assert!(e.starts_with("p.toml:3:"), "{e}");
        let e = parse("p.toml", "[calls]\n6050 = 65\n").unwrap_err();
        assert!(e.starts_with("p.toml:2:") && e.contains("G65"), "{e}");
        let e = parse("p.toml", "[calls]\n6071 = \"six\"\n").unwrap_err();
        assert!(e.starts_with("p.toml:2:"), "{e}");
        let e = parse("p.toml", "[call]\n6071 = 6\n").unwrap_err();
        assert!(e.starts_with("p.toml:1:"), "{e}");
    }
}
