//! The milling controls against their manuals, second round: the FMS-3000 (its programming manual,
//! sections named beside each test) and the Н33-2М tape. Each expected word is worked out by hand
//! from the program and the manual's rule.

use crate::cli_support;

use cli_support::{Dir, stderr};

/// `p.nc` written with `options` to out.nc and read back (`--verify`), which must pass: what the
/// run said on standard error, and the output.
fn verified(d: &Dir, options: &[&str]) -> (String, String) {
    let args = [&["run", "p.nc"], options, &["-o", "out.nc", "--verify"]].concat();
    let o = d.run(&args);
    assert!(o.status.success(), "{options:?}: {}", stderr(&o));
    (stderr(&o), d.read("out.nc"))
}

/// A tool length of 100 and the reference point at machine Z0: a home move through G54.
const HOME: &str = "\
O1
G90 G17 G21 G40 G49 G80
T1 M6
G0 X0 Y0
G43 H1 Z50.
G1 Z-2. F100
G91 G28 Z0
G90
M30
";

#[test]
fn a_home_move_through_an_unknown_g54_is_refused_not_guessed() {
    let d = Dir::new();
    d.file("p.nc", HOME);
    d.file(
        "off.toml",
        "[reference.G28]\nZ = 0\n[tool.1]\nlength = 100\n",
    );
    let args = [
        "run",
        "p.nc",
        "--dialect",
        "n33",
        "--start-point",
        "X0 Y0 Z300",
        "--offsets",
        "off.toml",
        "-o",
        "out.tap",
        // The reproducer's Z300 start and the return span more than the ram's 150 mm (A.2, tested
        // in the_tape_stays_within_the_machines_travels): not what this test is about.
        "--travel",
        "none",
    ];
    let o = d.run(&args);
    // Where machine Z0 lies in G54 is G54's offset, which nobody gave: the tape cannot say how
    // far down the return goes (taken as 0 it ends the tip 100 mm inside the part).
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("p.nc:7:1: warning: G54's work offset was never set"),
        "{}",
        stderr(&o)
    );
    // docs/offsets.md: a warning where the output can carry the return (Fanuc writes G28 itself),
    // an error with --strict-axes.
    let fanuc = [
        "run",
        "p.nc",
        "--dialect",
        "fanuc",
        "--resolve",
        "--offsets",
        "off.toml",
        "-o",
        "out.nc",
    ];
    let o = d.run(&fanuc);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("p.nc:7:1: warning: G54's work offset was never set"),
        "{}",
        stderr(&o)
    );
    let o = d.run(&[&fanuc[..], &["--strict-axes"]].concat());
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("G54's work offset was never set") && stderr(&o).contains("p.nc:7"),
        "{}",
        stderr(&o)
    );
    // Declared (G54 = 0: the part's zero at machine zero), the return is the spindle's gauge line
    // from Z98 (the tip at Z-2 with a 100 mm tool) to Z0: 98.00 mm down in 0.01 mm increments.
    d.file(
        "off.toml",
        "[reference.G28]\nZ = 0\n[tool.1]\nlength = 100\n[work.G54]\nX = 0\nY = 0\nZ = 0\n",
    );
    let o = d.run(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let tape = d.read("out.tap");
    for line in ["Z-015000", "Z-005200", "Z-009800"] {
        assert!(tape.lines().any(|l| l.contains(line)), "{line} in\n{tape}");
    }
}

/// G18 for an arc, then G17 in a block that moves nothing, then G43: on the FMS-3000 the length
/// correction goes on the axis normal to the plane in force (§3.3, Table 7), the kernel's on Z.
const PLANE: &str = "\
O1
G90 G17 G21 G40 G49 G80 G54
G0 X0 Y0 Z50.
G18 G2 X20. Z50. I10. K0 F200
G17 G0 Z50.
G43 H1 Z10.
G01 Z-2. F100
G0 Z50.
M30
";

#[test]
fn a_length_offset_on_the_fms3000_is_taken_on_in_g17() {
    let d = Dir::new();
    d.file("p.nc", PLANE);
    d.file(
        "fms.toml",
        "base = \"fms3000\"\nname = \"fmsctl\"\n[motion]\ntool_length = \"control\"\n",
    );
    let (_, out) = verified(&d, &["--dialect-file", "fms.toml"]);
    assert!(out.lines().any(|l| l == "G17 G43 G00 Z10 H1"), "{out}");
    // The same block without its G17 would put the length on Y: --verify reads the plane.
    d.file("bad.nc", &out.replace("G17 G43", "G43"));
    let o = d.run(&[
        "run",
        "p.nc",
        "--dialect-file",
        "fms.toml",
        "--verify-file",
        "bad.nc",
    ]);
    assert_eq!(o.status.code(), Some(7), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("G43 H1 in G18 (on Y), the kernel's no work system, G43 H1"),
        "{}",
        stderr(&o)
    );
}

const SKIP: &str = "\
O1
G90 G17 G21 G40 G49 G80 G54
G0 X0 Y0 Z10.
G31 Z-10. F100
G0 Z10.
M30
";

#[test]
fn a_skip_move_is_the_controls_touch_stop_or_refused() {
    let d = Dir::new();
    d.file("p.nc", SKIP);
    // Each control's own: the FMS-3000's G32 ends the block on the touch signal (§2.11) with the
    // block's G01; Fanuc's G31 (skip function); LinuxCNC's G38.3 (probe, no error without contact,
    // as G31 runs to its end).
    for (dialect, line) in [
        ("fms3000", "G01 G32 Z-10 F100"),
        ("fanuc", "G1 G31 Z-10. F100."),
        ("linuxcnc", "G38.3 Z-10 F100"),
    ] {
        let (_, out) = verified(&d, &["--dialect", dialect, "--resolve"]);
        assert!(
            out.lines().any(|l| l == line),
            "{dialect}: {line} in\n{out}"
        );
        // A plain feed in its place drives the probe through the surface: --verify says so.
        d.file("bad.nc", &out.replace(line, "G01 Z-10 F100"));
        let o = d.run(&[
            "run",
            "p.nc",
            "--dialect",
            dialect,
            "--resolve",
            "--verify-file",
            "bad.nc",
        ]);
        assert_eq!(o.status.code(), Some(7), "{dialect}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("the kernel: a skip move (G31)"),
            "{dialect}: {}",
            stderr(&o)
        );
    }
    // No touch-stop known: refused at the G31, nothing written.
    for (dialect, extra) in [("n33", Some("X0 Y0 Z10")), ("iso", None)] {
        let mut args = vec!["run", "p.nc", "--dialect", dialect, "-o", "none.nc"];
        if let Some(s) = extra {
            args.extend_from_slice(&["--start-point", s]);
        }
        let o = d.run(&args);
        assert_eq!(o.status.code(), Some(4), "{dialect}: {}", stderr(&o));
        assert!(stderr(&o).contains("G31 (a skip move)"), "{}", stderr(&o));
        assert!(stderr(&o).contains("p.nc:4:1"), "{}", stderr(&o));
        assert!(!d.path("none.nc").exists());
    }
    // Under cutter compensation a skip move is refused (FMS-3000 §7).
    d.file(
        "comp.nc",
        "O1\nG90 G17 G21 G40 G49 G80 G54\nG10 L12 P1 R5.\nG0 X0 Y0 Z10.\nG41 D1 G1 X10. F100\nG31 X20. F100\nG40 G0 X0\nM30\n",
    );
    let o = d.run(&["run", "comp.nc", "--dialect", "fms3000", "-o", "none.nc"]);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("a skip move (G31) under cutter compensation"),
        "{}",
        stderr(&o)
    );
}

/// `G51 X0 Y0 P…` then a move to X10 Y5: where it goes under each reading of P.
fn scaled_x(d: &Dir, p: &str, extra: &[&str]) -> String {
    d.file(
        "s.nc",
        &format!("O1\nG90 G17 G21 G40 G49 G80 G54\nG0 X0 Y0 Z10.\nG51 X0 Y0 {p}\nG1 X10. Y5. F100\nG50\nM30\n"),
    );
    let mut args = vec!["run", "s.nc", "--resolve", "-o", "-"];
    args.extend_from_slice(extra);
    let o = d.run(&args);
    assert!(o.status.success(), "{p}: {}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    out.lines()
        .find(|l| l.starts_with("G1 "))
        .unwrap_or_default()
        .to_string()
}

#[test]
fn a_scaling_magnification_without_a_point_is_in_the_controls_increment() {
    let d = Dir::new();
    // Fanuc ("Scaling (G50, G51)"): P a whole number in 0.001 by default, P2000 is ×2; I J K the
    // same, per axis.
    assert_eq!(scaled_x(&d, "P2000", &[]), "G1 X20. Y10. F100.");
    assert_eq!(scaled_x(&d, "I2000 J3000", &[]), "G1 X20. Y15. F100.");
    // Parameter 5400#7 SCR set to 0.00001: P200000 is ×2.
    d.file("p.toml", "[machine]\nscaling_unit = 0.00001\n");
    assert_eq!(
        scaled_x(&d, "P200000", &["--params", "p.toml"]),
        "G1 X20. Y10. F100."
    );
    // The NCT textbook writes the factor itself (its O7062: G51 X0 Y0 P2).
    assert_eq!(
        scaled_x(&d, "P2", &["--input", "nct"]),
        "G1 X20. Y10. F100."
    );
    // A unit that is not the control's: refused at its line.
    d.file("p.toml", "[machine]\nscaling_unit = 0.01\n");
    d.file("s.nc", "O1\nM30\n");
    let o = d.run(&["run", "s.nc", "--params", "p.toml", "-o", "-"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("p.toml:2:"), "{}", stderr(&o));
}

/// The Н33-2М: M00 takes the place of the M03 in force ("an M command holds until the next M",
/// A.8), so after the stop for a manual tool change the spindle is started again before the tape
/// moves on (as after the first tool's stop).
#[test]
fn the_tape_restarts_the_spindle_after_every_stop() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "O1\nG90 G17 G21 G40 G49 G80 G54\nT1 M6\nS1000 M3\nG0 X0 Y0 Z10.\nG1 Z-2. F100\nG0 Z10.\nT2 M6\nS1200 M3\nG0 X10. Y0\nG1 Z-8. F100\nG0 Z10.\nM30\n",
    );
    let (_, tape) = verified(&d, &["--dialect", "n33", "--start-point", "X0 Y0 Z10"]);
    let lines: Vec<&str> = tape.lines().collect();
    let stops: Vec<usize> = (0..lines.len())
        .filter(|&i| lines[i].contains("M00"))
        .collect();
    assert_eq!(stops.len(), 2, "{tape}");
    for i in stops {
        assert!(lines[i + 1].ends_with("M03"), "after {}: {tape}", lines[i]);
    }
}

/// The first block states every mode the motion depends on (FMS-3000 Table 6 note 1: groups 01–16
/// come from parameters at power-on and nothing resets them at M30), and after a native cycle the
/// next feed move says its F (§4.1, §4.3: G80 cancels the cycle's parameters, its F with them).
#[test]
fn the_first_block_states_the_modes_and_f_follows_a_native_cycle() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "O1\nG90 G17 G21 G54\nG0 X0 Y0 Z10.\nG1 X5. F2000\nG99 G81 X10. Y0 Z-5. R2. F100\nG80\nG1 X30. Z-5.\nM30\n",
    );
    let (_, out) = verified(&d, &["--dialect", "fms3000"]);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], "G90 G17 G94 G35 G40 G49 G80 G54", "{out}");
    let after = lines
        .iter()
        .position(|l| *l == "G80")
        .map(|i| lines[i + 1])
        .unwrap_or_default();
    // The program's F is modal (Fanuc): the cycle's F100 is in force after G80, and the FMS-3000
    // must be told it again.
    assert_eq!(after, "G01 X30 Z-5 F100", "{out}");
}

/// G98 G89: LinuxCNC's G89 feeds out to the initial level (its trace, `g89_g98`), the kernel with
/// it; a control's own G89 block feeds only to R, so that hole goes out as its moves and reads
/// back; under G99 the block is the control's.
#[test]
fn a_g89_returning_above_r_is_written_as_its_moves() {
    let d = Dir::new();
    for (retract, native) in [("G98", false), ("G99", true)] {
        d.file(
            "p.nc",
            &format!("O1\nG90 G17 G21 G54\nG0 X0 Y0 Z20.\n{retract} G89 X10. Y0 Z-5. R2. P500 F100\nX20.\nG80\nG0 Z20.\nM30\n"),
        );
        for dialect in ["fms3000", "linuxcnc"] {
            let (_, out) = verified(&d, &["--dialect", dialect]);
            let cycle = if dialect == "fms3000" { "G82" } else { "G89" };
            assert_eq!(out.contains(cycle), native, "{dialect} {retract}:\n{out}");
        }
    }
}

/// The FMS-3000's length correctors are H1–H255 (§1.2.3, Table 3): H300 is refused at its line.
#[test]
fn a_length_register_beyond_the_controls_range_is_refused() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "O1\nG90 G17 G21 G54\nG0 X0 Y0 Z50.\nG43 H300 Z10.\nG1 Z-2. F100\nG49 G0 Z50.\nM30\n",
    );
    d.file(
        "fms.toml",
        "base = \"fms3000\"\nname = \"fmsctl\"\n[motion]\ntool_length = \"control\"\n",
    );
    let o = d.run(&["run", "p.nc", "--dialect-file", "fms.toml", "-o", "out.nc"]);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(stderr(&o).contains("p.nc:4:1"), "{}", stderr(&o));
    assert!(!d.path("out.nc").exists());
}

/// A feed's digits follow the feed mode and units (Fanuc IS-B: F0.0001 mm/rev, F0.000001 in/rev):
/// F0.0125 mm/rev is not rounded to F0.013 (4 %), and an inch G95 feed verifies.
#[test]
fn a_feed_per_revolution_keeps_its_digits() {
    let d = Dir::new();
    for (units, z, f) in [("G21", "Z-5.", "F0.0125"), ("G20", "Z-0.5", "F0.1016")] {
        d.file(
            "p.nc",
            &format!("O1\nG90 G17 {units}\nG0 X0 Y0 Z1.\nG95 G1 {z} {f}\nG94 G0 Z1.\nM30\n"),
        );
        let o = d.run(&["run", "p.nc", "--resolve", "-o", "out.nc", "--verify"]);
        assert!(o.status.success(), "{units}: {}", stderr(&o));
        let out = d.read("out.nc");
        assert!(out.contains(&format!("G1 {z} {f}")), "{units}:\n{out}");
    }
}

/// `stats` reports the tool tip's extents, as `plot` does (a 100 mm tool at Z50 has its tip at
/// Z50, the gauge line at Z150), and says so.
#[test]
fn stats_reports_the_tool_tips_extents() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "O1\nG90 G17 G21 G54\nG10 L10 P1 R100.\nG0 X0 Y0 Z50.\nG43 H1 Z50.\nG1 Z-2. F100\nG0 Z50.\nM30\n",
    );
    let o = d.run(&["stats", "p.nc"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        text.contains("Z -2.000 .. 50.000  mm (the tool tip)"),
        "{text}"
    );
}

/// Literal Fanuc output leaves H to the control: no "never set" warning there; resolved output
/// computes with it and warns.
#[test]
fn a_register_warning_only_where_fmsvm_computes_with_it() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "O1\nG90 G17 G21\nG0 X0 Y0\nG43 H1 Z50.\nG1 Z-2. F100\nM30\n",
    );
    let o = d.run(&["run", "p.nc", "-o", "out.nc"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("never set"), "{}", stderr(&o));
    let o = d.run(&["run", "p.nc", "--resolve", "-o", "out.nc"]);
    assert!(
        stderr(&o).contains("H1: the tool length register 1 was never set"),
        "{}",
        stderr(&o)
    );
}

/// A helix in the FMS-3000's pitch form goes out half a turn a block at most (§2.5; a block
/// without axis words is a full circle there, §2.4.3): 270° is two blocks of 135°.
#[test]
fn a_pitch_helix_is_written_half_a_turn_at_most_a_block() {
    let d = Dir::new();
    // From X10 Y0 about X0 Y0, counter-clockwise 270° to X0 Y-10, Z down 3 (4 a turn).
    d.file(
        "p.nc",
        "O1\nG90 G17 G21 G54\nG0 X10. Y0 Z0\nG3 X0 Y-10. Z-3. I-10. J0 F100\nG0 Z10.\nM30\n",
    );
    let (_, out) = verified(&d, &["--dialect", "fms3000"]);
    let helix: Vec<&str> = out.lines().filter(|l| l.contains("G10")).collect();
    assert_eq!(helix.len(), 2, "{out}");
    // 135° from X10 Y0: Y7.071, Z down 1.5.
    assert!(helix[0].contains("X-7.071 Y7.071 Z-1.5"), "{out}");
}

/// Dwells under the FMS-3000's least (0.05 s rounds to no tenth, §2.12) are not written: said, not
/// dropped in silence. Exact stop is: the FMS-3000 has G09 (this block) and G61 (until cancelled)
/// with Fanuc's meaning, and its G62 cancels G61 as Fanuc's G64 does (§2.12, §2.13.1); Fanuc's G62
/// (automatic corner override) and G63 (tapping mode) mean other things there (G63 a deceleration to
/// parameter N3000, §2.13.2) and are said, not written. A dialect with no such words (LinuxCNC's
/// G61 is exact path, its G9 does not exist) says each.
#[test]
fn what_resolved_output_leaves_out_is_said() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "O1\nG90 G17 G21 G54\nG0 X0 Y0 Z10.\nG1 Z-1. F100\nG4 P40\nG09 G1 X10.\nX20.\nG61\nX30.\nY10.\nG64 X0\nG63\nG0 Z10.\nM30\n",
    );
    let (e, out) = verified(&d, &["--dialect", "fms3000"]);
    assert!(
        e.contains("p.nc:5:1: warning: a dwell of 0.04 s is under half"),
        "{e}"
    );
    assert!(
        e.contains("p.nc:12:1: warning: G63 (exact stop or cutting mode)"),
        "{e}"
    );
    assert!(!e.contains("G61 (exact") && !e.contains("G9 (exact"), "{e}");
    let out = out.replace('\r', "");
    assert_eq!(
        out,
        "G90 G17 G94 G35 G40 G49 G80 G54\nG00 X0 Y0 Z10\nG01 Z-1 F100\nG09 X10\nX20\nG61\nX30\nY10\nG62\nX0\nG00 Z10\nM30\n",
        "{out}"
    );
    let o = d.run(&["run", "p.nc", "--dialect", "linuxcnc", "-o", "out.ngc"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    for said in [
        "p.nc:6:1: warning: G9 (exact",
        "p.nc:8:1: warning: G61 (exact",
        "p.nc:11:1: warning: G64 (exact",
    ] {
        assert!(e.contains(said), "{said} in {e}");
    }
    assert!(!d.read("out.ngc").contains("G61"));
}

/// The Н33-2М's braking code before a slower block (§5.2.3): with d1 = 0 the control already slows
/// to the next block's feed at the end of the block, so a 2000 mm/min plunge into a 90° corner at
/// 40 mm/min is `F0720`, as the manual's Ex. 4 N016 writes it (`Z-007000 F0720` then
/// `X-003000 F0540`); at the same corner into 2000 mm/min it brakes (`F4720`).
#[test]
fn the_tape_brakes_only_where_the_next_feed_is_fast() {
    let d = Dir::new();
    for (next, want) in [("F40", "Z-007000F0720"), ("F2000", "Z-007000F4720")] {
        d.file(
            "p.nc",
            &format!("O1\nG90 G17 G21\nG1 Z-70. F2000\nX-30. {next}\nM30\n"),
        );
        let (_, tape) = verified(&d, &["--dialect", "n33", "--start-point", "X0 Y0 Z0"]);
        assert!(
            tape.lines().any(|l| l.ends_with(want)),
            "{next}: {want} in\n{tape}"
        );
    }
}

/// The Н33-2М tape is at most 30 m with the ФСУ-2 photo-reader (§5.1), ten rows an inch with its
/// leader, gaps and trailer: a long program is refused at the block that passes it, and
/// `--split-tapes` makes tapes that each fit.
#[test]
fn a_tape_is_no_longer_than_the_reader_takes() {
    let d = Dir::new();
    let mut program = String::from("G90 G17 G0 X0 Y0 Z5\nG1 Z0 F300\n");
    for i in 0..1400 {
        program += &format!("G1 X{:.2} Y{}\n", 10.0 + f64::from(i) * 0.1, (i % 2) * 5);
        if i % 200 == 199 {
            program += "G0 Z5\nG0 X0 Y0\nG1 Z0 F300\n";
        }
    }
    program += "G0 Z50\nM30\n";
    d.file("p.nc", &program);
    let base = [
        "run",
        "p.nc",
        "--dialect",
        "n33",
        "--start-point",
        "X0 Y0 Z0",
        "-o",
        "out.txt",
        "--verify",
    ];
    let o = d.run(&base);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("where the reader takes 30 m"),
        "{}",
        stderr(&o)
    );
    let mut args = base.to_vec();
    args.push("--split-tapes");
    let o = d.run(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = d.read("out.txt");
    let tapes: Vec<&str> = out.split("%\n").filter(|t| !t.is_empty()).collect();
    assert!(tapes.len() >= 2, "{out}");
    for tape in tapes {
        // 100 rows of leader, `%` and its end, each block's characters and end, 2 NUL rows after
        // each block, 100 rows of trailer.
        let rows: usize = 102 + tape.lines().map(|l| l.len() + 1 + 2).sum::<usize>() + 100;
        let metres = rows as f64 * 2.54 / 1000.0;
        assert!(metres <= 30.0, "{metres} m");
    }
}

/// A warning is located as an error is: FILE:LINE:COL, the file a library macro came from when
/// its block is the one warned about (two files may both have a line 3).
#[test]
fn warnings_name_the_file_line_and_column_of_their_block() {
    let d = Dir::new();
    d.file(
        "lib/O9010.nc",
        "%\nO9010\nG0 X0 Y0\n  G43 Z20. H1\nM99\n%\n",
    );
    d.file(
        "main.nc",
        "%\nO1\nG0 X0 Y0 Z50.\nG65 P9010\n G43 Z30. H2\nM30\n%\n",
    );
    let o = d.run(&[
        "run",
        "main.nc",
        "--lib",
        "lib",
        "--resolve",
        "-o",
        "out.nc",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    let lib = std::path::Path::new("lib").join("O9010.nc");
    let at_lib = format!(
        "{}:4:3: warning: H1: the tool length register 1 was never set",
        lib.display()
    );
    assert!(err.contains(&at_lib), "{at_lib} in\n{err}");
    assert!(
        err.contains("main.nc:5:2: warning: H2: the tool length register 2 was never set"),
        "{err}"
    );
}

/// The 6Р13Ф3-37 travels X 1000, Y 400 and its ram Z 150 mm (A.2, §4). Where the part is
/// clamped is the operator's choice, so what no clamping can run is a program whose moves on one
/// axis span more: refused at the block that passes it (alarm 0500, Fanuc's overtravel), an arc's
/// extremes counted. Another dialect declares its machine's travels in its profile
/// (`[motion] travel`) or on the command line (`--travel`).
#[test]
fn the_tape_stays_within_the_machines_travels() {
    let d = Dir::new();
    let tape = |d: &Dir, body: &str| {
        d.file(
            "p.nc",
            &format!("O1\nG90 G17 G21 G40 G49 G80\nG0 X0 Y0 Z0\n{body}M30\n"),
        );
        d.run(&[
            "run",
            "p.nc",
            "--dialect",
            "n33",
            "--start-point",
            "X0 Y0 Z0",
            "-o",
            "out.tap",
        ])
    };
    // The ram's whole travel is 150 mm: 150 down is the most.
    let o = tape(&d, "G1 Z-150. F100\nG0 Z0\n");
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::remove_file(d.0.path().join("out.tap")).expect("the tape of the run before");
    let o = tape(&d, "G1 Z-150.01 F100\nG0 Z0\n");
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("alarm 0500")
            && err.contains("Z moves over 150.010 mm (from -150.010 to 0.000 mm), more than the machine's 150 mm travel")
            && err.contains("p.nc:4:1"),
        "{err}"
    );
    assert!(!d.0.path().join("out.tap").exists(), "no tape is left");
    // A circle that starts and ends at Y0 but reaches Y402 through its extreme (radius 201).
    let o = tape(&d, "G1 X10. F100\nG2 X10. Y0 I0 J201.\n");
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(stderr(&o).contains("Y moves over 4"), "{}", stderr(&o));
    assert!(stderr(&o).contains("p.nc:5:1"), "{}", stderr(&o));
    // Radius 199: Y spans 398, within the 400.
    let o = tape(&d, "G1 X10. F100\nG2 X10. Y0 I0 J199.\n");
    assert!(o.status.success(), "{}", stderr(&o));
    // The FMS-3000 profile declares no machine; its machine's travels come from a profile built
    // on it, or from --travel, and the same span rule holds.
    d.file(
        "p.nc",
        "O1\nG90 G17 G21\nG0 X0 Y0 Z50.\nG1 Z-60. F100\nG0 Z50.\nM30\n",
    );
    d.file(
        "mine.toml",
        "base = \"fms3000\"\n[motion]\ntravel = \"X800 Y400 Z100\"\n",
    );
    let o = d.run(&["run", "p.nc", "--dialect-file", "mine.toml", "-o", "out.nc"]);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("Z moves over 110.000 mm (from -60.000 to 50.000 mm), more than the machine's 100 mm travel"),
        "{}",
        stderr(&o)
    );
    // No travel in the profile; --travel gives one (the span here is 110 mm), or is refused.
    for (travel, code) in [
        (None, 0),
        (Some("Z110"), 0),
        (Some("Z109.99"), 4),
        (Some("W5"), 2),
    ] {
        let mut args = vec!["run", "p.nc", "--dialect", "fms3000", "-o", "out.nc"];
        args.extend(travel.map(|t| ["--travel", t]).into_iter().flatten());
        let o = d.run(&args);
        assert_eq!(o.status.code(), Some(code), "{travel:?}: {}", stderr(&o));
    }
}

/// Haas NGC probing macros start with G103 P1 (the Haas mill operator's manual, "G103 Limit Block
/// Buffering": P0–P15 blocks of look-ahead, P0 none) so that macro reads see the finished moves.
/// Under `--control haas` it is read: it moves nothing, and no output control has it, so it is not
/// written. Elsewhere it stays an improper G code; P beyond 15 or another word with it is refused.
/// A setting or parameter read with a fraction (`#30001.116`) is refused with what is known.
#[test]
fn haas_look_ahead_limits_are_read_and_not_written() {
    let d = Dir::new();
    d.file("p.nc", "O1\nG103 P1\nG0 X1. Y2. Z3.\nN5 G103 P0\nM30\n");
    for resolve in [false, true] {
        let mut args = vec![
            "run",
            "p.nc",
            "--control",
            "haas",
            "-o",
            "out.nc",
            "--verify",
        ];
        if resolve {
            args.push("--resolve");
        }
        let o = d.run(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        let out = d.read("out.nc");
        assert!(
            !out.contains("G103") && !out.contains("P1") && out.contains("X1."),
            "{out}"
        );
    }
    let o = d.run(&["run", "p.nc", "-o", "out.nc"]);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("improper G-code: G103"),
        "{}",
        stderr(&o)
    );
    for bad in ["G103 P16", "G103 P1 X5."] {
        d.file("q.nc", &format!("O1\n{bad}\nM30\n"));
        let o = d.run(&["run", "q.nc", "--control", "haas", "-o", "out.nc"]);
        assert_eq!(o.status.code(), Some(4), "{bad}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("G103 (Haas: limit block look-ahead) takes P0–P15"),
            "{}",
            stderr(&o)
        );
    }
    d.file("q.nc", "O1\nG103 P1.5\nM30\n");
    let o = d.run(&["run", "q.nc", "--control", "haas", "-o", "out.nc"]);
    assert!(
        !o.status.success() && stderr(&o).contains("P takes a whole number"),
        "{}",
        stderr(&o)
    );
    d.file("r.nc", "O1\n#1=#30001.116\nM30\n");
    let o = d.run(&["run", "r.nc", "--control", "haas", "-o", "out.nc"]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("a variable number is a whole number")
            && stderr(&o).contains("#30000–#39999 parameters"),
        "{}",
        stderr(&o)
    );
}
