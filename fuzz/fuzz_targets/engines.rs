//! Interpreter versus JIT on arbitrary programs: the same bytes, variables and stop, always.
#![no_main]
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Some(p) = common::compile(text) {
            let a = common::expand(&p, fmsvm_vm::EngineKind::Interp);
            let b = common::expand(&p, fmsvm_vm::EngineKind::Jit);
            assert_eq!(a, b, "engines differ on {text:?}");
        }
    }
});
