//! Output files: where each output of a run goes, and writing it so that a failed run leaves nothing
//! that looks like a complete program.
//!
//! A regular file (or a name that does not exist yet) is written to a temporary file beside it and
//! renamed over it when every output of the run is complete ([`commit_all`]); a symbolic link is followed,
//! so its target is replaced and the link stays. A character device or a FIFO is opened and written
//! directly (it cannot be replaced); `-` is standard output. A new file gets the usual mode (0666 less the
//! umask); a replaced file keeps its mode (and, where fmsvm may, its owner). Every temporary file is listed
//! in the run's `Temporaries`, which the front end may share with a signal handler that removes them.

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

use tempfile::NamedTempFile;

mod platform;

/// The temporary files of a run's outputs that exist now, and whether they have all been
/// committed: what a signal handler removes (and says) when the process is stopped. Its lock is
/// held while a file is made and while the outputs are renamed, so a handler that takes it sees
/// every file or waits for the commit to end.
#[derive(Debug, Default)]
pub struct Temporaries {
    files: Mutex<Vec<PathBuf>>,
    committed: AtomicBool,
}

impl Temporaries {
    /// The files, locked.
    pub fn lock(&self) -> MutexGuard<'_, Vec<PathBuf>> {
        self.files.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Every output of the run has been committed (a late signal then says so).
    pub fn committed(&self) -> bool {
        self.committed.load(Ordering::SeqCst)
    }
}

/// Where one output goes, decided before anything runs.
#[derive(Clone, Debug)]
pub enum Target {
    /// Standard output (`-`).
    Stdout,
    /// A device or FIFO, written directly.
    Direct {
        /// The name as given.
        path: PathBuf,
    },
    /// A regular file (or a new name), written to a temporary file and renamed.
    File {
        /// The name as given (for messages).
        path: PathBuf,
        /// The file that is replaced: symbolic links resolved.
        resolved: PathBuf,
        /// The permissions and owner to keep, when the file exists.
        existing: Option<platform::Kept>,
        /// Where its temporary file is listed.
        temps: Arc<Temporaries>,
    },
}

impl Target {
    /// Decides how `path` is written: refuses folders, block devices and sockets, and a name whose
    /// folder does not exist.
    pub fn plan(path: &Path, temps: &Arc<Temporaries>) -> Result<Target, String> {
        if path.as_os_str() == "-" {
            return Ok(Target::Stdout);
        }
        let shown = path.display();
        match fs::metadata(path) {
            Ok(m) => match platform::special(&m.file_type()) {
                _ if m.is_dir() => Err(format!("{shown} is a folder, not a file")),
                Some(platform::Special::Stream) => Ok(Target::Direct {
                    path: path.to_path_buf(),
                }),
                Some(platform::Special::Disk) => Err(format!(
                    "{shown} is a block device; fmsvm does not write to disks"
                )),
                Some(platform::Special::Socket) => Err(format!(
                    "{shown} is a socket; give a file, a FIFO or a character device"
                )),
                None => {
                    let resolved = fs::canonicalize(path).map_err(|e| format!("{shown}: {e}"))?;
                    Ok(Target::File {
                        path: path.to_path_buf(),
                        resolved,
                        existing: Some(platform::Kept::of(&m)),
                        temps: Arc::clone(temps),
                    })
                }
            },
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                let target = dangling_target(path);
                let dir = folder_of(&target);
                match fs::metadata(&dir) {
                    Ok(m) if m.is_dir() => Ok(Target::File {
                        path: path.to_path_buf(),
                        // The folder's real name, so that two spellings of one new file compare equal.
                        resolved: match (fs::canonicalize(&dir), target.file_name()) {
                            (Ok(d), Some(n)) => d.join(n),
                            _ => target,
                        },
                        existing: None,
                        temps: Arc::clone(temps),
                    }),
                    Ok(_) => Err(format!("{shown}: {} is not a folder", dir.display())),
                    Err(e) => Err(format!("{shown}: folder {}: {e}", dir.display())),
                }
            }
            Err(e) => Err(format!("{shown}: {e}")),
        }
    }

    /// The name as given.
    pub fn path(&self) -> Option<&Path> {
        match self {
            Target::Stdout => None,
            Target::Direct { path } | Target::File { path, .. } => Some(path),
        }
    }

    /// Opens the output: a temporary file for a regular file, the device or FIFO itself, or stdout.
    pub fn open(&self) -> io::Result<Sink> {
        match self {
            Target::Stdout => Ok(Sink::Stdout(io::stdout())),
            Target::Direct { path } => {
                let file = OpenOptions::new().write(true).open(path)?;
                Ok(Sink::Direct(file))
            }
            Target::File {
                path,
                resolved,
                existing,
                temps,
            } => {
                let dir = folder_of(resolved);
                let name = resolved
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_else(|| "out".into());
                // The registry is held while the file is created, so a signal handler either sees it
                // or runs before it exists.
                let mut reg = temps.lock();
                remove_stale_partials(&dir, &name);
                let prefix = format!(".{name}.{}.", std::process::id());
                let mut builder = tempfile::Builder::new();
                builder.prefix(&prefix).suffix(".partial");
                platform::new_file(&mut builder);
                let temp = builder
                    .tempfile_in(&dir)
                    // tempfile's message ends with its temporary path ("… at path …"); the user
                    // named another.
                    .map_err(|e| {
                        let text = e.to_string();
                        let text = text.split(" at path ").next().unwrap_or(&text).to_string();
                        io::Error::new(
                            e.kind(),
                            format!("{text} (in folder {})", folder_of(path).display()),
                        )
                    })?;
                if let Some(kept) = existing {
                    kept.apply(temp.as_file())?;
                }
                reg.push(temp.path().to_path_buf());
                Ok(Sink::Temp(TempOutput {
                    file: Some(temp),
                    path: resolved.clone(),
                    temps: Arc::clone(temps),
                }))
            }
        }
    }
}

/// The folder a file name is in (`.` for a bare name).
fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Where a name that does not exist would be created: the target of a dangling symbolic link (followed
/// to its end), else the name itself.
fn dangling_target(path: &Path) -> PathBuf {
    let mut p = path.to_path_buf();
    for _ in 0..40 {
        match fs::read_link(&p) {
            Ok(t) => {
                p = if t.is_absolute() {
                    t
                } else {
                    folder_of(&p).join(t)
                }
            }
            Err(_) => break,
        }
    }
    p
}

/// An open output.
pub enum Sink {
    /// Standard output.
    Stdout(io::Stdout),
    /// A device or FIFO.
    Direct(File),
    /// A temporary file that becomes its final name on commit.
    Temp(TempOutput),
}

/// A temporary file beside its final name; deleted (and taken off the registry) if dropped.
pub struct TempOutput {
    file: Option<NamedTempFile>,
    path: PathBuf,
    temps: Arc<Temporaries>,
}

impl TempOutput {
    /// Renames the file to `to`; the caller holds the registry.
    fn persist(&mut self, registry: &mut Vec<PathBuf>, to: &Path) -> io::Result<()> {
        let Some(file) = self.file.take() else {
            return Ok(());
        };
        let from = file.path().to_path_buf();
        // `persist` is rename(2): atomic; on failure the temporary file is deleted as the error drops.
        let result = file.persist(to).map(|_| ()).map_err(|e| e.error);
        registry.retain(|p| p != &from);
        result
    }
}

impl Drop for TempOutput {
    fn drop(&mut self) {
        if let Some(file) = self.file.take() {
            let path = file.path().to_path_buf();
            drop(file);
            self.temps.lock().retain(|p| p != &path);
        }
    }
}

impl Sink {
    /// A buffered writer over the sink.
    pub fn writer(&mut self) -> BufWriter<Box<dyn Write + Send + '_>> {
        let w: Box<dyn Write + Send + '_> = match self {
            // Not locked: the pipelined emitter writes from its own thread.
            Sink::Stdout(s) => Box::new(&*s),
            Sink::Direct(f) => Box::new(f),
            Sink::Temp(t) => match &mut t.file {
                Some(f) => Box::new(f.as_file_mut()),
                None => Box::new(io::sink()),
            },
        };
        BufWriter::with_capacity(1 << 16, w)
    }

    /// Makes what was written durable (standard output is flushed, a file synced).
    fn sync(&mut self) -> io::Result<()> {
        match self {
            Sink::Stdout(s) => s.lock().flush(),
            Sink::Direct(f) => f.flush(),
            Sink::Temp(t) => t.file.as_ref().map_or(Ok(()), |f| f.as_file().sync_all()),
        }
    }

    /// Makes the output final under another name (a partial program kept with --keep-partial).
    pub fn commit_as(mut self, other: &Path) -> io::Result<()> {
        self.sync()?;
        if let Sink::Temp(t) = &mut self {
            let temps = Arc::clone(&t.temps);
            t.persist(&mut temps.lock(), other)?;
        }
        Ok(())
    }
}

/// Removes the temporary files an earlier run into `name` left when it was killed (SIGKILL gives it
/// no chance to): `.NAME.PID.XXXXXX.partial` whose process PID is gone. Only that pattern, for the
/// output this run writes, and only regular files; where the system has no `/proc`, nothing.
fn remove_stale_partials(dir: &Path, name: &str) {
    let proc = Path::new("/proc");
    if !proc.join("self").exists() {
        return;
    }
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    let prefix = format!(".{name}.");
    let own = std::process::id().to_string();
    for e in entries.flatten() {
        let file = e.file_name();
        let Some(file) = file.to_str() else {
            continue;
        };
        let Some(rest) = file
            .strip_prefix(&prefix)
            .and_then(|r| r.strip_suffix(".partial"))
        else {
            continue;
        };
        let Some((pid, random)) = rest.split_once('.') else {
            continue;
        };
        let stale = !pid.is_empty()
            && pid.bytes().all(|b| b.is_ascii_digit())
            && pid != own
            && !random.is_empty()
            && !proc.join(pid).exists()
            && e.file_type().is_ok_and(|t| t.is_file());
        if stale {
            let _ = fs::remove_file(e.path());
        }
    }
}

/// Makes every output of a run final together: all are synced first (a failure there leaves every final
/// name untouched), then renamed. The registry is held throughout, so a signal waits until it is done.
pub fn commit_all(mut sinks: Vec<Sink>) -> io::Result<()> {
    for s in &mut sinks {
        s.sync()?;
    }
    // Every temporary file of a run is listed in the same place.
    let Some(temps) = sinks.iter().find_map(|s| match s {
        Sink::Temp(t) => Some(Arc::clone(&t.temps)),
        _ => None,
    }) else {
        return Ok(());
    };
    let mut reg = temps.lock();
    let mut renamed: Vec<String> = Vec::new();
    for s in &mut sinks {
        if let Sink::Temp(t) = s {
            let to = t.path.clone();
            if let Err(e) = t.persist(&mut reg, &to) {
                let msg = if renamed.is_empty() {
                    e.to_string()
                } else {
                    format!("{e} (already replaced: {})", renamed.join(", "))
                };
                return Err(io::Error::new(e.kind(), msg));
            }
            renamed.push(to.display().to_string());
        }
    }
    temps.committed.store(true, Ordering::SeqCst);
    Ok(())
}

/// Writes `text` to `target` (used for small outputs: the variable store).
pub fn write_text(target: &Target, text: &[u8]) -> io::Result<Sink> {
    let mut sink = target.open()?;
    {
        let mut w = sink.writer();
        w.write_all(text)?;
        w.flush()?;
    }
    Ok(sink)
}

/// Which file an existing name is (links followed): two names with the same identity are one file.
pub fn identity(path: &Path) -> Option<platform::Identity> {
    platform::identity(path)
}
/// What a front end shows of a run as it goes (a spinner on a terminal): told the bytes of each
/// buffer written to the output file (`run`), or the canonical operations a report or a picture
/// has taken (`stats`, `plot`), and when the run ends.
pub trait Progress: Send + Sync {
    /// `bytes` more were written.
    fn written(&self, bytes: u64);
    /// `operations` more canonical operations (moves, dwells, tool changes …) were taken.
    fn operations(&self, operations: u64);
    /// The run has ended (well or not).
    fn done(&self);
    /// Runs `print` with the progress off the screen (a warning said while the run goes).
    fn aside(&self, print: &mut dyn FnMut()) {
        print();
    }
}

/// A writer that tells a `Progress` what goes through it (per buffer flush, not per block).
pub struct Counted<W: Write> {
    inner: W,
    progress: Option<std::sync::Arc<dyn Progress>>,
}

impl<W: Write> Counted<W> {
    /// `inner`, its bytes told to `progress` (None: told to no one).
    pub fn new(inner: W, progress: Option<std::sync::Arc<dyn Progress>>) -> Self {
        Counted { inner, progress }
    }
}

impl<W: Write> Write for Counted<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        if let Some(p) = &self.progress {
            p.written(n as u64);
        }
        Ok(n)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

impl<W: Write> Drop for Counted<W> {
    fn drop(&mut self) {
        if let Some(p) = &self.progress {
            p.done();
        }
    }
}

/// An output named on the command line: its flag, its target.
pub struct Named<'a> {
    /// The flag (`-o`, `--print`, `--dump-vars`).
    pub flag: &'static str,
    /// Where it goes.
    pub target: &'a Target,
}

/// Refuses a run whose outputs would overwrite one of its inputs or each other (device and inode, links
/// followed; names not yet created by their resolved path). `allowed` pairs an output flag with the input
/// flag it may replace (the variable store updated in place).
pub fn check_distinct(
    inputs: &[(&str, PathBuf)],
    outputs: &[Named<'_>],
    allowed: &[(&str, &str)],
) -> Result<(), String> {
    // Each input is looked up once (a --lib folder can hold many files).
    let input_ids: Vec<Option<platform::Identity>> =
        inputs.iter().map(|(_, p)| identity(p)).collect();
    for o in outputs {
        let Some(path) = o.target.path() else {
            continue;
        };
        let Some(id) = identity(path) else {
            continue;
        };
        for ((flag, input), input_id) in inputs.iter().zip(&input_ids) {
            if input_id.as_ref() == Some(&id) && !allowed.contains(&(o.flag, flag)) {
                let what = if path == input.as_path() {
                    String::new()
                } else {
                    format!(" ({} is the same file)", input.display())
                };
                let role = match *flag {
                    "the program" => "the program".to_string(),
                    f => format!("the {f} file"),
                };
                return Err(format!(
                    "{} {} would replace {role} {}{what}; name another output",
                    o.flag,
                    path.display(),
                    input.display()
                ));
            }
        }
    }
    for (i, a) in outputs.iter().enumerate() {
        for b in &outputs[i + 1..] {
            let same = match (a.target, b.target) {
                (Target::File { resolved: x, .. }, Target::File { resolved: y, .. }) => x == y,
                (Target::Direct { path: x }, Target::Direct { path: y }) => {
                    // One terminal or serial line may be named twice (`/dev/null`); one FIFO not.
                    let fifo = fs::metadata(x).is_ok_and(|m| platform::is_fifo(&m.file_type()));
                    identity(x) == identity(y) && fifo
                }
                _ => false,
            };
            if same {
                let (pa, pb) = (a.target.path(), b.target.path());
                let shown = |p: Option<&Path>| p.map_or(String::new(), |p| p.display().to_string());
                return Err(format!(
                    "{} {} and {} {} are the same file; give each output its own name",
                    a.flag,
                    shown(pa),
                    b.flag,
                    shown(pb)
                ));
            }
        }
    }
    Ok(())
}
