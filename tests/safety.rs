//! Safe motion (docs/kernel.md, "Known and unknown positions", "A block moves only what it names",
//! "Reference returns"): no output writes an axis the program did not position, a return to a
//! reference position is the control's own, a change of transform moves nothing, a block that
//! raises an alarm is never written. Every case on both engines and every resolving dialect it
//! concerns; the expected lines are worked out by hand from the rules.

use crate::cli_support;

use cli_support::{Dir, stderr, stdout};
use proptest::prelude::*;

/// The dialects that write resolved motion as words, with how each spells a rapid and a return.
const DIALECTS: [(&str, &[&str]); 4] = [
    ("fms3000", &["--dialect", "fms3000"]),
    ("iso", &["--dialect", "iso"]),
    ("linuxcnc", &["--dialect", "linuxcnc"]),
    ("fanuc", &["--resolve"]),
];

const ENGINES: [&str; 2] = ["interp", "jit"];

/// Runs `src` with `args` on `engine` into out.nc with --verify: the output's lines without the
/// tape's head, or the error text.
fn run(d: &Dir, src: &str, args: &[&str], engine: &str) -> Result<Vec<String>, String> {
    d.file("p.nc", src);
    let mut all = vec![
        "run", "p.nc", "-o", "out.nc", "--verify", "-q", "--engine", engine,
    ];
    all.extend_from_slice(args);
    let o = d.run(&all);
    if !o.status.success() {
        return Err(stderr(&o));
    }
    Ok(d.read("out.nc")
        .lines()
        .map(|l| l.trim().to_string())
        .filter(|l| !l.is_empty() && l != "%" && !l.starts_with('O'))
        // ISO renumbers: the N word is not motion.
        .map(|l| match l.strip_prefix('N') {
            Some(rest) => rest
                .split_once(' ')
                .map_or(String::new(), |(_, r)| r.to_string()),
            None => l,
        })
        .collect())
}

/// The axis letters of one output line (words X Y Z A B C).
fn axes_of(line: &str) -> String {
    let mut out = String::new();
    let b = line.as_bytes();
    for (i, &c) in b.iter().enumerate() {
        if b"XYZABC".contains(&c)
            && b.get(i + 1)
                .is_some_and(|n| n.is_ascii_digit() || *n == b'-' || *n == b'.')
            && (i == 0 || !b[i - 1].is_ascii_alphabetic())
        {
            out.push(c as char);
        }
    }
    out
}

/// The output lines that move (have an axis word).
fn moves(lines: &[String]) -> Vec<&String> {
    lines.iter().filter(|l| is_move(l)).collect()
}

fn is_move(line: &str) -> bool {
    !axes_of(line).is_empty()
}

/// The shop header `G91 G28 Z0` sends Z home and nothing else: no axis moves to the part zero, the
/// return is the control's own, X Y are written only where the program gives them.
#[test]
fn a_shop_header_g91_g28_z0_is_the_controls_own_return_of_z_alone() {
    let src = "%\nO1\nG91 G28 Z0\nG90 G54 G0 X10. Y10.\nZ5.\nG1 Z-1. F100\nG0 Z50.\nM30\n%\n";
    let d = Dir::new();
    for engine in ENGINES {
        for (name, args) in DIALECTS {
            let lines = run(&d, src, args, engine).unwrap_or_else(|e| panic!("{name}: {e}"));
            let ret = lines
                .iter()
                .position(|l| l.contains("G28"))
                .unwrap_or_else(|| panic!("{name}: no return in {lines:?}"));
            let want = if name == "fms3000" {
                "G28 Z0"
            } else if name == "linuxcnc" {
                "G91 G28 Z0"
            } else {
                "G91 G28 Z0."
            };
            assert_eq!(lines[ret], want, "{name}: {lines:?}");
            // Nothing moved before the return, and the next motion is the program's X10 Y10 with
            // no Z (Z is at an unknown reference position: never written until Z5.).
            for l in &lines[..ret] {
                assert_eq!(axes_of(l), "", "{name}: {l} before the return");
            }
            let first = lines[ret + 1..]
                .iter()
                .find(|l| is_move(l))
                .unwrap_or_else(|| panic!("{name}: {lines:?}"));
            assert_eq!(axes_of(first), "XY", "{name}: {first}");
            if name != "fms3000" {
                assert_eq!(lines[ret + 1], "G90", "{name}: back to absolute");
            }
        }
    }
}

/// A first move names X and Y: Z is not written (it was never positioned), in every dialect; with
/// a declared start point the same.
#[test]
fn a_first_move_naming_x_and_y_writes_x_and_y_only() {
    let d = Dir::new();
    for src in [
        "%\nO1\nG54 G0 X10. Y10.\nM30\n%\n",
        "%\nO1\nG1 X10 Y10 F100\nM30\n%\n",
    ] {
        for engine in ENGINES {
            for (name, args) in DIALECTS {
                for start in [&[][..], &["--start-point", "X0 Y0 Z100"][..]] {
                    let mut a = args.to_vec();
                    a.extend_from_slice(start);
                    let lines = run(&d, src, &a, engine).unwrap_or_else(|e| panic!("{name}: {e}"));
                    let moves = moves(&lines);
                    assert_eq!(moves.len(), 1, "{name}: {lines:?}");
                    assert_eq!(axes_of(moves[0]), "XY", "{name} {start:?}: {}", moves[0]);
                }
            }
        }
    }
}

/// After a mirror is cancelled a block that names only Z moves only Z (the tool stays where the
/// mirror left it): exercise 34's last `G0 Z100` has no X move.
#[test]
fn a_z_only_block_after_a_cancelled_mirror_moves_z_only() {
    let src = "%\nO1\nG0 X0 Y0 Z50.\nG51.1 X0\nG0 X20. Y10.\nG50.1 X0\nG0 Z100.\nM30\n%\n";
    let d = Dir::new();
    for engine in ENGINES {
        for (name, args) in DIALECTS {
            let lines = run(&d, src, args, engine).unwrap_or_else(|e| panic!("{name}: {e}"));
            let moves = moves(&lines);
            // X0 Y0 Z50, the mirrored X-20 Y10, then Z100 alone.
            assert_eq!(moves.len(), 3, "{name}: {lines:?}");
            assert!(
                moves[1].contains("X-20") && moves[1].contains("Y10"),
                "{name}: {}",
                moves[1]
            );
            assert_eq!(axes_of(moves[2]), "Z", "{name}: {}", moves[2]);
        }
    }
    // Scaling and rotation likewise: G50 and G69 move nothing.
    for src in [
        "%\nO1\nG0 X0 Y0 Z50.\nG51 X0 Y0 P2\nG0 X10. Y5.\nG50\nG0 Z100.\nM30\n%\n",
        "%\nO1\nG0 X0 Y0 Z50.\nG68 X0 Y0 R90.\nG0 X10. Y0\nG69\nG0 Z100.\nM30\n%\n",
    ] {
        let lines = run(&d, src, &["--resolve"], "interp").unwrap_or_else(|e| panic!("{e}"));
        let last = lines.iter().rfind(|l| is_move(l)).expect("a move");
        assert_eq!(axes_of(last), "Z", "{src}: {lines:?}");
    }
}

/// Alarm 0224 at the block that needs an unknown axis, naming it; nothing written.
#[test]
fn a_move_that_needs_an_unknown_axis_is_alarm_0224_at_its_block() {
    let d = Dir::new();
    let cases: [(&str, &str, &str); 7] = [
        (
            "G91 G0 X10.\n",
            "the incremental X word needs the position of X",
            "1:1",
        ),
        ("#1=#5003\n", "reading #5003 needs the position of Z", "1:4"),
        (
            "G0 X0\nG68 X0 Y0 R30.\nG0 X10.\n",
            "needs the position of Y",
            "3:1",
        ),
        (
            "G0 X0 Y0\nG81 X5. Y5. Z-5. R2. F100\n",
            "needs the position of Z",
            "2:1",
        ),
        (
            "G0 X0\nG41 D1 G1 X10. F100\n",
            "needs the position of Y",
            "2:1",
        ),
        ("G0 X5.\nG92 X0 Y0\n", "needs the position of Y", "2:1"),
        (
            "G0 Z10.\nG2 X10. Y0 I5. F100\n",
            "needs the position of X",
            "2:1",
        ),
    ];
    for engine in ENGINES {
        for (src, text, at) in cases {
            d.file("p.nc", src);
            let o = d.run(&[
                "run",
                "p.nc",
                "--resolve",
                "-o",
                "out.nc",
                "--engine",
                engine,
            ]);
            let e = stderr(&o);
            assert_eq!(o.status.code(), Some(4), "{src}: {e}");
            assert!(
                e.contains("error[alarm 0224]") && e.contains(text),
                "{src}: {e}"
            );
            assert!(e.contains(&format!("p.nc:{at}")), "{src}: {e}");
            assert!(!d.path("out.nc").exists(), "{src}: an output was left");
        }
    }
    // With the start declared, the same programs run.
    d.file("p.nc", "G91 G0 X10.\n#1=#5003\nM30\n");
    let o = d.run(&["run", "p.nc", "--resolve", "--start-point", "X0 Y0 Z0"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("G0 X10.\n"), "{}", stdout(&o));
}

/// The Н33-2М tape is incremental and has no return code: a first move needs the start, a return
/// needs the reference position; with both given it is a plain increment.
#[test]
fn the_n33_tape_refuses_what_it_cannot_count_from() {
    let d = Dir::new();
    d.file("p.nc", "G0 X10. Y5.\nM30\n");
    let o = d.run(&["run", "p.nc", "--dialect", "n33", "-o", "t.txt"]);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(stderr(&o).contains("--start-point"), "{}", stderr(&o));
    d.file("p.nc", "G0 X10. Y5. Z5.\nG91 G28 Z0\nM30\n");
    let o = d.run(&[
        "run",
        "p.nc",
        "--dialect",
        "n33",
        "-o",
        "t.txt",
        "--start-point",
        "X0 Y0 Z0",
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("G28 on the Н33-2М tape") && stderr(&o).contains("position of Z"),
        "{}",
        stderr(&o)
    );
    // The reference position given (machine Z100) and G54 declared at machine zero (a home move
    // is computed through G54, which is never taken as 0 unsaid): Z5 → Z100 is +95 mm.
    d.file(
        "o.toml",
        "[reference.G28]\nZ = 100.0\n[work.G54]\nX = 0\nY = 0\nZ = 0\n",
    );
    let o = d.run(&[
        "run",
        "p.nc",
        "--dialect",
        "n33",
        "-o",
        "t.txt",
        "--start-point",
        "X0 Y0 Z0",
        "--offsets",
        "o.toml",
        "--verify",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(d.read("t.txt").contains("Z+009500"), "{}", d.read("t.txt"));
}

/// A block that raises an alarm is never written, literal or resolved; the output file is not left.
#[test]
fn a_block_that_raises_an_alarm_is_never_written() {
    let d = Dir::new();
    for engine in ENGINES {
        // The arc's end is 20 mm away: R5 cannot reach it (alarm 0020), in literal output too.
        d.file("p.nc", "G0 X10. Y10.\nG2 X30. Y10. R5. F100\nM30\n");
        let o = d.run(&[
            "run",
            "p.nc",
            "--engine",
            engine,
            "--keep-partial",
            "-o",
            "o.nc",
        ]);
        assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
        assert!(stderr(&o).contains("alarm 0020"), "{}", stderr(&o));
        let partial = d.read("o.PARTIAL.nc");
        assert!(
            partial.contains("G0 X10. Y10.") && !partial.contains("G2"),
            "{partial}"
        );
        // G54.1 P60 is alarm 0033 before its block is written.
        d.file("p.nc", "G0 X1.\nG54.1 P60 G0 X2.\nM30\n");
        let o = d.run(&["run", "p.nc", "--engine", engine]);
        assert_eq!(o.status.code(), Some(4));
        assert!(!stdout(&o).contains("X2."), "{}", stdout(&o));
    }
}

/// A length or radius register nobody set is a warning naming it; `--strict-axes` refuses it, and
/// refuses an output move of an axis the block does not name.
#[test]
fn unset_registers_and_unnamed_axes_warn_and_strict_axes_refuses_them() {
    let d = Dir::new();
    d.file("p.nc", "G0 X0 Y0 Z50.\nG43 Z20. H1\nM30\n");
    let o = d.run(&["run", "p.nc", "--resolve"]);
    assert!(o.status.success());
    assert!(
        stderr(&o).contains("p.nc:2:1: warning: H1: the tool length register 1 was never set"),
        "{}",
        stderr(&o)
    );
    let o = d.run(&["run", "p.nc", "--resolve", "--strict-axes"]);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    // A length offset put in force without Z moves Z on the next move: said, refused when strict.
    d.file("o.toml", "[tool.1]\nlength = 25.0\n");
    d.file("p.nc", "G0 X0 Y0 Z50.\nG43 H1\nG0 X10.\nM30\n");
    let o = d.run(&["run", "p.nc", "--resolve", "--offsets", "o.toml"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("p.nc:3:1: warning: X10 also moves Z by 25.000"),
        "{}",
        stderr(&o)
    );
    assert!(stdout(&o).contains("\nX10. Z75.\n"), "{}", stdout(&o));
    let o = d.run(&[
        "run",
        "p.nc",
        "--resolve",
        "--offsets",
        "o.toml",
        "--strict-axes",
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
}

/// One random block of absolute moves: which of X Y Z it names, and the values.
fn block() -> impl Strategy<Value = (u8, [i32; 3])> {
    (1u8..8, prop::array::uniform3(-500i32..500))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// No output block moves an axis its source block does not name (no transform couples one
    /// here), and no axis is written before the program gave it: each source block is one output
    /// block whose axes are a subset of the block's.
    #[test]
    fn no_output_block_moves_an_axis_its_block_does_not_name(
        blocks in prop::collection::vec(block(), 1..12),
        dialect in 0usize..4,
        feed in any::<bool>(),
    ) {
        let mut src = String::from("%\nO1\n");
        let mut named = Vec::new();
        for (k, (mask, v)) in blocks.iter().enumerate() {
            let mut line = String::from(if feed { "G1" } else { "G0" });
            let mut axes = String::new();
            for (i, l) in ['X', 'Y', 'Z'].into_iter().enumerate() {
                if mask & (1 << i) != 0 {
                    // Distinct values block to block: every named axis changes.
                    line.push_str(&format!(" {l}{}.{:03}", v[i], k));
                    axes.push(l);
                }
            }
            if feed {
                line.push_str(" F100");
            }
            src.push_str(&line);
            src.push('\n');
            named.push(axes);
        }
        src.push_str("M30\n%\n");
        let d = Dir::new();
        let (name, args) = DIALECTS[dialect];
        let lines = run(&d, &src, args, "interp").map_err(TestCaseError::fail)?;
        let moves: Vec<String> = lines.iter().map(|l| axes_of(l)).filter(|a| !a.is_empty()).collect();
        // Every named axis changes block to block, so each source block is exactly one output
        // move, and it writes exactly the axes its block names.
        prop_assert_eq!(&moves, &named, "{}: {}\n{:?}", name, src, lines);
    }
}

/// `dnc --start-at` on the incremental Н33-2М tape: a resume preamble cannot be written in its
/// dialect, so nothing is sent (before any link is opened).
#[test]
fn a_dnc_resume_on_the_n33_tape_is_refused() {
    let d = Dir::new();
    d.file("p.nc", "G0 X1 Y1 Z1\nG1 X2 F100\nX3\nX4\nM30\n");
    for extra in [
        &["--dialect", "n33"][..],
        &["--dialect", "n33", "--tape"][..],
    ] {
        let mut args = vec![
            "dnc",
            "p.nc",
            "--start-point",
            "X0 Y0 Z0",
            "--start-at",
            "3",
            "--tcp",
            "127.0.0.1:9",
        ];
        args.extend_from_slice(extra);
        let o = d.run(&args);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(
            stderr(&o).contains("a resume preamble cannot be written in its dialect")
                && stderr(&o).contains("nothing was sent"),
            "{}",
            stderr(&o)
        );
    }
}

/// G53 is the control's own machine-coordinate move, so the flat program does not depend on a work
/// offset fmsvm was not told; the FMS-3000's G53 is modal, and G54 follows it (§2.15.5).
#[test]
fn g53_is_written_as_the_controls_own() {
    let src = "%\nO1\nG10 L2 P1 Z-300.\nG54 G0 X0 Y0 Z10.\nG53 Z-5.\nG1 X1. F100\nM30\n%\n";
    let d = Dir::new();
    for engine in ENGINES {
        for (name, args) in DIALECTS {
            let lines = run(&d, src, args, engine).unwrap_or_else(|e| panic!("{name}: {e}"));
            let at = lines
                .iter()
                .position(|l| l.starts_with("G53"))
                .unwrap_or_else(|| panic!("{name}: {lines:?}"));
            let want = match name {
                "fms3000" => "G53 G00 Z-5",
                "iso" => "G53 G00 Z-5.",
                "linuxcnc" => "G53 G0 Z-5",
                _ => "G53 G0 Z-5.",
            };
            assert_eq!(lines[at], want, "{name}");
            if name == "fms3000" {
                assert_eq!(lines[at + 1], "G54", "{name}: {lines:?}");
            }
            // The next block names X only: Z is not written again.
            let next = lines[at + 1..].iter().find(|l| is_move(l)).expect("a move");
            assert_eq!(axes_of(next), "X", "{name}: {next}");
        }
    }
}

/// G20/G21 move nothing: the tool's coordinates change unit, and a Z-only block moves only Z.
#[test]
fn a_unit_change_keeps_the_tool_where_it_is() {
    let src = "%\nO1\nG21\nG0 X25.4 Y25.4 Z1.\nG20\nG0 Z2.\nG21\nG0 Z10.\nM30\n%\n";
    // A feed given in inch/min stays the same speed after G21 (F10 inch/min is F254 mm/min), and
    // an arc whose end rounds onto its start is no motion (not a full circle).
    let feed =
        "%\nO1\nG20 G0 X0 Y0 Z0\nG1 X1. F10.\nG21\nG1 X30.\nG3 X30.0004 Y0 R10. F100\nM30\n%\n";
    let d0 = Dir::new();
    let lines = run(&d0, feed, &["--resolve"], "interp").unwrap_or_else(|e| panic!("{e}"));
    assert!(lines.contains(&"X30. F254.".to_string()), "{lines:?}");
    assert!(!lines.iter().any(|l| l.starts_with("G3")), "{lines:?}");
    let d = Dir::new();
    for engine in ENGINES {
        let lines = run(&d, src, &["--resolve"], engine).unwrap_or_else(|e| panic!("{e}"));
        // X Y stay where they were (25.4 mm = 1 inch) and are not restated: Z alone, in each unit.
        let at = lines.iter().position(|l| l == "G20").expect("G20");
        assert_eq!(lines[at + 1], "Z2.", "{lines:?}");
        assert_eq!(lines[at + 2], "G21", "{lines:?}");
        assert_eq!(lines[at + 3], "Z10.", "{lines:?}");
        // A control without inch mode gets mm throughout: Z2 inch is Z50.8, X Y not written.
        let lines =
            run(&d, src, &["--dialect", "fms3000"], engine).unwrap_or_else(|e| panic!("{e}"));
        assert!(lines.contains(&"Z50.8".to_string()), "{lines:?}");
        assert!(
            lines.iter().filter(|l| l.contains('X')).count() == 1,
            "{lines:?}"
        );
    }
}

/// A change of G54 while resolving in the G54 frame is said at its line (the flat program's control
/// keeps its own G54), an error with --strict-axes; machine coordinates need no warning.
#[test]
fn a_change_of_the_output_frame_is_said() {
    let d = Dir::new();
    d.file("p.nc", "G0 X10. Y10. Z10.\nG10 L2 P1 X-5.\nG0 Z9.\nM30\n");
    let o = d.run(&["run", "p.nc", "--resolve"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("p.nc:2:1: warning: the work offset the output is written in"),
        "{}",
        stderr(&o)
    );
    let o = d.run(&["run", "p.nc", "--resolve", "--strict-axes"]);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    let o = d.run(&["run", "p.nc", "--resolve", "--frame", "machine"]);
    assert!(o.status.success());
    assert!(
        !stderr(&o).contains("work offset the output"),
        "{}",
        stderr(&o)
    );
    assert!(stdout(&o).contains("\nZ9.\n"), "{}", stdout(&o));
}
