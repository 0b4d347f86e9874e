//! fmsvm-runtime: the kernel side of the pipeline. [`Kernel`] implements `fmsvm_block::Machine`: it
//! keeps the modal state and the positions, answers system variables, and hands each block to an
//! [`emit::Emitter`] that writes the flat program.
//!
//! This wave resolves no geometry: blocks are written as programmed (the literal emitter). Work offsets,
//! transforms, canned cycles and cutter compensation grow here, between `Kernel::block` and the emitter,
//! without touching the VM.
#![deny(missing_docs)]

pub mod canon;
pub mod comp;
pub mod decode;
pub mod dialect;
pub mod emit;
pub mod modal;
pub mod probe;
pub mod sysvars;
pub mod timing;

use fmsvm_block::{Alarm, Block, Flow, Letter, Machine, Stop, Word};

use decode::{DecimalInput, gcode, input_value};
use dialect::Dialect;
use emit::{Context, Emitter};
use modal::{Group, ModalState};

/// Axes tracked for position variables (#5001–#5006 → X Y Z A B C).
pub const AXES: [Letter; 6] = [
    Letter::X,
    Letter::Y,
    Letter::Z,
    Letter::A,
    Letter::B,
    Letter::C,
];

/// The index in `AXES` of an axis letter.
#[inline(always)]
fn axis_of(l: Letter) -> Option<usize> {
    const TABLE: [u8; Letter::COUNT] = {
        let mut t = [u8::MAX; Letter::COUNT];
        let mut i = 0;
        while i < AXES.len() {
            t[AXES[i] as usize] = i as u8;
            i += 1;
        }
        t
    };
    match TABLE[l.index()] {
        u8::MAX => None,
        i => Some(i as usize),
    }
}

/// Non-modal G codes whose axis words are not an end point (dwell, data setting, shifts, reference
/// returns, machine coordinates, macro call).
const AXES_NOT_A_MOVE: [u16; 9] = [40, 100, 520, 920, 280, 300, 290, 530, 650];

/// The kernel: modal state, positions and system variables in front of an emitter.
pub struct Kernel<E: Emitter> {
    emitter: E,
    dialect: Dialect,
    decimal_input: DecimalInput,
    modal: ModalState,
    /// Programmed end point of the last block, work coordinates.
    position: [f64; AXES.len()],
    /// Last value of each address (#4102–#4130 read from it).
    last: [f64; Letter::COUNT],
    /// Work offsets #5201–#5326 (external and G54–G59), stored as written.
    work_offsets: [f64; sysvars::WORK_OFFSETS],
    program_number: Option<u32>,
    /// Estimated machining time, and the clock the program reads.
    timing: timing::Timing,
    /// #3003, #3004 as last written (S7).
    flags_3003_3004: [f64; 2],
    /// `#3006` messages shown so far: (number, text).
    messages: Vec<(u32, String)>,
    /// What stops a G31 skip move.
    probe: probe::ProbeModel,
    /// Skip position of the last G31 (#5061–#5066).
    skip: [f64; AXES.len()],
    /// Things the user should know that are not errors (G31 without a model…).
    warnings: Vec<String>,
}

impl<E: Emitter> Kernel<E> {
    /// A kernel at power-on state writing to `emitter`.
    pub fn new(emitter: E, dialect: Dialect, decimal_input: DecimalInput) -> Self {
        Kernel {
            emitter,
            dialect,
            decimal_input,
            modal: ModalState::default(),
            position: [0.0; AXES.len()],
            last: [fmsvm_block::VACANT; Letter::COUNT],
            work_offsets: [0.0; sysvars::WORK_OFFSETS],
            program_number: None,
            timing: timing::Timing::default(),
            flags_3003_3004: [0.0; 2],
            messages: Vec::new(),
            probe: probe::ProbeModel::None,
            skip: [0.0; AXES.len()],
            warnings: Vec::new(),
        }
    }

    /// Sets the probe model for G31.
    pub fn set_probe(&mut self, model: probe::ProbeModel) {
        self.probe = model;
    }

    /// Warnings of the run so far.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// Sets the date and time #3011/#3012 read (YYYYMMDD, HHMMSS): fixed for the run, so output is
    /// reproducible.
    pub fn set_clock(&mut self, date: u32, time: u32) {
        self.timing.date = date;
        self.timing.time = time;
    }

    /// Sets the rapid traverse rate (mm/min) used to estimate machining time.
    pub fn set_rapid_rate(&mut self, mm_per_min: f64) {
        self.timing.rapid = mm_per_min;
    }

    /// Times motion for #3001/#3002 and `machining_seconds` (on by default; off saves time per block
    /// when nothing reads them).
    pub fn set_timing(&mut self, on: bool) {
        self.timing.enabled = on;
    }

    /// Estimated machining time so far, seconds (feed moves at F, rapids at the rapid rate, dwells).
    pub fn machining_seconds(&self) -> f64 {
        self.timing.total_seconds
    }

    /// The `#3006` messages of the run.
    pub fn messages(&self) -> &[(u32, String)] {
        &self.messages
    }

    /// #3003 and #3004 as the program left them (non-zero at the end deserves a warning, S7).
    pub fn flags_3003_3004(&self) -> [f64; 2] {
        self.flags_3003_3004
    }

    /// Starts the output of program `number`.
    pub fn begin(&mut self, number: Option<u32>, title: &str) -> Result<(), Stop> {
        self.program_number = number;
        self.emitter.begin(number, title)
    }

    /// Ends the output.
    pub fn end(&mut self) -> Result<(), Stop> {
        self.emitter.end()
    }

    /// The emitter back.
    pub fn into_emitter(self) -> E {
        self.emitter
    }

    /// The emitter.
    pub fn emitter(&self) -> &E {
        &self.emitter
    }

    /// The modal state.
    pub fn modal(&self) -> &ModalState {
        &self.modal
    }

    /// Programmed position (work coordinates) of X Y Z A B C.
    pub fn position(&self) -> [f64; AXES.len()] {
        self.position
    }
}

impl<E: Emitter> Machine for Kernel<E> {
    fn block(&mut self, block: &Block<'_>) -> Result<Flow, Stop> {
        // Step 1: G codes by group (a later code of the same group wins, as on Fanuc).
        let mut non_modal: Option<u16> = None;
        for w in block.words() {
            if w.letter == Letter::G {
                let code = gcode(w.value)?;
                if modal::group(code) == Some(Group::NonModal) {
                    non_modal = Some(code);
                }
                self.modal.set(code);
            }
        }
        let inch = self.modal.inch();
        // Step 2: the block goes out.
        self.emitter.block(block, &Context { inch })?;
        // Step 3: positions and last values.
        let moves = !non_modal.is_some_and(|c| AXES_NOT_A_MOVE.contains(&c));
        let incremental = self.modal.incremental();
        let start = self.position;
        let mut moved = false;
        let mut flow = Flow::Continue;
        for w in block.words() {
            let v = input_value(&self.dialect, self.decimal_input, w, inch);
            self.last[w.letter.index()] = v;
            if moves && let Some(axis) = axis_of(w.letter) {
                self.position[axis] = if incremental {
                    self.position[axis] + v
                } else {
                    v
                };
                moved = true;
            }
            // M02, M30 end the program (M98/M99 are the VM's: they never reach here as literals).
            if w.letter == Letter::M && matches!(v.round() as i64, 2 | 30) {
                flow = Flow::End;
            }
        }
        // G31: the probe stops where the model says; the tool is there afterwards (S4, S9).
        if non_modal == Some(310) && moved {
            let end = [self.position[0], self.position[1], self.position[2]];
            let (at, touched) = probe::skip(&mut self.probe, [start[0], start[1], start[2]], end);
            if matches!(self.probe, probe::ProbeModel::None)
                && self.warnings.iter().all(|w| !w.starts_with("G31"))
            {
                self.warnings.push(format!(
                    "G31 at line {} without a probe model: the skip position #5061-#5066 is the programmed end point (give --stock or --probe-points)",
                    block.line
                ));
            } else if !touched {
                self.warnings.push(format!(
                    "G31 at line {}: the probe touched nothing on its way",
                    block.line
                ));
            }
            self.position[..3].copy_from_slice(&at);
            self.skip = self.position;
        }
        // A full circle (G2/G3 with I J K or R but no end point) moves too.
        let arc = matches!(self.modal.get(Group::Motion), 20 | 30)
            && block
                .words()
                .iter()
                .any(|w| matches!(w.letter, Letter::I | Letter::J | Letter::K | Letter::R));
        let moved = moved || (moves && arc);
        if moved {
            self.timing
                .motion(&self.modal, start, self.position, block, &self.last);
            if flow == Flow::Continue {
                flow = Flow::Moved;
            }
        } else if non_modal == Some(40) {
            self.timing.dwell(block);
        }
        Ok(flow)
    }

    fn argument(&self, word: &Word) -> f64 {
        input_value(&self.dialect, self.decimal_input, word, self.modal.inch())
    }

    fn message(&mut self, number: u32, text: &str) -> Result<(), Stop> {
        self.messages.push((number, text.to_string()));
        self.emitter.message(number, text)
    }

    fn read_system(&mut self, number: u32) -> Result<f64, Stop> {
        sysvars::read(self, number).map_err(Stop::from)
    }

    fn write_system(&mut self, number: u32, value: f64) -> Result<(), Stop> {
        sysvars::write(self, number, value).map_err(Stop::from)
    }

    fn increment(&self, letter: Letter) -> f64 {
        self.dialect.increment(letter, self.modal.inch())
    }
}

/// An alarm for a system variable fmsvm does not model.
fn not_modelled(number: u32) -> Alarm {
    Alarm::new(
        115,
        format!("system variable #{number} is not available in fmsvm"),
    )
}
