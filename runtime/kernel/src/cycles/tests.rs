use super::*;

/// A G81 block with nothing in it, G90 G98 G17, spindle clockwise: the tests fill it in.
const NONE: CycleBlock = CycleBlock {
    cycle: Cycle::G81,
    plane: Plane::XY,
    incremental: false,
    retract_to_r: false,
    at: [None, None],
    depth: None,
    r: None,
    q: None,
    p: None,
    repeats: None,
    shift: [None, None],
    spindle_ccw: false,
};

fn pose(v: &[f64]) -> Pose {
    let mut p = [0.0; 6];
    p.copy_from_slice(v);
    p
}

/// The steps of canonical calls as `rs274 -g` prints them (rs274's line counter and N field cut
/// off, as `runtime/kernel/tests/cycles/regenerate.sh` writes them); `//` lines are comments.
fn parse(trace: &str) -> Vec<Step> {
    let mut steps = Vec::new();
    for line in trace.lines().map(str::trim) {
        if line.is_empty() || line.starts_with("//") {
            continue;
        }
        let (name, args) = line.split_once('(').expect("a call");
        let args: Vec<f64> = args
            .trim_end_matches(')')
            .split(',')
            .filter(|a| !a.trim().is_empty())
            .map(|a| a.trim().parse().expect("a number"))
            .collect();
        steps.push(match name {
            "STRAIGHT_TRAVERSE" => Step::Rapid(pose(&args)),
            "STRAIGHT_FEED" => Step::Feed(pose(&args)),
            "DWELL" => Step::Dwell(args[0]),
            "STOP_SPINDLE_TURNING" => Step::Spindle(SpindleAction::Stop),
            "START_SPINDLE_CLOCKWISE" => Step::Spindle(SpindleAction::Clockwise),
            "START_SPINDLE_COUNTERCLOCKWISE" => Step::Spindle(SpindleAction::CounterClockwise),
            "ORIENT_SPINDLE" => Step::Spindle(SpindleAction::Orient),
            "PROGRAM_STOP" => Step::Stop,
            _ => panic!("unknown canonical call {line}"),
        });
    }
    steps
}

/// Expands `blocks` one after the other from `start` (the kernel's part: the tool ends where
/// each block leaves it), with LinuxCNC's parameters.
fn run(start: Pose, inch: bool, blocks: &[CycleBlock]) -> Result<(Vec<Step>, Pose), Stop> {
    run_with(start, inch, &CycleParams::default(), blocks)
}

fn run_with(
    start: Pose,
    inch: bool,
    params: &CycleParams,
    blocks: &[CycleBlock],
) -> Result<(Vec<Step>, Pose), Stop> {
    let mut modal = CycleModal::default();
    let mut steps = Vec::new();
    let mut at = start;
    for b in blocks {
        at = expand(&mut modal, b, at, inch, params, &mut |s| {
            steps.push(s);
            Ok(())
        })?;
    }
    Ok((steps, at))
}

fn close(a: &Pose, b: &Pose) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-4)
}

fn same(a: &Step, b: &Step) -> bool {
    match (a, b) {
        (Step::Rapid(p), Step::Rapid(q)) | (Step::Feed(p), Step::Feed(q)) => close(p, q),
        (Step::Dwell(s), Step::Dwell(t)) => (s - t).abs() < 1e-4,
        _ => a == b,
    }
}

/// Runs `blocks` and compares the steps with `trace` and the end with `end`, to 1e-4.
#[track_caller]
fn check(start: Pose, inch: bool, blocks: &[CycleBlock], trace: &str, end: Pose) {
    let (steps, at) = run(start, inch, blocks).expect("no alarm");
    let want = parse(trace);
    let ok = steps.len() == want.len() && steps.iter().zip(&want).all(|(a, b)| same(a, b));
    assert!(ok, "steps differ\n got: {steps:#?}\nwant: {want:#?}",);
    assert!(close(&at, &end), "ends at {at:?}, want {end:?}");
}

#[track_caller]
fn alarm_of(r: Result<(Vec<Step>, Pose), Stop>) -> (u32, String) {
    match r {
        Err(Stop::Alarm(a)) => (a.number, a.message.into_owned()),
        Err(other) => panic!("not an alarm: {other}"),
        Ok((steps, _)) => panic!("no alarm; steps {steps:?}"),
    }
}

const XYZ10: Pose = [0.0, 0.0, 10.0, 0.0, 0.0, 0.0];

// In each test below taken from LinuxCNC, the expected steps are the lines of
// runtime/kernel/tests/cycles/NAME.trace (rs274 -g NAME.ngc) from the cycle's first move to the last
// step before the program end (M2 stops the spindle); NAME is the test's. The program's text is
// quoted in the comment, one block a `/`. A Fanuc P in ms is written in seconds in the .ngc.

#[test]
fn g81_g98() {
    // G21 G17 G90 G94 F100 S1000 M3 / G0 X0 Y0 Z10 / G98 G81 X1 Y2 Z-5 R2 / X3 / Y4 Z-3 / G80
    let first = CycleBlock {
        cycle: Cycle::G81,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-5.0),
        r: Some(2.0),
        ..NONE
    };
    let x3 = CycleBlock {
        cycle: Cycle::G81,
        at: [Some(3.0), None],
        ..NONE
    };
    let y4 = CycleBlock {
        cycle: Cycle::G81,
        at: [None, Some(4.0)],
        depth: Some(-3.0),
        ..NONE
    };
    check(
        XYZ10,
        false,
        &[first, x3, y4],
        "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 4.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 4.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(3.0000, 4.0000, -3.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 4.0000, 10.0000, 0.0000, 0.0000, 0.0000)
    ",
        [3.0, 4.0, 10.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g81_g99_then_r_raised_then_g98_g99_per_block() {
    // G99 G81 X1 Y2 Z-5 R2 / X3 R3 / G98 X5 / G99 X6 (from X0 Y0 Z10). A new R under G99 and the
    // G98 block after G99 position diagonally to the return level (LinuxCNC's CYCLE_MACRO).
    let g99 = CycleBlock {
        cycle: Cycle::G81,
        retract_to_r: true,
        ..NONE
    };
    let blocks = [
        CycleBlock {
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            ..g99
        },
        CycleBlock {
            at: [Some(3.0), None],
            r: Some(3.0),
            ..g99
        },
        CycleBlock {
            cycle: Cycle::G81,
            at: [Some(5.0), None],
            ..NONE
        },
        CycleBlock {
            at: [Some(6.0), None],
            ..g99
        },
    ];
    check(
        XYZ10,
        false,
        &blocks,
        "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(5.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(5.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(5.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(5.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(6.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(6.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(6.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(6.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
    ",
        [6.0, 2.0, 3.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g81_starting_below_r() {
    // G0 X0 Y0 Z0 / G98 G81 X1 Y2 Z-5 R2 / X3: up to R first; R is then the G98 level too (and
    // LinuxCNC repeats the move up to R, of length 0, in the second block).
    let blocks = [
        CycleBlock {
            cycle: Cycle::G81,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            ..NONE
        },
        CycleBlock {
            cycle: Cycle::G81,
            at: [Some(3.0), None],
            ..NONE
        },
    ];
    check(
        [0.0; 6],
        false,
        &blocks,
        "
        STRAIGHT_TRAVERSE(0.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
    ",
        [3.0, 2.0, 2.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g81_g91_g98_repeats_step() {
    // G91 G98 G81 X10 Y5 Z-7 R-8 L3 / X-5 L2 (from X0 Y0 Z10): R = 10 - 8 = 2, bottom = 2 - 7 = -5.
    let blocks = [
        CycleBlock {
            cycle: Cycle::G81,
            incremental: true,
            at: [Some(10.0), Some(5.0)],
            depth: Some(-7.0),
            r: Some(-8.0),
            repeats: Some(3.0),
            ..NONE
        },
        CycleBlock {
            cycle: Cycle::G81,
            incremental: true,
            at: [Some(-5.0), None],
            repeats: Some(2.0),
            ..NONE
        },
    ];
    check(
        XYZ10,
        false,
        &blocks,
        "
        STRAIGHT_TRAVERSE(10.0000, 5.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(10.0000, 5.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(10.0000, 5.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(10.0000, 5.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(20.0000, 10.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(20.0000, 10.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(20.0000, 10.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(20.0000, 10.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(30.0000, 15.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(30.0000, 15.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(30.0000, 15.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(30.0000, 15.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(25.0000, 15.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(25.0000, 15.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(25.0000, 15.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(25.0000, 15.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(20.0000, 15.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(20.0000, 15.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(20.0000, 15.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(20.0000, 15.0000, 10.0000, 0.0000, 0.0000, 0.0000)
    ",
        [20.0, 15.0, 10.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g81_g91_g99_r_from_the_initial_level() {
    // G91 G99 G81 X10 Z-7 R-8 L2 / Y5 R-6 (from X0 Y0 Z10): the new R is 10 - 6 = 4, from the
    // initial level, not from where the tool is (R2).
    let blocks = [
        CycleBlock {
            cycle: Cycle::G81,
            incremental: true,
            retract_to_r: true,
            at: [Some(10.0), None],
            depth: Some(-7.0),
            r: Some(-8.0),
            repeats: Some(2.0),
            ..NONE
        },
        CycleBlock {
            cycle: Cycle::G81,
            incremental: true,
            retract_to_r: true,
            at: [None, Some(5.0)],
            r: Some(-6.0),
            ..NONE
        },
    ];
    check(
        XYZ10,
        false,
        &blocks,
        "
        STRAIGHT_TRAVERSE(10.0000, 0.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(10.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(10.0000, 0.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(10.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(20.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(20.0000, 0.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(20.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(20.0000, 5.0000, 4.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(20.0000, 5.0000, -3.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(20.0000, 5.0000, 4.0000, 0.0000, 0.0000, 0.0000)
    ",
        [20.0, 5.0, 4.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g81_g90_repeats_the_same_hole() {
    // G99 G81 X1 Y2 Z-5 R2 L3 (from X0 Y0 Z10)
    let b = CycleBlock {
        cycle: Cycle::G81,
        retract_to_r: true,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-5.0),
        r: Some(2.0),
        repeats: Some(3.0),
        ..NONE
    };
    check(
        XYZ10,
        false,
        &[b],
        "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
    ",
        [1.0, 2.0, 2.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g81_g18_drills_along_y() {
    // G18 / G0 X0 Y10 Z0 / G98 G81 Z1 X2 Y-5 R2 / Z3: the plane words are (Z, X), the depth is Y.
    let g18 = CycleBlock {
        cycle: Cycle::G81,
        plane: Plane::ZX,
        ..NONE
    };
    let blocks = [
        CycleBlock {
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            ..g18
        },
        CycleBlock {
            at: [Some(3.0), None],
            ..g18
        },
    ];
    let start = [0.0, 10.0, 0.0, 0.0, 0.0, 0.0];
    check(
        start,
        false,
        &blocks,
        "
        STRAIGHT_TRAVERSE(2.0000, 10.0000, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(2.0000, -5.0000, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 10.0000, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 10.0000, 3.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(2.0000, -5.0000, 3.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 10.0000, 3.0000, 0.0000, 0.0000, 0.0000)
    ",
        [2.0, 10.0, 3.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g81_g19_drills_along_x() {
    // G19 / G0 X10 Y0 Z0 / G99 G81 Y1 Z2 X-5 R2 / Y3: the plane words are (Y, Z), the depth is X.
    let g19 = CycleBlock {
        cycle: Cycle::G81,
        plane: Plane::YZ,
        retract_to_r: true,
        ..NONE
    };
    let blocks = [
        CycleBlock {
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            ..g19
        },
        CycleBlock {
            at: [Some(3.0), None],
            ..g19
        },
    ];
    let start = [10.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    check(
        start,
        false,
        &blocks,
        "
        STRAIGHT_TRAVERSE(10.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(-5.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 3.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(-5.0000, 3.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 3.0000, 2.0000, 0.0000, 0.0000, 0.0000)
    ",
        [2.0, 3.0, 2.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g81_g19_g91_repeats() {
    // G19 / G0 X10 Y0 Z0 / G91 G98 G81 Y1 Z2 X-6 R-7 L2: R = 10 - 7 = 3, bottom = 3 - 6 = -3.
    let b = CycleBlock {
        cycle: Cycle::G81,
        plane: Plane::YZ,
        incremental: true,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-6.0),
        r: Some(-7.0),
        repeats: Some(2.0),
        ..NONE
    };
    let start = [10.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    check(
        start,
        false,
        &[b],
        "
        STRAIGHT_TRAVERSE(10.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(-3.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(10.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(10.0000, 2.0000, 4.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 4.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(-3.0000, 2.0000, 4.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(10.0000, 2.0000, 4.0000, 0.0000, 0.0000, 0.0000)
    ",
        [10.0, 2.0, 4.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g81_keeps_a_b_c() {
    // G0 X0 Y0 Z10 A15 B-5 C30 / G98 G81 X1 Y2 Z-5 R2
    let b = CycleBlock {
        cycle: Cycle::G81,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-5.0),
        r: Some(2.0),
        ..NONE
    };
    let start = [0.0, 0.0, 10.0, 15.0, -5.0, 30.0];
    check(
        start,
        false,
        &[b],
        "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 15.0000, -5.0000, 30.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 15.0000, -5.0000, 30.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 15.0000, -5.0000, 30.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 15.0000, -5.0000, 30.0000)
    ",
        [1.0, 2.0, 10.0, 15.0, -5.0, 30.0],
    );
}

#[test]
fn a_block_without_position_drills_nothing() {
    // G98 G81 X1 Y2 Z-5 R2 / F50: the F block makes no move (LinuxCNC and Fanuc).
    let blocks = [
        CycleBlock {
            cycle: Cycle::G81,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            ..NONE
        },
        CycleBlock {
            cycle: Cycle::G81,
            ..NONE
        },
    ];
    check(
        XYZ10,
        false,
        &blocks,
        "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
    ",
        [1.0, 2.0, 10.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g73_mm() {
    // G98 G73 X1 Y2 Z-5 R2 Q1.5: pecks to 0.5 -1 -2.5 -4, each backed off 0.254 mm.
    let b = CycleBlock {
        cycle: Cycle::G73,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-5.0),
        r: Some(2.0),
        q: Some(1.5),
        ..NONE
    };
    check(
        XYZ10,
        false,
        &[b],
        "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, 0.5000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 0.7540, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, -0.7460, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -2.5000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, -2.2460, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -4.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, -3.7460, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
    ",
        [1.0, 2.0, 10.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g73_inch() {
    // G20 / G0 X0 Y0 Z1 / G99 G73 X0.1 Y0.2 Z-0.3 R0.1 Q0.12: backed off 0.010 inch.
    let b = CycleBlock {
        cycle: Cycle::G73,
        retract_to_r: true,
        at: [Some(0.1), Some(0.2)],
        depth: Some(-0.3),
        r: Some(0.1),
        q: Some(0.12),
        ..NONE
    };
    let start = [0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
    check(
        start,
        true,
        &[b],
        "
        STRAIGHT_TRAVERSE(0.1000, 0.2000, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(0.1000, 0.2000, 0.1000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(0.1000, 0.2000, -0.0200, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(0.1000, 0.2000, -0.0100, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(0.1000, 0.2000, -0.1400, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(0.1000, 0.2000, -0.1300, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(0.1000, 0.2000, -0.2600, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(0.1000, 0.2000, -0.2500, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(0.1000, 0.2000, -0.3000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(0.1000, 0.2000, 0.1000, 0.0000, 0.0000, 0.0000)
    ",
        [0.1, 0.2, 0.1, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g83_mm_q_sticky() {
    // G99 G83 X1 Y2 Z-5 R2 Q2 / X4: out to R after each peck, back in to 0.254 above it.
    let blocks = [
        CycleBlock {
            cycle: Cycle::G83,
            retract_to_r: true,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            q: Some(2.0),
            ..NONE
        },
        CycleBlock {
            cycle: Cycle::G83,
            retract_to_r: true,
            at: [Some(4.0), None],
            ..NONE
        },
    ];
    check(
        XYZ10,
        false,
        &blocks,
        "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, 0.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 0.2540, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, -1.7460, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -4.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, -3.7460, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(4.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(4.0000, 2.0000, 0.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(4.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(4.0000, 2.0000, 0.2540, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(4.0000, 2.0000, -2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(4.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(4.0000, 2.0000, -1.7460, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(4.0000, 2.0000, -4.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(4.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(4.0000, 2.0000, -3.7460, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(4.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(4.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
    ",
        [4.0, 2.0, 2.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g83_inch() {
    // G20 / G0 X0 Y0 Z1 / G98 G83 X0.1 Y0.2 Z-0.3 R0.1 Q0.12: clearance 0.010 inch.
    let b = CycleBlock {
        cycle: Cycle::G83,
        at: [Some(0.1), Some(0.2)],
        depth: Some(-0.3),
        r: Some(0.1),
        q: Some(0.12),
        ..NONE
    };
    let start = [0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
    check(
        start,
        true,
        &[b],
        "
        STRAIGHT_TRAVERSE(0.1000, 0.2000, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(0.1000, 0.2000, 0.1000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(0.1000, 0.2000, -0.0200, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(0.1000, 0.2000, 0.1000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(0.1000, 0.2000, -0.0100, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(0.1000, 0.2000, -0.1400, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(0.1000, 0.2000, 0.1000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(0.1000, 0.2000, -0.1300, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(0.1000, 0.2000, -0.2600, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(0.1000, 0.2000, 0.1000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(0.1000, 0.2000, -0.2500, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(0.1000, 0.2000, -0.3000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(0.1000, 0.2000, 1.0000, 0.0000, 0.0000, 0.0000)
    ",
        [0.1, 0.2, 1.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g83_g91_repeats() {
    // G91 G99 G83 X5 Z-4 R-8 Q1.5 L2 (from X0 Y0 Z10): R 2, bottom -2.
    let b = CycleBlock {
        cycle: Cycle::G83,
        incremental: true,
        retract_to_r: true,
        at: [Some(5.0), None],
        depth: Some(-4.0),
        r: Some(-8.0),
        q: Some(1.5),
        repeats: Some(2.0),
        ..NONE
    };
    check(
        XYZ10,
        false,
        &[b],
        "
        STRAIGHT_TRAVERSE(5.0000, 0.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(5.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(5.0000, 0.0000, 0.5000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(5.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(5.0000, 0.0000, 0.7540, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(5.0000, 0.0000, -1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(5.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(5.0000, 0.0000, -0.7460, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(5.0000, 0.0000, -2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(5.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(10.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(10.0000, 0.0000, 0.5000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(10.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(10.0000, 0.0000, 0.7540, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(10.0000, 0.0000, -1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(10.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(10.0000, 0.0000, -0.7460, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(10.0000, 0.0000, -2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(10.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
    ",
        [10.0, 0.0, 2.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g83_g18_pecks_along_y() {
    // G18 / G0 X0 Y10 Z0 / G98 G83 Z1 X2 Y-3 R2 Q2
    let b = CycleBlock {
        cycle: Cycle::G83,
        plane: Plane::ZX,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-3.0),
        r: Some(2.0),
        q: Some(2.0),
        ..NONE
    };
    let start = [0.0, 10.0, 0.0, 0.0, 0.0, 0.0];
    check(
        start,
        false,
        &[b],
        "
        STRAIGHT_TRAVERSE(2.0000, 10.0000, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(2.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 0.2540, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(2.0000, -2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, -1.7460, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(2.0000, -3.0000, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 10.0000, 1.0000, 0.0000, 0.0000, 0.0000)
    ",
        [2.0, 10.0, 1.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g82_dwell_p_in_milliseconds_sticky() {
    // Fanuc G98 G82 X1 Y2 Z-5 R2 P1500 / X3 = LinuxCNC P1.5 (seconds).
    let blocks = [
        CycleBlock {
            cycle: Cycle::G82,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            p: Some(1500.0),
            ..NONE
        },
        CycleBlock {
            cycle: Cycle::G82,
            at: [Some(3.0), None],
            ..NONE
        },
    ];
    check(
        XYZ10,
        false,
        &blocks,
        "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        DWELL(1.5000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        DWELL(1.5000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
    ",
        [3.0, 2.0, 10.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g89_dwell_feed_out() {
    // Fanuc G99 G89 X1 Y2 Z-5 R2 P250 / X3 = LinuxCNC P0.25.
    let blocks = [
        CycleBlock {
            cycle: Cycle::G89,
            retract_to_r: true,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            p: Some(250.0),
            ..NONE
        },
        CycleBlock {
            cycle: Cycle::G89,
            retract_to_r: true,
            at: [Some(3.0), None],
            ..NONE
        },
    ];
    check(
        XYZ10,
        false,
        &blocks,
        "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        DWELL(0.2500)
        STRAIGHT_FEED(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        DWELL(0.2500)
        STRAIGHT_FEED(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
    ",
        [3.0, 2.0, 2.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g89_under_g98_feeds_out_to_the_initial_level() {
    // G98 G89 X1 Y2 Z-5 R2 P250 / G99 X3 (g89_g98.trace): unlike G85, LinuxCNC's G89 feeds
    // all the way out to the return level, the initial level under G98.
    let blocks = [
        CycleBlock {
            cycle: Cycle::G89,
            retract_to_r: false,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            p: Some(250.0),
            ..NONE
        },
        CycleBlock {
            cycle: Cycle::G89,
            retract_to_r: true,
            at: [Some(3.0), None],
            ..NONE
        },
    ];
    check(
        XYZ10,
        false,
        &blocks,
        "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        DWELL(0.2500)
        STRAIGHT_FEED(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        DWELL(0.2500)
        STRAIGHT_FEED(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
    ",
        [3.0, 2.0, 2.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g85_feed_out_to_r_then_rapid() {
    // G98 G85 X1 Y2 Z-5 R2 / G99 X3
    let blocks = [
        CycleBlock {
            cycle: Cycle::G85,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            ..NONE
        },
        CycleBlock {
            cycle: Cycle::G85,
            retract_to_r: true,
            at: [Some(3.0), None],
            ..NONE
        },
    ];
    check(
        XYZ10,
        false,
        &blocks,
        "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
    ",
        [3.0, 2.0, 2.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g84_tapping() {
    // M3 / G98 G84 X1 Y2 Z-5 R2 P500 / G99 X3 (LinuxCNC P0.5): under G98 the feed out goes to
    // the initial level.
    let blocks = [
        CycleBlock {
            cycle: Cycle::G84,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            p: Some(500.0),
            ..NONE
        },
        CycleBlock {
            cycle: Cycle::G84,
            retract_to_r: true,
            at: [Some(3.0), None],
            ..NONE
        },
    ];
    check(
        XYZ10,
        false,
        &blocks,
        "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STOP_SPINDLE_TURNING(0)
        START_SPINDLE_COUNTERCLOCKWISE(0)
        DWELL(0.5000)
        STRAIGHT_FEED(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STOP_SPINDLE_TURNING(0)
        START_SPINDLE_CLOCKWISE(0)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STOP_SPINDLE_TURNING(0)
        START_SPINDLE_COUNTERCLOCKWISE(0)
        DWELL(0.5000)
        STRAIGHT_FEED(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STOP_SPINDLE_TURNING(0)
        START_SPINDLE_CLOCKWISE(0)
    ",
        [3.0, 2.0, 2.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g74_counter_tapping() {
    // M4 / G99 G74 X1 Y2 Z-5 R2: no P, LinuxCNC dwells 0.
    let b = CycleBlock {
        cycle: Cycle::G74,
        retract_to_r: true,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-5.0),
        r: Some(2.0),
        spindle_ccw: true,
        ..NONE
    };
    check(
        XYZ10,
        false,
        &[b],
        "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STOP_SPINDLE_TURNING(0)
        START_SPINDLE_CLOCKWISE(0)
        DWELL(0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STOP_SPINDLE_TURNING(0)
        START_SPINDLE_COUNTERCLOCKWISE(0)
    ",
        [1.0, 2.0, 2.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g84_g19_feeds_along_x() {
    // G19 / G0 X10 Y0 Z0 / G98 G84 Y1 Z2 X-5 R2. The positioning is rs274's; its two feeds are
    // STRAIGHT_FEED(2, -5, 1) and STRAIGHT_FEED(2, 10, 1) (g84_g19.trace), the axes swapped by
    // LinuxCNC 2.9's convert_cycle_g74_g84. fmsvm feeds along X at Y1 Z2, as G81 does in G19.
    let b = CycleBlock {
        cycle: Cycle::G84,
        plane: Plane::YZ,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-5.0),
        r: Some(2.0),
        ..NONE
    };
    let trace = "
        STRAIGHT_TRAVERSE(10.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        // fmsvm, not LinuxCNC:
        STRAIGHT_FEED(-5.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STOP_SPINDLE_TURNING(0)
        START_SPINDLE_COUNTERCLOCKWISE(0)
        DWELL(0.0000)
        // fmsvm, not LinuxCNC:
        STRAIGHT_FEED(10.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STOP_SPINDLE_TURNING(0)
        START_SPINDLE_CLOCKWISE(0)
    ";
    let start = [10.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    check(start, false, &[b], trace, [10.0, 1.0, 2.0, 0.0, 0.0, 0.0]);
}

#[test]
fn g86_spindle_stop_rapid_out() {
    // M3 / G99 G86 X1 Y2 Z-5 R2 P500 (LinuxCNC P0.5)
    let b = CycleBlock {
        cycle: Cycle::G86,
        retract_to_r: true,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-5.0),
        r: Some(2.0),
        p: Some(500.0),
        ..NONE
    };
    check(
        XYZ10,
        false,
        &[b],
        "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        DWELL(0.5000)
        STOP_SPINDLE_TURNING(0)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        START_SPINDLE_CLOCKWISE(0)
    ",
        [1.0, 2.0, 2.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g86_restarts_counter_clockwise_after_m4() {
    // M4 / G98 G86 X1 Y2 Z-5 R2 P500
    let b = CycleBlock {
        cycle: Cycle::G86,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-5.0),
        r: Some(2.0),
        p: Some(500.0),
        spindle_ccw: true,
        ..NONE
    };
    check(
        XYZ10,
        false,
        &[b],
        "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        DWELL(0.5000)
        STOP_SPINDLE_TURNING(0)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        START_SPINDLE_COUNTERCLOCKWISE(0)
    ",
        [1.0, 2.0, 10.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn g88_stop_then_fanuc_return() {
    // M3 / G98 G88 X1 Y2 Z-5 R2 P500 / X3 (LinuxCNC P0.5). After PROGRAM_STOP fmsvm adds
    // Fanuc's rapid to the return level (here the initial level Z10) before the spindle restarts;
    // the rest is rs274's.
    let blocks = [
        CycleBlock {
            cycle: Cycle::G88,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            p: Some(500.0),
            ..NONE
        },
        CycleBlock {
            cycle: Cycle::G88,
            at: [Some(3.0), None],
            ..NONE
        },
    ];
    let trace = "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        DWELL(0.5000)
        STOP_SPINDLE_TURNING(0)
        PROGRAM_STOP()
        // fmsvm (Fanuc), not LinuxCNC:
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        START_SPINDLE_CLOCKWISE(0)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        DWELL(0.5000)
        STOP_SPINDLE_TURNING(0)
        PROGRAM_STOP()
        // fmsvm (Fanuc), not LinuxCNC:
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        START_SPINDLE_CLOCKWISE(0)
    ";
    check(
        XYZ10,
        false,
        &blocks,
        trace,
        [3.0, 2.0, 10.0, 0.0, 0.0, 0.0],
    );
}

// Alarms. err_*.ngc hold the LinuxCNC twins; their traces end in rs274's error message.

/// A peck so small that one block would expand for ever (the fuzzer's find: Q4e-308) is alarm
/// 045 before any move; the most pecks allowed still expand.
#[test]
fn a_peck_too_small_to_be_a_peck_is_alarm_45() {
    for (q, pecks_ok) in [
        (1e-7, false),
        (4e-308, false),
        (0.01, true),
        (0.0099, false),
    ] {
        let b = CycleBlock {
            cycle: Cycle::G83,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-99.0),
            r: Some(1.0),
            q: Some(q),
            ..NONE
        };
        let mut steps = 0u64;
        let r = expand(
            &mut CycleModal::default(),
            &b,
            XYZ10,
            false,
            &CycleParams::default(),
            &mut |_| {
                steps += 1;
                Ok(())
            },
        );
        if pecks_ok {
            assert!(r.is_ok(), "Q{q}: {r:?}");
            assert!(steps > 10_000, "Q{q}: {steps} steps");
        } else {
            assert!(
                matches!(r, Err(Stop::Alarm(ref a)) if a.number == 45 && a.message.contains("pecks")),
                "Q{q}: {r:?}"
            );
            assert_eq!(steps, 0, "Q{q}");
        }
    }
}

#[test]
fn q_zero_negative_or_missing_is_alarm_45() {
    // err_q0: G98 G83 X1 Y2 Z-5 R2 Q0 -> "Negative or zero q value used" (after rs274's two
    // positioning moves; fmsvm alarms before any move). err_no_q: G98 G73 X1 Y2 Z-5 R2 ->
    // "Q word missing with g73".
    for (cycle, q) in [
        (Cycle::G83, Some(0.0)),
        (Cycle::G73, Some(-1.0)),
        (Cycle::G73, None),
        (Cycle::G83, None),
    ] {
        let b = CycleBlock {
            cycle,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            q,
            ..NONE
        };
        let mut steps = 0;
        let r = expand(
            &mut CycleModal::default(),
            &b,
            XYZ10,
            false,
            &CycleParams::default(),
            &mut |_| {
                steps += 1;
                Ok(())
            },
        );
        assert!(
            matches!(r, Err(Stop::Alarm(ref a)) if a.number == 45),
            "{cycle:?} {q:?}"
        );
        assert_eq!(steps, 0);
    }
}

#[test]
fn missing_r_or_z_and_r_below_z_are_alarms() {
    // err_no_r: G98 G81 X1 Y2 Z-5 -> "R clearance plane unspecified in cycle";
    // err_no_z: G98 G81 X1 Y2 R2 -> "Z value unspecified in xy plane canned cycle";
    // err_r_below_z: G98 G81 X1 Y2 Z2 R-5 -> "R less than z in cycle in xy plane".
    let b = CycleBlock {
        cycle: Cycle::G81,
        at: [Some(1.0), Some(2.0)],
        ..NONE
    };
    let no_r = CycleBlock {
        depth: Some(-5.0),
        ..b
    };
    let (n, m) = alarm_of(run(XYZ10, false, &[no_r]));
    assert_eq!(
        (n, m.as_str()),
        (0, "G81: no R level given in the canned cycle mode")
    );
    let no_z = CycleBlock { r: Some(2.0), ..b };
    let (n, m) = alarm_of(run(XYZ10, false, &[no_z]));
    assert_eq!(
        (n, m.as_str()),
        (0, "G81: no Z depth given in the canned cycle mode")
    );
    let no_x = CycleBlock {
        plane: Plane::YZ,
        ..no_z
    };
    let (_, m) = alarm_of(run(XYZ10, false, &[no_x]));
    assert_eq!(m, "G81: no X depth given in the canned cycle mode");
    let below = CycleBlock {
        depth: Some(2.0),
        r: Some(-5.0),
        ..b
    };
    let (n, m) = alarm_of(run(XYZ10, false, &[below]));
    assert_eq!((n, m.as_str()), (0, "G81: R -5 is below the bottom Z2"));
}

#[test]
fn cancel_forgets_r_z_and_the_initial_level() {
    let mut modal = CycleModal::default();
    let b = CycleBlock {
        cycle: Cycle::G81,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-5.0),
        r: Some(2.0),
        ..NONE
    };
    let p = CycleParams::default();
    expand(&mut modal, &b, XYZ10, false, &p, &mut |_| Ok(())).expect("drills");
    assert_eq!(modal.initial_level(), Some(10.0));
    modal.cancel();
    assert_eq!(modal, CycleModal::default());
    let again = CycleBlock {
        cycle: Cycle::G81,
        at: [Some(3.0), None],
        ..NONE
    };
    let r = expand(&mut modal, &again, XYZ10, false, &p, &mut |_| Ok(()));
    assert!(matches!(r, Err(Stop::Alarm(a)) if a.number == 0));
}

#[test]
fn fanuc_r_only_block_drills() {
    // err_r_only: G98 G81 X1 Y2 Z-5 R2 / R3: rs274 refuses the R3 block ("R word with no g code
    // that uses it"); Fanuc drills again where the tool is, from the new R. By hand, the second
    // block: initial 10, R 3, start Z10 above R -> rapid at Z10 over the hole (1, 2), down to 3,
    // feed to -5, back to 10.
    let blocks = [
        CycleBlock {
            cycle: Cycle::G81,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            ..NONE
        },
        CycleBlock {
            cycle: Cycle::G81,
            r: Some(3.0),
            ..NONE
        },
    ];
    let trace = "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        // the R3 block (hand-computed):
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
    ";
    check(
        XYZ10,
        false,
        &blocks,
        trace,
        [1.0, 2.0, 10.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn fanuc_k0_stores_without_drilling() {
    // err_l0: G98 G81 X1 Y2 Z-5 R2 L0 -> rs274: "Cannot do zero repeats of cycle". Fanuc K0
    // stores Z and R; the next block X3 drills with them (hand: as the X3 block of g81_g98,
    // from Z10 at X0 Y0 as the K0 block left the tool).
    let blocks = [
        CycleBlock {
            cycle: Cycle::G81,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            repeats: Some(0.0),
            ..NONE
        },
        CycleBlock {
            cycle: Cycle::G81,
            at: [Some(3.0), None],
            ..NONE
        },
    ];
    let trace = "
        STRAIGHT_TRAVERSE(3.0000, 0.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(3.0000, 0.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 0.0000, 10.0000, 0.0000, 0.0000, 0.0000)
    ";
    check(
        XYZ10,
        false,
        &blocks,
        trace,
        [3.0, 0.0, 10.0, 0.0, 0.0, 0.0],
    );
}

#[test]
fn fanuc_keeps_r_z_across_cycle_codes_and_p_defaults_to_0() {
    // err_code_change: G98 G81 X1 Y2 Z-5 R2 / G82 X3 P1 -> rs274: "R clearance plane
    // unspecified in cycle". err_no_p: G98 G82 X1 Y2 Z-5 R2 -> rs274: "Dwell time p word missing
    // with g82". Fanuc: G82 X3 P1000 drills with R2 Z-5; a G82 with no P dwells 0 s (hand).
    let blocks = [
        CycleBlock {
            cycle: Cycle::G81,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            ..NONE
        },
        CycleBlock {
            cycle: Cycle::G82,
            at: [Some(3.0), None],
            p: Some(1000.0),
            ..NONE
        },
    ];
    let trace = "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        DWELL(1.0000)
        STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
    ";
    check(
        XYZ10,
        false,
        &blocks,
        trace,
        [3.0, 2.0, 10.0, 0.0, 0.0, 0.0],
    );
    let no_p = CycleBlock {
        cycle: Cycle::G82,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-5.0),
        r: Some(2.0),
        ..NONE
    };
    let (steps, _) = run(XYZ10, false, &[no_p]).expect("no alarm");
    assert_eq!(steps[3], Step::Dwell(0.0));
}

#[test]
fn bad_words_are_alarms() {
    let b = CycleBlock {
        cycle: Cycle::G81,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-5.0),
        r: Some(2.0),
        ..NONE
    };
    for k in [-1.0, 1.5, 10000.0] {
        let (n, _) = alarm_of(run(
            XYZ10,
            false,
            &[CycleBlock {
                repeats: Some(k),
                ..b
            }],
        ));
        assert_eq!(n, 0, "K{k}");
    }
    let (n, _) = alarm_of(run(XYZ10, false, &[CycleBlock { p: Some(-5.0), ..b }]));
    assert_eq!(n, 6);
    // Not a cycle: G0, G1, G80, G81.1, G90, G75 (alarm 0010 where the kernel decodes the code).
    for code in [0, 10, 800, 811, 900, 750].map(Code::from_tenths) {
        let e = Cycle::of(code).expect_err("not a cycle");
        assert_eq!(e.number, 10, "G{code}");
    }
    for (cycle, code) in Cycle::ALL {
        assert_eq!(Cycle::of(code), Ok(cycle));
        assert_eq!(cycle.code(), code);
    }
}

#[test]
fn vacant_words_are_omitted_words() {
    // X#0 in a Fanuc block: the word is as if not given, the hole is at the tool's X.
    let b = CycleBlock {
        cycle: Cycle::G81,
        at: [Some(f64::NAN), Some(2.0)],
        depth: Some(-5.0),
        r: Some(2.0),
        p: Some(f64::NAN),
        ..NONE
    };
    let (steps, end) = run(XYZ10, false, &[b]).expect("no alarm");
    assert_eq!(steps.len(), 4);
    assert!(close(&end, &[0.0, 2.0, 10.0, 0.0, 0.0, 0.0]));
}

#[test]
fn errors_of_out_stop_the_cycle() {
    let b = CycleBlock {
        cycle: Cycle::G83,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-5.0),
        r: Some(2.0),
        q: Some(0.001),
        ..NONE
    };
    let mut n = 0;
    let r = expand(
        &mut CycleModal::default(),
        &b,
        XYZ10,
        false,
        &CycleParams::default(),
        &mut |_| {
            n += 1;
            if n == 10 {
                Err(Stop::Limit {
                    kind: fmsvm_block::LimitKind::Blocks,
                    limit: 9,
                })
            } else {
                Ok(())
            }
        },
    );
    assert!(matches!(r, Err(Stop::Limit { limit: 9, .. })));
    assert_eq!(n, 10);
}

// Fanuc-only cycles, hand-computed (LinuxCNC has no Fanuc G76; its G87 is another cycle).

#[test]
fn g76_fine_boring_shift_by_q() {
    // G0 X0 Y0 Z10 / G98 G76 X1 Y2 Z-5 R2 Q0.5 P500 (M3): Q is the decoded value in mm,
    // P500 is 0.5 s, shift direction + first axis (+X in G17; Fanuc parameter 5101 RD2 RD1 = 0 0).
    // Positioning as G81: rapid over (1, 2) at Z10, down to R2. Feed to Z-5, dwell 0.5, oriented
    // stop, shift X 1 + 0.5 = 1.5 at Z-5, rapid out to the G98 level Z10 at X1.5, shift back to
    // X1 at Z10, spindle clockwise (M3 was on).
    let b = CycleBlock {
        cycle: Cycle::G76,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-5.0),
        r: Some(2.0),
        q: Some(0.5),
        p: Some(500.0),
        ..NONE
    };
    let trace = "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        DWELL(0.5000)
        ORIENT_SPINDLE()
        STRAIGHT_TRAVERSE(1.5000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.5000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        START_SPINDLE_CLOCKWISE(0)
    ";
    check(XYZ10, false, &[b], trace, [1.0, 2.0, 10.0, 0.0, 0.0, 0.0]);
    // A negative Q shifts the same way (Fanuc ignores its sign); shift direction − second axis
    // (RD2 RD1 = 1 1, −Y in G17) shifts to Y 2 − 0.5 = 1.5.
    let minus_y = CycleParams {
        shift_direction: ShiftDirection::MinusSecond,
        ..CycleParams::default()
    };
    let (steps, _) =
        run_with(XYZ10, false, &minus_y, &[CycleBlock { q: Some(-0.5), ..b }]).expect("ok");
    assert!(same(
        &steps[5],
        &Step::Rapid([1.0, 1.5, -5.0, 0.0, 0.0, 0.0])
    ));
}

#[test]
fn g76_g18_g99_shift_by_words() {
    // G18 / G0 X0 Y10 Z0 / G99 G76 Z1 X2 Y-5 R2 K0.3 I-0.4 (Fanuc SIJ: K I are the G18 shift,
    // plane order (Z, X)); no P: dwell 0.
    // Positioning: start Y10 above R2: rapid to Z1 X2 at Y10, down to Y2. Feed to Y-5. Shift:
    // Z 1 + 0.3 = 1.3, X 2 - 0.4 = 1.6, at Y-5; out to the G99 level Y2; back to Z1 X2; M3.
    let b = CycleBlock {
        cycle: Cycle::G76,
        plane: Plane::ZX,
        retract_to_r: true,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-5.0),
        r: Some(2.0),
        q: Some(9.0),
        shift: [Some(0.3), Some(-0.4)],
        ..NONE
    };
    let trace = "
        STRAIGHT_TRAVERSE(2.0000, 10.0000, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_FEED(2.0000, -5.0000, 1.0000, 0.0000, 0.0000, 0.0000)
        DWELL(0.0000)
        ORIENT_SPINDLE()
        STRAIGHT_TRAVERSE(1.6000, -5.0000, 1.3000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.6000, 2.0000, 1.3000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(2.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
        START_SPINDLE_CLOCKWISE(0)
    ";
    let start = [0.0, 10.0, 0.0, 0.0, 0.0, 0.0];
    check(start, false, &[b], trace, [2.0, 2.0, 1.0, 0.0, 0.0, 0.0]);
}

#[test]
fn g87_back_boring() {
    // G0 X0 Y0 Z10 / G98 G87 X1 Y2 Z-5 R-20 Q0.5 P1000 (M3): R-20 is below the part, Z-5 the
    // top of the back bore. Over the hole at Z10, oriented stop, shift X 1 + 0.5 = 1.5, rapid
    // down to Z-20, shift back to X1, M3, feed up to Z-5, dwell 1 s, oriented stop, shift to
    // X1.5, rapid up to the initial level Z10, shift back, M3.
    let b = CycleBlock {
        cycle: Cycle::G87,
        at: [Some(1.0), Some(2.0)],
        depth: Some(-5.0),
        r: Some(-20.0),
        q: Some(0.5),
        p: Some(1000.0),
        ..NONE
    };
    let trace = "
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        ORIENT_SPINDLE()
        STRAIGHT_TRAVERSE(1.5000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.5000, 2.0000, -20.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, -20.0000, 0.0000, 0.0000, 0.0000)
        START_SPINDLE_CLOCKWISE(0)
        STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        DWELL(1.0000)
        ORIENT_SPINDLE()
        STRAIGHT_TRAVERSE(1.5000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.5000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        START_SPINDLE_CLOCKWISE(0)
    ";
    check(XYZ10, false, &[b], trace, [1.0, 2.0, 10.0, 0.0, 0.0, 0.0]);
    // R above the top is an alarm for G87.
    let (n, m) = alarm_of(run(XYZ10, false, &[CycleBlock { r: Some(0.0), ..b }]));
    assert_eq!(
        (n, m.as_str()),
        (0, "G87: R 0 is above the top of the back bore Z-5")
    );
}

#[test]
fn g87_g91_repeats_always_back_to_the_initial_level() {
    // G0 X0 Y0 Z10 / G91 G99 G87 X10 Z10 R-30 Q0.5 K2, spindle M4, shift − second axis (−Y):
    // R = 10 - 30 = -20, top = -20 + 10 = -10; G99 is ignored (Fanuc G87 returns to the
    // initial level). Holes at X10 and X20, shifted to Y 0 - 0.5 = -0.5; restarts M4; no P.
    let b = CycleBlock {
        cycle: Cycle::G87,
        incremental: true,
        retract_to_r: true,
        at: [Some(10.0), None],
        depth: Some(10.0),
        r: Some(-30.0),
        q: Some(0.5),
        repeats: Some(2.0),
        spindle_ccw: true,
        ..NONE
    };
    let mut want = String::new();
    for x in ["10.0", "20.0"] {
        want += &format!(
            "STRAIGHT_TRAVERSE({x}, 0, 10, 0, 0, 0)
            ORIENT_SPINDLE()
            STRAIGHT_TRAVERSE({x}, -0.5, 10, 0, 0, 0)
            STRAIGHT_TRAVERSE({x}, -0.5, -20, 0, 0, 0)
            STRAIGHT_TRAVERSE({x}, 0, -20, 0, 0, 0)
            START_SPINDLE_COUNTERCLOCKWISE(0)
            STRAIGHT_FEED({x}, 0, -10, 0, 0, 0)
            DWELL(0)
            ORIENT_SPINDLE()
            STRAIGHT_TRAVERSE({x}, -0.5, -10, 0, 0, 0)
            STRAIGHT_TRAVERSE({x}, -0.5, 10, 0, 0, 0)
            STRAIGHT_TRAVERSE({x}, 0, 10, 0, 0, 0)
            START_SPINDLE_COUNTERCLOCKWISE(0)
            "
        );
    }
    let params = CycleParams {
        shift_direction: ShiftDirection::MinusSecond,
        ..CycleParams::default()
    };
    let (steps, end) = run_with(XYZ10, false, &params, &[b]).expect("no alarm");
    let want = parse(&want);
    assert!(
        steps.len() == want.len() && steps.iter().zip(&want).all(|(a, b)| same(a, b)),
        "got {steps:#?}"
    );
    assert!(close(&end, &[20.0, 0.0, 10.0, 0.0, 0.0, 0.0]));
}
