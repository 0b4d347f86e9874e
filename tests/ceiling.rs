//! The native ceiling of the benchmarks (`benches/ceiling.rs`) makes exactly the bytes the VM makes from
//! the hemisphere program, at the corpus step and at a finer one.

#[path = "../benches/ceiling.rs"]
mod ceiling;
mod common;

use fmsvm_runtime::Kernel;
use fmsvm_runtime::decode::InputRules;
use fmsvm_runtime::dialect::Dialect;
use fmsvm_runtime::emit::literal::{self, LiteralEmitter};

const HEMISPHERE: &str = include_str!("corpus/003-hemisphere.nc");

fn native(step: f64) -> String {
    let mut out = Vec::new();
    {
        let e = LiteralEmitter::new(&mut out, Dialect::fanuc(), literal::Options::default());
        let mut k = Kernel::new(e, InputRules::default());
        // The O line's program name is kept in the output, as the VM's run keeps it.
        let title = HEMISPHERE
            .lines()
            .find_map(|l| l.strip_prefix("O7118 "))
            .unwrap_or("");
        k.begin(Some(7118), title).unwrap();
        ceiling::hemisphere(&mut k, step);
        k.end().unwrap();
    }
    String::from_utf8(out).unwrap()
}

#[test]
fn the_ceiling_makes_the_vms_bytes() {
    assert_eq!(native(1.0), common::ok(HEMISPHERE).text);
    let fine = HEMISPHERE
        .replace("#2=#2+1", "#2=#2+0.25")
        .replace("#2=#2-1", "#2=#2-0.25")
        .replace("#1=#1+1", "#1=#1+0.25");
    assert_eq!(native(0.25), common::ok(&fine).text);
}
