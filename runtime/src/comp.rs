//! Cutter radius compensation (placeholder until the compensation module lands: moves pass unchanged).

use fmsvm_block::Stop;

use crate::canon::{Arc, Plane, Pose};

/// G41 or G42.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Side {
    /// G41.
    Left,
    /// G42.
    Right,
}

/// The compensation rules.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum Style {
    /// Fanuc's.
    #[default]
    Fanuc,
    /// LinuxCNC's.
    LinuxCnc,
}

/// A move in the output frame.
#[derive(Clone, Copy, PartialEq, Debug)]
pub enum Move {
    /// Straight.
    Line {
        /// End point.
        to: Pose,
        /// At rapid rate.
        rapid: bool,
    },
    /// Circular.
    Arc(Arc),
}

/// The compensation state.
#[derive(Debug)]
pub struct Compensator {
    active: bool,
}

impl Compensator {
    /// Off.
    pub fn new(_style: Style) -> Self {
        Compensator { active: false }
    }
    /// On or holding moves.
    pub fn is_active(&self) -> bool {
        self.active
    }
    /// G41/G42.
    pub fn start(&mut self, _side: Side, _radius: f64, _plane: Plane) {
        self.active = true;
    }
    /// G40.
    pub fn cancel(&mut self) {
        self.active = false;
    }
    /// The next move.
    pub fn push(
        &mut self,
        _from: Pose,
        m: Move,
        out: &mut dyn FnMut(Move) -> Result<(), Stop>,
    ) -> Result<(), Stop> {
        out(m)
    }
    /// Lets held moves go.
    pub fn flush(&mut self, _out: &mut dyn FnMut(Move) -> Result<(), Stop>) -> Result<(), Stop> {
        Ok(())
    }
}
