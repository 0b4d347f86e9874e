//! System variables answered by the kernel: modal information #4001–#4130 and #4201–#4330 (S3, S8),
//! positions #5001–#5026 and #5041–#5046 (S4, S9), work offsets #5201–#5326 (S5).
//!
//! fmsvm expands without a look-ahead buffer, so the "pre-read" (#4001…) and "executing block"
//! (#4201…) sets give the same state: the one after the last expanded block; #5041 (current position)
//! equals #5001 (end point of the last block), as on a control with buffering off (S9).

use fmsvm_block::{Alarm, Letter, VACANT};

use crate::emit::Emitter;
use crate::modal::Group;
use crate::{AXES, Kernel, not_modelled};

/// Number of work-offset variables #5201–#5326 (external + G54–G59, 20 apart, 6 axes used).
pub const WORK_OFFSETS: usize = 126;

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

/// Reads system variable `n`.
pub fn read<E: Emitter>(k: &Kernel<E>, n: u32) -> Result<f64, Alarm> {
    match n {
        4001..=4022 | 4201..=4222 => Ok(k.modal.get_number((n % 100) as u8) as f64 / 10.0),
        4101..=4130 | 4301..=4330 => match modal_letter(n % 100) {
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
        5001..=5006 | 5041..=5046 => Ok(k.position[(n % 10 - 1) as usize]),
        // Machine coordinates: work position plus the active work offset (no offsets in flat output yet).
        5021..=5026 => {
            let axis = (n % 10 - 1) as usize;
            Ok(k.position[axis] + active_offset(k, axis))
        }
        5201..=5326 if (n - 5201) % 20 < AXES.len() as u32 => {
            Ok(k.work_offsets[(n - 5201) as usize])
        }
        _ => Err(not_modelled(n)),
    }
}

/// The offset of the active work system (G54–G59) plus the external offset, for `axis`.
fn active_offset<E: Emitter>(k: &Kernel<E>, axis: usize) -> f64 {
    let wcs = k.modal.get(Group::WorkOffset);
    let index = match wcs {
        540..=590 if wcs.is_multiple_of(10) => (wcs / 10 - 53) as usize,
        _ => 1,
    };
    k.work_offsets[axis] + k.work_offsets[index * 20 + axis]
}

/// Writes system variable `n`.
pub fn write<E: Emitter>(k: &mut Kernel<E>, n: u32, v: f64) -> Result<(), Alarm> {
    match n {
        3001 => {
            k.timing.set_millis(crate::decode::vacant_as_zero(v));
            Ok(())
        }
        3002 => {
            k.timing.set_hours(crate::decode::vacant_as_zero(v));
            Ok(())
        }
        // S7: accepted and remembered; a flat program changes no feed hold or single-block state.
        3003 | 3004 => {
            let v = crate::decode::vacant_as_zero(v).round();
            if !(0.0..=7.0).contains(&v) {
                return Err(Alarm::new(115, format!("#{n} = {v}: the value is 0 to 7")));
            }
            k.flags_3003_3004[(n - 3003) as usize] = v;
            Ok(())
        }
        3011 | 3012 => Err(Alarm::new(WRITE_PROTECTED, format!("#{n} is read-only"))),
        5201..=5326 if (n - 5201) % 20 < AXES.len() as u32 => {
            k.work_offsets[(n - 5201) as usize] = crate::decode::vacant_as_zero(v);
            Ok(())
        }
        4001..=4330 | 5001..=5106 => Err(Alarm::new(WRITE_PROTECTED, format!("#{n} is read-only"))),
        _ => Err(not_modelled(n)),
    }
}
