//! `--verify` in the same pass: the output read back line by line as its emitter writes it, each
//! canonical operation checked against it by a [`Verifier`], with no second expansion.
//!
//! The emitter writes each line as it ends (`ResolvedEmitter::line_by_line`) through an [`Echo`],
//! which keeps a copy of the bytes for the reader ([`Echoed`]). A reader may need more than the
//! line of the operation in hand: the move after it (a dwell of no time the output may leave out
//! is matched by reading on), or a line its emitter writes one move late. So the operations wait in
//! a queue until [`LAG`] later moves have been written, and go to the verifier then, on a thread of
//! its own, in batches; at the end, once the emitter has written everything, the rest. A
//! difference does not stop the run: the first one is kept and the output is judged when the run
//! has ended, as a second expansion would have judged the file. The bytes not yet read back are
//! bounded: the run's thread waits when `POOL` batches are away.

use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;

use fmsvm_block::{Code, Stop};
use fmsvm_canon::decode::Decoded;
use fmsvm_canon::{Canon, Context, Emitter, Origin};

use crate::{Reader, Verifier};

/// Moves written after an operation before it is checked: one for the move a reader reads ahead,
/// one for a line written a move late.
pub const LAG: usize = 2;

/// The bytes written and not yet read back.
type Copy = Arc<Mutex<VecDeque<u8>>>;

/// A writer that keeps a copy of what it writes for [`Echoed`].
pub struct Echo<W: Write> {
    out: W,
    copy: Copy,
}

/// What an [`Echo`] wrote, to be read back; the end of what is written so far reads as the end of
/// the input.
pub struct Echoed(Copy);

/// `out` with a copy of its bytes kept, and the reader of the copy.
pub fn echo<W: Write>(out: W) -> (Echo<W>, Echoed) {
    let copy = Copy::default();
    (
        Echo {
            out,
            copy: Arc::clone(&copy),
        },
        Echoed(copy),
    )
}

impl<W: Write> Write for Echo<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.out.write(buf)?;
        self.copy
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .extend(&buf[..n]);
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }
}

impl Read for Echoed {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let mut copy = self.0.lock().unwrap_or_else(PoisonError::into_inner);
        let (front, _) = copy.as_slices();
        let n = buf.len().min(front.len());
        buf[..n].copy_from_slice(&front[..n]);
        copy.drain(..n);
        Ok(n)
    }
}

/// Operations sent to the checking thread at a time.
const BATCH: usize = 1024;

/// Batches in flight: one being filled, the rest at the checking thread or on their way back.
const POOL: usize = 4;

/// Operations held on the run's thread at most, waiting for moves after them; beyond, the output
/// is not checked in this pass (`ReadBeside::verdict` is None) and a second expansion checks it.
const MAX_HELD: usize = 1 << 16;

/// Operations and where they came from.
type Ops = Vec<(Canon<'static>, Origin)>;

/// What the run's thread tells the checking thread.
enum Message {
    /// Operations whose lines are written: check them.
    Check(Ops),
    /// The output is complete: check the rest, then that nothing more was written.
    End(Ops),
}

/// An emitter and a verifier of what it writes, in one pass: the emitter on the run's thread,
/// the reader and the verifier on a thread of their own.
pub struct ReadBeside<E: Emitter> {
    out: E,
    /// Operations written and not yet sent (a comment is not checked: it has no motion).
    batch: Ops,
    /// Where in `batch` the last `LAG` moves are, the oldest first (`usize::MAX`: none yet): the
    /// operations before the oldest have `LAG` moves written after them.
    last_moves: [usize; LAG],
    /// Batches to the checking thread (None once the output is complete).
    to_check: Option<SyncSender<Message>>,
    /// Emptied batches back.
    back: Receiver<Ops>,
    /// The checking thread, giving its outcome when it ends.
    checker: Option<JoinHandle<Result<u64, String>>>,
    verdict: Option<Result<u64, String>>,
}

impl<E: Emitter> ReadBeside<E> {
    /// `out`, its output read back by `check`'s reader as it is written.
    pub fn new<R: Reader + Send + 'static>(out: E, check: Verifier<R>) -> Self {
        const { assert!(E::CANON, "the verifier checks canonical operations") };
        let (to_check, inbox) = sync_channel::<Message>(POOL);
        let (to_run, back) = sync_channel::<Ops>(POOL);
        let checker = std::thread::spawn(move || checking(check, &inbox, &to_run));
        ReadBeside {
            out,
            batch: Vec::with_capacity(2 * BATCH),
            last_moves: [usize::MAX; LAG],
            to_check: Some(to_check),
            back,
            checker: Some(checker),
            verdict: None,
        }
    }

    /// The emitter.
    pub fn emitter(&self) -> &E {
        &self.out
    }

    /// The outcome, once the run has ended: the moves read back, or the first difference; None
    /// when the output was not checked in this pass (more than `MAX_HELD` operations came between
    /// moves).
    pub fn verdict(&self) -> Option<Result<u64, String>> {
        self.verdict.clone()
    }

    /// Stops checking in this pass: the checking thread ends, nothing more is held.
    fn abandon(&mut self) {
        self.to_check = None;
        self.batch = Vec::new();
        if let Some(checker) = self.checker.take() {
            let _ = checker.join();
        }
    }

    /// Sends the operations with `LAG` moves written after them (all of them with `last`, as the
    /// end), keeping the rest.
    fn send(&mut self, last: bool) {
        let ready = if last {
            self.batch.len()
        } else {
            self.last_moves[0]
        };
        let mut next = self
            .back
            .try_recv()
            .unwrap_or_else(|_| Vec::with_capacity(2 * BATCH));
        next.extend(self.batch.drain(ready..));
        for at in &mut self.last_moves {
            *at = at.saturating_sub(ready);
        }
        let full = std::mem::replace(&mut self.batch, next);
        let Some(to) = &self.to_check else { return };
        let message = if last {
            Message::End(full)
        } else {
            Message::Check(full)
        };
        // A checking thread that has gone has stopped at a difference, which it gives on joining.
        let _ = to.send(message);
    }
}

/// The checking thread: each operation checked by `check` as it comes; after the first
/// difference the rest are only taken. The moves read back, or that difference.
fn checking<R: Reader>(
    mut check: Verifier<R>,
    inbox: &Receiver<Message>,
    to_run: &SyncSender<Ops>,
) -> Result<u64, String> {
    let mut failed = false;
    for message in inbox {
        let (mut ops, end) = match message {
            Message::Check(ops) => (ops, false),
            Message::End(ops) => (ops, true),
        };
        for (op, origin) in &ops {
            if !failed && check.canon(op, *origin).is_err() {
                failed = true;
            }
        }
        if end && !failed && check.end().is_err() {
            failed = true;
        }
        ops.clear();
        let _ = to_run.try_send(ops);
        if end {
            break;
        }
    }
    match (&check.mismatch, failed) {
        (Some(m), _) => Err(m.clone()),
        (None, true) => Err("the output could not be read back".into()),
        (None, false) => Ok(check.moves()),
    }
}

impl<E: Emitter> Emitter for ReadBeside<E> {
    const CANON: bool = true;

    fn begin(&mut self, number: Option<u32>, title: &str) -> Result<(), Stop> {
        self.out.begin(number, title)
    }

    fn block(&mut self, block: &Decoded<'_, '_>, ctx: &Context) -> Result<(), Stop> {
        self.out.block(block, ctx)
    }

    /// The operation written; those with `LAG` moves written after them go to be checked.
    fn canon(&mut self, op: &Canon<'_>, origin: Origin) -> Result<(), Stop> {
        self.out.canon(op, origin)?;
        if let Some(op) = op.without_text()
            && self.to_check.is_some()
        {
            if op.is_motion() {
                self.last_moves.copy_within(1.., 0);
                self.last_moves[LAG - 1] = self.batch.len();
            }
            self.batch.push((op, origin));
            let ready = self.last_moves[0];
            if ready != usize::MAX && ready >= BATCH {
                self.send(false);
            } else if self.batch.len() > MAX_HELD {
                // So many operations without moves: not checked in this pass.
                self.abandon();
            }
        }
        Ok(())
    }

    fn native_cycle(&self, code: Code) -> bool {
        self.out.native_cycle(code)
    }

    fn corners(&self) -> bool {
        self.out.corners()
    }

    fn written(&self) -> u64 {
        self.out.written()
    }

    /// Ends the output, then has the rest checked and waits for the outcome.
    fn end(&mut self) -> Result<(), Stop> {
        self.out.end()?;
        if self.to_check.is_none() {
            return Ok(());
        }
        self.send(true);
        self.to_check = None;
        self.verdict = Some(match self.checker.take().map(JoinHandle::join) {
            Some(Ok(outcome)) => outcome,
            _ => Err("the read-back stopped".into()),
        });
        Ok(())
    }

    fn settle(&mut self) -> Result<(), Stop> {
        self.out.settle()
    }

    fn message(&mut self, number: u32, text: &str) -> Result<(), Stop> {
        self.out.message(number, text)
    }
}

impl<E: Emitter> Drop for ReadBeside<E> {
    /// A run that stopped before its end: the checking thread ends with its inbox.
    fn drop(&mut self) {
        self.to_check = None;
        if let Some(checker) = self.checker.take() {
            let _ = checker.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::words::WordReader;
    use fmsvm_emit::dialect::Dialect;
    use fmsvm_emit::resolved::ResolvedEmitter;

    /// A writer that writes `from` as `to` (an output that differs from what the emitter made).
    struct Altering<W: Write> {
        out: W,
        from: &'static [u8],
        to: &'static [u8],
    }

    impl<W: Write> Write for Altering<W> {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            match buf.windows(self.from.len()).position(|w| w == self.from) {
                Some(i) => {
                    let mut b = buf.to_vec();
                    b.splice(i..i + self.from.len(), self.to.iter().copied());
                    self.out.write_all(&b)?;
                }
                None => self.out.write_all(buf)?,
            }
            Ok(buf.len())
        }
        fn flush(&mut self) -> io::Result<()> {
            self.out.flush()
        }
    }

    fn origin(line: u32) -> Origin {
        Origin {
            line,
            ..Origin::default()
        }
    }

    /// Runs `ops` through a Fanuc resolved emitter whose bytes `alter` may change on their way out,
    /// read back beside it: the verdict and the output.
    fn beside(
        ops: &[Canon<'_>],
        alter: Option<(&'static [u8], &'static [u8])>,
    ) -> (Option<Result<u64, String>>, String) {
        let out = Arc::new(Mutex::new(Vec::new()));
        struct Shared(Arc<Mutex<Vec<u8>>>);
        impl Write for Shared {
            fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
                self.0.lock().unwrap().extend_from_slice(buf);
                Ok(buf.len())
            }
            fn flush(&mut self) -> io::Result<()> {
                Ok(())
            }
        }
        let (echo, echoed) = echo(Shared(Arc::clone(&out)));
        let (from, to) = alter.unwrap_or((b"\x00", b"\x00"));
        let writer = Altering {
            out: echo,
            from,
            to,
        };
        let emitter =
            ResolvedEmitter::new(writer, Dialect::fanuc(), Default::default()).line_by_line();
        let reader = WordReader::new(io::BufReader::new(echoed), Dialect::fanuc());
        let mut b = ReadBeside::new(emitter, Verifier::new(reader, Dialect::fanuc(), 0.001));
        b.begin(Some(1), "").unwrap();
        for (i, op) in ops.iter().enumerate() {
            b.canon(op, origin(i as u32 + 1)).unwrap();
        }
        b.end().unwrap();
        let verdict = b.verdict();
        drop(b);
        let text = String::from_utf8(out.lock().unwrap().clone()).unwrap();
        (verdict, text)
    }

    fn square() -> Vec<Canon<'static>> {
        let p = |x: f64, y: f64, z: f64| [x, y, z, f64::NAN, f64::NAN, f64::NAN];
        vec![
            Canon::Start([f64::NAN; 6]),
            Canon::Rapid(p(0.0, 0.0, 5.0)),
            Canon::FeedRate(100.0),
            Canon::Feed(p(0.0, 0.0, -1.0)),
            // A dwell of no time: the reader reads on to the next move to match it.
            Canon::Dwell(0.0),
            Canon::Feed(p(10.0, 0.0, -1.0)),
            Canon::Feed(p(10.0, 10.0, -1.0)),
            Canon::MCode(8.0),
            Canon::Feed(p(0.0, 10.0, -1.0)),
            Canon::Rapid(p(0.0, 10.0, 5.0)),
        ]
    }

    #[test]
    fn what_is_written_is_read_back_as_it_is_written() {
        let (verdict, text) = beside(&square(), None);
        // Seven blocks read back: the rapid down, four feeds, the dwell (`G4 P0` is written)
        // and the rapid up.
        assert_eq!(verdict, Some(Ok(7)), "{text}");
        assert!(text.contains("X10."), "{text}");
    }

    #[test]
    fn an_output_that_differs_from_what_was_made_fails() {
        // The third move's X written as 11 (the emitter wrote 10): the reader sees 11.
        let (verdict, text) = beside(&square(), Some((b"X10.", b"X11.")));
        let Some(Err(m)) = verdict else {
            panic!("an altered line passed: {verdict:?}\n{text}");
        };
        assert!(m.contains("output line"), "{m}");
        assert!(text.contains("X11."), "{text}");
        // A line taken out: the output ends a move early.
        let (verdict, _) = beside(&square(), Some((b"Z5.\n", b"\n")));
        assert!(matches!(verdict, Some(Err(_))), "{verdict:?}");
    }

    #[test]
    fn operations_without_moves_beyond_the_bound_are_left_to_a_second_expansion() {
        let mut ops = square();
        ops.extend(std::iter::repeat_n(Canon::FeedRate(200.0), MAX_HELD + 2));
        ops.push(Canon::Feed([1.0, 1.0, -1.0, f64::NAN, f64::NAN, f64::NAN]));
        let (verdict, _) = beside(&ops, None);
        assert_eq!(verdict, None);
    }
}
