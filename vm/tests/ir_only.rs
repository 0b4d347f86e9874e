//! The VM sees the compiler only through its IR (ARCHITECTURE.md, dependency rules): every path the
//! VM's code names in `fmsvm_compiler` starts with `fmsvm_compiler::ir`. Not `ast`, not `check`, not the
//! crate root. Tests that need the front end (`compile_str`) live here in `vm/tests/`, not in `vm/src/`.

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

/// The places in `text` that name `fmsvm_compiler` other than as `fmsvm_compiler::ir`.
fn violations(text: &str) -> Vec<(usize, String)> {
    const CRATE: &str = "fmsvm_compiler";
    let mut found = Vec::new();
    for (n, line) in text.lines().enumerate() {
        for (at, _) in line.match_indices(CRATE) {
            let rest = &line[at + CRATE.len()..];
            let ir = rest
                .strip_prefix("::ir")
                .is_some_and(|r| !r.starts_with(|c: char| c.is_alphanumeric() || c == '_'));
            if !ir {
                found.push((n + 1, line.trim().to_string()));
            }
        }
    }
    found
}

#[test]
fn the_rule_catches_what_it_should() {
    assert!(violations("use fmsvm_compiler::ir::{Op, Program};").is_empty());
    assert!(violations("fn f(s: fmsvm_compiler::ir::Span) {}").is_empty());
    for bad in [
        "use fmsvm_compiler::ast::{BinOp, CmpOp};",
        "use fmsvm_compiler::check::classify;",
        "use fmsvm_compiler::span::Span;",
        "use fmsvm_compiler::{ir::Op, ast::Func};",
        "use fmsvm_compiler::irx::Op;",
        "use fmsvm_compiler as c;",
        "let k = fmsvm_compiler::diag::alarm::MINUS_SIGN;",
    ] {
        assert_eq!(violations(bad).len(), 1, "{bad}");
    }
}

#[test]
fn vm_sources_name_only_compiler_ir() {
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
        "the VM may use the compiler only through fmsvm_compiler::ir (not ast, check or the crate \
         root; move what it needs into the IR):\n{report}"
    );
}
