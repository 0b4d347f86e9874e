//! The terminal's progress: `run -o`, `stats` and `plot` show a spinner on standard error when it is
//! a terminal (a pseudo-terminal here), and nothing in a pipe or with `-q`.

use std::io::Read;
use std::os::fd::{FromRawFd, OwnedFd};
use std::process::Stdio;

use crate::cli_support::{Dir, bin};

/// Enough moves that the run takes a good part of a second (a debug build).
const LONG: &str = "#1=0\nWHILE[#1LT200000]DO1\nG1 X[#1/1000] Y1 F1000\n#1=#1+1\nEND1\nM30\n";

/// A new pseudo-terminal: its master and slave ends.
fn pty() -> (OwnedFd, OwnedFd) {
    let (mut m, mut s) = (0, 0);
    // SAFETY: openpty writes two descriptors; no name buffer, termios or window size is passed.
    let r = unsafe {
        libc::openpty(
            &mut m,
            &mut s,
            std::ptr::null_mut(),
            std::ptr::null(),
            std::ptr::null(),
        )
    };
    assert_eq!(r, 0, "openpty: {}", std::io::Error::last_os_error());
    // SAFETY: both descriptors were just opened by openpty and are owned here alone.
    unsafe { (OwnedFd::from_raw_fd(m), OwnedFd::from_raw_fd(s)) }
}

/// What `fmsvm args…` writes to its standard error when that is a terminal, and its exit code.
fn on_a_terminal(d: &Dir, args: &[&str]) -> (String, Option<i32>) {
    let (master, slave) = pty();
    let mut child = bin()
        .args(args)
        .current_dir(d.0.path())
        .stdout(Stdio::null())
        .stderr(Stdio::from(slave))
        .spawn()
        .expect("fmsvm starts");
    // The slave's only other holder is the child: reading the master ends when it exits (EIO).
    let mut master = std::fs::File::from(master);
    let mut seen = Vec::new();
    let mut buf = [0u8; 4096];
    while let Ok(n) = master.read(&mut buf) {
        if n == 0 {
            break;
        }
        seen.extend_from_slice(&buf[..n]);
    }
    let status = child.wait().expect("fmsvm ends");
    (String::from_utf8_lossy(&seen).into_owned(), status.code())
}

#[test]
fn a_terminal_shows_the_operations_and_the_bytes_as_the_run_goes() {
    let d = Dir::new();
    d.file("p.nc", LONG);
    let (seen, code) = on_a_terminal(&d, &["stats", "p.nc"]);
    assert_eq!(code, Some(0), "{seen}");
    assert!(seen.contains(" operations, "), "{seen}");
    let (seen, code) = on_a_terminal(&d, &["plot", "p.nc", "-o", "p.svg"]);
    assert_eq!(code, Some(0), "{seen}");
    assert!(seen.contains(" operations, "), "{seen}");
    let (seen, code) = on_a_terminal(&d, &["run", "p.nc", "-o", "flat.nc"]);
    assert_eq!(code, Some(0), "{seen}");
    assert!(seen.contains(" written ("), "{seen}");
    // Quiet: nothing.
    let (seen, code) = on_a_terminal(&d, &["stats", "p.nc", "-q"]);
    assert_eq!(code, Some(0), "{seen}");
    assert_eq!(seen, "");
}

#[test]
fn a_pipe_gets_no_progress() {
    let d = Dir::new();
    d.file("p.nc", LONG);
    for args in [
        &["stats", "p.nc"][..],
        &["run", "p.nc", "-o", "flat.nc"][..],
    ] {
        let o = d.run(args);
        assert!(o.status.success(), "{args:?}");
        assert_eq!(String::from_utf8_lossy(&o.stderr), "", "{args:?}");
    }
}
