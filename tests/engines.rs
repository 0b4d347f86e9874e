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

/// Native code indexes an activation's registers through its own pointer while the entry points it
/// calls (a G65 call, an M98 sharing the caller's locals, an indirect `#[…]` store, DPRNT) work on
/// the same registers: they are handed on as a fixed slice, so nothing can grow the vector that
/// owns them under the native code. A nest four G65 levels deep, each filling its locals #2–#26
/// through indirect stores before calling the next and reading them back after, with an M98 that
/// writes the caller's #27: each level's sum is 25·100·A + (2 + … + 26) = 2500·A + 350, printed
/// deepest first.
#[test]
fn a_deep_macro_nest_keeps_every_levels_registers() {
    let src = "%\nO1\nPOPEN\nG65 P9001 A1.\nPCLOS\nM30\nO9001\n#30=2\nWHILE[#30 LE 26]DO1\n#[#30]=#1*100+#30\n#30=#30+1\nEND1\nIF[#1 GE 4]GOTO10\nG65 P9001 A[#1+1]\nN10 M98 P2000\n#31=0\n#30=2\nWHILE[#30 LE 26]DO1\n#31=#31+#[#30]\n#30=#30+1\nEND1\nDPRNT[L#1[10]*S#31[50]*M#27[10]]\nG1 X#31 Y#27\nM99\nO2000\n#[27]=#1+4\nM99\n%\n";
    let i = expand(src, EngineKind::Interp);
    let j = expand(src, EngineKind::Jit);
    assert_eq!(i, j, "interp and jit differ");
    // DPRNT's lines between the port's DC2 and DC4, each number right-aligned in its field.
    let printed = String::from_utf8(i.2).expect("ASCII");
    let sums: Vec<String> = printed
        .lines()
        .map(|l| {
            l.replace(['\u{12}', '\u{14}'], "")
                .split_whitespace()
                .collect()
        })
        .filter(|l: &String| !l.is_empty())
        .collect();
    assert_eq!(
        sums,
        ["L4S10350M8", "L3S7850M7", "L2S5350M6", "L1S2850M5"],
        "{printed}"
    );
    for level in [1.0_f64, 2.0, 3.0, 4.0] {
        let x = 2500.0 * level + 350.0;
        assert!(i.0.contains(&format!("X{x}")), "X{x} in\n{}", i.0);
    }
}
