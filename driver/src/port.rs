//! The DPRNT/BPRNT port: the printed output, opened on first use, committed with the flat program.
//! POPEN sends DC2 and PCLOS DC4 (macro-b-rules O5, Haas), unless asked not to. Its bytes count against
//! the run's `--max-bytes` and against `--max-print-bytes`.

use std::io::Write;

use fmsvm_block::{LimitKind, OutputBudget, Stop};
use fmsvm_vm::Port;

use crate::input::{Charset, Encode};
use crate::output::{Sink, Target};

/// Where printed records go.
pub struct PrintPort {
    target: Target,
    sink: Option<Sink>,
    buf: Vec<u8>,
    dc_codes: bool,
    charset: Charset,
    budget: OutputBudget,
    max_print: u64,
    /// Bytes printed.
    pub written: u64,
}

impl PrintPort {
    /// A port writing to `target` in `charset`; `max_print` bytes at most (0 = no limit of its own).
    pub fn new(
        target: Target,
        dc_codes: bool,
        charset: Charset,
        budget: OutputBudget,
        max_print: u64,
    ) -> Self {
        PrintPort {
            target,
            sink: None,
            buf: Vec::new(),
            dc_codes,
            charset,
            budget,
            max_print,
            written: 0,
        }
    }

    fn put(&mut self, bytes: &[u8]) -> Result<(), Stop> {
        if self.sink.is_none() {
            self.sink = Some(self.target.open()?);
        }
        let n = bytes.len() as u64;
        if self.max_print != 0 && self.written + n > self.max_print {
            return Err(Stop::Limit {
                kind: LimitKind::PrintBytes,
                limit: self.max_print,
            });
        }
        self.budget.spend(n)?;
        self.buf.extend_from_slice(bytes);
        self.written += n;
        if self.buf.len() > 1 << 16 {
            self.flush_buf()?;
        }
        Ok(())
    }

    fn flush_buf(&mut self) -> std::io::Result<()> {
        if let Some(sink) = &mut self.sink {
            let mut w = Encode::new(sink.writer(), self.charset);
            w.write_all(&self.buf)?;
            w.flush()?;
            self.buf.clear();
        }
        Ok(())
    }

    /// The printed output, ready to commit (None if nothing was printed).
    pub fn finish(mut self) -> std::io::Result<Option<Sink>> {
        self.flush_buf()?;
        Ok(self.sink.take())
    }
}

impl Port for PrintPort {
    fn open(&mut self) -> Result<(), Stop> {
        if self.dc_codes {
            self.put(&[fmsvm_vm::print::DC2])
        } else {
            self.put(&[])
        }
    }
    fn write(&mut self, record: &[u8]) -> Result<(), Stop> {
        self.put(record)
    }
    fn close(&mut self) -> Result<(), Stop> {
        if self.dc_codes {
            self.put(&[fmsvm_vm::print::DC4])
        } else {
            Ok(())
        }
    }
}
