//! The control's parameters: `--control NAME` (a built-in profile), then `--params FILE` (TOML) over
//! it, then the command-line flags over both. `fmsvm params --show` prints the effective set as a
//! file to start from. docs/params.md lists every key and its source; every error names its line.
//!
//! ```toml
//! [macro]
//! dialect = "fanuc"          # fanuc | haas
//! input = "fanuc"            # fanuc | nct
//! m97 = false
//! logic_level = "fanuc"      # fanuc | additive | lowest
//! nat = false                # 6004#0 NAT
//! mod_integers = false
//! decimal_input = "calculator"   # calculator | increment (3401#0 DPI)
//!
//! [calls]
//! 6050 = 100     # G100 calls O9010 as G65 does (6050–6059: O9010–O9019)
//! 6071 = 6       # M6 calls O9001 as M98 does (6071–6079: O9001–O9009)
//! 6080 = 123     # M123 calls O9020 as a macro (6080–6089: O9020–O9029)
//! t_code = true  # 6001#5 TCS: a T code calls O9000, the T value in #149
//!
//! [cycles]
//! 5114 = 0.254   # G73 retract
//! 5115 = 0.254   # G83 clearance
//! ```

use std::collections::BTreeMap;
use std::fmt::Write as _;

use fmsvm_compiler::CodeCalls;
use serde::Deserialize;
use toml::Spanned;

use crate::cli::{Control, DecimalInput, InputSyntax, Logic, MacroDialect};

/// The parameters a run uses (None: not set here; the flag or the default decides).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Params {
    /// The code-call tables.
    pub calls: CodeCalls,
    /// The macro dialect.
    pub dialect: Option<MacroDialect>,
    /// The input syntax.
    pub input: Option<InputSyntax>,
    /// M97 local calls.
    pub m97: Option<bool>,
    /// Where AND/OR/XOR bind.
    pub logic_level: Option<Logic>,
    /// NAT.
    pub nat: Option<bool>,
    /// MOD on integers.
    pub mod_integers: Option<bool>,
    /// Decimal-point input.
    pub decimal_input: Option<DecimalInput>,
    /// 5114: G73 retract (mm).
    pub g73_retract: Option<f64>,
    /// 5115: G83 clearance (mm).
    pub g83_clearance: Option<f64>,
}

/// The built-in parameters of a control.
pub fn profile(c: Control) -> Params {
    match c {
        Control::Fanuc0i => Params::default(),
        Control::Haas => Params {
            dialect: Some(MacroDialect::Haas),
            m97: Some(true),
            ..Params::default()
        },
        Control::Nct => Params {
            input: Some(InputSyntax::Nct),
            ..Params::default()
        },
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    #[serde(default, rename = "macro")]
    macro_: BTreeMap<Spanned<String>, Spanned<toml::Value>>,
    #[serde(default)]
    calls: BTreeMap<Spanned<String>, Spanned<toml::Value>>,
    #[serde(default)]
    cycles: BTreeMap<Spanned<String>, Spanned<toml::Value>>,
}

/// Reads a parameter file over `base`; the error says `name:line: what`.
pub fn parse(name: &str, text: &str, base: Params) -> Result<Params, String> {
    let file: File = crate::tomlfile::read(name, text)?;
    let mut p = base;
    let at = |key: &Spanned<String>| crate::tomlfile::at(name, text, key);
    let flag = |key: &Spanned<String>, v: &Spanned<toml::Value>| {
        v.get_ref()
            .as_bool()
            .ok_or_else(|| format!("{}: {} is true or false", at(key), key.get_ref()))
    };
    let word = |key: &Spanned<String>, v: &Spanned<toml::Value>, choices: &[&str]| {
        let s = v.get_ref().as_str().unwrap_or("");
        if choices.contains(&s) {
            Ok(s.to_string())
        } else {
            Err(format!(
                "{}: {} is one of {}",
                at(key),
                key.get_ref(),
                choices.join(", ")
            ))
        }
    };
    for (key, v) in &file.macro_ {
        match key.get_ref().as_str() {
            "dialect" => {
                p.dialect = Some(match word(key, v, &["fanuc", "haas"])?.as_str() {
                    "haas" => MacroDialect::Haas,
                    _ => MacroDialect::Fanuc,
                })
            }
            "input" => {
                p.input = Some(match word(key, v, &["fanuc", "nct"])?.as_str() {
                    "nct" => InputSyntax::Nct,
                    _ => InputSyntax::Fanuc,
                })
            }
            "logic_level" => {
                p.logic_level = Some(
                    match word(key, v, &["fanuc", "additive", "lowest"])?.as_str() {
                        "additive" => Logic::Additive,
                        "lowest" => Logic::Lowest,
                        _ => Logic::Fanuc,
                    },
                )
            }
            "decimal_input" => {
                p.decimal_input = Some(match word(key, v, &["calculator", "increment"])?.as_str() {
                    "increment" => DecimalInput::Increment,
                    _ => DecimalInput::Calculator,
                })
            }
            "m97" => p.m97 = Some(flag(key, v)?),
            "nat" => p.nat = Some(flag(key, v)?),
            "mod_integers" => p.mod_integers = Some(flag(key, v)?),
            other => {
                return Err(format!(
                    "{}: [macro] {other}: the keys are dialect, input, m97, logic_level, nat, mod_integers, decimal_input",
                    at(key)
                ));
            }
        }
    }
    for (key, v) in &file.cycles {
        let value = v
            .get_ref()
            .as_float()
            .or_else(|| v.get_ref().as_integer().map(|i| i as f64))
            .filter(|x| (0.0..=100.0).contains(x))
            .ok_or_else(|| {
                format!(
                    "{}: [cycles] {}: a distance 0 to 100",
                    at(key),
                    key.get_ref()
                )
            })?;
        match key.get_ref().as_str() {
            "5114" => p.g73_retract = Some(value),
            "5115" => p.g83_clearance = Some(value),
            other => {
                return Err(format!(
                    "{}: [cycles] {other}: the cycle parameters are 5114 (G73 retract) and 5115 (G83 clearance)",
                    at(key)
                ));
            }
        }
    }
    for (key, value) in &file.calls {
        let at = at(key);
        if key.get_ref() == "t_code" {
            p.calls.t_sub = flag(key, value)?;
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
                p.calls.g_macro[(n - 6050) as usize] = Some((v * 10) as u16);
            }
            6071..=6089 => {
                if v == 0 || v > 99_999_999 || matches!(v, 2 | 30 | 98 | 99) {
                    return Err(format!(
                        "{at}: parameter {n} = {v}: an M code other than M2, M30, M98, M99"
                    ));
                }
                if n >= 6080 {
                    p.calls.m_macro[(n - 6080) as usize] = Some(v);
                } else {
                    p.calls.m_sub[(n - 6071) as usize] = Some(v);
                }
            }
            _ => {
                return Err(format!(
                    "{at}: [calls] {n}: the call parameters are 6050–6059, 6071–6079 and 6080–6089"
                ));
            }
        }
    }
    Ok(p)
}

/// The effective parameters as a file `parse` reads back to the same set (`fmsvm params --show`).
pub fn to_toml(p: &Params) -> String {
    let mut s = String::from(
        "# fmsvm parameters (the effective set: --control, --params, the defaults)\n[macro]\n",
    );
    let name = |v: Option<&str>, default: &str| format!("\"{}\"", v.unwrap_or(default));
    let _ = writeln!(
        s,
        "dialect = {}",
        name(
            p.dialect.map(|d| match d {
                MacroDialect::Fanuc => "fanuc",
                MacroDialect::Haas => "haas",
            }),
            "fanuc"
        )
    );
    let _ = writeln!(
        s,
        "input = {}",
        name(
            p.input.map(|d| match d {
                InputSyntax::Fanuc => "fanuc",
                InputSyntax::Nct => "nct",
            }),
            "fanuc"
        )
    );
    let _ = writeln!(s, "m97 = {}", p.m97.unwrap_or(false));
    let _ = writeln!(
        s,
        "logic_level = {}",
        name(
            p.logic_level.map(|d| match d {
                Logic::Fanuc => "fanuc",
                Logic::Additive => "additive",
                Logic::Lowest => "lowest",
            }),
            "fanuc"
        )
    );
    let _ = writeln!(s, "nat = {}", p.nat.unwrap_or(false));
    let _ = writeln!(s, "mod_integers = {}", p.mod_integers.unwrap_or(false));
    let _ = writeln!(
        s,
        "decimal_input = {}",
        name(
            p.decimal_input.map(|d| match d {
                DecimalInput::Calculator => "calculator",
                DecimalInput::Increment => "increment",
            }),
            "calculator"
        )
    );
    s.push_str("\n[calls]\n");
    for (k, g) in p.calls.g_macro.iter().enumerate() {
        if let Some(g) = g {
            let _ = writeln!(
                s,
                "{} = {}     # G{} calls O{}",
                6050 + k,
                g / 10,
                g / 10,
                9010 + k
            );
        }
    }
    for (k, m) in p.calls.m_sub.iter().enumerate() {
        if let Some(m) = m {
            let _ = writeln!(
                s,
                "{} = {}     # M{m} calls O{} as M98",
                6071 + k,
                m,
                9001 + k
            );
        }
    }
    for (k, m) in p.calls.m_macro.iter().enumerate() {
        if let Some(m) = m {
            let _ = writeln!(
                s,
                "{} = {}     # M{m} calls O{} as G65",
                6080 + k,
                m,
                9020 + k
            );
        }
    }
    let _ = writeln!(s, "t_code = {}", p.calls.t_sub);
    let defaults = fmsvm_runtime::cycles::CycleParams::default();
    let _ = writeln!(
        s,
        "\n[cycles]\n5114 = {:?}   # G73 retract, mm\n5115 = {:?}   # G83 clearance, mm",
        p.g73_retract.unwrap_or(defaults.g73_retract),
        p.g83_clearance.unwrap_or(defaults.g83_clearance)
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: &str = "[macro]\ndialect = \"haas\"\ninput = \"fanuc\"\nm97 = true\nlogic_level = \"lowest\"\nnat = true\nmod_integers = true\ndecimal_input = \"increment\"\n[calls]\n6050 = 100\n6059 = 966\n6071 = 6\n6089 = 123\nt_code = true\n[cycles]\n5114 = 0.5\n5115 = 1\n";

    #[test]
    fn every_key() {
        let p = parse("p.toml", ALL, Params::default()).expect("parses");
        assert_eq!(p.dialect, Some(MacroDialect::Haas));
        assert_eq!(p.input, Some(InputSyntax::Fanuc));
        assert_eq!(
            (p.m97, p.nat, p.mod_integers),
            (Some(true), Some(true), Some(true))
        );
        assert_eq!(p.logic_level, Some(Logic::Lowest));
        assert_eq!(p.decimal_input, Some(DecimalInput::Increment));
        assert_eq!(p.calls.g_macro[0], Some(1000));
        assert_eq!(p.calls.g_macro[9], Some(9660));
        assert_eq!(p.calls.m_sub[0], Some(6));
        assert_eq!(p.calls.m_macro[9], Some(123));
        assert!(p.calls.t_sub);
        assert_eq!((p.g73_retract, p.g83_clearance), (Some(0.5), Some(1.0)));
        // The printed set reads back to the same parameters.
        let again = parse("shown.toml", &to_toml(&p), Params::default()).expect("reloads");
        assert_eq!(
            again,
            Params {
                input: Some(InputSyntax::Fanuc),
                ..p.clone()
            }
        );
        // A profile under the file: the file wins where it says something.
        let nct = parse("p.toml", "[macro]\nnat = true\n", profile(Control::Nct)).expect("parses");
        assert_eq!((nct.input, nct.nat), (Some(InputSyntax::Nct), Some(true)));
    }

    #[test]
    fn errors_name_their_line() {
        let cases = [
            ("[calls]\n6050 = 100\n6060 = 5\n", "p.toml:3:"),
            ("[calls]\n6050 = 65\n", "p.toml:2:"),
            ("[calls]\n6071 = \"six\"\n", "p.toml:2:"),
            ("[call]\n6071 = 6\n", "p.toml:1:"),
            ("[macro]\nnat = true\ndialect = \"okuma\"\n", "p.toml:3:"),
            ("[macro]\nnatt = true\n", "p.toml:2:"),
            ("[cycles]\n5114 = -1\n", "p.toml:2:"),
            ("[cycles]\n5116 = 1\n", "p.toml:2:"),
        ];
        for (text, at) in cases {
            let e = parse("p.toml", text, Params::default()).unwrap_err();
            assert!(e.starts_with(at), "{text:?}: {e}");
        }
    }
}
