//! A lathe control's machine cycles (`[[cycle]]` of a dialect profile, docs/postprocessor.md): what
//! the turning library's dialog shows for each (the `BEGIN_MACHINE_CYCLES` block it reads at the top
//! of a postprocessor) and how `fmsvm post` writes the control's own block for a `CYCLE` record.

use std::fmt::Write as _;

use serde::Deserialize;

/// One machine cycle of a control.
#[derive(Clone, Debug, PartialEq)]
pub struct MachineCycle {
    /// Its number (`CYCLE 72`).
    pub number: u32,
    /// Its name and comment, as the dialog shows them.
    pub name: String,
    /// Its comment.
    pub comment: String,
    /// `Turning`, `Drilling` or `Threading`.
    pub kind: String,
    /// `Chisel`, `Drill` or `Tap`.
    pub tool: String,
    /// The figures it takes (`TrapecG1 | TrapecG2`), empty for any.
    pub profile: String,
    /// Its parameters, in the dialog's order.
    pub parameters: Vec<Parameter>,
    /// The control's block, words with `{NAME}` for a parameter's value (`G72 X{_Xend} I{I}`): a
    /// word whose parameter is not given is left out.
    pub block: String,
    /// Where the format comes from (a manual, the seed's listing, or "inferred").
    pub source: String,
    /// The profile's blocks stay after the cycle's block (Fanuc's G71 names them by `{ns}` and
    /// `{nf}`, its first and last N); otherwise they are dropped with the G80.
    pub keep_profile: bool,
}

/// A parameter of a machine cycle.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Parameter {
    /// Its designation (`I`, `VP`, `P1`).
    pub name: String,
    /// `A` automatic, `O` obligatory, `S` free, `D` additional, `OD` obligatory additional.
    pub kind: String,
    /// What the dialog calls it.
    pub text: String,
    /// Its default, if any.
    #[serde(default)]
    pub default: Option<String>,
    /// The values a list offers.
    #[serde(default)]
    pub values: Vec<String>,
}

impl Parameter {
    /// The user must give it.
    pub fn obligatory(&self) -> bool {
        matches!(self.kind.as_str(), "O" | "OD")
    }
}

/// `[[cycle]]` of a profile.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CycleKeys {
    number: u32,
    name: String,
    #[serde(default)]
    comment: String,
    #[serde(rename = "type")]
    kind: String,
    #[serde(default)]
    tool: String,
    #[serde(default)]
    profile: String,
    #[serde(default)]
    parameters: Vec<Parameter>,
    block: String,
    #[serde(default)]
    source: String,
    #[serde(default)]
    keep_profile: bool,
}

/// The profile's cycles with `keys` added (a cycle of the same number replaced); each checked.
pub fn merge(cycles: &mut Vec<MachineCycle>, keys: Vec<CycleKeys>) -> Result<(), String> {
    for k in keys {
        if !matches!(k.kind.as_str(), "Turning" | "Drilling" | "Threading") {
            return Err(format!(
                "[[cycle]] {}: type = {:?}: Turning, Drilling or Threading",
                k.number, k.kind
            ));
        }
        for p in &k.parameters {
            if !matches!(p.kind.as_str(), "A" | "O" | "S" | "D" | "OD") {
                return Err(format!(
                    "[[cycle]] {} parameter {}: kind = {:?}: A, O, S, D or OD",
                    k.number, p.name, p.kind
                ));
            }
        }
        let c = MachineCycle {
            number: k.number,
            name: k.name,
            comment: k.comment,
            kind: k.kind,
            tool: k.tool,
            profile: k.profile,
            parameters: k.parameters,
            block: k.block,
            source: k.source,
            keep_profile: k.keep_profile,
        };
        cycles.retain(|o| o.number != c.number);
        cycles.push(c);
    }
    cycles.sort_by_key(|c| c.number);
    Ok(())
}

/// The `BEGIN_MACHINE_CYCLES … END_MACHINE_CYCLES` block of `cycles`, as the library reads it.
pub fn machine_cycles_block(cycles: &[MachineCycle]) -> String {
    let mut s = String::from("BEGIN_MACHINE_CYCLES\n");
    for c in cycles {
        let _ = writeln!(s, "\nBEGIN_CYCLE {}", c.number);
        let _ = writeln!(s, "NAME \"{}\"", c.name);
        let _ = writeln!(s, "COMMENT \"{}\"", c.comment);
        let _ = writeln!(s, "TYPE {}", c.kind);
        s.push_str("PARAMETERS\n");
        for p in &c.parameters {
            let _ = write!(s, "{} {} \"{}\"", p.name, p.kind, p.text);
            if let Some(d) = &p.default {
                let _ = write!(s, " {d}");
            }
            s.push('\n');
            if !p.values.is_empty() {
                s.push_str("begin_list\n");
                for v in &p.values {
                    let _ = writeln!(s, "\"{v}\"");
                }
                s.push_str("end_list\n");
            }
        }
        if !c.tool.is_empty() {
            let _ = writeln!(s, "TOOL_DEMANDS \"{}\"", c.tool);
        }
        if c.kind != "Drilling" || !c.profile.is_empty() {
            let _ = writeln!(s, "PROFIL_DEMANDS \"{}\"", c.profile);
        }
        s.push_str("END_CYCLE\n");
    }
    s.push_str("END_MACHINE_CYCLES\n");
    s
}
