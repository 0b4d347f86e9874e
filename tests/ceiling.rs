//! The native ceilings of the benchmarks (`benches/ceiling.rs`) make exactly the bytes the VM makes from
//! the hemisphere program: the kernel-driven one at the corpus step and at a finer one, the direct one
//! (no VM, no kernel) at those and at the benchmark's own step 0.05 (4 004 007 blocks, compared with
//! `fmsvm run`'s output).

#[path = "../benches/ceiling.rs"]
mod native;
use crate::common;

use fmsvm_canon::decode::InputRules;
use fmsvm_emit::dialect::Dialect;
use fmsvm_emit::literal::{self, LiteralEmitter};
use fmsvm_kernel::Kernel;

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
        native::hemisphere(&mut k, step);
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

const TITLE: &str = "(SEED 003 EXERCISE 38: HEMISPHERE R40 ON A 100X100 FIELD, ZIGZAG RASTER)";

fn direct(step: f64) -> Vec<u8> {
    let mut out = Vec::new();
    native::hemisphere_bytes(&mut out, TITLE, step).unwrap();
    out
}

/// The hemisphere at raster step `step`.
fn at_step(step: &str) -> String {
    HEMISPHERE
        .replace("#2=#2+1", &format!("#2=#2+{step}"))
        .replace("#2=#2-1", &format!("#2=#2-{step}"))
        .replace("#1=#1+1", &format!("#1=#1+{step}"))
}

#[test]
fn the_direct_ceiling_makes_the_vms_bytes() {
    assert_eq!(
        String::from_utf8(direct(1.0)).unwrap(),
        common::ok(HEMISPHERE).text
    );
    assert_eq!(String::from_utf8(direct(0.25)).unwrap(), native(0.25));
}

#[test]
fn the_direct_ceiling_makes_fmsvm_runs_bytes_at_the_benchmarks_step() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("fine.nc");
    let out = dir.path().join("fine.out");
    std::fs::write(&src, at_step("0.05")).unwrap();
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_fmsvm"))
        .arg("run")
        .arg(&src)
        .arg("-o")
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success(), "fmsvm run: {status}");
    let vm = std::fs::read(&out).unwrap();
    let native = direct(0.05);
    assert_eq!(vm.len(), native.len(), "lengths");
    assert!(vm.len() > 100_000_000, "{} bytes", vm.len());
    if let Some(i) = vm.iter().zip(&native).position(|(a, b)| a != b) {
        let line = vm[..i].iter().filter(|&&b| b == b'\n').count() + 1;
        panic!("the bytes differ from line {line}");
    }
}
