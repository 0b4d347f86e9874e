//! The base protocol's frames (`fmsvm lsp`, `fmsvm dap`) on arbitrary bytes: every read gives a
//! body of at most the bound, a reason it is no frame, or the end; none panics; a body's JSON is
//! read or refused (lone surrogates mended), never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;

use fmsvm_editor::frame::{Frame, MAX_BODY, json, read};

fuzz_target!(|data: &[u8]| {
    let mut input = std::io::BufReader::new(data);
    for _ in 0..256 {
        match read(&mut input) {
            Frame::Body(b) => {
                assert!(b.len() <= MAX_BODY && b.len() <= data.len());
                let _ = json(&b);
            }
            Frame::Bad(why) => assert!(!why.is_empty()),
            Frame::End | Frame::Failed(_) => break,
        }
    }
});
