//! The VM sees the front end only through its IR (ARCHITECTURE.md, dependency rules). Cargo enforces
//! it for the VM's code: its one front-end dependency is `fmsvm-ir`, the compiler is only a
//! dev-dependency (these tests build programs with `compile_str`). A dev-dependency is also in scope
//! for unit tests under `vm/src`, so this test keeps the compiler out of `vm/src` altogether: tests
//! that need the front end live here in `vm/tests/`.

use std::fs;
use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The lines of `text` that name the compiler crate.
fn violations(text: &str) -> Vec<(usize, String)> {
    text.lines()
        .enumerate()
        .filter(|(_, line)| line.contains("fmsvm_compiler"))
        .map(|(n, line)| (n + 1, line.trim().to_string()))
        .collect()
}

#[test]
fn the_rule_catches_what_it_should() {
    assert!(violations("use fmsvm_ir::{Op, Program};").is_empty());
    for bad in [
        "use fmsvm_compiler::ir::{Op, Program};",
        "use fmsvm_compiler::ast::{BinOp, CmpOp};",
        "use fmsvm_compiler as c;",
    ] {
        assert_eq!(violations(bad).len(), 1, "{bad}");
    }
}

#[test]
fn vm_sources_never_name_the_compiler() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    assert!(
        files.len() > 5,
        "found only {files:?} under {}",
        src.display()
    );
    let mut report = String::new();
    for file in &files {
        let text = fs::read_to_string(file).unwrap();
        for (line, code) in violations(&text) {
            report += &format!("{}:{line}: {code}\n", file.display());
        }
    }
    assert!(
        report.is_empty(),
        "vm/src uses the front end only through fmsvm_ir (move what it needs into the IR crate):\n{report}"
    );
}
