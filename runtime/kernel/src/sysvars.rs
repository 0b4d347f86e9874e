//! System variables answered by the kernel: modal information #4001–#4130 and #4201–#4330 (S3, S8),
//! positions #5001–#5026 and #5041–#5046 (S4, S9), work offsets #5201–#5326 and #7001–#7946 (S5), tool
//! registers #2001–#2800 and #10001–#13999 (memory C).
//!
//! fmsvm expands without a look-ahead buffer, so the "pre-read" (#4001…) and "executing block"
//! (#4201…) sets give the same state: the one after the last expanded block; #5041 (current position)
//! equals #5001 (end point of the last block), as on a control with buffering off (S9).

use fmsvm_block::{Alarm, Letter, VACANT};

use crate::frames::{ToolRegister, WorkOffset};
use crate::{Kernel, not_modelled};
use fmsvm_canon::AXES;
use fmsvm_canon::Emitter;
use fmsvm_canon::Pose;

/// 0116 WRITE PROTECTED VARIABLE.
const WRITE_PROTECTED: u32 = 116;

/// #4101–#4130 → address letters (S3: #4102 B, #4107 D, #4108 E, #4109 F, #4111 H, #4113 M, #4114 N,
/// #4115 O, #4119 S, #4120 T).
fn modal_letter(k: u32) -> Option<Letter> {
    Some(match k {
        2 => Letter::B,
        7 => Letter::D,
        8 => Letter::E,
        9 => Letter::F,
        11 => Letter::H,
        13 => Letter::M,
        14 => Letter::N,
        15 => Letter::O,
        19 => Letter::S,
        20 => Letter::T,
        _ => return None,
    })
}

/// What system variable `n` is to fmsvm's kernel (a mill's numbering), for an editor's hover;
/// None for a number it does not model (locals and commons are the compiler's).
pub fn describe(n: u32) -> Option<String> {
    use fmsvm_canon::AXES;
    let axis = |k: u32| {
        AXES.get((k % 10).wrapping_sub(1) as usize)
            .map(|l| l.as_str())
    };
    let offset = |n: u32| -> Option<String> {
        let (slot, a) = offset_slot(n)?;
        let a = AXES.get(a)?;
        Some(match slot {
            0 => format!("the external work offset, {a}"),
            1..=6 => format!("the G{} work offset, {a}", 53 + slot),
            p => format!("the G54.1 P{} work offset, {a}", p - 6),
        })
    };
    Some(match n {
        3000 => {
            "#3000: a macro alarm (writing n raises alarm 3000 + n with the comment's text)".into()
        }
        3001 => "#3001: the millisecond clock (machining time, writable)".into(),
        3002 => "#3002: the hour clock (machining time, writable)".into(),
        3003 => "#3003: single-block and wait-for-completion suppression (0–3)".into(),
        3004 => "#3004: feed hold, override and exact stop suppression (0–7)".into(),
        3006 => "#3006: a stop with a message (the comment's text)".into(),
        3011 => "#3011: the date, YYYYMMDD (read only)".into(),
        3012 => "#3012: the time, HHMMSS (read only)".into(),
        4001..=4022 => format!(
            "#{n}: the G code in force in modal group {:02} (read only)",
            n - 4000
        ),
        4130 => "#4130: the G54.1 P number in force (0 under G54–G59; read only)".into(),
        4101..=4129 => match modal_letter(n % 100) {
            Some(l) => format!("#{n}: the last {l} value (read only)"),
            None => return None,
        },
        5001..=5006 => format!(
            "#{n}: {} of the last block's end point, work coordinates (read only)",
            axis(n)?
        ),
        5021..=5026 => format!("#{n}: {} in machine coordinates (read only)", axis(n)?),
        5041..=5046 => format!("#{n}: {} in work coordinates (read only)", axis(n)?),
        5061..=5066 => format!(
            "#{n}: {} where the G31 skip signal came (read only)",
            axis(n)?
        ),
        5201..=5326 | 7001..=7946 => format!("#{n}: {}", offset(n)?),
        2001..=2800 | 10001..=13999 => {
            let (field, tool) = tool_slot(n);
            let what = [
                "length wear",
                "length geometry",
                "radius wear",
                "radius geometry",
            ]
            .get(field as usize)?;
            format!("#{n}: tool offset {}, {what} (H/D {})", tool + 1, tool + 1)
        }
        _ => return None,
    })
}

/// A position variable's value, or alarm 0224 when the axis is not known (never a guess: a control
/// reads where its axis is, fmsvm knows only what the program or `--start-point` said).
fn known(n: u32, v: f64) -> Result<f64, Alarm> {
    if v.is_nan() {
        return Err(fmsvm_canon::unknown_axis(
            (n % 10 - 1) as usize,
            &format!("reading #{n}"),
        ));
    }
    Ok(v)
}

/// A lathe's reading of the axis-numbered variables (#5001–#5006, #5021…, #5041…, #5061…): axis 1 is
/// X (in diameter on a diameter lathe), axis 2 is Z (Fanuc T series numbers its axes X, Z); None on a
/// mill. A lathe's offset registers (#5201…, #2001…) are not modelled yet: alarm.
fn lathe_axis<E: Emitter>(k: &Kernel<E>, n: u32) -> Option<Result<(usize, f64), Alarm>> {
    let lathe = k.settings.lathe?;
    let axis = match n % 10 {
        1 => (0, 1.0 / lathe.radius_per_x_word()),
        2 => (2, 1.0),
        _ => {
            return Some(Err(Alarm::new(
                115,
                format!("#{n}: a lathe has two axes, X (#50x1) and Z (#50x2)"),
            )));
        }
    };
    Some(Ok(axis))
}

/// The variables a control has that fmsvm does not model, as its parameters declare them
/// (`[variables]`, docs/params.md): more common variables (the 30i's #100000…), values the control
/// holds (#3901, the parts count), and another numbering of the variables fmsvm models (a
/// Mitsubishi-style map: #4012 read as #4014).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ControlVariables {
    /// Ranges of variables read and written as common variables (vacant at the start).
    pub ranges: Vec<(u32, u32)>,
    /// Variables the control holds, with their values at the start (read and written).
    pub values: std::collections::BTreeMap<u32, f64>,
    /// `(first, last, to)`: #first…#last are read and written as #to….
    pub aliases: Vec<(u32, u32, u32)>,
}

/// The most variables a run may create in the declared ranges.
pub const MAX_DECLARED: usize = 1_000_000;

impl ControlVariables {
    /// The number fmsvm reads for `#n` under the control's numbering.
    pub fn alias(&self, n: u32) -> u32 {
        self.aliases
            .iter()
            .find(|(a, b, _)| (*a..=*b).contains(&n))
            .map_or(n, |(a, _, to)| to + (n - a))
    }

    /// Whether `#n` is one of the declared common variables.
    pub fn in_range(&self, n: u32) -> bool {
        self.ranges.iter().any(|(a, b)| (*a..=*b).contains(&n))
    }
}

/// A variable fmsvm does not model: the value the control's parameters declare, or not modelled.
fn declared<E: Emitter>(k: &Kernel<E>, n: u32) -> Result<f64, Alarm> {
    match k.declared.get(&n) {
        Some(v) => Ok(*v),
        None if k.settings.variables.in_range(n) => Ok(VACANT),
        None => Err(not_modelled(n)),
    }
}

/// Writes a variable fmsvm does not model, where the parameters declare it.
fn declare<E: Emitter>(k: &mut Kernel<E>, n: u32, v: f64) -> Result<(), Alarm> {
    let known = k.declared.contains_key(&n);
    if !known && !k.settings.variables.in_range(n) {
        return Err(not_modelled(n));
    }
    if !known && k.declared.len() >= MAX_DECLARED {
        return Err(Alarm::new(
            115,
            format!("#{n}: more than {MAX_DECLARED} declared variables written in one run"),
        ));
    }
    k.declared.insert(n, v);
    Ok(())
}

/// Reads system variable `n`.
pub fn read<E: Emitter>(k: &Kernel<E>, n: u32) -> Result<f64, Alarm> {
    let n = k.settings.variables.alias(n);
    if n < 1000 {
        return Err(Alarm::new(
            115,
            format!(
                "#{n}: an alias of the parameters names a variable below #1000 (a local or common one, which the program reads itself)"
            ),
        ));
    }
    if let 5001..=5006 | 5021..=5026 | 5041..=5046 | 5061..=5066 = n
        && let Some(axis) = lathe_axis(k, n)
    {
        let (i, scale) = axis?;
        let v = match n {
            5061..=5066 => k.skip[i],
            5021..=5026 => k.machine_point(&k.position)[i],
            _ => k.position[i],
        };
        if v.is_nan() {
            return Err(fmsvm_canon::unknown_axis(i, &format!("reading #{n}")));
        }
        return Ok(v * scale);
    }
    if k.settings.lathe.is_some() {
        if let Some((field, tool)) = lathe_tool_slot(n) {
            return match k.frames.tools.get(tool) {
                Some(t) => Ok(lathe_field(t, field)),
                None => Err(not_modelled(n)),
            };
        }
        lathe_offset_range(n)?;
    }
    match n {
        4001..=4022 | 4201..=4222 => {
            Ok(f64::from(k.modal.get_number((n % 100) as u8).tenths()) / 10.0)
        }
        4101..=4129 | 4301..=4329 => match modal_letter(n % 100) {
            Some(Letter::O) => Ok(k.program_number.map_or(VACANT, |p| p as f64)),
            Some(l) => Ok(k.last[l.index()]),
            None => Err(not_modelled(n)),
        },
        3001 => Ok(k.timing.millis()),
        3002 => Ok(k.timing.hours()),
        3003 => Ok(k.flags_3003_3004[0]),
        3004 => Ok(k.flags_3003_3004[1]),
        3011 => Ok(k.timing.date as f64),
        3012 => Ok(k.timing.time as f64),
        5061..=5066 => Ok(k.skip[(n % 10 - 1) as usize]),
        4130 | 4330 => Ok(match k.frames.active {
            WorkOffset::Extended(p) => p as f64,
            WorkOffset::Standard(_) => 0.0,
        }),
        5001..=5006 | 5041..=5046 => known(n, k.position[(n % 10 - 1) as usize]),
        // Machine coordinates: through the transforms, the work offset, G52, G92 and the length offset.
        5021..=5026 => known(n, k.machine_point(&k.position)[(n % 10 - 1) as usize]),
        5201..=5326 | 7001..=7946 => match offset_slot(n) {
            Some((pose, axis)) => Ok(pose_of(k, pose)[axis]),
            None => Err(not_modelled(n)),
        },
        2001..=2800 | 10001..=13999 => {
            let (field, tool) = tool_slot(n);
            // #11000, #12000, #13000 fall between two kinds of the 999 registers: none.
            match k.frames.tools.get(tool) {
                Some(t) => Ok(field_of(t, field)),
                None => Err(not_modelled(n)),
            }
        }
        _ => declared(k, n),
    }
}

/// Which work offset a variable is: 0 external, 1–6 G54–G59, 7–54 G54.1 P1–P48; and the axis.
fn offset_slot(n: u32) -> Option<(usize, usize)> {
    let (base, first) = if n >= 7001 { (7001, 7) } else { (5201, 0) };
    let k = n - base;
    let axis = (k % 20) as usize;
    (axis < AXES.len()).then_some((first + (k / 20) as usize, axis))
}

fn pose_of<E: Emitter>(k: &Kernel<E>, slot: usize) -> &Pose {
    match slot {
        0 => &k.frames.external,
        1..=6 => &k.frames.standard[slot - 1],
        _ => &k.frames.extended[slot - 7],
    }
}

fn pose_mut<E: Emitter>(k: &mut Kernel<E>, slot: usize) -> &mut Pose {
    if let Some(set) = k.frames.work_set.get_mut(slot) {
        *set = true;
    }
    match slot {
        0 => &mut k.frames.external,
        1..=6 => &mut k.frames.standard[slot - 1],
        _ => &mut k.frames.extended[slot - 7],
    }
}

/// Memory C: #2001–#2200 (#10001–) length wear, #2201–#2400 (#11001–) length geometry, #2401–#2600
/// (#12001–) radius wear, #2601–#2800 (#13001–) radius geometry. Returns the field (0–3 in that
/// order) and the register index.
fn tool_slot(n: u32) -> (u32, usize) {
    if n >= 10001 {
        ((n - 10001) / 1000, ((n - 10001) % 1000) as usize)
    } else {
        ((n - 2001) / 200, ((n - 2001) % 200) as usize)
    }
}

/// On a lathe, the mill's offset ranges that are not a lathe's tool offset variables: alarm 0115.
fn lathe_offset_range(n: u32) -> Result<(), Alarm> {
    if matches!(n, 5201..=5326 | 7001..=7946 | 2001..=2999 | 10001..=19999) {
        return Err(Alarm::new(
            115,
            format!(
                "#{n}: not a tool offset variable of a lathe, and a lathe's work offsets are not modelled in fmsvm yet"
            ),
        ));
    }
    Ok(())
}

/// The registers of a lathe's tool offset, in the order of [`lathe_tool_slot`]'s fields.
const LATHE_FIELDS: [&str; 7] = [
    "X wear",
    "Z wear",
    "nose radius wear",
    "imaginary tool nose direction",
    "X geometry",
    "Z geometry",
    "nose radius geometry",
];

/// A lathe's tool offset variables (0i-TD "System variables", tool compensation memory with
/// geometry and wear): offsets 1–64 at #2001 X wear, #2101 Z wear, #2201 nose radius wear, #2301
/// tip, #2701 X geometry, #2801 Z geometry, #2901 nose radius geometry; offsets 1–999 at #10001,
/// #11001, #12001, #13001, #15001, #16001, #17001 in the same order. The field (an index of
/// [`LATHE_FIELDS`]) and the register index.
fn lathe_tool_slot(n: u32) -> Option<(u32, usize)> {
    let (field, i) = match n {
        2001..=2999 => {
            let (hundred, i) = ((n - 2001) / 100, (n - 2001) % 100);
            let field = match hundred {
                0..=3 => hundred,
                7..=9 => hundred - 3,
                _ => return None,
            };
            (field, i)
        }
        10001..=17999 => {
            let (thousand, i) = ((n - 10001) / 1000, (n - 10001) % 1000);
            let field = match thousand {
                0..=3 => thousand,
                5..=7 => thousand - 1,
                _ => return None,
            };
            (field, i)
        }
        _ => return None,
    };
    let last = if n < 10000 { 64 } else { 999 };
    (i < last).then_some((field, i as usize))
}

/// The value of a lathe's tool offset register `field`.
fn lathe_field(t: &ToolRegister, field: u32) -> f64 {
    match field {
        0 => t.xz_wear[0],
        1 => t.xz_wear[1],
        2 => t.radius_wear,
        3 => f64::from(t.tip),
        4 => t.xz_geometry[0],
        5 => t.xz_geometry[1],
        _ => t.radius_geometry,
    }
}

fn field_of(t: &ToolRegister, field: u32) -> f64 {
    match field {
        0 => t.length_wear,
        1 => t.length_geometry,
        2 => t.radius_wear,
        _ => t.radius_geometry,
    }
}

/// Writes system variable `n`.
pub fn write<E: Emitter>(k: &mut Kernel<E>, n: u32, v: f64) -> Result<(), Alarm> {
    let n = k.settings.variables.alias(n);
    if k.settings.lathe.is_some() {
        if let Some((field, tool)) = lathe_tool_slot(n) {
            // Resolved output makes the nose radius compensation itself: the nose registers are
            // fmsvm's. X and Z are the control's (it applies them by T), and literal output
            // leaves the compensation to the control too: a flat program cannot set them.
            if !(E::CANON && matches!(field, 2 | 3 | 6)) {
                return Err(Alarm::new(
                    115,
                    format!(
                        "#{n}: the {} of a lathe's tool offset is the control's register, which a flat program cannot set: set it on the control (and for fmsvm in --offsets)",
                        LATHE_FIELDS[field as usize]
                    ),
                ));
            }
            let Some(t) = k.frames.tools.get_mut(tool) else {
                return Err(not_modelled(n));
            };
            let v = fmsvm_canon::decode::vacant_as_zero(v);
            t.set = true;
            match field {
                2 => t.radius_wear = v,
                6 => t.radius_geometry = v,
                _ => {
                    if !(0.0..=9.0).contains(&v) || v.fract() != 0.0 {
                        return Err(Alarm::new(
                            115,
                            format!("#{n} = {v}: the imaginary tool nose direction is 0 to 9"),
                        ));
                    }
                    t.tip = v as u8;
                }
            }
            return Ok(());
        }
        lathe_offset_range(n)?;
    }
    match n {
        3001 => {
            k.timing.set_millis(fmsvm_canon::decode::vacant_as_zero(v));
            Ok(())
        }
        3002 => {
            k.timing.set_hours(fmsvm_canon::decode::vacant_as_zero(v));
            Ok(())
        }
        // S7: accepted and remembered; a flat program changes no feed hold or single-block state.
        3003 | 3004 => {
            let v = fmsvm_canon::decode::vacant_as_zero(v).round();
            if !(0.0..=7.0).contains(&v) {
                return Err(Alarm::new(115, format!("#{n} = {v}: the value is 0 to 7")));
            }
            k.flags_3003_3004[(n - 3003) as usize] = v;
            Ok(())
        }
        3011 | 3012 => Err(Alarm::new(WRITE_PROTECTED, format!("#{n} is read-only"))),
        5201..=5326 | 7001..=7946 if E::CANON && k.settings.control_offsets.work => Err(
            crate::kernel::control_register(&format!("#{n}"), "work offsets"),
        ),
        2001..=2400 | 10001..=11999 if E::CANON && k.settings.control_offsets.length => Err(
            crate::kernel::control_register(&format!("#{n}"), "tool lengths"),
        ),
        5201..=5326 | 7001..=7946 => match offset_slot(n) {
            Some((slot, axis)) => {
                // The tool stays where it is: a change of the active offset moves the program's zero.
                let old = k.frames.origin();
                pose_mut(k, slot)[axis] = fmsvm_canon::decode::vacant_as_zero(v);
                k.shift_origin(old);
                Ok(())
            }
            None => Err(not_modelled(n)),
        },
        2001..=2800 | 10001..=13999 => {
            let (field, tool) = tool_slot(n);
            if tool >= k.frames.tools.len() {
                return Err(not_modelled(n));
            }
            let t = &mut k.frames.tools[tool];
            t.set = true;
            let v = fmsvm_canon::decode::vacant_as_zero(v);
            match field {
                0 => t.length_wear = v,
                1 => t.length_geometry = v,
                2 => t.radius_wear = v,
                _ => t.radius_geometry = v,
            }
            Ok(())
        }
        4001..=4330 | 5001..=5106 => Err(Alarm::new(WRITE_PROTECTED, format!("#{n} is read-only"))),
        _ => declare(k, n, v),
    }
}
