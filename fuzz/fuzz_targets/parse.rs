//! Lexer + parser + checks + lowering on arbitrary text: never a panic, whatever the input.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = fmsvm_compiler::compile_str(text, &fmsvm_compiler::Options::default());
    }
});
