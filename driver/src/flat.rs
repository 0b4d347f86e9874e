//! NC-only programs straight from the file to the kernel: a program with no macro statement,
//! variable, call or subprogram (a CAM file) is read a line at a time into one reused `Block`, with
//! no tree and no IR — flat memory and the file's own speed, whatever its length.
//!
//! `scan` decides, by reading the file once, whether every line is in the plain subset whose meaning
//! the compiler would give exactly the same way (see `line`); any other line, anywhere, sends the
//! whole program to the compiler, so diagnostics and behaviour never depend on this path. `run` then
//! reads the file again and hands each block to the machine as the VM would.

use std::fs::File;
use std::io::{self, BufRead, BufReader};
use std::path::{Path, PathBuf};

use fmsvm_block::{Block, Flow, Machine, Stop};
use fmsvm_compiler::plain::{Line, line};
use fmsvm_vm::BlockGate;

/// A program that runs without compiling.
#[derive(Clone, Debug)]
pub struct FlatProgram {
    /// The file.
    pub path: PathBuf,
    /// Its O number, if it has one.
    pub number: Option<u32>,
    /// The comments of the O line, as the compiler keeps them (`(NAME)`).
    pub title: String,
    /// The line of the closing `%`, where reading stops (None: the end of the file).
    pub end_line: Option<u32>,
    /// The last line the run reads: the closing `%`'s, or the file's last (a file that ends before
    /// it changed since the scan).
    pub last_line: u32,
}

/// Where a flat run stopped: the stop, the byte range of the block in the file, the blocks run.
pub struct FlatStop {
    /// Why.
    pub stop: Stop,
    /// First byte of the block.
    pub start: u64,
    /// One past its last byte.
    pub end: u64,
    /// Blocks handed to the machine.
    pub blocks: u64,
}

/// The limits a flat run keeps (the VM's, as far as they apply: a flat program has no branches).
#[derive(Clone, Copy, Debug)]
pub struct FlatLimits {
    /// The run's limits: its blocks and wall time go through the VM's `BlockGate`, as the engines'
    /// do (a flat program takes no branch, so the step limit never stops one).
    pub limits: fmsvm_vm::Limits,
    /// The block-delete switch is on: `/` blocks are skipped.
    pub block_delete: bool,
}

/// The file a line at a time: the line's bytes without its end, and the offset where it starts.
struct Lines {
    input: BufReader<File>,
    buf: Vec<u8>,
    offset: u64,
    number: u32,
}

impl Lines {
    fn open(path: &Path) -> io::Result<Lines> {
        Ok(Lines {
            input: BufReader::with_capacity(1 << 18, File::open(path)?),
            buf: Vec::with_capacity(256),
            offset: 0,
            number: 0,
        })
    }

    /// The next line (None at the end), with its start offset.
    fn next(&mut self) -> io::Result<Option<u64>> {
        self.buf.clear();
        let start = self.offset;
        let got = self.input.read_until(b'\n', &mut self.buf)?;
        if got == 0 {
            return Ok(None);
        }
        self.offset += got as u64;
        self.number += 1;
        if self.buf.last() == Some(&b'\n') {
            self.buf.pop();
        }
        Ok(Some(start))
    }
}

/// Reads `path` once: the program when every line is in the plain subset, else None (the compiler
/// takes it). Files that are not ASCII go to the compiler too (their character set is its to read),
/// also after the closing `%`.
pub fn scan(path: &Path) -> io::Result<Option<FlatProgram>> {
    let mut lines = Lines::open(path)?;
    let mut block = Block::new();
    let mut number = None;
    let mut title = String::new();
    // As the lexer counts it: a line with anything but blanks (a comment, `/`, N) before a `%`
    // makes that `%` the closing one.
    let mut seen = false;
    let mut opened = false;
    // Words (or an O line): a program. Comment lines before the first of them are the tape's
    // leader, which the compiler drops when an O line follows.
    let mut program = false;
    let mut leader = false;
    let mut end_line = None;
    while lines.next()?.is_some() {
        if !lines.buf.is_ascii() {
            return Ok(None);
        }
        match line(&lines.buf, &mut block) {
            None => return Ok(None),
            Some(Line::Nothing) => {}
            Some(Line::Percent) => {
                if seen || opened {
                    // The closing tape mark: nothing after it is read (but it is decoded).
                    end_line = Some(lines.number);
                    break;
                }
                opened = true;
            }
            Some(Line::Number(n, (a, b))) => {
                if program || leader {
                    return Ok(None);
                }
                seen = true;
                program = true;
                number = Some(n);
                title = String::from_utf8_lossy(&lines.buf[a..b]).into_owned();
            }
            Some(Line::Sequence) => {
                seen = true;
                program = true;
            }
            Some(Line::Block { .. }) => {
                seen = true;
                if block.is_empty() {
                    leader |= !program;
                } else {
                    program = true;
                }
            }
        }
    }
    let last_line = end_line.unwrap_or(lines.number);
    if end_line.is_some() {
        while lines.next()?.is_some() {
            if !lines.buf.is_ascii() {
                return Ok(None);
            }
        }
    }
    if !program {
        // No program in it (a comment is none): the compiler says so.
        return Ok(None);
    }
    Ok(Some(FlatProgram {
        path: path.to_path_buf(),
        number,
        title,
        end_line,
        last_line,
    }))
}

/// Reading the program failed while it ran (an I/O error, or the file changed since the scan):
/// carried inside the stop's `io::Error` so that it is not reported as an output error.
#[derive(Debug)]
pub struct ReadFailed {
    /// The program's file.
    pub path: PathBuf,
    /// What went wrong.
    pub error: io::Error,
}

impl std::fmt::Display for ReadFailed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "reading {} failed: {}", self.path.display(), self.error)
    }
}

impl std::error::Error for ReadFailed {}

/// The read failure inside an I/O stop, if it is one.
pub fn read_failure(e: &io::Error) -> Option<&ReadFailed> {
    e.get_ref().and_then(|i| i.downcast_ref::<ReadFailed>())
}

/// Runs `program` on `machine`: each block as the VM hands it over; M02/M30 end it.
pub fn run<M: Machine>(
    program: &FlatProgram,
    machine: &mut M,
    limits: &FlatLimits,
) -> Result<fmsvm_vm::Stats, FlatStop> {
    let read_failed = |error: io::Error| {
        let kind = error.kind();
        let path = program.path.clone();
        Stop::Io(io::Error::new(kind, ReadFailed { path, error }))
    };
    let io_stop = |e: io::Error, blocks: u64| FlatStop {
        stop: read_failed(e),
        start: 0,
        end: 0,
        blocks,
    };
    let mut lines = Lines::open(&program.path).map_err(|e| io_stop(e, 0))?;
    let mut gate = BlockGate::new(&limits.limits);
    // One block for every line without a comment (the common case: no 1 KiB block per line);
    // a line with a comment gets a block that borrows its text.
    let mut plain: Block<'static> = Block::new();
    loop {
        let start = match lines.next() {
            Ok(Some(s)) => s,
            Ok(None) if lines.number < program.last_line => {
                let e = io::Error::other("the file ended before the line the program ended on");
                return Err(io_stop(e, gate.blocks));
            }
            Ok(None) => break,
            Err(e) => return Err(io_stop(e, gate.blocks)),
        };
        if Some(lines.number) == program.end_line {
            break;
        }
        let text = std::mem::take(&mut lines.buf);
        let parsed = line(&text, &mut plain);
        let at = |stop: Stop, blocks: u64| FlatStop {
            stop,
            start,
            end: start + text.len() as u64 - u64::from(text.last() == Some(&b'\r')),
            blocks,
        };
        match parsed {
            // The opening `%` (the scan found the closing one).
            Some(Line::Percent) => {}
            Some(Line::Number(..)) => {}
            Some(Line::Block {
                block_delete,
                comment,
            }) => {
                if (block_delete && limits.block_delete) || (plain.is_empty() && comment.is_none())
                {
                    lines.buf = text;
                    continue;
                }
                // The block's first character (files are ASCII: checked by the scan).
                let column = text
                    .iter()
                    .position(|c| !c.is_ascii_whitespace())
                    .map_or(1, |i| u16::try_from(i + 1).unwrap_or(u16::MAX));
                let result = match comment {
                    None => {
                        plain.line = lines.number;
                        plain.column = column;
                        plain.block_delete = block_delete;
                        gate.hand(machine, &plain)
                    }
                    Some((a, b)) => {
                        let mut block = Block::new();
                        for w in plain.words() {
                            block.push(*w);
                        }
                        block.line = lines.number;
                        block.column = column;
                        block.block_delete = block_delete;
                        // ASCII: checked by the scan.
                        block.comment = std::str::from_utf8(&text[a..b]).unwrap_or("");
                        gate.hand(machine, &block)
                    }
                };
                match result {
                    Ok(Flow::End) => break,
                    Ok(_) => {}
                    Err(stop) => return Err(at(stop, gate.blocks)),
                }
            }
            Some(Line::Nothing | Line::Sequence) => {}
            // The scan read every line; a file changed since is an error, not a guess.
            None => {
                return Err(at(
                    read_failed(io::Error::other("the file changed while the program ran")),
                    gate.blocks,
                ));
            }
        }
        lines.buf = text;
    }
    // No branch is taken in a flat program: no step, as the VM counts them.
    Ok(fmsvm_vm::Stats {
        steps: 0,
        blocks: gate.blocks,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use fmsvm_block::{Letter, Word};

    /// Counts the blocks it is handed.
    struct Count(u64);

    impl Machine for Count {
        fn block(&mut self, block: &Block<'_>) -> Result<Flow, Stop> {
            self.0 += 1;
            let end = block
                .words()
                .iter()
                .any(|w| w.letter == Letter::M && w.value == 30.0);
            Ok(if end { Flow::End } else { Flow::Continue })
        }
        fn read_system(&mut self, _: u32) -> Result<f64, Stop> {
            Ok(0.0)
        }
        fn write_system(&mut self, _: u32, _: f64) -> Result<(), Stop> {
            Ok(())
        }
        fn increment(&self, _: Letter) -> f64 {
            0.001
        }
        fn argument(&self, w: &Word) -> f64 {
            w.value
        }
    }

    /// A file cut short between the scan and the run is a read failure of that file (not an
    /// output error), after the blocks read before the cut.
    #[test]
    fn a_program_cut_short_while_it_runs_is_a_read_failure() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("cam.nc");
        let whole = "%\nO1\nG0 X0 Y0\nG1 X1 F100\nG1 X2\nG1 X3\nM30\n%\n";
        std::fs::write(&path, whole).expect("write");
        let program = scan(&path).expect("reads").expect("a flat program");
        std::fs::write(&path, "%\nO1\nG0 X0 Y0\nG1 X1 F100\n").expect("write");
        let limits = FlatLimits {
            limits: fmsvm_vm::Limits {
                max_blocks: 0,
                ..fmsvm_vm::Limits::default()
            },
            block_delete: false,
        };
        let mut machine = Count(0);
        let Err(stop) = run(&program, &mut machine, &limits) else {
            panic!("the run ends at the cut");
        };
        assert_eq!(stop.blocks, 2);
        let Stop::Io(e) = &stop.stop else {
            panic!("an I/O stop: {}", stop.stop);
        };
        let r = read_failure(e).expect("a read failure");
        assert_eq!(r.path, path);
        assert_eq!(
            r.to_string(),
            format!(
                "reading {} failed: the file ended before the line the program ended on",
                path.display()
            )
        );
        // A line no longer plain (a macro statement now): the same, at that line.
        std::fs::write(&path, "%\nO1\nG0 X0 Y0\n#1=2\nG1 X2\nG1 X3\nM30\n%\n").expect("write");
        let Err(stop) = run(&program, &mut Count(0), &limits) else {
            panic!("the run ends at the changed line");
        };
        // After `%`, `O1` and `G0 X0 Y0` (2 + 3 + 9 bytes), one block run.
        assert_eq!((stop.blocks, stop.start), (1, 14));
        let Stop::Io(e) = &stop.stop else {
            panic!("an I/O stop: {}", stop.stop);
        };
        assert!(
            read_failure(e).is_some_and(|r| r
                .to_string()
                .ends_with("failed: the file changed while the program ran")),
            "{e}"
        );
        // The whole file runs to its M30.
        std::fs::write(&path, whole).expect("write");
        let mut machine = Count(0);
        assert!(run(&program, &mut machine, &limits).is_ok());
        assert_eq!(machine.0, 5);
    }
}
