//! `fmsvm post`: every neutral word means on the control what the library meant (docs/postprocessor.md,
//! "Writing for the control" and "The controls' words"). Each expected line is worked out by hand
//! from the control's manual or vendor post named beside it.

use crate::cli_support;

use cli_support::{Dir, stdout};

/// Runs `post` for `control` on `input` with `extra` options: its standard output and output.tmp.
fn post(control: &str, input: &str, extra: &[&str]) -> (String, Option<String>) {
    let d = Dir::new();
    d.file("input.tmp", input);
    let mut args = vec!["post", "--dialect", control];
    args.extend_from_slice(extra);
    args.push("input.tmp");
    let o = d.run(&args);
    let out = d.path("output.tmp").exists().then(|| d.read("output.tmp"));
    (stdout(&o), out)
}

#[test]
fn the_neutral_g90_never_reaches_a_system_a_fanuc_and_the_feed_is_per_revolution() {
    // 0i-TD G-code list, system A: G90 is the outer/inner diameter cutting cycle; absolute is the X
    // Z words themselves. The neutral F is per revolution: G99 on the first block.
    let (said, out) = post(
        "fanuc0itd",
        "N001 G90 G00 X80 Z5\nN002 G01 X60 F0.2\nN003 G00 X80\nN004 M30\n",
        &[],
    );
    assert_eq!(said, "OK\n");
    assert_eq!(
        out.as_deref(),
        Some("N001 G18 G21 G99 G00 X80. Z5.\nN002 G01 X60. F0.2\nN003 G00 X80.\nN004 M30\n")
    );
    // An ISO-numbered control keeps G90 and says G95 (ISO 6983-1: G71 metric).
    let (said, out) = post("iso", "N001 G90 G00 X80 Z5\nN002 M30\n", &[]);
    assert_eq!(said, "OK\n");
    assert_eq!(
        out.as_deref(),
        Some("N001 G18 G90 G71 G95 G00 X80. Z5.\nN002 M30\n")
    );
}

#[test]
fn constant_surface_speed_needs_the_machines_clamp() {
    let input = "N001 G00 X80 Z2\nN002 G96 S180 M03\nN003 G01 X0 F0.2\nN004 G97 S800\nN005 M30\n";
    // No clamp known: refused at the G96 word, no output (Fanuc: not clamped at power-on).
    for control in ["fanuc0itd", "sinumerik802d", "fagor8035t"] {
        let (said, out) = post(control, input, &[]);
        assert!(
            said.starts_with("input.tmp:2:6: G96 (constant surface speed) with no spindle clamp"),
            "{control}: {said}"
        );
        assert!(out.is_none(), "{control}");
    }
    // With the machine's highest speed, the clamp goes first in the control's words.
    for (control, clamp) in [
        ("fanuc0itd", "N002 G50 S2500\nN003 G96 S180 M03\n"),
        ("sinumerik802d", "N002 LIMS=2500\nN003 G96 S180 M03\n"),
        ("fagor8035t", "N002 G92 S2500\nN003 G96 S180 M03\n"),
    ] {
        let (said, out) = post(control, input, &["--max-rpm", "2500"]);
        assert_eq!(said, "OK\n", "{control}");
        let out = out.unwrap_or_default();
        assert!(out.contains(clamp), "{control}: {out}");
    }
}

#[test]
fn dwells_and_tool_calls_are_the_controls_own() {
    let input = "N001 G00 X40 Z2 T0101\nN002 G04 X1.5\nN003 M30\n";
    // Fanuc G04 X seconds; SINUMERIK G4 F seconds and T1 D1 (tool, cutting edge); FAGOR G04 K in
    // hundredths (its 8037/8055 T post) and T1 D1: 1.5 s is K150.
    for (control, first, dwell) in [
        (
            "fanuc0itd",
            "N001 G18 G21 G99 G00 X40. Z2. T0101",
            "N002 G04 X1.5",
        ),
        (
            "sinumerik802d",
            "N001 G18 G90 DIAMON G71 G95 G00 X40 Z2 T1 D1",
            "N002 G04 F1.5",
        ),
        (
            "fagor8035t",
            "N001 G18 G90 G151 G71 G95 G00 X40 Z2 T1 D1",
            "N002 G04 K150",
        ),
    ] {
        let (said, out) = post(control, input, &[]);
        assert_eq!(said, "OK\n", "{control}");
        let out = out.unwrap_or_default();
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines[0], first, "{control}");
        assert_eq!(lines[1], dwell, "{control}");
    }
    // A dwell longer than FAGOR's K holds (9999 hundredths) is refused, not cut short.
    let (said, _) = post("fagor8035t", "N001 G04 X120\nN002 M30\n", &[]);
    assert!(
        said.contains("longer than the control's dwell word"),
        "{said}"
    );
}

#[test]
fn a_number_past_the_controls_digits_is_refused_as_run_refuses_it() {
    let (said, out) = post("fanuc0itd", "N001 G00 X123456789 Z2\nN002 M30\n", &[]);
    assert!(
        said.starts_with("input.tmp:1:10: alarm 0003: too many digits"),
        "{said}"
    );
    assert!(out.is_none());
}

#[test]
fn an_arc_by_r_goes_out_with_its_centre() {
    // From X60 Z2 to X70 Z-3 (diameters), G02 R5: the centre 5 mm out in X from the start, at the
    // start's Z (the radius 5 from both ends: (35−35, −3−2) and (30−35, 2−2) in radius), I5 K0.
    let (said, out) = post(
        "sinumerik802d",
        "N001 G00 X60 Z2\nN002 G02 X70 Z-3 R5 F0.1\nN003 M30\n",
        &[],
    );
    assert_eq!(said, "OK\n");
    assert!(
        out.unwrap_or_default()
            .contains("N002 G02 X70 Z-3 I5 K0 F0.1\n"),
    );
}

#[test]
fn the_mayak_g72_states_only_a_trapezoid_and_computes_its_taper() {
    // A cone from Ø118 at Z4.31 to Ø140 at Z-136.98, then the face to Ø156.31: K = (140 − 118) /
    // 141.29 = 0.15571 (ГОСТ 25548's конусность), written to four decimals.
    let cone = "N006 S500 F1.2\nN007 G00 X156.31 Z4.31\n\
        N008 CYCLE 72 I=5 B=0.5 VP=1 C=95 P=5 _Xbegin=118 _Zbegin=4.31 _Xend=156.31 _Zend=-136.98\n\
        N009 X140 Z-136.98\nN010 X156.31\nN011 G80\nN012 G00 X156.31 Z4.31\n";
    let (said, out) = post("mayak600t", cone, &[]);
    assert_eq!(said, "OK\n");
    assert!(
        out.unwrap_or_default()
            .contains("G72 X156.31 Z-136.98 I5 B0.5 VP1 C95 K0.1557 P=5\n"),
    );
    // Ø118 to Z-100, then a cone to Ø140: three moves, no trapezoid: refused at the record, where
    // the block would have said K0 (a cylinder: up to 11 mm overcut on the radius).
    let two = "N006 S500 F1.2\nN007 G00 X156.31 Z4.31\n\
        N008 CYCLE 72 I=5 B=0.5 VP=1 C=95 P=5 _Xbegin=118 _Zbegin=4.31 _Xend=156.31 _Zend=-136.98\n\
        N009 Z-100\nN010 X140 Z-136.98\nN011 X156.31\nN012 G80\nN013 G00 X156.31 Z4.31\n";
    let (said, out) = post("mayak600t", two, &[]);
    assert!(
        said.starts_with("input.tmp:3:1: CYCLE 72: the control's block states a trapezoid"),
        "{said}"
    );
    assert!(out.is_none());
    // A step with an R5 arc: refused likewise.
    let arc = "N006 S500 F1.2\nN007 G00 X80 Z2\n\
        N008 CYCLE 72 I=2 P=5 _Xbegin=54 _Zbegin=2 _Xend=80 _Zend=-80\n\
        N009 Z-40\nN010 G02 X64 Z-45 R5\nN011 G01 Z-80\nN012 X80\nN013 G80\nN014 G00 X80 Z2\n";
    let (said, _) = post("mayak600t", arc, &[]);
    assert!(said.contains("is an arc"), "{said}");
    // The profile's first block naming X and Z where only Z changes is still a cylinder: K0.
    let words = "N006 S500 F1.2\nN007 G00 X156.31 Z4.31\n\
        N008 CYCLE 72 I=5 B=0.5 VP=1 C=95 P=5 _Xbegin=118 _Zbegin=4.31 _Xend=156.31 _Zend=-136.98\n\
        N009 X118 Z-136.98\nN010 X156.31\nN011 G80\nN012 G00 X156.31 Z4.31\n";
    let (said, out) = post("mayak600t", words, &[]);
    assert_eq!(said, "OK\n");
    assert!(out.unwrap_or_default().contains(" K0 P=5\n"));
}

#[test]
fn the_mayak_block_numbers_wrap_after_999() {
    // The Маяк-600Т's profile: at most N999, then N001 again.
    let mut input = String::new();
    for k in 0..1001 {
        input.push_str(&format!("N{:03} G00 X{} Z2\n", k + 1, 40 + k % 2));
    }
    let (said, out) = post("mayak600t", &input, &[]);
    assert_eq!(said, "OK\n");
    let out = out.unwrap_or_default();
    let lines: Vec<&str> = out.lines().collect();
    assert!(lines[998].starts_with("N999 "), "{}", lines[998]);
    assert!(lines[999].starts_with("N001 "), "{}", lines[999]);
    assert!(!out.contains("N1000"));
}

#[test]
fn threads_need_constant_rpm_clearance_and_a_floating_holder() {
    let thread = |start_x: &str, speed: &str| {
        format!(
            "N001 {speed} M03\nN002 G00 X{start_x} Z2\n\
             N003 CYCLE 76 _FEED=1.5 _DEPTH=0.92 _NTHREADS=1 _Xbegin=18.16 _Zbegin=2 _Xend=18.16 _Zend=-20\n\
             N004 G00 X{start_x} Z2\nN005 M30\n"
        )
    };
    // The crest is at Ø18.16 + 2·0.92 = Ø20: a start at Ø22 clears it by 1 mm on the radius.
    let (said, _) = post("iso", &thread("22", "G97 S500"), &[]);
    assert_eq!(said, "OK\n");
    // A start on the crest: every pass would return along the finished thread.
    let (said, _) = post("iso", &thread("20", "G97 S500"), &[]);
    assert!(said.contains("is not 0.5 mm outside the thread"), "{said}");
    // Under G96 (802D: native CSS): threads are cut at constant rpm.
    let (said, _) = post(
        "sinumerik802d",
        &thread("22", "G96 S100"),
        &["--max-rpm", "2000"],
    );
    assert!(said.contains("a thread under G96"), "{said}");
    // Tapping in elementary moves: only with a floating holder, which no built-in profile declares.
    let tap = "N001 G97 S300 M03\nN002 G00 X0 Z5\n\
        N003 CYCLE 84 _FEED=1.5 _NTHREADS=1 _Zbegin=3 _Zend=-20\nN004 M30\n";
    let (said, _) = post("iso", tap, &[]);
    assert!(said.contains("floating tap holder"), "{said}");
}
