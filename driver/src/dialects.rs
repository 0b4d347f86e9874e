//! The output dialects: the built-in profiles (`dialects/*.toml`, shipped in the binary), a user's
//! `--dialect-file` over the profile it names as `base`, `fmsvm dialects` and `--show`. A profile is
//! data for `fmsvm_emit::dialect::Dialect`; a dialect that needs code (the Н33-2М tape) is listed
//! here with its own few keys.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use fmsvm_block::{Code, Letter};
use fmsvm_canon::modal::CodeSystem;
use fmsvm_emit::dialect::{
    AddressKind, ArcForm, ClampForm, CommentStyle, CssForm, CycleForm, Dialect, DwellForm,
    HelixForm, LatheForm, LineNumbers, MachineKind, NumberFormat, Point, ReferenceForm, ThreadForm,
    ToolForm,
};
use serde::Deserialize;
use toml::Spanned;

use crate::input::Charset;
use crate::tomlfile::at;

/// The built-in text dialects: name and profile.
pub const BUILT_IN: [(&str, &str); 10] = [
    ("fanuc", include_str!("../dialects/fanuc.toml")),
    ("iso", include_str!("../dialects/iso.toml")),
    ("linuxcnc", include_str!("../dialects/linuxcnc.toml")),
    ("fms3000", include_str!("../dialects/fms3000.toml")),
    ("mayak600t", include_str!("../dialects/mayak600t.toml")),
    ("nc31", include_str!("../dialects/nc31.toml")),
    ("fanuc0itd", include_str!("../dialects/fanuc0itd.toml")),
    (
        "sinumerik802d",
        include_str!("../dialects/sinumerik802d.toml"),
    ),
    ("fagor8035t", include_str!("../dialects/fagor8035t.toml")),
    ("haaslathe", include_str!("../dialects/haaslathe.toml")),
];

/// How a dialect is written: a text profile, or the Н33-2М tape's own emitter.
#[derive(Clone, Debug, PartialEq)]
pub enum Kind {
    /// Word-address text after a profile.
    Text,
    /// The Н33-2М punched tape (fixed-width increments, feed codes, quadrant arcs).
    N33,
}

/// A loaded dialect: the profile and the character set of its comments.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    /// How blocks are spelled.
    pub dialect: Dialect,
    /// The output's character set (None: the program's own).
    pub charset: Option<Charset>,
    /// Text or tape.
    pub kind: Kind,
    /// The control's machine cycles (`[[cycle]]`), for `fmsvm post`.
    pub cycles: Vec<crate::catalogue::MachineCycle>,
}

impl Profile {
    /// Why the control cannot take machine cycle `m` as the profile declares it (`elementary`:
    /// written in elementary moves even where it has a block), if it cannot: a thread or a tap in
    /// elementary moves where no single-block thread is known (`[lathe] thread = "none"`), or a
    /// tap in elementary moves without a floating holder (`floating_tap`: a rigid holder would be
    /// pulled by the spindle's run-down at the reversal). Such a cycle is not offered to the
    /// library (`offered`), and a record of it is refused with this.
    pub fn withheld(&self, m: &crate::catalogue::MachineCycle, elementary: bool) -> Option<String> {
        use crate::catalogue::Scheme;
        let lathe = self.dialect.lathe.as_ref()?;
        if m.block.is_some() && !elementary {
            return None;
        }
        match m.moves {
            Some(Scheme::Threading | Scheme::Tapping) if lathe.thread == ThreadForm::None => {
                Some(format!(
                    "no single-block thread is known for {} ([lathe] thread = \"none\"), and the cycle has no block of its own",
                    self.dialect.name
                ))
            }
            Some(Scheme::Tapping) if !lathe.floating_tap => Some(format!(
                "tapping in elementary moves (G33 in, the spindle reversed, G33 out) is right only with a floating tap holder, and the {} profile declares none ([lathe] floating_tap = true in a profile of your own)",
                self.dialect.name
            )),
            _ => None,
        }
    }

    /// The machine cycles the control can take: the catalogue the library is shown (launchers,
    /// `fmsvm dialects --cycles`) and the records `post` writes.
    pub fn offered(&self) -> Vec<crate::catalogue::MachineCycle> {
        self.cycles
            .iter()
            .filter(|m| self.withheld(m, false).is_none())
            .cloned()
            .collect()
    }
}

/// The Н33-2М tape: listed with the text dialects, written by its own emitter.
pub const N33_SUMMARY: &str = "Н33-2М punched tape (6Р13Ф3-37 mill): fixed-width increments in 0.01 mm, feed codes, one quadrant an arc, --tape for ISO 7-bit even parity";

/// Every dialect's name and summary, for `fmsvm dialects`.
pub fn list() -> Vec<(String, String)> {
    let mut v: Vec<(String, String)> = BUILT_IN
        .iter()
        .map(|(name, text)| {
            let summary = builtin(name)
                .map(|p| p.dialect.summary)
                .unwrap_or_else(|_| text.lines().next().unwrap_or("").to_string());
            (name.to_string(), summary)
        })
        .collect();
    v.insert(4, ("n33".into(), N33_SUMMARY.into()));
    v
}

/// The built-in dialect `name`.
pub fn builtin(name: &str) -> Result<Profile, String> {
    if name == "n33" {
        let mut dialect = Dialect::fanuc();
        dialect.name = "n33".into();
        dialect.summary = N33_SUMMARY.into();
        dialect.literal = false;
        dialect.inch = false;
        dialect.comments = CommentStyle::None;
        // 0.01 mm discretes (§5.1.1): what --verify holds the tape to.
        dialect.mm_digits = 2;
        dialect.angle_digits = 2;
        dialect.max_digits = 6;
        return Ok(Profile {
            dialect,
            charset: None,
            kind: Kind::N33,
            cycles: Vec::new(),
        });
    }
    let Some((_, text)) = BUILT_IN.iter().find(|(n, _)| *n == name) else {
        let names: Vec<String> = list().into_iter().map(|(n, _)| n).collect();
        return Err(format!(
            "no dialect `{name}`: the dialects are {} (or --dialect-file FILE)",
            names.join(", ")
        ));
    };
    let base = if name == "fanuc" {
        Profile {
            dialect: Dialect::fanuc(),
            charset: None,
            kind: Kind::Text,
            cycles: Vec::new(),
        }
    } else {
        builtin("fanuc")?
    };
    parse(&format!("dialects/{name}.toml (built in)"), text, base)
}

/// The profile in `text` (the file `file`): over its `base` (a built-in name; default `fanuc`).
pub fn load(file: &str, text: &str) -> Result<Profile, String> {
    let head: Head = crate::tomlfile::read(file, text)?;
    let base = match &head.base {
        Some(b) if b.get_ref() == "n33" => {
            return Err(format!(
                "{}: the Н33-2М tape is written by code, not by a profile: use --dialect n33",
                at(file, text, b.span().start)
            ));
        }
        Some(b) => {
            builtin(b.get_ref()).map_err(|e| format!("{}: {e}", at(file, text, b.span().start)))?
        }
        None => builtin("fanuc")?,
    };
    parse(file, text, base)
}

/// The shortest block limit a profile may set: no control takes fewer characters a block.
const MIN_BLOCK_LENGTH: u64 = 16;

/// Reads `text` over `base`, a section at a time.
fn parse(file: &str, text: &str, base: Profile) -> Result<Profile, String> {
    // `[[blocks]]` is an array of tables: only `[[cycle]]` is one.
    if let Ok(doc) = text.parse::<toml::Table>()
        && let Some((key, _)) = doc.iter().find(|(k, v)| {
            k.as_str() != "cycle"
                && v.as_array()
                    .is_some_and(|a| a.iter().all(toml::Value::is_table) && !a.is_empty())
        })
    {
        return Err(format!(
            "{file}: [[{key}]] is written [{key}]: only [[cycle]] repeats"
        ));
    }
    let f: File = crate::tomlfile::read(file, text)?;
    let mut p = base;
    let d = &mut p.dialect;
    if let Some(n) = f.name {
        // The name is one line of a message and of `--show`'s heading comment.
        if n.chars().any(char::is_control) {
            return Err(format!(
                "{file}: name: a dialect's name is one line without control characters"
            ));
        }
        d.name = n;
    }
    if let Some(s) = f.summary {
        d.summary = s;
    }
    set(&mut d.literal, f.literal);
    set(&mut d.haas, f.haas);
    set(&mut d.compact, f.compact);
    if let Some(b) = f.blocks {
        if let Some(m) = &b.max_length
            && (1..MIN_BLOCK_LENGTH).contains(&m.0)
        {
            return Err(format!(
                "{file}: [blocks] max_length = {}: 0 (no limit) or at least {MIN_BLOCK_LENGTH} characters (a block holds a word or two and its end)",
                m.0
            ));
        }
        blocks(d, b);
    }
    if let Some(n) = f.numbers {
        numbers(file, text, d, n)?;
    }
    if let Some(c) = f.comments {
        if let Some(s) = c.style {
            d.comments = match s {
                Style::Paren => CommentStyle::Paren,
                Style::Semicolon => CommentStyle::Semicolon,
                Style::None => CommentStyle::None,
            };
        }
        if let Some(active) = c.active {
            d.active_comments = active.iter().map(|w| w.to_ascii_uppercase()).collect();
        }
    }
    if let Some(m) = f.motion {
        motion(file, text, d, m)?;
    }
    if let Some(m) = f.machine {
        d.machine = match m {
            MachineName::Mill => MachineKind::Mill,
            MachineName::Lathe => MachineKind::Lathe,
            MachineName::Both => MachineKind::Both,
        };
    }
    if let Some(other) = &f.cycles_of {
        if other == &p.dialect.name {
            return Err(format!("{file}: cycles_of = {other:?} names this profile"));
        }
        p.cycles = builtin(other)
            .map_err(|e| format!("{file}: cycles_of: {e}"))?
            .cycles;
    }
    if let Some(c) = f.cycle {
        crate::catalogue::merge(&mut p.cycles, c).map_err(|e| format!("{file}: {e}"))?;
    }
    let d = &mut p.dialect;
    if let Some(l) = f.lathe {
        lathe(d, l).map_err(|e| format!("{file}: [lathe] {e}"))?;
    }
    if d.machine != MachineKind::Mill && d.lathe.is_none() {
        return Err(format!(
            "{file}: machine = \"lathe\" or \"both\" needs a [lathe] section (how the control writes turning)"
        ));
    }
    if let Some(g) = f.program {
        program(&mut p, g).map_err(|e| format!("{file}: {e}"))?;
    }
    Ok(p)
}

/// `[lathe]`: how the control writes turning, over the base's (or a diameter lathe in system A).
fn lathe(d: &mut Dialect, k: LatheKeys) -> Result<(), String> {
    let mut l = d.lathe.clone().unwrap_or(LatheForm {
        diameter: true,
        codes: CodeSystem::LatheA,
        frame: "G18".into(),
        css: CssForm::Native,
        clamp: ClampForm::G50,
        thread: ThreadForm::F,
        tool: ToolForm::Fanuc,
        metric: "G21".into(),
        inch: "G20".into(),
        max_rpm: None,
        floating_tap: false,
        y_axis: false,
    });
    if let Some(x) = k.x {
        l.diameter = x == LatheXName::Diameter;
    }
    if let Some(c) = k.codes {
        l.codes = match c {
            Codes::FanucA => CodeSystem::LatheA,
            Codes::FanucB => CodeSystem::LatheB,
            Codes::Iso => CodeSystem::Mill,
        };
    }
    if let Some(frame) = k.frame {
        // Words only: it is written as the output's first line.
        if frame.len() > 64
            || !frame
                .bytes()
                .all(|b| b.is_ascii_uppercase() || b.is_ascii_digit() || b" .-=".contains(&b))
        {
            return Err(format!(
                "frame = {frame:?}: at most 64 characters of words (capitals, digits, space, . - =)"
            ));
        }
        l.frame = frame;
    }
    if let Some(c) = k.css {
        l.css = match c {
            Css::Native => CssForm::Native,
            Css::Rpm => CssForm::Rpm,
        };
    }
    if let Some(c) = k.clamp {
        l.clamp = match c {
            Clamp::G50 => ClampForm::G50,
            Clamp::G92 => ClampForm::G92,
            Clamp::D => ClampForm::D,
            Clamp::Lims => ClampForm::Lims,
        };
    }
    if let Some(t) = k.thread {
        l.thread = match t {
            Thread::F => ThreadForm::F,
            Thread::K => ThreadForm::K,
            Thread::Din => ThreadForm::Din,
            Thread::None => ThreadForm::None,
        };
    }
    for (key, words, into) in [
        ("metric", k.metric, &mut l.metric),
        ("inch", k.inch, &mut l.inch),
    ] {
        if let Some(w) = words {
            if w.len() > 16
                || !w
                    .bytes()
                    .all(|b| b.is_ascii_uppercase() || b.is_ascii_digit())
            {
                return Err(format!(
                    "{key} = {w:?}: one code word (capitals and digits, `G21`, `G71`), or \"\" for none"
                ));
            }
            *into = w;
        }
    }
    if let Some(r) = k.max_rpm {
        if !(r.is_finite() && (1.0..=99_999.0).contains(&r)) {
            return Err(format!(
                "max_rpm = {r}: a spindle speed from 1 to 99999 rpm"
            ));
        }
        l.max_rpm = Some(r);
    }
    if let Some(f) = k.floating_tap {
        l.floating_tap = f;
    }
    if let Some(y) = k.y_axis {
        l.y_axis = y;
    }
    if let Some(t) = k.tool {
        l.tool = match t {
            Tool::Fanuc => ToolForm::Fanuc,
            Tool::Linuxcnc => ToolForm::LinuxCnc,
            Tool::TD => ToolForm::TD,
        };
    }
    d.lathe = Some(l);
    Ok(())
}

/// `[program]`: the envelope and the character set.
fn program(p: &mut Profile, g: ProgramKeys) -> Result<(), String> {
    for t in g
        .header
        .iter()
        .flatten()
        .chain(g.footer.iter().flatten())
        .chain(g.number.iter())
    {
        fmsvm_emit::dialect::Dialect::check_template(t)?;
    }
    let d = &mut p.dialect;
    set(&mut d.header, g.header);
    set(&mut d.footer, g.footer);
    set(&mut d.program_number, g.number);
    set(&mut d.header_comment, g.header_comment);
    set(&mut d.end_required, g.end_required);
    if let Some(c) = g.charset {
        p.charset = match c {
            CharsetName::Utf8 => Some(Charset::Utf8),
            CharsetName::Ascii => Some(Charset::Ascii),
            CharsetName::Latin1 => Some(Charset::Latin1),
            CharsetName::Cp1251 => Some(Charset::Cp1251),
            CharsetName::Cp866 => Some(Charset::Cp866),
            CharsetName::Koi8R => Some(Charset::Koi8R),
        };
    }
    Ok(())
}

/// `[blocks]`: block end, length, separator, line numbers, block delete.
fn blocks(d: &mut Dialect, b: BlockKeys) {
    if let Some(e) = b.end {
        d.eol = match e {
            Eol::Lf => "\n".into(),
            Eol::Crlf => "\r\n".into(),
        };
    }
    if let Some(m) = b.max_length {
        d.max_block = (m.0 > 0).then_some(m.0 as usize);
    }
    set(&mut d.separator, b.separator);
    let (start, step) = match d.line_numbers {
        LineNumbers::Renumber { start, step } => (start, step),
        _ => (10, 10),
    };
    let start = b.start.map_or(start, |s| s.0 as u32);
    let step = b.step.map_or(step, |s| s.0 as u32);
    d.line_numbers = match b.numbers {
        Some(Numbering::Keep) => LineNumbers::Keep,
        Some(Numbering::Off) => LineNumbers::Off,
        Some(Numbering::Renumber) => LineNumbers::Renumber { start, step },
        None => match d.line_numbers {
            LineNumbers::Renumber { .. } => LineNumbers::Renumber { start, step },
            other => other,
        },
    };
    if let Some(w) = b.width {
        d.number_width = w.0 as u8;
    }
    set(&mut d.block_delete, b.block_delete);
}

/// `[numbers]` and `[numbers.address.X]`: every address's format and the decimals, each count of
/// decimals within `max_digits` (the error at the value that broke it).
fn numbers(file: &str, text: &str, d: &mut Dialect, n: NumberKeys) -> Result<(), String> {
    let all = Format {
        digits: None,
        max: None,
        kind: None,
        point: n.point,
        trailing_zeros: n.trailing_zeros,
        leading_zero: n.leading_zero,
        plus: n.plus,
        width: n.width,
    };
    for (i, fmt) in d.numbers.iter_mut().enumerate() {
        // Codes and integer addresses keep their own format unless named below.
        if matches!(
            Letter::ALL[i].class(),
            fmsvm_block::AddressClass::Linear
                | fmsvm_block::AddressClass::Angular
                | fmsvm_block::AddressClass::Feed
        ) {
            all.apply(fmt);
        }
    }
    // Where each count of decimals was set in this file (the base's own are consistent).
    let mut written: [Option<usize>; 3] = [None; 3];
    for (i, (key, to)) in [
        (&n.mm_digits, &mut d.mm_digits),
        (&n.inch_digits, &mut d.inch_digits),
        (&n.angle_digits, &mut d.angle_digits),
    ]
    .into_iter()
    .enumerate()
    {
        if let Some(v) = key {
            *to = v.get_ref().0 as u32;
            written[i] = Some(v.span().start);
        }
    }
    let max_at = n.max_digits.as_ref().map(|v| v.span().start);
    if let Some(v) = &n.max_digits {
        d.max_digits = v.get_ref().0 as u32;
    }
    for (name, fmt) in n.address.unwrap_or_default() {
        let Some(letter) = Letter::ALL.iter().find(|l| l.as_str() == name.get_ref()) else {
            return Err(format!(
                "{}: no address `{}` (the letters A–Z, or ,A ,C ,R)",
                at(file, text, name.span().start),
                name.get_ref()
            ));
        };
        fmt.apply(&mut d.numbers[letter.index()]);
        if fmt.kind == Some(KindName::Linear) {
            d.kinds[letter.index()] = AddressKind::Linear;
        }
        if let Some(v) = &fmt.max {
            let k = &mut d.kinds[letter.index()];
            let AddressKind::Integer { max } = k else {
                return Err(format!(
                    "{}: [numbers.address.{}]: max is for integer addresses (S T M H D N P L O …)",
                    at(file, text, v.span().start),
                    letter.as_str()
                ));
            };
            *max = v.get_ref().0;
        }
        if let Some(v) = &fmt.digits {
            let digits = v.get_ref().0 as u32;
            d.address_digits[letter.index()] = Some(digits as u8);
            if digits > d.max_digits {
                return Err(format!(
                    "{}: [numbers.address.{}]: digits = {digits} does not fit max_digits = {}",
                    at(file, text, v.span().start),
                    letter.as_str(),
                    d.max_digits
                ));
            }
        }
    }
    let named = [
        ("mm_digits", d.mm_digits),
        ("inch_digits", d.inch_digits),
        ("angle_digits", d.angle_digits),
    ];
    for ((key, digits), here) in named.into_iter().zip(written) {
        if digits > d.max_digits {
            // At the value that set the decimals, or else at the max_digits that lowered the
            // limit under the base's decimals.
            let place = here
                .or(max_at)
                .map_or(file.to_string(), |o| at(file, text, o));
            return Err(format!(
                "{place}: [numbers]: {key} = {digits} does not fit max_digits = {}",
                d.max_digits
            ));
        }
    }
    // The base's own per-address decimals, under a max_digits lowered here.
    let too_many = d
        .address_digits
        .iter()
        .enumerate()
        .find_map(|(i, v)| v.filter(|&v| u32::from(v) > d.max_digits).map(|v| (i, v)));
    if let Some((i, v)) = too_many {
        let place = max_at.map_or(file.to_string(), |o| at(file, text, o));
        return Err(format!(
            "{place}: [numbers]: max_digits = {} is less than the {v} decimals of address {}",
            d.max_digits,
            Letter::ALL[i].as_str()
        ));
    }
    Ok(())
}

/// `[motion]`: arcs, helices, dwells, inch, cycles, native cycles, the reference return.
fn motion(file: &str, text: &str, d: &mut Dialect, m: MotionKeys) -> Result<(), String> {
    if let Some(a) = m.arcs {
        d.arcs = match a {
            Arcs::Ijk => ArcForm::Ijk,
            Arcs::Radius => ArcForm::Radius,
            Arcs::Chords => ArcForm::Linearize,
        };
    }
    if let Some(h) = m.helix {
        d.helix = match h {
            Helix::Axis => HelixForm::Axis,
            Helix::Pitch => HelixForm::Pitch,
            Helix::Chords => HelixForm::Linearize,
        };
    }
    if let Some(c) = m.full_circle {
        d.circle_by_centre = matches!(c, FullCircle::Centre);
    }
    if let Some(c) = m.centre {
        d.centre_absolute = matches!(c, CentreName::Absolute);
    }
    if let Some(w) = m.work_offsets {
        d.control_work = matches!(w, OffsetsBy::Control);
    }
    if let Some(w) = m.tool_length {
        d.control_length = matches!(w, OffsetsBy::Control);
    }
    if let Some(t) = m.thread {
        d.mill_thread = match t {
            MillThreadName::None => fmsvm_emit::dialect::MillThread::None,
            MillThreadName::G01G33F => fmsvm_emit::dialect::MillThread::G1G33F,
        };
    }
    if let Some(k) = m.skip {
        use fmsvm_emit::dialect::SkipForm;
        d.skip = match k {
            SkipName::None => SkipForm::None,
            SkipName::G31 => SkipForm::G31,
            SkipName::G01G32 => SkipForm::G01G32,
            SkipName::G38_3 => SkipForm::G38_3,
        };
    }
    if let Some(w) = m.dwell {
        d.dwell = match w {
            Dwell::PMilliseconds => DwellForm::Milliseconds,
            Dwell::PSeconds => DwellForm::PSeconds,
            Dwell::XSeconds => DwellForm::XSeconds,
            Dwell::FSeconds => DwellForm::FSeconds,
            Dwell::ETenths => DwellForm::ETenths,
            Dwell::KHundredths => DwellForm::KHundredths,
        };
    }
    set(&mut d.inch, m.inch);
    set(&mut d.cycles, m.cycles);
    if let Some(list) = m.native_cycles {
        let mut codes = Vec::new();
        for name in list {
            let code = match name.get_ref().as_str() {
                "G81" => Code::G81,
                "G82" => Code::G82,
                "G85" => Code::G85,
                "G89" => Code::G89,
                other => {
                    return Err(format!(
                        "{}: `{other}` cannot be written as a native cycle (G81 G82 G85 G89 can)",
                        at(file, text, name.span().start)
                    ));
                }
            };
            codes.push(code);
        }
        d.native_cycles = codes;
    }
    if let Some(list) = m.start_modes {
        let mut codes = Vec::new();
        for name in list {
            let code = name
                .get_ref()
                .strip_prefix('G')
                .and_then(|t| t.parse::<f64>().ok())
                .and_then(Code::of)
                .ok_or_else(|| {
                    format!(
                        "{}: start_modes: `{}` is not a G code (G94, G40 …)",
                        at(file, text, name.span().start),
                        name.get_ref()
                    )
                })?;
            codes.push(code);
        }
        d.start_modes = codes;
    }
    if let Some(list) = m.corners {
        let place = at(file, text, list.span().start);
        let codes: Option<Vec<Code>> = list
            .get_ref()
            .iter()
            .map(|name| {
                name.strip_prefix('G')
                    .and_then(|t| t.parse::<f64>().ok())
                    .and_then(Code::of)
            })
            .collect();
        d.corners = match codes.as_deref() {
            Some([]) => None,
            Some(&[once, exact, cutting]) => Some([once, exact, cutting]),
            _ => {
                return Err(format!(
                    "{place}: corners: three G codes, the control's exact stop on one block, exact stop until cancelled and cutting mode (Fanuc's G09, G61, G64), or [] for none"
                ));
            }
        };
    }
    if let Some(t) = m.travel {
        d.travel = fmsvm_emit::travel::parse(t.get_ref())
            .map_err(|e| format!("{}: travel: {e}", at(file, text, t.span().start)))?;
    }
    if let Some(f) = m.cycle_form {
        d.cycle_form = match f {
            Form::Fanuc => CycleForm::Fanuc,
            Form::Fms3000 => CycleForm::Fms3000,
        };
    }
    if let Some(r) = m.reference_return {
        d.reference = match r {
            Reference::G91G28 => ReferenceForm::Incremental,
            Reference::MachineZero => ReferenceForm::MachineZero,
            Reference::None => ReferenceForm::None,
        };
    }
    Ok(())
}

fn set<T>(field: &mut T, value: Option<T>) {
    if let Some(v) = value {
        *field = v;
    }
}

/// The profile as a file: every key, so that reading it back gives the same dialect.
pub fn show(p: &Profile) -> String {
    let mut s = String::new();
    for section in [
        show_head,
        show_program,
        show_numbers,
        show_motion,
        show_lathe,
        show_cycles,
    ] {
        section(&mut s, p);
    }
    s
}

/// A string as TOML writes it (quoted, escaped).
fn q(v: &str) -> String {
    toml::Value::String(v.to_string()).to_string()
}

/// A list of strings as TOML writes it.
fn q_list(v: &[String]) -> String {
    format!(
        "[{}]",
        v.iter().map(|x| q(x)).collect::<Vec<_>>().join(", ")
    )
}

/// `dialects --show`: The head: the name, the summary, what the dialect is.
fn show_head(s: &mut String, p: &Profile) {
    let d = &p.dialect;
    let _ = writeln!(
        s,
        "# The dialect {} with every key (fmsvm dialects --show).",
        d.name
    );
    let _ = writeln!(s, "name = {}", q(&d.name));
    let _ = writeln!(s, "summary = {}", q(&d.summary));
    let _ = writeln!(s, "literal = {}", d.literal);
    let _ = writeln!(s, "haas = {}", d.haas);
    let _ = writeln!(s, "compact = {}", d.compact);
    let _ = writeln!(
        s,
        "machine = {}",
        q(match d.machine {
            MachineKind::Mill => "mill",
            MachineKind::Lathe => "lathe",
            MachineKind::Both => "both",
        })
    );
}

/// `dialects --show`: `[program]` and `[blocks]`.
fn show_program(s: &mut String, p: &Profile) {
    let d = &p.dialect;
    let _ = writeln!(s, "\n[program]");
    let _ = writeln!(s, "header = {}", q_list(&d.header));
    let _ = writeln!(s, "footer = {}", q_list(&d.footer));
    let _ = writeln!(s, "number = {}", q(&d.program_number));
    let _ = writeln!(s, "header_comment = {}", d.header_comment);
    let _ = writeln!(s, "end_required = {}", d.end_required);
    if let Some(c) = p.charset {
        let _ = writeln!(s, "charset = {}", q(c.name()));
    }
    let _ = writeln!(s, "\n[blocks]");
    let _ = writeln!(
        s,
        "end = {}",
        q(if d.eol == "\r\n" { "crlf" } else { "lf" })
    );
    let _ = writeln!(s, "max_length = {}", d.max_block.unwrap_or(0));
    let _ = writeln!(s, "separator = {}", q(&d.separator));
    let (numbers, start, step) = match d.line_numbers {
        LineNumbers::Keep => ("keep", 10, 10),
        LineNumbers::Off => ("off", 10, 10),
        LineNumbers::Renumber { start, step } => ("renumber", start, step),
    };
    let _ = writeln!(s, "numbers = {}", q(numbers));
    let _ = writeln!(s, "start = {start}\nstep = {step}");
    let _ = writeln!(s, "width = {}", d.number_width);
    let _ = writeln!(s, "block_delete = {}", d.block_delete);
}

/// `dialects --show`: `[numbers]` and each address that differs from its class.
fn show_numbers(s: &mut String, p: &Profile) {
    let d = &p.dialect;
    let _ = writeln!(s, "\n[numbers]");
    let x = d.numbers[Letter::X.index()];
    write_format(s, &x);
    let _ = writeln!(s, "mm_digits = {}", d.mm_digits);
    let _ = writeln!(s, "inch_digits = {}", d.inch_digits);
    let _ = writeln!(s, "angle_digits = {}", d.angle_digits);
    let _ = writeln!(s, "max_digits = {}", d.max_digits);
    for (i, f) in d.numbers.iter().enumerate() {
        let l = Letter::ALL[i];
        let default = match l.class() {
            fmsvm_block::AddressClass::Linear
            | fmsvm_block::AddressClass::Angular
            | fmsvm_block::AddressClass::Feed => x,
            _ => NumberFormat::FANUC,
        };
        let digits = d.address_digits[i];
        let max = match d.kinds[i] {
            AddressKind::Integer { max } if max != fmsvm_canon::decode::integer_max(l) => Some(max),
            _ => None,
        };
        let linear =
            d.kinds[i] == AddressKind::Linear && l.class() != fmsvm_block::AddressClass::Linear;
        if *f != default || digits.is_some() || max.is_some() || linear {
            let _ = writeln!(s, "\n[numbers.address.{}]", q(l.as_str()));
            if linear {
                let _ = writeln!(s, "kind = \"linear\"");
            }
            write_format(s, f);
            if let Some(v) = digits {
                let _ = writeln!(s, "digits = {v}");
            }
            if let Some(v) = max {
                let _ = writeln!(s, "max = {v}");
            }
        }
    }
}

/// `dialects --show`: `[comments]` and `[motion]`.
fn show_motion(s: &mut String, p: &Profile) {
    let d = &p.dialect;
    let _ = writeln!(s, "\n[comments]");
    let style = match d.comments {
        CommentStyle::Paren => "paren",
        CommentStyle::Semicolon => "semicolon",
        CommentStyle::None => "none",
    };
    let _ = writeln!(s, "style = {}", q(style));
    if !d.active_comments.is_empty() {
        let words: Vec<String> = d.active_comments.iter().map(|w| q(w)).collect();
        let _ = writeln!(s, "active = [{}]", words.join(", "));
    }
    let _ = writeln!(s, "\n[motion]");
    let arcs = match d.arcs {
        ArcForm::Ijk => "ijk",
        ArcForm::Radius => "radius",
        ArcForm::Linearize => "chords",
    };
    let helix = match d.helix {
        HelixForm::Axis => "axis",
        HelixForm::Pitch => "pitch",
        HelixForm::Linearize => "chords",
    };
    let dwell = match d.dwell {
        DwellForm::Milliseconds => "p-milliseconds",
        DwellForm::PSeconds => "p-seconds",
        DwellForm::XSeconds => "x-seconds",
        DwellForm::FSeconds => "f-seconds",
        DwellForm::ETenths => "e-tenths",
        DwellForm::KHundredths => "k-hundredths",
    };
    let full_circle = if d.circle_by_centre {
        "centre"
    } else {
        "end-point"
    };
    let centre = if d.centre_absolute {
        "absolute"
    } else {
        "incremental"
    };
    let thread = match d.mill_thread {
        fmsvm_emit::dialect::MillThread::None => "none",
        fmsvm_emit::dialect::MillThread::G1G33F => "g01-g33-f",
    };
    let _ = writeln!(
        s,
        "arcs = {}\nhelix = {}\nfull_circle = {}\ncentre = {}\nthread = {}\nskip = {}\ndwell = {}",
        q(arcs),
        q(helix),
        q(full_circle),
        q(centre),
        q(thread),
        q(d.skip.name()),
        q(dwell)
    );
    let _ = writeln!(s, "inch = {}", d.inch);
    let _ = writeln!(s, "cycles = {}", q_list(&d.cycles));
    let native: Vec<String> = d.native_cycles.iter().map(|c| format!("G{c}")).collect();
    let _ = writeln!(s, "native_cycles = {}", q_list(&native));
    let start: Vec<String> = d.start_modes.iter().map(|c| format!("G{c}")).collect();
    let _ = writeln!(s, "start_modes = {}", q_list(&start));
    let _ = writeln!(s, "travel = {}", q(&fmsvm_emit::travel::text(&d.travel)));
    let corners: Vec<String> = d
        .corners
        .iter()
        .flatten()
        .map(|c| format!("G{c}"))
        .collect();
    let _ = writeln!(s, "corners = {}", q_list(&corners));
    let form = match d.cycle_form {
        CycleForm::Fanuc => "fanuc",
        CycleForm::Fms3000 => "fms3000",
    };
    let _ = writeln!(s, "cycle_form = {}", q(form));
    let reference = match d.reference {
        ReferenceForm::Incremental => "g91-g28",
        ReferenceForm::MachineZero => "machine-zero",
        ReferenceForm::None => "none",
    };
    let _ = writeln!(s, "reference_return = {}", q(reference));
    let by = |control| if control { "control" } else { "resolved" };
    let _ = writeln!(
        s,
        "work_offsets = {}\ntool_length = {}",
        q(by(d.control_work)),
        q(by(d.control_length))
    );
}

/// `dialects --show`: `[lathe]`, for a lathe's dialect.
fn show_lathe(s: &mut String, p: &Profile) {
    let d = &p.dialect;
    if let Some(l) = &d.lathe {
        let _ = writeln!(s, "\n[lathe]");
        let _ = writeln!(
            s,
            "x = {}",
            q(if l.diameter { "diameter" } else { "radius" })
        );
        let codes = match l.codes {
            CodeSystem::LatheA => "fanuc-a",
            CodeSystem::LatheB => "fanuc-b",
            CodeSystem::Mill => "iso",
        };
        let _ = writeln!(s, "codes = {}", q(codes));
        let _ = writeln!(s, "frame = {}", q(&l.frame));
        let css = match l.css {
            CssForm::Native => "native",
            CssForm::Rpm => "rpm",
        };
        let clamp = match l.clamp {
            ClampForm::G50 => "G50",
            ClampForm::G92 => "G92",
            ClampForm::D => "D",
            ClampForm::Lims => "LIMS",
        };
        let thread = match l.thread {
            ThreadForm::F => "F",
            ThreadForm::K => "K",
            ThreadForm::Din => "din",
            ThreadForm::None => "none",
        };
        let tool = match l.tool {
            ToolForm::Fanuc => "fanuc",
            ToolForm::LinuxCnc => "linuxcnc",
            ToolForm::TD => "t-d",
        };
        let _ = writeln!(
            s,
            "css = {}\nclamp = {}\nthread = {}\ntool = {}\nmetric = {}\ninch = {}\nfloating_tap = {}\ny_axis = {}",
            q(css),
            q(clamp),
            q(thread),
            q(tool),
            q(&l.metric),
            q(&l.inch),
            l.floating_tap,
            l.y_axis
        );
        if let Some(r) = l.max_rpm {
            let _ = writeln!(s, "max_rpm = {r}");
        }
    }
}

/// `dialects --show`: `[[cycle]]`: the machine cycles.
fn show_cycles(s: &mut String, p: &Profile) {
    for c in &p.cycles {
        let _ = writeln!(
            s,
            "\n[[cycle]]\nnumber = {}\nname = {}\ncomment = {}\ntype = {}\ntool = {}\nprofile = {}\nsource = {}\nkeep_profile = {}",
            c.number,
            q(&c.name),
            q(&c.comment),
            q(&c.kind),
            q(&c.tool),
            q(&c.profile),
            q(&c.source),
            c.keep_profile
        );
        if let Some(b) = &c.block {
            let _ = writeln!(s, "block = {}", q(b));
        }
        if let Some(m) = c.moves {
            let _ = writeln!(s, "moves = {}", q(m.name()));
        }
        s.push_str("parameters = [\n");
        for par in &c.parameters {
            let default = par
                .default
                .as_ref()
                .map_or(String::new(), |d| format!(", default = {}", q(d)));
            let role = par
                .role
                .as_ref()
                .map_or(String::new(), |r| format!(", role = {}", q(r)));
            let _ = writeln!(
                s,
                "  {{ name = {}, kind = {}, text = {}{default}{role}, values = {} }},",
                q(&par.name),
                q(&par.kind),
                q(&par.text),
                q_list(&par.values)
            );
        }
        s.push_str("]\n");
    }
}

fn write_format(s: &mut String, f: &NumberFormat) {
    let point = match f.point {
        Point::Always => "always",
        Point::WhenFractional => "when-fractional",
        Point::Never => "never",
    };
    let _ = writeln!(s, "point = \"{point}\"");
    let _ = writeln!(s, "trailing_zeros = {}", f.trailing_zeros);
    let _ = writeln!(s, "leading_zero = {}", f.leading_zero);
    let _ = writeln!(s, "plus = {}", f.plus);
    let _ = writeln!(s, "width = {}", f.width);
}

/// The one key read before the rest: which profile the file changes.
#[derive(Deserialize)]
struct Head {
    base: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    #[allow(dead_code)]
    base: Option<String>,
    name: Option<String>,
    summary: Option<String>,
    literal: Option<bool>,
    haas: Option<bool>,
    compact: Option<bool>,
    program: Option<ProgramKeys>,
    blocks: Option<BlockKeys>,
    numbers: Option<NumberKeys>,
    comments: Option<CommentKeys>,
    motion: Option<MotionKeys>,
    machine: Option<MachineName>,
    lathe: Option<LatheKeys>,
    /// The machine cycles of another built-in profile, before this one's own `[[cycle]]`.
    cycles_of: Option<String>,
    cycle: Option<Vec<crate::catalogue::CycleKeys>>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum MachineName {
    Mill,
    Lathe,
    Both,
}

#[derive(Deserialize, Clone, Copy, PartialEq)]
#[serde(rename_all = "kebab-case")]
enum LatheXName {
    Diameter,
    Radius,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum Codes {
    FanucA,
    FanucB,
    Iso,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum Css {
    Native,
    Rpm,
}

#[derive(Deserialize, Clone, Copy)]
enum Clamp {
    G50,
    G92,
    D,
    #[serde(rename = "LIMS")]
    Lims,
}

#[derive(Deserialize, Clone, Copy)]
enum Thread {
    F,
    K,
    #[serde(rename = "din")]
    Din,
    #[serde(rename = "none")]
    None,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LatheKeys {
    x: Option<LatheXName>,
    codes: Option<Codes>,
    frame: Option<String>,
    css: Option<Css>,
    clamp: Option<Clamp>,
    thread: Option<Thread>,
    tool: Option<Tool>,
    metric: Option<String>,
    inch: Option<String>,
    max_rpm: Option<f64>,
    floating_tap: Option<bool>,
    y_axis: Option<bool>,
}

#[derive(Deserialize, Clone, Copy)]
enum Tool {
    #[serde(rename = "fanuc")]
    Fanuc,
    #[serde(rename = "linuxcnc")]
    Linuxcnc,
    #[serde(rename = "t-d")]
    TD,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ProgramKeys {
    header: Option<Vec<String>>,
    footer: Option<Vec<String>>,
    number: Option<String>,
    header_comment: Option<bool>,
    end_required: Option<bool>,
    charset: Option<CharsetName>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum CharsetName {
    #[serde(rename = "utf-8")]
    Utf8,
    Ascii,
    Latin1,
    Cp1251,
    Cp866,
    #[serde(rename = "koi8-r")]
    Koi8R,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum Eol {
    Lf,
    Crlf,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum Numbering {
    Keep,
    Off,
    Renumber,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BlockKeys {
    end: Option<Eol>,
    max_length: Option<Bounded<0, 65_535>>,
    separator: Option<String>,
    numbers: Option<Numbering>,
    start: Option<Bounded<0, 99_999_999>>,
    step: Option<Bounded<1, 99_999>>,
    width: Option<Bounded<0, 9>>,
    block_delete: Option<bool>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum PointName {
    Always,
    WhenFractional,
    Never,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct NumberKeys {
    point: Option<PointName>,
    trailing_zeros: Option<bool>,
    leading_zero: Option<bool>,
    plus: Option<bool>,
    width: Option<Bounded<0, 9>>,
    mm_digits: Option<Spanned<Bounded<0, 6>>>,
    inch_digits: Option<Spanned<Bounded<0, 6>>>,
    angle_digits: Option<Spanned<Bounded<0, 6>>>,
    max_digits: Option<Spanned<Bounded<1, 9>>>,
    address: Option<BTreeMap<Spanned<String>, Format>>,
}

#[derive(Deserialize, Clone)]
#[serde(deny_unknown_fields)]
struct Format {
    /// Decimals of this address (per address only).
    #[serde(default)]
    digits: Option<Spanned<Bounded<0, 6>>>,
    point: Option<PointName>,
    trailing_zeros: Option<bool>,
    leading_zero: Option<bool>,
    plus: Option<bool>,
    width: Option<Bounded<0, 9>>,
    /// The largest value of an integer address (S, T, M, H, D, N …; per address only).
    #[serde(default)]
    max: Option<Spanned<Bounded<0, 99_999_999>>>,
    /// The address is a length on this control, written with a point (per address only: a Haas
    /// lathe's D, the depth of its one-block cycles).
    #[serde(default)]
    kind: Option<KindName>,
}

/// What an address's number is, where a control differs from Fanuc's language.
#[derive(Deserialize, Clone, Copy, PartialEq)]
#[serde(rename_all = "kebab-case")]
enum KindName {
    Linear,
}

impl Format {
    fn apply(&self, f: &mut NumberFormat) {
        if let Some(p) = self.point {
            f.point = match p {
                PointName::Always => Point::Always,
                PointName::WhenFractional => Point::WhenFractional,
                PointName::Never => Point::Never,
            };
        }
        set(&mut f.trailing_zeros, self.trailing_zeros);
        set(&mut f.leading_zero, self.leading_zero);
        set(&mut f.plus, self.plus);
        if let Some(w) = self.width {
            f.width = w.0 as u8;
        }
    }
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum Style {
    Paren,
    Semicolon,
    None,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CommentKeys {
    style: Option<Style>,
    active: Option<Vec<String>>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum Arcs {
    Ijk,
    Radius,
    Chords,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum Helix {
    Axis,
    Pitch,
    Chords,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum Dwell {
    PMilliseconds,
    PSeconds,
    XSeconds,
    FSeconds,
    ETenths,
    KHundredths,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MotionKeys {
    arcs: Option<Arcs>,
    helix: Option<Helix>,
    full_circle: Option<FullCircle>,
    centre: Option<CentreName>,
    thread: Option<MillThreadName>,
    skip: Option<SkipName>,
    dwell: Option<Dwell>,
    inch: Option<bool>,
    cycles: Option<Vec<String>>,
    native_cycles: Option<Vec<Spanned<String>>>,
    start_modes: Option<Vec<Spanned<String>>>,
    travel: Option<Spanned<String>>,
    corners: Option<Spanned<Vec<String>>>,
    cycle_form: Option<Form>,
    reference_return: Option<Reference>,
    work_offsets: Option<OffsetsBy>,
    tool_length: Option<OffsetsBy>,
}

/// Who applies an offset: fmsvm, writing resolved positions, or the control, from its own
/// registers that the output names.
#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum OffsetsBy {
    Resolved,
    Control,
}

#[derive(Deserialize, Clone, Copy)]
enum SkipName {
    #[serde(rename = "none")]
    None,
    #[serde(rename = "g31")]
    G31,
    #[serde(rename = "g01-g32")]
    G01G32,
    #[serde(rename = "g38.3")]
    G38_3,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum MillThreadName {
    None,
    #[serde(rename = "g01-g33-f")]
    G01G33F,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum CentreName {
    Incremental,
    Absolute,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum FullCircle {
    EndPoint,
    Centre,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum Reference {
    #[serde(rename = "g91-g28")]
    G91G28,
    MachineZero,
    None,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum Form {
    Fanuc,
    Fms3000,
}

/// A whole number from `LO` to `HI`; anything else is an error at its position.
#[derive(Clone, Copy, Debug)]
struct Bounded<const LO: u64, const HI: u64>(u64);

impl<'de, const LO: u64, const HI: u64> Deserialize<'de> for Bounded<LO, HI> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = i64::deserialize(d)?;
        if v < LO as i64 || v > HI as i64 {
            return Err(serde::de::Error::custom(format!(
                "{v} is out of range: {LO} to {HI}"
            )));
        }
        Ok(Bounded(v as u64))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_builtin_reads_and_shows_back_to_itself() {
        for (name, _) in list() {
            let p = builtin(&name).unwrap();
            assert_eq!(p.dialect.name, name);
            if p.kind == Kind::Text {
                let shown = show(&p);
                let again = load("shown.toml", &shown).unwrap();
                assert_eq!(
                    again, p,
                    "{name}: the shown profile reads back the same:\n{shown}"
                );
            }
        }
    }

    /// A Haas lathe's D is the depth of its one-block cycles: a length with a point (`D0.05`),
    /// not Fanuc's offset number; `max` is for integer addresses only.
    #[test]
    fn an_address_may_be_a_length_on_one_control() {
        let p = builtin("haaslathe").unwrap();
        assert_eq!(p.dialect.kinds[Letter::D.index()], AddressKind::Linear);
        assert!(p.dialect.haas);
        assert!(show(&p).contains("[numbers.address.\"D\"]\nkind = \"linear\""));
        let e = load(
            "my.toml",
            "base = \"haaslathe\"\n[numbers.address.D]\nmax = 99\n",
        )
        .unwrap_err();
        assert!(
            e.starts_with("my.toml:3:7:") && e.contains("max is for integer addresses"),
            "{e}"
        );
        assert!(!builtin("fanuc0itd").unwrap().dialect.haas);
    }

    #[test]
    fn a_profile_changes_its_base() {
        let p = load(
            "my.toml",
            "base = \"fms3000\"\nname = \"mine\"\n[blocks]\nnumbers = \"renumber\"\nstep = 5\n",
        )
        .unwrap();
        assert_eq!(p.dialect.eol, "\r\n", "CR LF from the base");
        assert_eq!(
            p.dialect.line_numbers,
            LineNumbers::Renumber { start: 10, step: 5 }
        );
        assert_eq!(p.dialect.helix, HelixForm::Pitch);
    }

    #[test]
    fn an_address_may_have_its_own_decimals() {
        let p = load(
            "my.toml",
            "[numbers.address.F]\ndigits = 1
",
        )
        .unwrap();
        assert_eq!(p.dialect.digits(Letter::F, false), 1);
        assert_eq!(p.dialect.digits(Letter::X, false), 3);
        assert_eq!(load("shown.toml", &show(&p)).unwrap(), p, "shows back");
        let e = load(
            "my.toml",
            "[numbers]\nmax_digits = 4\n[numbers.address.F]\ndigits = 5\n",
        )
        .unwrap_err();
        assert_eq!(
            e,
            "my.toml:4:10: [numbers.address.F]: digits = 5 does not fit max_digits = 4"
        );
        // Each error points at the value that made it.
        let e = load("my.toml", "[numbers]\nmax_digits = 4\nmm_digits = 5\n").unwrap_err();
        assert_eq!(
            e,
            "my.toml:3:13: [numbers]: mm_digits = 5 does not fit max_digits = 4"
        );
        // The base's 4 inch decimals, under a limit lowered here: at the limit.
        let e = load("my.toml", "name = \"x\"\n[numbers]\nmax_digits = 3\n").unwrap_err();
        assert_eq!(
            e,
            "my.toml:3:14: [numbers]: inch_digits = 4 does not fit max_digits = 3"
        );
        let e = load("my.toml", "[numbers.address.F]\ndigits = 5\n");
        assert!(e.is_ok(), "5 decimals fit the base's 8 digits: {e:?}");
        // The base's own per-address decimals, under a limit lowered by an override file.
        let base = load("base.toml", "[numbers.address.F]\ndigits = 5\n").unwrap();
        let e = parse(
            "my.toml",
            "[numbers]\nmax_digits = 4\nmm_digits = 2\ninch_digits = 3\n",
            base,
        )
        .unwrap_err();
        assert_eq!(
            e,
            "my.toml:2:14: [numbers]: max_digits = 4 is less than the 5 decimals of address F"
        );
    }

    #[test]
    fn errors_name_line_and_column() {
        let e = load("my.toml", "name = \"x\"\n[blocks]\nend = \"cr\"\n").unwrap_err();
        assert!(e.starts_with("my.toml:3:7:"), "{e}");
        let e = load("my.toml", "[numbers]\nmm_digits = 12\n").unwrap_err();
        assert!(
            e.starts_with("my.toml:2:13:") && e.contains("out of range"),
            "{e}"
        );
        let e = load("my.toml", "[motion]\nspeed = 1\n").unwrap_err();
        assert!(e.starts_with("my.toml:2:1:") && e.contains("speed"), "{e}");
        let e = load("my.toml", "[numbers.address.Q9]\nwidth = 2\n").unwrap_err();
        assert!(e.starts_with("my.toml:1:18:") && e.contains("Q9"), "{e}");
        let e = load("my.toml", "base = \"haas\"\n").unwrap_err();
        assert!(
            e.starts_with("my.toml:1:8:") && e.contains("no dialect `haas`"),
            "{e}"
        );
    }
}
