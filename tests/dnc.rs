#![cfg(feature = "dnc")]
//! `fmsvm dnc` against peers made by the test, never a real device: a pseudo-terminal pair (the
//! program opens the slave as its serial port) and loopback TCP (a serial device server's stand-in).
//! The peer plays the control: it reads, holds XOFF, releases it, hangs up.

use crate::cli_support;

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use cli_support::{Dir, bin};

const XON: u8 = 0x11;
const XOFF: u8 = 0x13;
const PART: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/dnc/part.nc");

/// The flat program `fmsvm run` writes for `program`.
fn flat(dir: &Dir, program: &Path) -> Vec<u8> {
    let out = dir.path("expected.nc");
    let o = bin()
        .arg("run")
        .arg(program)
        .arg("-o")
        .arg(&out)
        .output()
        .expect("runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::read(out).expect("the flat program")
}

/// The control's side of the link.
trait Peer {
    /// What arrives within `d` (less if the link closes).
    fn read_for(&mut self, d: Duration) -> Vec<u8>;
    fn send(&mut self, byte: u8);
    /// Whether the other side has closed.
    fn closed(&self) -> bool;
}

struct TcpPeer {
    stream: TcpStream,
    eof: bool,
}

impl TcpPeer {
    fn accept(listener: &TcpListener) -> TcpPeer {
        listener.set_nonblocking(false).expect("blocking");
        let (stream, _) = listener.accept().expect("the DNC link connects");
        stream
            .set_read_timeout(Some(Duration::from_millis(5)))
            .expect("timeout");
        TcpPeer { stream, eof: false }
    }
}

impl Peer for TcpPeer {
    fn read_for(&mut self, d: Duration) -> Vec<u8> {
        let end = Instant::now() + d;
        let mut out = Vec::new();
        let mut buf = [0u8; 4096];
        while !self.eof && Instant::now() < end {
            match self.stream.read(&mut buf) {
                Ok(0) => self.eof = true,
                Ok(n) => out.extend_from_slice(&buf[..n]),
                Err(e)
                    if matches!(
                        e.kind(),
                        std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                    ) => {}
                Err(_) => self.eof = true,
            }
        }
        out
    }
    fn send(&mut self, byte: u8) {
        self.stream.write_all(&[byte]).expect("the peer sends");
    }
    fn closed(&self) -> bool {
        self.eof
    }
}

/// The master side of a pseudo-terminal pair; the slave's name is the port `fmsvm dnc` opens. The
/// test keeps the slave open too, so that the master never sees a hang-up between two openers.
struct PtyPeer {
    master: OwnedFd,
    _slave: OwnedFd,
    slave_name: PathBuf,
}

impl PtyPeer {
    fn new() -> PtyPeer {
        let (mut m, mut s) = (0, 0);
        let mut name = [0 as libc::c_char; 128];
        // SAFETY: openpty writes two descriptors and a NUL-terminated name shorter than the buffer
        // (glibc's names are /dev/pts/N); no termios or window size is passed.
        let r = unsafe {
            libc::openpty(
                &mut m,
                &mut s,
                name.as_mut_ptr(),
                std::ptr::null(),
                std::ptr::null(),
            )
        };
        assert_eq!(r, 0, "openpty: {}", std::io::Error::last_os_error());
        // SAFETY: both descriptors were just opened by openpty and are owned here alone.
        let (master, slave) = unsafe { (OwnedFd::from_raw_fd(m), OwnedFd::from_raw_fd(s)) };
        // SAFETY: openpty NUL-terminated the name.
        let slave_name = unsafe { std::ffi::CStr::from_ptr(name.as_ptr()) }
            .to_string_lossy()
            .into_owned();
        PtyPeer {
            master,
            _slave: slave,
            slave_name: PathBuf::from(slave_name),
        }
    }
}

impl Peer for PtyPeer {
    fn read_for(&mut self, d: Duration) -> Vec<u8> {
        let end = Instant::now() + d;
        let mut out = Vec::new();
        let mut buf = [0u8; 4096];
        loop {
            let left = end.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return out;
            }
            let mut p = libc::pollfd {
                fd: self.master.as_raw_fd(),
                events: libc::POLLIN,
                revents: 0,
            };
            // SAFETY: one valid pollfd.
            let r = unsafe { libc::poll(&mut p, 1, left.as_millis().max(1) as libc::c_int) };
            if r <= 0 || p.revents & libc::POLLIN == 0 {
                continue;
            }
            // SAFETY: reads into a buffer of its length from a descriptor owned here.
            let n =
                unsafe { libc::read(self.master.as_raw_fd(), buf.as_mut_ptr().cast(), buf.len()) };
            if n > 0 {
                out.extend_from_slice(&buf[..n as usize]);
            }
        }
    }
    fn send(&mut self, byte: u8) {
        // SAFETY: writes one byte from a live buffer to a descriptor owned here.
        let n = unsafe { libc::write(self.master.as_raw_fd(), (&raw const byte).cast(), 1) };
        assert_eq!(n, 1, "the peer sends");
    }
    fn closed(&self) -> bool {
        false
    }
}

/// `fmsvm dnc PROGRAM ARGS…` with its standard error captured.
fn dnc(program: &Path, args: &[&str]) -> Child {
    bin()
        .arg("dnc")
        .arg(program)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("fmsvm dnc starts")
}

/// Reads until `n` bytes have arrived (or panics after 20 s).
fn read_at_least(peer: &mut dyn Peer, got: &mut Vec<u8>, n: usize) {
    let end = Instant::now() + Duration::from_secs(20);
    while got.len() < n {
        assert!(Instant::now() < end, "only {} bytes in 20 s", got.len());
        assert!(!peer.closed(), "the link closed after {} bytes", got.len());
        got.extend(peer.read_for(Duration::from_millis(20)));
    }
}

/// Reads until the child has ended and nothing more arrives; returns its exit code and standard error.
fn read_to_end(peer: &mut dyn Peer, got: &mut Vec<u8>, child: &mut Child) -> (Option<i32>, String) {
    let end = Instant::now() + Duration::from_secs(60);
    let status = loop {
        assert!(Instant::now() < end, "fmsvm dnc did not end");
        got.extend(peer.read_for(Duration::from_millis(20)));
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
    };
    loop {
        let more = peer.read_for(Duration::from_millis(150));
        if more.is_empty() {
            break;
        }
        got.extend(more);
    }
    let mut err = String::new();
    if let Some(mut e) = child.stderr.take() {
        let _ = e.read_to_string(&mut err);
    }
    (status.code(), err)
}

/// The control's side of the XOFF test: read a part, hold XOFF, check that nothing comes (but what
/// was already on its way: at most a few characters), release, read the rest.
/// The line rate of the XOFF tests. The bound is in characters (at most 8 after the XOFF); how many
/// leave before fmsvm's flow thread is scheduled to read the XOFF depends on the rate: at 9600 baud
/// (about 1 ms a character) 8 characters give the thread 8 ms, which a loaded two-core CI runner
/// needs (at 38400 baud, 2 ms, it failed about one run in five under load).
const XOFF_BAUD: &str = "9600";

fn xoff_mid_stream(peer: &mut dyn Peer, child: &mut Child, expected: &[u8]) {
    let mut got = Vec::new();
    read_at_least(peer, &mut got, 800);
    peer.send(XOFF);
    let on_the_way = peer.read_for(Duration::from_millis(100));
    assert!(
        on_the_way.len() <= 8,
        "{} bytes arrived after XOFF",
        on_the_way.len()
    );
    got.extend(on_the_way);
    let held = peer.read_for(Duration::from_millis(300));
    assert!(
        held.is_empty(),
        "{} bytes arrived while XOFF held",
        held.len()
    );
    assert!(got.len() < expected.len(), "all sent before the XOFF");
    peer.send(XON);
    let (code, err) = read_to_end(peer, &mut got, child);
    assert_eq!(code, Some(0), "{err}");
    let mut want = vec![0u8; 20];
    want.extend_from_slice(expected);
    want.extend_from_slice(&[0u8; 20]);
    assert!(
        got == want,
        "{} bytes arrived, {} expected; first difference at {:?}\n{err}",
        got.len(),
        want.len(),
        got.iter().zip(&want).position(|(a, b)| a != b)
    );
    assert!(err.contains("sent ") && err.contains("253 blocks"), "{err}");
}

#[test]
fn tcp_xoff_mid_stream_every_byte_once_in_order() {
    let dir = Dir::new();
    let expected = flat(&dir, Path::new(PART));
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind");
    let at = listener.local_addr().expect("address").to_string();
    let mut child = dnc(
        Path::new(PART),
        &[
            "--tcp",
            &at,
            "--baud",
            XOFF_BAUD,
            "--leader",
            "20",
            "--trailer",
            "20",
        ],
    );
    let mut peer = TcpPeer::accept(&listener);
    xoff_mid_stream(&mut peer, &mut child, &expected);
}

#[test]
fn pty_xoff_mid_stream_every_byte_once_in_order() {
    let dir = Dir::new();
    let expected = flat(&dir, Path::new(PART));
    let mut peer = PtyPeer::new();
    let port = peer.slave_name.display().to_string();
    let mut child = dnc(
        Path::new(PART),
        &[
            "--port",
            &port,
            "--baud",
            XOFF_BAUD,
            "--data",
            "7E1",
            "--leader",
            "20",
            "--trailer",
            "20",
        ],
    );
    xoff_mid_stream(&mut peer, &mut child, &expected);
}

#[test]
fn start_at_sends_the_restoring_blocks_then_exactly_the_blocks_from_n() {
    let dir = Dir::new();
    let expected = flat(&dir, Path::new(PART));
    let text = String::from_utf8(expected).expect("ASCII");
    let lines: Vec<&str> = text.split_inclusive('\n').collect();
    assert_eq!(lines[97], "G1 X22. Y40. F600.\n", "the program changed");
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind");
    let at = listener.local_addr().expect("address").to_string();
    let mut child = dnc(
        Path::new(PART),
        &[
            "--tcp",
            &at,
            "--baud",
            "115200",
            "--leader",
            "5",
            "--trailer",
            "5",
            "--start-at",
            "98",
        ],
    );
    let mut peer = TcpPeer::accept(&listener);
    let mut got = Vec::new();
    let (code, err) = read_to_end(&mut peer, &mut got, &mut child);
    assert_eq!(code, Some(0), "{err}");
    let mut want = "\0\0\0\0\0%\nG17 G21 G90 G94 G54\nT1\nS1200 M3\nM8\nG0 X22. Y0.\nG0 G43 H1 Z-1.\nG1 F150.\n".to_string();
    want.extend(lines[97..].iter().copied());
    want.push_str("\0\0\0\0\0");
    assert_eq!(String::from_utf8_lossy(&got), want);
    assert!(err.contains("resuming at block 98 of 253"), "{err}");
    assert!(err.contains("the tool in the spindle must be T1"), "{err}");
    assert!(err.contains("156 blocks (98 to 253)"), "{err}");
}

#[test]
fn ctrl_c_stops_between_characters_sends_the_trailer_and_names_the_block() {
    let dir = Dir::new();
    let expected = flat(&dir, Path::new(PART));
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind");
    let at = listener.local_addr().expect("address").to_string();
    // 2400 baud: 240 characters a second, so the program is far from sent when the signal comes.
    let mut child = dnc(
        Path::new(PART),
        &[
            "--tcp",
            &at,
            "--baud",
            "2400",
            "--leader",
            "10",
            "--trailer",
            "30",
        ],
    );
    let mut peer = TcpPeer::accept(&listener);
    let mut got = Vec::new();
    read_at_least(&mut peer, &mut got, 300);
    // SAFETY: signals the child this test started and has not waited for.
    let r = unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGINT) };
    assert_eq!(r, 0);
    let (code, err) = read_to_end(&mut peer, &mut got, &mut child);
    assert_eq!(code, Some(130), "{err}");
    assert!(peer.closed(), "the link is closed");
    // Leader, a prefix of the program, trailer.
    assert!(got.starts_with(&[0; 10]), "the leader");
    assert!(
        got.ends_with(&[0; 30]),
        "the trailer: {:?}",
        &got[got.len() - 40..]
    );
    let body = &got[10..got.len() - 30];
    assert!(!body.is_empty() && body.len() < expected.len() / 2);
    assert!(expected.starts_with(body), "what was sent is not a prefix");
    let complete = body.iter().filter(|&&b| b == b'\n').count();
    let resume = format!("resume with --start-at {}", complete + 1);
    assert!(
        err.contains("stopped by SIGINT (interrupt) while sending") && err.contains(&resume),
        "{err}"
    );
    assert!(err.contains(&format!("{complete} blocks")), "{err}");
}

#[test]
fn an_xoff_held_past_the_timeout_is_exit_12() {
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind");
    let at = listener.local_addr().expect("address").to_string();
    let mut child = dnc(
        Path::new(PART),
        &["--tcp", &at, "--baud", "9600", "--hold-timeout", "0.5"],
    );
    let mut peer = TcpPeer::accept(&listener);
    let mut got = Vec::new();
    read_at_least(&mut peer, &mut got, 100);
    peer.send(XOFF);
    let (code, err) = read_to_end(&mut peer, &mut got, &mut child);
    assert_eq!(code, Some(12), "{err}");
    assert!(
        err.contains("the control held XOFF for 0.5 s (--hold-timeout)"),
        "{err}"
    );
    assert!(err.contains("resume with --start-at"), "{err}");
}

#[test]
fn a_link_lost_mid_stream_is_exit_11() {
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind");
    let at = listener.local_addr().expect("address").to_string();
    let mut child = dnc(Path::new(PART), &["--tcp", &at, "--baud", "9600"]);
    let mut peer = TcpPeer::accept(&listener);
    let mut got = Vec::new();
    read_at_least(&mut peer, &mut got, 200);
    drop(peer);
    let status = child.wait().expect("ends");
    let mut err = String::new();
    if let Some(mut e) = child.stderr.take() {
        let _ = e.read_to_string(&mut err);
    }
    assert_eq!(status.code(), Some(11), "{err}");
    assert!(
        err.contains("was lost") && err.contains("resume with --start-at"),
        "{err}"
    );
}

#[test]
fn a_link_that_cannot_open_sends_nothing_exit_10() {
    let o = bin()
        .args(["dnc", PART, "--port", "/nonexistent/ttyS9"])
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(10), "{err}");
    assert!(
        err.contains("error: cannot open the serial port /nonexistent/ttyS9")
            && err.contains("nothing was sent"),
        "{err}"
    );
    // A port nobody listens on.
    let free = TcpListener::bind("127.0.0.1:0").expect("bind");
    let at = free.local_addr().expect("address").to_string();
    drop(free);
    let o = bin()
        .args(["dnc", PART, "--tcp", &at])
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(10), "{err}");
    assert!(err.contains(&format!("cannot connect to {at}")), "{err}");
}

#[test]
fn refusals_before_anything_is_sent() {
    let dir = Dir::new();
    let run = |args: &[&str]| {
        let o = Command::new(env!("CARGO_BIN_EXE_fmsvm"))
            .arg("dnc")
            .args(args)
            .current_dir(dir.0.path())
            .output()
            .expect("runs");
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    // None of these reaches the link (the port does not exist: it would be exit 10).
    let port = ["--port", "/nonexistent/ttyS9"];
    let (code, err) = run(&[&[PART, "--start-at", "254"][..], &port].concat());
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("the flat program has 253 blocks"), "{err}");
    let cycle = dir.file(
        "cycle.nc",
        "G90 G0 Z10.\nG81 X1. Y1. Z-5. R1. F100\nX2.\nG80\n",
    );
    let cycle = cycle.to_str().expect("path");
    // Block 1 is the tape start `%`; the G81 is block 3, the X2. under it block 4.
    let (code, err) = run(&[&[cycle, "--start-at", "4"][..], &port].concat());
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("canned cycle G81 is in force at block 4 (since block 3)"),
        "{err}"
    );
    let alarm = dir.file("alarm.nc", "G0 X1\n#3000=1(BROKEN)\n");
    let alarm = alarm.to_str().expect("path");
    let (code, err) = run(&[&[alarm][..], &port].concat());
    assert_eq!(code, Some(4), "{err}");
    assert!(err.contains("nothing was sent to the control"), "{err}");
    let (code, err) = run(&[PART, "--tcp", "127.0.0.1:9", "--flow", "rtscts"]);
    assert_eq!(code, Some(2), "{err}");
    let (code, err) = run(&[&[PART, "-o", "x.nc"][..], &port].concat());
    assert_eq!(code, Some(2), "{err}");
    assert!(!dir.path("x.nc").exists());
    let cyr = dir.file("cyr.nc", "G0 X1 (ФРЕЗА)\n");
    let cyr = cyr.to_str().expect("path");
    let (code, err) = run(&[&[cyr, "--comments", "--data", "7E1"][..], &port].concat());
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("sends 7 bits"), "{err}");
}

#[test]
fn a_program_that_changes_between_the_passes_stops_before_the_changed_blocks_go_out() {
    // The program file is edited once the counting pass is done, while the leader goes out and
    // before the sending pass reads it (X1. becomes X9. at block 1000, same length): the sending
    // pass checks each chunk of 256 blocks against the counting pass before sending any of it, so
    // no X9. reaches the control.
    let d = Dir::new();
    let lines: Vec<String> = (0..2000).map(|k| format!("N{:04} G0 X1.", k + 1)).collect();
    let text = lines.join("\n") + "\nM30\n";
    let program = d.file("p.nc", &text);
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind");
    let at = listener.local_addr().expect("address").to_string();
    let mut child = dnc(
        &program,
        &["--tcp", &at, "--baud", "115200", "--leader", "20000"],
    );
    let mut peer = TcpPeer::accept(&listener);
    let edited = text.replacen("N1000 G0 X1.", "N1000 G0 X9.", 1);
    std::fs::write(&program, edited).expect("edit");
    let mut got = Vec::new();
    let (code, err) = read_to_end(&mut peer, &mut got, &mut child);
    let sent = String::from_utf8_lossy(&got);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("the sending pass expanded other bytes than the counting pass by block"),
        "{err}"
    );
    assert!(!sent.contains("X9."), "an edited block went out");
    // Three chunks of 256 output lines went out whole: `%` and N1 to N767.
    let lines: Vec<&str> = sent.lines().collect();
    assert!(
        lines.contains(&"N767 G0 X1.") && !lines.iter().any(|l| l.starts_with("N768 ")),
        "the chunks before the edit went out, no more"
    );
}

#[test]
#[cfg(target_os = "linux")]
fn rts_cts_on_a_port_without_a_cts_line_is_refused_before_anything_is_sent() {
    // A pseudo-terminal has no modem lines: RTS/CTS cannot be read there. That is known when the
    // port opens (exit 10, nothing sent), not at the first character (exit 11).
    let mut peer = PtyPeer::new();
    let port = peer.slave_name.display().to_string();
    let mut child = dnc(Path::new(PART), &["--port", &port, "--flow", "rtscts"]);
    let mut got = Vec::new();
    let (code, err) = read_to_end(&mut peer, &mut got, &mut child);
    // Linux's pseudo-terminals do not answer TIOCMGET (the tty layer's pty driver has no modem
    // lines), so the refusal is certain here.
    assert_eq!(code, Some(10), "{err}");
    assert!(err.contains("cannot use --flow rtscts on"), "{err}");
    assert!(got.is_empty(), "{} bytes sent", got.len());
}

/// Nothing counts as sent before the link has passed it on. A device server that stops taking
/// data (its receive buffer of 4 KiB full, never read) leaves the rest of the program in fmsvm's
/// socket queue: `dnc` waits for the queue while it shrinks (`--hold-timeout 1` here), then resets
/// the connection so the queued bytes never arrive, and names as the block to resume at the first
/// one the server has not acknowledged whole. What the server holds is checked against that name:
/// every block before it, and no block after it.
#[test]
fn a_peer_that_stops_reading_is_not_told_sent_and_the_resume_block_is_the_first_it_lacks() {
    use std::os::fd::AsRawFd;
    let dir = Dir::new();
    let program = dir.file(
        "long.nc",
        "O1\n#1=0\nWHILE[#1LT900]DO1\nG1 X#1 Y[#1*2] F100\n#1=#1+1\nEND1\nM30\n",
    );
    let listener = TcpListener::bind("127.0.0.1:0").expect("bind");
    let small: libc::c_int = 4096;
    // SAFETY: SO_RCVBUF reads one int from the pointer given with its size; the accepted socket
    // inherits the listener's buffer size.
    let r = unsafe {
        libc::setsockopt(
            listener.as_raw_fd(),
            libc::SOL_SOCKET,
            libc::SO_RCVBUF,
            (&small as *const libc::c_int).cast(),
            std::mem::size_of::<libc::c_int>() as libc::socklen_t,
        )
    };
    assert_eq!(r, 0, "SO_RCVBUF");
    let at = listener.local_addr().expect("address").to_string();
    let mut child = dnc(
        &program,
        &[
            "--tcp",
            &at,
            "--baud",
            "115200",
            "--flow",
            "none",
            "--hold-timeout",
            "1",
        ],
    );
    let (mut stream, _) = listener.accept().expect("the DNC link connects");
    let status = child.wait().expect("fmsvm dnc ends");
    let mut err = String::new();
    if let Some(mut e) = child.stderr.take() {
        let _ = e.read_to_string(&mut err);
    }
    assert_eq!(status.code(), Some(11), "{err}");
    assert!(
        err.contains("took nothing more for 1.0 s at the end"),
        "{err}"
    );
    assert!(!err.contains("sent long.nc"), "{err}");
    let resume: u64 = err
        .split("resume with --start-at ")
        .nth(1)
        .and_then(|t| t.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no resume block in: {err}"));
    // What the server got before the reset.
    stream
        .set_read_timeout(Some(Duration::from_millis(200)))
        .expect("timeout");
    let mut got = Vec::new();
    let mut buf = [0u8; 4096];
    while let Ok(n) = stream.read(&mut buf) {
        if n == 0 {
            break;
        }
        got.extend_from_slice(&buf[..n]);
    }
    let whole = got.iter().filter(|&&b| b == b'\n').count() as u64;
    assert!(resume > 1 && resume < 900, "{err}");
    assert_eq!(
        whole,
        resume - 1,
        "the server holds {whole} whole blocks\n{err}"
    );
}

/// `/dev/ptmx` makes a new pseudo-terminal that nothing is connected to: refused when it opens.
#[test]
fn the_pseudo_terminal_multiplexer_is_no_serial_port() {
    if !Path::new("/dev/ptmx").exists() {
        return;
    }
    let o = bin()
        .args(["dnc", PART, "--port", "/dev/ptmx"])
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(10), "{err}");
    assert!(
        err.contains("it makes a new pseudo-terminal that nothing is connected to")
            && err.contains("nothing was sent"),
        "{err}"
    );
}
