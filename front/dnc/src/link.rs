//! The link to the control: a serial port (`serialport`) or a TCP connection to a serial device
//! server, and the flow thread that reads what the control sends back (XON/XOFF, the link closing).

use std::io::{self, Read, Write};
use std::net::{Shutdown, TcpStream, ToSocketAddrs};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;

use serialport::SerialPort;

/// XON (DC1): the control may receive again.
pub const XON: u8 = 0x11;
/// XOFF (DC3): the control's buffer is full; send nothing until XON.
pub const XOFF: u8 = 0x13;

/// How often a blocked reader or writer looks at the stop flags.
pub const TICK: Duration = Duration::from_millis(20);

/// Serial framing: data bits, parity, stop bits (`7E1`, `8N1`, `7E2` …).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Framing {
    pub data: u8,
    pub parity: u8,
    pub stop: u8,
}

impl Framing {
    /// Bits on the line per character: start, data, parity, stop.
    pub fn bits(self) -> u32 {
        1 + u32::from(self.data) + u32::from(self.parity != b'N') + u32::from(self.stop)
    }
}

impl std::fmt::Display for Framing {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}{}{}", self.data, self.parity as char, self.stop)
    }
}

/// `--data`: `7E1`, `8N1`, `7O2` …
pub fn parse_framing(s: &str) -> Result<Framing, String> {
    let b = s.trim().as_bytes();
    let bad = || {
        format!(
            "`{s}` is not a framing: give data bits 7 or 8, parity N E or O, stop bits 1 or 2 (7E1, 8N1, 7E2)"
        )
    };
    if b.len() != 3 {
        return Err(bad());
    }
    let parity = b[1].to_ascii_uppercase();
    match (b[0], parity, b[2]) {
        (b'7' | b'8', b'N' | b'E' | b'O', b'1' | b'2') => Ok(Framing {
            data: b[0] - b'0',
            parity,
            stop: b[2] - b'0',
        }),
        _ => Err(bad()),
    }
}

/// What flow control the writer honours (`--flow`).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// XOFF (DC3) from the control stops the sending within a character; XON (DC1) resumes it.
    Xonxoff,
    /// The control's CTS line (serial ports only).
    Rtscts,
    /// No flow control: send at the line's rate.
    None,
}

/// What the flow thread learnt from the control.
#[derive(Default)]
struct State {
    /// XOFF holds.
    held: bool,
    /// The link failed or closed, and how.
    lost: Option<String>,
}

/// Shared between the writer and the flow thread.
pub struct Shared {
    state: Mutex<State>,
    changed: Condvar,
    /// A quick copy of `state.held`, read before every byte.
    held: AtomicBool,
    /// Set when the session ends: the flow thread returns.
    done: AtomicBool,
}

impl Shared {
    fn new() -> Arc<Shared> {
        Arc::new(Shared {
            state: Mutex::new(State::default()),
            changed: Condvar::new(),
            held: AtomicBool::new(false),
            done: AtomicBool::new(false),
        })
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Whether XOFF holds now.
    pub fn held(&self) -> bool {
        self.held.load(Ordering::Acquire)
    }

    /// How the link was lost, if it was.
    pub fn lost(&self) -> Option<String> {
        self.lock().lost.clone()
    }

    /// Waits at most `d` for XON (or the link lost); returns whether XOFF still holds.
    pub fn wait_xon(&self, d: Duration) -> bool {
        let s = self.lock();
        if !s.held || s.lost.is_some() {
            return s.held;
        }
        let (s, _) = self
            .changed
            .wait_timeout(s, d)
            .unwrap_or_else(|p| p.into_inner());
        s.held
    }

    fn set_held(&self, held: bool) {
        let mut s = self.lock();
        s.held = held;
        self.held.store(held, Ordering::Release);
        self.changed.notify_all();
    }

    fn set_lost(&self, why: String) {
        let mut s = self.lock();
        if s.lost.is_none() {
            s.lost = Some(why);
        }
        // Nothing will lift a hold now.
        s.held = false;
        self.held.store(false, Ordering::Release);
        self.changed.notify_all();
    }
}

/// The open link.
pub struct Link {
    kind: Kind,
    /// The serial port is a pseudo-terminal: what its other end has read cannot be known.
    pty: bool,
    /// What had not left was thrown away (`discard`).
    discarded: bool,
    /// What the messages call it (`/dev/ttyS0`, `10.0.0.5:4001`).
    pub name: String,
    pub shared: Arc<Shared>,
    flow_thread: Option<std::thread::JoinHandle<()>>,
}

enum Kind {
    Serial(Box<dyn SerialPort>),
    Tcp(TcpStream),
}

/// Where to connect (`--port` or `--tcp`).
pub enum Endpoint<'a> {
    Serial {
        path: &'a str,
        baud: u32,
        framing: Framing,
    },
    Tcp {
        address: &'a str,
    },
}

/// How long a write may take before the link counts as lost.
const WRITE_TIMEOUT: Duration = Duration::from_secs(30);
const CONNECT_TIMEOUT: Duration = Duration::from_secs(10);

impl Link {
    /// Opens the port or connects, and starts the flow thread (it watches for XON/XOFF when `flow` is
    /// `xonxoff`, and for the link closing always).
    pub fn open(at: &Endpoint<'_>, flow: Flow) -> Result<Link, String> {
        let shared = Shared::new();
        let (kind, name, reader): (Kind, String, Box<dyn Read + Send>) = match at {
            Endpoint::Serial {
                path,
                baud,
                framing,
            } => {
                use serialport::{DataBits, FlowControl, Parity, StopBits};
                if terminal(path) == Terminal::PtyMaster {
                    return Err(format!(
                        "cannot use {path} as the serial port: it makes a new pseudo-terminal that nothing is connected to (give the other end's /dev/pts/N)"
                    ));
                }
                let port = serialport::new(*path, *baud)
                    .data_bits(if framing.data == 7 {
                        DataBits::Seven
                    } else {
                        DataBits::Eight
                    })
                    .parity(match framing.parity {
                        b'E' => Parity::Even,
                        b'O' => Parity::Odd,
                        _ => Parity::None,
                    })
                    .stop_bits(if framing.stop == 2 {
                        StopBits::Two
                    } else {
                        StopBits::One
                    })
                    // The writer honours XOFF and CTS itself (within a character, with a timeout);
                    // the driver must pass DC1/DC3 through and never hold the output on its own.
                    .flow_control(FlowControl::None)
                    .timeout(WRITE_TIMEOUT)
                    .open()
                    .map_err(|e| format!("cannot open the serial port {path}: {e}"))?;
                let mut reader = port
                    .try_clone()
                    .map_err(|e| format!("cannot open the serial port {path}: {e}"))?;
                reader
                    .set_timeout(TICK)
                    .map_err(|e| format!("cannot open the serial port {path}: {e}"))?;
                let mut port = port;
                // Ready to receive (RTS) and present (DTR): some controls wait for them.
                let _ = port.write_request_to_send(true);
                let _ = port.write_data_terminal_ready(true);
                // RTS/CTS needs a CTS line to read: a port without one (a pseudo-terminal) is
                // refused now, before anything is sent, not at the first character.
                if flow == Flow::Rtscts
                    && let Err(e) = port.read_clear_to_send()
                {
                    return Err(format!(
                        "cannot use --flow rtscts on {path}: its CTS line cannot be read ({e}); use --flow xonxoff"
                    ));
                }
                (Kind::Serial(port), path.to_string(), Box::new(reader))
            }
            Endpoint::Tcp { address } => {
                let fail = |e: &dyn std::fmt::Display| format!("cannot connect to {address}: {e}");
                let addrs: Vec<_> = address.to_socket_addrs().map_err(|e| fail(&e))?.collect();
                let mut last = None;
                let mut stream = None;
                for a in &addrs {
                    match TcpStream::connect_timeout(a, CONNECT_TIMEOUT) {
                        Ok(s) => {
                            stream = Some(s);
                            break;
                        }
                        Err(e) => last = Some(e),
                    }
                }
                let stream = match (stream, last) {
                    (Some(s), _) => s,
                    (None, Some(e)) => return Err(fail(&e)),
                    (None, None) => return Err(fail(&"the name has no address")),
                };
                // Each character leaves at once; the writer paces them.
                let setup = stream
                    .set_nodelay(true)
                    .and_then(|()| stream.set_write_timeout(Some(WRITE_TIMEOUT)))
                    .and_then(|()| stream.try_clone())
                    .and_then(|r| r.set_read_timeout(Some(TICK)).map(|()| r));
                let reader = setup.map_err(|e| fail(&e))?;
                (Kind::Tcp(stream), address.to_string(), Box::new(reader))
            }
        };
        let watch = flow == Flow::Xonxoff;
        let s = Arc::clone(&shared);
        let flow_thread = std::thread::Builder::new()
            .name("dnc-flow".into())
            .spawn(move || watch_incoming(reader, &s, watch))
            .map_err(|e| format!("cannot start the flow thread: {e}"))?;
        let pty =
            matches!(at, Endpoint::Serial { path, .. } if terminal(path) == Terminal::PtySlave);
        Ok(Link {
            kind,
            pty,
            discarded: false,
            name,
            shared,
            flow_thread: Some(flow_thread),
        })
    }

    /// Sends bytes (one character, in practice).
    pub fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        match &mut self.kind {
            Kind::Serial(p) => p.write_all(bytes),
            Kind::Tcp(s) => s.write_all(bytes),
        }
    }

    /// Whether CTS is asserted (serial; a TCP link has no such line).
    pub fn clear_to_send(&mut self) -> io::Result<bool> {
        match &mut self.kind {
            Kind::Serial(p) => p.read_clear_to_send().map_err(io::Error::from),
            Kind::Tcp(_) => Ok(true),
        }
    }

    /// Characters written but still in the driver's output queue (serial), so that the writer keeps
    /// at most one character ahead of the line.
    pub fn queued(&mut self) -> u32 {
        match &mut self.kind {
            Kind::Serial(p) => p.bytes_to_write().unwrap_or(0),
            Kind::Tcp(_) => 0,
        }
    }

    /// Whether the link is a serial port.
    pub fn is_serial(&self) -> bool {
        matches!(self.kind, Kind::Serial(_))
    }

    /// Bytes written that have not yet left: still in a serial driver's output queue, or in a
    /// socket's send queue not yet acknowledged by the device server. None when the link cannot
    /// tell: a pseudo-terminal (its other end's reading is not visible from this end), or a query
    /// that failed.
    pub fn unsent(&mut self) -> Option<u64> {
        match &mut self.kind {
            Kind::Serial(_) if self.pty => None,
            Kind::Serial(p) => p.bytes_to_write().ok().map(u64::from),
            Kind::Tcp(s) => send_queue(s),
        }
    }

    /// Whether the link can tell what has left (`unsent`).
    pub fn knows_unsent(&self) -> bool {
        !self.pty
    }

    /// Throws away what has not left (serial: the driver's output queue; TCP: the connection is
    /// reset, so that the device server never gets the bytes still queued), so that what `unsent`
    /// last said stays true: the control gets nothing after the block named to resume at.
    pub fn discard(&mut self) {
        match &mut self.kind {
            Kind::Serial(p) => {
                let _ = p.clear(serialport::ClearBuffer::Output);
            }
            Kind::Tcp(s) => reset_on_close(s),
        }
        self.discarded = true;
    }

    /// Stops sending and closes the link (serial: tcdrain, after the caller saw the driver's
    /// queue empty; TCP: the write side is shut), then stops the flow thread.
    pub fn close(mut self) -> io::Result<()> {
        let r = match &mut self.kind {
            // A reset connection (`discard`) is closed by dropping it, not shut down in order.
            Kind::Tcp(_) if self.discarded => Ok(()),
            Kind::Serial(p) => p.flush(),
            Kind::Tcp(s) => s.flush().and_then(|()| s.shutdown(Shutdown::Write)),
        };
        self.stop_flow();
        r
    }

    fn stop_flow(&mut self) {
        self.shared.done.store(true, Ordering::Release);
        if let Some(t) = self.flow_thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Link {
    fn drop(&mut self) {
        self.stop_flow();
    }
}

/// What kind of terminal a serial port's path names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Terminal {
    /// `/dev/ptmx`: opening it makes a new pseudo-terminal master with no other end.
    PtyMaster,
    /// A pseudo-terminal's slave (`/dev/pts/N`): a virtual serial port.
    PtySlave,
    /// Anything else (a UART, a USB serial adapter).
    Other,
}

/// The terminal `path` is, by its device number (Linux: the multiplexer is 5,2; slaves are majors
/// 136–143, "Unix98 PTY slaves" in the kernel's devices.txt).
#[cfg(unix)]
fn terminal(path: &str) -> Terminal {
    use std::os::unix::fs::{FileTypeExt, MetadataExt};
    let Ok(m) = std::fs::metadata(path) else {
        return Terminal::Other;
    };
    if !m.file_type().is_char_device() {
        return Terminal::Other;
    }
    let dev = m.rdev();
    let major = ((dev >> 8) & 0xfff) | ((dev >> 32) & !0xfff);
    let minor = (dev & 0xff) | ((dev >> 12) & !0xff);
    match (major, minor) {
        (5, 2) => Terminal::PtyMaster,
        (136..=143, _) => Terminal::PtySlave,
        _ => Terminal::Other,
    }
}

/// Elsewhere (Windows' `COM1`) a port is a serial line.
#[cfg(not(unix))]
fn terminal(_: &str) -> Terminal {
    Terminal::Other
}

/// Bytes in a TCP socket's send queue (written, not yet acknowledged by the other end): Linux's
/// SIOCOUTQ, tcp(7). None elsewhere or when the query fails.
#[cfg(target_os = "linux")]
#[allow(unsafe_code)]
fn send_queue(s: &TcpStream) -> Option<u64> {
    use std::os::fd::AsRawFd;
    let mut n: libc::c_int = 0;
    // SIOCOUTQ is TIOCOUTQ's number (tcp(7): "SIOCOUTQ ... TIOCOUTQ"), the name libc gives it.
    // SAFETY: the ioctl writes one int to the pointer given; `n` is an int that lives through the
    // call, and the descriptor is the open socket `s` borrows.
    let r = unsafe { libc::ioctl(s.as_raw_fd(), libc::TIOCOUTQ, &mut n as *mut libc::c_int) };
    (r == 0).then(|| u64::try_from(n).unwrap_or(0))
}

#[cfg(not(target_os = "linux"))]
fn send_queue(_: &TcpStream) -> Option<u64> {
    None
}

/// Makes closing `s` reset the connection and drop its send queue (SO_LINGER with a zero time,
/// socket(7); Winsock's `linger` the same), where std's `set_linger` is not yet stable.
fn reset_on_close(s: &TcpStream) {
    let _ = socket2::SockRef::from(s).set_linger(Some(Duration::ZERO));
}

/// The flow thread: reads what the control sends; DC3 holds and DC1 releases the writer (when
/// `watch`); an end of file or an error is the link lost.
fn watch_incoming(mut reader: Box<dyn Read + Send>, shared: &Shared, watch: bool) {
    let mut buf = [0u8; 256];
    while !shared.done.load(Ordering::Acquire) {
        match reader.read(&mut buf) {
            Ok(0) => {
                shared.set_lost("the other end closed the connection".into());
                return;
            }
            Ok(n) => {
                if watch {
                    // The last flow character of the burst decides.
                    if let Some(&c) = buf[..n].iter().rev().find(|&&c| c == XON || c == XOFF) {
                        shared.set_held(c == XOFF);
                    }
                }
            }
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::TimedOut
                        | io::ErrorKind::WouldBlock
                        | io::ErrorKind::Interrupted
                ) => {}
            Err(e) => {
                shared.set_lost(e.to_string());
                return;
            }
        }
    }
}
