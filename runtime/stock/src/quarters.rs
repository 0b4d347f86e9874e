//! A mill's height field in four quarters, cut two at a time by two worker threads while the
//! caller goes on: a batch of moves goes through each quarter in order, each quarter keeping its
//! own chain of moves (a move that does not pass over a quarter cuts what the last one left
//! there), and what each move did is the sum of what it did in each. Each worker takes its
//! batches in the order they were sent, so one may be a batch or two ahead of the other.

use std::collections::VecDeque;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, Sender, channel};
use std::thread::JoinHandle;

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

/// Batches smaller than this are cut on the calling thread (when no batch is away).
const ON_TWO: usize = 256;

/// A quarter and its first cell (column, row) in the whole field.
type Part = (HeightField, usize, usize);

/// What each move of a batch did in one quarter: what the move before it left and this one cut
/// (that move's), and what it removed; empty where no move did anything there.
type Cuts = Vec<(Cut, Cut)>;

/// The field in quarters (fewer when it is a cell wide), with where each came from.
#[derive(Debug)]
pub struct Quarters {
    whole: HeightField,
    /// Each quarter, in order, while they are here; the first two and the last two lie across
    /// each other (a raster along either axis passes over both of each pair in turn), and each
    /// pair is one worker's while they are away.
    parts: Vec<Part>,
    /// The two workers, once a batch was big enough for them.
    crew: Crew,
    /// The batches sent and not yet received, oldest first: their moves, and what each quarter's
    /// moves did where they were cut here (None where the crew has them).
    sent: VecDeque<(usize, Option<Vec<Cuts>>)>,
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
        Quarters {
            whole,
            parts,
            crew: Crew::default(),
            sent: VecDeque::new(),
        }
    }

    /// The field whole again, what the last move left cut.
    pub fn join(mut self) -> HeightField {
        self.home();
        let Quarters {
            mut whole, parts, ..
        } = self;
        whole.hold_cells(true);
        for (mut part, i, j) in parts {
            part.flush();
            whole.put(&part, i, j);
        }
        whole
    }

    /// Cuts `steps` in order: for each, what the move before it left and this one cut (that
    /// move's), and what it removed.
    pub fn run(&mut self, steps: &[Step]) -> Vec<(Cut, Cut)> {
        self.send(steps.into());
        // Batches sent before it and not received are cut first (what they did is dropped: the
        // caller receives them before).
        while self.sent.len() > 1 {
            self.receive();
        }
        self.receive()
    }

    /// Sends `steps` to be cut after the batches sent before them: to the two workers when the
    /// batch is big enough or others are away, else cut here and now. `receive` gives what
    /// they did, batch by batch in the order sent.
    pub fn send(&mut self, steps: Arc<[Step]>) {
        let away = self.parts.is_empty();
        if away && self.sent.is_empty() && steps.len() < ON_TWO {
            self.home();
        }
        if !self.parts.is_empty() && (steps.len() < ON_TWO || self.parts.len() < 4 || !self.hire())
        {
            let cuts = self
                .parts
                .iter_mut()
                .map(|(p, _, _)| cut(p, &steps))
                .collect();
            self.sent.push_back((steps.len(), Some(cuts)));
            return;
        }
        let mut pairs = std::mem::take(&mut self.parts).into_iter();
        for worker in &mut self.crew.0 {
            // The quarters go with the first batch after they were here.
            let pair: Vec<Part> = pairs.by_ref().take(2).collect();
            if !pair.is_empty() {
                worker.give(Job::Take(pair));
            }
            worker.give(Job::Cut(Arc::clone(&steps)));
        }
        self.sent.push_back((steps.len(), None));
    }

    /// What each move of the oldest batch sent and not yet received did, once it is cut.
    pub fn receive(&mut self) -> Vec<(Cut, Cut)> {
        let (n, cuts) = match self.sent.pop_front() {
            None => return Vec::new(),
            Some((n, Some(cuts))) => (n, cuts),
            Some((n, None)) => {
                let mut cuts = Vec::with_capacity(4);
                for worker in &mut self.crew.0 {
                    match worker.take() {
                        Reply::Cuts(c) => cuts.extend(c),
                        Reply::Parts(_) => {
                            unreachable!("the quarters are asked back only when no batch is away")
                        }
                    }
                }
                (n, cuts)
            }
        };
        // In the quarters' order (the sums' rounding that of one field's pieces in turn).
        let mut done = vec![(Cut::default(), Cut::default()); n];
        for quarter in cuts.iter().filter(|c| !c.is_empty()) {
            for (d, &(b, c)) in done.iter_mut().zip(quarter) {
                *d = (d.0.and(b), d.1.and(c));
            }
        }
        done
    }

    /// The quarters here again, every batch sent cut (what those did is dropped: the caller
    /// receives them first).
    fn home(&mut self) {
        while !self.sent.is_empty() {
            self.receive();
        }
        if !self.parts.is_empty() {
            return;
        }
        for worker in &mut self.crew.0 {
            worker.give(Job::Give);
            match worker.take() {
                Reply::Parts(p) => self.parts.extend(p),
                Reply::Cuts(_) => unreachable!("every batch sent was received"),
            }
        }
    }

    /// The two workers, started when first wanted; false where a thread cannot be started.
    fn hire(&mut self) -> bool {
        while self.crew.0.len() < 2 {
            match Worker::start() {
                Some(w) => self.crew.0.push(w),
                None => return false,
            }
        }
        true
    }

    /// Cuts what the last move left: what that move removed there.
    pub fn flush(&mut self) -> Cut {
        self.home();
        self.parts
            .iter_mut()
            .fold(Cut::default(), |c, (p, _, _)| c.and(p.flush()))
    }

    /// What the move would remove, the stock left as it is.
    pub fn touch(&mut self, from: [f64; 3], to: [f64; 3], cutter: &Cutter) -> Cut {
        self.home();
        self.parts.iter().fold(Cut::default(), |c, (p, _, _)| {
            c.and(p.touch(from, to, cutter))
        })
    }

    /// The stock's volume now.
    pub fn volume(&mut self) -> f64 {
        self.home();
        self.parts.iter().map(|(p, _, _)| p.volume()).sum()
    }

    /// The side of a cell.
    pub fn cell(&self) -> f64 {
        self.whole.grid().2
    }
}

/// What a worker is given to do.
enum Job {
    /// Hold these quarters.
    Take(Vec<Part>),
    /// Cut these moves through them.
    Cut(Arc<[Step]>),
    /// Give them back.
    Give,
}

/// What a worker gives back.
enum Reply {
    /// What each move of a batch did in each of its quarters.
    Cuts(Vec<Cuts>),
    /// Its quarters.
    Parts(Vec<Part>),
}

/// A thread cutting a pair of quarters, batch after batch.
#[derive(Debug)]
struct Worker {
    jobs: Option<Sender<Job>>,
    replies: Receiver<Reply>,
    thread: Option<JoinHandle<()>>,
}

impl Worker {
    /// A worker waiting for its quarters, or None where a thread cannot be started.
    fn start() -> Option<Worker> {
        let (jobs, given) = channel::<Job>();
        let (reply, replies) = channel();
        let thread = std::thread::Builder::new()
            .name("stock".into())
            .spawn(move || {
                let mut parts = Vec::new();
                while let Ok(job) = given.recv() {
                    let answer = match job {
                        Job::Take(p) => {
                            parts = p;
                            continue;
                        }
                        Job::Cut(steps) => {
                            Reply::Cuts(parts.iter_mut().map(|(p, _, _)| cut(p, &steps)).collect())
                        }
                        Job::Give => Reply::Parts(std::mem::take(&mut parts)),
                    };
                    if reply.send(answer).is_err() {
                        break;
                    }
                }
            })
            .ok()?;
        Some(Worker {
            jobs: Some(jobs),
            replies,
            thread: Some(thread),
        })
    }

    fn give(&mut self, job: Job) {
        if self.jobs.as_ref().is_none_or(|j| j.send(job).is_err()) {
            self.lost();
        }
    }

    fn take(&mut self) -> Reply {
        match self.replies.recv() {
            Ok(r) => r,
            Err(_) => self.lost(),
        }
    }

    /// The worker stopped (it panicked, a defect): its panic is carried on here.
    fn lost(&mut self) -> ! {
        match self.thread.take().map(JoinHandle::join) {
            Some(Err(e)) => std::panic::resume_unwind(e),
            _ => panic!("the stock's worker thread stopped without its quarters"),
        }
    }
}

/// The workers.
#[derive(Debug, Default)]
struct Crew(Vec<Worker>);

impl Drop for Crew {
    /// The workers are let go (a batch under way is finished first) and waited for.
    fn drop(&mut self) {
        for worker in &mut self.0 {
            worker.jobs = None;
        }
        for worker in &mut self.0 {
            if let Some(t) = worker.thread.take() {
                // A worker's panic was carried on where its quarters were asked for.
                let _ = t.join();
            }
        }
    }
}

/// `steps` through one quarter (empty where none did anything there).
fn cut(part: &mut HeightField, steps: &[Step]) -> Cuts {
    let nothing = (Cut::default(), Cut::default());
    let mut cuts = Vec::new();
    for (k, s) in steps.iter().enumerate() {
        let done = if part.reaches(s.from, s.to, s.cutter.radius) {
            part.advance(s.from, s.to, &s.cutter, s.chain)
        } else {
            (part.flush(), Cut::default())
        };
        if done != nothing {
            cuts.resize(steps.len(), nothing);
            cuts[k] = done;
        }
    }
    cuts
}
