//! An arc's centre as the read-back finds it from the words of the flat program, from the
//! definitions alone and on purpose not through the kernel's `arcs`: a wrong centre rule on either
//! side then shows up as a difference instead of agreeing with itself.
//!
//! I J K are the centre less the start point (or the centre itself, where the dialect writes it
//! so). R is the radius of the arc of at most 180° between the two points when positive, of more
//! than 180° when negative; of the two circles of that radius through both points, the centre is
//! the one from which the arc, taken in its direction, sweeps that much.

use std::f64::consts::{PI, TAU};

/// A point of the plane (its first and second axis).
pub type P2 = [f64; 2];

/// How far round from `s` to `e` about `c`, in the arc's direction, radians in (0, 2π].
pub fn sweep(s: P2, e: P2, c: P2, clockwise: bool) -> f64 {
    let a0 = (s[1] - c[1]).atan2(s[0] - c[0]);
    let a1 = (e[1] - c[1]).atan2(e[0] - c[0]);
    let ccw = (a1 - a0).rem_euclid(TAU);
    let turn = if clockwise { (TAU - ccw) % TAU } else { ccw };
    if turn == 0.0 { TAU } else { turn }
}

/// The centre from I J K given as the centre less the start point: checked against the end point
/// (both on one circle within `tolerance`).
pub fn from_offsets(s: P2, e: P2, offsets: P2, tolerance: f64) -> Result<P2, String> {
    let c = [s[0] + offsets[0], s[1] + offsets[1]];
    let r0 = offsets[0].hypot(offsets[1]);
    let r1 = (e[0] - c[0]).hypot(e[1] - c[1]);
    if r0 == 0.0 {
        return Err("an arc whose centre is its start point".into());
    }
    if (r1 - r0).abs() > tolerance {
        return Err(format!(
            "an arc whose end is {r1:.4} from its centre and start {r0:.4}"
        ));
    }
    Ok(c)
}

/// The centre from R: the circle of radius |R| through `s` and `e` on which the arc in its
/// direction sweeps at most 180° (R > 0) or more (R < 0). An end point further than 2|R| (beyond
/// `tolerance`) is an error; a half circle has one centre.
pub fn from_radius(s: P2, e: P2, r: f64, clockwise: bool, tolerance: f64) -> Result<P2, String> {
    let m = [(s[0] + e[0]) / 2.0, (s[1] + e[1]) / 2.0];
    let half = (e[0] - s[0]).hypot(e[1] - s[1]) / 2.0;
    if half == 0.0 {
        return Err("an arc by R whose end is its start".into());
    }
    if r == 0.0 || !r.is_finite() {
        return Err(format!("an arc of radius R{r}"));
    }
    let rr = r.abs();
    if half > rr + tolerance {
        return Err(format!(
            "R{r} cannot reach an end point {:.4} away",
            2.0 * half
        ));
    }
    // The two centres lie on the chord's perpendicular bisector, this far from the middle.
    let off = (rr * rr - half * half).max(0.0).sqrt();
    let u = [(e[1] - s[1]) / (2.0 * half), -(e[0] - s[0]) / (2.0 * half)];
    let candidates = [
        [m[0] + off * u[0], m[1] + off * u[1]],
        [m[0] - off * u[0], m[1] - off * u[1]],
    ];
    let major = r < 0.0;
    candidates
        .into_iter()
        .find(|&c| (sweep(s, e, c, clockwise) > PI + 1e-12) == major)
        // A half circle (both sweep 180°): either centre is the same point.
        .or(Some(m).filter(|_| off < 1e-9))
        .ok_or_else(|| format!("no centre of R{r} sweeps as its sign says"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: P2, b: P2) -> bool {
        (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9
    }

    /// By hand, from (0, 0) to (10, 0): R10 clockwise has its centre below the chord, at
    /// (5, −√75): the start at 120°, the end at 60°, 60° clockwise. R−10 the one above, 300°
    /// clockwise; counter-clockwise the other way round. R5 is the half circle about (5, 0).
    #[test]
    fn centres_by_hand() {
        let (s, e) = ([0.0, 0.0], [10.0, 0.0]);
        let h = 75f64.sqrt();
        let cw = |r| from_radius(s, e, r, true, 0.001).unwrap();
        let ccw = |r| from_radius(s, e, r, false, 0.001).unwrap();
        assert!(close(cw(10.0), [5.0, -h]));
        assert!(close(cw(-10.0), [5.0, h]));
        assert!(close(ccw(10.0), [5.0, h]));
        assert!(close(ccw(-10.0), [5.0, -h]));
        assert!(close(cw(5.0), [5.0, 0.0]));
        assert!((sweep(s, e, [5.0, -h], true) - PI / 3.0).abs() < 1e-12);
        assert!(from_radius(s, e, 4.0, true, 0.001).is_err());
        assert!(close(
            from_offsets(s, e, [5.0, -h], 0.001).unwrap(),
            [5.0, -h]
        ));
        assert!(from_offsets(s, [10.1, 0.0], [5.0, -h], 0.01).is_err());
    }

    /// The read-back's rule and the kernel's agree on arcs all round the circle, both directions,
    /// both signs of R; and the kernel's rule with its side flipped (the mutation a wrong centre
    /// rule would be) disagrees with the read-back on every one of them.
    #[test]
    fn the_kernels_rule_agrees_and_its_mutation_does_not() {
        use fmsvm_canon::Plane;
        use fmsvm_canon::arcs::{CentreWords, arc};
        let mut checked = 0;
        for k in 0..24 {
            let t = f64::from(k) * TAU / 24.0 + 0.1;
            let s = [3.0, -2.0];
            let e = [s[0] + 7.0 * t.cos(), s[1] + 7.0 * t.sin()];
            for (r, clockwise) in [(6.0, true), (6.0, false), (-6.0, true), (-6.0, false)] {
                let pose = |p: P2| [p[0], p[1], 0.0, 0.0, 0.0, 0.0];
                let ours = from_radius(s, e, r, clockwise, 0.001).unwrap();
                let kernel = |r| {
                    arc(
                        &pose(s),
                        &pose(e),
                        Plane::XY,
                        clockwise,
                        CentreWords::Radius(r),
                        0.001,
                    )
                    .unwrap()
                    .unwrap()
                    .centre
                };
                assert!(close(ours, kernel(r)), "R{r} cw {clockwise} to {e:?}");
                assert!(!close(ours, kernel(-r)), "the flipped rule passed at {e:?}");
                checked += 1;
            }
        }
        assert_eq!(checked, 96);
    }
}
