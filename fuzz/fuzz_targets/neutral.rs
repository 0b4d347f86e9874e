//! The turning library's neutral language (`fmsvm post`'s input) on arbitrary text: a program or
//! errors, each located inside the text; never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

use fmsvm_driver::neutral::{Kind, parse_for};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let lines = text.lines().count().max(1) as u32;
    // The catalogue decides some cycles' kinds (as a control's would), the records the rest.
    let kind = |n: u32| match n % 4 {
        0 => Some(Kind::Turning),
        1 => Some(Kind::Drilling),
        2 => Some(Kind::Threading),
        _ => None,
    };
    if let Err(errors) = parse_for(&text, &kind) {
        assert!(!errors.is_empty());
        for e in errors {
            assert!(e.at.line >= 1 && e.at.line <= lines + 1, "{e}");
        }
    }
});
