use super::*;

fn line(from: [f64; 2], to: [f64; 2]) -> Element {
    Element::Line { from, to }
}
fn arc(from: [f64; 2], to: [f64; 2], centre: [f64; 2], clockwise: bool) -> Element {
    Element::Arc {
        from,
        to,
        centre,
        clockwise,
    }
}
fn near(a: [f64; 2], b: [f64; 2], tol: f64) -> bool {
    dist(a, b) <= tol
}
#[track_caller]
fn assert_near(a: [f64; 2], b: [f64; 2], tol: f64) {
    assert!(near(a, b, tol), "{a:?} is not {b:?} (within {tol})");
}
#[track_caller]
fn fillet(e: &Element) -> ([f64; 2], [f64; 2], [f64; 2], bool) {
    match *e {
        Element::Arc {
            from,
            to,
            centre,
            clockwise,
        } => (from, to, centre, clockwise),
        Element::Line { .. } => panic!("not an arc: {e:?}"),
    }
}

/// Rounds the corner and checks what every rounding must be: the first element keeps its start
/// and ends where the rounding starts, the second starts where it ends and keeps its end; the
/// rounding has radius r at both ends, its ends lie on the elements' curves, its centre is r
/// from each line and ρ ± r from each arc's centre, and the direction of travel does not break
/// at either joint (tangency). Returns the rounding.
#[track_caller]
fn round(a: &Element, b: &Element, r: f64) -> Element {
    let (na, f, nb) = corner(a, b, Corner::Round(r)).unwrap();
    let (fa, fb, fc, _) = fillet(&f);
    assert_eq!(na.from(), a.from());
    assert_eq!(nb.to(), b.to());
    assert_eq!(na.to(), fa);
    assert_eq!(nb.from(), fb);
    assert!((dist(fa, fc) - r).abs() < 1e-9 && (dist(fb, fc) - r).abs() < 1e-9);
    for (e, t) in [(a, fa), (b, fb)] {
        match *e {
            Element::Line { from, to } => {
                let d = unit(sub(to, from)).unwrap();
                // On the line, and the centre r from it.
                assert!(cross(d, sub(t, from)).abs() < 1e-9);
                assert!((cross(d, sub(fc, from)).abs() - r).abs() < 1e-9);
            }
            Element::Arc { from, centre, .. } => {
                let rho = dist(from, centre);
                assert!((dist(t, centre) - rho).abs() < 1e-9);
                let k = dist(fc, centre);
                assert!(
                    (k - (rho - r)).abs() < 1e-9 || (k - (rho + r)).abs() < 1e-9,
                    "centre {k} from the arc's centre, not {rho} ± {r}"
                );
            }
        }
        let u = e.tangent_at(t).unwrap();
        let v = f.tangent_at(t).unwrap();
        assert!(near(u, v, 1e-9), "not tangent at {t:?}: {u:?} / {v:?}");
    }
    f
}

#[test]
fn line_line_rounding_at_right_angles() {
    // 11, corner X100 Y-50: X- → X+ then Y+, a left turn of 90°. The tangent points are
    // R·tan(45°) = R = 10 from the corner: X90 Y-50 and X100 Y-40; the centre X90 Y-40; G3.
    let a = line([-100.0, -50.0], [100.0, -50.0]);
    let b = line([100.0, -50.0], [100.0, 50.0]);
    let f = round(&a, &b, 10.0);
    assert_eq!(
        corner(&a, &b, Corner::Round(10.0)).unwrap(),
        (
            line([-100.0, -50.0], [90.0, -50.0]),
            arc([90.0, -50.0], [100.0, -40.0], [90.0, -40.0], false),
            line([100.0, -40.0], [100.0, 50.0]),
        )
    );
    assert_eq!(f, arc([90.0, -50.0], [100.0, -40.0], [90.0, -40.0], false));
    // 13 N240/N250, corner X0 Y100: X- then Y-, left: X20 Y100 → X0 Y80 about X20 Y80, G3.
    let f = round(
        &line([150.0, 100.0], [0.0, 100.0]),
        &line([0.0, 100.0], [0.0, 0.0]),
        20.0,
    );
    assert_eq!(f, arc([20.0, 100.0], [0.0, 80.0], [20.0, 80.0], false));
    // 30 N190/N200 ,R9, corner X11 Y-11: Y+ then X+, a right turn: X11 Y-20 → X20 Y-11 about
    // X20 Y-20, G2 (the twin's "G2 X20 Y-11 I9 J0").
    let f = round(
        &line([11.0, -35.0], [11.0, -11.0]),
        &line([11.0, -11.0], [120.0, -11.0]),
        9.0,
    );
    assert_eq!(f, arc([11.0, -20.0], [20.0, -11.0], [20.0, -20.0], true));
    // 30 N270/N280, corner X-11 Y-11: X+ then Y-, right: X-20 Y-11 → X-11 Y-20 about X-20 Y-20.
    let f = round(
        &line([-120.0, -11.0], [-11.0, -11.0]),
        &line([-11.0, -11.0], [-11.0, -35.0]),
        9.0,
    );
    let (fa, fb, fc, cw) = fillet(&f);
    assert_near(fa, [-20.0, -11.0], 1e-12);
    assert_near(fb, [-11.0, -20.0], 1e-12);
    assert_near(fc, [-20.0, -20.0], 1e-12);
    assert!(cw);
}

#[test]
fn line_line_rounding_at_135_degrees() {
    // 13 N230/N240 with ,R10: X200 Y50 → X150 Y100 (d₁ = (−1, 1)/√2), then X0 Y100 (d₂ = (−1, 0)).
    // d₁ × d₂ = 0·(−1/√2) − (1/√2)(−1) = 1/√2 > 0: left, G3, a turn θ = 45° (an inner angle of 135°).
    // The tangent points are R·tan(θ/2) = 10·(√2 − 1) = 4.142136 from the corner:
    // on the first line X150 + 4.142136/√2 = X152.928932, Y100 − 2.928932 = Y97.071068;
    // on the second X145.857864 Y100; the centre R to the left of d₂ (left(d₂) = (0, −1)):
    // X145.857864 Y90. Check: its distance from the first line, d₁ × (F − P) =
    // (−1/√2)(−10) − (1/√2)(−4.142136) = 14.142136/√2 = 10.
    let t = 10.0 * (2f64.sqrt() - 1.0);
    let f = round(
        &line([200.0, 50.0], [150.0, 100.0]),
        &line([150.0, 100.0], [0.0, 100.0]),
        10.0,
    );
    let (fa, fb, fc, cw) = fillet(&f);
    assert_near(fa, [150.0 + t / 2f64.sqrt(), 100.0 - t / 2f64.sqrt()], 1e-9);
    assert_near(fa, [152.928932, 97.071068], 1e-6);
    assert_near(fb, [145.857864, 100.0], 1e-6);
    assert_near(fc, [145.857864, 90.0], 1e-6);
    assert!(!cw);
}

#[test]
fn chamfers_between_lines() {
    // 13 N210/N220 ,C10, corner X200 Y0 (X+ then Y+): X190 Y0 → X200 Y10, as the twin.
    let (a, c, b) = corner(
        &line([100.0, 0.0], [200.0, 0.0]),
        &line([200.0, 0.0], [200.0, 50.0]),
        Corner::Chamfer(10.0),
    )
    .unwrap();
    assert_eq!(a, line([100.0, 0.0], [190.0, 0.0]));
    assert_eq!(c, line([190.0, 0.0], [200.0, 10.0]));
    assert_eq!(b, line([200.0, 10.0], [200.0, 50.0]));
    // ,C10 at the 135° corner X150 Y100: 10 back along d₁ = (−1, 1)/√2 is X150 + 10/√2 =
    // X157.071068, Y100 − 7.071068 = Y92.928932; 10 on along X−: X140 Y100.
    let (a, c, b) = corner(
        &line([200.0, 50.0], [150.0, 100.0]),
        &line([150.0, 100.0], [0.0, 100.0]),
        Corner::Chamfer(10.0),
    )
    .unwrap();
    assert_near(a.to(), [157.071068, 92.928932], 1e-6);
    assert_eq!(c.from(), a.to());
    assert_near(c.to(), [140.0, 100.0], 1e-9);
    assert_eq!(b, line(c.to(), [0.0, 100.0]));
}

#[test]
fn chamfer_on_an_arc_is_measured_as_the_chord() {
    // X0 Y0 → X10 Y0, then G2 about X20 Y0 (R10) over the top to X30 Y0: at X10 Y0 the arc
    // heads Y+, a left turn of 90°. ,C5: X5 Y0 on the line; on the arc the chord 5 spans
    // δ = 2·asin(5/20), cos δ = 1 − 2·(1/4)² = 0.875, sin δ = 2·(1/4)·√(1 − 1/16) = 0.484123,
    // and the radius vector (−10, 0) turned clockwise by δ is (−10 cos δ, 10 sin δ):
    // X20 − 8.75 = X11.25, Y4.841229; its distance from X10 Y0 is √(1.25² + 4.841229²) = 5.
    let a = line([0.0, 0.0], [10.0, 0.0]);
    let b = arc([10.0, 0.0], [30.0, 0.0], [20.0, 0.0], true);
    let (na, c, nb) = corner(&a, &b, Corner::Chamfer(5.0)).unwrap();
    assert_near(na.to(), [5.0, 0.0], 1e-12);
    assert_near(c.to(), [11.25, 4.841229], 1e-6);
    assert!((dist(c.to(), [10.0, 0.0]) - 5.0).abs() < 1e-9);
    assert_eq!(nb, arc(c.to(), [30.0, 0.0], [20.0, 0.0], true));
    // Longer than the diameter: 0055.
    assert_eq!(
        corner(&a, &b, Corner::Chamfer(21.0)).unwrap_err().number,
        DOES_NOT_FIT
    );
}

#[test]
fn line_arc_and_arc_line_rounding() {
    // The same corner: X0 Y0 → X10 Y0 (X+), then G2 about X20 Y0, R10, heading Y+ at X10 Y0: a
    // left turn, so the rounding R2 lies left of both, G3. The line's offset is Y2; left of a
    // G2 arc is its outside: the circle R10 + 2 = 12 about X20 Y0. They meet at
    // X20 − √(12² − 2²) = 20 − √140 = X8.167840 Y2 (the one nearer the corner). Tangent points:
    // X8.167840 Y0 on the line; on the arc X20 Y0 + (F − C)·10/12 =
    // (20 − 11.832160·10/12, 2·10/12) = X10.139867 Y1.666667.
    let a = line([0.0, 0.0], [10.0, 0.0]);
    let b = arc([10.0, 0.0], [30.0, 0.0], [20.0, 0.0], true);
    let f = round(&a, &b, 2.0);
    let (fa, fb, fc, cw) = fillet(&f);
    let x = 20.0 - 140f64.sqrt();
    assert_near(fc, [x, 2.0], 1e-12);
    assert_near(fc, [8.167840, 2.0], 1e-6);
    assert_near(fa, [8.167840, 0.0], 1e-6);
    assert_near(fb, [10.139867, 1.666667], 1e-6);
    assert!(!cw);
    // Backwards: G3 about X20 Y0 from X30 Y0 over the top to X10 Y0 (heading Y− there), then
    // X0 Y0 (X−): (0, −1) × (−1, 0) = −1, a right turn; the same circle, now G2 from the arc.
    let a = arc([30.0, 0.0], [10.0, 0.0], [20.0, 0.0], false);
    let b = line([10.0, 0.0], [0.0, 0.0]);
    let f = round(&a, &b, 2.0);
    let (fa, fb, fc, cw) = fillet(&f);
    assert_near(fc, [x, 2.0], 1e-12);
    assert_near(fa, [10.139867, 1.666667], 1e-6);
    assert_near(fb, [8.167840, 0.0], 1e-6);
    assert!(cw);
    // A rounding inside a G3 arc: X0 Y-10 → X0 Y0 (Y+), then G3 about X-10 Y0 (R10) from X0 Y0
    // (heading Y+: tangent, no corner) is not a corner; take G3 about X0 Y10 instead, which at
    // X0 Y0 heads X+: a right turn, the rounding right of both, i.e. outside that G3 arc
    // (R10 + 3 = 13 about X0 Y10) and at X3 from the line: X3, Y10 − √(169 − 9) = Y-2.649111.
    let a = line([0.0, -10.0], [0.0, 0.0]);
    let b = arc([0.0, 0.0], [0.0, 20.0], [0.0, 10.0], false);
    let f = round(&a, &b, 3.0);
    let (_, _, fc, cw) = fillet(&f);
    assert_near(fc, [3.0, 10.0 - 160f64.sqrt()], 1e-12);
    assert!(cw);
}

/// The four circles of 28 (R505 about X∓467.5, R185 about Y∓135) or 29 (R460 about X∓420, R200
/// about Y∓100), chained as the book's N200–N240 from the start X37.5 / X40 Y0.
fn chain(big: (f64, f64), small: (f64, f64), start: [f64; 2]) -> Vec<Element> {
    let centres = [
        ([-big.0, 0.0], big.1),
        ([0.0, -small.0], small.1),
        ([big.0, 0.0], big.1),
        ([0.0, small.0], small.1),
        ([-big.0, 0.0], big.1),
    ];
    let mut points = vec![start];
    for w in centres.windows(2) {
        points.push(circle_intersection(w[0].0, w[0].1, w[1].0, w[1].1, -1.0).unwrap());
    }
    points.push(start);
    (0..5)
        .map(|i| arc(points[i], points[i + 1], centres[i].0, false))
        .collect()
}

#[test]
fn the_nine_corners_of_the_q_table() {
    // README table: both arcs G3, Q-1 left of the line from the first centre to the second,
    // Q1 right of it. E.g. 28 N200/N210: d = (467.5, −135), L = 486.601, a = (505² − 185² +
    // L²)/2L = 454.345, h = √(505² − a²) = 220.445; left(d)/L = (0.27743, 0.96075):
    // X−467.5 + 454.345·0.96075 + 220.445·0.27743 = X35.346,
    // Y0 − 454.345·0.27743 + 220.445·0.96075 = Y46.592.
    // (first centre, R, second centre, R, Q, corner taken)
    type Row = ([f64; 2], f64, [f64; 2], f64, f64, [f64; 2]);
    let rows: [Row; 9] = [
        (
            [-467.5, 0.0],
            505.0,
            [0.0, -135.0],
            185.0,
            -1.0,
            [35.346, 46.592],
        ),
        (
            [0.0, -135.0],
            185.0,
            [467.5, 0.0],
            505.0,
            -1.0,
            [-35.346, 46.592],
        ),
        (
            [467.5, 0.0],
            505.0,
            [0.0, 135.0],
            185.0,
            -1.0,
            [-35.346, -46.592],
        ),
        (
            [0.0, 135.0],
            185.0,
            [-467.5, 0.0],
            505.0,
            -1.0,
            [35.346, -46.592],
        ),
        (
            [-420.0, 0.0],
            460.0,
            [0.0, -100.0],
            200.0,
            -1.0,
            [29.480, 97.815],
        ),
        (
            [0.0, -100.0],
            200.0,
            [420.0, 0.0],
            460.0,
            -1.0,
            [-29.480, 97.815],
        ),
        (
            [420.0, 0.0],
            460.0,
            [0.0, 100.0],
            200.0,
            -1.0,
            [-29.480, -97.815],
        ),
        (
            [0.0, 100.0],
            200.0,
            [-420.0, 0.0],
            460.0,
            -1.0,
            [29.480, -97.815],
        ),
        // 30 N230/N240: x = 0 by symmetry, y = −20 ± √(31² − 20²) = −20 ± 23.685; right of
        // the line X20 → X−20 (heading X−) is Y+: Y3.685.
        ([20.0, -20.0], 31.0, [-20.0, -20.0], 31.0, 1.0, [0.0, 3.685]),
    ];
    for (c1, r1, c2, r2, q, want) in rows {
        let p = circle_intersection(c1, r1, c2, r2, q).unwrap();
        assert_near(p, want, 0.001);
        // All G3: the turn rule gives the same point, and the point is on both circles.
        assert_eq!(
            arc_intersection(c1, r1, false, c2, r2, false, q).unwrap(),
            p
        );
        assert!((dist(p, c1) - r1).abs() < 1e-9 && (dist(p, c2) - r2).abs() < 1e-9);
        // The other Q takes the other point, mirrored in the line of centres.
        let o = circle_intersection(c1, r1, c2, r2, -q).unwrap();
        assert!(dist(o, p) > 1.0);
        // Q counts by its sign only.
        assert_eq!(circle_intersection(c1, r1, c2, r2, q * 7.0).unwrap(), p);
    }
    assert_near(
        circle_intersection([20.0, -20.0], 31.0, [-20.0, -20.0], 31.0, 1.0).unwrap(),
        [0.0, -20.0 + 561f64.sqrt()],
        1e-12,
    );
}

#[test]
fn q_for_g2_arcs_is_the_turn_rule() {
    // Inferred: Q-1 where the contour turns left. G2–G2 takes the same (left) point as G3–G3;
    // G3–G2 and G2–G3 the other one. Checked by the turn at the point itself.
    let (c1, c2, r) = ([20.0, -20.0], [-20.0, -20.0], 31.0);
    let left_point = circle_intersection(c1, r, c2, r, -1.0).unwrap();
    assert_near(left_point, [0.0, -43.685], 0.001);
    for (cw1, cw2) in [(false, false), (true, true), (false, true), (true, false)] {
        for q in [-1.0, 1.0] {
            let p = arc_intersection(c1, r, cw1, c2, r, cw2, q).unwrap();
            let a = arc([20.0, 11.0], p, c1, cw1);
            let b = arc(p, [-20.0, 11.0], c2, cw2);
            let turn = cross(a.tangent_at(p).unwrap(), b.tangent_at(p).unwrap());
            assert_eq!(turn > 0.0, q < 0.0, "{cw1} {cw2} Q{q}: turn {turn}");
            assert_eq!(near(p, left_point, 1e-9), (cw1 == cw2) == (q < 0.0));
        }
    }
}

#[test]
fn roundings_between_the_arcs_of_28_29_30() {
    // 28: ,R14 at each corner, G3 arcs turning left: inside both circles, the centre at
    // 505 − 14 = 491 and 185 − 14 = 171 from the two centres, on the Q side:
    // README X±22.2835 Y±34.5419.
    let want = [
        [22.2835, 34.5419],
        [-22.2835, 34.5419],
        [-22.2835, -34.5419],
        [22.2835, -34.5419],
    ];
    let arcs = chain((467.5, 505.0), (135.0, 185.0), [37.5, 0.0]);
    for (i, w) in want.iter().enumerate() {
        let f = round(&arcs[i], &arcs[i + 1], 14.0);
        let (_, _, fc, cw) = fillet(&f);
        assert_near(fc, *w, 0.0001);
        assert!(!cw);
        assert!(
            (dist(fc, [-467.5, 0.0]) - 491.0).abs() < 1e-9
                || (dist(fc, [467.5, 0.0]) - 491.0).abs() < 1e-9
        );
    }
    // 29: ,R18, inside both (460 − 18, 200 − 18): X±14.4349 Y±81.4267.
    let want = [
        [14.4349, 81.4267],
        [-14.4349, 81.4267],
        [-14.4349, -81.4267],
        [14.4349, -81.4267],
    ];
    let arcs = chain((420.0, 460.0), (100.0, 200.0), [40.0, 0.0]);
    for (i, w) in want.iter().enumerate() {
        let (_, _, fc, cw) = fillet(&round(&arcs[i], &arcs[i + 1], 18.0));
        assert_near(fc, *w, 0.0001);
        assert!(!cw);
    }
    // The rounded chain of 29 is still one contour: each element starts where the last ended.
    let mut prev = arcs[0].from();
    let mut rest = arcs[0];
    for b in &arcs[1..] {
        let (a, f, nb) = corner(&rest, b, Corner::Round(18.0)).unwrap();
        assert_eq!(a.from(), prev);
        assert_eq!(f.from(), a.to());
        assert_eq!(nb.from(), f.to());
        prev = f.to();
        rest = nb;
    }
    assert_eq!(rest.to(), [40.0, 0.0]);
    // 30 N230/N240 ,R5: both G3, turning right (Q1): outside both circles, 31 + 5 = 36 from
    // X±20 Y-20: x = 0, y = −20 + √(36² − 20²) = −20 + √896 = Y9.9333; G2.
    let p = circle_intersection([20.0, -20.0], 31.0, [-20.0, -20.0], 31.0, 1.0).unwrap();
    let a = arc([20.0, 11.0], p, [20.0, -20.0], false);
    let b = arc(p, [-20.0, 11.0], [-20.0, -20.0], false);
    let f = round(&a, &b, 5.0);
    let (fa, fb, fc, cw) = fillet(&f);
    assert_near(fc, [0.0, -20.0 + 896f64.sqrt()], 1e-9);
    assert_near(fc, [0.0, 9.9333], 0.0001);
    assert!(cw);
    // Tangent points on the lines from each centre through the rounding's centre, 31/36 of
    // the way: X20 − 20·31/36 = X2.7778, Y−20 + 29.9333·31/36 = Y5.7759 (and mirrored).
    assert_near(fa, [2.7778, 5.7759], 0.0001);
    assert_near(fb, [-2.7778, 5.7759], 0.0001);
}

#[test]
fn zero_values_are_markers() {
    // ,R0 (exercise 10): the elements unchanged, a zero-radius arc at the corner that says the
    // turn (X+ then Y+: left, G3); ,C0 a zero-length line.
    let a = line([-100.0, -50.0], [100.0, -50.0]);
    let b = line([100.0, -50.0], [100.0, 50.0]);
    let (na, m, nb) = corner(&a, &b, Corner::Round(0.0)).unwrap();
    assert_eq!((na, nb), (a, b));
    assert_eq!(
        m,
        arc([100.0, -50.0], [100.0, -50.0], [100.0, -50.0], false)
    );
    assert!(m.is_marker());
    let (_, m, _) = corner(&b, &line([100.0, 50.0], [200.0, 50.0]), Corner::Round(0.0)).unwrap();
    assert!(
        m.is_marker()
            && matches!(
                m,
                Element::Arc {
                    clockwise: true,
                    ..
                }
            )
    );
    let (na, m, nb) = corner(&a, &b, Corner::Chamfer(0.0)).unwrap();
    assert_eq!((na, nb), (a, b));
    assert_eq!(m, line([100.0, -50.0], [100.0, -50.0]));
    assert!(m.is_marker());
    // Real elements are not markers, a full circle included.
    assert!(!a.is_marker());
    assert!(!arc([10.0, 0.0], [10.0, 0.0], [0.0, 0.0], false).is_marker());
}

#[test]
fn corners_that_do_not_fit() {
    let a = line([0.0, 0.0], [100.0, 0.0]);
    let b = line([100.0, 0.0], [100.0, 5.0]);
    // At 90° R10 takes 10 from each line; the second is 5 long: 0055.
    let e = corner(&a, &b, Corner::Round(10.0)).unwrap_err();
    assert_eq!(e.number, DOES_NOT_FIT);
    assert!(e.message.contains("past the end"), "{}", e.message);
    let e = corner(
        &b.with_from([100.0, 0.0]),
        &line([100.0, 5.0], [0.0, 5.0]),
        Corner::Chamfer(6.0),
    );
    assert_eq!(e.unwrap_err().number, DOES_NOT_FIT);
    // Exactly the length of the first element: fits, the first element keeps no length.
    let (na, _, _) = corner(
        &line([95.0, 0.0], [100.0, 0.0]),
        &line([100.0, 0.0], [100.0, 50.0]),
        Corner::Round(5.0),
    )
    .unwrap();
    assert!(dist(na.from(), na.to()) < 1e-12);
    // A rounding R12 inside a G3 arc of R10 (the arc turning left, the turn left): 0055.
    let a = line([10.0, -20.0], [10.0, 0.0]);
    let b = arc([10.0, 0.0], [-10.0, 0.0], [0.0, 0.0], false);
    // At X10 Y0 the G3 arc about X0 Y0 heads Y+: tangent to the line — no corner, 0051.
    assert_eq!(
        corner(&a, &b, Corner::Round(2.0)).unwrap_err().number,
        NO_CORNER
    );
    let a = line([0.0, -20.0], [10.0, 0.0]);
    let e = corner(&a, &b, Corner::Round(12.0)).unwrap_err();
    assert_eq!(e.number, DOES_NOT_FIT);
    // A rounding larger than a short arc allows: 28's arcs with R150: 0055.
    let arcs = chain((467.5, 505.0), (135.0, 185.0), [37.5, 0.0]);
    assert_eq!(
        corner(&arcs[0], &arcs[1], Corner::Round(150.0))
            .unwrap_err()
            .number,
        DOES_NOT_FIT
    );
    // Negative or NaN values: 0055.
    let b = line([10.0, 0.0], [10.0, 10.0]);
    let a = line([0.0, 0.0], [10.0, 0.0]);
    assert_eq!(
        corner(&a, &b, Corner::Round(-1.0)).unwrap_err().number,
        DOES_NOT_FIT
    );
    assert_eq!(
        corner(&a, &b, Corner::Chamfer(f64::NAN))
            .unwrap_err()
            .number,
        DOES_NOT_FIT
    );
    // A reversal: 0055.
    let back = line([10.0, 0.0], [0.0, 0.0]);
    assert_eq!(
        corner(&a, &back, Corner::Round(1.0)).unwrap_err().number,
        DOES_NOT_FIT
    );
}

#[test]
fn no_corner() {
    // Collinear lines: 0051, for ,R0 too.
    let a = line([0.0, 0.0], [10.0, 0.0]);
    let b = line([10.0, 0.0], [20.0, 0.0]);
    for c in [Corner::Round(1.0), Corner::Round(0.0), Corner::Chamfer(1.0)] {
        let e = corner(&a, &b, c).unwrap_err();
        assert_eq!(e.number, NO_CORNER);
        assert!(e.message.contains("tangent"), "{}", e.message);
    }
    // 13 N180/N190: Y+ into the G2 R25 about X75 Y30, which heads Y+ at X50 Y30: tangent.
    let a = line([50.0, 0.0], [50.0, 30.0]);
    let b = arc([50.0, 30.0], [100.0, 30.0], [75.0, 30.0], true);
    assert_eq!(
        corner(&a, &b, Corner::Round(5.0)).unwrap_err().number,
        NO_CORNER
    );
    // 29 N240/N260: the G3 R460 about X-420 Y0 ends at X40 Y0 heading Y+, the line goes Y+.
    let a = arc([29.48, -97.815], [40.0, 0.0], [-420.0, 0.0], false);
    let b = line([40.0, 0.0], [40.0, 50.0]);
    assert_eq!(
        corner(&a, &b, Corner::Round(18.0)).unwrap_err().number,
        NO_CORNER
    );
    // An element without length, or a gap between the elements: 0051.
    let z = line([10.0, 0.0], [10.0, 0.0]);
    assert_eq!(
        corner(&a.with_to([10.0, 0.0]), &z, Corner::Round(1.0))
            .unwrap_err()
            .number,
        NO_CORNER
    );
    let gap = line([11.0, 0.0], [11.0, 10.0]);
    assert_eq!(
        corner(&line([0.0, 0.0], [10.0, 0.0]), &gap, Corner::Round(1.0))
            .unwrap_err()
            .number,
        NO_CORNER
    );
}

#[test]
fn messages_name_the_numbers() {
    // 28 N200/N210 with ,R150: the offsets 505 − 150 and 185 − 150 do not meet; with ,R60 the
    // rounding would start before N200's start X37.5 Y0 (N200 sweeps only 5.29°).
    let arcs = chain((467.5, 505.0), (135.0, 185.0), [37.5, 0.0]);
    let msg = |a: &Element, b: &Element, c| corner(a, b, c).unwrap_err().to_string();
    assert_eq!(
        msg(&arcs[0], &arcs[1], Corner::Round(150.0)),
        "alarm 0055: ,R150 at (35.3461, 46.5920): no arc of that radius is tangent to both elements"
    );
    assert_eq!(
        msg(&arcs[0], &arcs[1], Corner::Round(60.0)),
        "alarm 0055: ,R60 at (35.3461, 46.5920): the corner would begin at (37.3142, -13.6994), \
         before the start (37.5000, 0.0000) of the block (a G3 arc of radius 505.0000 about \
         (-467.5000, 0.0000) sweeping 5.2937°)"
    );
    assert_eq!(
        msg(
            &line([0.0, -20.0], [10.0, 0.0]),
            &arc([10.0, 0.0], [-10.0, 0.0], [0.0, 0.0], false),
            Corner::Round(12.0)
        ),
        "alarm 0055: ,R12 at (10.0000, 0.0000): a rounding of that radius cannot lie inside the \
         arc of radius 10.0000 about (0.0000, 0.0000)"
    );
    assert_eq!(
        circle_intersection([0.0, 0.0], 30.0, [100.0, 0.0], 40.0, -1.0)
            .unwrap_err()
            .to_string(),
        "alarm 0057: arc intersection: the circle R30 about (0.0000, 0.0000) and the circle R40 \
         about (100.0000, 0.0000) do not meet: their centres are 100.0000 apart, more than \
         R1 + R2 = 70.0000"
    );
}

#[test]
fn circles_that_do_not_meet() {
    // Centres 100 apart, radii 30 + 40 < 100: 0057.
    let e = circle_intersection([0.0, 0.0], 30.0, [100.0, 0.0], 40.0, -1.0).unwrap_err();
    assert_eq!(e.number, NO_INTERSECTION);
    assert!(e.message.contains("do not meet"), "{}", e.message);
    // One inside the other: 10 apart, |50 − 30| = 20 > 10.
    let e = circle_intersection([0.0, 0.0], 50.0, [10.0, 0.0], 30.0, 1.0).unwrap_err();
    assert!(
        e.number == NO_INTERSECTION && e.message.contains("inside"),
        "{}",
        e.message
    );
    // Concentric, a radius of 0, Q0 with two points: 0057.
    let e = circle_intersection([5.0, 5.0], 10.0, [5.0, 5.0], 10.0, 1.0).unwrap_err();
    assert!(e.number == NO_INTERSECTION && e.message.contains("concentric"));
    assert_eq!(
        circle_intersection([0.0, 0.0], 0.0, [1.0, 0.0], 1.0, 1.0)
            .unwrap_err()
            .number,
        NO_INTERSECTION
    );
    let e = circle_intersection([20.0, -20.0], 31.0, [-20.0, -20.0], 31.0, 0.0).unwrap_err();
    assert!(
        e.number == NO_INTERSECTION && e.message.contains("Q0"),
        "{}",
        e.message
    );
    // Touching circles (30 + 70 = 100): the one point, whatever Q (Q0 included).
    for q in [-1.0, 0.0, 1.0] {
        let p = circle_intersection([0.0, 0.0], 30.0, [100.0, 0.0], 70.0, q).unwrap();
        assert_near(p, [30.0, 0.0], 1e-9);
    }
}
