//! The `fmsvm` binary: exit codes, diagnostics on standard error with `file:line:col`, source line and
//! caret, output written atomically (nothing under the final name after a failure).

use std::io::Write;
use std::path::Path;
use std::process::Stdio;

use crate::cli_support;

use cli_support::{Dir, bin, run, stderr, stdout};

#[test]
fn run_to_stdout_and_to_a_file() {
    let d = Dir::new();
    d.file("p.nc", "%\nO12\n#1=2\nG0 X#1\nM30\n%\n");
    let o = run(&["run", "p.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(stdout(&o), "%\nO0012\nG0 X2.\nM30\n%\n");
    let o = run(&["run", "p.nc", "-o", "out.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(stdout(&o), "");
    assert_eq!(
        std::fs::read_to_string(d.path("out.nc")).unwrap(),
        "%\nO0012\nG0 X2.\nM30\n%\n"
    );
    assert_eq!(d.names(), vec!["out.nc", "p.nc"]);
}

#[test]
fn reads_standard_input() {
    let mut child = bin()
        .args(["run", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    child
        .stdin
        .take()
        .unwrap()
        .write_all(b"G1 X[1+2]\n")
        .unwrap();
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(stdout(&o), "%\nG1 X3.\n%\n");
}

#[test]
fn compile_errors_exit_3_with_position_line_and_caret() {
    let d = Dir::new();
    d.file("bad.nc", "O1\nG0 X1\n#1=[2+3]]\nWHILE[#1 LT 3]DO4\nM30\n");
    let o = run(&["check", "bad.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(3));
    let e = stderr(&o);
    // Both errors are reported, each with file:line:col, the line and a caret.
    assert!(
        e.contains("error[alarm 0114]: format error: unexpected `]`"),
        "{e}"
    );
    assert!(e.contains("--> bad.nc:3:9"), "{e}");
    assert!(e.contains("3 | #1=[2+3]]\n  |         ^ here"), "{e}");
    assert!(
        e.contains("error[alarm 0126]: illegal loop number 4"),
        "{e}"
    );
    assert!(
        e.contains("--> bad.nc:4:15\n  |\n4 | WHILE[#1 LT 3]DO4\n  |               ^^^ here"),
        "{e}"
    );
    assert!(e.contains("2 errors in bad.nc"), "{e}");
    // A compile error writes nothing.
    let o = run(&["run", "bad.nc", "-o", "out.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(3));
    assert_eq!(d.names(), vec!["bad.nc"]);
}

#[test]
fn each_compile_alarm_has_its_number() {
    let d = Dir::new();
    for (src, alarm, at) in [
        ("#1=[[[[[[1]]]]]]\n", "0118", "1:9"),
        ("WHILE[1 EQ 1]DO1\nG0 X1\n", "0124", "1:14"),
        ("END2\n", "0126", "1:1"),
        ("#34=1\n", "0115", "1:1"),
        ("#0=1\n", "0116", "1:1"),
        ("G0 X1 #1=2\n", "0127", "1:1"),
        ("IF[#1 EQ 1]THEN G0 X1\n", "0125", "1:17"),
        ("M3.5\n", "0007", "1:1"),
        ("M-3\n", "0006", "1:1"),
        ("#1=1 LTE 2\n", "0114", "1:6"),
    ] {
        let p = d.file("e.nc", src);
        let o = run(&["check", p.to_str().unwrap()], d.0.path());
        assert_eq!(o.status.code(), Some(3), "{src}");
        let e = stderr(&o);
        assert!(e.contains(&format!("[alarm {alarm}]")), "{src}: {e}");
        assert!(e.contains(&format!("e.nc:{at}\n")), "{src}: want {at}: {e}");
    }
}

#[test]
fn runtime_alarm_exit_4_and_no_output_file() {
    let d = Dir::new();
    d.file("a.nc", "O1\nG0 X1\n#1=0\nG1 X[10/#1]\nM30\n");
    let o = run(&["run", "a.nc", "-o", "out.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(4));
    let e = stderr(&o);
    assert!(e.contains("error[alarm 0112]: zero divide"), "{e}");
    assert!(
        e.contains("--> a.nc:4:6\n  |\n4 | G1 X[10/#1]\n  |      ^^^^^"),
        "{e}"
    );
    assert!(e.contains("no output file was written"), "{e}");
    assert_eq!(
        d.names(),
        vec!["a.nc"],
        "no partial or temporary file is left"
    );
    // An earlier complete output is not replaced by a failed run.
    std::fs::write(d.path("out.nc"), "previous").unwrap();
    let o = run(&["run", "a.nc", "-o", "out.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(4));
    assert_eq!(
        std::fs::read_to_string(d.path("out.nc")).unwrap(),
        "previous"
    );
}

#[test]
fn macro_alarm_3000_with_message() {
    let d = Dir::new();
    d.file("a.nc", "G0 X1\n#3000=12(SPINDLE NOT READY)\n");
    let o = run(&["run", "a.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(4));
    assert!(
        stderr(&o).contains("error[alarm 3012]: SPINDLE NOT READY"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn goto_missing_target_warns_then_alarms_when_taken() {
    let d = Dir::new();
    d.file("g.nc", "#1=1\nIF[#1 EQ 1]GOTO50\nM30\n");
    let o = run(&["check", "g.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(0));
    assert!(
        stderr(&o).contains("warning[alarm 0128]: GOTO50: there is no N50"),
        "{}",
        stderr(&o)
    );
    let o = run(&["check", "-q", "g.nc"], d.0.path());
    assert_eq!(stderr(&o), "");
    let o = run(&["run", "-q", "g.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(4));
    assert!(
        stderr(&o).contains("error[alarm 0128]: sequence number N50 not found"),
        "{}",
        stderr(&o)
    );
}

/// `--max-seconds` bounds a program that takes no branch too: a CAM file run straight from its file
/// (the flat path) and the same lines compiled (one macro line makes it a macro program). 400 000
/// moves take far longer than the 1 ms allowed; the clock is looked at every 4 096 blocks.
#[test]
fn the_wall_time_limit_stops_a_program_without_loops() {
    let d = Dir::new();
    let mut cam = String::from("%\nO1\nG0 X0 Y0 Z5\n");
    for i in 0..400_000u32 {
        cam.push_str(&format!("G1 X{}.{} Y{} F500\n", i % 100, i % 7, i % 13));
    }
    let macro_program = cam.replacen("G0 X0 Y0 Z5\n", "#1=1\nG0 X0 Y0 Z5\n", 1);
    d.file("cam.nc", &(cam + "M30\n%\n"));
    d.file("macro.nc", &(macro_program + "M30\n%\n"));
    for name in ["cam.nc", "macro.nc"] {
        let o = run(
            &["run", name, "--max-seconds", "0.001", "-o", "out.nc"],
            d.0.path(),
        );
        assert_eq!(o.status.code(), Some(5), "{name}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("limit of 0.001 seconds of wall time reached"),
            "{name}: {}",
            stderr(&o)
        );
        assert!(!d.0.path().join("out.nc").exists(), "{name}");
    }
}

#[test]
fn runaway_loop_stops_at_the_step_limit_exit_5() {
    let d = Dir::new();
    d.file("l.nc", "#1=0\nWHILE[1 EQ 1]DO1\n#1=#1+1\nEND1\n");
    let o = run(
        &["run", "l.nc", "--max-steps", "1000", "-o", "out.nc"],
        d.0.path(),
    );
    assert_eq!(o.status.code(), Some(5));
    assert!(stderr(&o).contains("limit of 1000 steps"), "{}", stderr(&o));
    assert_eq!(d.names(), vec!["l.nc"]);
    d.file("b.nc", "WHILE[1 EQ 1]DO1\nG1 X1\nEND1\n");
    let o = run(
        &["run", "b.nc", "--max-blocks", "50", "-o", "out.nc"],
        d.0.path(),
    );
    assert_eq!(o.status.code(), Some(5));
    assert!(
        stderr(&o).contains("limit of 50 output blocks"),
        "{}",
        stderr(&o)
    );
    let o = run(
        &["run", "b.nc", "--max-bytes", "100", "-o", "out.nc"],
        d.0.path(),
    );
    assert_eq!(o.status.code(), Some(5));
    assert!(
        stderr(&o).contains("limit of 100 output bytes"),
        "{}",
        stderr(&o)
    );
    assert_eq!(d.names(), vec!["b.nc", "l.nc"]);
}

#[test]
fn usage_and_io_errors() {
    let d = Dir::new();
    let o = run(&["run"], d.0.path());
    assert_eq!(o.status.code(), Some(2));
    let o = run(&["run", "missing.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(6));
    assert!(
        stderr(&o).contains("cannot read missing.nc"),
        "{}",
        stderr(&o)
    );
    d.file("p.nc", "G0 X1\n");
    let o = run(&["run", "p.nc", "-o", "no/such/dir/out.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(6));
    std::fs::write(d.path("bin.nc"), b"G0 X1\n\xff\xfe\n").unwrap();
    let o = run(&["run", "bin.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(3));
    assert!(
        stderr(&o).contains("bin.nc:2:1: byte 0xFF outside a comment is not UTF-8 text"),
        "{}",
        stderr(&o)
    );
    // EIA RS-244 sets the eighth bit on most characters: told apart from plain binary.
    let eia: Vec<u8> = b"G01X10\n".iter().map(|&b| b | 0x80).collect();
    std::fs::write(d.path("eia.nc"), eia).unwrap();
    let o = run(&["run", "eia.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(3));
    assert!(stderr(&o).contains("looks EIA-coded"), "{}", stderr(&o));
    d.file("empty.nc", "%\n%\n");
    let o = run(&["run", "empty.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(3));
    assert!(stderr(&o).contains("holds no program"), "{}", stderr(&o));
}

#[test]
fn output_options() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "%\nO5 (TITLE)\nN7 G0 X1 (FIRST)\n/G1 X2\n(ALONE)\nG1 X3\n%\n",
    );
    // Comments are kept by default.
    let o = run(&["run", "p.nc", "--renumber", "10"], d.0.path());
    assert_eq!(
        stdout(&o),
        "%\nO0005 (TITLE)\nN10 G0 X1. (FIRST)\n/N20 G1 X2.\n(ALONE)\nN30 G1 X3.\n%\n"
    );
    let o = run(
        &[
            "run",
            "p.nc",
            "--renumber",
            "100,5",
            "--block-delete",
            "--no-comments",
        ],
        d.0.path(),
    );
    // The O line's program name is kept with --no-comments.
    assert_eq!(
        stdout(&o),
        "%\nO0005 (TITLE)\nN100 G0 X1.\nN105 G1 X3.\n%\n"
    );
}

#[test]
fn common_variables_load_and_dump() {
    let d = Dir::new();
    d.file("p.nc", "#500=#500+1\n#100=7\nG0 X#500\n");
    d.file("store.txt", "#500=41\n");
    let o = run(
        &[
            "run",
            "p.nc",
            "--vars",
            "store.txt",
            "--dump-vars",
            "after.txt",
        ],
        d.0.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(stdout(&o), "%\nG0 X42.\n%\n");
    assert_eq!(
        std::fs::read_to_string(d.path("after.txt")).unwrap(),
        "(fmsvm common variables; #100-#199 are volatile and not reloaded)\n(#100=7)\n#500=42\n"
    );
    d.file("bad.txt", "#500=x\n");
    let o = run(&["run", "p.nc", "--vars", "bad.txt"], d.0.path());
    // A malformed file a flag names is a usage error, as for --params, --dialect-file and
    // --offsets (README, "Exit codes": one code for every malformed input file).
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("bad.txt:1: not a number"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn ir_is_printed() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "O9\n#1=0\nWHILE[#1 LT 2]DO1\nG1 X#1\n#1=#1+1\nEND1\nM30\n",
    );
    let o = run(&["ir", "p.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(0));
    let ir = stdout(&o);
    assert!(ir.starts_with("function O0009"), "{ir}");
    assert!(ir.contains("= #1 Lt 2.0"), "{ir}");
    assert!(ir.contains("branch b"), "{ir}");
    assert!(ir.contains("word X#1"), "{ir}");
    assert!(ir.contains("emit block (line 4)"), "{ir}");
    // A block of literal words is one op, its words as written.
    assert!(ir.contains("emit literal block (line 7) M30"), "{ir}");
}

#[test]
fn library_search_path_by_name_and_by_first_line() {
    let d = Dir::new();
    std::fs::create_dir(d.path("lib")).unwrap();
    d.file("lib/O9010.nc", "%\nO9010\nG0 X[#24*2]\nM99\n%\n");
    // Named like the textbook's files: the number comes from the first O line.
    d.file(
        "lib/15-O7053-pocket.nc",
        "%\nO7053 (POCKET)\nG1 Z-1.\nM99\n%\n",
    );
    d.file("lib/notes.txt", "just notes\n");
    d.file("main.nc", "%\nO1\nG65 P9010 X5.\nM98 P7053 L2\nM30\n%\n");
    let o = run(&["run", "main.nc", "--lib", "lib"], d.0.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(stdout(&o), "%\nO0001\nG0 X10.\nG1 Z-1.\nG1 Z-1.\nM30\n%\n");
    // Without the library: a warning when compiling, alarm 0076 when the call runs.
    let o = run(&["run", "main.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(4));
    let e = stderr(&o);
    assert!(
        e.contains("warning[alarm 0076]: program O9010 is not in this file nor in the library"),
        "{e}"
    );
    assert!(
        e.contains("error[alarm 0076]: program not found: O9010"),
        "{e}"
    );
}

#[test]
fn keep_partial_writes_a_clearly_named_incomplete_file() {
    let d = Dir::new();
    d.file(
        "a.nc",
        "O1\nG0 X1\nG0 X2\n#3000=5(OFFSET TOO LARGE)\nG0 X3\nM30\n",
    );
    let o = run(
        &["run", "a.nc", "-o", "out.nc", "--keep-partial"],
        d.0.path(),
    );
    assert_eq!(o.status.code(), Some(4));
    assert!(
        stderr(&o).contains("error[alarm 3005]: OFFSET TOO LARGE"),
        "{}",
        stderr(&o)
    );
    assert!(
        stderr(&o).contains("out.PARTIAL.nc (incomplete)"),
        "{}",
        stderr(&o)
    );
    assert_eq!(d.names(), vec!["a.nc", "out.PARTIAL.nc"]);
    let kept = std::fs::read_to_string(d.path("out.PARTIAL.nc")).unwrap();
    assert_eq!(
        kept,
        "%\nO0001\nG0 X1.\nG0 X2.\n(INCOMPLETE: ALARM 3005 OFFSET TOO LARGE: EXPANSION STOPPED HERE)\n"
    );
}

#[test]
fn printed_output_goes_to_its_own_file() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "POPEN\n#1=2.5\nDPRNT[X#1[32]]\nPCLOS\nG0 X#1\nM30\n",
    );
    let o = run(&["run", "p.nc", "-o", "flat.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(d.path("flat.prn")).unwrap(),
        b"\x12X   2.50\n\x14"
    );
    assert_eq!(
        std::fs::read_to_string(d.path("flat.nc")).unwrap(),
        "%\nG0 X2.5\nM30\n%\n"
    );
    let o = run(
        &["run", "p.nc", "--print", "-", "--no-dc-codes"],
        d.0.path(),
    );
    // Both go to standard output (the printed records after the program, which is buffered apart).
    assert_eq!(stdout(&o), "%\nG0 X2.5\nM30\n%\nX   2.50\n");
    // A failed run leaves no printed file either.
    d.file("q.nc", "POPEN\nDPRNT[A]\n#1=1/0\n");
    let o = run(&["run", "q.nc", "-o", "q.out"], d.0.path());
    assert_eq!(o.status.code(), Some(4));
    assert!(!d.path("q.prn").exists());
}

#[test]
fn main_m99_restart_or_end() {
    let d = Dir::new();
    d.file("m.nc", "O1\nG0 X1\nM99\n");
    let o = run(&["run", "m.nc", "--main-m99", "end"], d.0.path());
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(stdout(&o), "%\nO0001\nG0 X1.\nM99\n%\n");
    let o = run(&["run", "m.nc", "--max-blocks", "5"], d.0.path());
    assert_eq!(o.status.code(), Some(5));
    assert!(stderr(&o).contains("--main-m99 end"), "{}", stderr(&o));
}

/// A Renishaw-style single-surface measuring macro: G31 towards the one axis given, alarm when nothing
/// is touched, the surface at the ball centre plus the stylus radius R in the direction of travel.
const PROBE_MACRO: &str = "%
O9811 (SINGLE SURFACE MEASURE)
#10=#5001
#11=#5002
#12=#5003
G31 X#24 Y#25 Z#26 F#9
IF[#24 NE #0]GOTO10
IF[#25 NE #0]GOTO20
#13=#5063
#14=#26-#12
GOTO30
N10 #13=#5061
#14=#24-#10
GOTO30
N20 #13=#5062
#14=#25-#11
N30 IF[ABS[#13-[#12+#14]] GT 0.0001]GOTO40
N40 #130=#13+#18*#14/ABS[#14]
G1 X#10 Y#11 Z#12
M99
%
";

#[test]
fn probing_macro_against_a_box_of_stock() {
    let d = Dir::new();
    std::fs::create_dir(d.path("lib")).unwrap();
    d.file("lib/O9811.nc", PROBE_MACRO);
    d.file(
        "main.nc",
        "%\nO1 (FIND THE TOP AND THE LEFT FACE, SET G54)\nG90 G0 X60. Y25. Z10.\nG65 P9811 Z-10. F100. R2.\n#100=#130\nG0 X-10.\nZ-5.\nG65 P9811 X40. F100. R2.\n#101=#130\n#5221=#101\n#5223=#100\nG0 Z10.\nM30\n%\n",
    );
    // Stock X10..110, Y0..50, Z-30..0; stylus ball R2.
    let o = run(
        &[
            "run",
            "main.nc",
            "--lib",
            "lib",
            "--stock",
            "10,0,-30,110,50,0",
            "--probe-radius",
            "2",
            "--dump-vars",
            "v.txt",
        ],
        d.0.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // By hand: down from Z10 the ball centre stops at Z2 (top face Z0 + R) → surface Z0; along +X from
    // X-10 it stops at X8 (left face X10 − R) → surface X10. The G31 blocks pass through as programmed.
    assert_eq!(
        stdout(&o),
        "%\nO0001 (FIND THE TOP AND THE LEFT FACE, SET G54)\nG90 G0 X60. Y25. Z10.\nG31 Z-10. F100.\nG1 X60. Y25. Z10.\nG0 X-10.\nZ-5.\nG31 X40. F100.\nG1 X-10. Y25. Z-5.\nG0 Z10.\nM30\n%\n"
    );
    let vars = std::fs::read_to_string(d.path("v.txt")).unwrap();
    assert!(vars.contains("(#100=0)\n(#101=10)\n"), "{vars}");
    // Planned touch points instead of a stock model.
    d.file("touch.txt", "(top) X60 Y25 Z1.5\nX9.5 Y25 Z-5\n");
    let o = run(
        &[
            "run",
            "main.nc",
            "--lib",
            "lib",
            "--probe-points",
            "touch.txt",
            "--dump-vars",
            "w.txt",
        ],
        d.0.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let vars = std::fs::read_to_string(d.path("w.txt")).unwrap();
    assert!(vars.contains("(#100=-0.5)\n(#101=11.5)\n"), "{vars}");
    // No model: a warning, and the skip position is the programmed end point.
    let o = run(
        &["run", "main.nc", "--lib", "lib", "--dump-vars", "x.txt"],
        d.0.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("without a probe model"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn limits_wall_time_and_sub_depth() {
    let d = Dir::new();
    // A loop with no output at all stops at the wall-time limit.
    d.file("spin.nc", "#1=0\nWHILE[1 EQ 1]DO1\n#1=#1+1\nEND1\n");
    for engine in ["interp", "jit"] {
        let o = run(
            &[
                "run",
                "spin.nc",
                "--max-steps",
                "0",
                "--max-seconds",
                "0.3",
                "--engine",
                engine,
                "-o",
                "o.nc",
            ],
            d.0.path(),
        );
        assert_eq!(o.status.code(), Some(5), "{engine}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("seconds of wall time"),
            "{}",
            stderr(&o)
        );
    }
    // Five nested M98: alarm 0077 at the default depth 4, fine with --sub-depth 5.
    d.file(
        "deep.nc",
        "%\nO1\n#100=0\nM98 P9\nG0 X#100\nM30\nO9\n#100=#100+1\nIF[#100 GE 5]GOTO9\nM98 P9\nN9 M99\n%\n",
    );
    let o = run(&["run", "deep.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(4));
    assert!(stderr(&o).contains("[alarm 0077]"), "{}", stderr(&o));
    let o = run(&["run", "deep.nc", "--sub-depth", "5"], d.0.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stdout(&o).contains("G0 X5.\n"));
    let o = run(&["run", "deep.nc", "--sub-depth", "11"], d.0.path());
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn killed_mid_write_leaves_nothing_under_the_final_name() {
    let d = Dir::new();
    d.file(
        "big.nc",
        "#1=0\nWHILE[1 EQ 1]DO1\nG1 X#1 Y[#1*2] Z[#1*3]\n#1=#1+0.001\nEND1\n",
    );
    let mut child = bin()
        .args([
            "run",
            "big.nc",
            "-o",
            "out.nc",
            "--max-blocks",
            "0",
            "--max-steps",
            "0",
        ])
        .current_dir(d.0.path())
        .spawn()
        .expect("spawn");
    // Let it write megabytes, then kill it hard (no chance to clean up).
    std::thread::sleep(std::time::Duration::from_millis(400));
    child.kill().expect("kill");
    child.wait().expect("wait");
    let names = d.names();
    assert!(!names.contains(&"out.nc".to_string()), "{names:?}");
    // What remains is the temporary file, which says what it is.
    assert!(
        names
            .iter()
            .all(|n| n == "big.nc" || n.ends_with(".partial")),
        "{names:?}"
    );
}

#[test]
fn the_readme_gives_the_two_setup_commands_and_ci_runs_the_tests() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).expect("README.md");
    assert!(
        readme.contains("cargo run --release -- run samples/hemisphere.nc -o hemisphere-flat.nc")
    );
    assert!(readme.contains("cargo test --workspace"));
    assert!(root.join("samples/hemisphere.nc").exists());
    let ci = std::fs::read_to_string(root.join(".ci/run")).expect(".ci/run");
    assert!(ci.contains("cargo test --workspace"));
}

#[test]
fn the_library_fetches_the_program_the_call_runs() {
    // One rule for P (CallKind::target): rounded half away from zero, so G65 P9010.6 is O9011 for the
    // library lookup and for the call alike; an M98 with L keeps a five-digit P whole (C8).
    let d = Dir::new();
    std::fs::create_dir(d.path("lib")).unwrap();
    d.file("lib/O9010.nc", "O9010\nG0 X10\nM99\n");
    d.file("lib/O9011.nc", "O9011\nG0 X11\nM99\n");
    d.file("lib/O1000.nc", "O1000\nG0 X1\nM99\n");
    d.file("c.nc", "G65 P9010.6\nM98 P21000\nM30\n");
    let o = run(&["run", "c.nc", "--lib", "lib"], d.0.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(stdout(&o), "%\nG0 X11.\nG0 X1.\nG0 X1.\nM30\n%\n");
}

/// More distinct constants inside expressions than there are constant registers (16 384): the rest
/// are loaded where they are used (issue 14: no limit). 40 000 statements are more than the JIT
/// compiles (vm::jit::MAX_OPS): `auto` interprets them as `interp` does, `jit` says so.
#[test]
fn forty_thousand_distinct_constants_in_expressions() {
    let d = Dir::new();
    let mut text = String::from("O1\n#1=0\n");
    for i in 0..40_000u32 {
        text.push_str(&format!("#1=#1+{i}.{:03}\n", i % 1000));
    }
    // A constant beyond the registers used three times in one line is loaded once there, and again
    // after the IF's branch: (7.123456 + 7.123456) × 7.123456 = 101.48725…, then + 7.123456.
    text.push_str("#2=[7.123456+7.123456]*7.123456\nIF[#2 GT 0] THEN #2=#2+7.123456\n");
    text.push_str("G1 X[#1/1000000] Y#2 F100\nM30\n");
    d.file("c.nc", &text);
    let mut outs = Vec::new();
    for engine in ["interp", "auto"] {
        let o = run(&["run", "c.nc", "--engine", engine, "-o", "-"], d.0.path());
        assert!(o.status.success(), "{engine}: {}", stderr(&o));
        outs.push(stdout(&o));
    }
    assert_eq!(outs[0], outs[1], "both engines");
    // Σ i + (i mod 1000)/1000 over 0..40 000 = 799 980 000 + 19 980 = 799 999 980 → /10^6.
    assert!(outs[0].contains("G1 X800. Y108.611 F100."), "{}", outs[0]);
    let o = run(&["run", "c.nc", "--engine", "jit", "-o", "-"], d.0.path());
    assert_eq!(o.status.code(), Some(4));
    assert!(
        stderr(&o).contains("more than the JIT compiles (20000)"),
        "{}",
        stderr(&o)
    );
}

/// The top-level help names every exit code the README's table lists (0–7, 10–12, 128 + N).
#[test]
fn the_help_names_every_exit_code() {
    let o = bin().arg("--help").output().expect("runs");
    let help = String::from_utf8_lossy(&o.stdout);
    for code in [
        "0 success",
        "1 internal",
        "2 usage",
        "3 compile",
        "4 alarm",
        "5 limit",
        "6 file",
        "7 --verify",
        "10-12 dnc",
        "128+N",
    ] {
        assert!(help.contains(code), "{code}: {help}");
    }
}

/// `check *.nc`: each program on its own with the same flags, then one summary; the exit is the
/// first failure's (3 for a compile error), 0 when every one compiles.
#[test]
fn check_takes_many_programs_and_sums_them_up() {
    let d = Dir::new();
    d.file("a.nc", "G0 X1\nM30\n");
    d.file("b.nc", "#1=[1+\nM30\n");
    d.file("c.nc", "G0 X1\nM30\n");
    let o = d.run(&["check", "a.nc", "b.nc", "c.nc"]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("b.nc:1:4"), "{err}");
    assert!(
        err.contains("c.nc: no errors")
            && err.contains("checked 3 files: 2 without errors, 1 with errors"),
        "{err}"
    );
    let o = d.run(&["check", "a.nc", "c.nc"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).contains("checked 2 files: 2 without errors, 0 with errors"));
}

/// `stats -h` and `plot -h` say what -o is there and leave out the flags about the flat program's
/// text; given anyway, such a flag is a usage error naming it.
#[test]
fn stats_and_plot_help_lists_only_what_applies() {
    let mut commands = vec!["stats"];
    if cfg!(feature = "plot") {
        commands.push("plot");
    }
    for command in commands {
        let o = bin().args([command, "-h"]).output().expect("runs");
        let help = String::from_utf8_lossy(&o.stdout);
        for flag in [
            "--verify",
            "--tape",
            "--renumber",
            "--compact",
            "flat program here",
        ] {
            assert!(!help.contains(flag), "{command} -h lists {flag}:\n{help}");
        }
        let d = Dir::new();
        d.file("p.nc", "G0 X1\nM30\n");
        let o = d.run(&[command, "p.nc", "--verify", "-o", "out.svg"]);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(
            stderr(&o).contains(&format!(
                "fmsvm {command} writes no flat program: --verify applies to `fmsvm run`"
            )),
            "{}",
            stderr(&o)
        );
    }
}

/// A drilled hole seen end-on is a point: `plot`'s XY view marks each place a feed move went
/// straight down (one ring a hole, however many pecks: three G81 holes and one G83 hole of four
/// pecks are four rings); the XZ view, which sees the holes as lines, draws no ring.
#[cfg(feature = "plot")]
#[test]
fn plot_marks_each_hole_it_sees_end_on() {
    let d = Dir::new();
    d.file(
        "holes.nc",
        "G90 G17 G21\nG0 X0 Y0 Z10\nG99 G81 X10 Y10 Z-5 R2 F100\nX20\nX30\nG83 X40 Y10 Z-20 R2 Q5\nG80\nG0 Z10\nM30\n",
    );
    for (view, rings) in [("xy", 4), ("xz", 0)] {
        let o = d.run(&["plot", "holes.nc", "--view", view, "-o", "h.svg"]);
        assert!(o.status.success(), "{}", stderr(&o));
        let svg = d.read("h.svg");
        assert_eq!(svg.matches("<circle").count(), rings, "{view}");
    }
}

/// `plot` draws where the tool's tip goes: with tool lengths in --offsets and G43, the extents are
/// the program's Z, not the gauge line's (length 100 would put Z -5 at 95). Feed moves are coloured
/// by depth by default (the deepest pass at the ramp's dark end, #440154, the highest at its light
/// end, #FDE725), or by tool with `--colour tool` (the legend names T1 and T2).
#[cfg(feature = "plot")]
#[test]
fn plot_shows_the_tool_tip_and_colours_by_depth_or_tool() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "G90 G17 G21 G0 X0 Y0 Z50\nT1 M6\nG43 H1 Z50\nG0 Z5\nG1 Z-5 F200\nX100\nG0 Z50\nT2 M6\nG43 H2 Z50\nG0 X20 Y20 Z5\nG1 Z-10 F200\nX80\nG0 Z50\nM30\n",
    );
    d.file(
        "off.toml",
        "[tool.1]\nlength = 100\n[tool.2]\nlength = 80\n",
    );
    let o = d.run(&[
        "plot",
        "p.nc",
        "--offsets",
        "off.toml",
        "--view",
        "xz",
        "-o",
        "p.svg",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let svg = d.read("p.svg");
    assert!(
        svg.contains("X 0.000 .. 100.000   Z -10.000 .. 50.000"),
        "{svg}"
    );
    // The two passes: X0→100 at Z-5 and X20→80 at Z-10, the plunges between them and Z5.
    assert!(svg.contains("feed Z -10.000 .. 5.000"), "{svg}");
    // The Z-10 pass at the ramp's deep end; the Z-5 pass and the plunges in other colours.
    let colours: std::collections::BTreeSet<&str> = svg
        .lines()
        .filter(|l| l.contains("<polyline"))
        .filter_map(|l| l.split("stroke=\"").nth(1))
        .map(|s| &s[..7])
        .filter(|c| !["#D64000", "#000000"].contains(c))
        .collect();
    assert!(colours.contains("#440154"), "{colours:?}");
    assert!(colours.len() >= 3, "{colours:?}");
    let o = d.run(&[
        "plot",
        "p.nc",
        "--offsets",
        "off.toml",
        "--colour",
        "tool",
        "-o",
        "t.svg",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let svg = d.read("t.svg");
    assert!(
        svg.contains("stroke=\"#0054BE\"") && svg.contains("stroke=\"#008C46\""),
        "{svg}"
    );
    for t in ["T1", "T2"] {
        assert!(svg.contains(&format!(">\n{t}\n</text>")), "{t}: {svg}");
    }
}

/// `run -h` is one screen (40 lines of at most 100 columns) of the flags most runs need under
/// their headings; `--help` has every flag, the values of each choice listed.
#[test]
fn run_help_fits_a_screen_and_long_help_has_every_flag() {
    let d = Dir::new();
    let short = stdout(&run(&["run", "-h"], d.0.path()));
    assert!(short.lines().count() <= 40, "{short}");
    assert!(short.lines().all(|l| l.chars().count() <= 100), "{short}");
    for shown in [
        "Input:",
        "Output:",
        "Dialect:",
        "Verification:",
        "Kernel:",
        "-o, --output",
        "--dialect",
        "--verify",
        "--no-comments",
        "--lib",
        "--control",
    ] {
        assert!(short.contains(shown), "{shown} in\n{short}");
    }
    assert!(!short.contains("--n33-brake-step"), "{short}");
    let long = stdout(&run(&["run", "--help"], d.0.path()));
    for flag in [
        "--n33-brake-step",
        "--max-steps",
        "--comp-style",
        "--probe-points",
        "--print-without-popen",
        "--main-m99",
        "--strict-axes",
        "--verify-file",
        "Limits:",
        "Machine model:",
    ] {
        assert!(long.contains(flag), "{flag} in --help");
    }
    // A choice on the screen keeps its values in the long help.
    assert!(long.contains("- haas-lathe"), "{long}");
}
