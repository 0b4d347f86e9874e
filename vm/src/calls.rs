//! Macro call arguments: specification I and II and their mixing (macro-b-rules C2–C4, C11), and the
//! nesting limits (C6, C7).

use fmsvm_block::alarms::FORMAT;
use fmsvm_block::{Alarm, Letter, Machine, Word};

/// 0122 TOO MANY MACRO NESTING: a fifth G65/G66 level (C7).
pub const MACRO_NESTING: u32 = 122;
/// 0077 TOO MANY SUB, MACRO NESTING: a fifth nested M98 (C7).
pub const SUB_NESTING: u32 = 77;
/// 0076 PROGRAM NOT FOUND.
pub const PROGRAM_NOT_FOUND: u32 = 76;
/// Local levels 1–4 below the main program (V3, C6).
pub const MAX_MACRO_LEVELS: u8 = 4;
/// Nested subprogram calls: 4 on Fanuc by default (C7), up to 10 as an option.
pub const MAX_SUB_DEPTH: u8 = 10;

/// The default subprogram nesting (C7).
pub const DEFAULT_SUB_DEPTH: u8 = 4;

/// The local a specification-I letter sets (C2): A#1 B#2 C#3 I#4 J#5 K#6 D#7 E#8 F#9 H#11 M#13 Q#17
/// R#18 S#19 T#20 U#21 V#22 W#23 X#24 Y#25 Z#26.
pub fn spec_i(letter: Letter) -> Option<usize> {
    Some(match letter {
        Letter::A => 1,
        Letter::B => 2,
        Letter::C => 3,
        Letter::I => 4,
        Letter::J => 5,
        Letter::K => 6,
        Letter::D => 7,
        Letter::E => 8,
        Letter::F => 9,
        Letter::H => 11,
        Letter::M => 13,
        Letter::Q => 17,
        Letter::R => 18,
        Letter::S => 19,
        Letter::T => 20,
        Letter::U => 21,
        Letter::V => 22,
        Letter::W => 23,
        Letter::X => 24,
        Letter::Y => 25,
        Letter::Z => 26,
        _ => return None,
    })
}

/// Sets the callee's locals (`locals[n]` is `#n`; index 0 unused) from the argument words, in the
/// order given. I, J, K form specification-II sets (I1 J1 K1 = #4 #5 #6 … I10 J10 K10 = #31 #32 #33):
/// a new set starts at each I, at a J after J or K, at a K after K (C11). A later assignment to the same
/// local wins (C4). Words N, O, P, L and G carry no argument.
pub fn assign<M: Machine>(words: &[Word], locals: &mut [f64], machine: &M) -> Result<(), Alarm> {
    let mut set: i32 = -1;
    let (mut seen_i, mut seen_j, mut seen_k) = (false, false, false);
    for w in words {
        let target = match w.letter {
            Letter::I | Letter::J | Letter::K => {
                let new_set = match w.letter {
                    Letter::I => set < 0 || seen_i || seen_j || seen_k,
                    Letter::J => set < 0 || seen_j || seen_k,
                    _ => set < 0 || seen_k,
                };
                if new_set {
                    set += 1;
                    (seen_i, seen_j, seen_k) = (false, false, false);
                }
                if set > 9 {
                    return Err(Alarm::new(
                        FORMAT,
                        "more than 10 I J K argument sets (docs/semantics.md, row C3)",
                    ));
                }
                let offset = match w.letter {
                    Letter::I => {
                        seen_i = true;
                        4
                    }
                    Letter::J => {
                        seen_j = true;
                        5
                    }
                    _ => {
                        seen_k = true;
                        6
                    }
                };
                offset + 3 * set as usize
            }
            l => match spec_i(l) {
                Some(n) => n,
                None => continue,
            },
        };
        locals[target] = machine.argument(w);
    }
    Ok(())
}
