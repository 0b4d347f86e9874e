//! The control's parameters through the binary: `--params`, `--control`, flags over both, and
//! `fmsvm params --show` reloading to the same behaviour.

use crate::cli_support;

use cli_support::{Dir, stderr, stdout};

/// A program whose output depends on the parameters: the G100 macro call (6050), MOD on integers,
/// NAT (ATAN in −180…180), decimal-point input (X10 = 10 µm under increment input).
const PROGRAM: &str = "#100=[7.5 MOD 2]\n#101=ATAN[-1]/[-1]\nG100 X10\nG0 X10\nM30\n";
const MACRO: &str = "O9010\nG1 X#24 F100.\nM99\n";

fn run(d: &Dir, args: &[&str]) -> (String, String) {
    let mut all = vec!["run", "p.nc", "--lib", "lib", "--dump-vars", "v.txt"];
    all.extend_from_slice(args);
    let o = d.run(&all);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    (stdout(&o), d.read("v.txt"))
}

#[test]
fn the_file_sets_the_control_and_flags_override_it() {
    let d = Dir::new();
    d.file("p.nc", PROGRAM);
    d.file("lib/O9010.nc", MACRO);
    d.file(
        "p.toml",
        "[macro]\nnat = true\nmod_integers = true\ndecimal_input = \"increment\"\n[calls]\n6050 = 100\n",
    );
    let (out, vars) = run(&d, &["--params", "p.toml"]);
    // G100 calls O9010 with X10 (no point: 0.010 under increment input); X10 likewise.
    assert_eq!(out, "%\nG1 X0.01 F100.\nG0 X0.01\nM30\n%\n");
    // MOD on integers: 8 MOD 2 = 0; NAT: ATAN[-1]/[-1] = -135.
    assert!(
        vars.contains("(#100=0)") && vars.contains("(#101=-135)"),
        "{vars}"
    );
    // A flag overrides the file.
    let (out, _) = run(&d, &["--params", "p.toml", "--decimal-input", "calculator"]);
    assert_eq!(out, "%\nG1 X10. F100.\nG0 X10.\nM30\n%\n");
    // The printed parameters reload to the same behaviour.
    let o = d.run(&["params", "--show", "--params", "p.toml"]);
    assert!(o.status.success(), "{}", stderr(&o));
    d.file("shown.toml", &stdout(&o));
    let (again, vars_again) = run(&d, &["--params", "shown.toml"]);
    assert_eq!(again, "%\nG1 X0.01 F100.\nG0 X0.01\nM30\n%\n");
    assert_eq!(vars_again, vars);
    // A bad key names its file and line, exit 2.
    d.file("bad.toml", "[macro]\nnat = true\nnatt = true\n");
    let o = d.run(&["run", "p.nc", "--params", "bad.toml"]);
    assert_eq!(o.status.code(), Some(2));
    // Every TOML file's errors are `file:line:column` (one reader for --params, --offsets, --dialect-file).
    assert!(
        stderr(&o).contains("bad.toml:3:1: [macro] unknown field `natt`"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_control_profile_selects_its_syntax() {
    let d = Dir::new();
    d.file("h.nc", "G0 X0\nG81 XI10 Y50 R2 Z-10\nG80\nM30\n");
    // Fanuc syntax refuses XI; the nct profile reads it (XI10 from X0: X10).
    let o = d.run(&["run", "h.nc"]);
    assert_eq!(o.status.code(), Some(3));
    let o = d.run(&["run", "h.nc", "--control", "nct"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("G81 X10. Y50. R2. Z-10."),
        "{}",
        stdout(&o)
    );
    let o = d.run(&["params", "--show", "--control", "nct"]);
    assert!(stdout(&o).contains("input = \"nct\""), "{}", stdout(&o));
}

#[test]
fn an_output_never_replaces_the_parameter_or_offsets_file() {
    let d = Dir::new();
    d.file("p.nc", "G0 X1\nM30\n");
    d.file("p.toml", "[macro]\nnat = true\n");
    d.file("o.toml", "[tool.1]\nradius = 2.0\n");
    for (flag, file) in [("--params", "p.toml"), ("--offsets", "o.toml")] {
        let before = d.read(file);
        let o = d.run(&["run", "p.nc", flag, file, "-o", file]);
        assert_eq!(o.status.code(), Some(2), "{flag}: {}", stderr(&o));
        assert_eq!(d.read(file), before, "{flag}: the file is untouched");
    }
}

/// `[calls] s_code` and `b_code` through the binary: O9029 and O9028 from `--lib`, the S and B in
/// them ordinary words; `params --show` prints the keys and reloads to the same output.
#[test]
fn s_and_b_code_calls_from_the_file() {
    let d = Dir::new();
    d.file("p.nc", "G0 X1. S800 M3\nB45.\nM30\n");
    d.file("lib/O9029.nc", "O9029\n#100=#147\nS[#147*2]\nM99\n");
    d.file("lib/O9028.nc", "O9028\n#500=#146\nB#146\nM99\n");
    d.file("p.toml", "[calls]\ns_code = true\nb_code = true\n");
    let (out, vars) = run(&d, &["--params", "p.toml"]);
    assert_eq!(out, "%\nG0 X1. M3\nS1600\nB45.\nM30\n%\n");
    assert!(
        vars.contains("(#100=800)") && vars.contains("#500=45"),
        "{vars}"
    );
    let o = d.run(&["params", "--show", "--params", "p.toml"]);
    let shown = stdout(&o);
    assert!(
        shown.contains("s_code = true") && shown.contains("b_code = true"),
        "{shown}"
    );
    d.file("shown.toml", &shown);
    assert_eq!(run(&d, &["--params", "shown.toml"]).0, out);
    // s_code with 6089 calls O9029 two ways: refused at the second key's line.
    d.file("both.toml", "[calls]\n6089 = 123\ns_code = true\n");
    let o = d.run(&["run", "p.nc", "--params", "both.toml"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("both.toml:3:"), "{}", stderr(&o));
}

/// Inside O9028 the second auxiliary function's code is a code for the machine, not B-axis motion
/// (Fanuc: with the function at B the machine has no B axis): the literal output keeps `B45.`, the
/// resolved output writes the code on its own line and no move, `#5005` (the B position) stays 0,
/// `stats` counts no B motion, and `--verify` reads the code back as a code. Without `b_code` the
/// same `B45.` is a move of the rotary axis.
#[test]
fn the_second_auxiliary_code_is_not_b_axis_motion() {
    let d = Dir::new();
    d.file("p.nc", "G0 X1. S800 M3\nB45.\nG1 X2. F100\nM30\n");
    d.file("lib/O9028.nc", "O9028\n#500=#146\nB#146\n#501=#5005\nM99\n");
    // The B axis starts at B0 (declared: #5005 of an axis never positioned is not known), and
    // the code B45. must not move it.
    d.file(
        "p.toml",
        "[calls]\nb_code = true\n[machine]\nstart_point = \"X0 Y0 Z0 B0\"\n",
    );
    let (out, vars) = run(&d, &["--params", "p.toml"]);
    assert_eq!(out, "%\nG0 X1. S800 M3\nB45.\nG1 X2. F100.\nM30\n%\n");
    assert!(
        vars.contains("#500=45") && vars.contains("#501=0\n"),
        "{vars}"
    );
    let (out, _) = run(&d, &["--params", "p.toml", "--resolve"]);
    assert!(
        // From the declared start only X moves: X alone is written; B45 is a code, no B motion.
        out.contains("\nG0 X1.\nB45\nG1 X2. F100.\n"),
        "{out}"
    );
    for resolve in [false, true] {
        let mut args = vec!["run", "p.nc", "--lib", "lib", "--params", "p.toml"];
        args.extend(["-o", "out.nc", "--verify"]);
        if resolve {
            args.push("--resolve");
        }
        let o = d.run(&args);
        assert!(
            o.status.success(),
            "--verify, resolve {resolve}: {}",
            stderr(&o)
        );
    }
    let o = d.run(&["stats", "p.nc", "--lib", "lib", "--params", "p.toml"]);
    let report = stdout(&o);
    assert!(report.contains("moves        1 rapid, 1 feed"), "{report}");
    assert!(!report.contains(" B "), "{report}");
    // Without the parameter B is the rotary axis: a rapid move to B45.
    let (_, vars) = run(&d, &[]);
    assert!(!vars.contains("#500"), "O9028 is not called: {vars}");
    // From a declared B0 (unknown otherwise, and the extents would not hold it).
    let o = d.run(&[
        "stats",
        "p.nc",
        "--lib",
        "lib",
        "--start-point",
        "X0 Y0 Z0 B0",
    ]);
    let report = stdout(&o);
    assert!(report.contains("moves        2 rapid, 1 feed"), "{report}");
    assert!(report.contains("B 0.000 .. 45.000 deg"), "{report}");
}

/// The second auxiliary function's code is an integer code, not an angle: under decimal-point input
/// type I a `B7` written without a point inside O9028 is 7, not 0.007°; `--compact` never drops a
/// repeated code (a table index is not a position); NCT's incremental operator does not apply to it.
#[test]
fn the_second_auxiliary_code_is_a_code_in_every_rule() {
    let d = Dir::new();
    d.file("p.nc", "G0 X1. Y0 Z0\nB45\nB45\nG0 X1. Y0 Z0\nM30\n");
    // O9028 passes the code on, then writes a code of its own (a literal without a point).
    d.file("lib/O9028.nc", "O9028\nB#146\nB7\nM99\n");
    d.file(
        "p.toml",
        "[macro]\ndecimal_input = \"increment\"\n[calls]\nb_code = true\n",
    );
    // #146 holds 45 as written, and B7 is 7, not 0.007° (X1. has its point: 1 mm).
    let each = "B45.\nB7.\n";
    let want = format!("%\nG0 X1. Y0. Z0.\n{each}{each}G0 X1. Y0. Z0.\nM30\n%\n");
    let (out, _) = run(&d, &["--params", "p.toml"]);
    assert_eq!(out, want);
    let (out, _) = run(&d, &["--params", "p.toml", "--resolve"]);
    assert!(out.contains("\nB45\nB7\nB45\nB7\n"), "{out}");
    // --compact keeps every code, and forgets the position at them: the second X1. Y0 Z0 is written.
    let (out, _) = run(&d, &["--params", "p.toml", "--compact"]);
    assert_eq!(out, want);
    // A B axis, without the parameter: B45 is 0.045° under type I, and --compact drops the repeat.
    d.file("q.toml", "[macro]\ndecimal_input = \"increment\"\n");
    let o = d.run(&["run", "p.nc", "--params", "q.toml", "--compact", "-o", "-"]);
    assert_eq!(
        stdout(&o),
        "%\nG0 X1. Y0. Z0.\nB0.045\nM30\n%\n",
        "{}",
        stderr(&o)
    );
    // NCT's `BI` inside O9028: the incremental operator is for axes and R (alarm 0114 at its line).
    d.file("lib/O9028.nc", "O9028\nBI#146\nM99\n");
    d.file(
        "n.toml",
        "[macro]\ninput = \"nct\"\n[calls]\nb_code = true\n",
    );
    let o = d.run(&[
        "run", "p.nc", "--lib", "lib", "--params", "n.toml", "-o", "-",
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("alarm 0114") && err.contains("O9028.nc:2:1"),
        "{err}"
    );
}

/// `common_volatile` / `common_retained`: a variable outside them is alarm 0115 (compile time, exit
/// 3), `--vars` loads only the retained range and `--dump-vars` writes it back, the volatile range as
/// comments; a bad range is refused at its line.
#[test]
fn the_common_ranges_from_the_file() {
    let d = Dir::new();
    d.file(
        "p.toml",
        "[macro]\ncommon_volatile = [100, 149]\ncommon_retained = [500, 549]\n",
    );
    d.file("p.nc", "#149=#549+1\n#549=#149\nM30\n");
    d.file("store.txt", "#549=41\n");
    let o = d.run(&[
        "run",
        "p.nc",
        "--params",
        "p.toml",
        "--vars",
        "store.txt",
        "--dump-vars",
        "v.txt",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        d.read("v.txt"),
        "(fmsvm common variables; #100-#149 are volatile and not reloaded)\n(#149=42)\n#549=42\n"
    );
    // #550 is no variable under these ranges, in the program and in the store.
    d.file("q.nc", "#550=1\nM30\n");
    let o = d.run(&["run", "q.nc", "--params", "p.toml"]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stderr(&o).contains("alarm 0115"), "{}", stderr(&o));
    d.file("bad-store.txt", "#550=1\n");
    let o = d.run(&[
        "run",
        "p.nc",
        "--params",
        "p.toml",
        "--vars",
        "bad-store.txt",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("bad-store.txt:1:"), "{}", stderr(&o));
    // Without the file #550 is a retained common.
    assert!(d.run(&["run", "q.nc"]).status.success());
    // params --show prints the ranges.
    let shown = stdout(&d.run(&["params", "--show", "--params", "p.toml"]));
    assert!(
        shown.contains("common_volatile = [100, 149]")
            && shown.contains("common_retained = [500, 549]"),
        "{shown}"
    );
    // A range that overlaps the other, at its line.
    d.file(
        "bad.toml",
        "[macro]\nnat = true\ncommon_retained = [120, 999]\n",
    );
    let o = d.run(&["run", "p.nc", "--params", "bad.toml"]);
    assert_eq!(o.status.code(), Some(2));
    // Every TOML file's errors are `file:line:column` (one reader for --params, --offsets, --dialect-file).
    assert!(
        stderr(&o).contains("bad.toml:3:19: [macro] common_retained"),
        "{}",
        stderr(&o)
    );
}

/// `--control fms3000`: numbers without a point are mm (FMS-3000 §1.3.2), so `X10` is 10 mm even
/// where a flag-free Fanuc run would say so too, and `--decimal-input increment` still overrides it;
/// `params --show` names the profile and N3021 = 0.
#[test]
fn the_fms3000_profile() {
    let d = Dir::new();
    d.file("p.nc", "G1 X10 F100\nM30\n");
    let o = d.run(&["run", "p.nc", "--control", "fms3000"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stdout(&o), "%\nG1 X10. F100.\nM30\n%\n");
    let o = d.run(&[
        "run",
        "p.nc",
        "--control",
        "fms3000",
        "--decimal-input",
        "increment",
    ]);
    assert_eq!(stdout(&o), "%\nG1 X0.01 F100.\nM30\n%\n");
    let o = d.run(&["params", "--show", "--control", "fms3000"]);
    let shown = stdout(&o);
    assert!(shown.contains("# --control fms3000:"), "{shown}");
    assert!(shown.contains("decimal_input = \"calculator\""), "{shown}");
    assert!(shown.contains("N3021 = 0"), "{shown}");
    // N3021 = 1 and 2 are built (`arc_centres_as_n3021_sets_them`; until then this refused
    // `centre = "absolute"`); a mode that does not exist is refused at its line.
    d.file("n3021.toml", "[arcs]\ncentre = \"sideways\"\n");
    let o = d.run(&["run", "p.nc", "--params", "n3021.toml"]);
    assert_eq!(o.status.code(), Some(2));
    // Every TOML file's errors are `file:line:column` (one reader for --params, --offsets, --dialect-file).
    assert!(stderr(&o).contains("n3021.toml:2:10:"), "{}", stderr(&o));
}

/// FMS-3000 parameter N3021 (`[arcs] centre`), the manual's Fig. 17 arcs from (200, 40): centre
/// (140, 40) to (140, 100), then centre (90, 100) to (120, 60). With N3021 = 1 (§2.4.2) I J are
/// the centre itself under G90 and G91 alike (`I140 J40`, `I90 J100`); with N3021 = 2 (§2.4.3) the
/// centre itself under G90, from the start point under G91 (`I-60`, `I-50`). Each reads as the same
/// arcs Fanuc's I J from the start point give (`I-60 J0`, `I-50 J0`); literal output, which would
/// copy the words as written, is refused (alarm 0021), as is an absolute centre missing a word.
#[test]
fn arc_centres_as_n3021_sets_them() {
    let d = Dir::new();
    d.file("n1.toml", "[arcs]\ncentre = \"absolute\"\n");
    d.file("n2.toml", "[arcs]\ncentre = \"modal\"\n");
    let g91 = |i1: &str, i2: &str| {
        format!(
            "G90 G17 G21\nG0 X200 Y40 Z0\nG90 G03 X140 Y100 I140 J40 F300\nG02 X120 Y60 I90 J100\nG0 X200 Y40\nG91 G03 X-60 Y60 {i1}\nG02 X-20 Y-40 {i2}\nG90\nM30\n"
        )
    };
    d.file("n1.nc", &g91("I140 J40", "I90 J100"));
    d.file("n2.nc", &g91("I-60", "I-50"));
    let want = "G3 X140. Y100. I-60. J0. F300.\nG2 X120. Y60. I-50. J0.\nG0 X200. Y40.\nG3 X140. Y100. I-60. J0.\nG2 X120. Y60. I-50. J0.\n";
    for (program, params) in [("n1.nc", "n1.toml"), ("n2.nc", "n2.toml")] {
        let o = d.run(&[
            "run",
            program,
            "--control",
            "fms3000",
            "--params",
            params,
            "--resolve",
            "-o",
            "out.nc",
        ]);
        assert!(o.status.success(), "{program}: {}", stderr(&o));
        assert!(
            d.read("out.nc").contains(want),
            "{program}: {}",
            d.read("out.nc")
        );
        let o = d.run(&["run", program, "--control", "fms3000", "--params", params]);
        assert_eq!(o.status.code(), Some(4), "{program}: {}", stderr(&o));
        assert!(stderr(&o).contains("error[alarm 0021]"), "{}", stderr(&o));
    }
    d.file(
        "half.nc",
        "G90 G17 G21\nG0 X200 Y40 Z0\nG03 X140 Y100 I140 F300\nM30\n",
    );
    let o = d.run(&[
        "run",
        "half.nc",
        "--control",
        "fms3000",
        "--params",
        "n1.toml",
        "--resolve",
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(stderr(&o).contains("give I and J"), "{}", stderr(&o));
}
