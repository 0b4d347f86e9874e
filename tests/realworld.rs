//! Programs as shops write them (docs/semantics.md): what real shop and vendor programs do that
//! fmsvm must read as a control does, or refuse with a clear word. Programs of our own that
//! exercise each rule, on both engines.

mod cli_support;

use cli_support::{Dir, stderr, stdout};

#[test]
fn two_library_files_with_one_program_number_are_both_named_and_neither_taken() {
    // A shop's library folders hold O9010 twice (a copy left behind): which one the control has
    // is not known, so the run stops at the call and names both files.
    let d = Dir::new();
    d.file("a/O9010.nc", "O9010\nG0 X1.\nM99\n");
    d.file("b/probe.nc", "O9010\nG0 X2.\nM99\n");
    d.file("c/O9011.nc", "O9011\nG0 X3.\nM99\n");
    d.file("main.nc", "M98 P9011\nM98 P9010\nM30\n");
    for engine in ["interp", "jit"] {
        let o = d.run(&[
            "run", "main.nc", "--lib", "a", "--lib", "b", "--lib", "c", "--engine", engine,
        ]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(4), "{e}");
        assert!(
            e.contains("O9010 is held by a/O9010.nc and b/probe.nc"),
            "{engine}: {e}"
        );
        assert!(
            !stdout(&o).contains("X1.") && !stdout(&o).contains("X2."),
            "{engine}"
        );
        // The program only one file holds is found as before.
        let o = d.run(&[
            "run", "main.nc", "--lib", "a", "--lib", "c", "--engine", engine,
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(
            stdout(&o).contains("X3.") && stdout(&o).contains("X1."),
            "{}",
            stdout(&o)
        );
    }
}

#[test]
fn abbreviated_macro_words_read_as_the_full_words_with_a_warning() {
    // A shop's loop written with the two-letter forms a Fanuc takes at entry: the same flat
    // program as the full words give, on both engines, and `check` names each abbreviation.
    let short = "#1=0\nWH[#1LT3]DO1\n#1=#1+1\nG0 X[AB[-#1]] Y[SQ[#1*#1]]\nEN1\nIF[#1EQ3]TH#2=AT[1]/[1]\n\
                 GO10\nG0 X99.\nN10 G0 Z[#2]\nM30\n";
    let full = "#1=0\nWHILE[#1LT3]DO1\n#1=#1+1\nG0 X[ABS[-#1]] Y[SQRT[#1*#1]]\nEND1\nIF[#1EQ3]THEN#2=ATAN[1]/[1]\n\
                GOTO10\nG0 X99.\nN10 G0 Z[#2]\nM30\n";
    let d = Dir::new();
    d.file("short.nc", short);
    d.file("full.nc", full);
    for engine in ["interp", "jit"] {
        let a = d.run(&["run", "short.nc", "--engine", engine]);
        let b = d.run(&["run", "full.nc", "--engine", engine]);
        assert!(a.status.success() && b.status.success(), "{}", stderr(&a));
        assert_eq!(stdout(&a), stdout(&b), "{engine}");
        assert!(
            stdout(&a).contains("G0 X3. Y3.") && stdout(&a).contains("Z45."),
            "{}",
            stdout(&a)
        );
        assert!(!stdout(&a).contains("X99."), "GO10 jumps over it");
    }
    let o = d.run(&["check", "short.nc"]);
    let e = stderr(&o) + &stdout(&o);
    for (abbr, word) in [
        ("WH", "WHILE"),
        ("AB", "ABS"),
        ("SQ", "SQRT"),
        ("EN", "END"),
        ("TH", "THEN"),
        ("AT", "ATAN"),
        ("GO", "GOTO"),
    ] {
        assert!(
            e.contains(&format!("`{abbr}` is read as {word}")),
            "{abbr}: {e}"
        );
    }
    let o = d.run(&["check", "full.nc"]);
    assert!(
        !(stderr(&o) + &stdout(&o)).contains("is read as"),
        "the full words are no abbreviations"
    );
    // In capitals only: letters in other text (`O<MyProgram>`, an error anyway) are no words.
    d.file("lower.nc", "O<MyProgram>\nM30\n");
    let o = d.run(&["check", "lower.nc"]);
    assert!(!o.status.success());
    assert!(!stderr(&o).contains("is read as"), "{}", stderr(&o));
}
