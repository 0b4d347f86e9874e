//! A mill's cutter as the stock sees it: the height of its cutting surface above the tip at each
//! distance from its axis (flat, ball and bull-nose end mills), and its non-cutting part above the
//! flutes.

/// The cutting end's shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A flat end mill: the end is a disc.
    Flat,
    /// A ball end mill: the end is a hemisphere of the tool's radius.
    Ball,
    /// A bull-nose (toroidal) end mill: a flat disc with a corner of this radius round it.
    Bull(f64),
}

/// A milling cutter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cutter {
    pub shape: Shape,
    /// The radius of the cutting part.
    pub radius: f64,
    /// The length of the flutes above the tip: the shank (or holder) above it cuts nothing.
    pub flute_length: Option<f64>,
    /// The radius of the shank above the flutes (default: the cutting radius).
    pub shank_radius: Option<f64>,
    /// Whether the end cuts at its centre (it may plunge straight down into material).
    pub plunges: bool,
}

impl Cutter {
    /// A cutter of `shape` and `radius` that plunges and has no declared flute length.
    pub fn new(shape: Shape, radius: f64) -> Cutter {
        Cutter {
            shape,
            radius,
            flute_length: None,
            shank_radius: None,
            plunges: true,
        }
    }

    /// The height of the cutting surface above the tip at distance `d` from the axis; None beyond
    /// the radius.
    #[inline]
    pub fn lift(&self, d: f64) -> Option<f64> {
        let r = self.radius;
        if d > r {
            return None;
        }
        Some(match self.shape {
            Shape::Flat => 0.0,
            Shape::Ball => r - (r * r - d * d).max(0.0).sqrt(),
            Shape::Bull(c) => {
                let flat = r - c;
                if d <= flat {
                    0.0
                } else {
                    let e = d - flat;
                    c - (c * c - e * e).max(0.0).sqrt()
                }
            }
        })
    }

    /// Whether the cutting surface at distance √`d2` from the axis is at least `h` above the tip
    /// (`lift(√d2) ≥ h`), without a square root where the shape allows.
    #[inline]
    pub fn rises_at_least(&self, d2: f64, h: f64) -> bool {
        if h <= 0.0 {
            return true;
        }
        let r = self.radius;
        match self.shape {
            Shape::Flat => false,
            // r − √(r² − d²) ≥ h ⟺ d² ≥ r² − (r − h)², for h ≤ r; above r it never rises so far.
            Shape::Ball => h <= r && d2 >= r * r - (r - h) * (r - h),
            Shape::Bull(_) => self.lift(d2.sqrt()).is_some_and(|l| l >= h),
        }
    }

    /// The shank above the flutes as a flat-bottomed cylinder: its radius and its height above the
    /// tip, when the tool gives the flute length.
    pub fn shank(&self) -> Option<(f64, f64)> {
        self.flute_length
            .map(|l| (self.shank_radius.unwrap_or(self.radius), l))
    }
}
