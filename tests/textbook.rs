//! The NCT textbook (copied into `tests/textbook/` from the shared corpus): every exercise with expected
//! motion, read as NCT (`--input nct`), resolved with LinuxCNC's compensation, the tool (radius 2,
//! length 0) set by `G10 L12 P1 R2.` and `G10 L10 P1 R0` after the O line, gives the motion LinuxCNC
//! made from its twin (`NN-*.moves`, see `tests/kernel/regenerate.sh` for how such files are made),
//! within 0.0011 mm, on both engines. The other exercises expand; the subprograms run through their
//! callers; the Fanuc compensation style and the errors are checked by hand.

use crate::common;

use common::{Expansion, Failure, Setup, diff_moves, expand_full, moves_of_flat, moves_of_list};
use fmsvm_compiler::{Options, Syntax};
use fmsvm_kernel::CompStyle;
use fmsvm_kernel::Settings;
use fmsvm_vm::{Limits, RunOptions};

const TOL: f64 = 0.0011;

fn dir() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/tests/textbook/").to_string()
}

fn read(name: &str) -> String {
    std::fs::read_to_string(format!("{}{name}", dir())).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Every file of the folder ending in `ext`, sorted.
fn files(ext: &str) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir())
        .expect("tests/textbook")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(ext))
        .collect();
    v.sort();
    v
}

/// The four subprograms the main programs call (a library, as `--lib tests/textbook`).
const SUBPROGRAMS: [&str; 4] = [
    "15-O7053-pocket-subprogram.nc",
    "24-O7076-hole-column-subprogram.nc",
    "31-O7091-gear-tooth-subprogram.nc",
    "35-O7102-bolt-circle-quadrant-subprogram.nc",
];

/// The program with the tool set in it: `G10 L12 P1 R2.` and `G10 L10 P1 R0` after the O line.
fn with_tool(src: &str) -> String {
    let mut out = String::new();
    let mut done = false;
    for line in src.lines() {
        out.push_str(line);
        out.push('\n');
        if !done && line.starts_with('O') {
            out.push_str("G10 L12 P1 R2.\nG10 L10 P1 R0\n");
            done = true;
        }
    }
    out
}

fn nct(style: CompStyle) -> (Setup, Options) {
    (
        Setup {
            resolve: Some(Settings {
                comp_style: style,
                arc_intersections: true,
                // LinuxCNC's start, which the held traces assume (declared, as --start-point).
                start_point: [0.0; 6],
                // The textbook's G51 P2 is ×2, as `--input nct` reads it.
                scaling_unit: 0.0,
                ..Settings::default()
            }),
            ..Setup::default()
        },
        Options {
            syntax: Syntax::NCT,
            ..Options::default()
        },
    )
}

fn run_with(src: &str, setup: Setup, options: Options) -> Result<Expansion, Failure> {
    let lib: Vec<(String, String)> = SUBPROGRAMS
        .iter()
        .map(|n| (n.to_string(), read(n)))
        .collect();
    let lib: Vec<(&str, &str)> = lib.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
    expand_full(src, &lib, setup, RunOptions::default(), options)
}

fn resolved(name: &str, style: CompStyle) -> Expansion {
    let (setup, options) = nct(style);
    run_with(&with_tool(&read(name)), setup, options).unwrap_or_else(|f| panic!("{name}: {f:?}"))
}

#[test]
fn every_exercise_with_expected_motion_equals_linuxcnc() {
    let mut checked = 0;
    for moves in files(".moves") {
        let name = moves.trim_end_matches(".moves");
        let e = resolved(&format!("{name}.nc"), CompStyle::LinuxCnc);
        let want = moves_of_list(&read(&moves));
        if let Err(d) = diff_moves(&moves_of_flat(&e.text), &want, TOL) {
            panic!("{name}: {d}\nresolved output:\n{}", e.text);
        }
        checked += 1;
    }
    assert_eq!(checked, 28, "every textbook .moves file");
}

#[test]
fn the_exercises_without_expected_motion_expand() {
    for name in [
        "13-O7051-contour-chamfer-fillet.nc",
        "23-O7075-bolt-circle-g52.nc",
        "33-O7093-gear-while-g68.nc",
        "34-O7101-mirrored-bolt-circles.nc",
    ] {
        for style in [CompStyle::LinuxCnc, CompStyle::Fanuc] {
            let e = resolved(name, style);
            assert!(moves_of_flat(&e.text).len() > 10, "{name}");
        }
    }
}

/// 23 is the bolt circle of 21 about the G52 zero X60 Y60; 33 the gear of 32 by a WHILE loop (they
/// differ only in the last move, G0 G40 in 32, G1 G40 in 33); 34 drills 20 times at 18 points.
#[test]
fn the_exercises_without_expected_motion_agree_with_their_siblings() {
    let holes = |e: &Expansion| -> Vec<[f64; 3]> {
        moves_of_flat(&e.text)
            .iter()
            .filter(|m| m.kind == 1 && (m.end[2] + 10.0).abs() < 1e-6)
            .map(|m| m.end)
            .collect()
    };
    let b21 = holes(&resolved("21-O7073-bolt-circle.nc", CompStyle::LinuxCnc));
    let b23 = holes(&resolved(
        "23-O7075-bolt-circle-g52.nc",
        CompStyle::LinuxCnc,
    ));
    assert_eq!(b21.len(), 36);
    assert_eq!(b23.len(), 36);
    for (a, b) in b21.iter().zip(&b23) {
        assert!((a[0] + 60.0 - b[0]).abs() < 1e-3 && (a[1] + 60.0 - b[1]).abs() < 1e-3);
    }
    let g32 = moves_of_flat(&resolved("32-O7092-gear-main-m98-g68.nc", CompStyle::LinuxCnc).text);
    let g33 = moves_of_flat(&resolved("33-O7093-gear-while-g68.nc", CompStyle::LinuxCnc).text);
    assert_eq!(g32.len(), g33.len());
    let n = g32.len();
    assert!(diff_moves(&g32[..n - 2], &g33[..n - 2], TOL).is_ok());
    let h34 = holes(&resolved(
        "34-O7101-mirrored-bolt-circles.nc",
        CompStyle::LinuxCnc,
    ));
    assert_eq!(h34.len(), 20);
    let mut distinct: Vec<[i64; 2]> = h34
        .iter()
        .map(|p| {
            [
                (p[0] * 1000.0).round() as i64,
                (p[1] * 1000.0).round() as i64,
            ]
        })
        .collect();
    distinct.sort();
    distinct.dedup();
    assert_eq!(distinct.len(), 18);
}

#[test]
fn a_subprogram_run_alone_stops_at_a_limit() {
    let (setup, options) = nct(CompStyle::LinuxCnc);
    let run = RunOptions {
        limits: Limits {
            max_blocks: 5000,
            ..Limits::default()
        },
        ..RunOptions::default()
    };
    for name in SUBPROGRAMS {
        match expand_full(
            &with_tool(&read(name)),
            &[],
            setup.clone(),
            run,
            options.clone(),
        ) {
            Err(Failure::Limit(m)) => assert!(m.contains("5000 output blocks"), "{name}: {m}"),
            Err(Failure::Alarm(n, m, _)) => {
                // 24 steps X by 10 on every pass: it leaves the 8 digits before the block limit.
                assert_eq!((name, n), (SUBPROGRAMS[1], 3), "{m}")
            }
            other => panic!("{name}: {other:?}"),
        }
    }
}

/// Fanuc's compensation, by hand (tool radius 2). Exercise 9: the rectangle X±100 Y±50 under G42 from
/// X-120 Y-70: start-up at the intersection of the start-up line's offset with Y-52, convex
/// corners at the intersections X±102 Y±52, cancel at the intersection of X-102 with the cancel line's
/// offset (Y-49.172). Exercise 10 is the same contour with `,R0` at every corner: Fanuc's compensation
/// then goes round each convex corner on an arc of the tool radius about it, so its moves are the
/// straight sides offset by 2 joined by R2 arcs (as LinuxCNC's compensation does at every convex corner).
#[test]
fn fanuc_compensation_of_exercises_9_and_10_by_hand() {
    let e9 = resolved("09-O7032-rectangle-comp.nc", CompStyle::Fanuc);
    let body = e9.body();
    let at = body
        .iter()
        .position(|l| l.starts_with("G1 Z-10."))
        .expect("plunge");
    assert_eq!(
        body[at + 1..at + 7],
        [
            "X-99.172 Y-52. F50.",
            "X102.",
            "Y52.",
            "X-102.",
            "Y-49.172",
            "X-120. Y-70."
        ]
    );
    let e10 = resolved("10-O7033-rectangle-r0-corners.nc", CompStyle::Fanuc);
    let m = moves_of_flat(&e10.text);
    let arcs: Vec<_> = m.iter().filter(|m| m.kind == 2 || m.kind == 3).collect();
    assert_eq!(arcs.len(), 3, "{}", e10.text);
    for (a, c) in arcs
        .iter()
        .zip([[100.0, -50.0], [100.0, 50.0], [-100.0, 50.0]])
    {
        let centre = a.centre.expect("centre");
        assert!((centre[0] - c[0]).abs() < 1e-3 && (centre[1] - c[1]).abs() < 1e-3);
        assert!(((a.end[0] - c[0]).hypot(a.end[1] - c[1]) - 2.0).abs() < 1e-3);
    }
}

/// Exercise 13 (no expected motion): the G42 contour with `,C10` and `,R20` under Fanuc's compensation.
/// What is known by hand: every arc of the compensated path keeps its radius about its centre, and the
/// `,R20` rounding, offset by the tool radius 2, is an arc of radius 22 (outside the rounding) or 18.
#[test]
fn fanuc_compensation_of_exercise_13_rounds_and_chamfers() {
    let e = resolved("13-O7051-contour-chamfer-fillet.nc", CompStyle::Fanuc);
    let m = moves_of_flat(&e.text);
    // Every rounding arc of the compensated contour: radius 20 ± 2 about its centre.
    let mut from = [0.0f64; 3];
    let mut rounding = 0;
    for mv in &m {
        if let Some(c) = mv.centre {
            let r0 = (from[0] - c[0]).hypot(from[1] - c[1]);
            let r1 = (mv.end[0] - c[0]).hypot(mv.end[1] - c[1]);
            assert!((r0 - r1).abs() < 2e-3, "an arc keeps its radius: {r0} {r1}");
            if (r0 - 22.0).abs() < 2e-3 || (r0 - 18.0).abs() < 2e-3 {
                rounding += 1;
            }
        }
        from = mv.end;
    }
    assert!(rounding >= 1, "the ,R20 corner: {}", e.text);
}

#[test]
fn errors_of_the_nct_constructs() {
    let (setup, options) = nct(CompStyle::LinuxCnc);
    let alarm = |src: &str| match run_with(src, setup.clone(), options.clone()) {
        Err(Failure::Alarm(n, m, _)) => (n, m),
        other => panic!("{src:?}: {other:?}"),
    };
    // A corner too large for its elements.
    let (n, m) = alarm("G1 X10 Y10 F100\nX20 ,R50\nY20\nM30\n");
    assert_eq!(n, 55, "{m}");
    // Circles that do not meet.
    let (n, m) = alarm("G0 X0 Y0\nG3 X10 Y0 R5\nG3 I100 J0 R5 Q1\nG3 X0 Y0 I0 J0 R5\nM30\n");
    assert_eq!(n, 57, "{m}");
    assert!(m.contains("do not meet"), "{m}");
    // A missing Q where the circles meet twice.
    let (n, m) = alarm("G0 X0 Y0\nG3 X10 Y0 R5\nG3 I12 J0 R5\nG3 X17 Y0 I12 J0 R5\nM30\n");
    assert_eq!(n, 57, "{m}");
    assert!(m.contains('Q'), "{m}");
    // NCT words in Fanuc syntax: a compile error that names --input nct.
    match run_with("G81 XI10 Y50 R2 Z-10\n", setup.clone(), Options::default()) {
        Err(Failure::Compile(d)) => {
            let text = format!("{d:?}");
            assert!(text.contains("--input nct"), "{text}");
        }
        other => panic!("{other:?}"),
    }
    match run_with("POPEN31\nPCLOS31\nM30\n", setup, Options::default()) {
        Err(Failure::Compile(d)) => assert!(format!("{d:?}").contains("--input nct")),
        other => panic!("{other:?}"),
    }
}

/// The literal output of an NCT program is Fanuc form: no incremental operator is passed through (it is
/// written as the absolute value it stands for), and read back as Fanuc syntax and resolved it gives the
/// same motion as the NCT program resolved. Arc intersections have no literal Fanuc form (28–30 refuse
/// the literal output with a clear message), nor canned cycles stepped by L with an incremental word
/// (19–26).
#[test]
fn literal_fanuc_form_reads_back_to_the_same_motion() {
    let mut round_trips = 0;
    for name in files(".nc") {
        if SUBPROGRAMS.contains(&name.as_str()) {
            continue;
        }
        let src = with_tool(&read(&name));
        let literal = run_with(
            &src,
            Setup {
                literal_settings: Settings {
                    arc_intersections: true,
                    start_point: [0.0; 6],
                    ..Settings::default()
                },
                ..Setup::default()
            },
            Options {
                syntax: Syntax::NCT,
                ..Options::default()
            },
        );
        let literal = match literal {
            Ok(e) => e,
            Err(Failure::Alarm(0, m, _)) if m.contains("has no Fanuc literal form") => continue,
            Err(f) => panic!("{name}: {f:?}"),
        };
        assert!(
            !literal.text.contains("XI") && !literal.text.contains("YI"),
            "{name}: {}",
            literal.text
        );
        let (setup, _) = nct(CompStyle::LinuxCnc);
        let back = expand_full(
            &literal.text,
            &[],
            setup,
            RunOptions::default(),
            Options::default(),
        )
        .unwrap_or_else(|f| panic!("{name} read back: {f:?}\n{}", literal.text));
        let direct = resolved(&name, CompStyle::LinuxCnc);
        if let Err(d) = diff_moves(
            &moves_of_flat(&back.text),
            &moves_of_flat(&direct.text),
            TOL,
        ) {
            panic!("{name}: {d}");
        }
        round_trips += 1;
    }
    assert!(round_trips >= 20, "{round_trips} programs read back");
}
