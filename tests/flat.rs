//! NC-only programs run straight from the file (driver/src/flat.rs) exactly as compiled ones do: the same
//! bytes, messages and exit codes on every shipped program and on random NC-only programs, with the
//! compiler path forced by `--without flat` (which also makes the compiler parse every line with its
//! full grammar, so that the plain-line decoder both paths share is held to the grammar). And the
//! compiler's own plain lines give the program the full grammar gives, IR and diagnostics alike, in
//! programs with macro lines among them. And the path is taken: a CAM-size file runs in flat
//! memory (its peak is checked by the benchmark script, not here; here the file is only larger than
//! what a compiled run could hold cheaply).

use crate::cli_support;

use std::path::Path;
use std::process::Output;

use cli_support::{Dir, Rng, bin, stderr};

fn both(args: &[&str], cwd: &Path) -> (Output, Output) {
    let flat = bin().args(args).current_dir(cwd).output().expect("runs");
    let compiled = bin()
        .args(args)
        .current_dir(cwd)
        .args(["--without", "flat"])
        .output()
        .expect("runs");
    (flat, compiled)
}

fn same(args: &[&str], cwd: &Path, what: &str) {
    let (f, c) = both(args, cwd);
    assert_eq!(
        f.status.code(),
        c.status.code(),
        "{what}: exit\n{}\n{}",
        stderr(&f),
        stderr(&c)
    );
    assert_eq!(stderr(&f), stderr(&c), "{what}: messages");
    assert!(f.stdout == c.stdout, "{what}: output differs");
}

#[test]
fn shipped_programs_expand_the_same_both_ways() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in ["tests/kernel", "tests/dialects", "tests/dnc", "samples"] {
        for e in std::fs::read_dir(root.join(dir)).expect("dir") {
            let p = e.expect("entry").path();
            if p.extension().is_some_and(|x| x == "nc") {
                files.push(p);
            }
        }
    }
    assert!(files.len() >= 15);
    for p in files {
        let s = p.display().to_string();
        for flags in [
            &[][..],
            &["--resolve"],
            &["--dialect", "fms3000"],
            &["--comments", "--compact"],
        ] {
            let mut args = vec!["run", s.as_str(), "-o", "-"];
            args.extend_from_slice(flags);
            same(&args, root, &format!("{s} {flags:?}"));
        }
    }
}

/// A random NC-only program: motion, codes, comments, block delete, sequence numbers, blank lines,
/// odd spacing, values with and without points and signs — and, now and then, text outside the
/// flat subset (a sign or point where the compiler refuses one, a bad code), so that both paths
/// must also fail the same way.
fn program(r: &mut Rng) -> String {
    let mut s = String::new();
    if r.next().is_multiple_of(2) {
        s.push_str("%\n");
    }
    if r.next().is_multiple_of(2) {
        s.push_str(r.pick(&[
            "O1 (RANDOM)\n",
            "O0077\n",
            "O12 (A B)\n",
            "O12 (A B)\r\n",
            "O5\r\n",
        ]));
    }
    s.push_str("G21 G90 G17 G54\n");
    for _ in 0..(20 + r.next() % 40) {
        let mut line = String::new();
        match r.next() % 12 {
            0 => line.push('/'),
            1 => line.push_str(&format!("N{} ", r.next() % 2000)),
            2 => line.push_str("  "),
            _ => {}
        }
        let words = 1 + r.next() % 5;
        for _ in 0..words {
            let w = match r.next() % 14 {
                0 => format!(
                    "G{}",
                    r.pick(&[
                        "0", "1", "2", "3", "17", "90", "91", "94", "4", "54", "40", "80", "21"
                    ])
                ),
                1 => format!("M{}", r.pick(&["3", "5", "8", "9", "6", "0", "1"])),
                2 => format!("F{}", r.pick(&["100", "250.", "1000", "33.3"])),
                3 => format!("S{}", r.pick(&["1200", "800"])),
                4 => format!("T{}", r.next() % 20),
                5 => format!("P{}", r.pick(&["500", "1000"])),
                6 => format!("R{}", r.pick(&["5", "10.", "-2.5", "7.25"])),
                7 => format!("I{}", r.pick(&["-10", "5.", "0", "2.5"])),
                8 => format!("J{}", r.pick(&["-10", "5.", "0", "2.5"])),
                // Rare: outside the subset (the compiler decides).
                9 if r.next().is_multiple_of(8) => r
                    .pick(&["M-3", "S10.5", "G-1", "X1.2.3", "x5", "G999"])
                    .to_string(),
                _ => {
                    let axis = r.pick(&["X", "Y", "Z", "X", "Y"]);
                    let int = r.next() % 200;
                    let frac = r.next() % 1000;
                    let sign = if r.next().is_multiple_of(3) { "-" } else { "" };
                    match r.next() % 4 {
                        0 => format!("{axis}{sign}{int}"),
                        1 => format!("{axis}{sign}{int}."),
                        2 => format!("{axis}{sign}.{frac}"),
                        _ => format!("{axis}{sign}{int}.{frac:03}"),
                    }
                }
            };
            line.push_str(&w);
            line.push_str(r.pick(&[" ", "", "  ", "\t"]));
        }
        if r.next().is_multiple_of(6) {
            line.push_str(r.pick(&["(CUT)", " (NEXT PASS)", "(A)"]));
        }
        s.push_str(line.trim_end());
        s.push_str(r.pick(&["\n", "\n", "\r\n", "\n\n"]));
    }
    s.push_str(r.pick(&["M30\n", "M2\n", ""]));
    if r.next().is_multiple_of(2) {
        s.push_str("%\n");
    }
    s
}

#[test]
fn random_nc_only_programs_expand_the_same_both_ways() {
    let d = Dir::new();
    let mut r = Rng(0x9E37_79B9_7F4A_7C15);
    for i in 0..150 {
        let text = program(&mut r);
        d.file("p.nc", &text);
        for flags in [
            &[][..],
            &["--resolve"],
            &["--block-delete"],
            &["--max-blocks", "7"],
        ] {
            let mut args = vec!["run", "p.nc", "-o", "-", "--comments"];
            args.extend_from_slice(flags);
            same(
                &args,
                d.0.path(),
                &format!("program {i} {flags:?}:\n{text}"),
            );
        }
    }
}

#[test]
fn an_alarm_in_a_flat_program_points_at_its_block() {
    let d = Dir::new();
    d.file("p.nc", "G0 X1\nG1 X2 F100\n  G999 X3\nM30\n");
    let o = bin()
        .args(["run", "p.nc", "-o", "out.nc"])
        .current_dir(d.0.path())
        .output()
        .expect("runs");
    assert_eq!(o.status.code(), Some(4));
    let e = stderr(&o);
    assert!(e.contains("--> p.nc:3:1"), "{e}");
    assert!(e.contains("3 |   G999 X3"), "{e}");
    assert!(e.contains("stopped after 2 blocks"), "{e}");
    assert!(!d.path("out.nc").exists());
}

/// The cases a review found where the two paths once parted: a lone N before `%`, a CR inside a
/// line, `--max-blocks 0`, leader comments before the O line or before `%`, bytes after the closing
/// `%`, the step count of `--stats`.
#[test]
fn structural_cases_expand_the_same_both_ways() {
    let d = Dir::new();
    let cases: [(&str, &[u8], &[&str]); 9] = [
        ("lone-n", b"N10\n%\nG0 X1\nG0 X2\nM30\n%\n", &[]),
        ("cr", b"G0 X1\rY2\nM30\n", &[]),
        ("cr-comment", b"G0 X1 (A\rB) Y2\n", &[]),
        ("max-blocks-0", b"G0 X1\nM30\n", &["--max-blocks", "0"]),
        ("leader-o", b"(HDR)\nO1234\nG0 X1\nM30\n", &["--comments"]),
        ("leader-percent", b"(LEADER)\n%\nG0 X1\nM30\n%\n", &[]),
        ("after-percent", b"%\nG0X1\nM30\n%\n\xe4\xe4\n", &[]),
        ("stats", b"G0 X1\nG1 X2 F100\nM30\n", &["--stats"]),
        ("slash-leader", b"/\n%\nG0 X1\nM30\n%\n", &[]),
    ];
    for (name, text, flags) in cases {
        let file = format!("{name}.nc");
        d.bytes(&file, text);
        let mut args = vec!["run", file.as_str(), "-o", "-"];
        args.extend_from_slice(flags);
        let (f, c) = both(&args, d.0.path());
        assert_eq!(
            f.status.code(),
            c.status.code(),
            "{name}: exit\n{}\n{}",
            stderr(&f),
            stderr(&c)
        );
        // --stats prints a time: compare its first line up to " in ".
        let (fe, ce) = (stderr(&f), stderr(&c));
        let cut = |e: &str| e.split(" in ").next().unwrap_or("").to_string();
        assert_eq!(cut(&fe), cut(&ce), "{name}: messages");
        assert!(f.stdout == c.stdout, "{name}: output differs");
    }
}

/// A random program with macro lines among plain ones: the compiler decodes each plain line straight
/// from the text (`fmsvm_compiler::plain`); parsed with the full grammar instead, every line must give
/// the same IR, spans and diagnostics.
#[test]
fn plain_lines_compile_as_the_full_grammar_reads_them() {
    use fmsvm_compiler::{Options, compile_str};
    let mut r = Rng(0x2545_F491_4F6C_DD1D);
    let mut compiled = 0;
    for i in 0..300 {
        let text = program(&mut r);
        let mut mixed = String::from("#1=0\n");
        for line in text.split_inclusive('\n') {
            mixed.push_str(line);
            match r.next() % 9 {
                0 => mixed.push_str("#1=[#1+0.5]\n"),
                1 => mixed.push_str("G1 X[#1*2] Y-1.5\n"),
                2 => mixed.push_str("N77 #2=#1\n"),
                _ => {}
            }
        }
        let full = Options {
            parse_every_line: true,
            ..Options::default()
        };
        let (a, da, _) = compile_str(&mixed, &Options::default());
        let (b, db, _) = compile_str(&mixed, &full);
        assert_eq!(
            format!("{da:?}"),
            format!("{db:?}"),
            "program {i}:\n{mixed}"
        );
        assert_eq!(format!("{a:?}"), format!("{b:?}"), "program {i}:\n{mixed}");
        compiled += usize::from(a.is_some());
    }
    // Most are programs (some hold a word outside the subset, refused both ways).
    assert!(compiled > 150, "{compiled} of 300 compiled");
}
