//! Plane geometry, once: 2-D vectors, where lines and circles meet (under one tolerance), and the
//! angle an arc sweeps. The contour stage (corner words, NCT's arc intersections), cutter
//! compensation and the canonical arc all compute with these.
//!
//! **Tolerance.** Positions are programmed to a least increment of 0.001 mm (0.0001 inch); the
//! arithmetic on them errs by about 1e-12. [`EPS`] sits between the two: a line or circle that
//! misses a circle by no more than `EPS` touches it (one point, given twice), and two centres closer
//! than `EPS` are one centre. Nothing a program can say is decided by a smaller difference.

use std::f64::consts::TAU;

/// A point or a direction in the plane of motion (its first and second axis).
pub type V2 = [f64; 2];

/// Lengths closer than this are equal: the one tolerance of the plane geometry (program units).
pub const EPS: f64 = 1e-6;

/// A vector shorter than this has no direction.
const NO_DIRECTION: f64 = 1e-12;

/// Lines whose directions' cross product is below this are parallel (unit directions).
const PARALLEL: f64 = 1e-12;

/// `a + b`.
#[inline]
pub fn add(a: V2, b: V2) -> V2 {
    [a[0] + b[0], a[1] + b[1]]
}
/// `a − b`.
#[inline]
pub fn sub(a: V2, b: V2) -> V2 {
    [a[0] - b[0], a[1] - b[1]]
}
/// `a · k`.
#[inline]
pub fn scale(a: V2, k: f64) -> V2 {
    [a[0] * k, a[1] * k]
}
/// The dot product.
#[inline]
pub fn dot(a: V2, b: V2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
/// The z component of `a × b`: positive when `b` turns left of `a`.
#[inline]
pub fn cross(a: V2, b: V2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
/// The length of `a`.
#[inline]
pub fn norm(a: V2) -> f64 {
    a[0].hypot(a[1])
}
/// The distance between two points.
#[inline]
pub fn dist(a: V2, b: V2) -> f64 {
    norm(sub(a, b))
}
/// `a` turned +90° (to the left of a direction).
#[inline]
pub fn left(a: V2) -> V2 {
    [-a[1], a[0]]
}
/// `a` turned by `angle` radians counterclockwise.
#[inline]
pub fn rotate(a: V2, angle: f64) -> V2 {
    let (s, c) = angle.sin_cos();
    [a[0] * c - a[1] * s, a[0] * s + a[1] * c]
}
/// The direction of `a` as an angle (−π, π].
#[inline]
pub fn angle(a: V2) -> f64 {
    a[1].atan2(a[0])
}
/// The unit vector at `angle` radians.
#[inline]
pub fn dir(angle: f64) -> V2 {
    [angle.cos(), angle.sin()]
}
/// `a` scaled to length 1, or None when it is too short to have a direction.
#[inline]
pub fn unit(a: V2) -> Option<V2> {
    let n = norm(a);
    (n > NO_DIRECTION).then(|| scale(a, 1.0 / n))
}

/// Where `p + s·d` meets `q + t·e` (d, e unit vectors), or None when they are parallel.
pub fn line_line(p: V2, d: V2, q: V2, e: V2) -> Option<V2> {
    let den = cross(d, e);
    if den.abs() < PARALLEL {
        return None;
    }
    let s = cross(sub(q, p), e) / den;
    Some(add(p, scale(d, s)))
}

/// The parameters t₁ ≤ t₂ where `p + t·d` (d a unit vector) meets the circle about `c` of radius
/// `rho`, or None when it misses by more than [`EPS`].
pub fn line_circle(p: V2, d: V2, c: V2, rho: f64) -> Option<(f64, f64)> {
    // The foot of the perpendicular from c is at t = (c − p)·d; the circle is ±√(ρ² − e²) either
    // side of it, e the distance from c to the foot.
    let t = dot(sub(c, p), d);
    let e = dist(c, add(p, scale(d, t)));
    if e > rho + EPS {
        return None;
    }
    let h = (rho * rho - e * e).max(0.0).sqrt();
    Some((t - h, t + h))
}

/// The two intersections of two circles, [left, right] of the line from `c1` to `c2` (the same
/// point twice when they touch within [`EPS`]), or None: apart, one inside the other, concentric
/// or a radius not positive.
pub fn circle_circle(c1: V2, r1: f64, c2: V2, r2: f64) -> Option<[V2; 2]> {
    // With d = c₂ − c₁, L = |d|: the foot of the chord lies a = (r₁² − r₂² + L²) / 2L along d from
    // c₁, the intersections h = √(r₁² − a²) either side of it: c₁ + (a·d ± h·left(d)) / L.
    let d = sub(c2, c1);
    let l = norm(d);
    if !(r1 > 0.0 && r2 > 0.0) || l <= EPS || l > r1 + r2 + EPS || l < (r1 - r2).abs() - EPS {
        return None;
    }
    let a = (r1 * r1 - r2 * r2 + l * l) / (2.0 * l);
    let h = (r1 * r1 - a * a).max(0.0).sqrt();
    let u = scale(d, 1.0 / l);
    let foot = add(c1, scale(u, a));
    Some([add(foot, scale(left(u), h)), sub(foot, scale(left(u), h))])
}

/// The angle an arc from `s` to `e` about `c` sweeps: 0 < sweep ≤ 2π (an end on the start is a
/// whole circle), plus `turns` whole turns; as LinuxCNC's `find_turn` counts it.
pub fn sweep(s: V2, e: V2, c: V2, ccw: bool, turns: u32) -> f64 {
    let a0 = angle(sub(s, c));
    let a1 = angle(sub(e, c));
    let mut d = if ccw { a1 - a0 } else { a0 - a1 };
    if d <= 1e-12 {
        d += TAU;
    }
    d + turns as f64 * TAU
}

/// The angle turned from `s` to `e` about `c` in the given direction, 0 ≤ angle < 2π (an end on
/// the start has turned 0).
pub fn turned(s: V2, e: V2, c: V2, ccw: bool) -> f64 {
    let a0 = angle(sub(s, c));
    let a1 = angle(sub(e, c));
    (if ccw { a1 - a0 } else { a0 - a1 }).rem_euclid(TAU)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_through_a_circle_meets_it_twice() {
        // y = 3 through the circle of radius 5 about the origin: x = ±4.
        let (t1, t2) = line_circle([-10.0, 3.0], [1.0, 0.0], [0.0, 0.0], 5.0).unwrap();
        assert!((t1 - 6.0).abs() < 1e-12 && (t2 - 14.0).abs() < 1e-12);
        // A tangent that misses by rounding touches; one that misses by more does not.
        let (t1, t2) = line_circle([0.0, 5.0 + EPS / 2.0], [1.0, 0.0], [0.0, 0.0], 5.0).unwrap();
        assert_eq!(t1, t2);
        assert!(line_circle([0.0, 5.0 + 2.0 * EPS], [1.0, 0.0], [0.0, 0.0], 5.0).is_none());
    }

    #[test]
    fn two_circles_meet_left_then_right() {
        // Radius 5 about (0, 0) and (8, 0): (4, ±3), left of the line of centres first.
        let [l, r] = circle_circle([0.0, 0.0], 5.0, [8.0, 0.0], 5.0).unwrap();
        assert!(dist(l, [4.0, 3.0]) < 1e-12 && dist(r, [4.0, -3.0]) < 1e-12);
        assert!(circle_circle([0.0, 0.0], 5.0, [11.0, 0.0], 5.0).is_none());
        assert!(circle_circle([0.0, 0.0], 5.0, [1.0, 0.0], 1.0).is_none());
        assert!(circle_circle([0.0, 0.0], 5.0, [0.0, 0.0], 5.0).is_none());
        assert!(circle_circle([0.0, 0.0], 0.0, [1.0, 0.0], 1.0).is_none());
        // Touching from outside: one point, twice.
        let [l, r] = circle_circle([0.0, 0.0], 5.0, [10.0 + EPS / 2.0, 0.0], 5.0).unwrap();
        assert!(dist(l, r) < 1e-3 && dist(l, [5.0, 0.0]) < 1e-3);
    }

    #[test]
    fn sweeps_and_turns() {
        let c = [0.0, 0.0];
        let (s, e) = ([1.0, 0.0], [0.0, 1.0]);
        assert!((sweep(s, e, c, true, 0) - TAU / 4.0).abs() < 1e-12);
        assert!((sweep(s, e, c, false, 0) - 3.0 * TAU / 4.0).abs() < 1e-12);
        assert!((sweep(s, s, c, true, 1) - 2.0 * TAU).abs() < 1e-12);
        assert_eq!(turned(s, s, c, true), 0.0);
        assert!((turned(s, e, c, false) - 3.0 * TAU / 4.0).abs() < 1e-12);
    }

    #[test]
    fn parallel_lines_do_not_meet() {
        assert!(line_line([0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 0.0]).is_none());
        let x = line_line([0.0, 0.0], [1.0, 0.0], [2.0, -1.0], [0.0, 1.0]).unwrap();
        assert_eq!(x, [2.0, 0.0]);
    }
}
