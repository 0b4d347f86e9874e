//! The writers the expansion writes into: `Counter` (the counting pass) and `DncWriter` (the sending
//! pass), which sends one character at a time at the line's rate and honours XOFF or CTS before each.

use std::io::{self, Write};
use std::time::{Duration, Instant};

use super::link::{Flow, Link, TICK};
use super::resume::Modal;

/// The longest line the resume scanner reads whole (longer ones are cut; only comments are so long).
const MAX_SCANNED_LINE: usize = 64 * 1024;

/// How many characters the writer may send back to back to catch up with the line's clock after the
/// thread slept longer than it asked (each still checked for XOFF first): 4, or the line's
/// characters in `WINDOW` when that is more (`catch_up`).
const CATCH_UP: u32 = 4;

/// The shortest time the thread can keep to: a fast line (above about 40 000 baud) takes several
/// characters in it, which the writer then sends as they fall due, and the serial driver may queue.
const WINDOW: Duration = Duration::from_micros(250);

/// The characters the line takes in `WINDOW` at `char_time` a character (at least 1): how many a
/// serial driver's queue may hold before the writer waits.
fn window(char_time: Duration) -> u32 {
    let n = WINDOW.as_nanos() / char_time.as_nanos().max(1);
    u32::try_from(n).unwrap_or(u32::MAX).max(1)
}

/// How far behind the line's clock the writer may catch up by characters sent back to back.
fn catch_up(char_time: Duration) -> u32 {
    CATCH_UP.max(window(char_time))
}

/// The sending pass holds this many blocks back and checks them against the counting pass before
/// any of them goes out (their bytes and digest at the chunk's end).
pub const CHUNK_LINES: u64 = 256;

/// FNV-1a, to check that the sending pass expanded what the counting pass did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Digest(u64);

impl Default for Digest {
    fn default() -> Self {
        Digest(0xcbf2_9ce4_8422_2325)
    }
}

impl Digest {
    fn byte(&mut self, b: u8) {
        self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
    }
}

/// The counting pass: blocks, bytes, where block N starts, the modal state before it.
pub struct Counter {
    start_at: u64,
    /// Complete lines (blocks).
    pub lines: u64,
    /// Bytes of the program.
    pub bytes: u64,
    /// Bytes of the blocks before `start_at`.
    pub bytes_before: u64,
    /// The first block with a byte above 127 (it cannot go over 7 data bits).
    pub high_byte_block: Option<u64>,
    /// Whether lines end with CR LF.
    pub crlf: bool,
    pub digest: Digest,
    /// The bytes and digest at the end of every `CHUNK_LINES` blocks.
    pub checkpoints: Vec<(u64, Digest)>,
    /// The state after the blocks before `start_at`.
    pub modal: Modal,
    line: Vec<u8>,
}

impl Counter {
    pub fn new(start_at: u64) -> Counter {
        Counter {
            start_at,
            lines: 0,
            bytes: 0,
            bytes_before: 0,
            high_byte_block: None,
            crlf: false,
            digest: Digest::default(),
            checkpoints: Vec::new(),
            modal: Modal::default(),
            line: Vec::new(),
        }
    }
}

impl Write for Counter {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        for &b in buf {
            self.digest.byte(b);
            self.bytes += 1;
            let scanning = self.lines + 1 < self.start_at;
            if scanning {
                self.bytes_before += 1;
            }
            if b >= 0x80 && self.high_byte_block.is_none() {
                self.high_byte_block = Some(self.lines + 1);
            }
            if b == b'\n' {
                if self.lines == 0 {
                    self.crlf = self.line.last() == Some(&b'\r');
                }
                if scanning {
                    self.modal.line(&String::from_utf8_lossy(&self.line));
                }
                self.line.clear();
                self.lines += 1;
                if self.lines.is_multiple_of(CHUNK_LINES) {
                    self.checkpoints.push((self.bytes, self.digest));
                }
            } else if (scanning || self.lines == 0) && self.line.len() < MAX_SCANNED_LINE {
                self.line.push(b);
            }
        }
        Ok(buf.len())
    }
    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// Why the sending stopped before the end.
#[derive(Debug, Clone, PartialEq)]
pub enum Why {
    /// A signal (Ctrl-C is SIGINT).
    Signal(i32),
    /// The link failed or closed.
    Lost(String),
    /// XOFF (or CTS off) held longer than `--hold-timeout`.
    Held { what: &'static str, secs: f64 },
    /// The sending pass expanded other bytes than the counting pass in the chunk of blocks ending
    /// at this block: it was not sent.
    Differs(u64),
}

/// The link's own stop, reported by the session: the driver's `WriterStop`.
pub use fmsvm_driver::run::WriterStop as LinkStop;

/// What the session sends besides the program.
pub struct Plan {
    /// The block the program is sent from (1 = all of it).
    pub start_at: u64,
    /// `%` and the restoring blocks, with their ends of block (sent before block `start_at`).
    pub preamble: Vec<u8>,
    pub leader: u32,
    pub trailer: u32,
    /// The counting pass: blocks and bytes of the whole program.
    pub blocks: u64,
    /// Bytes to send in all (leader, preamble, program from `start_at`, trailer).
    pub to_send: u64,
    /// The counting pass's bytes and digest at the end of every `CHUNK_LINES` blocks.
    pub checkpoints: Vec<(u64, Digest)>,
    pub flow: Flow,
    /// 0 = wait for XON for ever.
    pub hold_timeout: Duration,
    /// Time on the line per character.
    pub char_time: Duration,
}

/// The sending pass: the link, the plan and what has been sent.
pub struct Session {
    link: Link,
    plan: Plan,
    /// Blocks of the program completely passed (written to the link, or skipped before
    /// `start_at`).
    pub done_lines: u64,
    /// Of those, the blocks known to have left: out of the serial driver's queue, or acknowledged
    /// by the device server (a pseudo-terminal tells nothing: there they are the blocks written).
    pub out_lines: u64,
    /// Where each block written but not yet known to have left ends: `sent` then, its number.
    ends: std::collections::VecDeque<(u64, u64)>,
    /// Bytes of the block being sent so far.
    pub line_bytes: u64,
    /// Every byte sent, leader and preamble included.
    pub sent: u64,
    /// Program bytes expanded in this pass (sent or skipped), and their digest.
    pub program_bytes: u64,
    pub digest: Digest,
    /// The bytes expanded and not yet checked against the counting pass (at most a chunk).
    pending: Vec<u8>,
    /// Blocks expanded in this pass.
    pass_lines: u64,
    preamble_sent: bool,
    pub why: Option<Why>,
    due: Option<Instant>,
    started: Instant,
    bar: Option<indicatif::ProgressBar>,
    shown: Instant,
    /// The longest XOFF hold, for the summary.
    pub longest_hold: Duration,
    /// The process's signals: the one that asked the sending to stop, if one did.
    signals: std::sync::Arc<dyn crate::Signals>,
}

/// What `put` may wait for.
#[derive(Clone, Copy)]
enum Mode {
    /// Program bytes: stop at a signal; hold up to `--hold-timeout`.
    Normal,
    /// The trailer after a stop: signals are ignored, a hold is waited out at most this long.
    Closing(Duration),
}

impl Session {
    pub fn new(
        link: Link,
        plan: Plan,
        show: bool,
        signals: std::sync::Arc<dyn crate::Signals>,
    ) -> Session {
        let bar = show.then(|| {
            let b = indicatif::ProgressBar::new(plan.to_send);
            b.set_style(
                indicatif::ProgressStyle::with_template("{bar:24} {msg}")
                    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            b
        });
        let now = Instant::now();
        Session {
            signals,
            link,
            plan,
            done_lines: 0,
            out_lines: 0,
            ends: std::collections::VecDeque::new(),
            line_bytes: 0,
            sent: 0,
            program_bytes: 0,
            digest: Digest::default(),
            pending: Vec::new(),
            pass_lines: 0,
            preamble_sent: false,
            why: None,
            due: None,
            started: now,
            bar,
            shown: now.checked_sub(Duration::from_secs(1)).unwrap_or(now),
            longest_hold: Duration::ZERO,
        }
    }

    /// The link's name in messages.
    pub fn link_name(&self) -> &str {
        &self.link.name
    }

    /// The plan sent.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// Seconds since the session started.
    pub fn elapsed(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    /// The writer for the expansion.
    pub fn writer(&mut self) -> DncWriter<'_> {
        DncWriter { s: self }
    }

    /// Sends the leader (before the expansion starts).
    pub fn leader(&mut self) -> bool {
        for _ in 0..self.plan.leader {
            if self.put(0, Mode::Normal).is_err() {
                return false;
            }
        }
        true
    }

    /// Sends the trailer: after the program (a hold is waited for as for the program), or after a
    /// stop (signals ignored; a hold waited out at most 2 s). Returns whether it was all sent.
    pub fn trailer(&mut self, after_stop: bool) -> bool {
        let mode = if after_stop {
            Mode::Closing(Duration::from_secs(2))
        } else {
            Mode::Normal
        };
        for _ in 0..self.plan.trailer {
            if self.put(0, mode).is_err() {
                return false;
            }
        }
        true
    }

    /// Clears the progress bar.
    pub fn hide(&mut self) {
        if let Some(b) = self.bar.take() {
            b.finish_and_clear();
        }
    }

    /// Waits until everything sent has left, and closes the link.
    pub fn close(mut self) -> io::Result<()> {
        self.hide();
        self.link.close()
    }

    /// The block the program is at: the one being sent.
    pub fn block(&self) -> u64 {
        self.done_lines + 1
    }

    fn fail(&mut self, why: Why) -> io::Error {
        if self.why.is_none() {
            self.why = Some(why);
        }
        io::Error::other(LinkStop)
    }

    /// Sends one character once the line is clear and its time has come.
    fn put(&mut self, b: u8, mode: Mode) -> io::Result<()> {
        if self.why.is_some() && matches!(mode, Mode::Normal) {
            return Err(io::Error::other(LinkStop));
        }
        let ct = self.plan.char_time;
        // The line's rate: at most one character ahead of it (a serial driver's queue included).
        if let Some(d) = self.due {
            let now = Instant::now();
            if d > now {
                std::thread::sleep(d - now);
            }
        }
        if self.link.is_serial() {
            let mut waited = Duration::ZERO;
            while self.link.queued() > window(ct) && waited < Duration::from_secs(5) {
                std::thread::sleep(ct.max(Duration::from_micros(100)));
                waited += ct.max(Duration::from_micros(100));
            }
        }
        // Just before the character: the stop flag, the link, XOFF or CTS.
        let mut held_since: Option<Instant> = None;
        loop {
            if let Mode::Normal = mode
                && let Some(n) = self.signals.requested()
            {
                return Err(self.fail(Why::Signal(n)));
            }
            if let Some(why) = self.link.shared.lost() {
                return Err(self.fail(Why::Lost(why)));
            }
            let (held, what) = match self.plan.flow {
                Flow::Xonxoff => (self.link.shared.held(), "XOFF"),
                Flow::Rtscts => match self.link.clear_to_send() {
                    Ok(cts) => (!cts, "CTS off"),
                    Err(e) => return Err(self.fail(Why::Lost(e.to_string()))),
                },
                Flow::None => (false, ""),
            };
            if !held {
                break;
            }
            let since = *held_since.get_or_insert_with(Instant::now);
            let limit = match mode {
                Mode::Normal => self.plan.hold_timeout,
                Mode::Closing(d) => d,
            };
            if !limit.is_zero() && since.elapsed() >= limit {
                return Err(self.fail(Why::Held {
                    what,
                    secs: limit.as_secs_f64(),
                }));
            }
            self.show(Some(what));
            match self.plan.flow {
                Flow::Xonxoff => {
                    self.link.shared.wait_xon(TICK);
                }
                _ => std::thread::sleep(ct.clamp(Duration::from_micros(200), TICK)),
            }
        }
        if let Some(s) = held_since {
            self.longest_hold = self.longest_hold.max(s.elapsed());
        }
        if let Err(e) = self.link.send(&[b]) {
            return Err(self.fail(Why::Lost(e.to_string())));
        }
        let now = Instant::now();
        // Never ahead of the line's clock. Behind it (the thread slept too long) the next few
        // characters go at once, but at most `catch_up` of them: after a hold or a slow stretch the
        // clock restarts now, with no burst.
        self.due = Some(match self.due {
            Some(d) if d + ct + ct * catch_up(ct) >= now => d + ct,
            _ => now + ct,
        });
        self.sent += 1;
        if now.duration_since(self.shown) >= Duration::from_millis(200) {
            self.show(None);
        }
        Ok(())
    }

    /// Updates the progress bar (blocks, bytes, rate, the time left at the line's rate).
    fn show(&mut self, held: Option<&str>) {
        let Some(bar) = &self.bar else {
            return;
        };
        let now = Instant::now();
        if now.duration_since(self.shown) < Duration::from_millis(200) {
            return;
        }
        self.shown = now;
        let p = &self.plan;
        let secs = self.started.elapsed().as_secs_f64().max(1e-3);
        let left = p.to_send.saturating_sub(self.sent);
        let eta = left as f64 * p.char_time.as_secs_f64();
        let state = match held {
            Some(w) => format!(" · held by {w}"),
            None => String::new(),
        };
        bar.set_position(self.sent);
        bar.set_message(format!(
            "block {}/{} · {}/{} · {}/s · ETA {}{state}",
            self.block().min(p.blocks),
            p.blocks,
            indicatif::HumanBytes(self.sent),
            indicatif::HumanBytes(p.to_send),
            indicatif::HumanBytes((self.sent as f64 / secs) as u64),
            super::duration(eta),
        ));
    }
}

/// What the expansion writes into: skips the blocks before `--start-at` (sending the preamble in their
/// place), and sends the rest character by character.
pub struct DncWriter<'a> {
    s: &'a mut Session,
}

impl Session {
    /// Sends the bytes held back (checked): the blocks before `--start-at` skipped, the preamble
    /// before the first one sent.
    pub fn send_pending(&mut self) -> io::Result<()> {
        let pending = std::mem::take(&mut self.pending);
        for &b in &pending {
            if self.done_lines + 1 < self.plan.start_at {
                if b == b'\n' {
                    self.done_lines += 1;
                    self.out_lines = self.done_lines;
                }
                continue;
            }
            if !self.preamble_sent {
                self.preamble_sent = true;
                for i in 0..self.plan.preamble.len() {
                    let c = self.plan.preamble[i];
                    self.put(c, Mode::Normal)?;
                }
            }
            self.put(b, Mode::Normal)?;
            self.line_bytes += 1;
            if b == b'\n' {
                self.done_lines += 1;
                self.line_bytes = 0;
                self.ends.push_back((self.sent, self.done_lines));
                self.look_at_queue();
            }
        }
        self.pending = pending;
        self.pending.clear();
        Ok(())
    }

    /// Asks the link what has not left yet, and moves `out_lines` on to the last block wholly out.
    /// Returns the bytes still queued (None: the link cannot tell).
    fn look_at_queue(&mut self) -> Option<u64> {
        if !self.link.knows_unsent() {
            self.out_lines = self.done_lines;
            self.ends.clear();
            return None;
        }
        let queued = self.link.unsent()?;
        let out = self.sent.saturating_sub(queued);
        while let Some(&(end, block)) = self.ends.front() {
            if end > out {
                break;
            }
            self.out_lines = block;
            self.ends.pop_front();
        }
        Some(queued)
    }

    /// Waits until everything written has left the driver's queue or been acknowledged by the
    /// device server, while the queue keeps shrinking: gives up (with the bytes still queued) after
    /// `patience` without progress, or at a signal when `signals`. A link that cannot tell (a
    /// pseudo-terminal) is taken as drained.
    pub fn drain(&mut self, patience: Duration, signals: bool) -> Result<(), u64> {
        let mut least = u64::MAX;
        let mut since = Instant::now();
        loop {
            let Some(queued) = self.look_at_queue() else {
                return Ok(());
            };
            if queued == 0 {
                return Ok(());
            }
            if queued < least {
                least = queued;
                since = Instant::now();
            }
            if since.elapsed() >= patience
                || (signals && self.signals.requested().is_some())
                || self.link.shared.lost().is_some()
            {
                return Err(queued);
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Throws away what has not left the link, after a last look at its queue: the blocks counted
    /// out are then all the control gets.
    pub fn discard(&mut self) {
        self.look_at_queue();
        self.link.discard();
    }

    /// Whether the link tells what has left it.
    pub fn knows_out(&self) -> bool {
        self.link.knows_unsent()
    }

    /// The chunk held back is what the counting pass expanded there (its bytes and digest).
    fn chunk_checked(&mut self) -> io::Result<()> {
        let k = (self.pass_lines / CHUNK_LINES) as usize;
        let same =
            k >= 1 && self.plan.checkpoints.get(k - 1) == Some(&(self.program_bytes, self.digest));
        if same {
            Ok(())
        } else {
            Err(self.fail(Why::Differs(self.pass_lines)))
        }
    }
}

impl Write for DncWriter<'_> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let s = &mut *self.s;
        if s.why.is_some() {
            return Err(io::Error::other(LinkStop));
        }
        for &b in buf {
            s.digest.byte(b);
            s.program_bytes += 1;
            s.pending.push(b);
            if b == b'\n' {
                s.pass_lines += 1;
                if s.pass_lines.is_multiple_of(CHUNK_LINES) {
                    // Nothing of a chunk goes out before it is known to be the counted program's.
                    s.chunk_checked()?;
                    s.send_pending()?;
                }
            }
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}
