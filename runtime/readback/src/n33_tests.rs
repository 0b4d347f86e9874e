//! The Н33-2М emitter (`fmsvm_emit::n33`) and reader (`crate::n33`) together: each test names the rule it proves.

use crate::n33::N33Reader;
use crate::{Motion, Move, ReadError, Reader};
use fmsvm_block::Stop;
use fmsvm_canon::{Arc, Canon, Emitter, Origin, Plane, Pose};
use fmsvm_emit::n33::*;

fn p(x: f64, y: f64, z: f64) -> Pose {
    [x, y, z, 0.0, 0.0, 0.0]
}

/// The output of `ops` (after a Start at `start`), the stop if any, the warnings, and the blocks
/// written after each op.
struct Run {
    out: Vec<u8>,
    stop: Option<Stop>,
    warnings: Vec<String>,
    after: Vec<u32>,
}

fn run(options: N33Options, start: Pose, ops: &[Canon<'_>]) -> Run {
    let mut out = Vec::new();
    let mut after = Vec::new();
    let (stop, warnings) = {
        let mut e = N33Emitter::new(&mut out, options);
        let mut go = || -> Result<(), Stop> {
            e.begin(None, "")?;
            e.canon(&Canon::Start(start), Origin::default())?;
            for (i, op) in ops.iter().enumerate() {
                let origin = Origin {
                    line: i as u32 + 1,
                    block_delete: false,
                    fixed: 0,
                    ..Origin::default()
                };
                e.canon(op, origin)?;
                after.push(e.blocks());
            }
            e.end()
        };
        let stop = go().err();
        (stop, e.warnings().iter().map(|w| w.text.clone()).collect())
    };
    Run {
        out,
        stop,
        warnings,
        after,
    }
}

fn text(options: N33Options, start: Pose, ops: &[Canon<'_>]) -> String {
    let r = run(options, start, ops);
    assert!(r.stop.is_none(), "stopped: {:?}", r.stop);
    String::from_utf8(r.out).expect("ASCII")
}

fn read_all(bytes: &[u8], start: Pose, iso: bool) -> Result<Vec<Move>, ReadError> {
    let mut r = N33Reader::new(bytes, start).g18_ccw_is_iso(iso);
    let mut moves = Vec::new();
    while let Some(m) = r.next_move()? {
        moves.push(m);
    }
    Ok(moves)
}

fn assert_lines(got: &str, expected: &[(&str, &str)]) {
    let lines: Vec<&str> = got.lines().collect();
    for (i, (want, rule)) in expected.iter().enumerate() {
        assert_eq!(lines.get(i).copied(), Some(*want), "line {}: {rule}", i + 1);
    }
    assert_eq!(lines.len(), expected.len(), "line count:\n{got}");
}

fn arc(to: Pose, centre: [f64; 2], plane: Plane, clockwise: bool) -> Canon<'static> {
    Canon::Arc(Arc {
        to,
        centre,
        plane,
        clockwise,
        turns: 0,
    })
}

/// Golden: a rapid, a square, a full circle crossing quadrants, a dwell, M3/M8/M5, M30.
#[test]
fn golden_small_program() {
    let ops = [
        Canon::FeedRate(500.0),
        Canon::MCode(3.0),
        Canon::MCode(8.0),
        Canon::Rapid(p(300.0, 0.0, 0.0)),
        Canon::Rapid(p(50.0, 0.0, 0.0)),
        Canon::Feed(p(50.0, 0.0, -5.0)),
        Canon::Feed(p(100.0, 0.0, -5.0)),
        Canon::Feed(p(100.0, 50.0, -5.0)),
        Canon::Feed(p(50.0, 50.0, -5.0)),
        Canon::Feed(p(50.0, 0.0, -5.0)),
        arc(p(50.0, 0.0, -5.0), [50.0, 20.0], Plane::XY, false),
        Canon::Dwell(2.5),
        Canon::Feed(p(50.0, 0.0, 0.0)),
        Canon::MCode(5.0),
        Canon::MCode(9.0),
        Canon::Rapid(p(0.0, 0.0, 0.0)),
        Canon::MCode(30.0),
    ];
    let got = text(N33Options::default(), p(0.0, 0.0, 0.0), &ops);
    assert_lines(
        &got,
        &[
            ("%", "program start % (§5.1.3)"),
            (
                "N001M13F0624",
                "M03 with M08 is M13; an M block at F0624 (A.8, §5.2.3)",
            ),
            // The rapid reverses into the next: it brakes (F4748, §5.2.3), as the manual's Ex. 4
            // N013 brakes its rapid before reversing. The second turns down into a feed of 500
            // mm/min, which the control reaches by the block's end by itself (d1 = 0, §5.2.3): a
            // 90° corner at 500 mm/min is unbraked (Ex. 12).
            (
                "N002G01X+030000F4748",
                "rapid of 300 mm: no G00, G01 F0748 with braking F4748 before the reversal (A.7, §5.2.3); N 3 digits, X sign + 6 (§5.1.1)",
            ),
            (
                "N003X-025000",
                "rapid of 250 mm: G modal (§5.2.2); braking is one block: a block without F after it runs at the previous speed again, the rapid's (§5.2.3)",
            ),
            (
                "N004Z-000500F0650",
                "feed 500 mm/min is F0650 (Table 6); Z increment (§5.2.6)",
            ),
            (
                "N005X+005000",
                "square: increments in 0.01 mm discretes (§5.2.6)",
            ),
            ("N006Y+005000", "square"),
            ("N007X-005000", "square"),
            ("N008Y-005000", "square"),
            (
                "N009G17",
                "the plane before the first arc, one G per block (§5.2.2, §5.2.9)",
            ),
            (
                "N010G03J+002000X+002000Y+002000",
                "full circle from the bottom: quadrant IV; the zero I omitted (A.12)",
            ),
            ("N011I+002000X-002000Y+002000", "quadrant I; G03 modal"),
            ("N012J+002000X-002000Y-002000", "quadrant II"),
            (
                "N013I+002000X+002000Y-002000",
                "quadrant III: a full circle from an axis is 4 blocks (A.12)",
            ),
            (
                "N014G04X+000250F0560",
                "dwell 2.5 s: X in hundredths of a second at F0560 (§5.2.7)",
            ),
            (
                "N015G01Z+000500F0650",
                "after G04 the G and the feed are re-stated (§5.2.7)",
            ),
            (
                "N016M05F0624",
                "M05 with M09 is M05; at F0624 (A.8, §5.2.3)",
            ),
            (
                "N017X-005000F0720",
                "rapid of 50 mm < 200: at the fastest working feed F0720 (A.7)",
            ),
            ("N018M02", "M30 is M02, in its own block (A.8)"),
        ],
    );
    // The same program read back.
    let moves = read_all(got.as_bytes(), p(0.0, 0.0, 0.0), true).expect("reads");
    let kinds: Vec<Motion> = moves.iter().map(|m| m.motion).collect();
    assert_eq!(moves.len(), 14);
    assert_eq!(kinds[0], Motion::Rapid);
    assert_eq!(moves[0].feed, 4800.0);
    assert_eq!(moves[1].to, p(50.0, 0.0, 0.0));
    assert_eq!(moves[2].feed, 500.0);
    for m in &moves[7..11] {
        assert_eq!(
            m.motion,
            Motion::Arc {
                centre: [50.0, 20.0],
                plane: Plane::XY,
                clockwise: false
            },
            "line {}",
            m.line
        );
    }
    assert_eq!(moves[7].to, p(70.0, 20.0, -5.0));
    assert_eq!(moves[11].motion, Motion::Dwell(2.5));
    assert_eq!(moves[13].to, p(0.0, 0.0, 0.0));
    // A short rapid is a feed at 2000 on this tape (the reader says what the tape does).
    assert_eq!((moves[13].motion, moves[13].feed), (Motion::Feed, 2000.0));
}

/// A.12: a full circle starting off an axis is 5 blocks, the first and last in the same quadrant.
#[test]
fn full_circle_off_axis_is_five_blocks() {
    let from = p(30.0, 40.0, 0.0);
    let ops = [
        Canon::FeedRate(100.0),
        arc(from, [0.0, 0.0], Plane::XY, true),
    ];
    let got = text(N33Options::default(), from, &ops);
    assert_lines(
        &got,
        &[
            ("%", "start"),
            ("N001G17", "plane"),
            (
                "N002G02I+003000J+004000X+002000Y-004000F0610",
                "quadrant I piece to the X axis (CW)",
            ),
            ("N003I+005000X-005000Y-005000", "quadrant IV"),
            ("N004J+005000X-005000Y+005000", "quadrant III"),
            ("N005I+005000X+005000Y+005000", "quadrant II"),
            (
                "N006J+005000X+003000Y-001000",
                "back in quadrant I to the start: 5 blocks",
            ),
            ("N007M02", "M02 added at the end (A.4)"),
        ],
    );
}

/// Ex. 1 (Fig. 4, §4): the simple contour, from canon ops, word for word (N001 Y−002000 is the
/// reading that closes).
#[test]
fn manual_example_1() {
    let ops = [
        Canon::FeedRate(2000.0),
        Canon::Feed(p(-35.0, -20.0, 0.0)),
        Canon::Feed(p(-35.0, -20.0, -30.0)),
        Canon::MCode(3.0),
        Canon::FeedRate(50.0),
        Canon::Feed(p(-20.0, 75.0, -30.0)),
        Canon::Feed(p(20.0, 75.0, -30.0)),
        Canon::Feed(p(32.0, 80.0, -30.0)),
        Canon::FeedRate(2000.0),
        Canon::Feed(p(0.0, 0.0, 0.0)),
        Canon::MCode(2.0),
    ];
    // Ex. 1 (§4) runs its 2000 mm/min approach into the plunge without braking, where a later
    // example brakes such a corner (Ex. 17 N017 `F4712`: Z at 1200 mm/min, then X Y) and §5.2.3
    // asks for braking at sharp corners; the manual is not consistent there (Ex. 4 N012 does not
    // brake either). Ex. 1 is compared with braking off.
    let options = N33Options {
        brake_step: f64::INFINITY,
        ..N33Options::default()
    };
    let r = run(options, p(0.0, 0.0, 0.0), &ops);
    assert!(
        r.stop.is_none() && r.warnings.is_empty(),
        "{:?}",
        r.warnings
    );
    assert_lines(
        &String::from_utf8(r.out).expect("ASCII"),
        &[
            ("%", "start"),
            ("N001G01X-003500Y-002000F0720", "Ex. 1 N001"),
            ("N002Z-003000", "Ex. 1 N002"),
            ("N003M03F0624", "Ex. 1 N003: the M block at 240 mm/min"),
            ("N004X+001500Y+009500F0550", "Ex. 1 N004"),
            ("N005X+004000", "Ex. 1 N005"),
            ("N006X+001200Y+000500", "Ex. 1 N006"),
            ("N007X-003200Y-008000Z+003000F0720", "Ex. 1 N007"),
            ("N008M02", "Ex. 1 N008"),
        ],
    );
}

/// Ex. 11 N006–N009 (the R70 circle, G03 from the top) and Ex. 12 N002–N005 (an arc from an
/// off-axis start, I and J both), from canon ops. Differences from the manual: G17 in its own
/// block, no L words (the path is already the tool centre), G01 for the G50 departure.
#[test]
fn manual_examples_11_and_12() {
    let top = p(0.0, 70.0, 0.0);
    let got = text(
        N33Options::default(),
        top,
        &[
            Canon::FeedRate(50.0),
            arc(top, [0.0, 0.0], Plane::XY, false),
        ],
    );
    assert_lines(
        &got,
        &[
            ("%", "start"),
            ("N001G17", "plane"),
            ("N002G03J+007000X-007000Y-007000F0550", "Ex. 11 N006"),
            ("N003I+007000X+007000Y-007000", "Ex. 11 N007"),
            ("N004J+007000X+007000Y+007000", "Ex. 11 N008"),
            ("N005I+007000X-007000Y+007000", "Ex. 11 N009"),
            ("N006M02", "end"),
        ],
    );
    let got = text(
        N33Options::default(),
        p(0.0, 0.0, 0.0),
        &[
            Canon::FeedRate(500.0),
            Canon::Feed(p(80.0, 60.0, 0.0)),
            arc(p(-60.0, 80.0, 0.0), [0.0, 0.0], Plane::XY, false),
            Canon::Feed(p(0.0, 0.0, 0.0)),
            Canon::MCode(2.0),
        ],
    );
    assert_lines(
        &got,
        &[
            ("%", "start"),
            ("N001G01X+008000Y+006000F0650", "Ex. 12 N002"),
            ("N002G17", "plane"),
            (
                "N003G03I+008000J+006000X-008000Y+004000",
                "Ex. 12 N003: I and J both",
            ),
            ("N004J+010000X-006000Y-002000", "Ex. 12 N004"),
            ("N005G01X+006000Y-008000", "Ex. 12 N005 (G50 there)"),
            ("N006M02", "Ex. 12 N006"),
        ],
    );
}

/// Ex. 13 (Fig. 23, XZ): the blend arc and the R50 circle; with `g18_ccw_is_iso: false` the manual's
/// G03, with the ISO default G02 (A.12: the plane sense is a setting).
#[test]
fn manual_example_13_g18_sense() {
    // Blend centre X0 Z20, from X30 Z20 to the top of the main circle X0 Z50 (centre 0 0).
    let ops = [
        Canon::FeedRate(500.0),
        arc(p(0.0, 0.0, 50.0), [20.0, 0.0], Plane::ZX, true),
        arc(p(0.0, 0.0, 50.0), [0.0, 0.0], Plane::ZX, true),
    ];
    let manual = N33Options {
        g18_ccw_is_iso: false,
        ..N33Options::default()
    };
    let got = text(manual, p(30.0, 0.0, 20.0), &ops);
    let expected = [
        ("%", "start"),
        ("N001G18", "plane XZ"),
        (
            "N002G03I+003000X-003000Z+003000F0650",
            "Ex. 13 N004: G03 in the manual's XZ sense",
        ),
        ("N003K+005000X-005000Z-005000", "Ex. 13 N005"),
        ("N004I+005000X+005000Z-005000", "Ex. 13 N006"),
        ("N005K+005000X+005000Z+005000", "Ex. 13 N007"),
        ("N006I+005000X-005000Z+005000", "Ex. 13 N008"),
        ("N007M02", "end"),
    ];
    assert_lines(&got, &expected);
    let back = read_all(got.as_bytes(), p(30.0, 0.0, 20.0), false).expect("reads");
    assert_eq!(
        back[1].motion,
        Motion::Arc {
            centre: [0.0, 0.0],
            plane: Plane::ZX,
            clockwise: true
        }
    );
    let iso = text(N33Options::default(), p(30.0, 0.0, 20.0), &ops);
    assert_eq!(
        iso,
        got.replace("G03", "G02"),
        "ISO sense: G02 for the same arcs"
    );
}

/// Ex. 19 (§6), the parts its data allow: N003 (M13 F0624) and the rhombus N006–N009 at 75 mm/min.
/// The rest needs the L corrections, G41/G51/G43/G52 rectangular cycles and deceleration codes F4xxx
/// this emitter does not write, and its OCR digits do not close (A.13).
#[test]
fn manual_example_19_rhombus() {
    let ops = [
        Canon::MCode(3.0),
        Canon::MCode(8.0),
        Canon::FeedRate(75.0),
        Canon::Feed(p(-60.0, 60.0, 0.0)),
        Canon::Feed(p(-120.0, 0.0, 0.0)),
        Canon::Feed(p(-60.0, -60.0, 0.0)),
        Canon::Feed(p(0.0, 0.0, 0.0)),
        Canon::MCode(5.0),
        Canon::MCode(2.0),
    ];
    assert_lines(
        &text(N33Options::default(), p(0.0, 0.0, 0.0), &ops),
        &[
            ("%", "start"),
            ("N001M13F0624", "Ex. 19 N003 / N015"),
            (
                "N002G01X-006000Y+006000F0575",
                "Ex. 19 N006 (F0575 from N005)",
            ),
            ("N003X-006000Y-006000", "Ex. 19 N007"),
            ("N004X+006000Y-006000", "Ex. 19 N008"),
            ("N005X+006000Y+006000", "Ex. 19 N009"),
            (
                "N006M05F0624",
                "Ex. 19 N011's M05 (there with a move and F4720)",
            ),
            ("N007M02", "Ex. 19 N027"),
        ],
    );
}

/// A small deterministic generator.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Arcs crossing quadrants in the three planes, off-grid centres, both senses: read back, every
/// piece's end lies on the programmed circle within 0.01 mm, its centre is the programmed one within
/// 0.01 mm, and the last piece ends on the quantised end point exactly (A.12, §5.2.11).
#[test]
fn arcs_read_back_within_a_discrete() {
    let (mut worst_r, mut worst_c, mut chords, mut pieces) = (0f64, 0f64, 0, 0);
    let mut fallbacks = 0;
    for (seed, iso) in [(33, true), (34, false), (35, true), (36, false), (37, true)] {
        let mut g = Lcg(seed);
        let mut ops = Vec::new();
        let mut arcs = Vec::new();
        ops.push(Canon::FeedRate(300.0));
        for i in 0..140 {
            let plane = [Plane::XY, Plane::ZX, Plane::YZ][i % 3];
            let (a, b, _) = plane.axes();
            let c = [g.next() * 400.0 - 200.0, g.next() * 400.0 - 200.0];
            let r = 0.5 + g.next() * g.next() * 400.0;
            let a0 = g.next() * std::f64::consts::TAU;
            let full = i % 7 == 0;
            let sweep = if full {
                std::f64::consts::TAU
            } else {
                0.05 + g.next() * 6.2
            };
            let cw = g.next() < 0.5;
            let a1 = if cw { a0 - sweep } else { a0 + sweep };
            let mut from = p(0.0, 0.0, 0.0);
            from[a] = c[0] + r * a0.cos();
            from[b] = c[1] + r * a0.sin();
            let mut to = from;
            if !full {
                to[a] = c[0] + r * a1.cos();
                to[b] = c[1] + r * a1.sin();
            }
            ops.push(Canon::Feed(from));
            arcs.push((ops.len(), c, r, plane, cw, to));
            ops.push(arc(to, c, plane, cw));
        }
        let options = N33Options {
            g18_ccw_is_iso: iso,
            // Many arcs on one tape: the tape itself (150 m), not the ФСУ-2's 30 m (§5.1); the
            // arcs wander further than the machine's travels (A.2), which are not what is tested.
            max_tape_m: 150.0,
            travel: [f64::INFINITY; 6],
            ..N33Options::default()
        };
        let r = run(options, p(0.0, 0.0, 0.0), &ops);
        assert!(r.stop.is_none(), "{:?}", r.stop);
        let moves = read_all(&r.out, p(0.0, 0.0, 0.0), iso).expect("reads");
        fallbacks += r
            .warnings
            .iter()
            .filter(|w| w.contains("cannot hold"))
            .count();
        for (op, c, radius, plane, cw, to) in arcs {
            let (a, b, _) = plane.axes();
            let first = r.after[op - 1];
            let last = r.after[op];
            // Block k is on line k + 1 (line 1 is %).
            let mine: Vec<&Move> = moves
                .iter()
                .filter(|m| m.line > first + 1 && m.line <= last + 1)
                .collect();
            assert!(!mine.is_empty(), "arc {op} wrote nothing");
            for m in &mine {
                let d = (m.to[a] - c[0]).hypot(m.to[b] - c[1]);
                worst_r = worst_r.max((d - radius).abs());
                match m.motion {
                    Motion::Arc {
                        centre,
                        plane: pl,
                        clockwise,
                    } => {
                        pieces += 1;
                        assert_eq!((pl, clockwise), (plane, cw), "line {}", m.line);
                        worst_c = worst_c.max((centre[0] - c[0]).hypot(centre[1] - c[1]));
                    }
                    Motion::Feed => chords += 1,
                    other => panic!("line {}: {other:?}", m.line),
                }
            }
            let end = mine[mine.len() - 1].to;
            for i in 0..3 {
                assert_eq!(end[i], (to[i] * 100.0).round() / 100.0, "arc {op} end");
            }
        }
    }
    eprintln!(
        "{pieces} quadrant pieces, {chords} straight blocks, {fallbacks} arcs as chords; worst radius error {worst_r:.5} mm, worst centre {worst_c:.5} mm"
    );
    assert!(worst_r <= 0.01 + 1e-9, "radius error {worst_r}");
    assert!(worst_c <= 0.01 + 1e-9, "centre error {worst_c}");
}

/// A.14 §2: increments are differences of quantised absolute positions, so nothing drifts: 10 000
/// moves of 0.0137 mm (naive rounded increments would drift 1.37 mm), over 20 tapes of 500 moves
/// (one tape holds 999 blocks), each read back from where the last ended: every read-back position
/// is the quantised target exactly.
#[test]
fn no_drift_over_10000_blocks() {
    let mut at = p(0.0, 0.0, 0.0);
    let mut read_at = at;
    let mut k = 0u32;
    for _tape in 0..20 {
        let mut ops = vec![Canon::FeedRate(1000.0)];
        let mut targets = Vec::new();
        for _ in 0..500 {
            k += 1;
            let t = p(k as f64 * 0.0137, -(k as f64) * 0.0071, 0.0);
            targets.push(t);
            ops.push(Canon::Feed(t));
        }
        let r = run(N33Options::default(), at, &ops);
        assert!(r.stop.is_none(), "{:?}", r.stop);
        let moves = read_all(&r.out, read_at, true).expect("reads");
        assert_eq!(moves.len(), 500);
        for (m, t) in moves.iter().zip(&targets) {
            assert_eq!(m.to[0], (t[0] * 100.0).round() / 100.0);
            assert_eq!(m.to[1], (t[1] * 100.0).round() / 100.0);
        }
        at = targets[499];
        read_at = moves[499].to;
    }
    assert_eq!(k, 10_000);
    assert_eq!(read_at[0], 137.0);
    assert_eq!(read_at[1], -71.0);
}

/// §5.2.1: 999 blocks at most; the 1000th stops the run with the documented message, and nothing of
/// it is written (the 999 before it are).
#[test]
fn block_1000_is_refused() {
    let mut ops = vec![Canon::FeedRate(100.0)];
    for k in 1..=1000 {
        ops.push(Canon::Feed(p(k as f64, 0.0, 0.0)));
    }
    // The tape itself (150 m, §5.1), so that the 999 blocks are the limit, not the ФСУ-2's 30 m.
    let options = N33Options {
        max_tape_m: 150.0,
        ..N33Options::default()
    };
    let r = run(options, p(0.0, 0.0, 0.0), &ops);
    let Some(Stop::Alarm(a)) = &r.stop else {
        panic!("no alarm: {:?}", r.stop)
    };
    assert_eq!(a.number, ALARM);
    assert!(
        a.message.starts_with(
            "the Н33-2М takes at most 999 blocks per tape; this program needs more than that: "
        ),
        "{}",
        a.message
    );
    assert!(a.message.contains("source line 1001"), "{}", a.message);
    let out = String::from_utf8(r.out).expect("ASCII");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 1000, "% and 999 blocks");
    assert_eq!(lines[999], "N999X+000100");
    assert!(out.ends_with('\n'));
}

/// §5.1.2, A.4: the tape image: NUL leader, `%`, 2 NUL rows after every block, NUL trailer, every
/// byte of even parity; without bit 8 and the NULs it is the text form. The reader reads it, and
/// names the line of a flipped bit.
#[test]
fn parity_tape() {
    let ops = [
        Canon::FeedRate(120.0),
        Canon::Feed(p(10.0, 0.0, 0.0)),
        arc(p(-10.0, 0.0, 0.0), [0.0, 0.0], Plane::XY, false),
        Canon::Dwell(1.0),
        Canon::Feed(p(0.0, 0.0, 0.0)),
        Canon::MCode(2.0),
    ];
    let plain = text(N33Options::default(), p(0.0, 0.0, 0.0), &ops);
    let tape_options = N33Options {
        tape: true,
        ..N33Options::default()
    };
    let r = run(tape_options, p(0.0, 0.0, 0.0), &ops);
    assert!(r.stop.is_none());
    let tape = r.out;
    assert!(tape.iter().all(|b| b.count_ones() % 2 == 0), "even parity");
    assert!(tape[..100].iter().all(|&b| b == 0), "leader");
    assert_eq!(&tape[100..102], &[0xa5, 0x0a], "% LF with parity");
    assert!(tape.ends_with(&[0u8; 100]), "trailer");
    assert!(
        tape.windows(3).any(|w| w == [0x0a, 0, 0]),
        "NUL gaps after blocks"
    );
    let stripped: Vec<u8> = tape.iter().map(|b| b & 0x7f).filter(|&b| b != 0).collect();
    assert_eq!(String::from_utf8(stripped).expect("ASCII"), plain);
    assert_eq!(
        read_all(&tape, p(0.0, 0.0, 0.0), true).expect("tape reads"),
        read_all(plain.as_bytes(), p(0.0, 0.0, 0.0), true).expect("text reads")
    );
    // One flipped bit in block N003 (line 4).
    let n3 = plain.lines().nth(3).expect("line 4");
    assert!(n3.starts_with("N003"));
    let needle: Vec<u8> = n3.bytes().map(with_parity).collect();
    let at = tape
        .windows(needle.len())
        .position(|w| w == needle)
        .expect("N003 on tape");
    let mut bad = tape.clone();
    bad[at + 6] ^= 0x04;
    let err = read_all(&bad, p(0.0, 0.0, 0.0), true).expect_err("odd parity");
    assert_eq!(err.line, 4, "{err}");
    assert!(err.message.contains("odd parity"), "{err}");
}

/// §5.2.3, Table 6 and every code A.7 lists: decode to the listed feed, and encode back.
#[test]
fn feed_codes_of_the_tables() {
    let listed: [(u16, f64); 28] = [
        (315, 0.1),
        (465, 6.5),
        (525, 25.0),
        (675, 750.0),
        (720, 2000.0),
        (748, 4800.0),
        (540, 40.0),
        (550, 50.0),
        (560, 60.0),
        (575, 75.0),
        (580, 80.0),
        (610, 100.0),
        (612, 120.0),
        (624, 240.0),
        (650, 500.0),
        (660, 600.0),
        (680, 800.0),
        (710, 1000.0),
        (712, 1200.0),
        (4680, 800.0),
        (4712, 1200.0),
        (4720, 2000.0),
        (4748, 4800.0),
        (4710, 1000.0),
        (4720, 2000.0),
        (650, 500.0),
        (610, 100.0),
        (710, 1000.0),
    ];
    for (code, feed) in listed {
        assert_eq!(decode_feed(code), Some(feed), "F{code:04}");
        let back = encode_feed(feed).expect("encodes");
        // d1 = 0 always (deceleration is not written); F0315 is 0.1, written F0310 (d4 ignored).
        let want = if code == 315 { 310 } else { code % 1000 };
        assert_eq!(back, want, "F{code:04} = {feed}");
    }
    // Table 6: every code of the grid, both ways.
    let mut n = 0;
    for d2 in 3u16..=7 {
        for m in 10u16..=99 {
            if (d2 == 3 && m % 10 != 0) || (d2 == 7 && m > 48) {
                continue;
            }
            let code = d2 * 100 + m;
            let f = decode_feed(code).expect("on the grid");
            assert_eq!(encode_feed(f), Some(code), "F{code:04} = {f}");
            assert_eq!(decode_feed(4000 + code), Some(f), "F4{code:03}");
            n += 1;
        }
    }
    assert_eq!(n, 9 + 90 * 3 + 39);
    // Rounding to 2 significant digits (1228 → 1200), the carry (9.96 → 10), and the range.
    assert_eq!(encode_feed(1228.0), Some(712));
    assert_eq!(encode_feed(9.96), Some(510));
    assert_eq!(encode_feed(0.97), Some(410));
    assert_eq!(encode_feed(4850.0), None);
    assert_eq!(encode_feed(0.04), None);
    for bad in [309, 800, 749, 1610, 205, 4309] {
        assert_eq!(decode_feed(bad), None, "F{bad:04}");
    }
}

/// §5.1.1: the reader checks every word's width and the word order, naming the word.
#[test]
fn reader_checks_widths_and_order() {
    let cases = [
        ("%\nN001G01X+01000F0610\nN002M02\n", "word X+01000", 2),
        ("%\nN01G01X+001000F0610\nN002M02\n", "word N01", 2),
        ("%\nN001X+001000G01F0610\nN002M02\n", "word G01", 2),
        ("%\nN001G01X001000F0610\nN002M02\n", "word X001000", 2),
        ("%\nN001G01X+001000F610\nN002M02\n", "word F610", 2),
        ("%\nN001G01X+001000S12\nN002M02\n", "word S12", 2),
        ("%\nN001G01X+001000F0610M03\nN002M02\n", "word M03", 2),
        (
            "%\nN001G17\nN002G02I-001000X+001000Y-001000F0610\n",
            "word I-001000",
            3,
        ),
    ];
    for (tape, word, line) in cases {
        let err = read_all(tape.as_bytes(), p(0.0, 0.0, 0.0), true).expect_err(tape);
        assert_eq!(err.line, line, "{err}");
        assert!(err.message.contains(word), "{err} should name {word}");
    }
    let err = read_all(b"%\nN001G01X+001000F0610\n", p(0.0, 0.0, 0.0), true).expect_err("no M02");
    assert!(err.message.contains("M02"), "{err}");
    // §5.2.11: radii that differ by more than a discrete stop the control.
    let err = read_all(
        b"%\nN001G17\nN002G03I+001000X-001000Y+001005F0610\nN003M02\n",
        p(0.0, 0.0, 0.0),
        true,
    )
    .expect_err("radii");
    assert!(err.message.contains("radii"), "{err}");
}

/// The refusals: A B C (A.2), G95 (A.7), M04 and unknown M codes (A.8).
#[test]
fn refusals_name_the_cause() {
    let refused = |ops: &[Canon<'_>], says: &str| {
        let r = run(N33Options::default(), p(0.0, 0.0, 0.0), ops);
        match r.stop {
            Some(Stop::Alarm(a)) => assert!(a.message.contains(says), "{}", a.message),
            other => panic!("{other:?}"),
        }
    };
    let mut with_a = p(1.0, 0.0, 0.0);
    with_a[3] = 90.0;
    refused(&[Canon::FeedRate(100.0), Canon::Feed(with_a)], "A90");
    refused(&[Canon::FeedPerRev(true)], "G95");
    refused(&[Canon::MCode(4.0)], "M04");
    refused(&[Canon::MCode(19.0)], "M19");
    refused(&[Canon::Feed(p(1.0, 0.0, 0.0))], "no feed rate");
}

/// S and T dropped with warnings (§5.2.18; S names the nearest of the 18 steps, A.2), M06 an M00
/// stop, a #3006 message an M00, comments dropped (A.4), inch converted to mm, a move above
/// 999999 discretes split into equal pieces, a zero move left out, a feed above 4800 clamped.
#[test]
fn changes_with_warnings() {
    let ops = [
        Canon::Comment("(ROUGH)"),
        Canon::Speed(1200.0),
        Canon::Tool(5.0),
        Canon::MCode(6.0),
        Canon::FeedRate(6000.0),
        Canon::Feed(p(25_000.0, 0.0, 0.0)),
        Canon::Feed(p(25_000.0, 0.0, 0.0)),
        Canon::Units(true),
        Canon::FeedRate(10.0),
        Canon::Feed(p(25_000.0 / 25.4 + 1.0, 0.0, 0.0)),
    ];
    // A 25 m move is beyond the machine's travels (A.2), not what is tested here.
    let free = N33Options {
        travel: [f64::INFINITY; 6],
        ..N33Options::default()
    };
    let r = run(free, p(0.0, 0.0, 0.0), &ops);
    assert!(r.stop.is_none(), "{:?}", r.stop);
    let out = String::from_utf8(r.out).expect("ASCII");
    assert_lines(
        &out,
        &[
            ("%", "start; the comment is dropped"),
            ("N001M00F0624", "M06: an M00 stop for a manual tool change"),
            (
                "N002G01X+833333F0748",
                "25 000 mm in 3 equal pieces; F6000 clamped to 4800",
            ),
            ("N003X+833334", "piece 2"),
            (
                "N004X+833333",
                "piece 3; the zero move after it is left out",
            ),
            (
                "N005X+002540F0625",
                "inch: 1 in is 2540 discretes; 10 in/min = 254 mm/min, F0625 (250)",
            ),
            ("N006M02", "end"),
        ],
    );
    let w = r.warnings.join("\n");
    assert!(w.contains("1250 rpm"), "{w}");
    assert!(w.contains("T5"), "{w}");
    assert!(w.contains("M06 to T5"), "{w}");
    assert!(w.contains("above the Н33-2М's 4800"), "{w}");
    assert!(w.contains("inch"), "{w}");
    // #3006.
    let mut out = Vec::new();
    {
        let mut e = N33Emitter::new(&mut out, N33Options::default());
        e.canon(&Canon::Start(p(0.0, 0.0, 0.0)), Origin::default())
            .expect("start");
        e.message(1, "CHECK PART").expect("message");
        assert!(e.warnings()[0].text.contains("CHECK PART"));
        e.end().expect("end");
    }
    assert_eq!(
        String::from_utf8(out).expect("ASCII"),
        "%\nN001M00F0624\nN002M02\n"
    );
}

/// No helix on the Н33-2М (§5.2.18): a helix is written as chords within the tolerance.
#[test]
fn helix_becomes_chords() {
    let ops = [
        Canon::FeedRate(200.0),
        arc(p(10.0, 0.0, -5.0), [0.0, 0.0], Plane::XY, false),
    ];
    let from = p(10.0, 0.0, 0.0);
    let r = run(N33Options::default(), from, &ops);
    assert!(r.stop.is_none());
    let out = String::from_utf8(r.out.clone()).expect("ASCII");
    assert!(!out.contains("G02") && !out.contains("G03"), "{out}");
    let moves = read_all(&r.out, from, true).expect("reads");
    assert!(moves.len() > 20, "{} chords", moves.len());
    for m in &moves {
        let d = m.to[0].hypot(m.to[1]);
        assert!((d - 10.0).abs() <= 0.011, "{m:?}");
    }
    assert_eq!(moves[moves.len() - 1].to, p(10.0, 0.0, -5.0));
    assert!(r.warnings.iter().any(|w| w.contains("helix")));
}
