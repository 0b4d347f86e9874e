//! A mill's height field in four quarters, cut two at a time on two threads: a batch of moves
//! goes through each quarter in order, each quarter keeping its own chain of moves (a move that
//! does not pass over a quarter cuts what the last one left there), and what each move did is
//! the sum of what it did in each.

use crate::cutter::Cutter;
use crate::mill::{Cut, HeightField};

/// A straight move of a cutter, to be cut.
#[derive(Clone, Copy, Debug)]
pub struct Step {
    pub from: [f64; 3],
    pub to: [f64; 3],
    pub cutter: Cutter,
    /// It may leave what is ahead of it to the next (see `HeightField::advance`).
    pub chain: bool,
}

/// Batches smaller than this are cut on the calling thread.
const ON_TWO: usize = 256;

/// The field in quarters (fewer when it is a cell wide), with where each came from.
#[derive(Debug)]
pub struct Quarters {
    whole: HeightField,
    /// Each quarter and its first cell; the first two and the last two lie across each other
    /// (a raster along either axis passes over both of each pair in turn).
    parts: Vec<(HeightField, usize, usize)>,
}

impl Quarters {
    pub fn new(mut whole: HeightField) -> Quarters {
        let (nx, ny, _) = whole.grid();
        let (mi, mj) = (nx / 2, ny / 2);
        let parts = if mi == 0 || mj == 0 {
            vec![(whole.part([0, nx], [0, ny]), 0, 0)]
        } else {
            [
                ([0, mi], [0, mj]),
                ([mi, nx], [mj, ny]),
                ([mi, nx], [0, mj]),
                ([0, mi], [mj, ny]),
            ]
            .into_iter()
            .map(|(i, j)| (whole.part(i, j), i[0], j[0]))
            .collect()
        };
        // The quarters hold the cells now (the grid is held twice only while it is split and
        // joined).
        whole.hold_cells(false);
        Quarters { whole, parts }
    }

    /// The field whole again, what the last move left cut.
    pub fn join(mut self) -> HeightField {
        self.whole.hold_cells(true);
        for (mut part, i, j) in self.parts {
            part.flush();
            self.whole.put(&part, i, j);
        }
        self.whole
    }

    /// Cuts `steps` in order: for each, what the move before it left and this one cut (that
    /// move's), and what it removed.
    pub fn run(&mut self, steps: &[Step]) -> Vec<(Cut, Cut)> {
        let results: Vec<Vec<(Cut, Cut)>> = if steps.len() < ON_TWO || self.parts.len() < 4 {
            self.parts
                .iter_mut()
                .map(|(p, _, _)| cut(p, steps))
                .collect()
        } else {
            let (mine, theirs) = self.parts.split_at_mut(2);
            std::thread::scope(|s| {
                let other = s.spawn(|| {
                    theirs
                        .iter_mut()
                        .map(|(p, _, _)| cut(p, steps))
                        .collect::<Vec<_>>()
                });
                let mut done: Vec<_> = mine.iter_mut().map(|(p, _, _)| cut(p, steps)).collect();
                match other.join() {
                    Ok(more) => done.extend(more),
                    // A panic in the other thread is a defect: carry it on here.
                    Err(e) => std::panic::resume_unwind(e),
                }
                done
            })
        };
        (0..steps.len())
            .map(|k| {
                results
                    .iter()
                    .fold((Cut::default(), Cut::default()), |(b, n), r| {
                        (b.and(r[k].0), n.and(r[k].1))
                    })
            })
            .collect()
    }

    /// Cuts what the last move left: what that move removed there.
    pub fn flush(&mut self) -> Cut {
        self.parts
            .iter_mut()
            .fold(Cut::default(), |c, (p, _, _)| c.and(p.flush()))
    }

    /// What the move would remove, the stock left as it is.
    pub fn touch(&self, from: [f64; 3], to: [f64; 3], cutter: &Cutter) -> Cut {
        self.parts.iter().fold(Cut::default(), |c, (p, _, _)| {
            c.and(p.touch(from, to, cutter))
        })
    }

    /// The stock's volume now.
    pub fn volume(&self) -> f64 {
        self.parts.iter().map(|(p, _, _)| p.volume()).sum()
    }

    /// The side of a cell.
    pub fn cell(&self) -> f64 {
        self.whole.grid().2
    }
}

/// `steps` through one quarter.
fn cut(part: &mut HeightField, steps: &[Step]) -> Vec<(Cut, Cut)> {
    steps
        .iter()
        .map(|s| {
            if part.reaches(s.from, s.to, s.cutter.radius) {
                part.advance(s.from, s.to, &s.cutter, s.chain)
            } else {
                (part.flush(), Cut::default())
            }
        })
        .collect()
}
