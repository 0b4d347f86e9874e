//! The shared corpus (copied into `tests/corpus/`): every program expands, and its motion equals the
//! motion LinuxCNC's interpreter made from the `.ngc` twin (`tests/corpus/*.moves`, see
//! `tests/corpus/regenerate.sh`), within the corpus tolerance of 0.0011 mm.

use crate::common;

use common::{diff_moves, moves_of_flat, moves_of_list, ok};

const TOL: f64 = 0.0011;

fn check(name: &str) -> String {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/corpus/");
    let src = std::fs::read_to_string(format!("{dir}{name}.nc")).expect("program");
    let want =
        moves_of_list(&std::fs::read_to_string(format!("{dir}{name}.moves")).expect("moves"));
    let e = ok(&src);
    let got = moves_of_flat(&e.text);
    if let Err(d) = diff_moves(&got, &want, TOL) {
        panic!("{name}: {d}");
    }
    e.text
}

#[test]
fn sine_matches_linuxcnc() {
    let text = check("003-sine");
    // 3600 feed blocks on the curve: X0 to X359.9 (X360 is never reached in IEEE double).
    let curve = text.lines().filter(|l| l.starts_with("N180 G1")).count();
    assert_eq!(curve, 3600);
    assert!(text.contains("N180 G1 X359.9 Y-0.002 F100.\n"));
}

#[test]
fn hemisphere_matches_linuxcnc_with_10201_motion_blocks() {
    let text = check("003-hemisphere");
    let raster = text.lines().filter(|l| l.contains(" G1 ")).count();
    assert_eq!(raster, 101 * 101);
    // The flat program is flat: no variables, brackets or loops left.
    assert!(
        !text.contains('#')
            && !text.contains('[')
            && !text.contains("WHILE")
            && !text.contains("GOTO")
    );
    assert!(text.starts_with(
        "%\nO7118 (SEED 003 EXERCISE 38: HEMISPHERE R40 ON A 100X100 FIELD, ZIGZAG RASTER)\nN100 T1\n"
    ));
    assert!(text.ends_with("N380 M30\n%\n"));
    // The pole of the hemisphere: R40 at X0 Y0.
    assert!(
        text.contains("N320 G1 X0. Y0. Z40.\n") || text.contains("N220 G1 X0. Y0. Z40. F1000.\n")
    );
}

#[test]
fn dprnt_hemisphere_prints_a_program_with_the_oracles_motion() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/corpus/");
    let src = std::fs::read_to_string(format!("{dir}003-hemisphere-dprnt.nc")).expect("program");
    let want = moves_of_list(
        &std::fs::read_to_string(format!("{dir}003-hemisphere-dprnt.printed.moves"))
            .expect("moves"),
    );
    let e = ok(&src);
    // The flat program itself holds only M30: everything went to the port.
    assert_eq!(e.body(), vec!["N390 M30"]);
    let printed = String::from_utf8(e.printed.clone()).expect("ASCII");
    // POPEN sends DC2, PCLOS DC4 (macro-b-rules O5); `*` prints a space; [53] is 5 whole, 3 fraction digits.
    assert!(
        printed.starts_with(
            "\u{12}O7120\nT1\nG54 G0 X-50 Y-50\nG43 Z50 H1\nG90 G01 S1000 M3 M8 F1000\n"
        ),
        "{printed:.200}"
    );
    assert!(
        printed.contains("\nG1 X   -50.000 Y   -50.000 Z     0.000\n"),
        "{printed:.300}"
    );
    assert!(printed.contains("\nG1 X     0.000 Y     0.000 Z    40.000\n"));
    assert!(printed.ends_with("\n\u{14}"));
    let got = moves_of_flat(&printed);
    if let Err(d) = diff_moves(&got, &want, TOL) {
        panic!("printed hemisphere: {d}");
    }
}
