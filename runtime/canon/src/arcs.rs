//! Circular interpolation G2/G3: the centre of an arc from I J K (incremental from the start, Fanuc) or
//! from R (positive up to 180°, negative beyond), the end-point check (alarm 0020), full circles,
//! helices, and chords within a tolerance for `--linearize`.

use fmsvm_block::Alarm;

use crate::canon::{Arc, Plane, Pose};

/// 0020 OVER TOLERANCE OF RADIUS.
pub const RADIUS_TOLERANCE: u32 = 20;

/// How an arc's centre was given.
#[derive(Clone, Copy, Debug)]
pub enum CentreWords {
    /// I J K, incremental from the start (each missing one is 0), in X Y Z order.
    Offsets([f64; 3]),
    /// R: signed radius.
    Radius(f64),
}

/// The arc from `from` to `to` in `plane`, or None when it does not move (an R arc whose end is its
/// start: Fanuc moves nothing). `tolerance` is how far the end may lie off the start's circle.
pub fn arc(
    from: &Pose,
    to: &Pose,
    plane: Plane,
    clockwise: bool,
    centre: CentreWords,
    tolerance: f64,
) -> Result<Option<Arc>, Alarm> {
    let (a, b, _) = plane.axes();
    let [sx, sy] = [from[a], from[b]];
    let [ex, ey] = [to[a], to[b]];
    let c = match centre {
        CentreWords::Offsets(ijk) => {
            let (ci, cj) = (ijk[a], ijk[b]);
            let c = [sx + ci, sy + cj];
            let r0 = ci.hypot(cj);
            let r1 = (ex - c[0]).hypot(ey - c[1]);
            if r0 == 0.0 {
                return Err(Alarm::new(
                    RADIUS_TOLERANCE,
                    "arc with zero radius: the centre (I J K) is the start point",
                ));
            }
            if (r1 - r0).abs() > tolerance {
                return Err(Alarm::new(
                    RADIUS_TOLERANCE,
                    format!(
                        "over tolerance of radius: the end point is {:.4} from the centre, the start {:.4} (tolerance {tolerance})",
                        r1, r0
                    ),
                ));
            }
            c
        }
        CentreWords::Radius(r) => {
            let (dx, dy) = (ex - sx, ey - sy);
            let d = dx.hypot(dy);
            if d < 1e-12 {
                return Ok(None);
            }
            if r == 0.0 {
                return Err(Alarm::new(RADIUS_TOLERANCE, "arc with R0"));
            }
            let half = d / 2.0;
            let h2 = r * r - half * half;
            let h = if h2 >= 0.0 {
                h2.sqrt()
            } else if half - r.abs() <= tolerance {
                0.0
            } else {
                return Err(Alarm::new(
                    RADIUS_TOLERANCE,
                    format!(
                        "over tolerance of radius: R{} cannot reach an end point {:.4} away",
                        r, d
                    ),
                ));
            };
            // The centre lies to the right of the chord for a clockwise arc of at most 180° (R > 0),
            // to the left for a counter-clockwise one; a negative R takes the other centre.
            let (nx, ny) = (-dy / d, dx / d);
            let side = if clockwise { -1.0 } else { 1.0 } * r.signum();
            [sx + dx / 2.0 + side * h * nx, sy + dy / 2.0 + side * h * ny]
        }
    };
    Ok(Some(Arc {
        to: *to,
        centre: c,
        plane,
        clockwise,
        turns: 0,
    }))
}

/// The chords of `arc` from `from` that stay within `tolerance` of it; calls `out` with each end point.
pub fn chords<E>(
    from: &Pose,
    arc: &Arc,
    tolerance: f64,
    out: &mut dyn FnMut(Pose) -> Result<(), E>,
) -> Result<(), E> {
    let (r, sweep) = arc.sweep(from);
    let (a, b, n) = arc.plane.axes();
    // A chord of angle θ strays r(1 − cos θ/2) from its arc.
    let step = if tolerance >= r {
        std::f64::consts::PI
    } else {
        2.0 * (1.0 - tolerance / r).acos()
    };
    let count = ((sweep / step).ceil() as u64).clamp(1, 1 << 20);
    let [cx, cy] = arc.centre;
    let a0 = (from[b] - cy).atan2(from[a] - cx);
    let dir = if arc.clockwise { -1.0 } else { 1.0 };
    for k in 1..count {
        let t = k as f64 / count as f64;
        let ang = a0 + dir * sweep * t;
        let mut p: Pose = std::array::from_fn(|i| from[i] + (arc.to[i] - from[i]) * t);
        p[a] = cx + r * ang.cos();
        p[b] = cy + r * ang.sin();
        p[n] = from[n] + (arc.to[n] - from[n]) * t;
        out(p)?;
    }
    out(arc.to)
}

#[cfg(test)]
mod tests {
    use super::*;

    const O: Pose = [0.0; 6];

    fn p(x: f64, y: f64, z: f64) -> Pose {
        [x, y, z, 0.0, 0.0, 0.0]
    }

    #[test]
    fn centre_from_r_both_signs() {
        // X0 Y0 → X10 Y0 with R5: a half circle, centre X5 Y0 either way.
        let a = arc(
            &O,
            &p(10.0, 0.0, 0.0),
            Plane::XY,
            true,
            CentreWords::Radius(5.0),
            0.005,
        )
        .unwrap()
        .unwrap();
        assert!((a.centre[0] - 5.0).abs() < 1e-9 && a.centre[1].abs() < 1e-9);
        // X0 Y0 → X10 Y0, R10 clockwise (≤180°): centre right of the chord (below it):
        // X5 Y-√75.
        let a = arc(
            &O,
            &p(10.0, 0.0, 0.0),
            Plane::XY,
            true,
            CentreWords::Radius(10.0),
            0.005,
        )
        .unwrap()
        .unwrap();
        assert!((a.centre[1] + 75f64.sqrt()).abs() < 1e-9);
        // the long way round, centre above.
        let a = arc(
            &O,
            &p(10.0, 0.0, 0.0),
            Plane::XY,
            true,
            CentreWords::Radius(-10.0),
            0.005,
        )
        .unwrap()
        .unwrap();
        assert!((a.centre[1] - 75f64.sqrt()).abs() < 1e-9);
        assert!(a.sweep(&O).1 > std::f64::consts::PI);
        // Counter-clockwise R10: centre above.
        let a = arc(
            &O,
            &p(10.0, 0.0, 0.0),
            Plane::XY,
            false,
            CentreWords::Radius(10.0),
            0.005,
        )
        .unwrap()
        .unwrap();
        assert!((a.centre[1] - 75f64.sqrt()).abs() < 1e-9);
        // R too small: alarm 0020; end equal to start: no move.
        let e = arc(
            &O,
            &p(10.0, 0.0, 0.0),
            Plane::XY,
            true,
            CentreWords::Radius(4.0),
            0.005,
        );
        assert_eq!(e.unwrap_err().number, 20);
        assert!(
            arc(&O, &O, Plane::XY, true, CentreWords::Radius(4.0), 0.005)
                .unwrap()
                .is_none()
        );
    }

    #[test]
    fn centre_from_offsets_and_the_end_point_check() {
        // G18: I (X) and K (Z) are the plane's; J is ignored.
        let from = p(10.0, 0.0, 0.0);
        let a = arc(
            &from,
            &p(0.0, 0.0, 10.0),
            Plane::ZX,
            false,
            CentreWords::Offsets([-10.0, 99.0, 0.0]),
            0.005,
        )
        .unwrap()
        .unwrap();
        assert_eq!(a.centre, [0.0, 0.0]);
        let e = arc(
            &O,
            &p(10.0, 1.0, 0.0),
            Plane::XY,
            true,
            CentreWords::Offsets([5.0, 0.0, 0.0]),
            0.005,
        );
        assert_eq!(e.unwrap_err().number, 20);
    }

    #[test]
    fn chords_stay_within_tolerance() {
        // A quarter of R10 with 0.01 tolerance: θ = 2 acos(0.999) = 0.0894 rad, 18 chords.
        let from = p(10.0, 0.0, 0.0);
        let a = Arc {
            to: p(0.0, 10.0, -5.0),
            centre: [0.0, 0.0],
            plane: Plane::XY,
            clockwise: false,
            turns: 0,
        };
        let mut pts = Vec::new();
        chords::<()>(&from, &a, 0.01, &mut |q| {
            pts.push(q);
            Ok(())
        })
        .unwrap();
        assert_eq!(pts.len(), 18);
        assert_eq!(*pts.last().unwrap(), a.to);
        let mut prev = from;
        for q in &pts {
            let mid = [(prev[0] + q[0]) / 2.0, (prev[1] + q[1]) / 2.0];
            let dev = 10.0 - mid[0].hypot(mid[1]);
            assert!((0.0..=0.01 + 1e-12).contains(&dev), "deviation {dev}");
            assert!((q[0].hypot(q[1]) - 10.0).abs() < 1e-9);
            prev = *q;
        }
        // The helix descends linearly: halfway round the quarter, Z is −2.5.
        assert!((pts[8][2] + 2.5).abs() < 1e-9);
    }
}
