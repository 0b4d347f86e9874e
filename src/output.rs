//! Output files written atomically: a temporary file in the same directory, fsync, rename. A failed run
//! leaves nothing under the final name. Standard output where a closed pipe counts as success.

use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use tempfile::NamedTempFile;

/// Where the flat program goes.
pub enum Sink {
    /// Standard output.
    Stdout(io::Stdout),
    /// A temporary file that becomes `path` on commit.
    File {
        /// The temporary file.
        temp: NamedTempFile,
        /// The final name.
        path: PathBuf,
    },
}

impl Sink {
    /// Opens standard output, or a temporary file beside `path`.
    pub fn open(path: Option<&Path>) -> io::Result<Sink> {
        match path {
            None => Ok(Sink::Stdout(io::stdout())),
            Some(p) => {
                let dir = match p.parent() {
                    Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
                    _ => PathBuf::from("."),
                };
                let name = p
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_else(|| "out".into());
                let temp = tempfile::Builder::new()
                    .prefix(&format!(".{name}."))
                    .suffix(".partial")
                    .tempfile_in(dir)?;
                Ok(Sink::File {
                    temp,
                    path: p.to_path_buf(),
                })
            }
        }
    }

    /// A buffered writer over the sink.
    pub fn writer(&mut self) -> BufWriter<Box<dyn Write + '_>> {
        let w: Box<dyn Write + '_> = match self {
            Sink::Stdout(s) => Box::new(s.lock()),
            Sink::File { temp, .. } => Box::new(temp.as_file_mut()),
        };
        BufWriter::with_capacity(1 << 16, w)
    }

    /// Makes the output final: fsync and rename for a file.
    pub fn commit(self) -> io::Result<()> {
        match self {
            Sink::Stdout(s) => s.lock().flush(),
            Sink::File { temp, path } => {
                temp.as_file().sync_all()?;
                temp.persist(&path).map_err(|e| e.error)?;
                Ok(())
            }
        }
    }
}

impl Sink {
    /// Makes the output final under another name (a partial program kept with --keep-partial).
    pub fn commit_as(self, other: &Path) -> io::Result<()> {
        match self {
            Sink::Stdout(s) => s.lock().flush(),
            Sink::File { temp, .. } => {
                temp.as_file().sync_all()?;
                temp.persist(other).map_err(|e| e.error)?;
                Ok(())
            }
        }
    }
}

/// A writer that shows the bytes written on a terminal spinner (standard error), for long expansions
/// to a file. Updated per buffer flush, not per block.
pub struct Progress<W: Write> {
    inner: W,
    bar: Option<indicatif::ProgressBar>,
}

impl<W: Write> Progress<W> {
    /// Shows progress only when `show` (standard error is a terminal and the output is a file).
    pub fn new(inner: W, show: bool) -> Self {
        let bar = show.then(|| {
            let b = indicatif::ProgressBar::new_spinner();
            b.set_style(
                indicatif::ProgressStyle::with_template(
                    "{spinner} {bytes} written ({bytes_per_sec}) {elapsed}",
                )
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
            );
            b
        });
        Progress { inner, bar }
    }
}

impl<W: Write> Write for Progress<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        if let Some(b) = &self.bar {
            b.inc(n as u64);
        }
        Ok(n)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

impl<W: Write> Drop for Progress<W> {
    fn drop(&mut self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

/// Writes `text` to `path` atomically.
pub fn write_atomic(path: &Path, text: &str) -> io::Result<()> {
    let mut sink = Sink::open(Some(path))?;
    {
        let mut w = sink.writer();
        w.write_all(text.as_bytes())?;
        w.flush()?;
    }
    sink.commit()
}

/// Reads a program: a file, or standard input for `-`.
pub fn read_input(path: &Path) -> io::Result<(String, Vec<u8>)> {
    if path.as_os_str() == "-" {
        let mut buf = Vec::new();
        io::Read::read_to_end(&mut io::stdin(), &mut buf)?;
        Ok(("<stdin>".into(), buf))
    } else {
        Ok((path.display().to_string(), fs::read(path)?))
    }
}
