//! The DPRNT/BPRNT port: a file written atomically (or standard output), opened on first use.
//! POPEN sends DC2 and PCLOS DC4 (macro-b-rules O5, Haas), unless asked not to.

use std::io::{self, Write};
use std::path::PathBuf;

use fmsvm_vm::Port;

use crate::output::Sink;

/// Where printed records go.
pub struct PrintPort {
    path: Option<PathBuf>,
    sink: Option<Sink>,
    buf: Vec<u8>,
    dc_codes: bool,
    /// Bytes written.
    pub written: u64,
}

impl PrintPort {
    /// A port writing to `path` (None = standard output).
    pub fn new(path: Option<PathBuf>, dc_codes: bool) -> Self {
        PrintPort {
            path,
            sink: None,
            buf: Vec::new(),
            dc_codes,
            written: 0,
        }
    }

    fn put(&mut self, bytes: &[u8]) -> io::Result<()> {
        if self.sink.is_none() {
            self.sink = Some(Sink::open(self.path.as_deref())?);
        }
        self.buf.extend_from_slice(bytes);
        self.written += bytes.len() as u64;
        if self.buf.len() > 1 << 16 {
            self.flush_buf()?;
        }
        Ok(())
    }

    fn flush_buf(&mut self) -> io::Result<()> {
        if let Some(sink) = &mut self.sink {
            let mut w = sink.writer();
            w.write_all(&self.buf)?;
            w.flush()?;
            self.buf.clear();
        }
        Ok(())
    }

    /// Makes the printed file final (nothing happens if nothing was printed).
    pub fn commit(mut self) -> io::Result<Option<PathBuf>> {
        self.flush_buf()?;
        match self.sink.take() {
            Some(s) => {
                s.commit()?;
                Ok(self.path.clone())
            }
            None => Ok(None),
        }
    }

    /// Keeps what was printed under `path` (a failed run with --keep-partial).
    pub fn keep_as(mut self, path: PathBuf) -> io::Result<Option<PathBuf>> {
        self.flush_buf()?;
        match self.sink.take() {
            Some(s) => {
                s.commit_as(&path)?;
                Ok(Some(path))
            }
            None => Ok(None),
        }
    }
}

impl Port for PrintPort {
    fn open(&mut self) -> io::Result<()> {
        if self.dc_codes {
            self.put(&[fmsvm_vm::print::DC2])
        } else {
            self.put(&[])
        }
    }
    fn write(&mut self, record: &[u8]) -> io::Result<()> {
        self.put(record)
    }
    fn close(&mut self) -> io::Result<()> {
        if self.dc_codes {
            self.put(&[fmsvm_vm::print::DC4])
        } else {
            Ok(())
        }
    }
}
