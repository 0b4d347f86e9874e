//! The pipelined emitters: the run's thread hands the steady work that cannot fail (a literal
//! emitter's plain blocks, a resolved emitter's straight moves and feed rates) to a writer thread in
//! batches, which formats and writes it; any other call waits for the writer to catch up and runs on
//! the run's thread, so the output and every stop are those of the emitter on one thread.
//!
//! Literal output: a block is handed on only when the run's thread can tell that writing it cannot fail: it takes
//! the plain path (`LiteralEmitter::plain_block`), every value is in its letter's safe range
//! (`Offload::safe`: no digit or range alarm), its longest possible line fits the dialect's length,
//! and the byte budget has room for that longest line on top of the longest lines of every block
//! still at the writer. Anything else, and any block once the budget is that close, waits for the
//! writer to finish what it has (a *drain*) and is written by the run's thread, which then gets the
//! exact alarm or limit the literal emitter gives. What the writer thread can still meet is an
//! output error (a full disk): it is reported when its batch comes back (at a later batch or a drain,
//! up to `POOL` × `BATCH` blocks on), not at the one whose line failed; after a stop that does not
//! touch the emitter (a VM alarm, a block limit) `settle` still reports it, so it is the run's stop
//! as on one thread. The budget is spent only by the writer while blocks are away (the run's
//! thread spends nothing then: a program that prints is not pipelined, see `fmsvm run`).
//!
//! Resolved output: a rapid or feed move is handed on when every axis it writes and the feed rate
//! it may write are in their safe ranges for the units in force (`resolved::Offload`), the budget
//! has room for the longest such line, and the operation before it was a move or a feed rate (the
//! first move after anything else, which may close a cycle or write offset codes, runs on the run's
//! thread); a feed rate is handed on when it is in its safe range. The safe ranges are worked out
//! again from the emitter after every operation that ran on the run's thread.

use std::io::Write;
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::thread::Scope;

use fmsvm_block::{Code, Letter, OutputBudget, Stop};

use crate::literal::LiteralEmitter;
use crate::resolved::ResolvedEmitter;
use fmsvm_canon::decode::{DecodeTable, Decoded};
use fmsvm_canon::{Canon, Origin};
use fmsvm_canon::{Context, Emitter};

/// Blocks in a batch.
const BATCH: usize = 1024;

/// Batches in flight: one being filled, the rest at the writer or on their way back.
const POOL: usize = 4;

/// Words of a block go in pieces of this many (a block of up to eight words is one fixed-size copy).
const PIECE: usize = 8;

// A block's word slots split into whole pieces (`as_chunks` would drop a remainder).
const _: () = assert!(fmsvm_block::MAX_WORDS.is_multiple_of(PIECE));

/// An emitter whose steady work a writer thread can take: what a batch holds, what the run's
/// thread checks before handing work on, and how the writer writes a batch.
pub trait Handing: Emitter + Send {
    /// Work on its way to the writer thread.
    type Batch: Send;
    /// What the run's thread checks.
    type Offload;
    /// The checks, or None when no work can be handed on (the emitter is then used as it is).
    fn offload(&self, decode: &DecodeTable) -> Option<Self::Offload>;
    /// An empty batch with room for `BATCH` pieces of work.
    fn new_batch() -> Self::Batch;
    /// The pieces of work in `batch`.
    fn batch_len(batch: &Self::Batch) -> usize;
    /// Empties `batch`, keeping its room.
    fn clear(batch: &mut Self::Batch);
    /// Writes `batch`; stops at the first error.
    fn write(&mut self, batch: &Self::Batch) -> Result<(), Stop>;
    /// The byte budget the lines are spent from.
    fn budget(&self) -> &OutputBudget;
}

/// Plain blocks on their way to the writer thread.
#[derive(Default)]
pub struct PlainBlocks {
    /// Per block: its word count, block delete, inch units.
    heads: Vec<(u8, bool, bool)>,
    /// Every block's letters, one after the other, in pieces (the last piece of a block padded).
    letters: Vec<[Letter; PIECE]>,
    /// Their decoded values, in the same pieces.
    values: Vec<[f64; PIECE]>,
}

impl<W: Write + Send> Handing for LiteralEmitter<W> {
    type Batch = PlainBlocks;
    type Offload = crate::literal::Offload;

    fn offload(&self, decode: &DecodeTable) -> Option<Self::Offload> {
        LiteralEmitter::offload(self, decode)
    }

    /// Room for `BATCH` blocks of up to two pieces each.
    fn new_batch() -> PlainBlocks {
        PlainBlocks {
            heads: Vec::with_capacity(BATCH),
            letters: Vec::with_capacity(BATCH * 2),
            values: Vec::with_capacity(BATCH * 2),
        }
    }

    fn batch_len(batch: &PlainBlocks) -> usize {
        batch.heads.len()
    }

    fn clear(batch: &mut PlainBlocks) {
        batch.heads.clear();
        batch.letters.clear();
        batch.values.clear();
    }

    fn write(&mut self, batch: &PlainBlocks) -> Result<(), Stop> {
        let mut at = 0;
        for &(n, block_delete, inch) in &batch.heads {
            let n = n as usize;
            let end = at + n.div_ceil(PIECE);
            let letters = &batch.letters[at..end].as_flattened()[..n];
            let values = &batch.values[at..end].as_flattened()[..n];
            at = end;
            self.plain_handed(letters, values, block_delete, inch)?;
        }
        Ok(())
    }

    fn budget(&self) -> &OutputBudget {
        LiteralEmitter::budget(self)
    }
}

/// Moves and feed rates on their way to the writer thread.
pub type Moves = Vec<(Canon<'static>, Origin)>;

impl<W: Write + Send> Handing for ResolvedEmitter<W> {
    type Batch = Moves;
    type Offload = crate::resolved::Offload;

    fn offload(&self, _: &DecodeTable) -> Option<Self::Offload> {
        ResolvedEmitter::offload(self)
    }

    fn new_batch() -> Moves {
        Vec::with_capacity(BATCH)
    }

    fn batch_len(batch: &Moves) -> usize {
        batch.len()
    }

    fn clear(batch: &mut Moves) {
        batch.clear();
    }

    fn write(&mut self, batch: &Moves) -> Result<(), Stop> {
        for (op, origin) in batch {
            self.canon(op, *origin)?;
        }
        Ok(())
    }

    fn budget(&self) -> &OutputBudget {
        ResolvedEmitter::budget(self)
    }
}

/// An emitter whose steady work is formatted and written by a second thread.
pub struct Pipelined<E: Handing> {
    emitter: Arc<Mutex<E>>,
    /// The checks made on the run's thread.
    offload: E::Offload,
    /// The batch being filled.
    batch: E::Batch,
    /// Empty batches at hand.
    spare: Vec<E::Batch>,
    /// Full batches to the writer (None once closed).
    to_writer: Option<SyncSender<E::Batch>>,
    /// Batches back from the writer, emptied, each with what stopped the writer in it.
    back: Receiver<(E::Batch, Option<Stop>)>,
    /// Batches at the writer or on their way back.
    away: usize,
    budget: OutputBudget,
    /// The budget's limit (kept here: the budget's own cache line is the writer's, who spends it
    /// every line).
    limit: Option<u64>,
    /// The budget spent at the last drain.
    used: u64,
    /// The longest lines of the work handed on since the last drain.
    bounds: u64,
    /// The block limit (a resolved block can make many lines: a cycle's moves, an arc's chords).
    line_limit: Option<u64>,
    /// The blocks spent at the last drain, and the lines handed on since.
    lines_used: u64,
    lines_away: u64,
    /// The writer stopped: nothing more is handed on.
    failed: bool,
}

impl<E: Handing> Pipelined<E> {
    /// `emitter` with its steady work written by a thread of `scope`, for blocks decoded by
    /// `decode`; the emitter back when none of its work can be handed on (`--compact`,
    /// renumbering of literal output: the caller uses it itself then).
    pub fn new<'scope>(
        scope: &'scope Scope<'scope, '_>,
        emitter: E,
        decode: &DecodeTable,
    ) -> Result<Self, Box<E>>
    where
        E: 'scope,
    {
        let Some(offload) = emitter.offload(decode) else {
            return Err(Box::new(emitter));
        };
        let budget = emitter.budget().clone();
        let emitter = Arc::new(Mutex::new(emitter));
        let (to_writer, full) = sync_channel::<E::Batch>(POOL);
        let (to_run, back) = sync_channel::<(E::Batch, Option<Stop>)>(POOL);
        let shared = Arc::clone(&emitter);
        scope.spawn(move || {
            let mut failed = false;
            for mut batch in full {
                let mut error = None;
                if !failed && let Err(stop) = lock(&shared).write(&batch) {
                    // An output error, or the wall-time limit the lines look at (the run's thread
                    // checked the bytes, and its gate stops at fewer blocks than the lines); the
                    // run stops at its next block.
                    debug_assert!(
                        matches!(
                            stop,
                            Stop::Io(_)
                                | Stop::Limit {
                                    kind: fmsvm_block::LimitKind::WallTime,
                                    ..
                                }
                        ),
                        "{stop}"
                    );
                    error = Some(stop);
                    failed = true;
                }
                E::clear(&mut batch);
                if to_run.send((batch, error)).is_err() {
                    break;
                }
            }
        });
        Ok(Pipelined {
            emitter,
            offload,
            batch: E::new_batch(),
            spare: (1..POOL).map(|_| E::new_batch()).collect(),
            to_writer: Some(to_writer),
            back,
            away: 0,
            used: budget.used(),
            limit: budget.limit(),
            line_limit: budget.line_limit(),
            lines_used: budget.lines(),
            lines_away: 0,
            budget,
            bounds: 0,
            failed: false,
        })
    }

    /// `f` on the emitter on the run's thread, once the writer has finished what it has; what
    /// it spends is noted.
    fn here<R>(&mut self, f: impl FnOnce(&mut E) -> Result<R, Stop>) -> Result<R, Stop> {
        self.drain()?;
        let result = f(&mut lock(&self.emitter));
        self.used = self.budget.used();
        self.lines_used = self.budget.lines();
        result
    }

    /// Waits until the writer has written all the work handed on, and notes the budget spent.
    fn drain(&mut self) -> Result<(), Stop> {
        let mut result = Ok(());
        if E::batch_len(&self.batch) > 0 {
            result = self.send();
        }
        while self.away > 0 {
            let r = self.receive();
            if result.is_ok() {
                result = r;
            }
        }
        self.used = self.budget.used();
        self.bounds = 0;
        self.lines_used = self.budget.lines();
        self.lines_away = 0;
        result
    }

    /// Sends the batch being filled and takes an empty one.
    fn send(&mut self) -> Result<(), Stop> {
        let next = match self.spare.pop() {
            Some(b) => b,
            None => {
                // Every batch is away: wait for one (the writer is the slower side here).
                self.receive()?;
                self.spare.pop().unwrap_or_else(E::new_batch)
            }
        };
        let full = std::mem::replace(&mut self.batch, next);
        let Some(to_writer) = &self.to_writer else {
            return Err(writer_gone());
        };
        to_writer.send(full).map_err(|_| writer_gone())?;
        self.away += 1;
        Ok(())
    }

    /// Takes one batch back from the writer, with the error it met.
    fn receive(&mut self) -> Result<(), Stop> {
        let Ok((batch, error)) = self.back.recv() else {
            // The writer is gone (it panicked) with the batches it had: none comes back.
            self.away = 0;
            self.failed = true;
            return Err(writer_gone());
        };
        self.away -= 1;
        self.spare.push(batch);
        match error {
            Some(stop) => {
                self.failed = true;
                Err(stop)
            }
            None => Ok(()),
        }
    }

    /// After work was put in the batch: a full batch goes to the writer (and a batch that came
    /// back tells of an output error early).
    #[inline]
    fn handed(&mut self) -> Result<(), Stop> {
        if E::batch_len(&self.batch) < BATCH {
            return Ok(());
        }
        while let Ok((b, error)) = self.back.try_recv() {
            self.away -= 1;
            self.spare.push(b);
            if let Some(stop) = error {
                self.failed = true;
                return Err(stop);
            }
        }
        self.send()
    }

    /// Whether the budget has room for `lines` lines (0 or 1) of at most `bound` bytes on top of
    /// every line away.
    fn room(&mut self, bound: u32, lines: u64) -> Result<bool, Stop> {
        if let Some(limit) = self.line_limit
            && self.lines_used + self.lines_away + lines > limit
        {
            // Find out how many lines those away made.
            self.drain()?;
            if self.lines_used + lines > limit {
                return Ok(false);
            }
        }
        self.lines_away += lines;
        let Some(limit) = self.limit else {
            return Ok(true);
        };
        let bound = bound as u64;
        if self.used + self.bounds + bound > limit {
            // Find out what the lines away took.
            self.drain()?;
            if self.used + bound > limit {
                return Ok(false);
            }
            self.lines_away += lines;
        }
        self.bounds += bound;
        Ok(true)
    }

    /// What the emitter has to tell the run (its warnings), once the writer has finished.
    pub fn warnings(&mut self) -> Vec<fmsvm_canon::Warning>
    where
        E: Warnings,
    {
        let _ = self.drain();
        lock(&self.emitter).warnings()
    }
}

/// An emitter with warnings for the run.
pub trait Warnings {
    /// What the run should be told about the output.
    fn warnings(&self) -> Vec<fmsvm_canon::Warning>;
}

impl<W: Write> Warnings for ResolvedEmitter<W> {
    fn warnings(&self) -> Vec<fmsvm_canon::Warning> {
        ResolvedEmitter::warnings(self)
    }
}

impl<W: Write> Warnings for crate::literal::LiteralEmitter<W> {
    fn warnings(&self) -> Vec<fmsvm_canon::Warning> {
        crate::literal::LiteralEmitter::warnings(self)
    }
}

/// The calls every pipelined emitter passes to its emitter once the writer has caught up.
macro_rules! caught_up {
    () => {
        fn begin(&mut self, number: Option<u32>, title: &str) -> Result<(), Stop> {
            self.here(|e| e.begin(number, title))
        }

        fn native_cycle(&self, code: Code) -> bool {
            lock(&self.emitter).native_cycle(code)
        }

        fn corners(&self) -> bool {
            lock(&self.emitter).corners()
        }

        /// Bytes of the complete lines the writer has written (all of them after `end`).
        fn written(&self) -> u64 {
            lock(&self.emitter).written()
        }

        fn end(&mut self) -> Result<(), Stop> {
            self.here(|e| e.end())
        }

        /// The output error a batch came back with, which the run's thread had not seen yet.
        fn settle(&mut self) -> Result<(), Stop> {
            self.drain()
        }

        fn message(&mut self, number: u32, text: &str) -> Result<(), Stop> {
            self.here(|e| e.message(number, text))
        }
    };
}

impl<W: Write + Send> Emitter for Pipelined<LiteralEmitter<W>> {
    const CANON: bool = false;

    caught_up!();

    #[inline]
    fn block(&mut self, decoded: &Decoded<'_, '_>, ctx: &Context) -> Result<(), Stop> {
        if !self.failed
            && !ctx.pq_integers
            && !ctx.per_rev
            && let Some(bound) = self.offload.bound(decoded, ctx.inch)
            && self.room(bound, 1)?
        {
            let block = decoded.block;
            let n = block.words().len();
            let b = &mut self.batch;
            b.heads.push((n as u8, block.block_delete, ctx.inch));
            let (words, _) = block.word_slots().as_chunks::<PIECE>();
            let (values, _) = decoded.value_buffer().as_chunks::<PIECE>();
            match n.div_ceil(PIECE) {
                // A block with no words (a comment line): its head says so.
                0 => {}
                // The usual block: one piece.
                1 => {
                    b.letters.push(words[0].map(|w| w.letter));
                    b.values.push(values[0]);
                }
                pieces => {
                    for (w, v) in words.iter().zip(values).take(pieces) {
                        b.letters.push(w.map(|w| w.letter));
                        b.values.push(*v);
                    }
                }
            }
            return self.handed();
        }
        self.here(|e| e.block(decoded, ctx))
    }

    fn canon(&mut self, op: &Canon<'_>, origin: Origin) -> Result<(), Stop> {
        self.here(|e| e.canon(op, origin))
    }
}

impl<W: Write + Send> Emitter for Pipelined<ResolvedEmitter<W>> {
    const CANON: bool = true;

    caught_up!();

    /// A move or feed rate the checks take goes to the writer; anything else runs here once the
    /// writer has caught up, and the checks are worked out again from the emitter after it.
    #[inline]
    fn canon(&mut self, op: &Canon<'_>, origin: Origin) -> Result<(), Stop> {
        if !self.failed
            && let Some(bound) = self.offload.takes(op)
            && self.room(bound, u64::from(bound > 0))?
            && let Some(op) = op.without_text()
        {
            self.batch.push((op, origin));
            return self.handed();
        }
        let mut offload = None;
        let result = self.here(|e| {
            let result = e.canon(op, origin);
            offload = e.offload();
            result
        });
        self.offload = offload.unwrap_or(self.offload).after(op);
        result
    }
}

impl<E: Handing> Drop for Pipelined<E> {
    /// After a stop, the work before it still reaches the output (as the emitter's complete lines
    /// do); then the writer thread ends.
    fn drop(&mut self) {
        let _ = self.drain();
        self.to_writer = None;
    }
}

/// The emitter, also after a panic on the writer thread (which the scope reports when it ends).
fn lock<E>(m: &Mutex<E>) -> MutexGuard<'_, E> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The writer thread is gone (it panicked: the scope reports it).
fn writer_gone() -> Stop {
    Stop::Io(std::io::Error::other("the output thread stopped"))
}

#[cfg(test)]
mod tests;
