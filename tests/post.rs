//! `fmsvm post`, the turning library's postprocessor contract (docs/postprocessor.md): the neutral
//! language in, the control's words out in `output.tmp`, `OK` or located errors on standard output.
//! The oracle: the seed's own Маяк-600Т listing (its input records and the postprocessor's output).

mod cli_support;

use cli_support::{Dir, stdout};

/// The seed's Маяк-600Т input, as the library writes `input.tmp` (the annotations are the seed's).
const MAYAK_INPUT: &str = include_str!("post/mayak-input.txt");

/// The seed's Маяк-600Т output for it, word for word.
const MAYAK_OUTPUT: &str = include_str!("post/mayak-output.txt");

#[test]
fn the_seeds_mayak_listing_comes_out_word_for_word() {
    let d = Dir::new();
    d.file("input.tmp", MAYAK_INPUT);
    let o = d.run(&["post", "--dialect", "mayak600t", "input.tmp"]);
    assert_eq!(stdout(&o), "OK\n");
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(d.read("output.tmp"), MAYAK_OUTPUT);
    // On Windows its lines end in CR LF, and so do the output's.
    d.file("input.tmp", &MAYAK_INPUT.replace('\n', "\r\n"));
    let o = d.run(&["post", "--dialect", "mayak600t", "input.tmp"]);
    assert_eq!(stdout(&o), "OK\n");
    assert_eq!(d.read("output.tmp"), MAYAK_OUTPUT.replace('\n', "\r\n"));
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
    assert_eq!(d.read("output.tmp"), MAYAK_OUTPUT);
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
            "input.tmp:1:1: CYCLE 77: not one of the control's machine cycles (72, 82)",
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
            "input.tmp:1:6: G96 (constant surface speed): not yet converted for this control",
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
    let o = d.run(&["post", "--dialect", "sinumerik802d", "input.tmp"]);
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
    let o = d.run(&["post", "--dialect-file", "shop.toml", "input.tmp"]);
    assert_eq!(stdout(&o), "OK\n");
    assert!(
        d.read("output.tmp")
            .contains("\nN008 G72 X156.31 Z-136.98 P5\n")
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
    let script = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("post/fmsvm_post_mayak600t.py"),
    )
    .expect("the launcher");
    let d = Dir::new();
    let block = stdout(&d.run(&["dialects", "--cycles", "mayak600t"]));
    assert!(
        script.contains(&format!("'''\n{block}'''\n")),
        "post/fmsvm_post_mayak600t.py carries `fmsvm dialects --cycles mayak600t` in its header"
    );
    // The library runs it with python; where there is none, the script's text is all there is to check.
    let Ok(python) = std::process::Command::new("python3")
        .arg("--version")
        .output()
    else {
        eprintln!("no python3 here: the launcher is not run");
        return;
    };
    assert!(python.status.success());
    d.file("input.tmp", MAYAK_INPUT);
    let o = std::process::Command::new("python3")
        .arg(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("post/fmsvm_post_mayak600t.py"))
        .arg(d.path("input.tmp"))
        .env("FMSVM", env!("CARGO_BIN_EXE_fmsvm"))
        .output()
        .expect("runs");
    assert_eq!(String::from_utf8_lossy(&o.stdout), "OK\n");
    assert_eq!(d.read("output.tmp"), MAYAK_OUTPUT);
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
    let want = "\
N001 T0101
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
