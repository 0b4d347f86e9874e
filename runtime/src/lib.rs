//! fmsvm-runtime: the kernel side of the pipeline. [`Kernel`] implements `fmsvm_block::Machine`: it
//! keeps the modal state and the positions, answers system variables, and hands each block to an
//! [`emit::Emitter`] that writes the flat program.
//!
//! This wave resolves no geometry: blocks are written as programmed (the literal emitter). Work offsets,
//! transforms, canned cycles and cutter compensation grow here, between `Kernel::block` and the emitter,
//! without touching the VM.
#![deny(missing_docs)]

pub mod dialect;
pub mod emit;
pub mod modal;
pub mod sysvars;

use fmsvm_block::{Alarm, Block, Flow, Letter, Machine, Stop};

use dialect::Dialect;
use emit::literal::{DecimalInput, gcode, input_value};
use emit::{Context, Emitter};
use modal::{ModalState, NON_MODAL};

/// Axes tracked for position variables (#5001–#5006 → X Y Z A B C).
pub const AXES: [Letter; 6] = [
    Letter::X,
    Letter::Y,
    Letter::Z,
    Letter::A,
    Letter::B,
    Letter::C,
];

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
        }
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
                if modal::group(code) == Some(NON_MODAL) {
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
        let mut flow = Flow::Continue;
        for w in block.words() {
            let v = input_value(&self.dialect, self.decimal_input, w, inch);
            self.last[w.letter.index()] = v;
            if moves && let Some(axis) = AXES.iter().position(|&a| a == w.letter) {
                self.position[axis] = if incremental {
                    self.position[axis] + v
                } else {
                    v
                };
            }
            // M02, M30 end the program; M99 in the main program restarts it on a control, which the
            // flat output keeps by writing the M99 (the run ends here).
            if w.letter == Letter::M && matches!(v.round() as i64, 2 | 30 | 99) {
                flow = Flow::End;
            }
        }
        Ok(flow)
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
