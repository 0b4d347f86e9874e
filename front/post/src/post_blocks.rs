//! An ordinary block of the neutral language in the control's words: each code translated by its
//! meaning through the control's table (its dialect profile's `[lathe]`, `[motion] dwell` and number
//! formats), never passed on by its number; a code the table does not have is refused at its word
//! (docs/postprocessor.md, "The controls' words").

use fmsvm_block::{Code, Letter};
use fmsvm_canon::modal::CodeSystem;
use fmsvm_emit::dialect::{ClampForm, CssForm, Dialect, LatheForm};

use crate::post_words::number_word;
use fmsvm_driver::neutral::{At, Error, Plain, Word};

/// The neutral codes fmsvm does not convert: G66 (the spindle's zero, not Fanuc's macro call),
/// G08/G09 (acceleration and deceleration: Fanuc's G08 is look-ahead control, its G09 an exact stop
/// in one block).
const NOT_CONVERTED: [(f64, &str); 3] = [
    (8.0, "G08 (acceleration)"),
    (9.0, "G09 (deceleration)"),
    (66.0, "G66 (synchronisation with the spindle's zero)"),
];

/// The control's table and what the program has said so far that changes how a block is written.
pub struct Translator<'d> {
    dialect: &'d Dialect,
    lathe: &'d LatheForm,
    /// The machine's highest spindle speed (`--max-rpm`, or the profile's `[lathe] max_rpm`).
    max_rpm: Option<f64>,
    /// The clamp is written.
    clamped: bool,
    /// G96 is in force.
    css: bool,
    /// The tool in the turret, once called.
    tool: Option<u32>,
}

impl<'d> Translator<'d> {
    /// The table of `dialect`, which must write turning.
    pub fn new(dialect: &'d Dialect, max_rpm: Option<f64>) -> Result<Self, String> {
        let lathe = dialect.lathe.as_ref().ok_or_else(|| {
            format!(
                "{}: the dialect writes no turning ([lathe]): fmsvm post writes for a lathe control",
                dialect.name
            )
        })?;
        Ok(Translator {
            dialect,
            lathe,
            max_rpm: max_rpm.or(lathe.max_rpm),
            clamped: false,
            css: false,
            tool: None,
        })
    }

    /// Constant surface speed is in force (a thread needs constant rpm).
    pub fn css(&self) -> bool {
        self.css
    }

    /// The words every program starts with, so that none of the library's meanings rests on the
    /// control's power-on state: the frame (plane, absolute, diameter programming: `[lathe] frame`),
    /// millimetres (`[lathe] metric`; the neutral program is in mm) and feed per revolution (the
    /// neutral F is per revolution: `F1.2`).
    pub fn start(&self) -> Vec<String> {
        let mut words: Vec<String> = self
            .lathe
            .frame
            .split_whitespace()
            .map(str::to_string)
            .collect();
        if !self.lathe.metric.is_empty() && !words.contains(&self.lathe.metric) {
            words.push(self.lathe.metric.clone());
        }
        words.push(self.code(Code::G95));
        words
    }

    /// A code of `meaning` as the control writes it (G99 for feed per revolution in Fanuc's
    /// G-code system A), two digits at least as the library writes them.
    fn code(&self, meaning: Code) -> String {
        let c = self.lathe.codes.written(meaning);
        if c.tenths().is_multiple_of(10) {
            format!("G{:02}", c.tenths() / 10)
        } else {
            format!("G{c}")
        }
    }

    /// The control's code for `meaning`, when its table reads it back as that meaning (no code is
    /// written by its number alone).
    fn code_of(&self, meaning: Code) -> Option<String> {
        let written = self.lathe.codes.written(meaning);
        (self.lathe.codes.meaning(written) == Some(meaning)).then(|| self.code(meaning))
    }

    /// A G word of the neutral language in the control's codes (or the line before it: a spindle
    /// clamp); refused where the control has no code of its meaning.
    fn g_word(
        &mut self,
        w: &Word,
        lines: &mut Vec<String>,
        out: &mut Vec<String>,
    ) -> Result<(), Error> {
        let err = |at: At, what: String| Error { at, what };
        if let Some((_, t)) = NOT_CONVERTED.iter().find(|(g, _)| *g == w.value) {
            return Err(err(
                w.at,
                format!(
                    "{t}: not converted: the control has no code of that meaning known to fmsvm"
                ),
            ));
        }
        match w.value as u32 {
            g @ 0..=3 => out.push(self.code(Code::from_tenths(g * 10))),
            4 => out.push(self.code(Code::G4)),
            g @ 40..=42 => match self.code_of(Code::from_tenths(g * 10)) {
                Some(c) => out.push(c),
                None => {
                    return Err(err(w.at, format!("G{g}: not in the control's table")));
                }
            },
            80 => {
                if let Some(c) = self.code_of(Code::G80) {
                    out.push(c);
                }
            }
            // Absolute dimensions: G90 where the control has the code; in Fanuc's
            // G-code system A absolute is X Z themselves (U W the increments) and G90
            // is the outer/inner diameter cutting cycle (0i-TD G-code list).
            90 => {
                if self.lathe.codes != CodeSystem::LatheA {
                    out.push(self.code(Code::G90));
                }
            }
            96 => {
                if self.lathe.css != CssForm::Native {
                    return Err(err(
                        w.at,
                        "G96 (constant surface speed): this control has none known ([lathe] css = \"rpm\"): have the library write the spindle speed in rpm (G97)".into(),
                    ));
                }
                if !self.clamped {
                    let Some(max) = self.max_rpm else {
                        return Err(err(
                            w.at,
                            format!(
                                "G96 (constant surface speed) with no spindle clamp: the neutral program cannot give one and the {} does not clamp the spindle at power-on (Fanuc lathe manuals, \"Clamp of maximum spindle speed\"): give the machine's highest speed, `--max-rpm N` (the launcher's OPTIONS) or `[lathe] max_rpm` in a profile of your own",
                                self.dialect.name
                            ),
                        ));
                    };
                    match self.clamp_line(max) {
                        Some(l) => lines.push(l),
                        None => out.push(format!("D{}", max.round() as u64)),
                    }
                    self.clamped = true;
                }
                self.css = true;
                out.push(self.code(Code::G96));
            }
            97 => {
                self.css = false;
                if self.lathe.css == CssForm::Native {
                    out.push(self.code(Code::G97));
                }
            }
            _ => {
                return Err(err(
                    w.at,
                    format!("G{}: not in the neutral language", w.text),
                ));
            }
        }
        Ok(())
    }

    /// G04's X (seconds) as the control's dwell word, within what the word holds.
    fn dwell_x(&self, w: &Word) -> Result<String, Error> {
        let err = |at: At, what: String| Error { at, what };
        if w.value < 0.0 {
            return Err(err(
                w.at,
                format!("G04 X{}: a dwell's time is not negative", w.text),
            ));
        }
        let form = self.dialect.dwell;
        if let Some(most) = form.most_a_block()
            && (w.value * form.units_per_second()).round() > most as f64
        {
            return Err(err(
                w.at,
                format!(
                    "G04 X{}: longer than the control's dwell word holds ({} s)",
                    w.text,
                    most as f64 / form.units_per_second()
                ),
            ));
        }
        Ok(dwell_word(w.value, self.dialect.dwell))
    }

    /// The lines of block `p` (a clamp line before a G96 block where none was written).
    /// `centre` is an arc's centre (X radius, Z) and `from` where it starts, worked out by the
    /// caller: an arc is written with I K from the start whatever the library wrote (I K or R).
    pub fn block(
        &mut self,
        p: &Plain,
        arc: Option<([f64; 2], [f64; 2])>,
    ) -> Result<Vec<String>, Error> {
        let err = |at: At, what: String| Error { at, what };
        let dwell = p.has_g(4.0);
        let mut lines = Vec::new();
        let mut out: Vec<String> = Vec::with_capacity(p.words.len() + 1);
        let mut arc_written = false;
        let x_scale = if self.lathe.diameter { 1.0 } else { 0.5 };
        let number =
            |l: Letter, v: f64, w: &Word| number_word(self.dialect, l, v).map_err(|m| err(w.at, m));
        for w in &p.words {
            match w.letter {
                'G' => self.g_word(w, &mut lines, &mut out)?,
                'M' => out.push(format!("M{:02}", w.value as u32)),
                'T' => {
                    let (text, tool) = self
                        .lathe
                        .tool_call(w.value, self.tool)
                        .map_err(|m| err(w.at, m))?;
                    self.tool = Some(tool);
                    out.push(text);
                }
                'S' => {
                    let max = self.dialect.integer_max(Letter::S);
                    if w.value.fract() != 0.0 || w.value < 0.0 || w.value > max as f64 {
                        return Err(err(
                            w.at,
                            format!(
                                "S{}: a whole number from 0 to {max} on this control",
                                w.text
                            ),
                        ));
                    }
                    out.push(format!("S{}", w.value as u64));
                }
                'X' if dwell => out.push(self.dwell_x(w)?),
                'P' if dwell => {
                    return Err(err(
                        w.at,
                        "G04 P: the unit of a dwell's P is not documented for the neutral language (seconds or milliseconds): fmsvm reads G04 X<seconds>".into(),
                    ));
                }
                'P' => {
                    return Err(err(
                        w.at,
                        "P outside a cycle record: no meaning in the neutral language".into(),
                    ));
                }
                'X' => out.push(number(Letter::X, w.value * x_scale, w)?),
                'Z' => out.push(number(Letter::Z, w.value, w)?),
                'F' => out.push(number(Letter::F, w.value, w)?),
                'I' | 'K' | 'R' => {
                    let Some((from, centre)) = arc else {
                        return Err(err(
                            w.at,
                            format!("{}: an arc's word in a block that is no arc", w.letter),
                        ));
                    };
                    if !arc_written {
                        arc_written = true;
                        // I on the radius, as the neutral language and every lathe dialect write it.
                        out.push(number(Letter::I, centre[0] - from[0], w)?);
                        out.push(number(Letter::K, centre[1] - from[1], w)?);
                    }
                }
                _ => {
                    return Err(err(
                        w.at,
                        format!("{}: not in the neutral language", w.letter),
                    ));
                }
            }
        }
        if !out.is_empty() {
            lines.push(out.join(" "));
        }
        Ok(lines)
    }

    /// The clamp `max` rpm as the control writes it on a line of its own (None: on the G96 block,
    /// LinuxCNC's `G96 D`).
    fn clamp_line(&self, max: f64) -> Option<String> {
        let rpm = max.round() as u64;
        match self.lathe.clamp {
            // G50 S in system A, G92 S in system B: the coordinate-setting code's meaning.
            ClampForm::G50 => Some(format!("{} S{rpm}", self.code(Code::G92))),
            ClampForm::G92 => Some(format!("G92 S{rpm}")),
            ClampForm::Lims => Some(format!("LIMS={rpm}")),
            ClampForm::D => None,
        }
    }
}

/// A dwell of `seconds` as the control writes it (the dialect's `[motion] dwell`).
fn dwell_word(seconds: f64, form: fmsvm_emit::dialect::DwellForm) -> String {
    let units = (seconds.max(0.0) * form.units_per_second()).round();
    let value = if form.whole_units() {
        format!("{units}")
    } else {
        // Seconds, to the millisecond, trailing zeros off (`P1.5`, `X2.`).
        let t = format!("{:.3}", units / form.units_per_second());
        t.trim_end_matches('0').to_string()
    };
    format!("{}{value}", form.letter())
}
