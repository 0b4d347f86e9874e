//! A probe model for G31 skip moves, so probing macros expand offline (S4: #5061–#5066 skip position):
//! planned touch points in order, or a box of stock the probe stops at. Without a model a G31 runs to
//! its programmed end point.

/// What stops a G31 move.
#[derive(Clone, Debug, Default)]
pub enum ProbeModel {
    /// No model: the skip position is the programmed end point (the kernel warns once).
    #[default]
    None,
    /// Touch points given by the user, taken one per G31 in order (X Y Z).
    Points {
        /// The points.
        points: Vec<[f64; 3]>,
        /// The next one.
        next: usize,
    },
    /// A box of stock (work coordinates); the probe tip is a ball of `radius`.
    Stock {
        /// Lower corner X Y Z.
        min: [f64; 3],
        /// Upper corner X Y Z.
        max: [f64; 3],
        /// Stylus ball radius: the centre stops `radius` before a face.
        radius: f64,
    },
}

/// Where a skip move from `start` to `end` stops, and whether the probe touched.
pub fn skip(model: &mut ProbeModel, start: [f64; 3], end: [f64; 3]) -> ([f64; 3], bool) {
    match model {
        ProbeModel::None => (end, false),
        ProbeModel::Points { points, next } => match points.get(*next) {
            Some(p) => {
                *next += 1;
                (*p, true)
            }
            None => (end, false),
        },
        ProbeModel::Stock { min, max, radius } => {
            let lo = [min[0] - *radius, min[1] - *radius, min[2] - *radius];
            let hi = [max[0] + *radius, max[1] + *radius, max[2] + *radius];
            match entry(start, end, lo, hi) {
                Some(t) => {
                    let p = [0, 1, 2].map(|i| start[i] + t * (end[i] - start[i]));
                    (p, true)
                }
                None => (end, false),
            }
        }
    }
}

/// The first parameter t in [0, 1] where the segment start→end is inside the box (slab method).
fn entry(start: [f64; 3], end: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> Option<f64> {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for i in 0..3 {
        let d = end[i] - start[i];
        if d.abs() < 1e-12 {
            if start[i] < lo[i] || start[i] > hi[i] {
                return None;
            }
        } else {
            let (a, b) = ((lo[i] - start[i]) / d, (hi[i] - start[i]) / d);
            let (a, b) = if a < b { (a, b) } else { (b, a) };
            t0 = t0.max(a);
            t1 = t1.min(b);
            if t0 > t1 {
                return None;
            }
        }
    }
    Some(t0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stock_faces_stop_the_probe() {
        let mut m = ProbeModel::Stock {
            min: [0.0, 0.0, -30.0],
            max: [100.0, 50.0, 0.0],
            radius: 0.0,
        };
        // Down onto the top face.
        assert_eq!(
            skip(&mut m, [50.0, 25.0, 10.0], [50.0, 25.0, -10.0]),
            ([50.0, 25.0, 0.0], true)
        );
        // Along +X onto the left face.
        assert_eq!(
            skip(&mut m, [-10.0, 25.0, -5.0], [20.0, 25.0, -5.0]),
            ([0.0, 25.0, -5.0], true)
        );
        // Past the stock: no touch, the move ends at its end point.
        assert_eq!(
            skip(&mut m, [-10.0, 60.0, -5.0], [20.0, 60.0, -5.0]),
            ([20.0, 60.0, -5.0], false)
        );
        // A 2 mm ball stops 2 mm before the face.
        let mut m = ProbeModel::Stock {
            min: [0.0, 0.0, -30.0],
            max: [100.0, 50.0, 0.0],
            radius: 2.0,
        };
        assert_eq!(
            skip(&mut m, [-10.0, 25.0, -5.0], [20.0, 25.0, -5.0]),
            ([-2.0, 25.0, -5.0], true)
        );
    }
}
