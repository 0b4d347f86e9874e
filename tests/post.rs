//! `fmsvm post`, the turning library's postprocessor contract (docs/postprocessor.md): the neutral
//! language in, the control's words out in `output.tmp`, `OK` or located errors on standard output.
//! The oracle: the seed's own Маяк-600Т listing (its input records and the postprocessor's output).

use crate::cli_support;

use cli_support::{Dir, stdout};

/// The seed's Маяк-600Т input, as the library writes `input.tmp` (the annotations are the seed's).
const MAYAK_INPUT: &str = include_str!("post/mayak-input.txt");

/// The seed's Маяк-600Т output for it, word for word.
const MAYAK_LISTING: &str = include_str!("post/mayak-output.txt");

/// The seed's listing (an excerpt of a program, from N006) as fmsvm writes it: word for word, with
/// the start every program now gets on its first block (`G90 G95`: absolute, and feed per
/// revolution, the neutral F's meaning, written rather than left to the control's state).
fn mayak_output() -> String {
    MAYAK_LISTING.replacen("N006 ", "N006 G90 G95 ", 1)
}

#[test]
fn the_seeds_mayak_listing_comes_out_word_for_word() {
    let d = Dir::new();
    d.file("input.tmp", MAYAK_INPUT);
    let o = d.run(&["post", "--dialect", "mayak600t", "input.tmp"]);
    assert_eq!(stdout(&o), "OK\n");
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(d.read("output.tmp"), mayak_output());
    // On Windows its lines end in CR LF, and so do the output's.
    d.file("input.tmp", &MAYAK_INPUT.replace('\n', "\r\n"));
    let o = d.run(&["post", "--dialect", "mayak600t", "input.tmp"]);
    assert_eq!(stdout(&o), "OK\n");
    assert_eq!(d.read("output.tmp"), mayak_output().replace('\n', "\r\n"));
    // The library writes in its users' code page: the same in CP1251 (a Cyrillic annotation).
    let cp1251: Vec<u8> = MAYAK_INPUT
        .replace(
            "; cutting conditions",
            "; \u{440}\u{435}\u{436}\u{438}\u{43c}\u{44b}",
        )
        .chars()
        .map(|c| match c {
            '\u{430}'..='\u{44f}' => (c as u32 - 0x430 + 0xE0) as u8,
            c => c as u8,
        })
        .collect();
    std::fs::write(d.path("input.tmp"), cp1251).expect("written");
    let o = d.run(&["post", "--dialect", "mayak600t", "input.tmp"]);
    assert_eq!(stdout(&o), "OK\n");
    assert_eq!(d.read("output.tmp"), mayak_output());
}

#[test]
fn a_malformed_input_gets_located_errors_and_no_output() {
    let d = Dir::new();
    // A stale output.tmp from an earlier run must not pass for this one's.
    d.file("output.tmp", "N001 G00 X0 Z0\n");
    for (input, want) in [
        (
            "N007 G00 X68 Z2.5\nN008 CYCLE 72 I=5 P=2?5 _Xend=68 _Zend=-23.5\nN009 Z-23.5\nN010 G80\n",
            "input.tmp:2:21: P=`2?5`: the value of P is not a number",
        ),
        (
            "N008 CYCLE 72 I=5 _Xend=68 _Zend=-23.5\nN009 Z-23.5\nN010 G80\n",
            "input.tmp:1:1: CYCLE 72: the obligatory parameter P (параметр перемещения по X) is not given",
        ),
        (
            "N008 CYCLE 77 P1=2 W=1 _Xend=68 _Zend=-23.5\nN009 Z-23.5\nN010 G80\n",
            "input.tmp:1:1: CYCLE 77: not one of the control's machine cycles (72, 73, 82)",
        ),
        (
            "N008 CYCLE 72 I=5 Q=3 P=5 _Xend=68 _Zend=-23.5\nN009 Z-23.5\nN010 G80\n",
            "input.tmp:1:19: CYCLE 72: Q is not a parameter of this cycle",
        ),
        (
            "N005 G00 X68 Y2\n",
            "input.tmp:1:14: `Y2`: not a word of the neutral language",
        ),
        (
            "N005 G96 S180\n",
            // The Маяк-600Т has no constant surface speed known (docs/lathe.md).
            "input.tmp:1:6: G96 (constant surface speed): this control has none known",
        ),
        (
            "N008 CYCLE 72 I=5 P=5 _Xend=68 _Zend=-23.5\nN009 Z-23.5\n",
            "input.tmp:1:1: CYCLE 72: its profile has no G80",
        ),
    ] {
        d.file("input.tmp", input);
        let o = d.run(&["post", "--dialect", "mayak600t", "input.tmp"]);
        let out = stdout(&o);
        assert!(out.lines().any(|l| l.starts_with(want)), "{input}\n{out}");
        assert!(!out.contains("OK"), "{out}");
        assert_eq!(o.status.code(), Some(2), "{out}");
        assert!(
            !d.path("output.tmp").exists(),
            "no output.tmp after {input}"
        );
    }
    // Every error of the input, one a line.
    d.file(
        "input.tmp",
        "N001 G00 X1 Y2\nN002 G65 X1\nN003 CYCLE 72 I=5 P=5 _Xend=1 _Zend=1\nN004 Z1\nN005 G80\n",
    );
    let out = stdout(&d.run(&["post", "--dialect", "mayak600t", "input.tmp"]));
    assert_eq!(out.lines().count(), 2, "{out}");
    // A control without a catalogue, and no control at all, are usage errors, said on stdout.
    let o = d.run(&["post", "--dialect", "fanuc", "input.tmp"]);
    assert!(
        stdout(&o).contains("declares no machine cycles"),
        "{}",
        stdout(&o)
    );
    assert_eq!(o.status.code(), Some(2));
    let o = d.run(&["post", "input.tmp"]);
    assert!(stdout(&o).contains("give the control"), "{}", stdout(&o));
}

#[test]
fn the_catalogue_prints_as_the_library_reads_it_and_a_profile_adds_to_it() {
    let d = Dir::new();
    let o = d.run(&["dialects", "--cycles", "mayak600t"]);
    assert_eq!(o.status.code(), Some(0));
    let text = stdout(&o);
    assert!(
        text.starts_with(
            "BEGIN_MACHINE_CYCLES\n\nBEGIN_CYCLE 72\nNAME \"Цикл продольного точения\"\n"
        ),
        "{text}"
    );
    assert!(text.contains("\nP O \"параметр перемещения по X\"\nbegin_list\n\"с подачей F\"\n\"с максимальной скоростью (G0)\"\nend_list\n"), "{text}");
    assert!(text.contains("\nPROFIL_DEMANDS \"TrapecV1 | TrapecV2 | TrapecV3 | TrapecV4\"\nEND_CYCLE\nEND_MACHINE_CYCLES\n"), "{text}");
    // A shop's own profile over the built-in one: a cycle added, one changed.
    d.file(
        "shop.toml",
        "base = \"mayak600t\"\n\n[[cycle]]\nnumber = 72\nname = \"G72 (ours)\"\ntype = \"Turning\"\n\
         block = \"G72 X{_Xend} Z{_Zend} P{P}\"\nparameters = [{ name = \"P\", kind = \"O\", text = \"P\" }, \
         { name = \"I\", kind = \"S\", text = \"I\" }, { name = \"B\", kind = \"S\", text = \"B\" }, \
         { name = \"VP\", kind = \"S\", text = \"VP\" }, { name = \"C\", kind = \"S\", text = \"C\" }]\n\n\
         [[cycle]]\nnumber = 81\nname = \"drill\"\ntype = \"Drilling\"\nblock = \"G81 Z{_Zend}\"\n",
    );
    let text = stdout(&d.run(&["dialects", "--cycles", "shop.toml"]));
    assert!(
        text.contains("BEGIN_CYCLE 72\nNAME \"G72 (ours)\""),
        "{text}"
    );
    assert!(
        text.contains("BEGIN_CYCLE 81\n") && text.contains("BEGIN_CYCLE 82\n"),
        "{text}"
    );
    d.file("input.tmp", MAYAK_INPUT);
    // A shop's block with no model (`moves` unset) cannot be read back: --no-verify, or the
    // verification refuses the output.
    let o = d.run(&["post", "--dialect-file", "shop.toml", "input.tmp"]);
    assert!(
        stdout(&o).contains("verify it with --moves"),
        "{}",
        stdout(&o)
    );
    let o = d.run(&[
        "post",
        "--dialect-file",
        "shop.toml",
        "--no-verify",
        "input.tmp",
    ]);
    assert_eq!(stdout(&o), "OK\n");
    // The shop's {P} (not {P:as}) gets the point the Маяк-600Т profile puts on every number.
    assert!(
        d.read("output.tmp")
            .contains("\nN008 G72 X156.31 Z-136.98 P5.\n")
    );
    d.file("bad.toml", "base = \"mayak600t\"\n[[cycle]]\nnumber = 1\nname = \"x\"\ntype = \"Milling\"\nblock = \"G1\"\n");
    let o = d.run(&["post", "--dialect-file", "bad.toml", "input.tmp"]);
    assert!(
        stdout(&o).contains("Turning, Drilling or Threading"),
        "{}",
        stdout(&o)
    );
}

#[test]
fn the_launcher_script_carries_the_catalogue_and_runs_fmsvm() {
    let d = Dir::new();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    // Each shipped launcher is `fmsvm dialects --launcher NAME` (post/regenerate.sh), its header
    // the catalogue the library reads.
    for control in [
        "fanuc0itd",
        "mayak600t",
        "nc31",
        "sinumerik802d",
        "fagor8035t",
        "iso",
    ] {
        let shipped = std::fs::read_to_string(root.join(format!("post/fmsvm_post_{control}.py")))
            .expect("the launcher");
        assert_eq!(
            shipped,
            stdout(&d.run(&["dialects", "--launcher", control])),
            "post/fmsvm_post_{control}.py is not current: run post/regenerate.sh"
        );
        let block = stdout(&d.run(&["dialects", "--cycles", control]));
        assert!(shipped.contains(&format!("'''\n{block}'''\n")), "{control}");
        assert!(
            shipped.contains(&format!("CONTROL = \"{control}\"\n")),
            "{control}"
        );
    }
}

/// The launcher as the library runs it, with python: it converts the seed's input and says OK.
/// `cargo test` lists it as ignored where python3 may be missing; `.ci/run` runs it with
/// `--ignored` where python3 is installed.
#[test]
#[ignore = "needs python3; .ci/run runs it with --ignored where python3 is installed"]
fn the_launcher_runs_under_python() {
    let d = Dir::new();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    d.file("input.tmp", MAYAK_INPUT);
    let o = std::process::Command::new("python3")
        .arg(root.join("post/fmsvm_post_mayak600t.py"))
        .arg(d.path("input.tmp"))
        .env("FMSVM", env!("CARGO_BIN_EXE_fmsvm"))
        .output()
        .expect("python3 runs the launcher");
    assert_eq!(String::from_utf8_lossy(&o.stdout), "OK\n");
    assert_eq!(d.read("output.tmp"), mayak_output());
}

/// Without FMSVM and off the PATH, the launcher finds fmsvm beside itself (the library's
/// POSTPROCESSORS folder), and where it finds none it says each place it looked.
#[test]
#[ignore = "needs python3; .ci/run runs it with --ignored where python3 is installed"]
fn the_launcher_finds_fmsvm_beside_it_or_says_where_it_looked() {
    let d = Dir::new();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    d.file("input.tmp", MAYAK_INPUT);
    let launcher = d.path("fmsvm_post_mayak600t.py");
    std::fs::copy(root.join("post/fmsvm_post_mayak600t.py"), &launcher).expect("copied");
    // python3 by its full path: the launcher's PATH has no fmsvm (nor python3).
    // (the interpreter itself, not a shim that looks for it on the PATH).
    let found = std::process::Command::new("python3")
        .args(["-c", "import sys; print(sys.executable)"])
        .output()
        .expect("python3 runs");
    let python3 = String::from_utf8_lossy(&found.stdout).trim().to_string();
    let python = |path: &str| {
        std::process::Command::new(&python3)
            .arg(&launcher)
            .arg(d.path("input.tmp"))
            .env_remove("FMSVM")
            .env("PATH", path)
            .output()
            .expect("python3 runs the launcher")
    };
    let o = python("/nonexistent");
    let said = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        !o.status.success(),
        "{said}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(said.contains("fmsvm not found: FMSVM is not set"), "{said}");
    let folder = std::fs::canonicalize(d.path("")).expect("the folder");
    assert!(
        said.contains(&format!("not in this script's folder {}", folder.display())),
        "{said}"
    );
    assert!(said.contains("not on the PATH (/nonexistent)"), "{said}");
    std::fs::copy(env!("CARGO_BIN_EXE_fmsvm"), d.path("fmsvm")).expect("copied");
    let o = python("/nonexistent");
    assert_eq!(String::from_utf8_lossy(&o.stdout), "OK\n");
    assert_eq!(d.read("output.tmp"), mayak_output());
}

#[test]
fn fanuc_0i_td_gets_its_own_cycles_with_the_profile_between_p_and_q_and_runs_them() {
    // The 0i-TD's catalogue: G71 (two blocks, the profile kept and named by P and Q), G74 (Q in
    // micrometres), G76 (P as m r a, the thread's height and first depth in micrometres). A Fanuc
    // reads X20 as 20 µm: every length the library wrote without a point gets one.
    let input = "\
N001 T0101
N002 S800 M03
N003 G00 X52 Z2
N004 CYCLE 71 U=2 R=0.5 DU=0.4 DW=0.1 F=0.25 _L1=2 _L2=0 _Xbegin=20 _Zbegin=2 _Xend=52 _Zend=-40
N005 G00 X20
N006 G01 Z-20
N007 G01 X40 Z-30
N008 G01 Z-40
N009 G01 X52
N010 G80
N011 G00 X52 Z2
N012 G00 X0 Z5
N013 CYCLE 74 E=1 Q=5 F=0.1 _D=8 _L1=3 _L2=0 _Angle=118 _Zbegin=5 _Zend=-25
N014 G00 X0 Z5
N015 G00 X42 Z5
N016 CYCLE 76 M=1 A=60 DMIN=0.1 D=0.05 DD=0.4 _FEED=2. _NTHREADS=1 _DEPTH=1.2 _L1=5 _L2=2 _Xbegin=37.6 _Zbegin=5 _Xend=37.6 _Zend=-20
N017 G00 X42 Z5
N018 M30
";
    // The first block says the program's start (the ZX plane, mm, G99 feed per revolution).
    let want = "\
N001 G18 G21 G99 T0101
N002 S800 M03
N003 G00 X52. Z2.
N004 G71 U2. R0.5
N005 G71 P6 Q10 U0.4 W0.1 F0.25
N006 G00 X20.
N007 G01 Z-20.
N008 G01 X40. Z-30.
N009 G01 Z-40.
N010 G01 X52.
N011 G00 X52. Z2.
N012 G00 X0. Z5.
N013 G74 R1.
N014 G74 Z-25. Q5000 F0.1
N015 G00 X0. Z5.
N016 G00 X42. Z5.
N017 G76 P010060 Q100 R0.05
N018 G76 X37.6 Z-20. P1200 Q400 F2.
N019 G00 X42. Z5.
N020 M30
";
    let d = Dir::new();
    d.file("input.tmp", input);
    let o = d.run(&["post", "--dialect", "fanuc0itd", "input.tmp"]);
    assert_eq!(stdout(&o), "OK\n");
    assert_eq!(d.read("output.tmp"), want);
    // The proof: the output is a 0i-TD program fmsvm runs and reads back, each cycle back at its
    // start point (the library's return blocks then move nothing), on both engines.
    for engine in ["interp", "jit"] {
        let o = d.run(&[
            "run",
            "output.tmp",
            "--control",
            "fanuc-0i-t",
            "--resolve",
            "--start-point",
            "X100 Z100",
            "--engine",
            engine,
            "-o",
            "out.nc",
            "--verify",
        ]);
        assert!(o.status.success(), "{engine}: {}", cli_support::stderr(&o));
        assert!(cli_support::stderr(&o).contains("verified:"));
        let out = d.read("out.nc");
        // After G71's last pass the tool is at its start point: the return block writes nothing
        // more, and the next block's move is to X0. Z5.
        let lines: Vec<&str> = out.lines().collect();
        let drill = lines
            .iter()
            .position(|l| *l == "X0. Z5.")
            .expect("the drill's start");
        assert_eq!(lines[drill - 1], "G0 X52. Z2.", "{out}");
    }
    // An obligatory parameter missing, and a cycle with no profile where the control needs one.
    d.file(
        "input.tmp",
        "N004 CYCLE 71 U=2 _Xend=52 _Zend=-40\nN005 G00 X20\nN006 G80\n",
    );
    let out = stdout(&d.run(&["post", "--dialect", "fanuc0itd", "input.tmp"]));
    assert!(
        out.contains("the obligatory parameter R (retract) is not given"),
        "{out}"
    );
}

/// The blocks of a path.tmp or output.tmp: (its words by letter) for each block that is not a
/// comment, N dropped.
fn blocks(text: &str) -> Vec<Vec<(char, f64)>> {
    text.lines()
        .filter(|l| !l.starts_with(';') && !l.trim().is_empty())
        .map(|l| {
            l.split_whitespace()
                .filter(|w| !w.starts_with('N'))
                .filter_map(|w| {
                    let mut c = w.chars();
                    let letter = c.next()?;
                    c.as_str()
                        .trim_start_matches('=')
                        .parse()
                        .ok()
                        .map(|v| (letter, v))
                })
                .collect()
        })
        .collect()
}

/// path.tmp's cycles: each `; CYCLE` comment's blocks, followed as absolute X Z moves. Every cycle
/// starts with a point at its start (both axes named) and ends back there (B.6's continuity rule).
fn check_paths(path: &str, starts: &[(f64, f64)]) {
    let cycles: Vec<&str> = path.split("; CYCLE").skip(1).collect();
    assert_eq!(cycles.len(), starts.len(), "{path}");
    for (text, &(x0, z0)) in cycles.iter().zip(starts) {
        let body = text.split_once('\n').map_or("", |(_, b)| b);
        let b = blocks(body);
        let first = &b[0];
        let get = |bl: &[(char, f64)], l: char| bl.iter().find(|(c, _)| *c == l).map(|(_, v)| *v);
        assert_eq!(
            (get(first, 'X'), get(first, 'Z')),
            (Some(x0), Some(z0)),
            "the path starts at the cycle's start: {text}"
        );
        let (mut x, mut z) = (x0, z0);
        for bl in &b {
            for (c, v) in bl {
                assert!("GXZIKFM".contains(*c), "a neutral word: {c}{v} in {text}");
                assert!(
                    *c != 'G' || [0.0, 1.0, 2.0, 3.0].contains(v),
                    "G{v} in {text}"
                );
            }
            x = get(bl, 'X').unwrap_or(x);
            z = get(bl, 'Z').unwrap_or(z);
        }
        assert!(
            (x - x0).abs() < 1e-9 && (z - z0).abs() < 1e-9,
            "the path ends at X{x} Z{z}, not at its start X{x0} Z{z0}: {text}"
        );
    }
}

#[test]
fn the_seeds_mayak_cycle_in_elementary_moves_passes_by_its_parameters() {
    // CYCLE 72 I=5 B=0.5 VP=1 from X156.31 Z4.31 to the figure at _Xbegin=118, by hand: the depth I
    // (radius) takes 10 off the diameter a pass (X146.31, 136.31, 126.31), each to the figure's
    // end Z-136.98, out at 45° by the 0.5 mm retract (X+1 on the diameter, Z+0.5); then the pass
    // along the profile moved by the allowance B (on the diameter: X118.5), and VP=1 finishing
    // pass on the profile itself (X118, then up the face to X156.31); back to the start.
    let d = Dir::new();
    d.file("input.tmp", MAYAK_INPUT);
    let o = d.run(&[
        "post",
        "--dialect",
        "mayak600t",
        "--moves",
        "--verify",
        "input.tmp",
    ]);
    assert_eq!(stdout(&o), "OK\n");
    let want = "\
N006 G90 G95 S500 F1.2
N007 G00 X156.31 Z4.31
N008 G00 X146.31
N009 G01 Z-136.98
N010 G00 X147.31 Z-136.48
N011 Z4.31
N012 X136.31
N013 G01 Z-136.98
N014 G00 X137.31 Z-136.48
N015 Z4.31
N016 X126.31
N017 G01 Z-136.98
N018 G00 X127.31 Z-136.48
N019 Z4.31
N020 X118.5
N021 G01 Z-136.98
N022 X156.81
N023 G00 X156.31 Z4.31
N024 X118.
N025 G01 Z-136.98
N026 X156.31
N027 G00 Z4.31
N028 G00 X156.31 Z4.31
";
    assert_eq!(d.read("output.tmp"), want);
    check_paths(&d.read("path.tmp"), &[(156.31, 4.31)]);
    // In its own cycle (the default), the path inside it is still written for the library.
    let o = d.run(&["post", "--dialect", "mayak600t", "input.tmp"]);
    assert_eq!(stdout(&o), "OK\n");
    assert_eq!(d.read("output.tmp"), mayak_output());
    check_paths(&d.read("path.tmp"), &[(156.31, 4.31)]);
    // The Маяк-600Т's own G72 is not modelled: it is written because the record is a trapezoid
    // its words state exactly (a cylinder, K0), and the verification reads it as its elementary
    // moves (the default, which the run above passed); `--verify` says the same.
    let o = d.run(&["post", "--dialect", "mayak600t", "--verify", "input.tmp"]);
    assert_eq!(stdout(&o), "OK\n");
    assert_eq!(d.read("output.tmp"), mayak_output());
}

/// The НЦ-31 records of seed 004 (B.5), the OCR's `P1=2?5` read as 2.5.
const NC31_INPUT: &str = "\
N006 S800 M03
N007 G00 X68 Z2.5
N008 CYCLE 77 P1=2.5 W=1 _L1=1.5 _L2=1.5 _Xbegin=53.24 _Zbegin=2.5 _Xend=68 _Zend=-23.5
N009 G01 Z-23.5
N010 G01 X68
N011 G80
N012 G00 X68 Z2.5
N049 G00 X0 Z-22.40
N050 CYCLE 73 P=10 _D=8 _L1=0 _L2=1 _Angle=118 _Zbegin=-22.40 _Zend=-47.29
N051 G00 X0 Z-22.40
N144 G00 X36 Z-0.5
N145 CYCLE 31 P2=0.5 _FEED=2. _NTHREADS=1 _DEPTH=1.62 _L1=6 _L2=5.5 _Xbegin=32.75 _Zbegin=-0.5 _Xend=32.75 _Zend=-35.5
N146 G00 X36 Z-0.5
N164 G00 X0 Z-3.5
N165 CYCLE 33 S=1 _FEED=1.5 _NTHREADS=1 _L1=3 _L2=3 _Zbegin=-3.5 _Zend=-27
N166 M03
";

#[test]
fn the_nc31_records_convert_and_its_threads_wait_for_a_known_thread_block() {
    let d = Dir::new();
    // Turning and drilling: by hand, P1=2.5 (radius) takes 5 off the diameter a pass from X68 to
    // the figure at X53.24; P=10 pecks from Z-22.4 to Z-47.29, 0.5 back after each.
    let turning_and_drilling: String = NC31_INPUT
        .lines()
        .take(10)
        .map(|l| format!("{l}\n"))
        .collect();
    d.file("input.tmp", &turning_and_drilling);
    let o = d.run(&["post", "--dialect", "nc31", "--verify", "input.tmp"]);
    assert_eq!(stdout(&o), "OK\n");
    let out = d.read("output.tmp");
    let lines: Vec<&str> = out.lines().collect();
    for want in [
        "N007 G00 X68. Z2.5",
        "N008 G0 X63.",
        "N009 G1 Z-23.5",
        "N010 G0 X64. Z-23.",
        "N012 X58.",
        "N016 X53.24",
        "N018 X68.",
        "N022 G1 Z-32.4",
        "N023 G0 Z-31.9",
        "N024 G1 Z-42.4",
        "N026 G1 Z-47.29",
        "N027 G0 Z-22.4",
    ] {
        assert!(lines.contains(&want), "{want} in\n{out}");
    }
    check_paths(&d.read("path.tmp"), &[(68.0, 2.5), (0.0, -22.4)]);
    // The threads: the НЦ-31's thread block is not known, so both are refused, located, with
    // what to do; its catalogue does not offer them to the library.
    d.file("input.tmp", NC31_INPUT);
    let o = d.run(&["post", "--dialect", "nc31", "input.tmp"]);
    let text = stdout(&o);
    for line in [12, 15] {
        assert!(
            text.contains(&format!(
                "input.tmp:{line}:1: CYCLE 3{}: the control cannot take it: no single-block thread is known for nc31",
                if line == 12 { 1 } else { 3 }
            )),
            "{text}"
        );
    }
    assert_eq!(o.status.code(), Some(2));
    assert!(!d.path("output.tmp").exists());
    let o = d.run(&["dialects", "--cycles", "nc31"]);
    let catalogue = stdout(&o);
    assert!(
        catalogue.contains("BEGIN_CYCLE 73") && catalogue.contains("BEGIN_CYCLE 77"),
        "{catalogue}"
    );
    assert!(
        !catalogue.contains("BEGIN_CYCLE 31") && !catalogue.contains("BEGIN_CYCLE 33"),
        "{catalogue}"
    );
    // A shop whose НЦ-31 threads with G33 K and taps with a floating holder says so.
    d.file(
        "shop.toml",
        "base = \"nc31\"\nname = \"shop\"\nmachine = \"lathe\"\n[lathe]\nthread = \"K\"\nfloating_tap = true\n",
    );
    // The library's record starts 0.005 mm (radius) off its crest (Ø36 against 32.75 + 2·1.62):
    // refused (every pass returns at the start's X).
    let o = d.run(&["post", "--dialect-file", "shop.toml", "input.tmp"]);
    let text = stdout(&o);
    assert!(
        text.contains("input.tmp:12:1: CYCLE 31: G76: the start point X18 (radius) is not 0.5 mm outside the thread"),
        "{text}"
    );
    // All four convert once the thread starts 0.5 mm (radius) clear of its crest (X37).
    d.file("input.tmp", &NC31_INPUT.replace("X36 Z-0.5", "X37 Z-0.5"));
    let o = d.run(&[
        "post",
        "--dialect-file",
        "shop.toml",
        "--verify",
        "input.tmp",
    ]);
    assert_eq!(stdout(&o), "OK\n");
    let out = d.read("output.tmp");
    // The thread: from X36 with P2=0.5 the first depth, the root at X32.75 (_DEPTH=1.62 below the
    // crest X35.99); the tap: in at the lead, the spindle reversed, out, turned back.
    assert!(out.contains("G33 Z-35.5 K2.\n"), "{out}");
    assert!(
        out.contains("G33 Z-27. K1.5\nN")
            && out.contains(" M4\n")
            && out.contains("G33 Z-3.5 K1.5\n"),
        "{out}"
    );
    check_paths(
        &d.read("path.tmp"),
        &[(68.0, 2.5), (0.0, -22.4), (37.0, -0.5), (0.0, -3.5)],
    );
}

#[test]
fn one_cycle_of_each_type_converts_for_every_control_and_verifies() {
    // For each control, a program with one turning, one drilling and one threading cycle in its
    // own catalogue's numbers; --verify reads output.tmp back with the control's reader (the
    // 0i-TD's own cycles expanded by fmsvm's lathe kernel) and compares it with the neutral
    // program's motion.
    let turning = |n: u32, params: &str| {
        format!(
            "N003 G00 X52 Z2\nN004 CYCLE {n} {params} _L1=2 _L2=0 _Xbegin=20 _Zbegin=2 _Xend=52 _Zend=-40\n\
             N005 G01 Z-20\nN006 G03 X30 Z-25 R5\nN007 G01 X40\nN008 Z-40\nN009 X52\nN010 G80\nN011 G00 X52 Z2\n"
        )
    };
    let drilling = |n: u32, params: &str| {
        format!(
            "N012 G00 X0 Z5\nN013 CYCLE {n} {params} _D=8 _L1=3 _L2=0 _Angle=118 _Zbegin=2 _Zend=-25\nN014 G00 X0 Z5\n"
        )
    };
    let threading = |n: u32, params: &str| {
        format!(
            "N015 G00 X42 Z5\nN016 CYCLE {n} {params} _FEED=2. _NTHREADS=1 _DEPTH=1.2 _ALFA=60 _L1=5 _L2=2 _Xbegin=37.6 _Zbegin=5 _Xend=37.6 _Zend=-20\nN017 G00 X42 Z5\n"
        )
    };
    let head = "N001 T0101\nN002 S800 M03\n";
    let tail = "N030 M30\n";
    let cases: [(&str, String, usize); 6] = [
        (
            "fanuc0itd",
            format!(
                "{head}{}{}{}{tail}",
                turning(71, "U=2 R=0.5 DU=0.4 DW=0.1 F=0.25"),
                drilling(74, "E=1 Q=5 F=0.1"),
                threading(76, "M=1 A=60 DMIN=0.1 D=0.05 DD=0.4")
            ),
            3,
        ),
        (
            "iso",
            format!(
                "{head}{}{}{}{tail}",
                turning(71, "I=2 U=0.4 W=0.1 VP=1 C=93 F=0.25"),
                drilling(83, "P=5 F=0.1"),
                threading(76, "P=0.4 VP=2")
            ),
            3,
        ),
        (
            "sinumerik802d",
            format!(
                "{head}{}{}{}{tail}",
                turning(72, "I=2 F=0.25").replace("CYCLE 72", "CYCLE 71"),
                drilling(83, "P=5"),
                threading(76, "P=0.3")
            ),
            3,
        ),
        // No thread block is known for these three: their threading records are refused (the
        // test above); turning and drilling convert.
        (
            "fagor8035t",
            format!(
                "{head}{}{}{tail}",
                turning(71, "J=4 U=0.4 F=0.25"),
                drilling(83, "P=5 F=0.1")
            ),
            2,
        ),
        (
            "mayak600t",
            format!(
                "{head}{}{}{tail}",
                turning(72, "I=2 B=0.4 VP=1 C=95 P=5"),
                drilling(73, "P=5 F=0.1")
            ),
            2,
        ),
        (
            "nc31",
            format!(
                "{head}{}{}{tail}",
                turning(77, "P1=2 W=1"),
                drilling(73, "P=5")
            ),
            2,
        ),
    ];
    let d = Dir::new();
    for (control, input, cycles) in &cases {
        d.file("input.tmp", input);
        for moves in [false, true] {
            let mut args = vec!["post", "--dialect", control, "--verify", "input.tmp"];
            if moves {
                args.push("--moves");
            }
            // The Маяк-600Т's own G72 is not modelled: --verify needs --moves there.
            if *control == "mayak600t" && !moves {
                continue;
            }
            let o = d.run(&args);
            assert_eq!(stdout(&o), "OK\n", "{control} (moves: {moves})");
            let starts = [(52.0, 2.0), (0.0, 5.0), (42.0, 5.0)];
            check_paths(&d.read("path.tmp"), &starts[..*cycles]);
        }
    }
}

#[test]
fn verify_catches_a_cycle_block_that_says_something_else_and_moves_respect_the_tool() {
    let d = Dir::new();
    let input = "N002 G01 F0.25\nN003 G00 X52 Z2\nN004 CYCLE 71 U=2 R=0.5 _Xbegin=20 _Zbegin=2 _Xend=52 _Zend=-40\nN005 G01 Z-20\nN006 X52\nN007 G80\nN008 G00 X52 Z2\n";
    d.file("input.tmp", input);
    // A profile whose G71 writes the retract where the depth goes: the 0i-TD would cut 0.5 mm
    // passes; --verify sees the first pass at X51. where the record's depth U=2 puts it at X48.
    d.file(
        "shop.toml",
        "base = \"fanuc0itd\"\nname = \"shop\"\n[[cycle]]\nnumber = 71\nname = \"G71\"\ntype = \"Turning\"\n\
         block = \"G71 U{R} R{U}\\nG71 P{ns} Q{nf}\"\nkeep_profile = true\nmoves = \"turning\"\n\
         parameters = [{ name = \"U\", kind = \"O\", role = \"depth\", text = \"depth\" }, \
         { name = \"R\", kind = \"O\", role = \"retract\", text = \"retract\" }]\n",
    );
    let o = d.run(&[
        "post",
        "--dialect-file",
        "shop.toml",
        "--verify",
        "input.tmp",
    ]);
    let text = stdout(&o);
    assert!(
        text.contains("--verify: move 2: the neutral program makes a rapid to X48.000 Z2.000"),
        "{text}"
    );
    assert_eq!(o.status.code(), Some(7));
    assert!(!d.path("output.tmp").exists());
    // The record's tool cannot cut the profile's square shoulder with a 60° plan angle.
    d.file(
        "input.tmp",
        &input.replace("CYCLE 71 U=2 R=0.5", "CYCLE 71 I=2 C=60"),
    );
    let o = d.run(&["post", "--dialect", "iso", "input.tmp"]);
    assert!(
        stdout(&o).contains("input.tmp:3:1: CYCLE 71: the profile's move 2 rises 90.0° from the feed's direction, steeper than the tool's plan angle C = 60°"),
        "{}",
        stdout(&o)
    );
    // A role fmsvm does not know is refused when the profile is read.
    d.file(
        "bad.toml",
        "base = \"iso\"\n[[cycle]]\nnumber = 9\nname = \"x\"\ntype = \"Drilling\"\nmoves = \"drilling\"\n\
         parameters = [{ name = \"P\", kind = \"S\", role = \"pek\", text = \"p\" }]\n",
    );
    let o = d.run(&["post", "--dialect-file", "bad.toml", "input.tmp"]);
    assert!(
        stdout(&o).contains("role = \"pek\": one of depth"),
        "{}",
        stdout(&o)
    );
}

#[test]
fn an_input_that_would_make_too_many_blocks_is_refused_in_time() {
    let d = Dir::new();
    let mut input = String::new();
    for k in 0..3 {
        input.push_str(&format!(
            "N{} G00 X200 Z2\nN{} CYCLE 71 I=0.005 _Xbegin=20 _Zbegin=2 _Xend=200 _Zend=-400\nN{} G01 Z-400\nN{} G80\n",
            k * 4 + 1,
            k * 4 + 2,
            k * 4 + 3,
            k * 4 + 4
        ));
    }
    d.file("input.tmp", &input);
    let o = d.run(&["post", "--dialect", "iso", "input.tmp"]);
    assert!(
        stdout(&o)
            .contains("input.tmp:6:1: output.tmp and path.tmp would hold more than 250000 blocks"),
        "{}",
        stdout(&o)
    );
    assert!(!d.path("output.tmp").exists());
}

#[test]
fn constant_surface_speed_goes_where_the_control_has_it() {
    let d = Dir::new();
    d.file(
        "input.tmp",
        "N001 G96 S180 M03\nN002 G00 X40 Z2\nN003 G97 S800\nN004 M30\n",
    );
    // The 0i-TD's and the 802D's G96 S is m/min, G97 S rpm: the same words, the clamp (the
    // machine's, --max-rpm) first in the control's words.
    for (control, clamp) in [("fanuc0itd", "G50 S2500"), ("sinumerik802d", "LIMS=2500")] {
        let o = d.run(&[
            "post",
            "--dialect",
            control,
            "--max-rpm",
            "2500",
            "input.tmp",
        ]);
        assert_eq!(stdout(&o), "OK\n", "{control}");
        let out = d.read("output.tmp");
        assert!(
            out.contains(&format!(" {clamp}\nN002 G96 S180 M03\n")),
            "{control}: {out}"
        );
        assert!(out.contains("N004 G97 S800\n"), "{control}: {out}");
    }
    // The Маяк-600Т has no G96 known: refused at its word; G97 (rpm, its only way) is left out.
    let o = d.run(&["post", "--dialect", "mayak600t", "input.tmp"]);
    assert!(
        stdout(&o).starts_with(
            "input.tmp:1:6: G96 (constant surface speed): this control has none known"
        ),
        "{}",
        stdout(&o)
    );
    d.file(
        "input.tmp",
        "N001 G97 S800 M03\nN002 G00 X40 Z2\nN003 G97\nN004 M30\n",
    );
    let o = d.run(&["post", "--dialect", "mayak600t", "input.tmp"]);
    assert_eq!(stdout(&o), "OK\n");
    assert_eq!(
        d.read("output.tmp"),
        "N001 G90 G95 S800 M03\nN002 G00 X40. Z2.\nN003 M30\n"
    );
}

#[test]
fn records_a_machine_would_suffer_from_are_refused_at_their_line() {
    // Each input is refused (exit 2, no output.tmp) with the words of the message. The cylinder:
    // Ø40 turned from Ø50, its figure _Xbegin=40.
    let cyl = |dialect_params: &str, profile: &str| {
        format!(
            "N001 G00 X50 Z2\nN002 CYCLE 71 {dialect_params} _Xbegin=40 _Zbegin=2 _Xend=50 _Zend=-30\n{profile}N009 G80\n"
        )
    };
    let cases: Vec<(&str, String, &str)> = vec![
        // A dwell's X is its time, not a position: the drill is still at X10.
        (
            "iso",
            "N001 G00 X10 Z10\nN002 G04 X0\nN003 CYCLE 83 P=5 _D=10 _Zbegin=2 _Zend=-12\n".into(),
            "input.tmp:3:1: CYCLE 83: a hole on the spindle's axis is drilled or tapped from X0, and the cycle starts at X10",
        ),
        (
            "iso",
            "N001 G04 P1000\n".into(),
            "input.tmp:1:10: G04 P: the unit of a dwell's P is not documented",
        ),
        // A thread whose start is inside its crest (root Ø20 + 2 × 0.92 = Ø21.84 > Ø21).
        (
            "iso",
            "N001 G00 X21 Z5\nN002 CYCLE 76 _FEED=1.5 _DEPTH=0.92 _Xbegin=20 _Zbegin=5 _Xend=20 _Zend=-20\n".into(),
            "input.tmp:2:1: CYCLE 76: G76: the start point X10.5 (radius) is not 0.5 mm outside the thread",
        ),
        // A negative finishing allowance would cut into the part.
        (
            "iso",
            cyl("I=2 U=-3", "N003 G01 Z-30\nN004 X50\n"),
            "input.tmp:2:1: CYCLE 71: U = -3: not negative",
        ),
        (
            "iso",
            cyl("I=2 F=0", "N003 G01 Z-30\nN004 X50\n"),
            "input.tmp:2:1: CYCLE 71: F = 0: above 0",
        ),
        // The control's own G71 is checked by the model first: a profile with a pocket (type II,
        // written so) that rises above the start point, a thread of two starts, a peck too small
        // for the micrometre word.
        (
            "fanuc0itd",
            cyl("U=2 R=0.5", "N003 G01 X45 Z-15\nN004 X55 Z-20\nN005 X50 Z-30\n"),
            "input.tmp:2:1: CYCLE 71: G71 (type II): the start point X25 (radius) lies inside the profile",
        ),
        (
            "fanuc0itd",
            "N001 G00 X42 Z5\nN002 CYCLE 76 M=1 A=60 DMIN=0.1 D=0.05 DD=0.4 _FEED=1.5 _NTHREADS=2 _DEPTH=0.92 _Xbegin=38 _Zbegin=5 _Xend=38 _Zend=-20\n".into(),
            "input.tmp:2:1: CYCLE 76: _NTHREADS=2: a thread of several starts",
        ),
        (
            "fanuc0itd",
            "N001 G00 X0 Z5\nN002 CYCLE 74 E=1 Q=0.0001 _D=8 _Zbegin=5 _Zend=-25\n".into(),
            "input.tmp:2:1: CYCLE 74: Q = 0.0001: at least 0.001 mm here",
        ),
        // An arc without its centre is no straight line.
        (
            "iso",
            cyl("I=2", "N003 G01 Z-15\nN004 G02 X50 Z-20\n"),
            "input.tmp:2:1: line 4: an arc (G02) in the profile without I K or R",
        ),
        // One word of each letter; a profile is moves only.
        (
            "iso",
            "N001 G00 X50 X60 Z2\n".into(),
            "input.tmp:1:14: X60: the block already has X50",
        ),
        (
            "iso",
            cyl("I=2", "N003 G01 Z-30 M05\nN004 X50\n"),
            "input.tmp:3:15: M05: a cycle's profile is moves",
        ),
        (
            "iso",
            "N001 G00 X0 Z5\nN002 CYCLE 83 P=5 _FOO=3 _D=8 _Zend=-10\n".into(),
            "input.tmp:2:19: _FOO: not one of the library's environment variables",
        ),
    ];
    let d = Dir::new();
    for (dialect, input, want) in &cases {
        d.file("input.tmp", input);
        let o = d.run(&["post", "--dialect", dialect, "input.tmp"]);
        let out = stdout(&o);
        assert!(
            out.contains(want),
            "{dialect}: {input}\nwant {want}\ngot {out}"
        );
        assert_eq!(o.status.code(), Some(2), "{out}");
        assert!(!d.path("output.tmp").exists(), "{input}");
    }
    // A dwell is written as the control writes one: G04 F on the 802D, G04 X on ISO (the code in
    // two digits, as the library writes it).
    d.file("input.tmp", "N001 G00 X10 Z10\nN002 G04 X2\nN003 M30\n");
    for (dialect, want) in [("sinumerik802d", "N002 G04 F2."), ("iso", "N002 G04 X2.")] {
        let o = d.run(&["post", "--dialect", dialect, "--verify", "input.tmp"]);
        assert_eq!(stdout(&o), "OK\n", "{dialect}");
        assert!(
            d.read("output.tmp").contains(want),
            "{dialect}: {}",
            d.read("output.tmp")
        );
    }
    // A block that names an undeclared parameter is refused when the profile is read.
    d.file(
        "shop.toml",
        "base = \"iso\"\n[[cycle]]\nnumber = 9\nname = \"x\"\ntype = \"Drilling\"\nblock = \"G83 Q{QQ}\"\n",
    );
    let o = d.run(&["post", "--dialect-file", "shop.toml", "input.tmp"]);
    assert!(
        stdout(&o).contains("{QQ} is none of the cycle's parameters"),
        "{}",
        stdout(&o)
    );
}

#[test]
fn a_bore_gets_the_0i_tds_allowance_on_the_inside() {
    // Boring Ø30 out to Ø40 from a Ø25 hole: the 0i-TD's G71 takes the allowance U negative for a
    // bore (the stock is inside the profile); the library gives its size. --verify runs the output
    // through fmsvm's lathe kernel and compares it with the model's passes.
    let input = "N001 G00 X25 Z2\nN002 CYCLE 71 U=1.5 R=0.5 DU=0.4 DW=0.1 F=0.2 _Xbegin=40 _Zbegin=2 _Xend=30 _Zend=-20\n\
                 N003 G01 Z-10\nN004 X30\nN005 Z-20\nN006 X25\nN007 G80\nN008 G00 X25 Z2\nN009 M30\n";
    let d = Dir::new();
    d.file("input.tmp", input);
    let o = d.run(&["post", "--dialect", "fanuc0itd", "--verify", "input.tmp"]);
    assert_eq!(stdout(&o), "OK\n");
    let out = d.read("output.tmp");
    assert!(out.contains("G71 P4 Q8 U-0.4 W0.1 F0.2\n"), "{out}");
    // The model's first pass: 1.5 (radius) out from Ø25: Ø28.
    assert!(
        d.read("path.tmp").contains("X28\n"),
        "{}",
        d.read("path.tmp")
    );
}

/// A pocketed profile for the 0i-TD: its G71 type II ("the first block of the finishing shape
/// specifies both X(U) and Z(W)", 0i-TD lathe manual, G71), the catalogue's `PROFIL_DEMANDS ""`
/// passing the library's whole contour.
#[test]
fn a_profile_with_a_pocket_goes_to_the_0i_td_as_its_type_ii() {
    let input = "\
N001 G97 S800 M03
N002 F0.2
N003 G00 X62 Z2
N004 CYCLE 71 U=1.5 R=0.5 DU=0.4 DW=0.1 F=0.25 _Xbegin=20 _Zbegin=2 _Xend=62 _Zend=-60
N005 G01 X20 Z0
N006 Z-15
N007 X40 Z-25
N008 X30 Z-40
N009 X50 Z-45
N010 Z-60
N011 X62
N012 G80
N013 G00 X62 Z2
N014 M30
";
    let d = Dir::new();
    d.file("input.tmp", input);
    let o = d.run(&["post", "--dialect", "fanuc0itd", "input.tmp"]);
    assert_eq!(stdout(&o), "OK\n");
    let out = d.read("output.tmp");
    for line in [
        "N005 G71 P6 Q13 U0.4 W0.1 F0.25",
        // The infeed to the figure's begin names both axes: type II.
        "N006 G00 X20. Z2.",
        "N010 X30. Z-40.",
        // The library's F0.2 again after the cycle's F0.25 (its next block without an F means
        // the feed it set; the control would keep the cycle's).
        "N014 G00 X62. Z2. F0.2",
    ] {
        assert!(out.lines().any(|l| l == line), "{line} in\n{out}");
    }
    // Type II ends its roughing with a pass along the profile moved by the allowance (U0.4 on the
    // diameter, W0.1): through the pocket's bottom X30 Z-40 at X30.4 Z-39.9.
    let path = d.read("path.tmp");
    assert!(path.lines().any(|l| l.ends_with(" X30.4 Z-39.9")), "{path}");
}

/// The catalogue's TYPE says what a record is, not the variables it happens to carry: a drilling
/// record with only `_Depth` has no profile and no G80.
#[test]
fn the_catalogues_type_decides_whether_a_record_has_a_profile() {
    let d = Dir::new();
    d.file(
        "input.tmp",
        "N001 G00 X0 Z5\nN002 CYCLE 83 P=5 F=0.1 _Depth=20 _Zbegin=5 _Zend=-15\nN003 G00 X0 Z5\n",
    );
    let o = d.run(&["post", "--dialect", "iso", "input.tmp"]);
    assert_eq!(stdout(&o), "OK\n");
    // Pecks of 5 from Z5 to Z-15, 0.5 back after each (the catalogue's E).
    let out = d.read("output.tmp");
    for z in ["G01 Z0. F0.1", "G01 Z-5.", "G01 Z-10.", "G01 Z-15."] {
        assert!(out.lines().any(|l| l.ends_with(z)), "{z} in\n{out}");
    }
}

/// `_DIRECT` (the thread's hand): the library's manual names it but not how its value says which
/// hand; refused at the parameter rather than ignored.
#[test]
fn a_threads_hand_is_refused_at_its_parameter() {
    let d = Dir::new();
    d.file(
        "input.tmp",
        "N001 G97 S500 M03\nN002 G00 X42 Z5\nN003 CYCLE 76 _FEED=2. _DEPTH=1.2 _DIRECT=1 _Xbegin=37.6 _Zbegin=5 _Xend=37.6 _Zend=-20\n",
    );
    let o = d.run(&["post", "--dialect", "iso", "input.tmp"]);
    assert!(
        stdout(&o).contains("input.tmp:3:35: CYCLE 76: _DIRECT (the thread's hand)"),
        "{}",
        stdout(&o)
    );
    assert_eq!(o.status.code(), Some(2));
}

/// "A missing default means 0" (the library's manual, §4.3): the catalogue writes no default of
/// 0, and offers no cycle the control cannot take (an ISO control taps only with a floating
/// holder, which its profile does not declare).
#[test]
fn the_catalogue_writes_no_zero_default_and_only_what_the_control_takes() {
    let d = Dir::new();
    let o = d.run(&["dialects", "--cycles", "iso"]);
    let text = stdout(&o);
    assert!(
        text.contains("A S \"угол врезания по боковой стороне (0: радиальное)\"\n"),
        "{text}"
    );
    assert!(!text.contains("BEGIN_CYCLE 84"), "{text}");
    let o = d.run(&["dialects", "--cycles", "fagor8035t"]);
    let text = stdout(&o);
    assert!(
        !text.contains("BEGIN_CYCLE 76") && text.contains("BEGIN_CYCLE 71"),
        "{text}"
    );
}

/// `post` never takes its own outputs for its input: `post path.tmp`, `post output.tmp` and an
/// input that is a link to output.tmp are refused and leave the file as it was. An output.tmp
/// that is a link to a file elsewhere is replaced by a new file in the folder; the file it pointed
/// to is not written.
#[cfg(unix)]
#[test]
fn post_never_replaces_its_input_nor_writes_through_a_link() {
    let d = Dir::new();
    for name in ["path.tmp", "output.tmp"] {
        d.file(name, "N001 G00 X?\n");
        let o = d.run(&["post", "--dialect", "mayak600t", name]);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stdout(&o));
        assert!(stdout(&o).contains("post writes"), "{}", stdout(&o));
        assert_eq!(d.read(name), "N001 G00 X?\n", "{name} was changed");
        std::fs::remove_file(d.path(name)).expect("removed");
    }
    d.file("output.tmp", "the last program's\n");
    std::os::unix::fs::symlink("output.tmp", d.path("input.tmp")).expect("a link");
    let o = d.run(&["post", "--dialect", "mayak600t", "input.tmp"]);
    assert_eq!(o.status.code(), Some(2), "{}", stdout(&o));
    assert_eq!(d.read("output.tmp"), "the last program's\n");
    std::fs::remove_file(d.path("input.tmp")).expect("removed");
    // output.tmp a link to a file outside the folder: the outside file stays as it was.
    let elsewhere = Dir::new();
    elsewhere.file("precious.nc", "keep me\n");
    std::fs::remove_file(d.path("output.tmp")).expect("removed");
    std::os::unix::fs::symlink(elsewhere.path("precious.nc"), d.path("output.tmp"))
        .expect("a link");
    d.file("input.tmp", MAYAK_INPUT);
    let o = d.run(&["post", "--dialect", "mayak600t", "input.tmp"]);
    assert_eq!(stdout(&o), "OK\n");
    assert_eq!(elsewhere.read("precious.nc"), "keep me\n");
    let meta = std::fs::symlink_metadata(d.path("output.tmp")).expect("output.tmp");
    assert!(
        meta.file_type().is_file(),
        "output.tmp is a file of its own"
    );
    assert_eq!(d.read("output.tmp"), mayak_output());
}

/// The last program's output.tmp and path.tmp are gone as soon as `post` starts, so that a run
/// stopped by a signal (here while it waits to read its input from a FIFO) leaves nothing that
/// could pass for this program's.
#[cfg(unix)]
#[test]
fn a_stopped_post_leaves_no_stale_output() {
    let d = Dir::new();
    d.file("output.tmp", "the last program's\n");
    d.file("path.tmp", "the last program's path\n");
    let fifo = d.fifo("input.tmp");
    let mut child = cli_support::bin()
        .args(["post", "--dialect", "mayak600t"])
        .arg(&fifo)
        .current_dir(d.0.path())
        .stdout(std::process::Stdio::null())
        .spawn()
        .expect("post starts");
    let started = std::time::Instant::now();
    while d.path("output.tmp").exists() || d.path("path.tmp").exists() {
        assert!(
            started.elapsed() < std::time::Duration::from_secs(20),
            "the stale outputs are still there"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    // SAFETY: kill has no preconditions; the pid is the child's.
    unsafe { libc::kill(child.id() as i32, libc::SIGTERM) };
    let status = child.wait().expect("post ends");
    assert!(!status.success(), "{status}");
    assert!(!d.path("output.tmp").exists() && !d.path("path.tmp").exists());
}

/// No text of a catalogue can change what the launcher runs: a name with backslashes (a Windows
/// path) is held as text by the launcher's raw string; a `'''`, a
/// double quote or a line break, which the library's catalogue or the launcher cannot carry, and a
/// parameter named twice are refused where the profile is read.
#[test]
fn catalogue_text_cannot_change_the_launcher() {
    let d = Dir::new();
    let cycle = |name: &str, text: &str, extra: &str| {
        format!(
            "base = \"mayak600t\"\n\n[[cycle]]\nnumber = 81\nname = {name}\ntype = \"Drilling\"\nblock = \"G81 Z{{_Zend}}\"\nparameters = [{{ name = \"P\", kind = \"O\", text = {text} }}{extra}]\n"
        )
    };
    d.file("ok.toml", &cycle("'C:\\Users\\shop\\drill'", "\"P\"", ""));
    let o = d.run(&["dialects", "--launcher", "ok.toml"]);
    assert_eq!(o.status.code(), Some(0), "{}", stdout(&o));
    let script = stdout(&o);
    assert!(
        script.contains("NAME \"C:\\Users\\shop\\drill\""),
        "{script}"
    );
    // The catalogue sits in a raw string (no escapes), whose quotes are the only `'''` of the
    // script: no text of it ends the string.
    assert!(script.contains("r'''\nBEGIN_MACHINE_CYCLES"), "{script}");
    assert_eq!(script.matches("'''").count(), 2, "{script}");
    for (name, text, extra, says) in [
        ("\"x'''y\"", "\"P\"", "", "'''"),
        ("\"x\"", "'a \"quoted\" text'", "", "quote"),
        ("\"x\"", "\"two\\nlines\"", "", "line break"),
        (
            "\"x\"",
            "\"P\"",
            ", { name = \"P\", kind = \"S\", text = \"again\" }",
            "named twice",
        ),
    ] {
        d.file("bad.toml", &cycle(name, text, extra));
        let o = d.run(&["dialects", "--launcher", "bad.toml"]);
        assert_eq!(o.status.code(), Some(2), "{name} {text}: {}", stdout(&o));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(says), "{says} in {err}");
    }
}

/// A thread's finishing passes (the 0i-TD's m, two digits, 01–99) are said with one range
/// whatever is wrong with them.
#[test]
fn a_threads_finishing_passes_have_one_range() {
    let d = Dir::new();
    for m in ["1.5", "100", "0"] {
        d.file(
            "input.tmp",
            &format!("N001 T0101\nN002 S800 M03\nN003 G00 X40 Z5\nN004 CYCLE 76 M={m} A=60 DMIN=0.1 D=0.05 DD=0.4 _FEED=2. _NTHREADS=1 _DEPTH=1.2 _L1=5 _L2=2 _Xbegin=37.6 _Zbegin=5 _Xend=37.6 _Zend=-20\nN005 M30\n"),
        );
        let o = d.run(&["post", "--dialect", "fanuc0itd", "input.tmp"]);
        assert!(
            stdout(&o).contains(&format!(
                "input.tmp:4:1: CYCLE 76: M = {m}: a whole number from 1 to 99"
            )),
            "{}",
            stdout(&o)
        );
    }
}
