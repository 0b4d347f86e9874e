//! The three engines give byte-identical output on programs long enough for `auto` to move from the
//! interpreter to the JIT in the middle of a loop (on-stack replacement), with and without calls.
//! (Every other test program is run on the interpreter and the JIT by `common::expand`.)

use fmsvm_canon::decode::InputRules;
use fmsvm_compiler::Options;
use fmsvm_emit::dialect::Dialect;
use fmsvm_emit::literal::{self, LiteralEmitter};
use fmsvm_kernel::Kernel;
use fmsvm_vm::{EngineKind, MemoryPort, RunOptions, Variables};

const HEMISPHERE: &str = include_str!("corpus/003-hemisphere.nc");

fn expand(src: &str, engine: EngineKind) -> (String, u64, Vec<u8>) {
    let (p, d, _) = fmsvm_compiler::compile_str(src, &Options::default());
    let p = p.unwrap_or_else(|| panic!("{d:?}"));
    let mut out = Vec::new();
    let mut port = MemoryPort::default();
    let stats = {
        let e = LiteralEmitter::new(&mut out, Dialect::fanuc(), literal::Options::default());
        let mut k = Kernel::new(e, InputRules::default());
        let options = RunOptions {
            engine,
            ..RunOptions::default()
        };

        fmsvm_vm::run(&p, &mut k, &mut port, &mut Variables::default(), &options).expect("runs")
    };
    (
        String::from_utf8(out).expect("ASCII"),
        stats.steps,
        port.bytes,
    )
}

fn all_alike(src: &str) {
    let i = expand(src, EngineKind::Interp);
    assert!(
        i.1 > fmsvm_vm::TIER_UP_STEPS,
        "the program must run long enough to tier up ({} steps)",
        i.1
    );
    assert_eq!(i, expand(src, EngineKind::Jit), "interp and jit differ");
    assert_eq!(i, expand(src, EngineKind::Auto), "interp and auto differ");
}

#[test]
fn tier_up_in_the_middle_of_the_raster() {
    let fine = HEMISPHERE
        .replace("#2=#2+1", "#2=#2+0.25")
        .replace("#2=#2-1", "#2=#2-0.25")
        .replace("#1=#1+1", "#1=#1+0.25");
    all_alike(&fine);
}

#[test]
fn tier_up_inside_a_called_macro_and_with_prints() {
    let src = "%\nO1\nPOPEN\n#100=0\nWHILE[#100 LT 300]DO1\nG65 P9010 X[#100*0.5] R3.\n#100=#100+1\nEND1\nPCLOS\nM30\nO9010\n#1=0\nWHILE[#1 LT 200]DO1\n#2=#24+#18*COS[#1*1.8]\nIF[#1 NE 100]GOTO5\nDPRNT[P#100[40]*X#2[43]]\nN5 #1=#1+1\nEND1\nG1 X#2 Y#1\nM99\n%\n";
    all_alike(src);
}
