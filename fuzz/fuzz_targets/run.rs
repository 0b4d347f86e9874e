//! Compile and interpret arbitrary text with small limits: alarms and limits are fine, panics are not.
#![no_main]
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Some(p) = common::compile(text) {
            let _ = common::expand(&p, fmsvm_vm::EngineKind::Interp);
        }
    }
});
