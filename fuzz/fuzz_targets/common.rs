//! Shared by the fuzz targets: expand a program with small limits on one engine.

use fmsvm_canon::decode::InputRules;
use fmsvm_compiler::{Options, Program};
use fmsvm_emit::dialect::Dialect;
use fmsvm_emit::literal::{self, LiteralEmitter};
use fmsvm_kernel::Kernel;
use fmsvm_vm::{EngineKind, Limits, MemoryPort, RunOptions, Variables};

/// Output bytes, printed bytes, commons as bits, and the stop (as text) of one run.
pub type Outcome = (Vec<u8>, Vec<u8>, Vec<u64>, Option<String>);

pub fn compile(text: &str) -> Option<Program> {
    fmsvm_compiler::compile_str(text, &Options::default()).0
}

pub fn expand(p: &Program, engine: EngineKind) -> Outcome {
    let mut out = Vec::new();
    let mut port = MemoryPort::default();
    let mut vars = Variables::default();
    let stop = {
        let e = LiteralEmitter::new(&mut out, Dialect::fanuc(), literal::Options::default());
        let mut k = Kernel::new(e, InputRules::default());
        let options = RunOptions {
            engine,
            limits: Limits {
                max_steps: 20_000,
                max_blocks: 2_000,
                ..Limits::default()
            },
            print_without_popen: true,
            ..RunOptions::default()
        };
        fmsvm_vm::run(p, &mut k, &mut port, &mut vars, &options)
            .err()
            .map(|e| format!("{} at {}..{}", e.stop, e.span.start, e.span.end))
    };
    let commons = vars.commons.iter().map(|v| v.to_bits()).collect();
    (out, port.bytes, commons, stop)
}
