use super::*;
use fmsvm_canon::geom::norm;

/// The tool radius of the textbook corpus (tool.tbl: D0.15748031496063 in = 4 mm).
const R: f64 = 2.0;
/// The comparison tolerance of `ncmotion.py diff`.
const TOL: f64 = 0.0011;

/// A programmed path fed to a compensator, as the kernel would: each move with the programmed
/// point it starts from.
struct Run {
    c: Compensator,
    pos: Pose,
    plane: Plane,
    out: Vec<Move>,
}

fn p(x: f64, y: f64, z: f64) -> Pose {
    [x, y, z, 0.0, 0.0, 0.0]
}

/// The centre of an arc given by R (ncmotion's rule: positive R ≤ 180°).
fn centre_r(s: V2, e: V2, r: f64, cw: bool) -> V2 {
    let d = sub(e, s);
    let l = norm(d);
    let h = (r * r - l * l / 4.0).max(0.0).sqrt();
    let m = add(s, scale(d, 0.5));
    let n = left(scale(d, 1.0 / l));
    let sign = if cw { -1.0 } else { 1.0 } * r.signum();
    add(m, scale(n, sign * h))
}

impl Run {
    fn new(style: Style) -> Self {
        Run {
            c: Compensator::new(style),
            pos: [0.0; 6],
            plane: Plane::XY,
            out: Vec::new(),
        }
    }
    fn try_push(&mut self, m: Move) -> Result<(), Stop> {
        let from = self.pos;
        self.pos = m.to();
        let out = &mut self.out;
        self.c.push(from, m, &mut |mv| {
            out.push(mv);
            Ok(())
        })
    }
    fn push(&mut self, m: Move) {
        if let Err(e) = self.try_push(m) {
            panic!("unexpected stop: {e}");
        }
    }
    fn g0(&mut self, x: f64, y: f64, z: f64) {
        self.push(Move::Line {
            to: p(x, y, z),
            rapid: true,
        });
    }
    fn g1(&mut self, x: f64, y: f64, z: f64) {
        self.push(Move::Line {
            to: p(x, y, z),
            rapid: false,
        });
    }
    fn arc_move(&self, to: Pose, centre: V2, cw: bool) -> Move {
        Move::Arc(Arc {
            to,
            centre,
            plane: self.plane,
            clockwise: cw,
            turns: 0,
        })
    }
    /// G2/G3 to x y z about the absolute centre.
    fn arc(&mut self, cw: bool, x: f64, y: f64, z: f64, centre: V2) {
        let m = self.arc_move(p(x, y, z), centre, cw);
        self.push(m);
    }
    /// G2/G3 to x y z with R.
    fn arc_r(&mut self, cw: bool, x: f64, y: f64, z: f64, r: f64) -> Result<(), Stop> {
        let to = p(x, y, z);
        let c = centre_r(
            self.plane.project(&self.pos),
            self.plane.project(&to),
            r,
            cw,
        );
        let m = self.arc_move(to, c, cw);
        self.try_push(m)
    }
    fn g2r(&mut self, x: f64, y: f64, z: f64, r: f64) {
        if let Err(e) = self.arc_r(true, x, y, z, r) {
            panic!("unexpected stop: {e}");
        }
    }
    fn g3r(&mut self, x: f64, y: f64, z: f64, r: f64) {
        if let Err(e) = self.arc_r(false, x, y, z, r) {
            panic!("unexpected stop: {e}");
        }
    }
    /// A full circle (G2/G3 with I J only) about the absolute centre.
    fn full(&mut self, cw: bool, centre: V2) {
        let m = self.arc_move(self.pos, centre, cw);
        self.push(m);
    }
    fn g41(&mut self) {
        self.c.start(Side::Left, R, self.plane);
    }
    fn g42(&mut self) {
        self.c.start(Side::Right, R, self.plane);
    }
    fn g40(&mut self) {
        self.c.cancel();
    }
    fn end(&mut self) {
        let out = &mut self.out;
        if let Err(e) = self.c.flush(&mut |mv| {
            out.push(mv);
            Ok(())
        }) {
            panic!("unexpected stop: {e}");
        }
    }
    /// The output as `ncmotion.py moves` prints it: `KIND X Y Z [C1 C2]` (the arc centre in
    /// plane coordinates), straight moves that go nowhere left out, from X0 Y0 Z0.
    fn moves(&self) -> Vec<(String, Vec<f64>)> {
        let mut pos = [0.0; 6];
        let mut v = Vec::new();
        for m in &self.out {
            match *m {
                Move::Line { to, rapid } => {
                    if (0..3).any(|i| (to[i] - pos[i]).abs() > 1e-9) {
                        let k = if rapid { "G0" } else { "G1" };
                        v.push((k.to_string(), to[..3].to_vec()));
                    }
                    pos = to;
                }
                Move::Arc(a) => {
                    let k = if a.clockwise { "G2" } else { "G3" };
                    let mut vals = a.to[..3].to_vec();
                    vals.extend_from_slice(&a.centre);
                    v.push((k.to_string(), vals));
                    pos = a.to;
                }
            }
        }
        v
    }
    fn check(&self, expected: &str) {
        let want: Vec<(String, Vec<f64>)> = expected
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .map(|l| {
                let mut w = l.split_whitespace();
                let k = w.next().unwrap_or_default().to_string();
                let vals = w.map(|x| x.parse::<f64>().unwrap_or(f64::NAN)).collect();
                (k, vals)
            })
            .collect();
        let got = self.moves();
        let show = |v: &[(String, Vec<f64>)]| {
            v.iter()
                .map(|(k, vals)| {
                    let vals: Vec<String> = vals.iter().map(|x| format!("{x:.4}")).collect();
                    format!("{k} {}", vals.join(" "))
                })
                .collect::<Vec<_>>()
                .join("\n")
        };
        let same = got.len() == want.len()
            && got.iter().zip(&want).all(|(g, w)| {
                g.0 == w.0
                    && g.1.len() == w.1.len()
                    && g.1.iter().zip(&w.1).all(|(a, b)| (a - b).abs() <= TOL)
            });
        assert!(
            same,
            "moves differ\n--- got\n{}\n--- expected\n{}",
            show(&got),
            show(&want)
        );
    }
}

fn alarm_number(r: Result<(), Stop>) -> u32 {
    match r {
        Err(Stop::Alarm(a)) => a.number,
        Err(e) => panic!("not an alarm: {e}"),
        Ok(()) => panic!("no alarm"),
    }
}

// -- LinuxCNC style against the textbook corpus --------------------------------------------

/// The expected motion of a textbook program, or None (with a note) without the corpus.
fn textbook(name: &str) -> Option<String> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../shared/corpus/textbook");
    let path = format!("{dir}/{name}.moves");
    match std::fs::read_to_string(&path) {
        Ok(s) => Some(s),
        Err(_) => {
            eprintln!("note: {path} is absent; the textbook comparison is skipped");
            None
        }
    }
}

/// The common head of the circle programs: N110 G0 X Y, N120 G43 Z50, N140 G0 Z5, N150 G1 Z-10.
fn head(r: &mut Run, x: f64, y: f64) {
    r.g0(x, y, 0.0);
    r.g0(x, y, 50.0);
    r.g0(x, y, 5.0);
    r.g1(x, y, -10.0);
}

#[test]
fn linuxcnc_02_circle_cutter_comp() {
    let Some(want) = textbook("02-O7012-circle-cutter-comp") else {
        return;
    };
    let mut r = Run::new(Style::LinuxCnc);
    head(&mut r, 0.0, 70.0);
    r.g42(); // N160 G1 G42 X0 Y50 D1
    r.g1(0.0, 50.0, -10.0);
    r.full(false, [0.0, 0.0]); // N170 G3 J-50
    r.g40(); // N180 G1 G40 X0 Y70
    r.g1(0.0, 70.0, -10.0);
    r.g0(0.0, 70.0, 100.0);
    r.end();
    r.check(&want);
}

#[test]
fn linuxcnc_04_circle_tangent_comp() {
    let Some(want) = textbook("04-O7014-circle-tangent-comp") else {
        return;
    };
    let mut r = Run::new(Style::LinuxCnc);
    head(&mut r, 20.0, 70.0);
    r.g42();
    r.g1(0.0, 50.0, -10.0);
    r.full(false, [0.0, 0.0]);
    r.g40();
    r.g1(-20.0, 70.0, -10.0);
    r.g0(-20.0, 70.0, 100.0);
    r.end();
    r.check(&want);
}

#[test]
fn linuxcnc_06_internal_circle_comp() {
    let Some(want) = textbook("06-O7022-internal-circle-comp") else {
        return;
    };
    let mut r = Run::new(Style::LinuxCnc);
    head(&mut r, 0.0, 0.0);
    r.g41();
    r.g1(0.0, 50.0, -10.0);
    r.full(false, [0.0, 0.0]);
    r.g40();
    r.g1(0.0, 0.0, -10.0);
    r.g0(0.0, 0.0, 100.0);
    r.end();
    r.check(&want);
}

#[test]
fn linuxcnc_07_internal_circle_arc_approach() {
    let Some(want) = textbook("07-O7023-internal-circle-arc-approach") else {
        return;
    };
    let mut r = Run::new(Style::LinuxCnc);
    head(&mut r, 0.0, 0.0);
    r.g41();
    r.g1(25.0, 25.0, -10.0); // N160 G1 G41 X25 Y25
    r.g3r(0.0, 50.0, -10.0, 25.0); // N170 G3 X0 Y50 R25
    r.full(false, [0.0, 0.0]); // N180 G3 J-50
    r.g3r(-25.0, 25.0, -10.0, 25.0); // N190 G3 X-25 Y25 R25
    r.g40();
    r.g1(0.0, 0.0, -10.0);
    r.g0(0.0, 0.0, 100.0);
    r.end();
    r.check(&want);
}

#[test]
fn linuxcnc_09_rectangle_comp() {
    let Some(want) = textbook("09-O7032-rectangle-comp") else {
        return;
    };
    let mut r = Run::new(Style::LinuxCnc);
    head(&mut r, -120.0, -70.0);
    r.g42();
    r.g1(-100.0, -50.0, -10.0);
    r.g1(100.0, -50.0, -10.0);
    r.g1(100.0, 50.0, -10.0);
    r.g1(-100.0, 50.0, -10.0);
    r.g1(-100.0, -50.0, -10.0);
    r.g40();
    r.g1(-120.0, -70.0, -10.0);
    r.g0(-120.0, -70.0, 100.0);
    r.end();
    r.check(&want);
}

#[test]
fn linuxcnc_12_rectangle_pocket_arc_approach() {
    let Some(want) = textbook("12-O7041-rectangle-pocket-arc-approach") else {
        return;
    };
    let mut r = Run::new(Style::LinuxCnc);
    head(&mut r, 0.0, 0.0);
    r.g41();
    r.g1(80.0, 10.0, -10.0);
    r.g3r(40.0, 50.0, -10.0, 40.0);
    r.g1(-100.0, 50.0, -10.0);
    r.g1(-100.0, -50.0, -10.0);
    r.g1(100.0, -50.0, -10.0);
    r.g1(100.0, 50.0, -10.0);
    r.g1(-40.0, 50.0, -10.0);
    r.g3r(-80.0, 10.0, -10.0, 40.0);
    r.g40();
    r.g1(0.0, 0.0, -10.0);
    r.g0(0.0, 0.0, 100.0);
    r.end();
    r.check(&want);
}

// -- LinuxCNC style against rs274 traces of our own contours -------------------------------
//
// Each expected list is `rs274 -t tool.tbl -g prog.ngc | ncmotion.py moves` (tool.tbl of the
// textbook corpus, radius 2), the program in the comment above it.

/// Outside contour, G41: start-up at an inner corner, a tangent line→G2 and G2→line, convex
/// line corners (arcs), a Z plunge at a convex corner, a convex corner into a G3 with the tool
/// inside it, a concave line corner, cancel.
///
/// ```text
/// G17 G21 G90
/// G0 X-30 Y-30 Z5
/// G1 Z-2 F100
/// G41 D1 G1 X-20 Y0
/// G1 Y20
/// G2 X0 Y40 R20
/// G1 X20 Y40
/// G1 X30 Y20
/// G1 Z-4
/// G1 X30 Y0
/// G3 X20 Y-10 R10
/// G1 X0 Y-10
/// G1 X-5 Y5
/// G1 X-25 Y5
/// G40 G1 X-35 Y-10
/// G0 Z10
/// M2
/// ```
const L1: &str = "
    G0 -30.0000 -30.0000 5.0000
    G1 -30.0000 -30.0000 -2.0000
    G1 -22.0000 0.3246 -2.0000
    G1 -22.0000 20.0000 -2.0000
    G2 0.0000 42.0000 -2.0000 0.0000 20.0000
    G1 20.0000 42.0000 -2.0000
    G2 21.7889 40.8944 -2.0000 20.0000 40.0000
    G1 31.7889 20.8944 -2.0000
    G1 31.7889 20.8944 -4.0000
    G2 32.0000 20.0000 -4.0000 30.0000 20.0000
    G1 32.0000 0.0000 -4.0000
    G2 30.0000 -2.0000 -4.0000 30.0000 0.0000
    G3 22.0000 -10.0000 -4.0000 30.0000 -10.0000
    G2 20.0000 -12.0000 -4.0000 20.0000 -10.0000
    G1 0.0000 -12.0000 -4.0000
    G2 -1.8974 -10.6325 -4.0000 0.0000 -10.0000
    G1 -6.4415 3.0000 -4.0000
    G1 -25.0000 3.0000 -4.0000
    G1 -35.0000 -10.0000 -4.0000
    G0 -35.0000 -10.0000 10.0000";

#[test]
fn linuxcnc_outside_contour_g41() {
    let mut r = Run::new(Style::LinuxCnc);
    r.g0(-30.0, -30.0, 5.0);
    r.g1(-30.0, -30.0, -2.0);
    r.g41();
    r.g1(-20.0, 0.0, -2.0);
    r.g1(-20.0, 20.0, -2.0);
    r.g2r(0.0, 40.0, -2.0, 20.0);
    r.g1(20.0, 40.0, -2.0);
    r.g1(30.0, 20.0, -2.0);
    r.g1(30.0, 20.0, -4.0);
    r.g1(30.0, 0.0, -4.0);
    r.g3r(20.0, -10.0, -4.0, 10.0);
    r.g1(0.0, -10.0, -4.0);
    r.g1(-5.0, 5.0, -4.0);
    r.g1(-25.0, 5.0, -4.0);
    r.g40();
    r.g1(-35.0, -10.0, -4.0);
    r.g0(-35.0, -10.0, 10.0);
    r.end();
    r.check(L1);
}

/// G42 around the inside: concave line corners, a tangent line→G2 with the tool inside, a Z
/// plunge at a concave corner (it moves with the corner point), a G3 with the tool outside,
/// G2 with I J, a convex corner into a G2, an arc→rapid concave corner, cancel.
///
/// ```text
/// G17 G21 G90
/// G0 X0 Y0 Z5
/// G1 Z-3 F100
/// G42 D1 G1 X-20 Y10
/// G1 X-20 Y30
/// G1 X10 Y30
/// G2 X25 Y15 R15
/// G1 Z-5
/// G1 X25 Y-10
/// G3 X15 Y-20 R10
/// G1 X0 Y-20
/// G2 X-10 Y-10 I0 J10
/// G1 X-10 Y0
/// G2 X-20 Y0 R6
/// G0 X-20 Y10
/// G40 G1 X0 Y0
/// G0 Z10
/// M2
/// ```
const L2: &str = "
    G0 0.0000 0.0000 5.0000
    G1 0.0000 0.0000 -3.0000
    G1 -18.0000 11.2361 -3.0000
    G1 -18.0000 28.0000 -3.0000
    G1 10.0000 28.0000 -3.0000
    G2 23.0000 15.0000 -3.0000 10.0000 15.0000
    G1 23.0000 15.0000 -5.0000
    G1 23.0000 -8.1678 -5.0000
    G3 13.1678 -18.0000 -5.0000 25.0000 -20.0000
    G1 0.0000 -18.0000 -5.0000
    G2 -8.0000 -10.0000 -5.0000 0.0000 -10.0000
    G1 -8.0000 0.0000 -5.0000
    G3 -11.6667 1.1055 -5.0000 -10.0000 0.0000
    G2 -18.0000 0.6709 -5.0000 -15.0000 3.3166
    G0 -18.0000 10.0000 -5.0000
    G1 0.0000 0.0000 -5.0000
    G0 0.0000 0.0000 10.0000";

#[test]
fn linuxcnc_inside_contour_g42() {
    let mut r = Run::new(Style::LinuxCnc);
    r.g0(0.0, 0.0, 5.0);
    r.g1(0.0, 0.0, -3.0);
    r.g42();
    r.g1(-20.0, 10.0, -3.0);
    r.g1(-20.0, 30.0, -3.0);
    r.g1(10.0, 30.0, -3.0);
    r.g2r(25.0, 15.0, -3.0, 15.0);
    r.g1(25.0, 15.0, -5.0);
    r.g1(25.0, -10.0, -5.0);
    r.g3r(15.0, -20.0, -5.0, 10.0);
    r.g1(0.0, -20.0, -5.0);
    r.arc(true, -10.0, -10.0, -5.0, [0.0, -10.0]);
    r.g1(-10.0, 0.0, -5.0);
    r.g2r(-20.0, 0.0, -5.0, 6.0);
    r.g0(-20.0, 10.0, -5.0);
    r.g40();
    r.g1(0.0, 0.0, -5.0);
    r.g0(0.0, 0.0, 10.0);
    r.end();
    r.check(L2);
}

/// G42 with rapids: a rapid start-up, a tangent rapid→G3, G3→G3 reversing on top of an "m"
/// (an inner corner), tangent G3→line→G2, convex acute corner after a G2 (arc), a convex rapid
/// corner (a straight rapid instead of the arc), convex and concave line corners, rapid cancel.
///
/// ```text
/// G17 G21 G90
/// G0 X40 Y-20 Z5
/// G1 Z-1 F100
/// G42 D1 G0 X30 Y0
/// G0 X30 Y20
/// G3 X10 Y20 R10
/// G3 X-10 Y20 R10
/// G1 X-10 Y0
/// G2 X-20 Y-10 R10
/// G1 X0 Y-30
/// G0 X20 Y-30
/// G1 X25 Y-10
/// G1 X40 Y-10
/// G40 G0 X50 Y-30
/// M2
/// ```
const L3: &str = "
    G0 40.0000 -20.0000 5.0000
    G1 40.0000 -20.0000 -1.0000
    G0 32.0000 0.4721 -1.0000
    G0 32.0000 20.0000 -1.0000
    G3 10.0000 26.6332 -1.0000 20.0000 20.0000
    G3 -12.0000 20.0000 -1.0000 0.0000 20.0000
    G1 -12.0000 0.0000 -1.0000
    G2 -20.0000 -8.0000 -1.0000 -20.0000 0.0000
    G3 -21.4142 -11.4142 -1.0000 -20.0000 -10.0000
    G1 -1.4142 -31.4142 -1.0000
    G0 0.0000 -32.0000 -1.0000
    G0 20.0000 -32.0000 -1.0000
    G3 21.9403 -30.4851 -1.0000 20.0000 -30.0000
    G1 26.5616 -12.0000 -1.0000
    G1 40.0000 -12.0000 -1.0000
    G0 50.0000 -30.0000 -1.0000";

#[test]
fn linuxcnc_rapids_and_reversal_g42() {
    let mut r = Run::new(Style::LinuxCnc);
    r.g0(40.0, -20.0, 5.0);
    r.g1(40.0, -20.0, -1.0);
    r.g42();
    r.g0(30.0, 0.0, -1.0);
    r.g0(30.0, 20.0, -1.0);
    r.g3r(10.0, 20.0, -1.0, 10.0);
    r.g3r(-10.0, 20.0, -1.0, 10.0);
    r.g1(-10.0, 0.0, -1.0);
    r.g2r(-20.0, -10.0, -1.0, 10.0);
    r.g1(0.0, -30.0, -1.0);
    r.g0(20.0, -30.0, -1.0);
    r.g1(25.0, -10.0, -1.0);
    r.g1(40.0, -10.0, -1.0);
    r.g40();
    r.g0(50.0, -30.0, -1.0);
    r.end();
    r.check(L3);
}

/// G41, every kind of concave corner that is not tangent: line→G2 and G2→line with the tool
/// outside the arc, line→line, G2→G3 (outside → inside), plus a convex line corner, tangent
/// line→line, G3→G2.
///
/// ```text
/// G17 G21 G90
/// G0 X0 Y-30 Z0
/// G41 D1 G1 X0 Y-10 F100
/// G1 X0 Y0
/// G1 X20 Y0
/// G2 X40 Y0 R15
/// G1 X60 Y0
/// G1 X60 Y20
/// G3 X40 Y20 R10
/// G2 X20 Y20 R10
/// G3 X0 Y20 R12
/// G40 G1 X-10 Y0
/// M2
/// ```
const L4: &str = "
    G0 0.0000 -30.0000 0.0000
    G1 -2.0000 -10.0000 0.0000
    G1 -2.0000 0.0000 0.0000
    G2 0.0000 2.0000 0.0000 0.0000 0.0000
    G1 19.2632 2.0000 0.0000
    G2 40.7368 2.0000 0.0000 30.0000 -11.1803
    G1 58.0000 2.0000 0.0000
    G1 58.0000 20.0000 0.0000
    G3 42.0000 20.0000 0.0000 50.0000 20.0000
    G2 18.0180 19.3427 0.0000 30.0000 20.0000
    G3 1.6667 18.8945 0.0000 10.0000 13.3668
    G1 -10.0000 0.0000 0.0000";

#[test]
fn linuxcnc_concave_arcs_g41() {
    let mut r = Run::new(Style::LinuxCnc);
    r.g0(0.0, -30.0, 0.0);
    r.g41();
    r.g1(0.0, -10.0, 0.0);
    r.g1(0.0, 0.0, 0.0);
    r.g1(20.0, 0.0, 0.0);
    r.g2r(40.0, 0.0, 0.0, 15.0);
    r.g1(60.0, 0.0, 0.0);
    r.g1(60.0, 20.0, 0.0);
    r.g3r(40.0, 20.0, 0.0, 10.0);
    r.g2r(20.0, 20.0, 0.0, 10.0);
    r.g3r(0.0, 20.0, 0.0, 12.0);
    r.g40();
    r.g1(-10.0, 0.0, 0.0);
    r.end();
    r.check(L4);
}

/// G18 (the Z X plane; arc centres below are Z X): G41 start-up, a G2 with the tool outside, a
/// Y-only move (normal to the plane) before a convex corner: the corner arc is made at the new
/// Y. Converted by hand from the trace (rs274 prints ARC_FEED(Z, X, centre Z, X, turn, Y) in
/// G18; ncmotion compares XY arcs only):
///
/// ```text
/// G18 G21 G90
/// G0 X30 Y0 Z30
/// G41 D1 G1 X20 Z10 F100
/// G1 X0 Z10
/// G2 X-10 Z0 R10
/// G1 X-10 Z-20
/// G1 Y5
/// G1 X10 Z-30
/// G40 G1 X20 Z-40
/// M2
///
/// STRAIGHT_TRAVERSE(30.0000, 0.0000, 30.0000, ...)
/// STRAIGHT_FEED(18.7639, 0.0000, 12.0000, ...)
/// STRAIGHT_FEED(0.0000, 0.0000, 12.0000, ...)
/// ARC_FEED(0.0000, -12.0000, -0.0000, -0.0000, -1, 0.0000, ...)
/// STRAIGHT_FEED(-12.0000, 0.0000, -20.0000, ...)
/// STRAIGHT_FEED(-12.0000, 5.0000, -20.0000, ...)
/// ARC_FEED(-21.7889, -10.8944, -20.0000, -10.0000, -1, 5.0000, ...)
/// STRAIGHT_FEED(9.1056, 5.0000, -31.7889, ...)
/// STRAIGHT_FEED(20.0000, 5.0000, -40.0000, ...)
/// ```
const L5: &str = "
    G0 30.0000 0.0000 30.0000
    G1 18.7639 0.0000 12.0000
    G1 0.0000 0.0000 12.0000
    G2 -12.0000 0.0000 0.0000 0.0000 0.0000
    G1 -12.0000 0.0000 -20.0000
    G1 -12.0000 5.0000 -20.0000
    G2 -10.8944 5.0000 -21.7889 -20.0000 -10.0000
    G1 9.1056 5.0000 -31.7889
    G1 20.0000 5.0000 -40.0000";

#[test]
fn linuxcnc_g18_plane() {
    let mut r = Run::new(Style::LinuxCnc);
    r.plane = Plane::ZX;
    r.g0(30.0, 0.0, 30.0);
    r.g41();
    r.g1(20.0, 0.0, 10.0);
    r.g1(0.0, 0.0, 10.0);
    r.g2r(-10.0, 0.0, 0.0, 10.0);
    r.g1(-10.0, 0.0, -20.0);
    r.g1(-10.0, 5.0, -20.0);
    r.g1(10.0, 5.0, -30.0);
    r.g40();
    r.g1(20.0, 5.0, -40.0);
    r.end();
    r.check(L5);
}

/// Z-only moves in the middle: held, moved to the corner point with the element before them,
/// a rapid Z pair too; the G40 block with Z only goes straight back to the programmed X Y.
///
/// ```text
/// G17 G21 G90
/// G0 X-20 Y-20 Z5
/// G1 Z-1 F100
/// G41 D1 G1 X0 Y0
/// G1 X50
/// G1 Z-3
/// G1 Y30
/// G0 Z2
/// G0 Z-3
/// G1 X0
/// G1 Z-4
/// G1 X10 Y10
/// G40 G1 Z10
/// M2
/// ```
const L6: &str = "
    G0 -20.0000 -20.0000 5.0000
    G1 -20.0000 -20.0000 -1.0000
    G1 -1.4142 1.4142 -1.0000
    G2 0.0000 2.0000 -1.0000 0.0000 0.0000
    G1 48.0000 2.0000 -1.0000
    G1 48.0000 2.0000 -3.0000
    G1 48.0000 28.0000 -3.0000
    G0 48.0000 28.0000 2.0000
    G0 48.0000 28.0000 -3.0000
    G1 3.2361 28.0000 -3.0000
    G1 3.2361 28.0000 -4.0000
    G1 11.7889 10.8944 -4.0000
    G1 10.0000 10.0000 10.0000";

#[test]
fn linuxcnc_z_moves_keep_the_corner() {
    let mut r = Run::new(Style::LinuxCnc);
    r.g0(-20.0, -20.0, 5.0);
    r.g1(-20.0, -20.0, -1.0);
    r.g41();
    r.g1(0.0, 0.0, -1.0);
    r.g1(50.0, 0.0, -1.0);
    r.g1(50.0, 0.0, -3.0);
    r.g1(50.0, 30.0, -3.0);
    r.g0(50.0, 30.0, 2.0);
    r.g0(50.0, 30.0, -3.0);
    r.g1(0.0, 30.0, -3.0);
    r.g1(0.0, 30.0, -4.0);
    r.g1(10.0, 10.0, -4.0);
    r.g40();
    r.g1(10.0, 10.0, 10.0);
    r.end();
    r.check(L6);
    assert!(!r.c.is_active());
    assert_eq!(r.c.tool_position(), Some(p(10.0, 10.0, 10.0)));
}

/// rs274 stops at the arc: "Tool radius not less than arc radius with comp". What it wrote
/// before (the start-up and the convex corner arc) is what we wrote.
///
/// ```text
/// G17 G21 G90
/// G0 X-20 Y-20 Z5
/// G41 D1 G1 X0 Y0 F100
/// G1 X10
/// G3 X13 Y0 R1.5
/// ```
#[test]
fn inside_arc_smaller_than_the_tool_is_an_alarm() {
    for style in [Style::LinuxCnc, Style::Fanuc] {
        let mut r = Run::new(style);
        r.g0(-20.0, -20.0, 5.0);
        r.g41();
        r.g1(0.0, 0.0, 5.0);
        r.g1(10.0, 0.0, 5.0);
        assert_eq!(
            alarm_number(r.arc_r(false, 13.0, 0.0, 5.0, 1.5)),
            41,
            "{style:?}"
        );
        if style == Style::LinuxCnc {
            r.check(
                "G0 -20.0000 -20.0000 5.0000
                 G1 -1.4142 1.4142 5.0000
                 G2 0.0000 2.0000 5.0000 0.0000 0.0000",
            );
        }
    }
}

// -- Fanuc style, hand-computed -------------------------------------------------------------
//
// t = 2·tan(22.5°) = 2(√2 − 1) = 0.828427: how far the intersection of two offset lines at
// distance 2 lies from the perpendicular end point at a 45° corner.

/// Exercise 9 the Fanuc (NCT) way: G42 around the rectangle X±100 Y±50 from X-120 Y-70.
///
/// - start-up, inner corner (the start-up direction (1,1) turns right into X+, the tool is on
///   the right): the start-up line's parallel offset x − y = −50 + ... meets y = −52 at
///   X = −100 + t = −99.1716;
/// - the four convex corners are 90° (α = 90°, the obtuse rule): offset lines y = −52,
///   x = 102, y = 52, x = −102 meet at (102, −52), (102, 52), (−102, 52);
/// - cancel: Y− turns right into the G40 move (−1,−1): inner, so the last element x = −102
///   ends where it meets the G40 line's parallel offset (through (−101.414, −48.586), direction
///   (1,1)): Y = −50 + t = −49.1716; then straight to X-120 Y-70.
#[test]
fn fanuc_outside_rectangle() {
    let mut r = Run::new(Style::Fanuc);
    head(&mut r, -120.0, -70.0);
    r.g42();
    r.g1(-100.0, -50.0, -10.0);
    r.g1(100.0, -50.0, -10.0);
    r.g1(100.0, 50.0, -10.0);
    r.g1(-100.0, 50.0, -10.0);
    r.g1(-100.0, -50.0, -10.0);
    r.g40();
    r.g1(-120.0, -70.0, -10.0);
    r.g0(-120.0, -70.0, 100.0);
    r.end();
    r.check(
        "G0 -120.0000 -70.0000 0.0000
         G0 -120.0000 -70.0000 50.0000
         G0 -120.0000 -70.0000 5.0000
         G1 -120.0000 -70.0000 -10.0000
         G1 -99.1716 -52.0000 -10.0000
         G1 102.0000 -52.0000 -10.0000
         G1 102.0000 52.0000 -10.0000
         G1 -102.0000 52.0000 -10.0000
         G1 -102.0000 -49.1716 -10.0000
         G1 -120.0000 -70.0000 -10.0000
         G0 -120.0000 -70.0000 100.0000",
    );
}

/// G42 counter-clockwise around the triangle A(0,0) B(60,0) C(0,20), from S(−10,−10), then
/// along AB again to (20,0) and G40 to (30,−10).
///
/// - start-up at A: S→A (1,1) turns right 45° into AB: inner; parallel offset meets y = −2 at
///   X = t = 0.8284;
/// - B: AB (1,0) turns left 161.57° into BC t₂ = (−3,1)/√10: outer, α = 18.43° < 90°, acute.
///   n₁ = (0,−1): A = (60,−2), extended by r along t₁: (62,−2) (the line AB is lengthened);
///   n₂ = (1,3)/√10: B = (60.6325, 1.8974), back by r along t₂: B − 2t₂ =
///   (60.6325 + 1.8974, 1.8974 − 0.6325) = (62.5298, 1.2649): one extra straight move there;
/// - C: BC turns left 108.43° into CA (0,−1): acute. A = C + 2n₁ = (0.6325, 21.8974), + 2t₁ =
///   (0.6325 − 1.8974, 21.8974 + 0.6325) = (−1.2649, 22.5298) (BC lengthened); n₂ = (−1,0):
///   B = (−2, 20), − 2t₂ = (−2, 22): the extra move;
/// - A again: CA (0,−1) turns left 90° into (1,0): α = 90°, obtuse rule: x = −2 meets y = −2;
/// - cancel at (20,0): (1,0) turns right 45° into the G40 move (1,−1): inner; y = −2 meets the
///   G40 line's parallel offset at X = 20 − t = 19.1716, then straight to (30,−10).
#[test]
fn fanuc_triangle_acute_corners() {
    let mut r = Run::new(Style::Fanuc);
    r.g0(-10.0, -10.0, 0.0);
    r.g42();
    r.g1(0.0, 0.0, 0.0);
    r.g1(60.0, 0.0, 0.0);
    r.g1(0.0, 20.0, 0.0);
    r.g1(0.0, 0.0, 0.0);
    r.g1(20.0, 0.0, 0.0);
    r.g40();
    r.g1(30.0, -10.0, 0.0);
    r.end();
    r.check(
        "G0 -10.0000 -10.0000 0.0000
         G1 0.8284 -2.0000 0.0000
         G1 62.0000 -2.0000 0.0000
         G1 62.5298 1.2649 0.0000
         G1 -1.2649 22.5298 0.0000
         G1 -2.0000 22.0000 0.0000
         G1 -2.0000 -2.0000 0.0000
         G1 19.1716 -2.0000 0.0000
         G1 30.0000 -10.0000 0.0000",
    );
}

/// G41 from (0,−10): start-up up to (0,0), then X+ (a right turn: outer, 90°), a concave
/// G2 X40 Y0 R15 (centre (30, −√125) = (30, −11.1803), the tool outside: offset radius 17),
/// X60, Y30, G40 to (70,40).
///
/// - start-up, outer, type A: it ends at B = (0,0) + 2·(0,1) = (0, 2);
/// - line→G2: turns left 41.8° (concave). y = 2 meets (x − 30)² + 13.1803² = 17²:
///   x − 30 = ±√(289 − 173.7214) = ±10.7368; the one just behind (20, 2) is X19.2632;
/// - G2→line: y = 2 meets the same circle; the one just behind the arc's perpendicular end
///   (41.3333, 1.4907) is X40.7368 (2.6° back along the arc, the other is 81° back);
/// - (60,0): y = 2 meets x = 58;
/// - cancel: Y+ turns right 45° into (1,1): outer, type A: the last element ends at its
///   perpendicular end (58, 30), then straight to (70, 40).
#[test]
fn fanuc_concave_corners_and_type_a() {
    let mut r = Run::new(Style::Fanuc);
    r.g0(0.0, -10.0, 0.0);
    r.g41();
    r.g1(0.0, 0.0, 0.0);
    r.g1(20.0, 0.0, 0.0);
    r.g2r(40.0, 0.0, 0.0, 15.0);
    r.g1(60.0, 0.0, 0.0);
    r.g1(60.0, 30.0, 0.0);
    r.g40();
    r.g1(70.0, 40.0, 0.0);
    r.end();
    r.check(
        "G0 0.0000 -10.0000 0.0000
         G1 0.0000 2.0000 0.0000
         G1 19.2632 2.0000 0.0000
         G2 40.7368 2.0000 0.0000 30.0000 -11.1803
         G1 58.0000 2.0000 0.0000
         G1 58.0000 30.0000 0.0000
         G1 70.0000 40.0000 0.0000",
    );
}

/// Start-up and cancel of type B (No. 5003#0 SUP = 1) at outer corners.
///
/// - G42 from (−10,−10) to (0,0), then Y+: (1,1) turns left 45°, outer obtuse. Type A ends at
///   B = (2, 0); type B at the intersection of the start-up line's parallel offset (through
///   (1.4142, −1.4142), direction (1,1)) with x = 2: Y = −t = −0.8284.
/// - G40 to (10, 30): Y+ turns right 45°, inner for G42, the same for both types: x = 2 meets
///   the G40 line's parallel offset at Y = 20 − t = 19.1716.
/// - The last test's cancel (G41, Y+ then (1,1), outer) of type B: x = 58 meets the parallel
///   offset of the G40 line (through (58.5858, 31.4142), direction (1,1)) at Y = 30 + t =
///   30.8284.
#[test]
fn fanuc_type_b() {
    let mut want_a = String::from("G0 -10 -10 0\nG1 2 0 0\n");
    let mut want_b = String::from("G0 -10 -10 0\nG1 2 -0.8284 0\n");
    for w in [&mut want_a, &mut want_b] {
        w.push_str("G1 2 19.1716 0\nG1 10 30 0\n");
    }
    for (type_b, want) in [(false, want_a), (true, want_b)] {
        let mut r = Run::new(Style::Fanuc);
        r.c.set_type_b(type_b);
        r.g0(-10.0, -10.0, 0.0);
        r.g42();
        r.g1(0.0, 0.0, 0.0);
        r.g1(0.0, 20.0, 0.0);
        r.g40();
        r.g1(10.0, 30.0, 0.0);
        r.end();
        r.check(&want);
    }
    let mut r = Run::new(Style::Fanuc);
    r.c.set_type_b(true);
    r.g0(60.0, 0.0, 0.0);
    r.g41();
    r.g1(60.0, 10.0, 0.0);
    r.g1(60.0, 30.0, 0.0);
    r.g40();
    r.g1(70.0, 40.0, 0.0);
    r.end();
    // Start-up straight on (tangent): it ends at the perpendicular offset (58, 10).
    r.check("G0 60 0 0\nG1 58 10 0\nG1 58 30.8284 0\nG1 70 40 0");
}

/// G41 along X from (−10,0), a 135° convex corner at (20,0) with a Z plunge programmed between,
/// a 45° concave corner with the G40 move.
///
/// - start-up straight on: it ends at the perpendicular offset (0, 2);
/// - (20,0): X+ turns right 45° into (1,−1): outer, α = 135°: y = 2 meets the offset of the
///   second line (through (21.4142, 1.4142), direction (1,−1)) at X = 20 + t = 20.8284; the Z
///   plunge is made there;
/// - cancel at (40,−20): (1,−1) turns left 45° into X+: inner; the offset (through (41.4142,
///   −18.5858), direction (1,−1)) meets y = −18 at X = 40 + t = 40.8284.
#[test]
fn fanuc_obtuse_corner_and_z_plunge() {
    let mut r = Run::new(Style::Fanuc);
    r.g0(-10.0, 0.0, 0.0);
    r.g41();
    r.g1(0.0, 0.0, 0.0);
    r.g1(20.0, 0.0, 0.0);
    r.g1(20.0, 0.0, -5.0);
    r.g1(40.0, -20.0, -5.0);
    r.g40();
    r.g1(50.0, -20.0, -5.0);
    r.end();
    r.check(
        "G0 -10 0 0
         G1 0 2 0
         G1 20.8284 2 0
         G1 20.8284 2 -5
         G1 40.8284 -18 -5
         G1 50 -20 -5",
    );
}

/// Exercise 2 the Fanuc (NCT) way: G42 X0 Y50 from X0 Y70, G3 J-50, G40 X0 Y70.
///
/// - start-up: Y− turns right 90° into the circle (tangent (−1,0) at (0,50)): inner; the
///   parallel offset x = −2 meets the offset circle R52 at Y = √(52² − 2²) = √2700 = 51.9615;
/// - cancel: the circle's end tangent (−1,0) turns right 90° into the G40 move Y+: inner; the
///   circle meets the G40 line's parallel offset x = 2 at Y = 51.9615 (2.2° before its
///   perpendicular end (0,52)); the circle is 360° − 2 × 2.2° and the G40 move goes from there.
#[test]
fn fanuc_full_circle() {
    let mut r = Run::new(Style::Fanuc);
    head(&mut r, 0.0, 70.0);
    r.g42();
    r.g1(0.0, 50.0, -10.0);
    r.full(false, [0.0, 0.0]);
    r.g40();
    r.g1(0.0, 70.0, -10.0);
    r.g0(0.0, 70.0, 100.0);
    r.end();
    r.check(
        "G0 0 70 0
         G0 0 70 50
         G0 0 70 5
         G1 0 70 -10
         G1 -2 51.9615 -10
         G3 2 51.9615 -10 0 0
         G1 0 70 -10
         G0 0 70 100",
    );
}

/// Fanuc, G41 → G42 in offset mode between two collinear lines: the offset lines y = 2 and
/// y = −2 are parallel (no intersection), so the first ends at its perpendicular end (10, 2)
/// and a straight move goes to the second's perpendicular start (10, −2). Start-up and cancel
/// are straight on (tangent): perpendicular ends.
#[test]
fn fanuc_change_of_side() {
    let mut r = Run::new(Style::Fanuc);
    r.g0(-10.0, 0.0, 0.0);
    r.g41();
    r.g1(0.0, 0.0, 0.0);
    r.g1(10.0, 0.0, 0.0);
    r.g42();
    r.g1(20.0, 0.0, 0.0);
    r.g40();
    r.g1(30.0, 0.0, 0.0);
    r.end();
    r.check("G0 -10 0 0\nG1 0 2 0\nG1 10 2 0\nG1 10 -2 0\nG1 20 -2 0\nG1 30 0 0");
}

#[test]
fn arcs_as_start_up_or_cancel() {
    // Fanuc: no start-up on an arc.
    let mut r = Run::new(Style::Fanuc);
    r.g0(0.0, -10.0, 0.0);
    r.g41();
    assert_eq!(alarm_number(r.arc_r(false, 10.0, 0.0, 0.0, 10.0)), 34);
    // Both: no cancel on an arc.
    for style in [Style::Fanuc, Style::LinuxCnc] {
        let mut r = Run::new(style);
        r.g0(0.0, -10.0, 0.0);
        r.g41();
        r.g1(0.0, 0.0, 0.0);
        r.g1(10.0, 0.0, 0.0);
        r.g40();
        assert_eq!(
            alarm_number(r.arc_r(false, 20.0, 0.0, 0.0, 5.0)),
            34,
            "{style:?}"
        );
    }
}

#[test]
fn negative_radius_swaps_the_side_and_zero_is_off() {
    let mut a = Run::new(Style::LinuxCnc);
    let mut b = Run::new(Style::LinuxCnc);
    for (r, side, radius) in [(&mut a, Side::Left, -R), (&mut b, Side::Right, R)] {
        r.g0(-120.0, -70.0, 0.0);
        r.c.start(side, radius, Plane::XY);
        r.g1(-100.0, -50.0, 0.0);
        r.g1(100.0, -50.0, 0.0);
        r.g40();
        r.g1(120.0, -70.0, 0.0);
    }
    assert_eq!(a.out, b.out);
    let mut r = Run::new(Style::Fanuc);
    r.c.start(Side::Left, 0.0, Plane::XY);
    assert!(!r.c.is_active());
    r.g1(10.0, 0.0, 0.0);
    r.check("G1 10 0 0");
}

/// Moves without plane motion right after G41 pass through; the start-up waits for the plane
/// move (rs274ngc would refuse the Z move).
#[test]
fn z_move_before_the_start_up_passes_through() {
    for style in [Style::LinuxCnc, Style::Fanuc] {
        let mut r = Run::new(style);
        r.g0(-120.0, -70.0, 5.0);
        r.g42();
        r.g1(-120.0, -70.0, -10.0);
        r.g1(-100.0, -50.0, -10.0);
        r.g1(100.0, -50.0, -10.0);
        r.end();
        r.check(
            "G0 -120 -70 5
             G1 -120 -70 -10
             G1 -99.1716 -52 -10
             G1 100 -52 -10",
        );
        assert!(r.c.is_active());
        assert_eq!(r.c.tool_position(), Some(p(100.0, -52.0, -10.0)));
    }
}

/// After a flush in the middle: the held element ends perpendicular; the next one starts with
/// a straight move from there to its own perpendicular start offset (Fanuc), or with the usual
/// arc at this convex corner, which needs nothing held (LinuxCNC).
#[test]
fn flush_in_the_middle() {
    // The cancel corner (Y+ into (1,1), a right turn under G42) is inner: LinuxCNC ends Y+ at its
    // perpendicular end, Fanuc at the intersection with the G40 line's offset (Y = 50 − t).
    for (style, joint, last) in [
        (Style::LinuxCnc, "G3 102 -50 0 100 -50", "G1 102 50 0"),
        (Style::Fanuc, "G1 102 -50 0", "G1 102 49.1716 0"),
    ] {
        let mut r = Run::new(style);
        r.g0(-120.0, -70.0, 0.0);
        r.g42();
        r.g1(-100.0, -50.0, 0.0);
        r.g1(100.0, -50.0, 0.0);
        r.end();
        r.g1(100.0, 50.0, 0.0);
        r.g40();
        r.g1(120.0, 70.0, 0.0);
        r.check(&format!(
            "G0 -120 -70 0
             G1 -99.1716 -52 0
             G1 100 -52 0
             {joint}
             {last}
             G1 120 70 0"
        ));
    }
}
