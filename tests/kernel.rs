//! The geometry kernel (`--resolve`) against LinuxCNC's interpreter and against hand computation.
//!
//! Data in `tests/kernel/`: `NAME.nc` (a Fanuc program), `NAME.ngc` (its LinuxCNC twin) and `NAME.moves`
//! (the motion `rs274` made of the twin, reduced by `kmoves.py`; `regenerate.sh` remakes them). Every
//! program here is expanded with `--resolve` settings on both engines (`common::expand_full`), and its
//! resolved motion compared with the oracle's within 0.0011 mm. Where LinuxCNC lacks the feature
//! (G68, G51, G51.1, Fanuc's reads of system variables) the expected values are worked out by hand in
//! the comments beside them.

use crate::cli_support;
use crate::common;

use common::{
    Expansion, Failure, Move, Setup, diff_moves, expand_full, moves_of_flat, moves_of_list,
};
use fmsvm_compiler::Options;
use fmsvm_kernel::Settings;
use fmsvm_kernel::frames::Frames;
use fmsvm_vm::RunOptions;

/// The corpus tolerance.
const TOL: f64 = 0.0011;

fn dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/kernel")
}

fn read(rel: &str) -> String {
    let p = dir().join(rel);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Resolving with the default settings.
fn resolving() -> Setup {
    Setup {
        resolve: Some(start0()),
        ..literal()
    }
}

/// The settings every test here runs with: the tool starts where LinuxCNC's interpreter starts, X0
/// Y0 Z0 (A B C 0), and G28 goes to machine zero (LinuxCNC's parameters 5161–5166 at 0): the
/// oracle's traces and the hand-computed positions assume both (declared, as `--start-point` and
/// `--offsets [reference.G28]` do).
fn start0() -> Settings {
    Settings {
        start_point: [0.0; 6],
        ..Settings::default()
    }
}

/// Literal output from the start of `start0`, G28 at machine zero and G54 at machine zero
/// (LinuxCNC's parameters 5221–5226 at 0): a machine position lies in G54 only through a G54 that
/// was declared, as `--offsets [work.G54]` declares it.
fn literal() -> Setup {
    let mut frames = Frames::default();
    frames.reference[0] = [0.0; 6];
    frames.work_set[1] = true;
    Setup {
        literal_settings: start0(),
        frames: Some(frames),
        ..Setup::default()
    }
}

/// Resolving with the given frames loaded before the run (what `--offsets` does).
fn resolving_with(mut frames: Frames) -> Setup {
    if frames.reference[0][0].is_nan() {
        frames.reference[0] = [0.0; 6];
    }
    frames.work_set[1] = true;
    Setup {
        frames: Some(frames),
        ..resolving()
    }
}

/// Expands `src` (with library files) under `setup`, or panics with the failure.
fn run(src: &str, library: &[(&str, &str)], setup: Setup) -> Expansion {
    match expand_full(
        src,
        library,
        setup,
        RunOptions::default(),
        Options::default(),
    ) {
        Ok(e) => e,
        Err(f) => panic!("expansion failed: {f:?}\n{src}"),
    }
}

/// Expands `src` resolved.
fn resolved(src: &str) -> Expansion {
    run(src, &[], resolving())
}

/// The failure of `src` under `setup`.
fn failure(src: &str, setup: Setup) -> Failure {
    match expand_full(src, &[], setup, RunOptions::default(), Options::default()) {
        Ok(e) => panic!("{src:?} ran without an alarm:\n{}", e.text),
        Err(f) => f,
    }
}

/// Resolved output is flat motion: only G0 G1 G2 G3 (and G4, the plane, units, feed mode, G90) —
/// no frame, transform, cycle or compensation code is left for the control. Its first block also
/// cancels what an earlier program may have left (G40 G49 G80) and selects the G54 it is written
/// in: states, not work for the control.
#[track_caller]
fn assert_resolved(text: &str) {
    const ALLOWED: [i64; 11] = [0, 10, 20, 30, 40, 170, 180, 190, 200, 210, 900];
    const START: [i64; 4] = [400, 490, 800, 540];
    let mut first = true;
    for line in text.lines() {
        if line.starts_with('O') || line.starts_with('%') {
            continue;
        }
        let start = std::mem::take(&mut first);
        let words: String = line.split('(').next().unwrap_or("").to_string();
        let mut rest = words.as_str();
        while let Some(at) = rest.find('G') {
            let digits: String = rest[at + 1..]
                .chars()
                .take_while(|c| c.is_ascii_digit() || *c == '.')
                .collect();
            let code = (digits.parse::<f64>().expect("a G code") * 10.0).round() as i64;
            assert!(
                ALLOWED.contains(&code)
                    || code == 940
                    || code == 950
                    || (start && START.contains(&code)),
                "resolved output holds G{digits}: {line}\n{text}"
            );
            rest = &rest[at + 1..];
        }
    }
}

/// Compares the resolved motion of `text` with `want`.
#[track_caller]
fn assert_motion(name: &str, text: &str, want: &[Move]) {
    assert_resolved(text);
    let got = moves_of_flat(text);
    if let Err(d) = diff_moves(&got, want, TOL) {
        panic!("{name}: {d}\nresolved output:\n{text}");
    }
}

/// Runs `NAME.nc` resolved (with `setup` and library files given by name in `tests/kernel/`) and
/// compares its motion with `NAME.moves`.
#[track_caller]
fn pair_with(name: &str, library: &[&str], setup: Setup) -> Expansion {
    let src = read(&format!("{name}.nc"));
    let lib: Vec<(String, String)> = library.iter().map(|l| (l.to_string(), read(l))).collect();
    let lib: Vec<(&str, &str)> = lib.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
    let e = run(&src, &lib, setup);
    let want = moves_of_list(&read(&format!("{name}.moves")));
    assert!(!want.is_empty(), "{name}.moves is empty");
    assert_motion(name, &e.text, &want);
    e
}

#[track_caller]
fn pair(name: &str) -> Expansion {
    pair_with(name, &[], resolving())
}

// ---------------------------------------------------------------------------------------------------
// Work offsets

#[test]
fn g54_to_g59_set_by_g10_l2_switched_and_added_in_g91() {
    pair("offsets-g10-l2");
}

#[test]
fn g54_to_g59_set_by_macro_assignment_with_the_external_offset() {
    pair("offsets-macro");
}

#[test]
fn g54_1_p1_p2_set_by_g10_l20_and_7001() {
    // LinuxCNC has no G54.1: the twin stands its 7th and 8th systems (G59.1, G59.2) in for P1 and
    // P2, and the moves are also worked out here by hand. A point is G54 frame = point + the active
    // offset − G54 (X5 Y5 Z0); a block that leaves an axis out keeps its machine position.
    let e = pair("offsets-g54-1");
    assert_motion(
        "by hand",
        &e.text,
        &[
            // G54 X0 Y0 Z10 from machine zero.
            line(0, 0.0, 0.0, 10.0),
            // P1 = X20 Y30 Z-10: X0 Y0 is machine X20 Y30 → G54 X15 Y25; Z stays at machine 10.
            line(0, 15.0, 25.0, 10.0),
            // X10 Y-10 Z0 of P1 = machine X30 Y20 Z-10 → X25 Y15 Z-10.
            line(1, 25.0, 15.0, -10.0),
            // P2 = #7021-#7023 = X-40 Y15 Z2: X0 Y0 → machine X-40 Y15 → X-45 Y10.
            line(0, -45.0, 10.0, -10.0),
            // #7021 = −30 while P2 is active: X0 Y0 is now machine X-30 → X-35.
            line(1, -35.0, 10.0, -10.0),
            // G91 G10 L20 P1 X1 Y1: P1 = X21 Y31; its X0 Y0 → X16 Y26.
            line(1, 16.0, 26.0, -10.0),
            line(1, 0.0, 0.0, 10.0),
        ],
    );
}

// ---------------------------------------------------------------------------------------------------
// Shifts and machine moves

#[test]
fn g52_local_shift_set_changed_cancelled() {
    pair("g52-local");
}

#[test]
fn g92_shift_and_g92_1() {
    pair("g92-shift");
}

#[test]
fn g53_g28_g30_through_an_intermediate_point() {
    let mut frames = Frames::default();
    // LinuxCNC's trace went to its G28 position, parameters 5161–5166 at machine zero: declared.
    frames.reference[0] = [0.0; 6];
    frames.reference[1] = [-100.0, -50.0, -10.0, 0.0, 0.0, 0.0];
    pair_with("g53-g28-g30", &[], resolving_with(frames));
}

// ---------------------------------------------------------------------------------------------------
// Arcs

#[test]
fn arcs_in_g17_ij_r_full_circles_helices() {
    pair("arcs-xy");
}

#[test]
fn arcs_in_g18_and_g19() {
    pair("arcs-planes");
}

#[test]
fn arcs_under_work_offsets_and_g52() {
    pair("arcs-offset");
}

// ---------------------------------------------------------------------------------------------------
// Canned cycles

#[test]
fn canned_cycles_through_the_frames() {
    pair("cycles-frames");
}

#[test]
fn g81_g84_under_g98_g99_g91_repeats_in_every_plane_from_linuxcnc() {
    for name in [
        "g17-g98-g81",
        "g17-g99-g81",
        "g18-g98-g81",
        "g18-g99-g81",
        "g19-g98-g81",
        "g19-g99-g81",
        // G84 in G17 only: LinuxCNC 2.9 feeds G84 along the wrong axis in G18 and G19 (its own
        // tests/interp/g84/g18 expected trace has STRAIGHT_FEED(-1, 1, 1) for Y-1; see cycles.rs).
        "g17-g98-g84",
        "g17-g99-g84",
    ] {
        pair(&format!("linuxcnc/{name}"));
    }
}

// ---------------------------------------------------------------------------------------------------
// Tool length

#[test]
fn tool_length_g43_g44_g49_with_registers_set_by_g10_and_variables() {
    pair("tool-length");
}

#[test]
fn tool_registers_and_work_offsets_loaded_before_the_run() {
    let mut frames = Frames::default();
    frames.tools[0].length_geometry = 100.0;
    frames.tools[1].length_geometry = -50.0;
    frames.standard[1] = [-100.0, 20.0, -300.0, 0.0, 0.0, 0.0];
    pair_with("tool-length-frames", &[], resolving_with(frames));
}

// ---------------------------------------------------------------------------------------------------
// Transforms LinuxCNC lacks: expected points by hand.

/// A straight move.
fn line(kind: u8, x: f64, y: f64, z: f64) -> Move {
    Move {
        kind,
        end: [x, y, z],
        centre: None,
        plane: 17,
    }
}

/// An arc in `plane`, its centre on the plane's two axes in X Y Z order.
fn arc(plane: u8, kind: u8, end: [f64; 3], centre: [f64; 2]) -> Move {
    Move {
        kind,
        end,
        centre: Some(centre),
        plane,
    }
}

/// The resolved motion of `src` equals `want`.
#[track_caller]
fn motion_is(src: &str, want: &[Move]) -> Expansion {
    let e = resolved(src);
    assert_motion("program", &e.text, want);
    e
}

#[test]
fn g68_rotation_in_g17_absolute_and_incremental_r() {
    let (s120, c120) = (120f64.to_radians().sin(), 120f64.to_radians().cos());
    motion_is(
        "%\nO1\nG21 G17 G90\nG0 X0 Y0 Z5.\n\
         G68 X10. Y0 R90.\n\
         G1 X20. Y0 F100.\n\
         Y10.\n\
         G3 X10. Y20. I-10. J0\n\
         G91 G1 X10.\n\
         G91 G68 X10. Y0 R30.\n\
         G90 G1 X20. Y0\n\
         G69\n\
         G1 X0 Y0\n\
         M30\n%\n",
        &[
            line(0, 0.0, 0.0, 5.0),
            // 90° about X10 Y0: X20 Y0 is 10 along +X from the centre → 10 along +Y: X10 Y10.
            line(1, 10.0, 10.0, 5.0),
            // X20 Y10 = centre + (10, 10) → centre + (−10, 10) = X0 Y10.
            line(1, 0.0, 10.0, 5.0),
            // The arc's centre X10 Y10 = c + (0, 10) → X0 Y0; its end X10 Y20 = c + (0, 20) → X-10 Y0.
            arc(17, 3, [-10.0, 0.0, 5.0], [0.0, 0.0]),
            // G91 X10 is a step along the rotated X axis, +Y: X-10 Y10.
            line(1, -10.0, 10.0, 5.0),
            // G91 G68 R30 adds to the 90°: 120° about X10 Y0; X20 Y0 = c + (10, 0) →
            // c + (10 cos 120°, 10 sin 120°) = X5 Y8.660254.
            line(1, 10.0 + 10.0 * c120, 10.0 * s120, 5.0),
            line(1, 0.0, 0.0, 5.0),
        ],
    );
}

#[test]
fn g68_rotation_in_g18() {
    motion_is(
        "%\nO1\nG21 G17 G90\nG0 X0 Y0 Z0\n\
         G18 G68 X0 Z0 R90.\n\
         G1 X0 Z10. F100.\n\
         X5.\n\
         G2 X15. Z10. R5.\n\
         G69 G17\n\
         G0 X0 Y0 Z0\n\
         M30\n%\n",
        &[
            // In G18 (Z, X), 90° turns +Z into +X: (z, x) → (z cos − x sin, z sin + x cos).
            // X0 Z10: (10, 0) → (0, 10) = X10 Z0.
            line(1, 10.0, 0.0, 0.0),
            // X5 Z10: (10, 5) → (−5, 10) = X10 Z-5.
            line(1, 10.0, 0.0, -5.0),
            // The half circle X5 Z10 → X15 Z10 about X10 Z10: centre (10, 10) → (−10, 10) = X10 Z-10;
            // end (10, 15) → (−15, 10) = X10 Z-15; a rotation keeps G2.
            arc(18, 2, [10.0, 0.0, -15.0], [10.0, -10.0]),
            line(0, 0.0, 0.0, 0.0),
        ],
    );
}

#[test]
fn g51_scaling_with_p_and_with_ijk() {
    motion_is(
        // P is a whole number in Fanuc's least increment of magnification, 0.001 by default
        // ("Scaling (G50, G51)", parameter 5400#7 SCR): P2000 is ×2, P3000 ×3.
        "%\nO1\nG21 G17 G90\nG0 X0 Y0 Z0\n\
         G51 X0 Y0 P2000\n\
         G1 X10. Y5. Z-3. F100.\n\
         G2 X20. Y5. R5.\n\
         G50\n\
         G0 X0 Y0 Z0\n\
         G51 X10. Y10. Z0 I0.5 J0.5 K0.5\n\
         G1 X20. Y20. Z-10.\n\
         G50\n\
         G0 X2. Y2. Z2.\n\
         G51 P3000\n\
         G1 X3. Y4. Z5.\n\
         G50\n\
         G0 X0 Y0 Z0\n\
         G51 X0 Y0 Z0 I2. J3. K0.5\n\
         G1 X1. Y1. Z-4.\n\
         G50\n\
         G0 X0 Y0 Z0\n\
         M30\n%\n",
        &[
            // G51 X0 Y0 P2000 (×2) scales X and Y about X0 Y0 (the axes the block gives a centre for); Z stays.
            line(1, 20.0, 10.0, -3.0),
            // The half circle X10 Y5 → X20 Y5 about X15 Y5 → end X40 Y10, centre X30 Y10 (radius ×2).
            arc(17, 2, [40.0, 10.0, -3.0], [30.0, 10.0]),
            line(0, 0.0, 0.0, 0.0),
            // About X10 Y10 Z0, ×0.5 on all three (I J K): X20 Y20 Z-10 → X15 Y15 Z-5.
            line(1, 15.0, 15.0, -5.0),
            line(0, 2.0, 2.0, 2.0),
            // G51 P3000 without a centre: about the position X2 Y2 Z2, all axes: X3 Y4 Z5 → X5 Y8 Z11.
            line(1, 5.0, 8.0, 11.0),
            line(0, 0.0, 0.0, 0.0),
            // I J K: X×2, Y×3, Z×0.5 about the origin.
            line(1, 2.0, 3.0, -2.0),
            line(0, 0.0, 0.0, 0.0),
        ],
    );
}

#[test]
fn g51_negative_factor_and_g51_1_mirror_swap_arc_direction() {
    motion_is(
        "%\nO1\nG21 G17 G90\nG0 X15. Y5. Z0\n\
         G51.1 X10.\n\
         G1 X15. Y5. F100.\n\
         G2 X25. Y5. R5.\n\
         G3 X15. Y5. I-5. J0\n\
         G51.1 Y0\n\
         G0 X15. Y5.\n\
         G2 X25. Y5. R5.\n\
         G50.1 X0 Y0\n\
         G0 X0 Y0\n\
         G51 X0 Y0 I-1. J1.\n\
         G2 X10. Y0 I5. J0\n\
         G50\n\
         G0 X0 Y0\n\
         M30\n%\n",
        &[
            line(0, 15.0, 5.0, 0.0),
            // Mirror about X10: X15 → X5 (the start X15 Y5 was unmirrored).
            line(1, 5.0, 5.0, 0.0),
            // The half circle X15 → X25 about X20, clockwise → X5 → X-5 about X0, counter-clockwise.
            arc(17, 3, [-5.0, 5.0, 0.0], [0.0, 5.0]),
            arc(17, 2, [5.0, 5.0, 0.0], [0.0, 5.0]),
            // Mirrored in X about 10 and in Y about 0: X15 Y5 → X5 Y-5.
            line(0, 5.0, -5.0, 0.0),
            // Two flips keep G2: X25 Y5 → X-5 Y-5, the centre X20 Y5 → X0 Y-5.
            arc(17, 2, [-5.0, -5.0, 0.0], [0.0, -5.0]),
            line(0, 0.0, 0.0, 0.0),
            // Factor −1 on X mirrors: X10 Y0 → X-10, the centre X5 → X-5, G2 → G3.
            arc(17, 3, [-10.0, 0.0, 0.0], [-5.0, 0.0]),
            line(0, 0.0, 0.0, 0.0),
        ],
    );
}

// ---------------------------------------------------------------------------------------------------
// Arc end-point check (alarm 0020) and its tolerance

#[test]
fn arc_end_point_off_the_circle_is_alarm_0020_within_the_tolerance_flag() {
    // From X0 Y0 about X5 Y0 (radius 5) to X10 Y0.004: the end is 5.0000016 from the centre, within
    // the default 0.005; to X10 Y0.4 it is 5.016, over it.
    let near = "%\nO1\nG21 G17 G90\nG0 X0 Y0\nG2 X10. Y0.004 I5. J0 F100.\nM30\n%\n";
    let far = "%\nO1\nG21 G17 G90\nG0 X0 Y0\nG2 X10. Y0.4 I5. J0 F100.\nM30\n%\n";
    motion_is(near, &[arc(17, 2, [10.0, 0.004, 0.0], [5.0, 0.0])]);
    assert_eq!(failure(far, resolving()).alarm(), Some(20));
    // The end 0.0499 off (X10.0499): within a tolerance of 0.05, over one of 0.04.
    let off = "%\nO1\nG21 G17 G90\nG0 X0 Y0\nG2 X10.0499 Y0 I5. J0 F100.\nM30\n%\n";
    let with = |t: f64| Setup {
        resolve: Some(Settings {
            arc_tolerance: t,
            ..start0()
        }),
        ..literal()
    };
    assert_eq!(failure(off, with(0.04)).alarm(), Some(20));
    let e = run(off, &[], with(0.05));
    assert_motion(
        "0.05",
        &e.text,
        &[arc(17, 2, [10.0499, 0.0, 0.0], [5.0, 0.0])],
    );
    // R too short to reach the end: 2 R = 9.99 against a chord of 10, over 0.005.
    let short = "%\nO1\nG21 G17 G90\nG0 X0 Y0\nG2 X10. Y0 R4.99 F100.\nM30\n%\n";
    assert_eq!(failure(short, resolving()).alarm(), Some(20));
    // The literal mode checks the arc too before writing it: a control would stop at it, and a
    // block that raises an alarm is never written (the safe-motion rule).
    assert_eq!(failure(far, literal()).alarm(), Some(20));
}

// ---------------------------------------------------------------------------------------------------
// System variables after each kind of move and offset change, in both modes

/// Runs `src` literal and resolved (each on both engines) and checks common variables.
#[track_caller]
fn vars_in_both_modes(src: &str, library: &[(&str, &str)], want: &[(u32, f64)]) {
    for (mode, setup) in [("literal", literal()), ("resolved", resolving())] {
        let e = run(src, library, setup);
        for &(n, v) in want {
            let got = e.var(n);
            assert!(
                got.is_some_and(|g| (g - v).abs() < 1e-9),
                "{mode}: #{n} = {got:?}, expected {v}\n{}",
                e.text
            );
        }
    }
}

#[test]
fn position_and_offset_variables_after_moves_and_offset_changes() {
    let src = "%\nO1\nG21 G17 G90 G40 G49 G80\n\
        G10 L2 P1 X100. Y50. Z-20.\n\
        G10 L2 P2 X-10. Y5. Z0\n\
        G54 G0 X10. Y20. Z30.\n\
        #100=#5001\n#101=#5002\n#102=#5003\n#103=#5021\n#104=#5022\n#105=#5023\n#106=#5041\n\
        #107=#4003\n#108=#4014\n#109=#4001\n\
        G55\n\
        #110=#5001\n#111=#5002\n#112=#5003\n#113=#4014\n#114=#5241\n\
        G91 G1 X1. F100.\n\
        #115=#4003\n#116=#5001\n#117=#5021\n#118=#4001\n\
        G90 G52 X5. Y5.\n\
        #119=#5001\n#120=#5021\n\
        G52 X0 Y0\n\
        G92 X0 Y0 Z0\n\
        #121=#5001\n#122=#5021\n#123=#5003\n\
        G92.1 X0 Y0 Z0\n\
        #124=#5001\n\
        G53 X0 Y0 Z0\n\
        #125=#5001\n#126=#5002\n#127=#5021\n#128=#5023\n\
        G10 L20 P1 X1. Y2. Z3.\n\
        G54.1 P1\n\
        #129=#4014\n#130=#4130\n#131=#5001\n#132=#7001\n#133=#7003\n\
        #7001=4.\n\
        #134=#5001\n#135=#5221\n\
        #5221=101.\n\
        #136=#5221\n\
        G54\n\
        #137=#4130\n#138=#5001\n#139=#5003\n\
        M30\n%\n";
    vars_in_both_modes(
        src,
        &[],
        &[
            // G54 is X100 Y50 Z-20: X10 Y20 Z30 is machine X110 Y70 Z10.
            (100, 10.0),
            (101, 20.0),
            (102, 30.0),
            (103, 110.0),
            (104, 70.0),
            (105, 10.0),
            (106, 10.0),
            (107, 90.0),
            (108, 54.0),
            (109, 0.0),
            // In G55 (X-10 Y5 Z0) the same machine point is X120 Y65 Z10.
            (110, 120.0),
            (111, 65.0),
            (112, 10.0),
            (113, 55.0),
            (114, -10.0),
            // G91 X1: X121, machine X111; G1 is group 1's 1.
            (115, 91.0),
            (116, 121.0),
            (117, 111.0),
            (118, 1.0),
            // G52 X5 Y5 moves the zero by +5: X116; the machine point stays.
            (119, 116.0),
            (120, 111.0),
            // G92 X0 Y0 Z0 makes the tool's point zero.
            (121, 0.0),
            (122, 111.0),
            (123, 0.0),
            // G92.1: back to G55: X121.
            (124, 121.0),
            // G53 to machine zero: in G55 that is X10 Y-5; machine X0 Z0.
            (125, 10.0),
            (126, -5.0),
            (127, 0.0),
            (128, 0.0),
            // G54.1 P1 (X1 Y2 Z3): machine X0 is X-1; #4014 reads 54.1, #4130 the P number.
            (129, 54.1),
            (130, 1.0),
            (131, -1.0),
            (132, 1.0),
            (133, 3.0),
            // #7001 = 4 while active: the tool stays, X reads -4.
            (134, -4.0),
            (135, 100.0),
            (136, 101.0),
            // Back in G54 (now X101): X-101, Z = 0 − (−20) = 20; #4130 is 0 outside G54.1.
            (137, 0.0),
            (138, -101.0),
            (139, 20.0),
        ],
    );
}

#[test]
fn position_variables_under_rotation_tool_length_and_reference_returns() {
    let src = "%\nO1\nG21 G17 G90 G40 G49 G80\n\
        G10 L2 P1 X100. Y0 Z-50.\n\
        G10 L10 P1 R100.\n\
        G54 G0 X0 Y0 Z10.\n\
        G68 X0 Y0 R90.\n\
        G0 X10. Y0\n\
        #100=#5001\n#101=#5002\n#102=#5021\n#103=#5022\n#104=#4016\n\
        G69\n\
        G43 Z20. H1\n\
        #105=#5003\n#106=#5023\n#107=#4008\n#108=#4111\n\
        G49 Z20.\n\
        #109=#5023\n\
        G91 G28 Z0\n\
        #110=#5003\n#111=#5023\n\
        G90 G28 X0 Y0\n\
        #112=#5001\n#113=#5021\n\
        M30\n%\n";
    vars_in_both_modes(
        src,
        &[],
        &[
            // Under 90° about X0 Y0 the programmed X10 Y0 is where #5001 #5002 say; the machine is at
            // X100 + 0 Y10.
            (100, 10.0),
            (101, 0.0),
            (102, 100.0),
            (103, 10.0),
            (104, 68.0),
            // G43 H1 (100): Z20 programmed, machine 20 − 50 + 100 = 70.
            (105, 20.0),
            (106, 70.0),
            (107, 43.0),
            (108, 1.0),
            (109, -30.0),
            // G28 Z to the reference (machine 0): Z reads 50 in G54.
            (110, 50.0),
            (111, 0.0),
            (112, -100.0),
            (113, 0.0),
        ],
    );
}

#[test]
fn a_macro_reading_5003_after_a_cycle_gets_its_return_level() {
    let src = "%\nO1\nG21 G17 G90 G40 G49 G80\n\
        G10 L2 P1 X0 Y0 Z-10.\n\
        G54 G0 X0 Y0 Z20.\n\
        G98 G81 X10. Y10. Z-5. R2. F100.\n\
        #100=#5003\n#101=#5001\n#102=#5023\n#103=#4009\n#104=#4010\n\
        G99 X20.\n\
        #105=#5003\n#106=#4010\n\
        G91 G99 X10. Z-7. R-18. K2\n\
        #107=#5001\n#108=#5003\n\
        G90 G80\n\
        #109=#4009\n\
        G52 Z-5.\n\
        G98 G83 X0 Y0 Z-10. R3. Q4.\n\
        #110=#5003\n\
        G80 G52 Z0\n\
        M30\n%\n";
    vars_in_both_modes(
        src,
        &[],
        &[
            // G98: back at the initial level Z20 (machine Z10), at the hole.
            (100, 20.0),
            (101, 10.0),
            (102, 10.0),
            (103, 81.0),
            (104, 98.0),
            // G99: at R.
            (105, 2.0),
            (106, 99.0),
            // G91 K2 in the same cycle mode: Fanuc's incremental R is measured from the initial level
            // Z20 (LinuxCNC's from the Z the block starts at): R = 20 − 18 = 2, Z = 2 − 7 = −5; two
            // holes X30 X40, back at R.
            (107, 40.0),
            (108, 2.0),
            (109, 80.0),
            // G52 Z-5 moves the zero down 5: the tool at Z2 reads 7, and G98 G83 returns to that
            // initial level.
            (110, 7.0),
        ],
    );
}

#[test]
fn a_g65_macro_reads_5001_and_returns_there() {
    let main = "%\nO1\nG21 G17 G90 G40 G49 G80\n\
        G10 L2 P1 X50. Y50. Z0\n\
        G54 G0 X10. Y20. Z5.\n\
        G65 P9001 A5. B3.\n\
        #100=#5001\n#101=#5002\n\
        G52 X1. Y1.\n\
        G65 P9001 A2. B2.\n\
        #104=#5001\n#105=#5002\n\
        M30\n%\n";
    let sub = "%\nO9001 (A SQUARE A BY B FROM WHERE THE TOOL IS, BACK THERE)\n\
        #10=#5001\n#11=#5002\n\
        G91 G1 X#1 F100.\n\
        Y#2\n\
        X-#1\n\
        #102=#5001\n#103=#5002\n\
        G90 G1 X#10 Y#11\n\
        M99\n%\n";
    let lib = [("O9001.nc", sub)];
    vars_in_both_modes(
        main,
        &lib,
        &[
            (100, 10.0),
            (101, 20.0),
            // The second call starts at X9 Y19 of the shifted system; its last G91 corner is X9 Y21.
            (102, 9.0),
            (103, 21.0),
            (104, 9.0),
            (105, 19.0),
        ],
    );
    let e = run(main, &lib, resolving());
    assert_motion(
        "G65",
        &e.text,
        &[
            // Out of machine zero into G54 X10 Y20 Z5 (G54 frame).
            line(0, 10.0, 20.0, 5.0),
            line(1, 15.0, 20.0, 5.0),
            line(1, 15.0, 23.0, 5.0),
            line(1, 10.0, 23.0, 5.0),
            line(1, 10.0, 20.0, 5.0),
            // The G52 shift makes X9 Y19 the same point: a 2 by 2 square from there.
            line(1, 12.0, 20.0, 5.0),
            line(1, 12.0, 22.0, 5.0),
            line(1, 10.0, 22.0, 5.0),
            line(1, 10.0, 20.0, 5.0),
        ],
    );
}

#[test]
fn tool_register_variables_round_trip() {
    let src = "%\nO1\n\
        #2001=1.5\n#2201=100.\n#2401=0.1\n#2601=4.\n\
        #100=#10001\n#101=#11001\n#102=#12001\n#103=#13001\n\
        #10200=-2.\n#11200=-3.\n#12200=-4.\n#13200=-5.\n\
        #104=#2200\n#105=#2400\n#106=#2600\n#107=#2800\n\
        G10 L10 P7 R50.\nG10 L11 P7 R-0.2\nG10 L12 P7 R3.\nG10 L13 P7 R0.05\n\
        #108=#2207\n#109=#2007\n#110=#2607\n#111=#2407\n\
        G91 G10 L10 P7 R1.\nG91 G10 L13 P7 R0.05\n\
        #112=#11007\n#113=#12007\n\
        #10999=9.\n#114=#10999\n\
        M30\n%\n";
    vars_in_both_modes(
        src,
        &[],
        &[
            (100, 1.5),
            (101, 100.0),
            (102, 0.1),
            (103, 4.0),
            (104, -2.0),
            (105, -3.0),
            (106, -4.0),
            (107, -5.0),
            (108, 50.0),
            (109, -0.2),
            (110, 3.0),
            (111, 0.05),
            (112, 51.0),
            (113, 0.1),
            (114, 9.0),
        ],
    );
}

#[test]
fn tool_register_variables_past_the_last_offset_are_an_alarm() {
    // #11000, #12000, #13000 lie between the 999 registers of two kinds: no register. Reading one
    // is alarm 0115 as writing it is (it used to index past the registers and panic).
    for n in [11000, 12000, 13000] {
        let src = format!("%\nO1\n#100=#{n}\nM30\n%\n");
        assert_eq!(failure(&src, Setup::default()).alarm(), Some(115), "#{n}");
    }
}

// ---------------------------------------------------------------------------------------------------
// The literal mode is unchanged by the kernel

#[test]
fn literal_output_of_frames_cycles_and_transforms_is_the_words_as_programmed() {
    let src = "%\nO1234 (LITERAL MODE)\n\
        N10 G21 G17 G90 G40 G49 G80\n\
        N20 G10 L2 P1 X10 Y20.5 Z-5\n\
        N30 G52 X5. Y5.\n\
        N40 G0 X1.23456 Y-0.0004 Z10\n\
        N50 G98 G81 X10 Y10 Z-5. R2 F100\n\
        N60 X20.\n\
        N70 G91 Y10. K2\n\
        N80 G90 G80\n\
        N90 G68 X0 Y0 R45.\n\
        N100 G1 X10. Y0\n\
        N110 G69\n\
        N120 G52 X0 Y0\n\
        N130 G51 X0 Y0 P2\n\
        N140 G51.1 X0\n\
        N150 G0 X10. Y0\n\
        N160 G2 X0 Y-10. R10.\n\
        N170 G50.1 X0\n\
        N180 G50 G0\n\
        N190 G43 H1 Z5.\n\
        N200 G49 G53 Z0\n\
        N210 G28 X0 Y0\n\
        N220 #100=#5001\n\
        N230 M30\n%\n";
    // By hand: every block as written, in program order; lengths with the decimal point and three
    // decimals at most (X1.23456 → X1.235, Y-0.0004 → Y0.), integer addresses (L P H) bare, the
    // macro statement gone.
    let want = "%\nO1234 (LITERAL MODE)\n\
        N10 G21 G17 G90 G40 G49 G80\n\
        N20 G10 L2 P1 X10. Y20.5 Z-5.\n\
        N30 G52 X5. Y5.\n\
        N40 G0 X1.235 Y0. Z10.\n\
        N50 G98 G81 X10. Y10. Z-5. R2. F100.\n\
        N60 X20.\n\
        N70 G91 Y10. K2.\n\
        N80 G90 G80\n\
        N90 G68 X0. Y0. R45.\n\
        N100 G1 X10. Y0.\n\
        N110 G69\n\
        N120 G52 X0. Y0.\n\
        N130 G51 X0. Y0. P2\n\
        N140 G51.1 X0.\n\
        N150 G0 X10. Y0.\n\
        N160 G2 X0. Y-10. R10.\n\
        N170 G50.1 X0.\n\
        N180 G50 G0\n\
        N190 G43 H1 Z5.\n\
        N200 G49 G53 Z0.\n\
        N210 G28 X0. Y0.\n\
        N230 M30\n%\n";
    let literal = run(src, &[], literal());
    assert_eq!(literal.text, want);
    // The kernel still follows the frames in the literal mode: after G28 X0 Y0 (machine zero) the
    // programmed X is −10 in G54 (X10), with nothing else left.
    assert_eq!(literal.var(100), Some(-10.0));
    // Resolved, the same program is motion only, the same #100.
    let e = resolved(src);
    assert_resolved(&e.text);
    assert_eq!(e.var(100), Some(-10.0));
    assert!(!e.text.contains("G81") && !e.text.contains("G52") && !e.text.contains("G68"));
}

#[test]
fn resolved_output_of_a_three_axis_program_has_no_rotary_words() {
    // G21 in a metric run changes nothing. The first move writes the axes that change from the
    // declared start X0 Y0 Z0 (Z does not: the block does not name it), never A B C that do not
    // move; G20 moves nothing (LinuxCNC and Fanuc keep the tool where it is) and restates nothing:
    // the next move writes X alone, in inch (this test wrote `X3. Y2. Z0.` before: Y2 inch is a
    // 48.8 mm move the program never asked for).
    let e = resolved("%\nO1\nG21 G17 G90\nG0 X1. Y2.\nG20\nG0 X3.\nM30\n%\n");
    assert_eq!(
        e.body(),
        // The first block states the modes the motion depends on (issue of the milling controls:
        // nothing rests on what an earlier program left).
        [
            "G90 G17 G94 G40 G49 G80 G54",
            "G21",
            "G0 X1. Y2.",
            "G20",
            "X3.",
            "M30"
        ]
    );
}

#[test]
fn an_arc_right_after_a_mirror_change_starts_where_the_tool_is() {
    // G0 X10 Y0 puts the tool at X10; G51.1 X5. mirrors about X5 from here on, the tool staying.
    // The arc G2 X0 Y-10 I-10 J0 (centre X0 Y0 from the programmed start X10) mirrors to the centre
    // X10 Y0 and the end X10 Y-10: from the tool at X10 Y0 that centre is the start itself.
    let src = "%\nO1\nG21 G17 G90\nG0 X10. Y0\nG51.1 X5.\nG2 X0 Y-10. I-10. J0 F100.\nM30\n%\n";
    assert_eq!(failure(src, resolving()).alarm(), Some(20));
}

#[test]
fn a_cycle_under_rotation_and_scaling_drills_the_turned_holes() {
    motion_is(
        "%\nO1\nG21 G17 G90\nG0 X0 Y0 Z10.\n\
         G68 X0 Y0 R90.\n\
         G98 G81 X10. Y0 Z-5. R2. F100.\n\
         X20.\n\
         G80 G69\n\
         G51 X0 Y0 P2000\n\
         G99 G81 X5. Y5. Z-5. R2.\n\
         G80 G50\n\
         G0 X0 Y0\n\
         M30\n%\n",
        &[
            line(0, 0.0, 0.0, 10.0),
            // 90° about X0 Y0: X10 Y0 → X0 Y10; the drilling axis Z is not turned.
            line(0, 0.0, 10.0, 10.0),
            line(0, 0.0, 10.0, 2.0),
            line(1, 0.0, 10.0, -5.0),
            line(0, 0.0, 10.0, 10.0),
            // X20 → X0 Y20.
            line(0, 0.0, 20.0, 10.0),
            line(0, 0.0, 20.0, 2.0),
            line(1, 0.0, 20.0, -5.0),
            line(0, 0.0, 20.0, 10.0),
            // ×2 in X Y about X0 Y0 (G51 X0 Y0 P2000, P in 0.001, leaves Z alone): X5 Y5 → X10 Y10, R and Z as given;
            // G99 returns to R.
            line(0, 10.0, 10.0, 10.0),
            line(0, 10.0, 10.0, 2.0),
            line(1, 10.0, 10.0, -5.0),
            line(0, 10.0, 10.0, 2.0),
            line(0, 0.0, 0.0, 2.0),
        ],
    );
}

// ---------------------------------------------------------------------------------------------------
// LinuxCNC's tests/interp: G52/G92, G53 and the machine position, cutter compensation

#[test]
fn g52_g92_interaction_from_linuxcnc() {
    let e = pair("linuxcnc/g52-g92-interaction");
    // By hand (inch): G92 X1 Y2 at X0.5 Y0.5 makes that point X1 Y2; G92.1 gives X0 Y0 back (the
    // tool went there); G52 X2 Y3 at X0 Y0 reads X-2 Y-3; G52 X0 Y0 at the local zero reads X2 Y3.
    for (n, v) in [
        (100, 1.0),
        (101, 2.0),
        (102, -0.5),
        (103, -1.5),
        (104, -2.0),
        (105, -3.0),
        (106, 2.0),
        (107, 3.0),
    ] {
        assert_eq!(e.var(n), Some(v), "#{n}");
    }
}

#[test]
fn machine_position_after_g53_from_linuxcnc() {
    let e = pair("linuxcnc/machine-coord-params");
    // By hand: #5021-#5023 after G53 X0 Y0 Z0 and G53 X1 Y2 Z3 are those values whatever the work
    // offset (X3 Y7) or the G92 shift; and under the length offset too.
    let mut want = Vec::new();
    for _ in 0..3 {
        want.extend([0.0, 0.0, 0.0, 1.0, 2.0, 3.0]);
    }
    for (k, v) in want.into_iter().enumerate() {
        let n = 100 + k as u32;
        assert_eq!(e.var(n), Some(v), "#{n}");
    }
    // G53 X1 Y2 Z3 under H1 = 5: machine Z3 (G53 cancels the length vector of the axes it names).
    for (n, v) in [(124, 1.0), (125, 2.0), (126, 3.0)] {
        assert_eq!(e.var(n), Some(v), "#{n}");
    }
}

#[test]
fn machine_position_after_g53_without_a_length_offset() {
    // The part of machine-coord-params that holds today: the three suites without the length offset.
    let src = read("linuxcnc/machine-coord-params.nc");
    let e = resolved(&src);
    for round in 0..3 {
        for (k, v) in [0.0, 0.0, 0.0, 1.0, 2.0, 3.0].into_iter().enumerate() {
            let n = 100 + 6 * round + k as u32;
            assert_eq!(e.var(n), Some(v), "#{n}");
        }
    }
}

/// The LinuxCNC compensation rules, D1's radius set by the program itself.
fn compensating() -> Setup {
    Setup {
        resolve: Some(Settings {
            comp_style: fmsvm_kernel::CompStyle::LinuxCnc,
            ..start0()
        }),
        ..literal()
    }
}

#[test]
fn cutter_compensation_inside_corners_from_linuxcnc() {
    pair_with("linuxcnc/inside-corners", &[], compensating());
}

#[test]
fn cutter_compensation_crazy_paths_from_linuxcnc() {
    pair_with("linuxcnc/crazy-paths", &[], compensating());
}

#[test]
fn cutter_compensation_with_inverse_time_feed_from_linuxcnc() {
    // Resolved output has no inverse-time feed (G93): resolving refuses it, naming the code, rather
    // than write feeds the control would read as mm/min. (The .moves stay for when G93 is converted.)
    let src = read("linuxcnc/inverse-time-with-comp.nc");
    match failure(&src, compensating()) {
        Failure::Alarm(10, m, _) => assert!(m.contains("G93 inverse time"), "{m}"),
        f => panic!("{f:?}"),
    }
}

// ---------------------------------------------------------------------------------------------------
// The textbook corpus (shared/corpus/textbook, copied to tests/textbook, which tests/textbook.rs runs
// whole in NCT syntax; here the programs that are Fanuc syntax, with the tool set from outside)

fn textbook(name: &str, setup: Setup) {
    pair_with(
        &format!("../textbook/{name}"),
        &["../textbook/15-O7053-pocket-subprogram.nc"],
        setup,
    );
}

/// Tool 1 of the textbook: radius 2, length 0; LinuxCNC's compensation; G51's P the factor
/// itself, as the textbook writes it (`--input nct`).
fn textbook_tool() -> Setup {
    let mut frames = Frames::default();
    frames.tools[0].radius_geometry = 2.0;
    let compensating = compensating();
    Setup {
        frames: Some(frames),
        resolve: compensating.resolve.map(|s| Settings {
            scaling_unit: 0.0,
            ..s
        }),
        ..compensating
    }
}

#[test]
fn textbook_programs_without_compensation() {
    for name in [
        "01-O7011-circle-radial-approach",
        "03-O7013-circle-tangent-approach",
        "05-O7021-internal-circle",
        "08-O7031-rectangle",
        "27-O7079-hole-grid-nested-while",
        "37-O7112-helix",
    ] {
        textbook(name, resolving());
    }
}

/// The textbook's compensated contours (LinuxCNC's rules, tool radius 2): start-up on a line and on
/// an arc, convex corners rolled round, concave corners at the intersection, full circles inside and
/// outside, cancel; exercise 10's `,R0` corners (the same motion as 09).
#[test]
fn textbook_programs_with_cutter_compensation() {
    for name in [
        "02-O7012-circle-cutter-comp",
        "04-O7014-circle-tangent-comp",
        "06-O7022-internal-circle-comp",
        "07-O7023-internal-circle-arc-approach",
        "09-O7032-rectangle-comp",
        "10-O7033-rectangle-r0-corners",
        "12-O7041-rectangle-pocket-arc-approach",
    ] {
        textbook(name, textbook_tool());
    }
}

#[test]
fn textbook_16_g52_shifts_of_a_compensated_pocket() {
    textbook("16-O7061-subprogram-g52-shifts", textbook_tool());
}

#[test]
fn textbook_17_scaled_compensated_pocket() {
    textbook("17-O7062-scaling-subprogram", textbook_tool());
}

#[test]
fn textbook_18_scaled_about_a_point() {
    textbook("18-O7063-scaling-about-point", textbook_tool());
}

// ---------------------------------------------------------------------------------------------------
// Fanuc rules the kernel does not keep yet (expected values by hand from the manuals cited)

#[test]
fn g10_l2_p0_sets_the_external_offset() {
    let e = motion_is(
        "%\nO1\nG21 G17 G90\nG10 L2 P0 X5. Y-5. Z1.\nG10 L2 P2 X10. Y0 Z0\n\
         G54 G0 X0 Y0 Z0\nG55 X0 Y0\n#100=#5201\n#101=#5021\n#102=#5203\nM30\n%\n",
        &[
            // The external offset moves G54 and G55 alike: G55's X0 Y0 is X10 of the G54 frame. (The
            // move to G54's X0 Y0 Z0 before it is not written: see
            // `the_first_move_after_a_g54_change_is_written`.)
            line(0, 10.0, 0.0, 0.0),
        ],
    );
    // #5021: G55's X0 is machine X = 5 (external) + 10.
    assert_eq!(e.var(100), Some(5.0));
    assert_eq!(e.var(101), Some(15.0));
    assert_eq!(e.var(102), Some(1.0));
}

#[test]
fn the_first_move_after_a_g54_change_is_written() {
    let e = resolved(
        "%\nO1\nG21 G17 G90\nG10 L2 P1 X100. Y50. Z0\nG54 G0 X0 Y0\nG1 X10. F100.\nM30\n%\n",
    );
    assert_eq!(
        e.body(),
        [
            "G90 G17 G94 G40 G49 G80 G54",
            "G21",
            "G0 X0. Y0. Z0.",
            "G1 X10. F100.",
            "M30"
        ]
    );
}

#[test]
fn g53_moves_at_rapid_under_g1() {
    motion_is(
        "%\nO1\nG21 G17 G90\nG0 X5. Y5.\nG1 X10. F100.\nG53 X0 Y0\nM30\n%\n",
        &[
            line(0, 5.0, 5.0, 0.0),
            line(1, 10.0, 5.0, 0.0),
            line(0, 0.0, 0.0, 0.0),
        ],
    );
}

#[test]
fn g53_z_cancels_the_tool_length_vector() {
    let e = motion_is(
        "%\nO1\nG21 G17 G90\nG10 L10 P1 R100.\nG43 H1 G0 Z50.\nG53 Z0\n#100=#5023\nM30\n%\n",
        &[line(0, 0.0, 0.0, 150.0), line(0, 0.0, 0.0, 0.0)],
    );
    assert_eq!(e.var(100), Some(0.0));
}

#[test]
fn g92_1_presets_only_the_axes_it_names() {
    let e = motion_is(
        "%\nO1\nG21 G17 G90\nG0 X10. Y10.\nG92 X0 Y0\nG92.1 X0\n#100=#5001\n#101=#5002\n\
         G0 X0 Y0\nM30\n%\n",
        &[line(0, 10.0, 10.0, 0.0), line(0, 0.0, 10.0, 0.0)],
    );
    assert_eq!(e.var(100), Some(10.0));
    assert_eq!(e.var(101), Some(0.0));
}

#[test]
fn g92_cancels_the_local_shift_of_its_axes() {
    let e = motion_is(
        "%\nO1\nG21 G17 G90\nG52 X10.\nG0 X0 Y0\nG92 X0\nG52 X0\n#100=#5001\nG0 X0\nM30\n%\n",
        &[line(0, 10.0, 0.0, 0.0)],
    );
    assert_eq!(e.var(100), Some(0.0));
}

// ---------------------------------------------------------------------------------------------------
// The binary: `fmsvm run --resolve`, with `--offsets`

#[test]
fn the_binary_resolves_with_offsets_from_a_file() {
    use cli_support::{Dir, stderr, stdout};
    let d = Dir::new();
    d.file("p.nc", &read("g53-g28-g30.nc"));
    d.file(
        "o.toml",
        "[reference.G28]\nX = 0.0\nY = 0.0\nZ = 0.0\n[reference.\"G30 P2\"]\nX = -100.0\nY = -50.0\nZ = -10.0\n",
    );
    // Returns written as moves to the declared positions (the reference form is tests/safety.rs's).
    d.file("moves.toml", "[motion]\nreference_return = \"none\"\n");
    let o = d.run(&[
        "run",
        "--resolve",
        "--dialect-file",
        "moves.toml",
        "--offsets",
        "o.toml",
        "p.nc",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = stdout(&o);
    assert_motion(
        "fmsvm run --resolve",
        &text,
        &moves_of_list(&read("g53-g28-g30.moves")),
    );
    // Into a file, the same bytes; and the tool registers of the file are the program's H.
    d.file("t.nc", &read("tool-length-frames.nc"));
    d.file(
        "t.toml",
        "[tool.1]\nlength = 100.0\n[tool.2]\nlength = -50.0\n[work.G55]\nX = -100.0\nY = 20.0\nZ = -300.0\n",
    );
    let o = d.run(&[
        "run",
        "--resolve",
        "--offsets",
        "t.toml",
        "t.nc",
        "-o",
        "t.out",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_motion(
        "fmsvm run --resolve -o",
        &d.read("t.out"),
        &moves_of_list(&read("tool-length-frames.moves")),
    );
    // --frame machine writes machine coordinates: G55's X0 Y0 Z0 is machine X-100 Y20 Z-300.
    let o = d.run(&[
        "run",
        "--resolve",
        "--frame",
        "machine",
        "--offsets",
        "t.toml",
        "t.nc",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let moves = moves_of_flat(&stdout(&o));
    assert_eq!(moves[0].end, [-100.0, 20.0, 0.0]);
    // Without --resolve the words go out as written.
    let o = d.run(&["run", "p.nc"]);
    assert!(
        stdout(&o).contains("G30 P2 X0. Y0. Z20.\n"),
        "{}",
        stdout(&o)
    );
}

#[test]
fn the_binary_stops_with_alarm_0020_and_takes_the_arc_tolerance() {
    use cli_support::{Dir, stderr, stdout};
    let d = Dir::new();
    d.file(
        "a.nc",
        "%\nO1\nG21 G17 G90\nG0 X0 Y0\nG2 X10.0499 Y0 I5. J0 F100.\nM30\n%\n",
    );
    let o = d.run(&["run", "--resolve", "a.nc"]);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(stderr(&o).contains("alarm 0020"), "{}", stderr(&o));
    let o = d.run(&["run", "--resolve", "--arc-tolerance", "0.05", "a.nc"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("G2 X10.05 Y0. I5. J0. F100.\n"),
        "{}",
        stdout(&o)
    );
}
