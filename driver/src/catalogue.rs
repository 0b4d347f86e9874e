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
    /// word whose parameter is not given is left out. None: the control has no such cycle, and
    /// fmsvm writes it in elementary moves.
    pub block: Option<String>,
    /// How fmsvm writes the cycle in elementary moves (None: it cannot).
    pub moves: Option<Scheme>,
    /// Where the format comes from (a manual, the library's listing, or "inferred").
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
    /// What the parameter means to the cycle's elementary moves (one of [`ROLES`]).
    #[serde(default)]
    pub role: Option<String>,
}

/// How a cycle runs, for its elementary moves: which of the kernel's turning cycles makes them
/// (docs/postprocessor.md, "Elementary moves").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Scheme {
    /// Passes along Z at X levels, from the start to the figure (Fanuc's G71).
    Turning,
    /// Passes along X at Z levels (Fanuc's G72).
    Facing,
    /// The profile repeated, moved in towards it (Fanuc's G73).
    Pattern,
    /// Pecks along Z on the spindle's axis (Fanuc's G74 without grooves).
    Drilling,
    /// Passes deeper each time along the thread (Fanuc's G76).
    Threading,
    /// A tap or die in along the thread, the spindle reversed, out again.
    Tapping,
}

impl Scheme {
    /// Its name in a profile (`moves = "turning"`).
    pub fn name(self) -> &'static str {
        match self {
            Scheme::Turning => "turning",
            Scheme::Facing => "facing",
            Scheme::Pattern => "pattern",
            Scheme::Drilling => "drilling",
            Scheme::Threading => "threading",
            Scheme::Tapping => "tapping",
        }
    }

    /// The record kind (`TYPE`) the scheme serves.
    fn kind(self) -> &'static str {
        match self {
            Scheme::Turning | Scheme::Facing | Scheme::Pattern => "Turning",
            Scheme::Drilling => "Drilling",
            Scheme::Threading | Scheme::Tapping => "Threading",
        }
    }
}

/// The roles a parameter can have in a cycle's elementary moves, and what each means (lengths in
/// mm; X values on the diameter unless the role says radius).
pub const ROLES: [(&str, &str); 15] = [
    ("depth", "the depth of cut of each pass (radius)"),
    (
        "passes",
        "the number of roughing passes (when no depth is given)",
    ),
    (
        "allowance_x",
        "the finishing allowance in X (on the diameter)",
    ),
    ("allowance_z", "the finishing allowance in Z"),
    (
        "finish_passes",
        "the number of finishing passes that take the allowance off",
    ),
    (
        "plan_angle",
        "the tool's main angle in plan, degrees (a wall steeper than it is refused)",
    ),
    ("feed", "the cutting feed"),
    ("retract", "the retract after each pass or peck"),
    (
        "relief_x",
        "the first pass's distance from the profile in X (radius), pattern repeating",
    ),
    (
        "relief_z",
        "the first pass's distance from the profile in Z, pattern repeating",
    ),
    ("peck", "the depth of each peck"),
    ("first_depth", "a thread's first depth of cut (radius)"),
    ("least_depth", "a thread's least depth of cut"),
    (
        "thread_allowance",
        "a thread's finishing allowance (radius)",
    ),
    (
        "tool_angle",
        "a thread tool's angle, degrees: the infeed runs along its flank (0: radial)",
    ),
];

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
    #[serde(default)]
    block: Option<String>,
    #[serde(default)]
    moves: Option<Scheme>,
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
        carried(&k)?;
        for (i, p) in k.parameters.iter().enumerate() {
            if k.parameters[..i].iter().any(|q| q.name == p.name) {
                return Err(format!(
                    "[[cycle]] {} parameter {}: named twice (each parameter once)",
                    k.number, p.name
                ));
            }
            if !matches!(p.kind.as_str(), "A" | "O" | "S" | "D" | "OD") {
                return Err(format!(
                    "[[cycle]] {} parameter {}: kind = {:?}: A, O, S, D or OD",
                    k.number, p.name, p.kind
                ));
            }
            if let Some(r) = &p.role
                && !ROLES.iter().any(|(name, _)| name == r)
            {
                return Err(format!(
                    "[[cycle]] {} parameter {}: role = {r:?}: one of {}",
                    k.number,
                    p.name,
                    ROLES.map(|(n, _)| n).join(", ")
                ));
            }
        }
        if let Some(block) = &k.block {
            check_block(k.number, block, &k.parameters)?;
        }
        match (&k.block, k.moves) {
            (None, None) => {
                return Err(format!(
                    "[[cycle]] {}: give its block (the control's cycle) or moves (fmsvm's elementary moves), or both",
                    k.number
                ));
            }
            (_, Some(m)) if m.kind() != k.kind => {
                return Err(format!(
                    "[[cycle]] {}: moves = {:?} makes a {} cycle, and its type is {}",
                    k.number,
                    m,
                    m.kind(),
                    k.kind
                ));
            }
            _ => {}
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
            moves: k.moves,
            source: k.source,
            keep_profile: k.keep_profile,
        };
        cycles.retain(|o| o.number != c.number);
        cycles.push(c);
    }
    cycles.sort_by_key(|c| c.number);
    Ok(())
}

/// Every text of a `[[cycle]]` is one the library's catalogue can carry and the launcher can hold:
/// a name one word of letters, digits and `_`; a text on one line without `"` (the catalogue's
/// quotes) or `'''` (the launcher's comment); none of them may change what the launcher runs.
fn carried(k: &CycleKeys) -> Result<(), String> {
    let word = |what: &str, t: &str| {
        if t.is_empty() || !t.chars().all(|c| c.is_alphanumeric() || c == '_') {
            Err(format!(
                "[[cycle]] {} {what} {t:?}: one word of letters, digits and _",
                k.number
            ))
        } else {
            Ok(())
        }
    };
    let text = |what: &str, t: &str| {
        if t.chars().any(|c| c == '"' || c.is_control()) || t.contains("'''") {
            Err(format!(
                "[[cycle]] {} {what} {t:?}: the library's catalogue cannot carry a quote (\"), a line break or a control character, nor the launcher ''' ",
                k.number
            ))
        } else {
            Ok(())
        }
    };
    text("name", &k.name)?;
    text("comment", &k.comment)?;
    text("tool", &k.tool)?;
    text("profile", &k.profile)?;
    for p in &k.parameters {
        word("parameter", &p.name)?;
        text(&format!("parameter {}", p.name), &p.text)?;
        for v in &p.values {
            text(&format!("parameter {} value", p.name), v)?;
        }
        if let Some(d) = &p.default {
            text(&format!("parameter {} default", p.name), d)?;
            if d.contains(char::is_whitespace) {
                return Err(format!(
                    "[[cycle]] {} parameter {} default {d:?}: one word",
                    k.number, p.name
                ));
            }
        }
    }
    Ok(())
}

/// The formats a `{NAME:spec}` of a cycle's block may ask for (`fmsvm post` writes each).
pub const SPECS: [&str; 6] = ["02", "int", "um", "as", "xside", "zside"];

/// The formats, for a message: `:02, :int, …`.
pub fn specs_named() -> String {
    SPECS.map(|s| format!(":{s}")).join(", ")
}

/// Every `{NAME}` of a cycle's block names one of its parameters, one of the library's environment
/// variables, or `ns`/`nf`, with a format fmsvm knows.
fn check_block(number: u32, block: &str, parameters: &[Parameter]) -> Result<(), String> {
    let mut rest = block;
    while let Some((_, after)) = rest.split_once('{') {
        let Some((field, tail)) = after.split_once('}') else {
            return Err(format!(
                "[[cycle]] {number}: block: a {{NAME}} is not closed"
            ));
        };
        let (name, spec) = field.split_once(':').unwrap_or((field, ""));
        let known = matches!(name, "ns" | "nf")
            || parameters.iter().any(|p| p.name == name)
            || crate::neutral::ENVIRONMENT.contains(&name);
        if !known {
            return Err(format!(
                "[[cycle]] {number}: block: {{{name}}} is none of the cycle's parameters, nor an environment variable of the library ({}), nor ns or nf",
                crate::neutral::ENVIRONMENT.join(" ")
            ));
        }
        if !spec.is_empty() && !SPECS.contains(&spec) {
            return Err(format!(
                "[[cycle]] {number}: block: {{{field}}}: the formats are {}",
                specs_named()
            ));
        }
        rest = tail;
    }
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
            // "A missing default means 0" (the library's manual, §4.3): a 0 is not written.
            if let Some(d) = p.default.as_ref().filter(|d| d.parse::<f64>() != Ok(0.0)) {
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
