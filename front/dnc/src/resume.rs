//! `--start-at N`: the modal state a control needs to resume at block N, read from the text of the
//! blocks before it, and the preamble that restores it (docs/dnc.md "Resuming").
//!
//! The scanner is dialect-agnostic: it reads words as a letter and a number, skips `(…)` comments and
//! what follows `;`, and classifies G codes by the kernel's one table of modal groups
//! (`fmsvm_canon::modal`), M codes by `fmsvm_block::Code`. It restores
//! only what it recognised; where a resume cannot be made safe (a canned cycle, cutter compensation,
//! rotation, scaling, mirror or polar coordinates in force) it refuses and names the block to resume
//! from instead.

use fmsvm_block::{AXES_ARE_DATA, Code};
use fmsvm_canon::modal::{self, Group, ModalState};

/// One word of a block: its letter (upper case), its text as written (`G01`, `X-10.5`) and value.
#[derive(Debug, Clone, PartialEq)]
pub struct Word<'a> {
    pub letter: u8,
    pub text: &'a str,
    pub value: f64,
}

/// The words of one line: a letter followed by a number; comments, `,R`-style words and anything
/// else are skipped.
pub fn words(line: &str) -> Vec<Word<'_>> {
    let b = line.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let mut depth = 0usize;
    while i < b.len() {
        let c = b[i];
        match c {
            b'(' => depth += 1,
            b')' => depth = depth.saturating_sub(1),
            b';' if depth == 0 => break,
            b',' if depth == 0 => {
                // `,R5.` `,C2.`: corner words; skip the letter so that it is not read as R or C.
                i += 1;
                if i < b.len() && b[i].is_ascii_alphabetic() {
                    i += 1;
                }
                continue;
            }
            _ if depth == 0 && c.is_ascii_alphabetic() => {
                let start = i;
                let mut j = i + 1;
                if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
                    j += 1;
                }
                let digits = j;
                while j < b.len() && (b[j].is_ascii_digit() || b[j] == b'.') {
                    j += 1;
                }
                if j > digits
                    && let Ok(value) = line[digits..j].parse::<f64>()
                {
                    let value = if b[digits - 1] == b'-' { -value } else { value };
                    out.push(Word {
                        letter: c.to_ascii_uppercase(),
                        text: &line[start..j],
                        value,
                    });
                }
                i = j.max(start + 1);
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    out
}

/// A modal setting: the words that set it, as written, and the block that set it.
#[derive(Debug, Clone, PartialEq)]
struct Set {
    text: String,
    block: u64,
}

impl Set {
    fn new(text: impl Into<String>, block: u64) -> Option<Set> {
        Some(Set {
            text: text.into(),
            block,
        })
    }
}

/// The positioning axes tracked (for absolute programs).
const AXES: [u8; 6] = [b'X', b'Y', b'Z', b'A', b'B', b'C'];

/// An axis' last absolute value, or why it is not known.
#[derive(Debug, Clone, PartialEq)]
enum Axis {
    /// Never programmed.
    Unseen,
    /// The word of the last absolute move (`X10.5`).
    At(String),
    /// Lost at this block, for this reason.
    Unknown(u64, &'static str),
}

/// The modal state the scanner recognised, block after block.
#[derive(Debug, Clone)]
pub struct Modal {
    /// Blocks (lines) scanned.
    pub blocks: u64,
    /// Whether the first line is the tape start `%` (sent again before the preamble).
    pub starts_with_percent: bool,
    /// Every cycle block carries all its words and says where it ends (the FMS-3000's
    /// `G81 U Z I`, §4.1: I the exit point, U when I is absent): no cycle mode to restore, and
    /// the cycle axis known after the block.
    pub self_contained_cycles: bool,
    motion: Option<Set>,
    cycle: Option<Set>,
    cycle_seen: bool,
    plane: Option<Set>,
    distance: Option<Set>,
    units: Option<Set>,
    feed_mode: Option<Set>,
    work: Option<Set>,
    retract: Option<Set>,
    comp: Option<Set>,
    comp_seen: bool,
    length: Option<Set>,
    /// Rotation, scaling, mirror, polar coordinates in force (the group, the words).
    transforms: Vec<(Group, Set)>,
    shift: Option<Set>,
    f: Option<Set>,
    s: Option<Set>,
    spindle: Option<Set>,
    mist: bool,
    flood: bool,
    coolant_seen: bool,
    t: Option<Set>,
    /// The tool of the last M6.
    tool_change: Option<Set>,
    axes: [Axis; 6],
}

impl Default for Modal {
    fn default() -> Self {
        Modal {
            blocks: 0,
            starts_with_percent: false,
            self_contained_cycles: false,
            motion: None,
            cycle: None,
            cycle_seen: false,
            plane: None,
            distance: None,
            units: None,
            feed_mode: None,
            work: None,
            retract: None,
            comp: None,
            comp_seen: false,
            length: None,
            transforms: Vec::new(),
            shift: None,
            f: None,
            s: None,
            spindle: None,
            mist: false,
            flood: false,
            coolant_seen: false,
            t: None,
            tool_change: None,
            axes: std::array::from_fn(|_| Axis::Unseen),
        }
    }
}

/// What `--start-at` sends before block N, and what the operator must know.
#[derive(Debug, Clone, PartialEq)]
pub struct Preamble {
    /// The restoring blocks, each without its end of block.
    pub lines: Vec<String>,
    /// Safety notes (printed before sending).
    pub notes: Vec<String>,
}

impl Modal {
    /// The modal G codes of block `k` (its words `words`), each in its group.
    fn modal_codes(&mut self, words: &[Word<'_>], k: u64) {
        let word = |l: u8| words.iter().find(|w| w.letter == l).map(|w| w.text);
        for w in words.iter().filter(|w| w.letter == b'G') {
            let Some(g) = Code::of(w.value).filter(|g| g.is_exact(w.value)) else {
                continue;
            };
            let Some(group) = modal::group(g) else {
                continue;
            };
            match group {
                Group::Motion => {
                    self.motion = Set::new(w.text, k);
                    self.cycle = None;
                }
                Group::CannedCycle if g == Code::G80 => self.cycle = None,
                Group::CannedCycle if self.self_contained_cycles => self.cycle_seen = true,
                Group::CannedCycle => {
                    // A cycle restated hole after hole is one mode since the block it began.
                    let since = self.cycle.as_ref().map_or(k, |c| c.block);
                    self.cycle = Set::new(w.text, since);
                    self.cycle_seen = true;
                }
                Group::Plane => self.plane = Set::new(w.text, k),
                Group::Distance => self.distance = Set::new(w.text, k),
                Group::Units => self.units = Set::new(w.text, k),
                Group::FeedMode => self.feed_mode = Set::new(w.text, k),
                Group::WorkOffset if g == Code::G54_1 => {
                    let p = word(b'P').map_or(String::new(), |p| format!(" {p}"));
                    self.work = Set::new(format!("{}{p}", w.text), k);
                }
                Group::WorkOffset => self.work = Set::new(w.text, k),
                Group::ReturnLevel => self.retract = Set::new(w.text, k),
                Group::CutterComp => {
                    let since = self.comp.as_ref().map_or(k, |c| c.block);
                    self.comp = if g == Code::G40 {
                        None
                    } else {
                        Set::new(w.text, since)
                    };
                    self.comp_seen = true;
                }
                Group::LengthComp if g == Code::G49 => self.length = Set::new(w.text, k),
                Group::LengthComp => {
                    let h = word(b'H').map_or(String::new(), |h| format!(" {h}"));
                    self.length = Set::new(format!("{}{h}", w.text), k);
                }
                // Polar coordinates, scaling, mirror, rotation: on, or their cancel.
                Group::Polar | Group::Scaling | Group::Mirror | Group::Rotation => {
                    self.transforms.retain(|(c, _)| *c != group);
                    if ModalState::default().get(group) != g
                        && let Some(s) = Set::new(w.text, k)
                    {
                        self.transforms.push((group, s));
                    }
                }
                _ => {}
            }
        }
    }

    /// Reads one line (a block) of the flat program.
    pub fn line(&mut self, line: &str) {
        self.blocks += 1;
        let k = self.blocks;
        let trimmed = line.trim();
        if k == 1 && trimmed == "%" {
            self.starts_with_percent = true;
        }
        if trimmed.starts_with('%') {
            return;
        }
        let words = words(line);
        let gs: Vec<Code> = words
            .iter()
            .filter(|w| w.letter == b'G')
            .filter_map(|w| Code::of(w.value))
            .collect();
        let has = |g: Code| gs.contains(&g);
        let word = |l: u8| words.iter().find(|w| w.letter == l).map(|w| w.text);
        self.modal_codes(&words, k);
        for w in &words {
            match w.letter {
                b'F' => self.f = Set::new(w.text, k),
                b'S' => self.s = Set::new(w.text, k),
                b'T' => self.t = Set::new(w.text, k),
                b'M' => match Code::of_integer(w.value) {
                    Some(Code::M3 | Code::M4 | Code::M5) => self.spindle = Set::new(w.text, k),
                    Some(Code::M6) => {
                        self.tool_change = self.t.clone().map(|t| Set { block: k, ..t })
                    }
                    Some(Code::M7) => {
                        self.mist = true;
                        self.coolant_seen = true;
                    }
                    Some(Code::M8) => {
                        self.flood = true;
                        self.coolant_seen = true;
                    }
                    Some(Code::M9) => {
                        self.mist = false;
                        self.flood = false;
                        self.coolant_seen = true;
                    }
                    _ => {}
                },
                _ => {}
            }
        }
        // Positions: the codes whose axis words are data carry no position (the shifts are read
        // below: after G92 the words are where the tool stands, after G52 and the G92.1 preset
        // it is not known); reference returns, machine coordinates and skip moves end where the
        // text does not say; a canned cycle ends at its retract level; an incremental move loses
        // the absolute value.
        let shifts = has(Code::G52) || has(Code::G92) || has(Code::G92_1);
        if has(Code::G11) || (AXES_ARE_DATA.iter().any(|&c| has(c)) && !shifts) {
            return;
        }
        let lost: Option<&'static str> = if has(Code::G28) || has(Code::G30) {
            Some("a reference return")
        } else if has(Code::G53) {
            Some("a move in machine coordinates (G53)")
        } else if has(Code::G31) {
            Some("a skip move (G31)")
        } else if has(Code::G52) {
            Some("a local coordinate shift (G52)")
        } else if has(Code::G92_1) {
            Some("a work coordinate system preset (G92.1)")
        } else if self.cycle.is_some() {
            None
        } else if self
            .distance
            .as_ref()
            .is_some_and(|d| code_of(&d.text) == Some(Code::G91))
        {
            Some("an incremental move")
        } else {
            None
        };
        if has(Code::G92) || has(Code::G52) {
            let code = if has(Code::G92) { "G92" } else { "G52" };
            self.shift = Set::new(code, k);
        }
        let in_cycle = self.cycle.is_some();
        for w in &words {
            let Some(i) = AXES.iter().position(|a| *a == w.letter) else {
                continue;
            };
            self.axes[i] = match lost {
                Some(why) => Axis::Unknown(k, why),
                None if in_cycle && w.letter == b'Z' => Axis::Unknown(k, "a canned cycle"),
                None => Axis::At(w.text.to_string()),
            };
        }
        if in_cycle && words.iter().any(|w| AXES.contains(&w.letter)) {
            self.axes[2] = Axis::Unknown(k, "a canned cycle (it ends at its retract level)");
        }
        // A self-contained cycle block ends at I, or at U without it (absolute values; its Z is
        // the bottom of the hole). FMS-3000 Table 11: the cycle axis is Z in G17.
        let cycle_block = gs
            .iter()
            .any(|g| modal::group(*g) == Some(Group::CannedCycle) && *g != Code::G80);
        if self.self_contained_cycles && cycle_block {
            let plane_xy = self
                .plane
                .as_ref()
                .is_none_or(|p| code_of(&p.text) == Some(Code::G17));
            self.axes[2] = match (word(b'I').or(word(b'U')), &lost, plane_xy) {
                (Some(end), None, true) => Axis::At(format!("Z{}", &end[1..])),
                _ => Axis::Unknown(k, "a canned cycle"),
            };
        }
    }

    /// The blocks that move the tool back to where block `n` starts, in G0: X Y (and the rotary
    /// axes) first, then Z with the tool length compensation in force; none in G91. Says whether
    /// any axis was positioned; an axis that is not known is a note, and a length compensation
    /// over an unknown Z a refusal.
    fn position(
        &self,
        n: u64,
        incremental: bool,
        length_on: Option<&Set>,
        lines: &mut Vec<String>,
        notes: &mut Vec<String>,
    ) -> Result<bool, String> {
        let mut positioned = false;
        if incremental {
            notes.push(format!(
                "the program is incremental (G91) at block {n}: no position is restored; the tool \
                 must stand exactly where block {n} starts"
            ));
            if let Some(l) = length_on {
                notes.push(format!(
                    "tool length compensation ({}) is not restored in incremental mode: set it up \
                     as the program had it",
                    l.text
                ));
            }
        } else {
            let mut xy = vec!["G0".to_string()];
            for (i, a) in self.axes.iter().enumerate() {
                if i == 2 {
                    continue;
                }
                match a {
                    Axis::At(t) => xy.push(t.clone()),
                    Axis::Unknown(b, why) => notes.push(format!(
                        "{} is not known before block {n} (after {why} at block {b}); it is not \
                         positioned",
                        AXES[i] as char
                    )),
                    Axis::Unseen => {}
                }
            }
            if xy.len() > 1 {
                positioned = true;
                push(lines, xy);
            }
            match &self.axes[2] {
                Axis::At(z) => {
                    let mut line = vec!["G0".to_string()];
                    if let Some(l) = length_on {
                        line.push(l.text.clone());
                    }
                    line.push(z.clone());
                    positioned = true;
                    push(lines, line);
                }
                other => {
                    if let Some(l) = length_on {
                        return Err(format!(
                            "tool length compensation {} is in force at block {n} but the Z \
                             position before it is not known; resume at an earlier block that \
                             moves Z",
                            l.text
                        ));
                    }
                    if let Axis::Unknown(b, why) = other {
                        notes.push(format!(
                            "Z is not known before block {n} (after {why} at block {b}); Z stays \
                             where it is"
                        ));
                    }
                }
            }
        }
        Ok(positioned)
    }

    /// The blocks that restore the state before block `n` (this scanner has read blocks 1 to n−1),
    /// or why a resume at `n` cannot be made safe.
    pub fn preamble(&self, n: u64) -> Result<Preamble, String> {
        // The first block a resume is accepted at: where the earliest of the modes a preamble
        // cannot restore began (each is a continuous mode since then, restatements included).
        let first = [self.cycle.as_ref(), self.comp.as_ref()]
            .into_iter()
            .flatten()
            .chain(self.transforms.iter().map(|(_, t)| t))
            .map(|s| s.block)
            .min()
            .unwrap_or(n);
        let refuse = |what: String, s: &Set| {
            Err(format!(
                "{what} is in force at block {n} (since block {}); resume at block {first} or \
                 earlier, or after it is cancelled",
                s.block
            ))
        };
        if let Some(c) = &self.cycle {
            return refuse(format!("canned cycle {}", c.text), c);
        }
        if let Some(c) = &self.comp {
            return refuse(format!("cutter compensation {}", c.text), c);
        }
        if let Some((group, t)) = self.transforms.first() {
            let what = match group {
                Group::Polar => "polar coordinates",
                Group::Scaling => "scaling",
                Group::Mirror => "mirroring",
                _ => "coordinate rotation",
            };
            return refuse(format!("{what} ({})", t.text), t);
        }
        let mut lines = Vec::new();
        let mut notes = Vec::new();
        let incremental = self
            .distance
            .as_ref()
            .is_some_and(|d| code_of(&d.text) == Some(Code::G91));
        let length_on = self
            .length
            .as_ref()
            .filter(|l| matches!(code_of(first_word(&l.text)), Some(Code::G43 | Code::G44)));
        // 1. The modal G codes the program set, cancels included.
        let mut g: Vec<String> = [
            &self.plane,
            &self.units,
            &self.distance,
            &self.feed_mode,
            &self.work,
            &self.retract,
        ]
        .into_iter()
        .flatten()
        .map(|s| s.text.clone())
        .collect();
        if self.comp_seen {
            g.push("G40".into());
        }
        if self.cycle_seen {
            g.push("G80".into());
        }
        if let Some(l) = &self.length
            && length_on.is_none()
        {
            g.push(l.text.clone());
        }
        push(&mut lines, g);
        // 2. The tool, the spindle, the coolant.
        if let Some(t) = &self.t {
            push(&mut lines, vec![t.text.clone()]);
        }
        push(
            &mut lines,
            [&self.s, &self.spindle]
                .into_iter()
                .flatten()
                .map(|s| s.text.clone())
                .collect(),
        );
        if self.coolant_seen {
            let mut c = Vec::new();
            if self.mist {
                c.push("M7".to_string());
            }
            if self.flood {
                c.push("M8".to_string());
            }
            if c.is_empty() {
                c.push("M9".to_string());
            }
            push(&mut lines, c);
        }
        // 3. The position: X Y (and rotary axes) first, then Z (with tool length compensation).
        let positioned = self.position(n, incremental, length_on, &mut lines, &mut notes)?;
        // 4. The motion mode and the feed, last (positioning left G0 in force).
        let motion = self.motion.as_ref().map(|m| m.text.clone());
        let mut last = Vec::new();
        match motion {
            Some(m) if !(positioned && code_of(&m) == Some(Code::G0)) => last.push(m),
            _ => {}
        }
        if let Some(f) = &self.f {
            last.push(f.text.clone());
        }
        push(&mut lines, last);
        if let Some(s) = &self.shift {
            notes.push(format!(
                "the program shifted its coordinates ({} at block {}); the preamble assumes the \
                 shift is still in force on the control",
                s.text, s.block
            ));
        }
        if let Some(t) = &self.tool_change {
            notes.push(format!(
                "the tool in the spindle must be {} (the tool change at block {}); the preamble \
                 changes no tool",
                t.text, t.block
            ));
        }
        Ok(Preamble { lines, notes })
    }
}

fn push(lines: &mut Vec<String>, words: Vec<String>) {
    if !words.is_empty() {
        lines.push(words.join(" "));
    }
}

fn first_word(text: &str) -> &str {
    text.split_whitespace().next().unwrap_or("")
}

/// The code of a G word's text (`G01` and `G1.0` are G1).
fn code_of(text: &str) -> Option<Code> {
    words(text).first().and_then(|w| Code::of(w.value))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(text: &str) -> Modal {
        let mut m = Modal::default();
        for l in text.lines() {
            m.line(l);
        }
        m
    }

    #[test]
    fn words_are_letters_and_numbers() {
        let w = words("N10 G01 X-1.5 Y.5 (COMMENT X9) ,R2. F300 ; Z7");
        let t: Vec<&str> = w.iter().map(|w| w.text).collect();
        assert_eq!(t, ["N10", "G01", "X-1.5", "Y.5", "F300"]);
        assert_eq!(w[2].value, -1.5);
        assert_eq!(words("g54.1 p2")[0].letter, b'G');
        assert!(words("%").is_empty());
    }

    #[test]
    fn an_absolute_program_restores_modes_tool_spindle_and_position() {
        let m = state(
            "%\nO1\nT1 M6\nG17 G21 G90 G94 G54\nS1000 M3\nM8\nG0 X10. Y20.\nG43 Z50. H1\n\
             G1 Z-1. F200.\nX30.\n",
        );
        assert!(m.starts_with_percent);
        let p = m.preamble(11).expect("resumable");
        assert_eq!(
            p.lines,
            [
                "G17 G21 G90 G94 G54",
                "T1",
                "S1000 M3",
                "M8",
                "G0 X30. Y20.",
                "G0 G43 H1 Z-1.",
                "G1 F200."
            ]
        );
        assert!(p.notes.iter().any(|n| n.contains("must be T1")), "{p:?}");
    }

    #[test]
    fn incremental_programs_restore_no_position() {
        let m = state("G91 G1 X1. F100\nX1.\n");
        let p = m.preamble(3).expect("resumable");
        assert_eq!(p.lines, ["G91", "G1 F100"]);
        assert!(p.notes[0].contains("must stand exactly where block 3 starts"));
    }

    /// A bolt circle whose every hole restates G81 is one cycle mode since its first hole: the
    /// refusal names that block, the first a resume is accepted at (not the block before, which
    /// would be refused in turn).
    #[test]
    fn a_refusal_names_the_first_block_a_resume_is_accepted_at() {
        let text = "G90 G0 Z10.\nG41 D1 G1 X0 Y0 F100\nG40 G0 X0 Y0\n\
                    G99 G81 X10. Y0 Z-5. R1. F100\nG81 X0 Y10.\nG81 X-10. Y0\nG81 X0 Y-10.\n";
        let m = state(text);
        let e = m.preamble(8).unwrap_err();
        assert!(
            e.contains("(since block 4); resume at block 4 or earlier"),
            "{e}"
        );
        // And block 4 is accepted.
        let m = state(&text.lines().take(3).collect::<Vec<_>>().join("\n"));
        assert!(m.preamble(4).is_ok());
        // Under compensation begun at block 2 and a cycle begun at block 3: block 2.
        let m = state("G90 G0 Z10.\nG41 D1 G1 X0 Y0 F100\nG81 X1. Y1. Z-5. R1.\nX2.\n");
        let e = m.preamble(5).unwrap_err();
        assert!(e.contains("resume at block 2 or earlier"), "{e}");
    }

    /// The FMS-3000 writes every hole as a whole block, `G00 X Y G81 U Z I F` (§4.1: U the start
    /// of the feed, Z the bottom, I the exit point), so a resume at any hole needs no cycle mode:
    /// the control gets the cycle's every word in the block itself. The tool ends each hole at I.
    #[test]
    fn a_resume_inside_whole_cycle_blocks_is_accepted() {
        let text = "G90 G17 G94 G35 G40 G49 G80 G54\nG00 X0 Y0 Z10\n\
                    G00 X10 Y0 G81 U2 Z-5 I10 F100\nG00 X20 Y0 G81 U2 Z-5 I10 F100\n\
                    G00 X30 Y0 G81 U2 Z-5 I12 F100\n";
        let mut m = Modal {
            self_contained_cycles: true,
            ..Modal::default()
        };
        for l in text.lines().take(4) {
            m.line(l);
        }
        let p = m.preamble(5).expect("resumable inside the cycle");
        assert!(p.lines.iter().any(|l| l == "G0 X20 Y0"), "{p:?}");
        assert!(p.lines.iter().any(|l| l == "G0 Z10"), "{p:?}");
        // The same text read as Fanuc's (a modal cycle, begun again by each block's G00 G81) is
        // refused.
        let e = state(&text.lines().take(4).collect::<Vec<_>>().join("\n"))
            .preamble(5)
            .unwrap_err();
        assert!(e.contains("canned cycle G81 is in force at block 5"), "{e}");
        // A G91 cycle block says no absolute end.
        let mut m = Modal {
            self_contained_cycles: true,
            ..Modal::default()
        };
        m.line("G91 G00 X10 G81 U-8 Z-15 I15 F100");
        assert!(matches!(m.axes[2], Axis::Unknown(..)));
    }

    #[test]
    fn cycles_compensation_and_rotation_refuse() {
        let e = state("G90 G0 Z10.\nG81 X1. Y1. Z-5. R1. F100\nX2.\n")
            .preamble(4)
            .unwrap_err();
        assert!(
            e.contains("canned cycle G81") && e.contains("block 2"),
            "{e}"
        );
        // After G80 the cycle is gone, and Z is lost (the cycle ends at its retract level).
        let p = state("G90 G0 Z10.\nG81 X1. Y1. Z-5. R1. F100\nG80\n")
            .preamble(4)
            .expect("resumable");
        assert!(p.lines.contains(&"G0 X1. Y1.".to_string()), "{p:?}");
        assert!(p.notes.iter().any(|n| n.starts_with("Z is not known")));
        let e = state("G41 D1 G1 X1. F10\n").preamble(2).unwrap_err();
        assert!(e.contains("cutter compensation G41"), "{e}");
        let e = state("G68 X0 Y0 R30.\n").preamble(2).unwrap_err();
        assert!(e.contains("coordinate rotation"), "{e}");
        assert!(state("G68 X0 Y0 R30.\nG69\n").preamble(3).is_ok());
    }

    /// G92.1 X0 presets the work coordinate system (Fanuc's workpiece coordinate system preset):
    /// the tool does not move and its position in the restored system is not in the text.
    #[test]
    fn a_preset_is_not_a_position() {
        let m = state("G90 G0 X5. Y5.\nG92.1 X0\n");
        let p = m.preamble(3).expect("resumable");
        assert!(
            p.notes.iter().any(|n| n.contains("X is not known")),
            "{p:?}"
        );
        assert!(p.lines.contains(&"G0 Y5.".to_string()), "{p:?}");
    }

    #[test]
    fn dwell_and_reference_returns_are_not_positions() {
        let m = state("G90 G0 X5. Y5.\nG4 X2.\nG28 Y0\n");
        let p = m.preamble(4).expect("resumable");
        assert!(p.lines.contains(&"G0 X5.".to_string()), "{p:?}");
        assert!(p.notes.iter().any(|n| n.contains("Y is not known")));
    }
}
