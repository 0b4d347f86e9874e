//! Programs as shops write them (docs/semantics.md): what real shop and vendor programs do that
//! fmsvm must read as a control does, or refuse with a clear word. Programs of our own that
//! exercise each rule, on both engines.

use crate::cli_support;

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

#[test]
fn a_g_code_before_g65_runs_first_and_is_no_argument() {
    // A shop's line: the work offset, then the call whose moves are in it. G57's X is 100 from
    // G54's, so the macro's `G0 X#24` (X160.) lands at X260. in G54's frame, and the next move
    // X10. (still G57) at X110.
    let d = Dir::new();
    d.file(
        "p.nc",
        "%\nO0001\nG90 G54 G0 X0 Y0 Z50.\nN10 G57 G65 P9100 X160. Z5.\nG0 X10.\nM30\nO9100\nG0 X#24 Z#26\nM99\n%\n",
    );
    d.file(
        "off.toml",
        "[work.G54]\nX = 0\nY = 0\nZ = 0\n[work.G57]\nX = 100\nY = 0\nZ = 0\n",
    );
    for engine in ["interp", "jit"] {
        let o = d.run(&[
            "run",
            "p.nc",
            "--resolve",
            "--offsets",
            "off.toml",
            "--engine",
            engine,
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let out = stdout(&o);
        assert!(out.contains("\nX260. Z5.\nX110.\n"), "{engine}: {out}");
        assert!(
            stderr(&o).contains("the G codes before G65/G66 run as a block of their own"),
            "{}",
            stderr(&o)
        );
        // Literal output keeps the G code as its own block before the macro's moves.
        let o = d.run(&["run", "p.nc", "--engine", engine]);
        assert!(
            stdout(&o).contains("\nN10 G57\nG0 X160. Z5.\n"),
            "{}",
            stdout(&o)
        );
    }
    // A G code after G65 is still no argument (alarm 0129).
    d.file("q.nc", "G65 P9100 G57 X1.\nM30\nO9100\nM99\n");
    let o = d.run(&["check", "q.nc"]);
    assert!(stderr(&o).contains("alarm 0129"), "{}", stderr(&o));
}

#[test]
fn m97_on_a_control_that_is_not_a_haas_is_written_with_a_warning() {
    // A Haas program's bolt circle called by M97 P100 L3: without --control haas, M97 is an M code
    // of the machine builder's, written as it is, and the run says why the holes are missing.
    let d = Dir::new();
    d.file(
        "p.nc",
        "G90 G0 X0 Y0 Z5.\nM97 P100 L3\nM30\nN100 G91 G0 X10.\nM99\n",
    );
    for engine in ["interp", "jit"] {
        let o = d.run(&["run", "p.nc", "--engine", engine]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(
            stderr(&o).contains("M97 is written as a plain M code: on a Haas it calls"),
            "{}",
            stderr(&o)
        );
        // On a Haas it is the local call: three moves of X10.
        let o = d.run(&["run", "p.nc", "--control", "haas", "--engine", engine]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(!stderr(&o).contains("M97 is written"), "{}", stderr(&o));
        assert_eq!(stdout(&o).matches("X10.").count(), 3, "{}", stdout(&o));
    }
}

#[test]
fn the_control_s_other_variables_come_from_its_parameters() {
    // A 30i shop's macro keeps its data in the additional commons and counts parts in #3901.
    let d = Dir::new();
    d.file(
        "p.nc",
        "#100000=1068\n#500001=#100000+1\n#26=#901064\nIF[#901011EQ#0]GOTO10\n#1=1\nN10 G0 X#500001\n\
         #3901=#3901+1\nG0 Y#3901\nG0 Z#4012\nM30\n",
    );
    for engine in ["interp", "jit"] {
        // Without the parameters: the first additional common stops the run, naming the key.
        let o = d.run(&["run", "p.nc", "--engine", engine]);
        assert_eq!(o.status.code(), Some(4));
        assert!(
            stderr(&o).contains("system variable #100000 is not available in fmsvm: if the control has it, declare it in --params: [variables]"),
            "{}",
            stderr(&o)
        );
        // The 30i's ranges: #901064 and #901011 are vacant commons; #3901 is still the control's.
        let o = d.run(&["run", "p.nc", "--control", "fanuc-30i", "--engine", engine]);
        assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
        assert!(stdout(&o).contains("N10 G0 X1069."), "{}", stdout(&o));
        assert!(
            stderr(&o).contains("#3901 is not available"),
            "{}",
            stderr(&o)
        );
        // The parts count the control holds, and a Mitsubishi-style #4012 read as Fanuc's #4014
        // (the work offset's G code: G54 at power-on).
        d.file(
            "v.toml",
            "[variables]\nvalues = { 3901 = 41 }\nalias = { 4012 = 4014 }\n",
        );
        let o = d.run(&[
            "run",
            "p.nc",
            "--control",
            "fanuc-30i",
            "--params",
            "v.toml",
            "--engine",
            engine,
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let out = stdout(&o);
        assert!(out.contains("G0 Y42.\nG0 Z54.\n"), "{out}");
    }
    // params --show carries them, and reads back.
    let o = d.run(&[
        "params",
        "--show",
        "--control",
        "fanuc-30i",
        "--params",
        "v.toml",
    ]);
    let shown = stdout(&o);
    assert!(
        shown.contains("ranges = [[100000, 199999], [500000, 999999]]"),
        "{shown}"
    );
    assert!(shown.contains("values = { 3901 = 41.0 }"), "{shown}");
    assert!(shown.contains("alias = { 4012 = 4014 }"), "{shown}");
    d.file("shown.toml", &shown);
    let o = d.run(&["params", "--show", "--params", "shown.toml"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // Declarations that are not variables of the control's own are refused at their line.
    for (bad, want) in [
        ("[variables]\nranges = [[500, 999]]\n", "v.toml:2:"),
        (
            "[variables]\nvalues = { 33 = 1 }\n",
            "a variable number from 1000",
        ),
        (
            "[variables]\nalias = { \"5000-4000\" = 4014 }\n",
            "[variables] alias",
        ),
    ] {
        d.file("v.toml", bad);
        let o = d.run(&["run", "p.nc", "--params", "v.toml"]);
        assert_eq!(o.status.code(), Some(2), "{bad}");
        assert!(stderr(&o).contains(want), "{bad}: {}", stderr(&o));
    }
}

#[test]
fn a_library_program_fmsvm_cannot_read_stops_only_the_run_that_calls_it() {
    // A probe vendor's macro jumps over a call to a program with a line fmsvm cannot read (here a
    // `LTE`): a control never reads that program, and neither does the run. When the call does
    // run, its alarm names the unreadable line.
    let d = Dir::new();
    d.file("lib/O9724.nc", "O9724\nG0 X5.\nM99\n");
    d.file("lib/O9732.nc", "O9732\nG0 X1.\n#1=[1 LTE 2]\nM99\n");
    let main = "O0001\nG0 X0 Y0 Z10.\n#1=0\nIF [#1 EQ 0] GOTO 20\nM98 P9732\nN20 M98 P9724\nM30\n";
    d.file("main.nc", main);
    for engine in ["interp", "jit"] {
        let o = d.run(&["run", "main.nc", "--lib", "lib", "--engine", engine]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(stdout(&o).contains("G0 X5.\nM30"), "{}", stdout(&o));
        assert!(
            stderr(&o).contains("fmsvm raises the alarm when O9732 is called"),
            "{}",
            stderr(&o)
        );
        d.file("main.nc", &main.replace("#1=0", "#1=1"));
        let o = d.run(&["run", "main.nc", "--lib", "lib", "--engine", engine]);
        assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
        let lib = std::path::Path::new("lib").join("O9732.nc");
        assert!(
            stderr(&o).contains(&format!(
                "error[alarm 0114]: O9732 cannot be read: {}:3:7:",
                lib.display()
            )),
            "{}",
            stderr(&o)
        );
        d.file("main.nc", main);
    }
    // check reports the line, as a warning that says when a control would alarm.
    let o = d.run(&["check", "main.nc", "--lib", "lib"]);
    assert!(o.status.success());
    assert!(stderr(&o).contains("warning[alarm 0114]"), "{}", stderr(&o));
}

#[test]
fn haas_programs_dwell_in_seconds_and_guard_blocks_with_if() {
    // Haas: `G04 P200.` dwells 200 s (a decimal P is seconds); `IF [cond] G65 P…` without THEN
    // calls when the condition holds. Fanuc refuses both.
    let d = Dir::new();
    d.file("O9725.nc", "O9725\nG0 X#1\nM99\n");
    let p = "O0001\nG0 X0 Y0 Z5.\n#598=0\nIF [#598 NE 1.] G65 P9725 A2.\nN10 IF [#598 EQ 1] G0 X7.\nG04 P200.\nG04 P1500\nM30\n";
    d.file("p.nc", p);
    for engine in ["interp", "jit"] {
        let o = d.run(&[
            "run",
            "p.nc",
            "--lib",
            ".",
            "--control",
            "haas",
            "--engine",
            engine,
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let out = stdout(&o);
        assert!(out.contains("G0 X2.\nG4 P200000\nG4 P1500\n"), "{out}");
        assert!(!out.contains("X7."), "{out}");
    }
    let o = d.run(&["check", "p.nc", "--lib", "."]);
    let e = stderr(&o);
    assert!(
        e.contains("an NC block after IF without THEN is Haas's"),
        "{e}"
    );
    assert!(
        e.contains("illegal use of decimal point: P takes a whole number"),
        "{e}"
    );
}

#[test]
fn check_says_where_a_run_would_stop_on_a_variable_fmsvm_does_not_model() {
    // check used to pass this program, and its run stopped at #3901. Now check warns at each
    // variable fmsvm does not model (once a variable), unless the parameters declare it.
    let d = Dir::new();
    d.file("p.nc", "#1=#3901\n#3901=#1+1\n#2=#1000\nG0 X#1\nM30\n");
    let o = d.run(&["check", "p.nc"]);
    assert!(o.status.success());
    let e = stderr(&o);
    assert_eq!(e.matches("fmsvm does not model #3901").count(), 1, "{e}");
    assert!(e.contains("fmsvm does not model #1000"), "{e}");
    assert!(e.contains(" --> p.nc:1:4"), "{e}");
    let o = d.run(&["check", "p.nc", "--deny-warnings"]);
    assert_eq!(o.status.code(), Some(3));
    d.file("v.toml", "[variables]\nvalues = { 3901 = 7, 1000 = 0 }\n");
    let o = d.run(&["check", "p.nc", "--params", "v.toml", "--deny-warnings"]);
    assert!(o.status.success(), "{}", stderr(&o));
}
