//! Turning programs (docs/lathe.md): the lathe's reading of a program (X a diameter, U W increments,
//! G-code system A or B, G96/G97 with the G50 S clamp, G98/G99, G32, the single cycles G90 G92 G94),
//! its output in every lathe dialect with `--verify`, and `stats` under constant surface speed.
//!
//! The oracle: `tests/lathe/NAME.ngc` is the LinuxCNC twin of `NAME.nc` (G7 diameter mode, G95,
//! `G96 D`, `G33 K`), `NAME.moves` what `rs274 -g` made of it (`tests/lathe/regenerate.sh`, which also
//! runs fmsvm's own LinuxCNC output through `rs274` and requires the same motion). Where LinuxCNC
//! has no such code (Fanuc's single cycles) the expected moves are worked out by hand from the
//! Fanuc manual's figures, as the comments say.

use crate::cli_support;
use crate::common;

use cli_support::{Dir, stderr, stdout};
use common::{Move, diff_moves, moves_of_flat, moves_of_list};

/// The kernel tests' tolerance (0.001 mm output, 0.0001 mm in the trace).
const TOL: f64 = 0.0011;

fn data(name: &str) -> String {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/lathe")
        .join(name);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The moves of LinuxCNC lathe output (`G7`: X a diameter; `G33 … K` a synchronised feed move, as the
/// trace's STRAIGHT_FEED), in radius, as `rs274 -g` reports them.
fn moves_of_lathe_output(text: &str) -> Vec<Move> {
    let mut flat = String::new();
    for line in text.lines() {
        let thread = line.split_whitespace().any(|w| w == "G33");
        let words: Vec<String> = line
            .split_whitespace()
            .filter(|w| !(thread && w.starts_with('K')))
            .map(|w| match (w, w.strip_prefix('X')) {
                ("G33", _) => "G1".to_string(),
                (_, Some(v)) => match v.parse::<f64>() {
                    Ok(d) => format!("X{}", d / 2.0),
                    Err(_) => w.to_string(),
                },
                _ => w.to_string(),
            })
            .collect();
        flat.push_str(&words.join(" "));
        flat.push('\n');
    }
    moves_of_flat(&flat)
}

/// LinuxCNC lathe output `out` moves as its twin's trace `want`, move for move.
fn assert_moves_as_twin(out: &str, want: &[Move], engine: &str) {
    let got = moves_of_lathe_output(out);
    if let Err(e) = diff_moves(&got, want, TOL) {
        panic!("{engine}: {e}\n{out}");
    }
    assert_eq!(got.len(), want.len(), "{engine}: {out}");
}

/// Expands `NAME.nc` for LinuxCNC as a lathe from X0 Z0 (where rs274 starts), verified, on `engine`.
fn linuxcnc_lathe(d: &Dir, name: &str, engine: &str) -> String {
    linuxcnc_lathe_with(d, name, engine, &[])
}

/// `linuxcnc_lathe` with more arguments.
fn linuxcnc_lathe_with(d: &Dir, name: &str, engine: &str, extra: &[&str]) -> String {
    let file = format!("{name}.nc");
    d.file(&file, &data(&file));
    let mut args = vec![
        "run",
        &file,
        "--dialect",
        "linuxcnc",
        "--machine",
        "lathe",
        "--start-point",
        "X0 Z0",
        "--engine",
        engine,
        "-o",
        "out.ngc",
        "--verify",
    ];
    args.extend_from_slice(extra);
    let o = d.run(&args);
    assert!(o.status.success(), "{name} ({engine}): {}", stderr(&o));
    assert!(stderr(&o).contains("verified:"), "{}", stderr(&o));
    d.read("out.ngc")
}

#[test]
fn a_turning_program_moves_as_linuxcnc_moves_its_twin() {
    let want = moves_of_list(&data("turn.moves"));
    assert_eq!(want.len(), 13, "the trace's moves");
    for engine in ["interp", "jit"] {
        let d = Dir::new();
        let out = linuxcnc_lathe(&d, "turn", engine);
        assert!(
            out.starts_with("%\nG7 G18 G90\n"),
            "LinuxCNC: diameter mode and the ZX plane first\n{out}"
        );
        assert!(
            !out.contains("G17") && !has_word(&out, 'Y'),
            "X and Z only\n{out}"
        );
        // T0101 is tool 1 with its own offsets: LinuxCNC changes tools by M6 and applies the
        // offsets by G43 (a bare T101 would only prepare tool 101).
        for line in [
            "G95",
            "G96 D2500 S180",
            "G97 S1000",
            "G33 Z-30 K1.5",
            "T1 M6 G43",
        ] {
            assert!(
                out.lines().any(|l| l == line),
                "`{line}` in the output\n{out}"
            );
        }
        assert_moves_as_twin(&out, &want, engine);
    }
}

#[test]
fn tool_nose_radius_compensation_moves_as_linuxcnc_compensates_its_twin() {
    // nose.nc turns an outside profile with G42 (T0101: nose radius 0.8, tip 3) and bores with G41
    // (T0202: 0.4, tip 2); its twin sets the same tools by G10 L1 (LinuxCNC's Q2 and Q3: its
    // orientations mirror Fanuc's in X). Under LinuxCNC's corner rules the output moves as the trace.
    let want = moves_of_list(&data("nose.moves"));
    assert_eq!(want.len(), 24, "the trace's moves");
    for engine in ["interp", "jit"] {
        let d = Dir::new();
        d.file("nose.toml", &data("nose.toml"));
        let out = linuxcnc_lathe_with(
            &d,
            "nose",
            engine,
            &["--offsets", "nose.toml", "--comp-style", "linuxcnc"],
        );
        assert!(
            !out.contains("G41") && !out.contains("G42"),
            "the compensation is in the moves\n{out}"
        );
        assert_moves_as_twin(&out, &want, engine);
    }
}

#[test]
fn every_imaginary_tool_nose_direction_moves_as_linuxcnc_moves_its_twin() {
    // tips.nc turns one profile (a chamfer, a taper, a concave and a convex arc, a shoulder) with
    // T0101 … T0808, tips 1 to 8, nose radii 0.5 to 1.2; the twin sets each tool by G10 L1 with
    // LinuxCNC's orientation (Fanuc's mirrored in X).
    let want = moves_of_list(&data("tips.moves"));
    assert_eq!(want.len(), 112, "the trace's moves");
    for engine in ["interp", "jit"] {
        let d = Dir::new();
        d.file("tips.toml", &data("tips.toml"));
        let out = linuxcnc_lathe_with(
            &d,
            "tips",
            engine,
            &["--offsets", "tips.toml", "--comp-style", "linuxcnc"],
        );
        assert_moves_as_twin(&out, &want, engine);
    }
}

#[test]
fn tool_nose_radius_compensation_keeps_the_imaginary_tip_on_the_profile() {
    // Fanuc's rules (0i-TD, "Tool nose radius compensation"), worked out by hand. The controlled
    // point is the imaginary tool nose: on a move along Z (or X) it runs on the programmed line
    // itself, so the cylinder X20 is cut at X20. and the shoulder X40 at Z-25., tip 3 (nose centre
    // 0.8 above and 0.8 right of the tip) and tip 2 (0.4 below, 0.8 right) alike. At the outer
    // obtuse corner chamfer/cylinder (type A: the two offset lines meet) the centre is on x = 10.8
    // (radius) and on the chamfer's offset x = 9 - z + 0.8*sqrt(2): z = -0.6686, the tip 0.8 lower
    // in Z: Z-1.4686. The start-up (from X60 Z5 to X16 Z1) meets the chamfer at an inner corner:
    // the centre goes to where the two offset lines meet, (x, z) = (9.6453, 0.4860), the tip to
    // (8.8453, -0.3140): X17.691 Z-0.314.
    let src = data("nose.nc");
    let d = Dir::new();
    let offsets = d.file("nose.toml", &data("nose.toml"));
    let offsets = offsets.to_string_lossy().into_owned();
    for engine in ["interp", "jit"] {
        let got = fanuc_lathe_moves(&src, &["--offsets", &offsets, "--engine", engine]);
        let cut: Vec<_> = got.iter().copied().filter(|m| m.0 != 0).collect();
        assert_moves(
            &cut[..4],
            &[
                (1, 17.691, -0.314),
                (1, 20.0, -1.469),
                (1, 20.0, -20.8),
                (2, 28.4, -25.0),
            ],
            engine,
        );
        assert!(
            got.contains(&(1, 38.4, -25.0)),
            "{engine}: the shoulder at Z-25.: {got:?}"
        );
        assert!(
            got.iter().any(|m| m.0 == 1 && m.1 == 20.0 && m.2 == -15.4),
            "{engine}: the bore at X20.: {got:?}"
        );
    }
    // A thread under compensation is refused where it stands.
    let o = Dir::new();
    o.file(
        "p.nc",
        "T0101\nG0 X40. Z2.\nG42 G1 X30. Z0. F0.2\nG32 Z-10. F1.5\nM30\n",
    );
    let r = o.run(&[
        "run",
        "p.nc",
        "--control",
        "fanuc-0i-t",
        "--resolve",
        "--offsets",
        &offsets,
    ]);
    assert_eq!(r.status.code(), Some(4), "{}", stderr(&r));
    assert!(
        stderr(&r).contains("p.nc:4:")
            && stderr(&r).contains("a thread under tool nose radius compensation"),
        "{}",
        stderr(&r)
    );
    // G70 runs the profile's blocks again: under G42 its output is that of the blocks written out
    // (and the rapid back to its start point), compensated alike. Roughing is refused under it.
    let profile = "N10 G0 X16.\nG1 X20. Z-1. F0.2\nZ-20.\nG2 X30. Z-25. R5.\nG1 X40.\n\
                   G3 X50. Z-30. R5. F0.1\nN20 G1 Z-45. F0.2\n";
    let head = "T0101\nG97 S1000 M3\nG0 X60. Z5.\nG42 G0 X42. Z2.\n";
    let tail = "G40 G0 X60. Z5.\nM30\n";
    let args = ["--offsets", offsets.as_str()];
    let cycle = fanuc_lathe_text(&format!("{head}G70 P10 Q20\n{profile}{tail}"), &args);
    let blocks = fanuc_lathe_text(
        &format!(
            "{head}{}G0 X42. Z2.\n{tail}",
            profile.replace("N10 ", "").replace("N20 ", "")
        ),
        &args,
    );
    assert_eq!(cycle, blocks);
    assert!(
        cycle
            .as_ref()
            .is_ok_and(|t| t.contains("|G1 X20. Z-1.558 F0.2|")),
        "{cycle:?}"
    );
    let rough = fanuc_lathe_text(
        &format!("{head}G71 U1. R0.5\nG71 P10 Q20 U0.4 W0.1 F0.3\n{profile}{tail}"),
        &args,
    );
    assert!(
        rough.as_ref().is_err_and(
            |e| e.contains(":6:") && e.contains("G71 under tool nose radius compensation")
        ),
        "{rough:?}"
    );
    // Without the registers the compensation is of radius 0, and says so.
    let o = Dir::new();
    o.file("p.nc", &src);
    let r = o.run(&[
        "run",
        "p.nc",
        "--control",
        "fanuc-0i-t",
        "--resolve",
        "--start-point",
        "X100 Z100",
    ]);
    assert!(r.status.success(), "{}", stderr(&r));
    assert!(
        stderr(&r).contains("tool offset 01: the tool nose radius register 1 was never set"),
        "{}",
        stderr(&r)
    );
}

/// Whether `out` has a word of `letter` outside comments (`Y5.`, `Y-2`).
fn has_word(out: &str, letter: char) -> bool {
    out.lines()
        .map(|l| l.split(['(', ';']).next().unwrap_or(""))
        .any(|l| {
            l.split_whitespace().any(|w| {
                let mut c = w.chars();
                c.next() == Some(letter)
                    && c.next()
                        .is_some_and(|d| d.is_ascii_digit() || d == '-' || d == '.')
            })
        })
}

/// The turning program without its thread, for the dialects that refuse one.
fn unthreaded() -> String {
    data("turn.nc")
        .lines()
        .filter(|l| !l.starts_with("G32"))
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

#[test]
fn every_lathe_dialect_writes_the_turning_program_and_reads_it_back() {
    // Each dialect's own spelling (docs/lathe.md); hand-checked against the program: the arc from
    // X30 (diameter) Z-40 to X40 Z-45 R5 has its centre at X40 Z-40 (I5 K0 from the start, I in
    // radius); `U2. W-5.` from X60 Z-50 ends at X62 Z-55.
    let cases: [(&str, bool, &[&str]); 7] = [
        (
            "fanuc0itd",
            true,
            &[
                "G18",
                "G99",
                "T0101",
                "G50 S2500",
                "G96 S180",
                "G2 X40. Z-45. K0. I5.",
                "X62. Z-55.",
                "G97 S1000",
                "G32 Z-30. F1.5",
            ],
        ),
        (
            "linuxcnc",
            true,
            &["G7 G18 G90", "G95", "G96 D2500 S180", "G33 Z-30 K1.5"],
        ),
        (
            "sinumerik802d",
            true,
            // DIAMON and G71 (mm) on the 802D: its list of instructions names G70/G71 the inch and
            // metric codes (G21 is not the 802D's), and X on the diameter is stated, not left to
            // the machine data.
            &[
                "G18 G90 DIAMON",
                "N10 G71",
                "N20 G95",
                "N40 LIMS=2500",
                "N50 G96 S180",
            ],
        ),
        // No constant surface speed on these: S per move, the rpm at the move's larger diameter
        // 1000·180/(π·D): D30 → 1909.9 (S1910), D40 → 1432.4, D50 → 1145.9, D60 → 954.9 (clamp 2500
        // not reached).
        (
            "mayak600t",
            false,
            // The spindle starts at the rpm where the tool stands (X200, a diameter as every X a
            // user gives on a diameter lathe: 1000·180/(π·200) = 286.5), not at whatever S the
            // control had (M3 came before any S).
            &[
                "G90",
                // The tool call through the one rule `post` uses too: tool 01, offset 01, in the
                // four digits the library's records and docs/lathe.md write.
                "N002 T0101",
                "N003 S286",
                "N004 M3",
                "N006 S1910",
                // A point on every length: a Маяк-600 reads a coordinate without one in
                // micrometres (its configuration's x_koef = 1; docs/dialects.md).
                "N007 G01 Z-40. F0.25",
                "N008 S1432",
            ],
        ),
        (
            "nc31",
            false,
            &[
                "G90",
                "N003 S286",
                "N006 S1910",
                "N010 S1146",
                "N012 S955",
                "N016 S819",
            ],
        ),
        // G151 (X on the diameter) and G71 (mm) as the FAGOR 8037/8055 T post writes them.
        (
            "fagor8035t",
            false,
            &["G18 G90 G151", "G71", "G92 S2500", "G96 S180"],
        ),
        // ISO 6983-1 under --machine lathe (its [lathe]): G71 mm, G95, S per move as on the
        // Маяк (no clamp is known), the thread's lead as K along Z.
        (
            "iso",
            true,
            &[
                "G18 G90",
                "N10 G71",
                "N20 G95",
                "N30 T0101",
                "N220 G33 Z-30. K1.5",
            ],
        ),
    ];
    for (dialect, threads, lines) in cases {
        let d = Dir::new();
        d.file(
            "p.nc",
            &if threads {
                data("turn.nc")
            } else {
                unthreaded()
            },
        );
        let mut args = vec![
            "run",
            "p.nc",
            "--dialect",
            dialect,
            "--start-point",
            "X200 Z200",
            "-o",
            "out.nc",
            "--verify",
            // The lines below are numbered without the comment lines.
            "--no-comments",
        ];
        if dialect == "linuxcnc" || dialect == "iso" {
            args.extend_from_slice(&["--machine", "lathe"]);
        }
        if dialect == "fanuc0itd" {
            args.push("--resolve");
        }
        let o = d.run(&args);
        assert!(o.status.success(), "{dialect}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("verified:"),
            "{dialect}: {}",
            stderr(&o)
        );
        let out = d.read("out.nc");
        for line in lines {
            assert!(
                out.lines().any(|l| l.trim_end_matches('\r') == *line),
                "{dialect}: `{line}` in\n{out}"
            );
        }
        assert!(
            !out.contains("G17") && !has_word(&out, 'Y'),
            "{dialect}: X and Z only\n{out}"
        );
        // X is a diameter in every lathe dialect: the largest X the part reaches is 70.
        assert!(
            out.contains("X70") && !out.contains("X35"),
            "{dialect}: X in diameter\n{out}"
        );
        // And a corrupted X is caught by --verify.
        let bad = out.replacen("X70", "X71", 1);
        d.file("bad.nc", &bad);
        let mut check = args.clone();
        check.retain(|a| *a != "-o" && *a != "out.nc" && *a != "--verify");
        check.extend_from_slice(&["--verify-file", "bad.nc"]);
        let o = d.run(&check);
        assert_eq!(o.status.code(), Some(7), "{dialect}: {}", stderr(&o));
    }
}

#[test]
fn a_thread_is_refused_where_the_dialect_has_no_thread_block() {
    for dialect in ["mayak600t", "nc31", "fagor8035t"] {
        let d = Dir::new();
        d.file("p.nc", &data("turn.nc"));
        let o = d.run(&["run", "p.nc", "--dialect", dialect, "-o", "out.nc"]);
        assert_eq!(o.status.code(), Some(4), "{dialect}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains("alarm 0010") && e.contains("has no known form") && e.contains("p.nc:18:1"),
            "{dialect}: {e}"
        );
        assert!(!d.path("out.nc").exists(), "{dialect}: nothing written");
    }
}

/// The moves of fanuc0itd's resolved output of `src` from X200 Z100 (diameter), as (G, X diameter, Z).
fn fanuc_lathe_moves(src: &str, extra: &[&str]) -> Vec<(u8, f64, f64)> {
    let d = Dir::new();
    d.file("p.nc", src);
    let mut args = vec![
        "run",
        "p.nc",
        "--dialect",
        "fanuc0itd",
        "--resolve",
        // X200 is a diameter, as every X a user gives on a diameter lathe (docs/lathe.md): the
        // tool stands at a radius of 100.
        "--start-point",
        "X200 Z100",
        "-o",
        "out.nc",
        "--verify",
    ];
    args.extend_from_slice(extra);
    let o = d.run(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = d.read("out.nc");
    let (mut g, mut x, mut z) = (0u8, 100.0, 100.0);
    let mut moves = Vec::new();
    for line in out.lines() {
        let mut moved = false;
        // A dwell's X is seconds.
        if line.split_whitespace().any(|w| w == "G4") {
            continue;
        }
        for w in line.split_whitespace() {
            let (letter, v) = w.split_at(1);
            let Ok(v) = v.parse::<f64>() else { continue };
            match letter {
                "G" if [0.0, 1.0, 2.0, 3.0, 32.0].contains(&v) => g = v as u8,
                "X" => (x, moved) = (v, true),
                "Z" => (z, moved) = (v, true),
                _ => {}
            }
        }
        if moved {
            moves.push((g, x, z));
        }
    }
    moves
}

/// `got` is `want`, move for move, within the output's resolution (0.001 mm).
fn assert_moves(got: &[(u8, f64, f64)], want: &[(u8, f64, f64)], engine: &str) {
    let close = got.len() == want.len()
        && got
            .iter()
            .zip(want)
            .all(|(g, w)| g.0 == w.0 && (g.1 - w.1).abs() < TOL && (g.2 - w.2).abs() < TOL);
    assert!(close, "{engine}:\n got {got:?}\nwant {want:?}");
}

#[test]
fn single_cycles_move_as_the_fanuc_figures_on_both_engines() {
    // Fanuc 0i-TD, "Outer diameter/internal diameter cutting cycle (G90)", "Threading cycle (G92)",
    // "End face turning cycle (G94)": four moves from the start point A and back to it, 1 rapid,
    // 2 feed (G92: thread), 3 feed (G92: rapid), 4 rapid; X(U) Z(W) R modal, R in radius (the X at
    // the cut's start minus the X at its end for G90/G92, the same in Z for G94).
    let src = "G99\nG0 X52. Z2.\nG90 X46. Z-30. F0.3\nX42.\nG0 X50. Z2.\nG90 X40. Z-20. R-3. F0.2\nG0 X60. Z2.\nG94 X20. Z-2. F0.2\nZ-4.\nG0 X40. Z5.\nG92 X38. Z-15. F1.5\nX37.4\nG0 X100. Z100.\nM30\n";
    let want: Vec<(u8, f64, f64)> = vec![
        (0, 52.0, 2.0),
        // G90 X46 Z-30 from X52 Z2.
        (0, 46.0, 2.0),
        (1, 46.0, -30.0),
        (1, 52.0, -30.0),
        (0, 52.0, 2.0),
        // X42: the same cycle, modal Z-30.
        (0, 42.0, 2.0),
        (1, 42.0, -30.0),
        (1, 52.0, -30.0),
        (0, 52.0, 2.0),
        (0, 50.0, 2.0),
        // G90 X40 Z-20 R-3 from X50 Z2: the cut starts at diameter 40 + 2·(-3) = 34.
        (0, 34.0, 2.0),
        (1, 40.0, -20.0),
        (1, 50.0, -20.0),
        (0, 50.0, 2.0),
        (0, 60.0, 2.0),
        // G94 X20 Z-2 from X60 Z2: Z first, then the face, back along Z, then X.
        (0, 60.0, -2.0),
        (1, 20.0, -2.0),
        (1, 20.0, 2.0),
        (0, 60.0, 2.0),
        // Z-4: modal X20.
        (0, 60.0, -4.0),
        (1, 20.0, -4.0),
        (1, 20.0, 2.0),
        (0, 60.0, 2.0),
        (0, 40.0, 5.0),
        // G92 X38 Z-15 F1.5 from X40 Z5: the thread, then rapid out and back.
        (0, 38.0, 5.0),
        (32, 38.0, -15.0),
        (0, 40.0, -15.0),
        (0, 40.0, 5.0),
        (0, 37.4, 5.0),
        (32, 37.4, -15.0),
        (0, 40.0, -15.0),
        (0, 40.0, 5.0),
        (0, 100.0, 100.0),
    ];
    for engine in ["interp", "jit"] {
        let got = fanuc_lathe_moves(src, &["--engine", engine]);
        assert_eq!(got, want, "{engine}");
    }
}

#[test]
fn system_b_and_a_radius_lathe_read_their_own_words() {
    // G-code system B: G91 incremental, G77 the turning cycle, G95 feed per revolution. The same
    // part as system A's `G0 X52. Z2.`, `U-2.`, `G90 X46. Z-30.`.
    let b = "G95\nG0 X52. Z2.\nG91 X-2.\nG90\nG77 X46. Z-30. F0.3\nM30\n";
    let a = "G99\nG0 X52. Z2.\nU-2.\nG90 X46. Z-30. F0.3\nM30\n";
    assert_eq!(
        fanuc_lathe_moves(b, &["--gcode-system", "b"]),
        fanuc_lathe_moves(a, &[])
    );
    // A radius lathe (1006#3 = 0): X26 is a radius of 26, written as the diameter 52.
    let r = "G99\nG0 X26. Z2.\nU-1.\nM30\n";
    assert_eq!(
        fanuc_lathe_moves(r, &["--lathe-x", "radius"]),
        vec![(0, 52.0, 2.0), (0, 50.0, 2.0)]
    );
}

#[test]
fn position_variables_read_as_a_lathe_has_them() {
    // Fanuc T: #5001 is X (a diameter), #5002 is Z; G50 sets the current position (X in diameter).
    let src = "G0 X40. Z5.\n#1=#5001\n#2=#5002\nG0 X[#1-10.] Z[#2+1.]\nG50 X80. Z10.\nG0 U-10. W-2.\n#3=#5001\nG0 X[#3-10.]\nM30\n";
    assert_eq!(
        fanuc_lathe_moves(src, &[]),
        vec![
            (0, 40.0, 5.0),
            (0, 30.0, 6.0),
            // G50 X80 Z10 at X30 Z6: U-10 W-2 reaches X20 Z4 of the G54 frame (X70 Z8 in the new).
            (0, 20.0, 4.0),
            // #5001 reads 70 in the new coordinates: X60 there is X10 here.
            (0, 10.0, 4.0),
        ]
    );
    let d = Dir::new();
    d.file("p.nc", "G0 X40. Z5.\n#1=#5003\nM30\n");
    let o = d.run(&["run", "p.nc", "--control", "fanuc-0i-t", "-o", "out.nc"]);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("a lathe has two axes"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn stats_time_per_revolution_feed_under_constant_surface_speed() {
    // Hand-computed. Facing from X60 to X20 at F0.2 mm/rev under G96 S180 clamped at 2000 rpm:
    // n = 1000·180/(π·D) = k/r with k = 1000·180/(2π) = 28647.89 mm/min, clamped below
    // r_c = k/2000 = 14.3239 mm; time = (1/F)·[(30² − r_c²)/(2k) + (r_c − 10)/2000] min = 4.286685 s.
    // Then 40 mm along Z at 1000 rpm and F0.25: 40/(0.25·1000) min = 9.6 s.
    let d = Dir::new();
    d.file(
        "p.nc",
        "G99 G21\nG0 X60. Z0.\nG50 S2000\nG96 S180 M3\nG1 X20. F0.2\nG97 S1000\nG0 X30. Z2.\nG1 Z-38. F0.25\nM30\n",
    );
    let o = d.run(&["stats", "p.nc", "--control", "fanuc-0i-t", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("json");
    let feed = v["time"]["feed_s"].as_f64().expect("feed_s");
    let k = 1000.0 * 180.0 / std::f64::consts::TAU;
    let rc = k / 2000.0;
    let facing =
        (1.0 / 0.2) * ((30.0f64.powi(2) - rc * rc) / (2.0 * k) + (rc - 10.0) / 2000.0) * 60.0;
    assert!((facing - 4.286685).abs() < 1e-6, "{facing}");
    assert!((feed - (facing + 9.6)).abs() < 1e-6, "{feed}");
    assert_eq!(v["time"]["untimed_feeds"].as_u64(), Some(0));
}

#[test]
fn a_bad_turning_program_gets_a_located_alarm() {
    let cases: [(&str, &str); 6] = [
        ("G0 X20. Y5. Z2.\nM30\n", "Y: this lathe has no Y axis"),
        ("G17\nM30\n", "G17 does not exist on a lathe"),
        ("G0 X20. Z2.\nG32 Z-10.\nM30\n", "a thread without its lead"),
        ("G96 M3\nM30\n", "G96 without S"),
        ("G0 X20. U2. Z2.\nM30\n", "X and U in one block"),
        // A Fanuc has no exponents: Z-1 and E300, an address no rule gives a meaning here, which
        // flat motion would drop.
        (
            "G0 X20. Z2.\nG1 Z-1e300 F0.1\nM30\n",
            "E300: no rule gives the address E a meaning",
        ),
    ];
    for (src, what) in cases {
        let d = Dir::new();
        d.file("p.nc", src);
        let o = d.run(&[
            "run",
            "p.nc",
            "--dialect",
            "fanuc0itd",
            "--resolve",
            "-o",
            "out.nc",
        ]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(4), "{src}: {e}");
        assert!(e.contains(what) && e.contains("p.nc:"), "{src}: {e}");
    }
    // A mill dialect cannot write a turning program.
    let d = Dir::new();
    d.file("p.nc", "G0 X20. Z2.\nM30\n");
    let o = d.run(&["run", "p.nc", "--dialect", "fms3000", "--machine", "lathe"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("writes for a milling machine"));
}

/// The program of the stock removal tests: G71 roughing (depth 2, retract 0.5, allowance U0.4 W0.1)
/// of a profile with a taper and an R5 arc, then G70 finishing it.
const G71_G70: &str = "G99 G21\nT0101\nG97 S1000 M3\nG0 X52. Z2.\nG71 U2. R0.5\nG71 P10 Q20 U0.4 W0.1 F0.3\nN10 G0 X20.\nG1 Z-20. F0.15\nX30. Z-30.\nG2 X40. Z-35. R5.\nG1 Z-50.\nN20 X52.\nG70 P10 Q20\nG0 X100. Z100.\nM30\n";

#[test]
fn g71_and_g70_move_as_worked_out_by_hand() {
    // Hand-computed (Fanuc 0i-TD G71 type I; Robur "Concise Guide Fanuc" p. 48): from A = X52 Z2
    // (radius 26) levels 2 apart in radius, X48 … X24 (X20 would reach the moved profile's start
    // X20.4); each cut ends on the profile moved by U0.4/2 = 0.2 in X and 0.1 in Z: on the last
    // piece at Z-49.9 for X48 and X44, on the moved arc (centre X40.4 Z-29.9 as a diameter, R5)
    // for X40, X36 and X32 (Z = -29.9 - sqrt(25 - (r - 20.2)^2): -34.896, -34.390, -32.613), on
    // the moved taper for X28 and X24 (-27.5, -23.5); 45° out by 0.5 at rapid, back to Z2; then the
    // moved profile from X20.4 Z2.1 (in at rapid: N10 is G0), back to A; G70 runs N10–N20 with its
    // own F0.15 and returns to A.
    let mut want: Vec<(u8, f64, f64)> = vec![(0, 52.0, 2.0)];
    for (x, z) in [
        (48.0, -49.9),
        (44.0, -49.9),
        (40.0, -34.896),
        (36.0, -34.39),
        (32.0, -32.613),
        (28.0, -27.5),
        (24.0, -23.5),
    ] {
        want.extend([
            (0, x, 2.0),
            (1, x, z),
            (0, x + 1.0, z + 0.5),
            (0, x + 1.0, 2.0),
        ]);
    }
    want.extend([
        (0, 20.4, 2.1),
        (1, 20.4, -19.9),
        (1, 30.4, -29.9),
        (2, 40.4, -34.9),
        (1, 40.4, -49.9),
        (1, 52.4, -49.9),
        (0, 52.0, 2.0),
        (0, 20.0, 2.0),
        (1, 20.0, -20.0),
        (1, 30.0, -30.0),
        (2, 40.0, -35.0),
        (1, 40.0, -50.0),
        (1, 52.0, -50.0),
        (0, 52.0, 2.0),
        (0, 100.0, 100.0),
    ]);
    // The emitter leaves out a move that does not change (X49 Z-49.4 after X48's cut, then Z2.).
    for engine in ["interp", "jit"] {
        let got = fanuc_lathe_moves(G71_G70, &["--engine", engine]);
        assert_moves(&got, &want, engine);
    }
}

/// The profile N10–N20 of `G71_G70` as (X radius, Z) points along it, every 0.05 mm.
fn g71_profile_radius_at(z: f64) -> f64 {
    // N10 X20 at Z2 … Z-20; taper to X30 Z-30; R5 arc (centre radius 20, Z-30) to X40 Z-35;
    // X40 to Z-50; then the face up to X52.
    match z {
        z if z >= -20.0 => 10.0,
        z if z >= -30.0 => 10.0 + (-20.0 - z) * 0.5,
        z if z >= -35.0 => 20.0 - (25.0 - (z + 30.0).powi(2)).sqrt(),
        // The face at Z-50 belongs to the cut side: a pass may end on it.
        z if z >= -50.0 - 1e-6 => 20.0,
        _ => 26.0,
    }
}

#[test]
fn g71_roughing_never_feeds_inside_the_part_and_its_allowance() {
    // The invariants of any stock removal: no feed move inside the finished profile plus its
    // allowance (0.2 in X, 0.1 in Z), no pass deeper than the depth of cut, the cycle back at A.
    let d = Dir::new();
    d.file(
        "p.nc",
        G71_G70
            .replace("G70 P10 Q20\n", "")
            .replace("G0 X100. Z100.\n", "")
            .as_str(),
    );
    let o = d.run(&[
        "run",
        "p.nc",
        "--dialect",
        "linuxcnc",
        "--machine",
        "lathe",
        "--start-point",
        "X0 Z0",
        "-o",
        "out.ngc",
        "--verify",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let moves = moves_of_lathe_output(&d.read("out.ngc"));
    let mut from = [0.0f64, 0.0, 0.0];
    let mut checked = 0;
    for m in &moves {
        if m.kind == 1 {
            for k in 0..=200 {
                let t = k as f64 / 200.0;
                let (r, z) = (
                    from[0] + (m.end[0] - from[0]) * t,
                    from[2] + (m.end[2] - from[2]) * t,
                );
                // The part with its allowance: radius profile(z - 0.1) + 0.2.
                let limit = g71_profile_radius_at(z - 0.1) + 0.2;
                assert!(
                    r >= limit - 0.0011,
                    "a feed at X{} Z{z} is inside the part ({limit})",
                    2.0 * r
                );
                checked += 1;
            }
        }
        from = m.end;
    }
    assert!(checked > 1000);
    let last = moves.last().expect("moves");
    assert_eq!((last.end[0], last.end[2]), (26.0, 2.0), "back at A");
    // The roughing levels: each at most the depth of cut (2) below the one before.
    let levels: Vec<f64> = moves
        .windows(2)
        .filter(|w| w[1].kind == 1 && w[1].end[0] == w[0].end[0] && w[0].end[2] == 2.0)
        .map(|w| w[1].end[0])
        .collect();
    assert!(levels.len() >= 7, "{levels:?}");
    let mut prev = 26.0;
    for l in levels {
        assert!(prev - l <= 2.0 + 1e-9, "a pass {} deep", prev - l);
        prev = l;
    }
}

#[test]
fn g72_g73_move_as_worked_out_by_hand() {
    // G72 (facing; Z levels 2 apart from Z2, cuts along X to the profile moved by 0.2 in X and
    // 0.2 in Z, 45° out by 0.5) and G73 (three passes; relief U4. W2. — U a radius — shrinking
    // evenly to the allowance U0.4 W0.1; back to A between passes), hand-computed.
    let src = "G99\nG0 X82. Z2.\nG72 W2. R0.5\nG72 P10 Q20 U0.4 W0.2 F0.25\nN10 G0 Z-10.\nG1 X60.\nX40. Z-4.\nX20.\nN20 Z2.\nG0 X100. Z50.\nG73 U4. W2. R3\nG73 P30 Q40 U0.4 W0.1 F0.2\nN30 G0 X20. Z2.\nG1 Z-10.\nG2 X40. Z-20. R10.\nN40 G1 X60.\nM30\n";
    let mut want: Vec<(u8, f64, f64)> = vec![(0, 82.0, 2.0)];
    for (z, x) in [
        (0.0, 20.4),
        (-2.0, 20.4),
        // On the moved taper X60.4 Z-9.8 → X40.4 Z-3.8.
        (-4.0, 41.067),
        (-6.0, 47.733),
        (-8.0, 54.4),
    ] {
        want.extend([
            (0, 82.0, z),
            (1, x, z),
            (0, x + 1.0, z + 0.5),
            (0, 82.0, z + 0.5),
        ]);
    }
    want.extend([
        (0, 82.4, -9.8),
        (1, 60.4, -9.8),
        (1, 40.4, -3.8),
        (1, 20.4, -3.8),
        (1, 20.4, 2.2),
        (0, 82.0, 2.0),
        (0, 100.0, 50.0),
    ]);
    for (dx, dz) in [(4.2, 2.1), (2.2, 1.1), (0.2, 0.1)] {
        want.extend([
            (0, 20.0 + 2.0 * dx, 2.0 + dz),
            (1, 20.0 + 2.0 * dx, -10.0 + dz),
            (2, 40.0 + 2.0 * dx, -20.0 + dz),
            (1, 60.0 + 2.0 * dx, -20.0 + dz),
            (0, 100.0, 50.0),
        ]);
    }
    for engine in ["interp", "jit"] {
        let got: Vec<(u8, f64, f64)> = fanuc_lathe_moves(src, &["--engine", engine]);
        // The retract's second rapid (back to X82 at z + 0.5) and the next level's rapid (to z)
        // are both there; compare within the output's resolution.
        assert_moves(&got, &want, engine);
    }
}

#[test]
fn g74_g75_g76_move_as_worked_out_by_hand() {
    // G74: grooves from X60 to X20 6 mm apart in radius (P6000: least increments), pecks of 5
    // (Q5000) with a 1 mm retract; G75: grooves from Z5 to Z-15 2 apart, pecks of 3 (radius) from
    // X30 to X20 with 0.5 back; G76 P020000 Q100 R0.05 / X18.16 Z-20 P920 Q400 F1.5: depths
    // 0.4·sqrt(n) — 0.4, 0.566, 0.693, 0.8 — then 0.87 (k − d), then m = 2 passes at 0.92,
    // each X = 18.16 + 2·(0.92 − depth).
    let src = "G99\nG0 X60. Z2.\nG74 R1.\nG74 X20. Z-12. P6000 Q5000 F0.1\nG0 X30. Z5.\nG75 R0.5\nG75 X20. Z-15. P3000 Q2000 F0.08\nG0 X26. Z5.\nG76 P020000 Q100 R0.05\nG76 X18.16 Z-20. P920 Q400 F1.5\nM30\n";
    let mut want: Vec<(u8, f64, f64)> = vec![(0, 60.0, 2.0)];
    for (i, x) in [60.0, 48.0, 36.0, 24.0, 20.0].into_iter().enumerate() {
        if i > 0 {
            want.push((0, x, 2.0));
        }
        want.extend([
            (1, x, -3.0),
            (0, x, -2.0),
            (1, x, -8.0),
            (0, x, -7.0),
            (1, x, -12.0),
            (0, x, 2.0),
        ]);
    }
    want.extend([(0, 60.0, 2.0), (0, 30.0, 5.0)]);
    for i in 0..11 {
        let z = 5.0 - 2.0 * i as f64;
        if i > 0 {
            want.push((0, 30.0, z));
        }
        want.extend([(1, 24.0, z), (0, 25.0, z), (1, 20.0, z), (0, 30.0, z)]);
    }
    want.extend([(0, 30.0, 5.0), (0, 26.0, 5.0)]);
    for depth in [
        0.4,
        0.4 * 2f64.sqrt(),
        0.4 * 3f64.sqrt(),
        0.8,
        0.87,
        0.92,
        0.92,
    ] {
        let x = 18.16 + 2.0 * (0.92 - depth);
        want.extend([
            (0, x, 5.0),
            (32, x, -20.0),
            (0, 26.0, -20.0),
            (0, 26.0, 5.0),
        ]);
    }
    for engine in ["interp", "jit"] {
        let got = fanuc_lathe_moves(src, &["--engine", engine]);
        assert_moves(&got, &want, engine);
    }
}

#[test]
fn repetitive_cycles_pass_through_literally_and_verify_everywhere() {
    // fanuc0itd has G70–G76: literal output writes them as programmed, P and Q as whole numbers
    // (sequence numbers; least increments), and --verify resolves both sides.
    let d = Dir::new();
    d.file("p.nc", G71_G70);
    let o = d.run(&[
        "run",
        "p.nc",
        "--control",
        "fanuc-0i-t",
        "-o",
        "out.nc",
        "--verify",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = d.read("out.nc");
    for line in [
        "G71 U2. R0.5",
        "G71 P10 Q20 U0.4 W0.1 F0.3",
        "N10 G0 X20.",
        "G70 P10 Q20",
    ] {
        assert!(out.lines().any(|l| l == line), "`{line}` in\n{out}");
    }
    // Resolved, every lathe dialect reads the cycles' moves back.
    for dialect in [
        "fanuc0itd",
        "sinumerik802d",
        "mayak600t",
        "nc31",
        "fagor8035t",
    ] {
        let o = d.run(&[
            "run",
            "p.nc",
            "--dialect",
            dialect,
            "--resolve",
            "-o",
            "r.nc",
            "--verify",
        ]);
        assert!(o.status.success(), "{dialect}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("verified: 44 moves"),
            "{dialect}: {}",
            stderr(&o)
        );
    }
}

#[test]
fn a_bad_repetitive_cycle_gets_a_located_alarm() {
    let cases: [(&str, &str); 7] = [
        // A profile that turns back in X: type I needs it monotonic.
        (
            "G0 X52. Z2.\nG71 U2. R0.5\nG71 P10 Q20 U0.4 W0.1 F0.3\nN10 G0 X20.\nG1 Z-20.\nX40. Z-30.\nX30. Z-40.\nN20 X52.\nM30\n",
            "is not monotonic on X and Z (type I needs it)",
        ),
        (
            "G0 X52. Z2.\nG71 P10 Q20 U0.4 W0.1 F0.3\nN10 G0 X20.\nN20 G1 Z-20.\nM30\n",
            "without its first block",
        ),
        (
            "G0 X52. Z2.\nG71 U2. R0.5\nG71 P10 Q20 F0.3\nG0 X60.\nN10 G0 X20.\nN20 G1 Z-20.\nM30\n",
            "the next block must be N10",
        ),
        (
            // Once refused as type II; now type II, which may not turn back along Z.
            "G0 X52. Z2.\nG71 U2. R0.5\nG71 P10 Q20 F0.3\nN10 G0 X20. Z0.\nG1 Z-20.\nN20 Z-10.\nM30\n",
            "turns back along Z",
        ),
        (
            "G0 X52. Z2.\nG71 U2. R0.5\nG71 P10 Q20 F0.3\nN10 G0 X20.\nM3\nN20 G1 Z-20.\nM30\n",
            "only moves",
        ),
        (
            "G0 X26. Z5.\nG76 P020000 Q100 R0.05\nG76 X18.16 Z-20. P0.92 Q400 F1.5\nM30\n",
            // P is an integer address: the decoder's own alarm (Fanuc 0007).
            "illegal use of decimal point",
        ),
        (
            "G0 X26. Z5.\nG76 P021060 Q100 R0.05\nG76 X18.16 Z-20. P920 Q400 F1.5\nM30\n",
            "end chamfer",
        ),
    ];
    for (src, what) in cases {
        let d = Dir::new();
        d.file("p.nc", src);
        let o = d.run(&[
            "run",
            "p.nc",
            "--dialect",
            "fanuc0itd",
            "--resolve",
            "-o",
            "out.nc",
        ]);
        let e = stderr(&o);
        // 4: an alarm while running; 3: the decimal point, refused when the program is compiled.
        assert!(matches!(o.status.code(), Some(3 | 4)), "{src}: {e}");
        assert!(e.contains(what) && e.contains("p.nc:"), "{src}: {e}");
        assert!(!d.path("out.nc").exists());
    }
}

#[test]
fn dnc_does_not_resume_a_turning_program_mid_way() {
    // The resume preamble writes a mill's modal codes (G90 would be a turning cycle on a lathe).
    let d = Dir::new();
    d.file("p.nc", &data("turn.nc"));
    let port = d.path("port").display().to_string();
    let o = d.run(&[
        "dnc",
        "p.nc",
        "--control",
        "fanuc-0i-t",
        "--port",
        &port,
        "--start-at",
        "5",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("not yet written for turning programs"),
        "{}",
        stderr(&o)
    );
    assert!(!d.path("port").exists(), "nothing sent");
}

/// The resolved fanuc0itd output of `src` from X200 Z100 (a diameter, as every X a user gives on a
/// diameter lathe), without its envelope, one line a block.
fn fanuc_lathe_text(src: &str, extra: &[&str]) -> Result<String, String> {
    let d = Dir::new();
    d.file("p.nc", src);
    let mut args = vec![
        "run",
        "p.nc",
        "--dialect",
        "fanuc0itd",
        "--resolve",
        "--start-point",
        "X200 Z100",
        "-o",
        "out.nc",
        "--verify",
    ];
    args.extend_from_slice(extra);
    let o = d.run(&args);
    if !o.status.success() {
        return Err(stderr(&o));
    }
    Ok(d.read("out.nc")
        .lines()
        .filter(|l| !matches!(*l, "%" | "G18" | "G21" | "G99"))
        .collect::<Vec<_>>()
        .join("|"))
}

#[test]
fn what_a_hostile_trial_found_stays_mended() {
    // Each case hand-checked against the rule it names.
    let cases: [(&str, &[&str], &str); 7] = [
        // G50 S is the clamp, not the S of a later G96 alone (0i-TD: S keeps its value).
        (
            "G99\nG97 S500 M3\nG0 X100. Z2.\nG50 S3000\nG96\nG1 Z-10. F0.2\nM30\n",
            &[],
            "S500|M3|G0 X100. Z2.|G50 S3000|G96 S500|G1 Z-10. F0.2|M30",
        ),
        // G50 U W: the position becomes where the tool stands plus U W (52+(-10)... from the set
        // X100 Z50: X90 Z40), so X0 Z0 is 90 and 40 below the tool: X-38 Z-38 of the G54 frame.
        (
            "G0 X52. Z2.\nG50 X100. Z50.\nG50 U-10. W-10.\nG0 X0. Z0.\nM30\n",
            &[],
            "G0 X52. Z2.|X-38. Z-38.|M30",
        ),
        // G53's X is a diameter too.
        (
            "G0 X52. Z2.\nG53 X100. Z100.\nM30\n",
            &[],
            "G0 X52. Z2.|G53 G0 X100. Z100.|M30",
        ),
        // A frame change respells X and Z, never a Y.
        (
            "G0 X40. Z2.\nG10 L2 P1 Z-100.\nG0 X40. Z0.\nM30\n",
            &["-q"],
            "G0 X40. Z2.|X40. Z0.|M30",
        ),
        // G70 runs from where the tool stands (its first block names X only: Z stays at Z5).
        (
            "G99 F0.1\nG0 X52. Z2.\nG71 U4. R0.5\nG71 P10 Q20 U0.4 W0.1 F0.3\nN10 G0 X40.\nG1 Z-20.\nN20 X52.\nG0 X60. Z5.\nG70 P10 Q20\nM30\n",
            &[],
            "G0 X52. Z2.|X44.|G1 Z-19.9 F0.3|G0 X45. Z-19.4|Z2.|X40.4 Z2.1|G1 Z-19.9|X52.4|G0 X52. Z2.|X60. Z5.|X40.|G1 Z-20.|X52.|G0 X60. Z5.|M30",
        ),
        // The same numbers read again (a loop, a subprogram): the profile after the cycle is the
        // one cut, and its blocks are not run as moves.
        (
            "G99\nG0 X52. Z2.\nG71 U4. R0.5\nG71 P10 Q20 F0.3\nN10 G0 X40.\nN20 G1 Z-20.\nG0 X52. Z2.\nG71 P10 Q20 F0.3\nN10 G0 X30.\nN20 G1 Z-10.\nM30\n",
            &[],
            // Levels 4 apart in radius (8 in X): X44 for the first; X44 and X36 for the second,
            // each then along its own profile (X40, then X30).
            "G0 X52. Z2.|X44.|G1 Z-20. F0.3|G0 X45. Z-19.5|Z2.|X40.|G1 Z-20.|G0 X52. Z2.|X44.|G1 Z-10.|G0 X45. Z-9.5|Z2.|X36.|G1 Z-10.|G0 X37. Z-9.5|Z2.|X30.|G1 Z-10.|G0 X52. Z2.|M30",
        ),
        // System B: the output's codes are system B's (G95 feed per revolution).
        (
            "G95\nG0 X30. Z2.\nG32 Z-20. F1.5\nM30\n",
            &["--gcode-system", "b"],
            "G95|G0 X30. Z2.|G32 Z-20. F1.5|M30",
        ),
    ];
    for (src, extra, want) in cases {
        assert_eq!(fanuc_lathe_text(src, extra).as_deref(), Ok(want), "{src}");
    }
    let refused: [(&str, &str); 8] = [
        ("G0 X52. Z2.\nG1 Z-20.\nM30\n", "alarm 0011]: feed zero"),
        (
            "G0 X52. Z2.\nG71 U2. R0.5\nG71 P10 Q20 U0.4 F0.3\nN10 G0 X20.\nG1 Z-20.\nX52.\n",
            "the program ends inside the profile N10–N20",
        ),
        (
            // Once refused as not resolved; now a corner R1 whose next move goes the wrong way.
            "G0 X40. Z2.\nG1 Z-20. R1. F0.1\nX30.\nM30\n",
            "MISSING MOVE AFTER CNR/CHF",
        ),
        ("G0 X40. Z2. C90.\nM30\n", "has no C axis"),
        (
            "G0 X30. Z2.\nG32 Z-20. F3. Q90000\nM30\n",
            "multi-start thread",
        ),
        (
            "G0 X52. Z2.\nG71 U2. R-1.\nG71 P10 Q20 F0.3\nN10 G0 X20.\nN20 G1 Z-20.\nM30\n",
            "the retract R-1 is negative",
        ),
        (
            "G0 X30. Z2.\nG71 U2. R0.5\nG71 P10 Q20 F0.3\nN10 G0 X20.\nG1 Z-20.\nN20 X52.\nM30\n",
            "lies inside the profile",
        ),
        (
            "G0 X26. Z5.\nG76 P020099 Q100 R0.05\nG76 X18.16 Z-20. P920 Q400 F1.5\nM30\n",
            "is one of 80, 60, 55, 30, 29, 00",
        ),
    ];
    for (src, what) in refused {
        let e = fanuc_lathe_text(src, &[]).expect_err(src);
        assert!(e.contains(what), "{src}: {e}");
    }
    // --verify catches a feed per revolution turned into a feed per minute.
    let d = Dir::new();
    d.file("p.nc", &data("turn.nc"));
    let args = [
        "run",
        "p.nc",
        "--dialect",
        "fanuc0itd",
        "--resolve",
        "--start-point",
        "X200 Z200",
    ];
    let mut write = args.to_vec();
    write.extend_from_slice(&["-o", "out.nc"]);
    assert!(d.run(&write).status.success());
    d.file("bad.nc", &d.read("out.nc").replacen("G99\n", "G98\n", 1));
    let mut check = args.to_vec();
    check.extend_from_slice(&["--verify-file", "bad.nc"]);
    let o = d.run(&check);
    assert_eq!(o.status.code(), Some(7), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("the feed is read as feed per minute"),
        "{}",
        stderr(&o)
    );
    // A lathe's options without a lathe.
    let o = d.run(&["run", "p.nc", "--gcode-system", "b", "-o", "x.nc"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn the_plot_outlines_the_stock_with_x_as_the_program_writes_it() {
    // `--stock` is XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX; on a diameter lathe its X is a diameter, as the
    // program's: the box 0..50 there is the box 0..25 on a radius lathe running the same path.
    let d = Dir::new();
    d.file("dia.nc", "G0 X60. Z2.\nG1 X40. Z0 F0.2\nZ-30.\nX60.\nM30\n");
    d.file("rad.nc", "G0 X30. Z2.\nG1 X20. Z0 F0.2\nZ-30.\nX30.\nM30\n");
    // The start point's X is the program's kind of X too: a diameter of 200 where the radius
    // lathe says 100.
    let plot = |name: &str, extra: &[&str]| {
        let start = if name == "dia.nc" {
            "X200 Z100"
        } else {
            "X100 Z100"
        };
        let mut args = vec![
            "plot",
            name,
            "--machine",
            "lathe",
            "--start-point",
            start,
            "-o",
            "p.svg",
        ];
        args.extend_from_slice(extra);
        let o = d.run(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        d.read("p.svg")
    };
    let diameter = plot("dia.nc", &["--stock", "0,0,-40,50,0,0"]);
    let radius = plot(
        "rad.nc",
        &["--stock", "0,0,-40,25,0,0", "--lathe-x", "radius"],
    );
    assert_eq!(diameter, radius);
    assert!(diameter.contains("\nstock\n</text>"), "the legend");
    let plain = plot("dia.nc", &[]);
    assert!(!plain.contains("stock"), "no stock, no outline");
    let grey = |svg: &str| svg.matches("#969696").count();
    assert_eq!(
        grey(&diameter) - grey(&plain),
        13,
        "twelve edges and the legend's line"
    );
}

#[test]
fn chamfering_and_corner_r_move_as_worked_out_by_hand() {
    // 0i-TD "Chamfering and corner R": `X20. K-1.` goes along X to the corner X20 (radius 10) and
    // chamfers 1 (a radius) towards -Z, where the next block goes; `Z-20. R2.` rounds the corner
    // at Z-20 by R2 towards +X; `C` chamfers either way. From X16 Z0 (radius 8):
    //   X18. (1 before the corner), X20. Z-1., Z-18. (2 before the next corner), an arc of R2 about
    //   (x 12, z -18) to X24. Z-20. (clockwise seen from +Y: G2), X30.
    let src = "G0 X16. Z2.\nG1 Z0 F0.2\nX20. K-1.\nZ-20. R2.\nX30.\nG0 X40. Z2.\n\
               G1 X20. Z0 F0.2\nZ-10. C-1.\nX14.\nM30\n";
    for engine in ["interp", "jit"] {
        let got = fanuc_lathe_moves(src, &["--engine", engine]);
        assert_moves(
            &got,
            &[
                (0, 16.0, 2.0),
                (1, 16.0, 0.0),
                (1, 18.0, 0.0),
                (1, 20.0, -1.0),
                (1, 20.0, -18.0),
                (2, 24.0, -20.0),
                (1, 30.0, -20.0),
                (0, 40.0, 2.0),
                (1, 20.0, 0.0),
                (1, 20.0, -9.0),
                (1, 18.0, -10.0),
                (1, 14.0, -10.0),
            ],
            engine,
        );
    }
    // The literal output keeps the words for the control, and reads them back as the same moves.
    let d = Dir::new();
    d.file("p.nc", src);
    let o = d.run(&[
        "run",
        "p.nc",
        "--control",
        "fanuc-0i-t",
        "--start-point",
        "X100 Z100",
        "-o",
        "out.nc",
        "--verify",
    ]);
    assert!(
        o.status.success() && stderr(&o).contains("verified:"),
        "{}",
        stderr(&o)
    );
    let out = d.read("out.nc");
    assert!(
        out.contains("\nX20. K-1.\nZ-20. R2.\n") && out.contains("\nZ-10. C-1.\n"),
        "{out}"
    );
    let bad: [(&str, &str); 5] = [
        ("Z-10. C-1.\nX24.\n", "MISSING MOVE AFTER CNR/CHF"),
        ("Z-10. C-1.\nG0 X14.\n", "CODE IS NOT G01 AFTER CHF/CNR"),
        ("Z-10. C-1.\nX14. Z-12.\n", "MISSING MOVE AFTER CNR/CHF"),
        ("X24. Z-5. C1.\nZ-8.\n", "NO TAPER ALLOWED AFTER CHF/CNR"),
        ("Z-10. I1. R1.\nX24.\n", "TOO MANY ADDRESS COMMANDS"),
    ];
    for (tail, what) in bad {
        let e = fanuc_lathe_text(&format!("G0 X20. Z2.\nG1 Z0 F0.2\n{tail}M30\n"), &[])
            .expect_err(tail);
        assert!(e.contains(what) && e.contains("p.nc:"), "{tail}: {e}");
    }
    // In a profile they are made when the profile is worked out. G70 from X42 Z2 (radius 21):
    // X20., Z-18. (2 before the corner), the arc of R2 about (x 12, z -18) to X24. Z-20., X28. (1
    // before the next corner, a radius), X30. Z-21., Z-40., back to the start at rapid.
    let finish = "G0 X42. Z2.\nG70 P10 Q20\nN10 G0 X20.\nG1 Z-20. R2. F0.2\nX30. K-1.\n\
                  N20 Z-40.\nM30\n";
    for engine in ["interp", "jit"] {
        let got = fanuc_lathe_moves(finish, &["--engine", engine]);
        assert_moves(
            &got,
            &[
                (0, 42.0, 2.0),
                (0, 20.0, 2.0),
                (1, 20.0, -18.0),
                (2, 24.0, -20.0),
                (1, 28.0, -20.0),
                (1, 30.0, -21.0),
                (1, 30.0, -40.0),
                (0, 42.0, 2.0),
            ],
            engine,
        );
    }
    // G71 roughs to the same corners: its pass at X24. (radius 12) stops on the arc moved by the
    // allowance (centre x 12.2, z -17.9): z = -17.9 - sqrt(4 - 0.04) = -19.89; its pre-finishing
    // pass is the profile moved by the allowance. Literal output passes the words on.
    let cycle = "G0 X42. Z2.\nG71 U1. R0.5\nG71 P10 Q20 U0.4 W0.1 F0.3\nN10 G0 X20.\n\
                 G1 Z-20. R2.\nX30. K-1.\nN20 Z-40.\nG70 P10 Q20\nM30\n";
    let text = fanuc_lathe_text(cycle, &[]).expect("resolved");
    assert!(text.contains("|X24.|G1 Z-19.89|"), "{text}");
    assert!(
        text.contains("|G2 X24.4 Z-19.9 K0. I2.|G1 X28.4|X30.4 Z-20.9|Z-39.9|"),
        "{text}"
    );
    let d = Dir::new();
    d.file("p.nc", cycle);
    let o = d.run(&[
        "run",
        "p.nc",
        "--control",
        "fanuc-0i-t",
        "--start-point",
        "X100 Z100",
        "-o",
        "out.nc",
        "--verify",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(d.read("out.nc").contains("\nG1 Z-20. R2.\nX30. K-1.\n"));
    for (profile, what) in [
        (
            "N10 G0 X20.\nG1 Z-20. R2. F0.2\nN20 X30. Z-25.\n",
            "must move along X (U) only, towards +",
        ),
        (
            "N10 G0 X20.\nN20 G1 Z-20. R2. F0.2\n",
            "the next block must be one",
        ),
        (
            "N10 G0 X20.\nG1 Z-20. R30. F0.2\nN20 X30.\n",
            "MISSING MOVE VALUE IN CHF/CNR",
        ),
    ] {
        let e = fanuc_lathe_text(&format!("G0 X42. Z2.\nG70 P10 Q20\n{profile}M30\n"), &[])
            .expect_err(profile);
        assert!(e.contains(what), "{profile}: {e}");
    }
}

#[test]
fn a_lathes_tool_offsets_read_as_the_0i_td_numbers_them() {
    // 0i-TD system variables of the tool offsets (geometry and wear): offset 3 at #2003 X wear,
    // #2103 Z wear, #2203 nose radius wear, #2303 tip, #2703 X geometry, #2803 Z geometry, #2903
    // nose radius geometry, and at #10003 … #17003 (no #14003) the same. Their sum here:
    // 0.02 - 0.01 + 0.01 + 3 - 120.5 - 230.25 + 0.4 = -347.33, so both words are 52.67.
    let d = Dir::new();
    let offsets = d.file(
        "off.toml",
        "[tool.3]\nx = -120.5\nz = -230.25\nx_wear = 0.02\nz_wear = -0.01\n\
         radius = 0.4\nradius_wear = 0.01\ntip = 3\n",
    );
    let offsets = offsets.to_string_lossy().into_owned();
    let src = "#1=#2003+#2103+#2203+#2303+#2703+#2803+#2903\n\
               #2=#10003+#11003+#12003+#13003+#15003+#16003+#17003\n\
               G0 X[#1+400.] Z[#2+400.]\nG10 P3 R0.8 Q2\nG0 X[#2903*100] Z[#2303+#2203]\nM30\n";
    // G10 P3 sets the wear: the geometry stays 0.4, the tip is 2, the wear 0.8.
    for engine in ["interp", "jit"] {
        let got = fanuc_lathe_moves(src, &["--offsets", &offsets, "--engine", engine]);
        assert_moves(&got, &[(0, 52.67, 52.67), (0, 40.0, 2.8)], engine);
    }
    // Literal output passes G10 on (P and Q whole numbers); a flat program cannot set X Z.
    let o = Dir::new();
    o.file("p.nc", src);
    let r = o.run(&[
        "run",
        "p.nc",
        "--control",
        "fanuc-0i-t",
        "--offsets",
        &offsets,
        "-o",
        "out.nc",
    ]);
    assert!(r.status.success(), "{}", stderr(&r));
    assert!(
        o.read("out.nc").contains("\nG10 P3 R0.8 Q2\n"),
        "{}",
        o.read("out.nc")
    );
    for (src, what) in [
        (
            "#2001=0.1\nM30\n",
            "the X wear of a lathe's tool offset is the control's register",
        ),
        (
            "G10 P10003 X1.\nM30\n",
            "G10 P X Z: the X and Z of a lathe's tool offset",
        ),
        (
            "G10 P3 Q12\nM30\n",
            "the imaginary tool nose direction is 0 to 9",
        ),
        (
            "#1=#2065\nM30\n",
            "#2065: not a tool offset variable of a lathe",
        ),
    ] {
        let e = fanuc_lathe_text(src, &[]).expect_err(src);
        assert!(e.contains(what), "{src}: {e}");
    }
}

#[test]
fn tool_calls_are_written_in_each_controls_words() {
    // T0101 is tool 01 with offset 01 (0i-TD "Tool function"). LinuxCNC changes tools by M6 and
    // applies a tool's offsets by G43 (H for another tool's); Sinumerik calls T and edge D.
    let src = "T0101\nG0 X50. Z2.\nT0100\nG0 X60. Z5.\nT0302\nG0 X50. Z2.\nM30\n";
    let d = Dir::new();
    d.file("p.nc", src);
    for (dialect, want) in [
        ("linuxcnc", "T1 M6 G43|G49|T3 M6 G43 H2"),
        ("sinumerik802d", "T1 D1|T1 D0|T3 D2"),
        ("fanuc0itd", "T0101|T0100|T0302"),
    ] {
        let o = d.run(&[
            "run",
            "p.nc",
            "--dialect",
            dialect,
            "--machine",
            "lathe",
            "--resolve",
            "--start-point",
            "X100 Z100",
            "-o",
            "out.nc",
            "--verify",
        ]);
        assert!(o.status.success(), "{dialect}: {}", stderr(&o));
        let calls: Vec<String> = d
            .read("out.nc")
            .lines()
            .map(|l| {
                l.split_whitespace()
                    .filter(|w| !w.starts_with('N'))
                    .collect::<Vec<_>>()
                    .join(" ")
            })
            .filter(|l| l.starts_with('T') || l.starts_with("G49") || l.starts_with("G43"))
            .collect();
        assert_eq!(calls.join("|"), want, "{dialect}");
    }
}

#[test]
fn g70_runs_the_s_and_t_of_its_profile() {
    // 0i-TD: F, S and T in the blocks ns–nf are ignored by G71–G73 and in force in G70. The S
    // under G96 is a surface speed; a control without CSS gets the rpm per move from it:
    // 1000 * 200 / (pi * 20) = 3183 clamped by G50 S2000 at X20, 1000 * 200 / (pi * 42) = 1516.
    let src = "G50 S2000\nG96 S150 M3\nG0 X42. Z2.\nG70 P10 Q20\nN10 G0 X20. S200 T0202\n\
               G1 Z-20. F0.2\nN20 X42.\nG0 X100.\nM30\n";
    let text = fanuc_lathe_text(src, &[]).expect("resolved");
    assert!(
        text.contains("G0 X42. Z2.|T0202|G96 S200|X20.|G1 Z-20. F0.2|X42.|G0 Z2.|"),
        "{text}"
    );
    let d = Dir::new();
    d.file("p.nc", src);
    let o = d.run(&[
        "run",
        "p.nc",
        "--dialect",
        "mayak600t",
        "--start-point",
        "X100 Z100",
        "-o",
        "out.nc",
        "--verify",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = d.read("out.nc");
    let words: Vec<&str> = out
        .lines()
        .filter_map(|l| l.split_whitespace().nth(1))
        .collect();
    let at = |w: &str| words.iter().position(|x| *x == w);
    assert!(
        at("T202") < at("X20.") && at("X20.") < at("S2000") && at("S2000") < at("S1516"),
        "{out}"
    );
}

/// The radius of the type II test profile (a shoulder, a round groove, a taper, a step), moved by
/// the allowance U0.4 W0.1, at `z`: the highest where a wall stands on `z`.
fn type_two_radius_at(z: f64) -> f64 {
    let z = z - 0.1;
    let r = if z > -10.0 + 1e-9 {
        10.0
    } else if z >= -15.0 - 1e-9 {
        15.0
    } else if z > -25.0 {
        // The groove: R6 from X30 Z-15 to X30 Z-25, its centre at x = 15 + sqrt(36 - 25).
        15.0 + 11.0_f64.sqrt() - (36.0 - (z + 20.0).powi(2)).sqrt()
    } else if z > -28.0 {
        15.0 + (-25.0 - z) * 2.0 / 3.0
    } else {
        17.0
    };
    r + 0.2
}

#[test]
fn g71_type_ii_cuts_the_pockets_without_entering_the_part() {
    // A type II profile (its first block names X and Z): after the shoulder the level runs over a
    // round groove, which is cut in passes of its own. Invariants, both engines: no feed move
    // enters the profile moved by its allowance; every point of the stock is cut down to within
    // Δd = 1 of it before the pass along the profile; the cycle ends at its start point.
    let src = "G0 X42. Z2.\nG71 U1. R0.5\nG71 P10 Q20 U0.4 W0.1 F0.2\nN10 G0 X20. Z0\n\
               G1 Z-10.\nX30.\nZ-15.\nG2 X30. Z-25. R6.\nG1 X34. Z-28.\nZ-35.\nN20 X42.\nM30\n";
    for engine in ["interp", "jit"] {
        let got = fanuc_lathe_moves(src, &["--engine", engine]);
        assert_eq!(
            got.last().map(|m| (m.1, m.2)),
            Some((42.0, 2.0)),
            "{engine}: back at A"
        );
        let final_in = got
            .iter()
            .rposition(|m| (m.1, m.2) == (20.4, 0.1))
            .expect("the pass along the profile");
        let mut lowest = vec![f64::INFINITY; 349];
        let mut from = (42.0 / 2.0, 2.0);
        for (i, &(g, x, z)) in got.iter().enumerate() {
            let to = (x / 2.0, z);
            if g == 1 {
                let n = ((to.0 - from.0).hypot(to.1 - from.1) * 50.0)
                    .ceil()
                    .max(64.0) as u32;
                for k in 0..=n {
                    let t = f64::from(k) / f64::from(n);
                    let (r, zz) = (from.0 + (to.0 - from.0) * t, from.1 + (to.1 - from.1) * t);
                    if (-34.9..=0.1).contains(&zz) {
                        // On a wall (a step in Z) the lower side bounds the part.
                        let h = type_two_radius_at(zz - 1e-6).min(type_two_radius_at(zz + 1e-6));
                        assert!(
                            r >= h - 1e-3,
                            "{engine}: move {i} to X{x} Z{z} enters the part at r {r} z {zz}"
                        );
                    }
                    if i < final_in {
                        let cell = (-zz * 10.0).round();
                        if (0.0..349.0).contains(&cell) {
                            let c = cell as usize;
                            lowest[c] = lowest[c].min(r);
                        }
                    }
                }
            }
            from = to;
        }
        for (c, low) in lowest.iter().enumerate() {
            let z = -(c as f64) / 10.0;
            let left = low - type_two_radius_at(z);
            assert!(
                left <= 1.0 + 1e-6,
                "{engine}: at Z{z} {left} of stock is left (Δd is 1)"
            );
        }
    }
    // A type II profile must still go one way along Z.
    let e = fanuc_lathe_text(
        "G0 X42. Z2.\nG71 U1. R0.5\nG71 P10 Q20 F0.2\nN10 G0 X20. Z0\nG1 Z-10.\nX30. Z-5.\nN20 Z-20.\nM30\n",
        &[],
    )
    .expect_err("Z turns back");
    assert!(e.contains("turns back along Z"), "{e}");
}

/// The face of the G72 type II test profile, moved by the allowance U0.2 W0.1, at radius `r`:
/// Z-10 from X80 to X60, up to Z-5 at X50, Z-5 to X40, down into a pocket at Z-8 from X30 to X20.
fn type_two_face_at(r: f64) -> f64 {
    let r = r - 0.1;
    let z = if r >= 30.0 {
        -10.0
    } else if r >= 25.0 {
        -10.0 + (30.0 - r)
    } else if r >= 20.0 {
        -5.0
    } else if r >= 15.0 {
        -5.0 - (20.0 - r) * 3.0 / 5.0
    } else {
        -8.0
    };
    z + 0.1
}

#[test]
fn g72_type_ii_cuts_the_pockets_of_a_face() {
    // G72 with a type II profile: levels in Z, cuts along X, a pocket in the face beyond a bump.
    // The same invariants as for G71, on the other axes.
    let src = "G0 X82. Z2.\nG72 W1. R0.5\nG72 P10 Q20 U0.2 W0.1 F0.2\nN10 G0 X80. Z-10.\n\
               G1 X60.\nX50. Z-5.\nX40.\nX30. Z-8.\nX20.\nN20 Z2.\nM30\n";
    for engine in ["interp", "jit"] {
        let got = fanuc_lathe_moves(src, &["--engine", engine]);
        assert_eq!(
            got.last().map(|m| (m.1, m.2)),
            Some((82.0, 2.0)),
            "{engine}: back at A"
        );
        let final_in = got
            .iter()
            .rposition(|m| (m.1, m.2) == (80.2, -9.9))
            .expect("the pass along the profile");
        let mut lowest = vec![f64::INFINITY; 300];
        let mut from = (41.0, 2.0);
        for (i, &(g, x, z)) in got.iter().enumerate() {
            let to = (x / 2.0, z);
            if g == 1 {
                let n = ((to.0 - from.0).hypot(to.1 - from.1) * 50.0)
                    .ceil()
                    .max(64.0) as u32;
                for k in 0..=n {
                    let t = f64::from(k) / f64::from(n);
                    let (r, zz) = (from.0 + (to.0 - from.0) * t, from.1 + (to.1 - from.1) * t);
                    if (10.1..=40.1).contains(&r) {
                        let face = type_two_face_at(r - 1e-6).min(type_two_face_at(r + 1e-6));
                        assert!(
                            zz >= face - 1e-3,
                            "{engine}: move {i} to X{x} Z{z} enters the part at r {r} z {zz}"
                        );
                    }
                    if i < final_in {
                        let cell = ((r - 10.1) * 10.0).round();
                        if (0.0..300.0).contains(&cell) {
                            let c = cell as usize;
                            lowest[c] = lowest[c].min(zz);
                        }
                    }
                }
            }
            from = to;
        }
        for (c, low) in lowest.iter().enumerate().skip(1).take(298) {
            let r = 10.1 + c as f64 / 10.0;
            let left = low - type_two_face_at(r);
            assert!(
                left <= 1.0 + 1e-6,
                "{engine}: at radius {r} {left} of stock is left (Δd is 1)"
            );
        }
    }
}

#[test]
fn drilling_cycles_move_as_linuxcnc_drills_their_twin() {
    // Face drilling G83 (pecks of Q, out to R between them) and face boring G85, Fanuc's words (R
    // from the initial level, Z the bottom), against rs274's G17 G83 / G85 of the twin (R a level,
    // G98: back to the initial level).
    let want = moves_of_list(&data("drill.moves"));
    assert_eq!(want.len(), 16, "the trace's moves");
    for engine in ["interp", "jit"] {
        let d = Dir::new();
        let out = linuxcnc_lathe(&d, "drill", engine);
        assert_moves_as_twin(&out, &want, engine);
    }
    // Side drilling G87 along X at Z, worked out by hand: from X40. (radius 20) R-3. is the R
    // level at radius 17 (X34.), the bottom X10., P500 a dwell of 0.5 s, back to X40.; the next
    // hole at Z-20. likewise.
    let src = "G97 S800 M3\nG0 X40. Z-10.\nG87 X10. R-3. P500 F0.1\nZ-20.\nG80\nM30\n";
    for engine in ["interp", "jit"] {
        let got = fanuc_lathe_moves(src, &["--engine", engine]);
        assert_moves(
            &got,
            &[
                (0, 40.0, -10.0),
                (0, 34.0, -10.0),
                (1, 10.0, -10.0),
                (0, 40.0, -10.0),
                (0, 40.0, -20.0),
                (0, 34.0, -20.0),
                (1, 10.0, -20.0),
                (0, 40.0, -20.0),
            ],
            engine,
        );
    }
    let text = fanuc_lathe_text(src, &[]).expect("resolved");
    assert!(text.contains("|G4 X0.5|"), "{text}");
}

#[test]
fn what_the_second_lathe_trial_found_stays_mended() {
    // A `/` block under compensation went out with its neighbour's slash: refused in resolved
    // output (on the mill too), expanded with the switch on or passed on literally.
    let d = Dir::new();
    let offsets = d.file("o.toml", "[tool.1]\nradius = 0.8\ntip = 3\n");
    let offsets = offsets.to_string_lossy().into_owned();
    let bd = "T0101\nG0 X60. Z5.\nG42 G0 X20. Z2.\nG1 Z-10. F0.2\n/G1 X30.\n/G1 Z-20.\nG1 X40. Z-25.\nG40 G0 X60.\nM30\n";
    let e = fanuc_lathe_text(bd, &["--offsets", &offsets]).expect_err("a / block under G42");
    assert!(
        e.contains("p.nc:5:") && e.contains("a block-delete block (/)"),
        "{e}"
    );
    let on = fanuc_lathe_text(bd, &["--offsets", &offsets, "--block-delete"]).expect("skipped");
    assert!(!on.contains('/') && !on.contains("X30."), "{on}");
    d.file("m.nc", "G90 G0 X-10. Y-10. Z5.\nG1 Z-2. F100.\nG41 D1 G1 X0 Y0\nG1 Y50.\n/G1 X50.\nG1 Y0\nG40 G1 X-10. Y-10.\nM30\n");
    d.file("mill.toml", "[tool.1]\nradius = 5.0\n");
    let o = d.run(&[
        "run",
        "m.nc",
        "--resolve",
        "--offsets",
        "mill.toml",
        "--start-point",
        "X0 Y0 Z10",
    ]);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(stderr(&o).contains("m.nc:5:"), "{}", stderr(&o));
    // A negative nose radius, and the mill's G10 L10–L13, on a lathe.
    let neg = d.file(
        "neg.toml",
        "[tool.1]\nradius = 0.4\nradius_wear = -0.6\ntip = 3\n",
    );
    let neg = neg.to_string_lossy().into_owned();
    let e = fanuc_lathe_text(
        "T0101\nG0 X60. Z5.\nG42 G1 X20. Z0 F0.2\nG40 G0 X60.\nM30\n",
        &["--offsets", &neg],
    )
    .expect_err("negative");
    assert!(e.contains("below zero"), "{e}");
    let e = fanuc_lathe_text("G10 L10 P1 R5.\nM30\n", &[]).expect_err("L10");
    assert!(e.contains("a lathe's offsets are G10 P X Z R Q"), "{e}");
    // Offsets that are not numbers.
    d.file("nan.toml", "[tool.1]\nx = nan\n");
    d.file("p.nc", "G0 X20. Z2.\nM30\n");
    let o = d.run(&[
        "run",
        "p.nc",
        "--control",
        "fanuc-0i-t",
        "--offsets",
        "nan.toml",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("tool.1.x: not a finite number"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_corner_arc_under_linuxcnc_compensation_moves_at_its_blocks_feed() {
    // rs274 queues a block's F with its moves: the arc round a convex corner belongs to the block
    // after the corner and moves at its F (the trial's `fchg2` twin: F0.05 and F0.07, not the
    // F0.2 and F0.3 before them); a first F on that block is no F0 (which rs274 refuses).
    let d = Dir::new();
    let offsets = d.file("o.toml", "[tool.1]\nradius = 0.8\ntip = 3\n");
    let offsets = offsets.to_string_lossy().into_owned();
    d.file(
        "f.nc",
        "T0101\nG97 S1000 M3\nG0 X60. Z5.\nG42 G0 X20. Z2.\nG1 Z0 F0.2\nG1 X30. Z-10.\nG1 Z-20. F0.05\n\
         G1 X40. Z-25. F0.3\nG1 Z-30. F0.07\nG40 G0 X60. Z5.\nM30\n",
    );
    d.file(
        "face.nc",
        "T0101\nG0 X60. Z5.\nG42 G0 X52. Z0\nG1 X0 F0.1\nG0 Z3.\nG40 G0 X60.\nM30\n",
    );
    for engine in ["interp", "jit"] {
        let run = |name: &str| {
            let o = d.run(&[
                "run",
                name,
                "--dialect",
                "linuxcnc",
                "--machine",
                "lathe",
                "--comp-style",
                "linuxcnc",
                "--start-point",
                "X0 Z0",
                "--offsets",
                &offsets,
                "--engine",
                engine,
                "-o",
                "-",
            ]);
            assert!(o.status.success(), "{}", stderr(&o));
            stdout(&o)
        };
        let out = run("f.nc");
        let arcs: Vec<&str> = out.lines().filter(|l| l.starts_with("G3")).collect();
        assert_eq!(arcs.len(), 2, "{out}");
        assert!(
            arcs[0].ends_with(" F0.05") && arcs[1].ends_with(" F0.07"),
            "{out}"
        );
        let out = run("face.nc");
        assert!(!out.contains(" F0\n") && out.contains(" F0.1\n"), "{out}");
    }
}
