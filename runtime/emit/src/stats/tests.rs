use super::*;
use fmsvm_canon::Plane;
use std::f64::consts::PI;

fn p(x: f64, y: f64, z: f64) -> Pose {
    [x, y, z, 0.0, 0.0, 0.0]
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9 * (1.0 + b.abs())
}

fn run(ops: &[Canon<'_>], rapid: f64) -> Report {
    let mut s = Stats::default();
    for op in ops {
        s.op(op);
    }
    s.finish(rapid)
}

#[test]
fn stats_square_at_feed() {
    // A 10 × 10 square at F100 after a rapid of 100 to its corner: 40 mm at 100 mm/min is 24 s; the
    // rapid at 5000 mm/min is 1.2 s.
    let r = run(
        &[
            Canon::Rapid(p(100.0, 0.0, 0.0)),
            Canon::FeedRate(100.0),
            Canon::Feed(p(110.0, 0.0, 0.0)),
            Canon::Feed(p(110.0, 10.0, 0.0)),
            Canon::Feed(p(100.0, 10.0, 0.0)),
            Canon::Feed(p(100.0, 0.0, 0.0)),
        ],
        5000.0,
    );
    assert_eq!((r.rapids, r.feeds, r.arcs), (1, 4, 0));
    assert!(close(r.rapid_length, 100.0) && close(r.feed_length, 40.0));
    assert!(close(r.feed_seconds, 24.0), "{}", r.feed_seconds);
    assert!(close(r.rapid_seconds, 1.2), "{}", r.rapid_seconds);
    assert!(close(r.total_seconds, 25.2));
    let b = r.bounds.expect("moved");
    // The start (origin) is in the box: the rapid left from there.
    assert_eq!(
        (b.min[0], b.min[1], b.max[0], b.max[1]),
        (0.0, 0.0, 110.0, 10.0)
    );
    assert!(!r.inch && r.untimed_feeds == 0);
}

#[test]
fn stats_quarter_arc_passes_the_quadrant_point() {
    // R10 about the origin from 45° to 135°, counter-clockwise: it passes (0, 10), which neither end
    // reaches (their Y is 7.07).
    let h = 10.0 / 2f64.sqrt();
    let mut s = Stats::new(p(h, h, 0.0));
    s.op(&Canon::FeedRate(60.0));
    s.op(&Canon::Arc(Arc {
        to: p(-h, h, 0.0),
        centre: [0.0, 0.0],
        plane: Plane::XY,
        clockwise: false,
        turns: 0,
    }));
    let r = s.finish(10_000.0);
    let b = r.bounds.expect("moved");
    assert!(close(b.max[1], 10.0), "{:?}", b);
    assert!(close(b.min[1], h) && close(b.min[0], -h) && close(b.max[0], h));
    // A quarter of 2π·10 at 60 mm/min: 5π mm, 5π s.
    assert!(close(r.arc_length, 5.0 * PI) && close(r.feed_length, 5.0 * PI));
    assert!(close(r.feed_seconds, 5.0 * PI));
    // The same arc clockwise goes the long way round: through (10, 0), (0, −10) and (−10, 0).
    let mut s = Stats::new(p(h, h, 0.0));
    s.op(&Canon::Arc(Arc {
        to: p(-h, h, 0.0),
        centre: [0.0, 0.0],
        plane: Plane::XY,
        clockwise: true,
        turns: 0,
    }));
    let b = s.finish(1.0).bounds.expect("moved");
    assert!(close(b.max[0], 10.0) && close(b.min[1], -10.0) && close(b.min[0], -10.0));
    assert!(close(b.max[1], h));
}

#[test]
fn stats_arc_extents_in_other_planes() {
    // G18 (Z X): from Z0 X10 (90° in the Z X plane) to Z10 X0 (0°) counter-clockwise is three
    // quarters, through 180° (Z −10) and 270° (X −10).
    let from = p(10.0, 0.0, 0.0);
    let arc = Arc {
        to: p(0.0, 0.0, 10.0),
        centre: [0.0, 0.0],
        plane: Plane::ZX,
        clockwise: false,
        turns: 0,
    };
    let mut b = Bounds::EMPTY;
    b.add_arc(&from, &arc);
    assert!(close(b.min[0], -10.0) && close(b.min[2], -10.0), "{b:?}");
    assert!(close(b.max[0], 10.0) && close(b.max[2], 10.0));
    assert_eq!((b.min[1], b.max[1]), (0.0, 0.0));
    // A whole extra turn passes every extreme.
    let mut b = Bounds::EMPTY;
    b.add_arc(
        &from,
        &Arc {
            clockwise: true,
            turns: 1,
            ..arc
        },
    );
    assert!(close(b.min[0], -10.0) && close(b.min[2], -10.0));
}

#[test]
fn stats_helix_length() {
    // A full circle R5 in G17 dropping 2 in Z (end = start in the plane: one turn), then one more
    // turn (turns 1) dropping 2 again: each is hypot(10π, 2).
    let mut s = Stats::new(p(5.0, 0.0, 0.0));
    s.op(&Canon::FeedRate(100.0));
    let helix = Arc {
        to: p(5.0, 0.0, -2.0),
        centre: [0.0, 0.0],
        plane: Plane::XY,
        clockwise: true,
        turns: 0,
    };
    s.op(&Canon::Arc(helix));
    let one = (10.0 * PI).hypot(2.0);
    let r = s.finish(1.0);
    assert!(close(r.arc_length, one), "{} {}", r.arc_length, one);
    s.op(&Canon::Arc(Arc {
        to: p(5.0, 0.0, -6.0),
        turns: 1,
        ..helix
    }));
    let r = s.finish(1.0);
    assert!(close(r.arc_length, one + (20.0 * PI).hypot(4.0)));
    assert!(close(r.feed_seconds, r.arc_length / 100.0 * 60.0));
    let b = r.bounds.expect("moved");
    assert!(close(b.min[0], -5.0) && close(b.max[1], 5.0) && close(b.min[2], -6.0));
    assert_eq!(r.arcs, 2);
}

#[test]
fn stats_dwell_and_rapid_rate() {
    let r = run(
        &[
            Canon::Rapid(p(0.0, 0.0, 50.0)),
            Canon::Dwell(2.5),
            Canon::Rapid(p(30.0, 40.0, 50.0)),
            Canon::Dwell(0.5),
        ],
        3000.0,
    );
    assert_eq!((r.dwells, r.rapids), (2, 2));
    assert!(close(r.dwell_seconds, 3.0));
    // 50 + 50 = 100 mm at 3000 mm/min: 2 s.
    assert!(close(r.rapid_length, 100.0) && close(r.rapid_seconds, 2.0));
    assert!(close(r.total_seconds, 5.0));
    assert_eq!(r.feed_seconds, 0.0);
    assert_eq!(r.rapid_rate, 3000.0);
}

#[test]
fn stats_feed_per_rev_needs_the_spindle() {
    // G95 F0.1 with no S: untimed. Then S1000: 0.1 mm/rev × 1000 rev/min = 100 mm/min.
    let r = run(
        &[
            Canon::FeedPerRev(true),
            Canon::FeedRate(0.1),
            Canon::Feed(p(10.0, 0.0, 0.0)),
            Canon::Speed(1000.0),
            Canon::Feed(p(20.0, 0.0, 0.0)),
        ],
        1.0,
    );
    assert_eq!(r.untimed_feeds, 1);
    assert!(close(r.untimed_length, 10.0) && close(r.feed_length, 20.0));
    assert!(close(r.feed_seconds, 6.0));
    // A feed with no F at all is untimed too.
    let r = run(&[Canon::Feed(p(1.0, 0.0, 0.0))], 1.0);
    assert_eq!((r.untimed_feeds, r.feed_seconds), (1, 0.0));
}

#[test]
fn stats_inch_program_reports_inches() {
    // G20 X1 at F10 inch/min: 6 s; reported as 1 inch.
    let r = run(
        &[
            Canon::Units(true),
            Canon::FeedRate(10.0),
            Canon::Feed(p(1.0, 0.0, 0.0)),
            Canon::Rapid(p(1.0, 2.0, 0.0)),
        ],
        2540.0,
    );
    assert!(r.inch);
    assert!(close(r.feed_length, 1.0) && close(r.rapid_length, 2.0));
    assert!(close(r.feed_seconds, 6.0));
    // 2 in = 50.8 mm at 2540 mm/min: 1.2 s.
    assert!(close(r.rapid_seconds, 1.2));
    assert!(close(r.bounds.expect("moved").max[1], 2.0));
}

#[test]
fn stats_rotary_feed_in_degrees() {
    // A90 alone at F360 (deg/min): 15 s, no length.
    let r = run(
        &[
            Canon::FeedRate(360.0),
            Canon::Feed([0.0, 0.0, 0.0, 90.0, 0.0, 0.0]),
        ],
        1.0,
    );
    assert_eq!(r.feed_length, 0.0);
    assert!(close(r.feed_seconds, 15.0));
    assert_eq!(r.bounds.expect("moved").max[3], 90.0);
}

#[test]
fn stats_tool_changes_m_codes_comments() {
    // With M6: the M6s count (T1 M6, T2 M6, T2 again without M6 does nothing).
    let r = run(
        &[
            Canon::Tool(1.0),
            Canon::MCode(6.0),
            Canon::MCode(3.0),
            Canon::Comment("ROUGH"),
            Canon::Tool(2.0),
            Canon::MCode(6.0),
            Canon::Tool(3.0),
            Canon::MCode(30.0),
        ],
        1.0,
    );
    assert_eq!((r.tool_changes, r.m_codes, r.comments), (2, 4, 1));
    assert!(r.bounds.is_none() && r.total_seconds == 0.0);
    // A lathe program without M6: each different T is a change.
    let r = run(
        &[
            Canon::Tool(101.0),
            Canon::Tool(101.0),
            Canon::Tool(202.0),
            Canon::Tool(101.0),
        ],
        1.0,
    );
    assert_eq!(r.tool_changes, 3);
}

#[test]
fn stats_memory_is_constant() {
    // Many moves: the statistics hold no move (the type's size is all there is).
    let mut s = Stats::default();
    s.op(&Canon::FeedRate(1000.0));
    for i in 0..200_000 {
        let x = (i % 2) as f64;
        s.op(&Canon::Feed(p(x, i as f64 * 0.001, 0.0)));
    }
    let r = s.finish(1.0);
    assert_eq!(r.feeds, 200_000);
    assert!(std::mem::size_of::<Stats>() < 512);
}
