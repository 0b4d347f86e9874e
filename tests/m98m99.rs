//! LinuxCNC's 14 `tests/interp/m98m99` cases, translated to Custom Macro B (`tests/m98m99/`, see its
//! README): each row of `cases.tsv` runs the binary and checks the exit code, the alarm text, the motion
//! (LinuxCNC's `rs274 -g` on the original, or written by hand where stated) and the DPRNT output.

use crate::common;

use std::path::Path;
use std::process::Command;

use common::{diff_moves, moves_of_flat, moves_of_list};

/// Rows whose originals drill with G81: the flat output keeps the canned cycle until the kernel
/// resolves cycles (next wave), so only their exit code and printed output are compared now.
const NEEDS_CANNED_CYCLES: [&str; 3] = ["01-basics", "05-M98-loops", "09-disable-fanuc-subs-fanuc"];

/// `printnorm.py`: words and numbers of each printed line (numbers with a point as %.4f).
fn norm(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in text.lines() {
        let line = line.replace(['\u{12}', '\u{14}'], "").to_ascii_uppercase();
        let b = line.as_bytes();
        let mut toks = Vec::new();
        let mut i = 0;
        while i < b.len() {
            let c = b[i];
            if c.is_ascii_uppercase() {
                let s = i;
                while i < b.len() && b[i].is_ascii_uppercase() {
                    i += 1;
                }
                toks.push(line[s..i].to_string());
            } else if c.is_ascii_digit()
                || (c == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit))
            {
                let s = i;
                i += 1;
                while i < b.len() && b[i].is_ascii_digit() {
                    i += 1;
                }
                if i + 1 < b.len() && b[i] == b'.' && b[i + 1].is_ascii_digit() {
                    i += 1;
                    while i < b.len() && b[i].is_ascii_digit() {
                        i += 1;
                    }
                }
                let t = &line[s..i];
                if t.contains('.') {
                    let v: f64 = t.parse().unwrap_or(0.0) + 0.0;
                    let f = format!("{v:.4}");
                    toks.push(if f == "-0.0000" { "0.0000".into() } else { f });
                } else {
                    toks.push(t.to_string());
                }
            } else {
                i += 1;
            }
        }
        if !toks.is_empty() {
            out.push(toks.join(" "));
        }
    }
    out
}

#[test]
fn linuxcnc_m98m99_cases() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/m98m99");
    let table = std::fs::read_to_string(dir.join("cases.tsv")).expect("cases.tsv");
    let tmp = tempfile::tempdir().expect("temp dir");
    let mut ran = 0;
    let mut failures = Vec::new();
    for row in table
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let c: Vec<&str> = row.split('\t').collect();
        let (id, nc, options, exit, alarm, moves, printed) =
            (c[0], c[2], c[3], c[4], c[5], c[6], c[7]);
        let out = tmp.path().join(format!("{ran}.nc"));
        let prn = tmp.path().join(format!("{ran}.prn"));
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_fmsvm"));
        cmd.arg("run")
            .arg(dir.join(nc))
            .arg("-o")
            .arg(&out)
            .arg("--print")
            .arg(&prn);
        if options != "-" {
            cmd.args(options.split_whitespace());
        }
        let o = cmd.output().expect("runs");
        ran += 1;
        let stderr = String::from_utf8_lossy(&o.stderr);
        let code = o.status.code().unwrap_or(-1).to_string();
        if code != exit {
            failures.push(format!("{id}: exit {code}, want {exit}: {stderr}"));
            continue;
        }
        if alarm != "-" && !stderr.contains(alarm) {
            failures.push(format!("{id}: stderr lacks `{alarm}`: {stderr}"));
        }
        if moves != "-" && !NEEDS_CANNED_CYCLES.contains(&id) {
            let want = moves_of_list(&std::fs::read_to_string(dir.join(moves)).expect("moves"));
            let got = moves_of_flat(&std::fs::read_to_string(&out).expect("output"));
            if let Err(d) = diff_moves(&got, &want, 0.0011) {
                failures.push(format!("{id}: {d}"));
            }
        }
        if printed != "-" {
            let want: Vec<String> = std::fs::read_to_string(dir.join(printed))
                .expect("printed")
                .lines()
                .map(str::to_string)
                .collect();
            let got = norm(&std::fs::read_to_string(&prn).unwrap_or_default());
            if got != want {
                failures.push(format!("{id}: printed {got:?}, want {want:?}"));
            }
        }
    }
    assert_eq!(ran, 25, "every row of cases.tsv runs");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
