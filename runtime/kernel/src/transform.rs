//! Programmable transforms of the program's points, in the order the Fanuc manual applies them:
//! mirror image (G51.1), then scaling (G51), then coordinate rotation (G68). Each maps a point of the
//! local frame (after G52/G92, before the work offset) to the point the tool goes to.

use fmsvm_block::Alarm;
use fmsvm_block::alarms::NO_FANUC_NUMBER;

use fmsvm_canon::{Plane, Pose};

/// A rotation about a centre in a plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rotation {
    /// The plane rotated in.
    pub plane: Plane,
    /// Centre in the plane's coordinates.
    pub centre: [f64; 2],
    /// Angle, degrees counter-clockwise seen from the positive normal axis.
    pub degrees: f64,
    cos: f64,
    sin: f64,
}

impl Rotation {
    /// A rotation by `degrees` about `centre` in `plane`.
    pub fn new(plane: Plane, centre: [f64; 2], degrees: f64) -> Rotation {
        let r = degrees.to_radians();
        Rotation {
            plane,
            centre,
            degrees,
            cos: r.cos(),
            sin: r.sin(),
        }
    }
}

/// The active transforms.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Transform {
    /// G51.1: the mirror line of each axis X Y Z (None = not mirrored).
    pub mirror: [Option<f64>; 3],
    /// G51: centre and factor of each axis X Y Z (factor 1 = not scaled).
    pub scale: Option<([f64; 3], [f64; 3])>,
    /// G68.
    pub rotation: Option<Rotation>,
}

impl Transform {
    /// No transform is active (the common case, checked first on every block).
    #[inline(always)]
    pub fn is_identity(&self) -> bool {
        self.mirror == [None; 3] && self.scale.is_none() && self.rotation.is_none()
    }

    /// Where programmed point `p` goes.
    pub fn apply(&self, p: &Pose) -> Pose {
        let mut q = *p;
        for (i, m) in self.mirror.iter().enumerate() {
            if let Some(c) = m {
                q[i] = 2.0 * c - q[i];
            }
        }
        if let Some((c, f)) = &self.scale {
            for i in 0..3 {
                q[i] = c[i] + f[i] * (q[i] - c[i]);
            }
        }
        if let Some(r) = &self.rotation {
            let (a, b, _) = r.plane.axes();
            let (x, y) = (q[a] - r.centre[0], q[b] - r.centre[1]);
            q[a] = r.centre[0] + x * r.cos - y * r.sin;
            q[b] = r.centre[1] + x * r.sin + y * r.cos;
        }
        q
    }

    /// The programmed point that goes to `q`: the inverse of `apply` (rotation back, then the
    /// scaling undone, then the mirror again).
    pub fn invert(&self, q: &Pose) -> Pose {
        let mut p = *q;
        if let Some(r) = &self.rotation {
            let (a, b, _) = r.plane.axes();
            let (x, y) = (p[a] - r.centre[0], p[b] - r.centre[1]);
            p[a] = r.centre[0] + x * r.cos + y * r.sin;
            p[b] = r.centre[1] - x * r.sin + y * r.cos;
        }
        if let Some((c, f)) = &self.scale {
            for i in 0..3 {
                p[i] = c[i] + (p[i] - c[i]) / f[i];
            }
        }
        for (i, m) in self.mirror.iter().enumerate() {
            if let Some(c) = m {
                p[i] = 2.0 * c - p[i];
            }
        }
        p
    }

    /// Whether the transform reverses the direction of arcs in `plane` (an odd number of mirrored or
    /// negatively scaled axes of the plane); cutter compensation swaps sides likewise.
    pub fn reverses(&self, plane: Plane) -> bool {
        let (a, b, _) = plane.axes();
        let flips = |i: usize| {
            let m = self.mirror.get(i).copied().flatten().is_some();
            let s = self.scale.as_ref().is_some_and(|(_, f)| f[i] < 0.0);
            m != s
        };
        flips(a) != flips(b)
    }

    /// The factor a radius in `plane` is scaled by, or an alarm when the plane's axes are scaled
    /// unequally (the arc would be an ellipse).
    pub fn radius_factor(&self, plane: Plane) -> Result<f64, Alarm> {
        let Some((_, f)) = &self.scale else {
            return Ok(1.0);
        };
        let (a, b, _) = plane.axes();
        if (f[a].abs() - f[b].abs()).abs() > 1e-12 {
            return Err(Alarm::new(
                NO_FANUC_NUMBER,
                "an arc under unequal scaling factors of its plane (G51 I J K) would be an ellipse",
            ));
        }
        Ok(f[a].abs())
    }

    /// Alarm when an arc in `plane` meets a rotation in another plane.
    pub fn check_arc_plane(&self, plane: Plane) -> Result<(), Alarm> {
        match &self.rotation {
            Some(r) if r.plane != plane && r.degrees.rem_euclid(360.0) != 0.0 => Err(Alarm::new(
                NO_FANUC_NUMBER,
                "an arc in another plane than the coordinate rotation (G68) is not an arc",
            )),
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &Pose, b: [f64; 3]) -> bool {
        (0..3).all(|i| (a[i] - b[i]).abs() < 1e-9)
    }

    #[test]
    fn order_is_mirror_scale_rotate() {
        // Hand-computed: X10 Y0 mirrored about X0 → X-10; scaled ×2 about the origin → X-20;
        // rotated 90° about X0 Y0 → X0 Y-20.
        let t = Transform {
            mirror: [Some(0.0), None, None],
            scale: Some(([0.0; 3], [2.0, 2.0, 1.0])),
            rotation: Some(Rotation::new(Plane::XY, [0.0, 0.0], 90.0)),
        };
        assert!(close(
            &t.apply(&[10.0, 0.0, 5.0, 0.0, 0.0, 0.0]),
            [0.0, -20.0, 5.0]
        ));
        assert!(t.reverses(Plane::XY));
        assert!(t.reverses(Plane::ZX));
        assert!(!t.reverses(Plane::YZ));
        assert_eq!(t.radius_factor(Plane::XY).unwrap(), 2.0);
        assert!(t.radius_factor(Plane::ZX).is_err());
    }

    #[test]
    fn rotation_about_a_centre() {
        // 30° about X10 Y10: X20 Y10 → X10+10cos30 Y10+10sin30.
        let t = Transform {
            rotation: Some(Rotation::new(Plane::XY, [10.0, 10.0], 30.0)),
            ..Transform::default()
        };
        let c = 30f64.to_radians().cos() * 10.0 + 10.0;
        assert!(close(
            &t.apply(&[20.0, 10.0, 0.0, 0.0, 0.0, 0.0]),
            [c, 15.0, 0.0]
        ));
        // G18 rotation turns Z toward X.
        let t = Transform {
            rotation: Some(Rotation::new(Plane::ZX, [0.0, 0.0], 90.0)),
            ..Transform::default()
        };
        assert!(close(
            &t.apply(&[0.0, 0.0, 10.0, 0.0, 0.0, 0.0]),
            [10.0, 0.0, 0.0]
        ));
    }
}
