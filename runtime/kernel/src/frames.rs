//! Coordinate frames and offset registers: the external offset, G54–G59 and G54.1 P1–P48 work offsets,
//! the G52 local shift, the G92 shift, the G28/G30 reference positions, and the tool length and radius
//! registers (Fanuc memory C) with the active length offset. What a programmed point is in machine
//! coordinates is `origin() + point + length offset`.

use fmsvm_block::Alarm;
use fmsvm_block::alarms::FORMAT;

use fmsvm_canon::Pose;

/// Number of G54.1 P work offsets (Fanuc's standard 48).
pub const EXTENDED: usize = 48;
/// Number of tool registers (offset numbers 1–999; #2001–#2800 reach the first 200).
pub const TOOLS: usize = 999;
/// Number of reference positions (G28 is the first, G30 P2–P4 the others).
pub const REFERENCES: usize = 4;

/// Which work offset is active.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum WorkOffset {
    /// G54 (1) to G59 (6).
    Standard(u8),
    /// G54.1 P1–P48.
    Extended(u8),
}

/// The four registers of one offset number (memory C).
#[derive(Clone, Copy, Default, Debug, PartialEq)]
pub struct ToolRegister {
    /// Length, geometry (G10 L10, #2201 / #11001).
    pub length_geometry: f64,
    /// Length, wear (G10 L11, #2001 / #10001).
    pub length_wear: f64,
    /// Radius, geometry (G10 L12, #2601 / #13001).
    pub radius_geometry: f64,
    /// Radius, wear (G10 L13, #2401 / #12001).
    pub radius_wear: f64,
    /// A lathe tool's X and Z offsets, geometry (#2701/#2801, #15001/#16001), as the control
    /// holds them (fmsvm's output leaves them to the control, which applies them by T).
    pub xz_geometry: [f64; 2],
    /// A lathe tool's X and Z wear (#2001/#2101, #10001/#11001).
    pub xz_wear: [f64; 2],
    /// A lathe tool's imaginary tool nose direction, 0–9 (Fanuc's numbering; 0 and 9: the nose
    /// centre is the controlled point). The radius registers are its nose radius.
    pub tip: u8,
    /// Something set it (G10, a variable, `--offsets`): an offset number nobody set is a guess.
    pub set: bool,
}

impl ToolRegister {
    /// Length offset in effect (geometry + wear).
    pub fn length(&self) -> f64 {
        self.length_geometry + self.length_wear
    }

    /// Radius in effect (geometry + wear).
    pub fn radius(&self) -> f64 {
        self.radius_geometry + self.radius_wear
    }
}

/// The frames and registers of the control.
#[derive(Clone, Debug)]
pub struct Frames {
    /// External work offset (#5201–#5206, G10 L2 P0).
    pub external: Pose,
    /// G54–G59 (#5221–#5326, G10 L2 P1–P6).
    pub standard: [Pose; 6],
    /// G54.1 P1–P48 (#7001–#7946, G10 L20 P1–P48).
    pub extended: [Pose; EXTENDED],
    /// The active work offset.
    pub active: WorkOffset,
    /// G52 local shift.
    pub local: Pose,
    /// G92 shift.
    pub shift: Pose,
    /// Reference positions, machine coordinates (G28 = 1st, G30 P2–P4); NaN where not known.
    pub reference: [Pose; REFERENCES],
    /// Tool registers, offset numbers 1–999 (index 0 = number 1).
    pub tools: Vec<ToolRegister>,
    /// Active tool length offset along the tool axis (G43 +, G44 −, G49 0).
    pub length: f64,
    /// Which work offsets something set (G10, a variable, `--offsets`), by slot: 0 the external
    /// offset, 1–6 G54–G59, 7–54 G54.1 P1–P48. One nobody set is not known.
    pub work_set: [bool; SLOTS],
}

/// Work offset slots: the external offset, G54–G59, G54.1 P1–P48.
pub const SLOTS: usize = 1 + 6 + EXTENDED;

impl Default for Frames {
    fn default() -> Self {
        Frames {
            external: [0.0; 6],
            standard: [[0.0; 6]; 6],
            extended: [[0.0; 6]; EXTENDED],
            active: WorkOffset::Standard(1),
            local: [0.0; 6],
            shift: [0.0; 6],
            // Unknown until `--offsets` (or a test) gives them: never machine zero by assumption.
            reference: [[f64::NAN; 6]; REFERENCES],
            tools: vec![ToolRegister::default(); TOOLS],
            length: 0.0,
            work_set: [false; SLOTS],
        }
    }
}

impl Frames {
    /// The active work offset's values.
    pub fn work(&self) -> &Pose {
        match self.active {
            WorkOffset::Standard(n) => &self.standard[(n.clamp(1, 6) - 1) as usize],
            WorkOffset::Extended(p) => &self.extended[(p.clamp(1, EXTENDED as u8) - 1) as usize],
        }
    }

    /// The active work offset's slot (1–6 G54–G59, 7–54 G54.1 P1–P48).
    pub fn active_slot(&self) -> usize {
        match self.active {
            WorkOffset::Standard(n) => n.clamp(1, 6) as usize,
            WorkOffset::Extended(p) => 6 + p.clamp(1, EXTENDED as u8) as usize,
        }
    }

    /// The active work offset as a program names it (`G55`, `G54.1 P3`).
    pub fn active_name(&self) -> String {
        match self.active {
            WorkOffset::Standard(n) => format!("G{}", 53 + n),
            WorkOffset::Extended(p) => format!("G54.1 P{p}"),
        }
    }

    /// The origin of the active work system as the control holds it: external + work offset
    /// (without G52 and G92).
    pub fn work_origin(&self) -> Pose {
        let w = self.work();
        std::array::from_fn(|i| self.external[i] + w[i])
    }

    /// Where the program's zero is, machine coordinates: external + work offset + G52 + G92.
    pub fn origin(&self) -> Pose {
        let w = self.work();
        std::array::from_fn(|i| self.external[i] + w[i] + self.local[i] + self.shift[i])
    }

    /// The origin of G54 with the external offset: the frame resolved output is written in.
    pub fn g54_origin(&self) -> Pose {
        std::array::from_fn(|i| self.external[i] + self.standard[0][i])
    }

    /// The work offset a `G10 L2 P` or `L20 P` number sets.
    pub fn register_mut(&mut self, l: u32, p: f64) -> Result<&mut Pose, Alarm> {
        let n = p.round();
        let slot = match (l, n as i64) {
            (2, 0..=6) => n as usize,
            (20, 1..=48) => 6 + n as usize,
            _ => 0,
        };
        self.work_set[slot] |= matches!((l, n as i64), (2, 0..=6) | (20, 1..=48));
        match (l, n as i64) {
            (2, 0) => Ok(&mut self.external),
            (2, 1..=6) => Ok(&mut self.standard[n as usize - 1]),
            (20, 1..=48) => Ok(&mut self.extended[n as usize - 1]),
            _ => Err(Alarm::new(
                FORMAT,
                format!(
                    "G10 L{l} P{p}: the work offset number is {}",
                    if l == 2 { "0 to 6" } else { "1 to 48" }
                ),
            )),
        }
    }

    /// Tool register `n` (1–999).
    pub fn tool(&self, n: f64) -> Result<&ToolRegister, Alarm> {
        let i = n.round();
        if !(1.0..=TOOLS as f64).contains(&i) {
            return Err(Alarm::new(
                i_out_of_range(),
                format!("offset number {n} is out of range (1 to {TOOLS})"),
            ));
        }
        Ok(&self.tools[i as usize - 1])
    }

    /// Tool register `n` for writing.
    pub fn tool_mut(&mut self, n: f64) -> Result<&mut ToolRegister, Alarm> {
        self.tool(n)?;
        let t = &mut self.tools[n.round() as usize - 1];
        t.set = true;
        Ok(t)
    }
}

/// 0114 (G10 format) is used for data-setting numbers; an H or D number out of range is Fanuc's 0033
/// on some controls and 0043 on others; fmsvm says 0043 (ILLEGAL T/H/D CODE on the 0i series).
const fn i_out_of_range() -> u32 {
    43
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn origin_adds_every_offset() {
        let mut f = Frames {
            external: [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            ..Frames::default()
        };
        f.standard[1] = [10.0, 20.0, -5.0, 0.0, 0.0, 0.0];
        f.active = WorkOffset::Standard(2);
        f.local = [0.5, 0.0, 0.0, 0.0, 0.0, 0.0];
        f.shift = [0.0, 2.0, 0.0, 0.0, 0.0, 0.0];
        assert_eq!(f.origin()[..3], [11.5, 22.0, -5.0]);
        assert_eq!(f.g54_origin()[..3], [1.0, 0.0, 0.0]);
        assert!(f.register_mut(2, 7.0).is_err());
        assert!(f.register_mut(20, 48.0).is_ok());
        assert_eq!(f.tool(1000.0).unwrap_err().number, 43);
    }
}
