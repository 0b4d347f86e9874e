//! Haas lathe programs (`--control haas-lathe`, or `--control haas --machine lathe`): the one-block
//! forms of G71, G72 and G73, the bare G28, G04 P, G154. Each cycle is checked against the Fanuc
//! two-block form of the same cycle (which tests/lathe.rs holds to LinuxCNC's trace) and by hand;
//! the Haas lathe operator's manual sections are named beside each test.

use crate::cli_support;

use cli_support::{Dir, stderr};

/// The retract of a one-block G71/G72 is the control's Setting 73 (NGC 287).
const SETTING_73: &str = "[cycles]\nsetting_73 = 0.5\n";

/// `fmsvm run FILE --control haas-lathe` and `more`.
fn haas_run<'a>(file: &'a str, more: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec!["run", file, "--control", "haas-lathe"];
    args.extend_from_slice(more);
    args
}

/// Runs fmsvm with `args`, which must stop with exit `code` saying each of `says`.
fn refused(d: &Dir, args: &[&str], code: i32, says: &[&str]) {
    let o = d.run(args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(code), "{args:?}: {err}");
    for s in says {
        assert!(err.contains(s), "{s} in {err}");
    }
}

/// Expands `file` with `args` to `out`, verified by reading it back, on both engines (the same
/// bytes); the text.
fn expand(d: &Dir, file: &str, args: &[&str]) -> String {
    let mut texts = Vec::new();
    for engine in ["interp", "jit"] {
        let mut all = vec![
            "run",
            file,
            "--resolve",
            "-o",
            "out.nc",
            "--verify",
            "--engine",
            engine,
        ];
        all.extend_from_slice(args);
        let o = d.run(&all);
        assert!(
            o.status.success(),
            "{file} {args:?} {engine}: {}",
            stderr(&o)
        );
        texts.push(d.read("out.nc"));
    }
    assert_eq!(texts[0], texts[1], "the two engines differ");
    texts.remove(0)
}

/// "G71 O.D./I.D. Stock Removal Cycle": `G71 P Q U W D F` in one block, D the depth of cut (a
/// positive radius), U the X finishing allowance (a diameter), W the Z one; the retract is Setting
/// 73. It cuts as the Fanuc two-block form `G71 U(D) R(Setting 73)` / `G71 P Q U W F` does.
#[test]
fn a_one_block_g71_cuts_as_the_two_block_form() {
    let d = Dir::new();
    let haas = "O1\nG99 G0 X52. Z2.\nG71 P10 Q20 U0.5 W0.1 D2. F0.25\nN10 G0 X20.\nG1 Z-15.\nX30. Z-25.\nZ-40.\nN20 X50.\nG70 P10 Q20\nG28 U0 W0\nM30\n";
    d.file("h.nc", haas);
    d.file(
        "f.nc",
        &haas.replace(
            "G71 P10 Q20 U0.5 W0.1 D2. F0.25",
            "G71 U2. R0.5\nG71 P10 Q20 U0.5 W0.1 F0.25",
        ),
    );
    d.file("p.toml", SETTING_73);
    let h = expand(
        &d,
        "h.nc",
        &["--control", "haas-lathe", "--params", "p.toml"],
    );
    let f = expand(&d, "f.nc", &["--control", "fanuc-0i-t"]);
    assert_eq!(h, f);
    // By hand: passes 2 mm a side (4 on the diameter) from X52 down, each to the profile moved by
    // U0.5 (diameter) and W0.1, then 0.5 back at 45° (X +1.0 on the diameter, Z +0.5). At X28 the
    // moved taper (X20.5 Z-14.9 to X30.5 Z-24.9) is at Z-14.9 - 10·(28-20.5)/10 = -22.4.
    let lines: Vec<&str> = h.lines().collect();
    for want in [
        ["X48.", "G1 Z-39.9 F0.25", "G0 X49. Z-39.4"],
        ["X28.", "G1 Z-22.4", "G0 X29. Z-21.9"],
        ["X24.", "G1 Z-18.4", "G0 X25. Z-17.9"],
    ] {
        assert!(lines.windows(3).any(|w| w == want), "{want:?} in\n{h}");
    }
    // The same program under `--control haas --machine lathe`.
    let same = expand(
        &d,
        "h.nc",
        &[
            "--control",
            "haas",
            "--machine",
            "lathe",
            "--params",
            "p.toml",
        ],
    );
    assert_eq!(same, h);
}

/// Without Setting 73 the retract is not known: refused at the cycle, saying how to give it. I and
/// K (the rough-pass allowance) are refused: how the Haas leaves them is not described in the
/// manual text fmsvm follows. In literal output a Fanuc would read the one-block form otherwise.
#[test]
fn what_a_one_block_g71_cannot_say_is_refused() {
    let d = Dir::new();
    let body =
        |g71: &str| format!("O1\nG99 G0 X52. Z2.\n{g71}\nN10 G0 X20.\nG1 Z-15.\nN20 X50.\nM30\n");
    d.file("p.nc", &body("G71 P10 Q20 U0.5 W0.1 D2. F0.25"));
    refused(
        &d,
        &haas_run("p.nc", &["--resolve", "-o", "out.nc"]),
        4,
        &[
            "its retract is the control's Setting 73",
            "[cycles] setting_73",
            "p.nc:3:1",
        ],
    );
    d.file("s.toml", SETTING_73);
    d.file("q.nc", &body("G71 P10 Q20 U0.5 W0.1 I0.2 D2. F0.25"));
    refused(
        &d,
        &haas_run("q.nc", &["--params", "s.toml", "--resolve", "-o", "out.nc"]),
        4,
        &["rough-pass allowance"],
    );
    // Literal output for a Fanuc (the one-block form is a Haas's only; a Haas's own dialect keeps
    // it: `literal_output_for_a_haas_keeps_its_forms`).
    refused(
        &d,
        &haas_run(
            "p.nc",
            &[
                "--params",
                "s.toml",
                "--dialect",
                "fanuc0itd",
                "-o",
                "out.nc",
            ],
        ),
        4,
        &["no Fanuc literal form"],
    );
    // Fanuc's own syntax keeps D a register number: D2. is a format error there.
    refused(
        &d,
        &["run", "p.nc", "--control", "fanuc-0i-t", "--resolve"],
        3,
        &["D takes a whole number"],
    );
}

/// The Haas lathe manual's own G72 example (O60722, "G72 End Face Stock Removal Cycle"), in inch:
/// D0.2 a side along Z from Z0.2, each pass to the profile moved by U0.03 (diameter) and W0.03,
/// the retract Setting 73 (here 0.05) at 45°, then along the moved profile; G70 finishes it, and
/// the bare G28 sends both axes home (the Haas manuals: "returns all axes … when no axis is
/// specified"), written as the 0i-TD's `G28 U0. W0.`.
#[test]
fn the_manuals_g72_example() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "O60722\nT101\nG00 G18 G20 G40 G80 G99\nG50 S1000\nG97 S500 M03\nG00 G54 X4.05 Z0.2\nM08\nG96 S200\nG72 P1 Q2 U0.03 W0.03 D0.2 F0.01\nN1 G00 Z-1.\nG01 X1.5\nX1. Z-0.75\nG01 Z0\nN2 X0\nG70 P1 Q2\nG28\nM30\n",
    );
    d.file("s.toml", "[cycles]\nsetting_73 = 0.05\n");
    let out = expand(
        &d,
        "p.nc",
        &["--control", "haas-lathe", "--params", "s.toml"],
    );
    let lines: Vec<&str> = out.lines().collect();
    // Passes at Z0, -0.2, -0.4, -0.6 reach X1.03 (the X1. wall plus U); at Z-0.8 the moved taper
    // (X1.5 Z-0.97 to X1. Z-0.72) is at X1.5 - 0.5·0.17/0.25 = 1.16, plus U: X1.19.
    for (z, x) in [
        ("Z0.", "X1.03"),
        ("Z-0.2", "X1.03"),
        ("Z-0.6", "X1.03"),
        ("Z-0.8", "X1.19"),
    ] {
        assert!(
            lines.windows(2).any(
                |w| w[0].ends_with(z) && w[1].starts_with(&format!("G1 {x}"))
                    || w[0] == z && w[1] == format!("G1 {x}")
            ),
            "{z} then {x} in\n{out}"
        );
    }
    // The retract after the pass at Z-0.8: 0.05 at 45° (X +0.1 on the diameter, Z +0.05).
    assert!(out.contains("G0 X1.29 Z-0.75"), "{out}");
    assert!(out.contains("G28 U0. W0."), "{out}");
    // Under Fanuc's rules a bare G28 moves nothing (it names no axis).
    d.file("g.nc", "O1\nG99 G0 X20. Z2.\nG28\nM30\n");
    let fanuc = expand(&d, "g.nc", &["--control", "fanuc-0i-t"]);
    assert!(!fanuc.contains("G28"), "{fanuc}");
    let haas = expand(&d, "g.nc", &["--control", "haas-lathe"]);
    assert!(haas.contains("G0 X20. Z2.\nG28 U0. W0.\n"), "{haas}");
}

/// "G73 Irregular Path Stock Removal Cycle": `G73 P Q U W I K D F` in one block, I and K the
/// relief from the first cut to the last (I a radius), D the number of passes: the Fanuc two-block
/// form `G73 U(I) W(K) R(D)` / `G73 P Q U W F`.
#[test]
fn a_one_block_g73_cuts_as_the_two_block_form() {
    let d = Dir::new();
    let haas = "O1\nG99 G0 X60. Z5.\nG73 P10 Q20 U0.4 W0.1 I3. K1. D3 F0.2\nN10 G0 X20. Z2.\nG1 Z-10.\nX40. Z-20.\nN20 X56.\nG70 P10 Q20\nM30\n";
    d.file("h.nc", haas);
    d.file(
        "f.nc",
        &haas.replace(
            "G73 P10 Q20 U0.4 W0.1 I3. K1. D3 F0.2",
            "G73 U3. W1. R3\nG73 P10 Q20 U0.4 W0.1 F0.2",
        ),
    );
    let h = expand(&d, "h.nc", &["--control", "haas-lathe"]);
    let f = expand(&d, "f.nc", &["--control", "fanuc-0i-t"]);
    assert_eq!(h, f);
    // By hand: the first pass starts 3 (radius) and 1 off the profile moved by U W: X20.4 + 6.0.
    assert!(h.contains("X26.4 Z3.1"), "{h}");
}

/// G04 P with a point is seconds, without milliseconds (the Haas operator's manuals, "G04
/// Dwell"); G154 P selects an additional work offset (Fanuc's G54.1 P, "G154 Select Work
/// Coordinates P1-P99"): the resolved output is the same as through G54.1.
#[test]
fn dwells_and_additional_work_offsets() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "O1\nG99 G0 X20. Z2.\nG04 P1.5\nG04 P500\nG154 P5\nG0 X30. Z5.\nM30\n",
    );
    d.file(
        "o.toml",
        "[work.G54]\nX = 0\nZ = 0\n[work.\"G54.1 P5\"]\nX = 10\nZ = -20\n",
    );
    // Written for a 0i-TD: G4 X seconds (its lathe habit); for a Haas (the haas-lathe control's
    // own dialect): G04 P seconds, always with a point (P500 without one would be 500 ms).
    let fanuc = expand(
        &d,
        "p.nc",
        &[
            "--control",
            "haas-lathe",
            "--offsets",
            "o.toml",
            "--dialect",
            "fanuc0itd",
        ],
    );
    assert!(fanuc.contains("G4 X1.5\nG4 X0.5\n"), "{fanuc}");
    let out = expand(
        &d,
        "p.nc",
        &["--control", "haas-lathe", "--offsets", "o.toml"],
    );
    assert!(out.contains("G4 P1.5\nG4 P0.5\n"), "{out}");
    // G54.1 P5 lies 10 from G54 in X (a radius in --offsets: 20 on the diameter) and -20 in Z:
    // X30. Z5. in it is X50. Z-15. in G54, the frame the output is written in.
    assert!(out.contains("X50. Z-15."), "{out}");
    d.file("q.nc", "O1\nG154 P60\nM30\n");
    refused(
        &d,
        &haas_run("q.nc", &["--resolve"]),
        4,
        &["G154 P60: fmsvm keeps the first 48"],
    );
}

/// "G76 Threading Cycle, Multiple Pass": `G76 X Z K D F A` in one block, K the thread height and
/// D the first depth (radii), A the tool angle; the finish allowance, least cut and end chamfer
/// are the control's Settings 86, 99 and 95. It cuts as the Fanuc two-block form
/// `G76 P(01 00 60) Q(Setting 99) R(Setting 86)` / `G76 X Z P(K) Q(D) F`.
#[test]
fn a_one_block_g76_cuts_as_the_two_block_form() {
    let d = Dir::new();
    let haas =
        "O1\nG99 G97 S500 M3\nG0 X22. Z5.\nG76 X16.93 Z-25. K1.534 D0.485 A60 F2.5\nG0 X50.\nM30\n";
    d.file("h.nc", haas);
    d.file(
        "f.nc",
        &haas.replace(
            "G76 X16.93 Z-25. K1.534 D0.485 A60 F2.5",
            "G76 P010060 Q100 R0.02\nG76 X16.93 Z-25. P1534 Q485 F2.5",
        ),
    );
    d.file(
        "s.toml",
        "[cycles]\nsetting_86 = 0.02\nsetting_99 = 0.1\nsetting_95 = 0\n",
    );
    let h = expand(
        &d,
        "h.nc",
        &["--control", "haas-lathe", "--params", "s.toml"],
    );
    let f = expand(&d, "f.nc", &["--control", "fanuc-0i-t"]);
    assert_eq!(h, f);
    // By hand: the crest is X16.93 + 2·1.534 = X19.998; the first pass 0.485 deep (X19.028),
    // starting 0.485·tan 30° = 0.28 along the cut (Z4.72); the last two at K − Setting 86 = 1.514
    // (X16.97) and at K (X16.93).
    let lines: Vec<&str> = h.lines().collect();
    for want in [
        ["Z4.72", "X19.028", "G32 Z-25. F2.5"],
        ["Z4.114", "X16.93", "G32 Z-25. F2.5"],
    ] {
        assert!(lines.windows(3).any(|w| w == want), "{want:?} in\n{h}");
    }
    assert!(h.contains("X16.97\nG32 Z-25. F2.5"), "{h}");
    // Without the settings, or with a chamfer, or P2, refused at the cycle.
    for (params, block, says) in [
        (
            "[cycles]\n",
            "G76 X16.93 Z-25. K1.534 D0.485 A60 F2.5",
            "Settings 86, 99 and 95",
        ),
        (
            "[cycles]\nsetting_86 = 0.02\nsetting_99 = 0.1\nsetting_95 = 1\n",
            "G76 X16.93 Z-25. K1.534 D0.485 A60 F2.5",
            "end chamfer",
        ),
        (
            "[cycles]\nsetting_86 = 0.02\nsetting_99 = 0.1\nsetting_95 = 0\n",
            "G76 X16.93 Z-25. K1.534 D0.485 A60 P2 F2.5",
            "only P1",
        ),
    ] {
        d.file("t.toml", params);
        d.file(
            "q.nc",
            &haas.replace("G76 X16.93 Z-25. K1.534 D0.485 A60 F2.5", block),
        );
        refused(
            &d,
            &haas_run("q.nc", &["--params", "t.toml", "--resolve", "-o", "out.nc"]),
            4,
            &[says, "q.nc:4:1"],
        );
    }
}

/// G74/G75 in Haas's one-block form: their words' units and retract are not in the Haas text at
/// hand, so they are refused with what to write instead, not read as Fanuc's second block.
#[test]
fn a_one_block_g75_is_refused_saying_why() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "O1\nG99 G0 X52. Z-10.\nG75 X30. Z-20. I2. K3. F0.1\nM30\n",
    );
    refused(
        &d,
        &haas_run("p.nc", &["--resolve"]),
        4,
        &["G75 in Haas's one-block form", "p.nc:3:1"],
    );
}

/// Turning centres: a Swiss-type program is named at its first path header, an Okuma OSP one at
/// its first variable; Y (V its increment) on a lathe that declares no Y axis, and polar
/// coordinate interpolation, are refused saying what is missing, not read as other words (a
/// `G28 V0` returning X and Z would move axes the program did not name).
#[test]
fn turning_centres_and_other_languages_are_refused_saying_what_they_are() {
    let d = Dir::new();
    for (text, line, says) in [
        (
            "O1000\n(PART)\n$1\nG50 Z0\n!2L10\nM30\n",
            3,
            "Citizen Cincom, Star",
        ),
        ("O1\nG50 S2000\nVC1=10\nM02\n", 3, "Okuma OSP"),
    ] {
        d.file("p.nc", text);
        let at = format!("p.nc:{line}:1");
        refused(&d, &haas_run("p.nc", &["--resolve"]), 3, &[says, &at]);
    }
    for (block, says) in [
        ("G28 V0", "V: this lathe has no Y axis"),
        ("G0 Y0", "Y: this lathe has no Y axis"),
        ("G112", "polar coordinate interpolation"),
    ] {
        d.file("p.nc", &format!("O1\nG99 G0 X20. Z2.\n{block}\nM30\n"));
        refused(
            &d,
            &haas_run("p.nc", &["--resolve"]),
            4,
            &[says, "p.nc:3:1"],
        );
    }
}

/// A Haas program goes to every lathe dialect through the lathe kernel, each output read back
/// (`--verify`); a dialect without a return of its own writes G28 as a move to the reference
/// position, which the offsets give (with G54, through which it is reached).
#[test]
fn a_haas_program_in_every_lathe_dialect() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "O1\nG99 G0 X52. Z2.\nG71 P10 Q20 U0.5 W0.1 D2. F0.25\nN10 G0 X20.\nG1 Z-15.\nX30. Z-25.\nZ-40.\nN20 X50.\nG70 P10 Q20\nG28 U0 W0\nM30\n",
    );
    d.file("s.toml", SETTING_73);
    d.file(
        "o.toml",
        "[reference.G28]\nX = 200\nZ = 100\n[work.G54]\nX = 0\nZ = 0\n",
    );
    let mut all = Vec::new();
    for dialect in [
        "fanuc0itd",
        "haaslathe",
        "mayak600t",
        "nc31",
        "sinumerik802d",
        "fagor8035t",
        "linuxcnc",
        "iso",
    ] {
        let out = expand(
            &d,
            "p.nc",
            &[
                "--control",
                "haas-lathe",
                "--params",
                "s.toml",
                "--offsets",
                "o.toml",
                "--dialect",
                dialect,
            ],
        );
        all.push(out);
    }
    // A Haas writes this program as a 0i-TD does (no dwell here, where they differ); the rest are
    // seven different spellings of the same motion.
    assert_eq!(all[0], all[1], "fanuc0itd and haaslathe");
    all.sort();
    all.dedup();
    assert_eq!(all.len(), 7);
}

/// Literal output for a Haas (`--control haas-lathe` writes for its own `haaslathe` dialect): the
/// Haas's one-block cycles, a profile under tool nose compensation (G42 in its first block, as Haas
/// programs write it), a one-block G75, G04 P and G154 are kept as the program wrote them; D
/// (the depth of cut, a length) keeps its point, G76's A none ("Do not use a decimal point").
/// The one-block G75 is the control's to run (its moves are not resolved).
#[test]
fn literal_output_for_a_haas_keeps_its_forms() {
    let d = Dir::new();
    let program = "O1\nG20 G99 G0 X1.6 Z0.1\nG71 P10 Q20 U0.01 W0.005 D0.05 F0.01\nN10 G0 G42 X0.3\nG1 Z-0.5\nX1.0 Z-1.\nN20 G0 G40 X1.6\nG70 P10 Q20\nG76 X0.4069 Z-1.5 K0.0431 D0.0108 A60 F0.076923\nG04 P1.5\nG154 P5\nG0 X1.6 Z-2.\nG75 X0.5 I0.005 F0.004\nG0 X1.6\nM30\n";
    d.file("p.nc", program);
    let o = d.run(&haas_run("p.nc", &["-o", "out.nc"]));
    assert!(o.status.success(), "{}", stderr(&o));
    let out = d.read("out.nc");
    for line in [
        "G71 P10 Q20 U0.01 W0.005 D0.05 F0.01\nN10 G0 G42 X0.3\n",
        "N20 G0 G40 X1.6\nG70 P10 Q20\n",
        // The lead keeps the finer decimals of a feed per revolution (Fanuc IS-B inch:
        // 0.000001 in/rev): 1/13 in is F0.076923, not F0.0769.
        "G76 X0.4069 Z-1.5 K0.0431 D0.0108 A60 F0.076923\n",
        // G04 P1.5 (seconds) as the literal output writes a dwell: P in milliseconds, which the
        // Haas reads so without a point ("G04 P10 is a dwell of 10 milliseconds").
        "G4 P1500\nG154 P5\n",
        "G75 X0.5 I0.005 F0.004\n",
    ] {
        assert!(out.contains(line), "{line} in {out}");
    }
    // Proof by reading back resolves both: what it cannot resolve is named at its line (the
    // compensated profile, then the G75).
    d.file("s.toml", SETTING_73);
    refused(
        &d,
        &haas_run("p.nc", &["--params", "s.toml", "-o", "v.nc", "--verify"]),
        7,
        &["tool nose radius compensation", "p.nc:4:1"],
    );
    d.file(
        "all.toml",
        "[cycles]\nsetting_73 = 0.02\nsetting_86 = 0.001\nsetting_95 = 0\nsetting_99 = 0.001\n",
    );
    d.file(
        "g75.nc",
        &program
            .replace("N10 G0 G42 X0.3", "N10 G0 X0.3")
            .replace("N20 G0 G40 X1.6", "N20 G0 X1.6"),
    );
    refused(
        &d,
        &haas_run(
            "g75.nc",
            &["--params", "all.toml", "-o", "v.nc", "--verify"],
        ),
        7,
        &["G75 in Haas's one-block form", "g75.nc:13:1"],
    );
}

/// `--verify` of literal output for a Haas resolves the program and the output alike: it needs
/// what resolving needs (Setting 73 for a one-block G71), and with it reads the same motion.
#[test]
fn literal_output_for_a_haas_is_verified_by_resolving_both() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "O1\nG99 G0 X52. Z2.\nG71 P10 Q20 U0.5 W0.1 D2. F0.25\nN10 G0 X20.\nG1 Z-15.\nX30. Z-25.\nN20 X50.\nG70 P10 Q20\nG04 P0.5\nM30\n",
    );
    let args = haas_run("p.nc", &["-o", "out.nc", "--verify"]);
    refused(&d, &args, 7, &["Setting 73", "p.nc:3:1"]);
    assert!(
        !d.path("out.nc").exists(),
        "an unverified output is not left"
    );
    d.file("s.toml", SETTING_73);
    let mut with = args.to_vec();
    with.extend(["--params", "s.toml"]);
    let o = d.run(&with);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("verified"), "{}", stderr(&o));
    assert!(
        d.read("out.nc")
            .contains("G71 P10 Q20 U0.5 W0.1 D2. F0.25\n")
    );
}

/// A turning centre's Y axis (`[machine] y_axis = true`): Y a position moved by G0/G1, V its
/// increment (`G28 V0` returns Y through where it stands, as `G28 U0 W0` does X and Z), written by
/// the dialects whose lathes have one (the Haas ST-…Y, the 0i-TD's Y-axis option) and refused by
/// the others at the block; never in an arc or a cycle. By hand: the output repeats the program's
/// moves, Y unmoved until it is named.
#[test]
fn a_turning_centres_y_axis() {
    let d = Dir::new();
    d.file("y.toml", "[machine]\ny_axis = true\n");
    d.file(
        "p.nc",
        "O1\nG99 G0 X50. Z2.\nG1 Z-10. F0.2\nG0 X60.\nY10.\nG1 X20. F0.1\nG0 Y0\nG28 V0\nG28 U0 W0\nM30\n",
    );
    for dialect in ["haaslathe", "fanuc0itd"] {
        let out = expand(
            &d,
            "p.nc",
            &[
                "--control",
                "haas-lathe",
                "--params",
                "y.toml",
                "--dialect",
                dialect,
            ],
        );
        assert!(
            out.contains("G0 X50. Z2.\nG1 Z-10. F0.2\nG0 X60.\nY10.\nG1 X20. F0.1\nG0 Y0.\nG28 V0.\nG28 U0. W0.\n"),
            "{dialect}: {out}"
        );
    }
    for dialect in ["mayak600t", "sinumerik802d", "linuxcnc"] {
        refused(
            &d,
            &haas_run(
                "p.nc",
                &[
                    "--params",
                    "y.toml",
                    "--dialect",
                    dialect,
                    "--machine",
                    "lathe",
                ],
            ),
            4,
            &["a Y move", "p.nc:5:1"],
        );
    }
    // In an arc, a Y would be a helix; in a cycle, an offset the cycle does not know.
    for block in ["G2 X30. Z-15. R5. Y2.", "G90 X40. Z-20. Y1. F0.2"] {
        d.file("q.nc", &format!("O1\nG99 G0 X50. Z2.\n{block}\nM30\n"));
        refused(
            &d,
            &haas_run("q.nc", &["--params", "y.toml", "--resolve"]),
            4,
            &["moves with G0 or G1", "q.nc:3:1"],
        );
    }
}
