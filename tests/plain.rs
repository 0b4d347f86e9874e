//! The plain paths (the kernel's plain move, the literal emitter's plain block and its cache of
//! each letter's last word) write exactly what the general paths write: the same bytes, messages,
//! statistics, variables and exit codes on random macro programs that mix plain moves with every
//! kind of block that must leave them (G91, arcs, cycles, polar coordinates, rotation, work offsets,
//! inch, comments, block delete, values that repeat and values that overflow), with the general
//! paths forced by `--without plain`; and the same programs on one thread and with the plain blocks
//! written by a second (`--without pipeline`).

use crate::cli_support;

use std::path::Path;
use std::process::Output;

use cli_support::{Dir, Rng, bin, messages, stderr};

/// Runs `args` in `cwd`, with environment variable `off` set to 1 (a shortcut turned off).
fn run(args: &[&str], cwd: &Path, off: Option<&str>) -> (Output, String) {
    let mut c = bin();
    c.args(args)
        .arg("--dump-vars")
        .arg("vars.txt")
        .current_dir(cwd);
    if let Some(path) = off {
        c.args(["--without", path]);
    }
    let _ = std::fs::remove_file(cwd.join("vars.txt"));
    let o = c.output().expect("runs");
    let vars = std::fs::read_to_string(cwd.join("vars.txt")).unwrap_or_default();
    (o, vars)
}

fn same(args: &[&str], cwd: &Path, what: &str) {
    same_without(args, cwd, what, "plain");
}

/// `args` run as they are and with `off` set write the same.
fn same_without(args: &[&str], cwd: &Path, what: &str, off: &str) {
    let (p, pv) = run(args, cwd, None);
    let (g, gv) = run(args, cwd, Some(off));
    assert_eq!(
        p.status.code(),
        g.status.code(),
        "{what}: exit\n{}\n{}",
        stderr(&p),
        stderr(&g)
    );
    assert_eq!(messages(&p), messages(&g), "{what}: messages");
    assert!(
        p.stdout == g.stdout,
        "{what}: output differs\nplain:\n{}\ngeneral:\n{}",
        String::from_utf8_lossy(&p.stdout),
        String::from_utf8_lossy(&g.stdout)
    );
    assert_eq!(pv, gv, "{what}: variables");
}

/// Program `i`, `text`, written to `d` and run both ways with `flags`.
fn same_program(d: &Dir, text: &str, flags: &[&str], i: usize) {
    same_program_without(d, text, flags, i, "plain");
}

/// Program `i`, `text`, run with `flags` as it is and with `off` set.
fn same_program_without(d: &Dir, text: &str, flags: &[&str], i: usize, off: &str) {
    d.file("p.nc", text);
    let mut args = vec!["run", "p.nc", "-o", "-"];
    args.extend_from_slice(flags);
    same_without(
        &args,
        d.0.path(),
        &format!("program {i} {flags:?} ({off}):\n{text}"),
        off,
    );
}

/// A value expression: literals with and without points, variables that repeat from block to
/// block, the rounding boundary, negative zero, and now and then one too large for the digits.
fn value(r: &mut Rng, overflow: bool) -> String {
    match r.next() % 12 {
        0 => "#1".into(),
        1 => "#2".into(),
        2 => "[#1*0.37-5]".into(),
        3 => "[#2/3]".into(),
        4 => format!("{}", r.next() % 300),
        5 => format!("-{}.{:03}", r.next() % 90, r.next() % 1000),
        6 => "[#1+0.0005]".into(),
        7 => "[0*-1]".into(),
        8 => "#5001".into(),
        9 if overflow && r.next().is_multiple_of(4) => "[#1*10000000]".into(),
        10 => "[#4109+1]".into(),
        _ => format!("{}.", r.next() % 50),
    }
}

/// A block: mostly plain moves (in every combination of N, G0/G1, axes and F), else one of the
/// blocks that take the general path or change the state the plain ones rely on.
fn block(r: &mut Rng, nct: bool, overflow: bool) -> String {
    let mut s = String::new();
    if r.next().is_multiple_of(9) {
        s.push('/');
    }
    if r.next().is_multiple_of(3) {
        s.push_str(&format!("N{} ", r.next() % 500));
    }
    match r.next() % 24 {
        0 => s.push_str("G91 G1 X1. Y-1."),
        1 => s.push_str("G90"),
        2 => s.push_str("G2 X10. Y0 R5. F200"),
        3 => s.push_str("G90 G81 X5. Y5. Z-2. R1. F100\nX7.\nG80"),
        4 => s.push_str("G80"),
        5 => s.push_str("G90 G16 G1 X10. Y30.\nY45.\nG15"),
        6 => s.push_str("G15"),
        7 => s.push_str("G68 X0 Y0 R30."),
        8 => s.push_str("G69"),
        9 => s.push_str(r.pick(&["G55", "G54", "G52 X5. Y5.", "G52 X0 Y0"])),
        10 => s.push_str(r.pick(&["G20", "G21"])),
        11 => s.push_str(r.pick(&["M3 S1000", "M5", "T2 M6", "G4 P100"])),
        12 => s.push_str(&format!("G#3 X{}", value(r, overflow))),
        13 => s.push_str("#3=1-#3"),
        14 => s.push_str("#100=#5001+#5002+#5003+#4001+#4109"),
        15 if nct => s.push_str(r.pick(&["G1 XI1. Y2.", "G0 ZI-0.5"])),
        16 => s.push_str("G1.0 X1."),
        _ => {
            if !r.next().is_multiple_of(3) {
                s.push_str(r.pick(&["G1 ", "G0 ", "G01 ", "G00 "]));
            }
            for axis in ["X", "Y", "Z", "A"] {
                if !r.next().is_multiple_of(3) {
                    s.push_str(&format!("{axis}{} ", value(r, overflow)));
                }
            }
            if r.next().is_multiple_of(4) {
                s.push_str(&format!("F{}", r.pick(&["100", "250.", "[#1+50]", "33.3"])));
            }
        }
    }
    if r.next().is_multiple_of(7) {
        s.push_str(" (PASS)");
    }
    s.trim_end().to_string()
}

/// `head`, then a loop of 2–5 passes over 8–27 blocks of `block`, then the end.
fn looped(mut head: String, r: &mut Rng, mut block: impl FnMut(&mut Rng) -> String) -> String {
    head.push_str(&format!("WHILE[#1LT{}]DO1\n", 2 + r.next() % 4));
    for _ in 0..(8 + r.next() % 20) {
        head.push_str(&block(r));
        head.push('\n');
    }
    head.push_str("#1=#1+1\n#2=#2-0.5\nEND1\nM30\n%\n");
    head
}

fn program(r: &mut Rng, nct: bool) -> String {
    // One program in eight may stop at a value too large for the digits (alarm 0003).
    let overflow = r.next().is_multiple_of(8);
    let head = String::from("%\nO1\nG21 G90 G17 G54\n#1=0\n#2=5\n#3=0\n");
    looped(head, r, |r| block(r, nct, overflow))
}

#[test]
fn random_programs_write_the_same_either_way() {
    let d = Dir::new();
    let mut r = Rng(0x2545_F491_4F6C_DD1D);
    for i in 0..120 {
        let text = program(&mut r, i % 6 == 3);
        let flags: &[&str] = match i % 6 {
            0 => &[],
            1 => &["--comments", "--stats"],
            2 => &["--dialect", "fanuc0itd"],
            3 => &["--decimal-input", "increment", "--input", "nct"],
            4 => &["--block-delete", "--engine", "interp"],
            _ => &["--compact"],
        };
        same_program(&d, &text, flags, i);
    }
}

/// A block for canonical output: one of `block`'s, or one that changes what a plain move under
/// resolving relies on (a tool length that moves Z unnamed, a work offset that moves the output
/// frame, by a block or between blocks, cutter compensation, a corner word, an axis no block has
/// positioned).
fn canon_block(r: &mut Rng) -> String {
    match r.next() % 14 {
        0 => r.pick(&["G43 H1 Z20.", "G43 H2", "G49", "G49 Z50."]).into(),
        1 => r
            .pick(&[
                "G10 L2 P1 X5. Y-3.",
                "G10 L2 P1 X0 Y0",
                "G10 L2 P2 Z1.",
                "#5221=[#1*2]",
                "#5203=#2",
            ])
            .into(),
        2 => r
            .pick(&[
                "G41 D1 G1 X5. Y5. F300\nX15.\nY15.\nG40 G1 X20. Y20.",
                "G42 D1 G1 X0 Y10. F300\nX10.\nG40 G1 X15. Y15.",
            ])
            .into(),
        3 => r
            .pick(&[
                "G1 X30. Y30.\nX40. ,R1.\nY40.",
                "G1 X30. Y30.\nY40. ,C0.5\nX20.",
            ])
            .into(),
        4 => r.pick(&["G0 B10.", "G1 A[#1*3] F100", "G92 X0 Y0"]).into(),
        _ => block(r, false, false),
    }
}

/// A program of `canon_block`s, with tool registers set (H1, D1) and H2 left unset.
fn canon_program(r: &mut Rng) -> String {
    let mut s = String::from(
        "%\nO1\nG21 G90 G17 G54\nG10 L2 P1 X0 Y0 Z0\nG10 L2 P2 X0 Y0 Z0\nG10 L10 P1 R50.\nG10 L12 P1 R2.\n#1=0\n#2=5\n#3=0\n",
    );
    // A is positioned in half the programs (an unknown axis in the others).
    s.push_str(r.pick(&["G0 X0 Y0 Z10.\n", "G0 X0 Y0 Z10. A0\n"]));
    looped(s, r, canon_block)
}

/// The plain move under canonical output (resolved output, the dialects, `stats`) makes the
/// general path's operations, warnings and alarms: the same bytes, messages, variables and exit
/// codes with `--without plain` set, on programs that mix plain moves with every state that must
/// take them off it.
#[test]
fn random_programs_resolve_the_same_either_way() {
    let d = Dir::new();
    let mut r = Rng(0x5DEE_CE66_D1CE_4E5B);
    let mut resolved = 0;
    for i in 0..100 {
        let text = canon_program(&mut r);
        let flags: &[&str] = match i % 5 {
            0 => &["--resolve"],
            1 => &["--dialect", "fms3000", "--engine", "interp"],
            2 => &["--dialect", "linuxcnc"],
            3 => &["--resolve", "--frame", "machine"],
            _ => &["--dialect", "iso", "--stats"],
        };
        same_program(&d, &text, flags, i);
        same_program_without(&d, &text, flags, i, "pipeline");
        d.file("p.nc", &text);
        let mut args = vec!["run", "p.nc", "-o", "-"];
        args.extend_from_slice(flags);
        let (o, _) = run(&args, d.0.path(), None);
        resolved += usize::from(o.status.success());
        same(
            &["stats", "p.nc", "--json"],
            d.0.path(),
            &format!("stats {i}"),
        );
    }
    // Most programs run to their end (an arc that cannot reach its end, compensation that finds no
    // corner or a move of an unknown axis stops some, which is compared too).
    assert!(resolved > 55, "only {resolved} of 100 ran to the end");
}

/// The same programs write the same on one thread as with the plain blocks written by a second
/// (`emit::pipelined`; tests/pipelined.rs has the long programs and the stops mid-batch).
#[test]
fn random_programs_write_the_same_on_one_thread() {
    let d = Dir::new();
    let mut r = Rng(0x2545_F491_4F6C_DD1D);
    for i in 0..120 {
        let text = program(&mut r, i % 6 == 3);
        let flags: &[&str] = match i % 4 {
            0 => &[],
            1 => &["--comments", "--stats"],
            2 => &["--decimal-input", "increment", "--input", "nct"],
            _ => &[
                "--block-delete",
                "--engine",
                "interp",
                "--dialect",
                "fms3000",
            ],
        };
        same_program_without(&d, &text, flags, i, "pipeline");
    }
    let mut r = Rng(0x9E37_79B9_7F4A_7C15);
    for i in 0..40 {
        same_program_without(&d, &nc_only(&mut r), &[], i, "pipeline");
    }
}

/// The cache of each letter's last word is keyed by the value's bits, the word's place (first or
/// after the separator) and the units: the same number after a unit change, or first in one block
/// and after N in the next, is written anew.
#[test]
fn a_repeated_value_is_written_anew_where_its_text_changes() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "%\nO1\nG21 G90\nX1.5\nN5 X1.5\nG1 X1.5\nY[1/3]\nG20\nY[1/3]\nG21\nY[1/3]\nY[1/3]\nM30\n%\n",
    );
    let o = bin()
        .args(["run", "p.nc", "-o", "-"])
        .current_dir(d.0.path())
        .output()
        .expect("runs");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    let lines: Vec<&str> = text.lines().collect();
    // Hand-derived: Fanuc format, 0.001 mm, 0.0001 inch.
    let want = [
        "%", "O0001", "G21 G90", "X1.5", "N5 X1.5", "G1 X1.5", "Y0.333", "G20", "Y0.3333", "G21",
        "Y0.333", "Y0.333", "M30", "%",
    ];
    assert_eq!(lines, want, "{text}");
    same(&["run", "p.nc", "-o", "-"], d.0.path(), "units and places");
}

/// A CAM-like program with no macro statement, which runs straight from the file (driver/src/flat.rs):
/// the plain paths there too, with values written with and without points (decimal-point input
/// type I reads `X10` as 10 µm).
fn nc_only(r: &mut Rng) -> String {
    let mut s = String::from("%\nO2\nG21 G90 G17\n");
    for _ in 0..(20 + r.next() % 40) {
        let mut line = String::new();
        if r.next().is_multiple_of(10) {
            line.push('/');
        }
        match r.next() % 10 {
            0 => line.push_str(r.pick(&["G91", "G90", "G20", "G21", "M3 S900", "G2 X5. Y5. R5."])),
            _ => {
                line.push_str(r.pick(&["G1 ", "G0 ", "", "N10 G1 "]));
                for axis in ["X", "Y", "Z"] {
                    if !r.next().is_multiple_of(3) {
                        let v = r.next() % 400;
                        line.push_str(&match r.next() % 3 {
                            0 => format!("{axis}{v} "),
                            1 => format!("{axis}{v}. "),
                            _ => format!("{axis}-{v}.{:03} ", r.next() % 1000),
                        });
                    }
                }
                if r.next().is_multiple_of(5) {
                    line.push_str("F500");
                }
            }
        }
        if r.next().is_multiple_of(8) {
            line.push_str(" (CUT)");
        }
        s.push_str(line.trim_end());
        s.push('\n');
    }
    s.push_str("M30\n%\n");
    s
}

#[test]
fn nc_only_programs_write_the_same_either_way() {
    let d = Dir::new();
    let mut r = Rng(0x9E37_79B9_7F4A_7C15);
    for i in 0..60 {
        let text = nc_only(&mut r);
        let flags: &[&str] = match i % 3 {
            0 => &[],
            1 => &["--decimal-input", "increment", "--comments"],
            _ => &["--stats", "--block-delete"],
        };
        same_program(&d, &text, flags, i);
    }
}
