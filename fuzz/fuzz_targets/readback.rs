//! The `--verify` readers on arbitrary bytes: every built-in dialect's word reader (Fanuc, the
//! FMS-3000, the lathes, LinuxCNC …) and the Н33-2М tape reader. None panics, loops or grows without
//! bound on the way; each gives moves or a located read error, and no move goes to an infinite
//! position (NaN is an axis the program never positioned).
#![no_main]
use libfuzzer_sys::fuzz_target;

use fmsvm_readback::Reader;

/// Moves read at most (the input is at most a few KiB: far fewer moves are possible).
const MOST: usize = 100_000;

fn drain(mut r: impl Reader) {
    for _ in 0..MOST {
        match r.next_move() {
            Ok(Some(m)) => assert!(
                m.to.iter().all(|v| !v.is_infinite()),
                "a move to {:?}",
                m.to
            ),
            Ok(None) | Err(_) => return,
        }
    }
    panic!("more than {MOST} moves from a short input");
}

fuzz_target!(|data: &[u8]| {
    let Some((&which, rest)) = data.split_first() else {
        return;
    };
    let names = fmsvm_driver::dialects::BUILT_IN;
    let pick = which as usize % (names.len() + 1);
    if pick == names.len() {
        drain(fmsvm_readback::n33::N33Reader::new(
            std::io::Cursor::new(rest),
            [0.0; 6],
        ));
        return;
    }
    let Ok(profile) = fmsvm_driver::dialects::builtin(names[pick].0) else {
        return;
    };
    drain(fmsvm_readback::words::WordReader::new(
        std::io::Cursor::new(rest),
        profile.dialect,
    ));
});
