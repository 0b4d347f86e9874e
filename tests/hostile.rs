//! Hostile file systems and input: nothing the user did not name as output is replaced, outputs are
//! committed together or not at all, signals leave nothing behind, every output and input is bounded,
//! option values are checked, text in the shops' character sets is read and written back.
//!
//! Every test works inside its own temporary folder: FIFOs and files of its own, a tmpfs of its own (in a
//! private mount namespace, where the system allows one) or a file-size limit for a full disk; never a
//! real device node.

use std::os::unix::fs::{FileTypeExt, PermissionsExt};
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::cli_support;

use cli_support::{Dir, bin, run, stderr};

const SMALL: &str = "G0 X1\nM30\n";
const SMALL_OUT: &str = "%\nG0 X1.\nM30\n%\n";
/// An endless loop that writes a block per turn.
const ENDLESS: &str = "#1=0\nWHILE[1 EQ 1]DO1\nG1 X[#1 MOD 1000]\n#1=#1+1\nEND1\n";

#[test]
fn an_output_that_is_an_input_or_another_output_is_refused_before_anything_runs() {
    let d = Dir::new();
    d.file("a.nc", SMALL);
    d.file("store.txt", "#500=1\n");
    std::fs::create_dir(d.path("lib")).unwrap();
    d.file("lib/O9010.nc", "O9010\nG0 X2\nM99\n");
    std::os::unix::fs::symlink("a.nc", d.path("link.nc")).unwrap();
    let cases: &[&[&str]] = &[
        &["run", "a.nc", "-o", "a.nc"],
        &["run", "a.nc", "-o", "./a.nc"],
        &["run", "a.nc", "-o", "link.nc"],
        &["run", "a.nc", "--print", "a.nc"],
        &["run", "a.nc", "--dump-vars", "a.nc"],
        &["run", "a.nc", "--vars", "store.txt", "-o", "store.txt"],
        &["run", "a.nc", "--lib", "lib", "-o", "lib/O9010.nc"],
        &["run", "a.nc", "-o", "x.nc", "--print", "x.nc"],
        &["run", "a.nc", "-o", "x.nc", "--print", "./x.nc"],
        &["run", "a.nc", "-o", "x.nc", "--dump-vars", "x.nc"],
    ];
    for args in cases {
        let o = run(args, d.0.path());
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains(" would replace the ") || e.contains("are the same file"),
            "{args:?}: {e}"
        );
    }
    // Nothing was touched.
    assert_eq!(d.read("a.nc"), SMALL);
    assert_eq!(d.read("store.txt"), "#500=1\n");
    assert_eq!(d.read("lib/O9010.nc"), "O9010\nG0 X2\nM99\n");
    assert_eq!(
        d.names(),
        ["a.nc", "lib", "link.nc", "store.txt"].map(String::from)
    );
    // The variable store may be updated in place.
    d.file("p.nc", "#500=#500+1\nG0 X#500\n");
    let o = run(
        &[
            "run",
            "p.nc",
            "--vars",
            "store.txt",
            "--dump-vars",
            "store.txt",
        ],
        d.0.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(d.read("store.txt").contains("\n#500=2\n"));
}

#[test]
fn a_fifo_is_written_directly_and_stays_a_fifo() {
    let d = Dir::new();
    d.file("a.nc", SMALL);
    let fifo = d.fifo("pipe");
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).expect("read fifo"))
    };
    let o = run(&["run", "a.nc", "-o", "pipe"], d.0.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(reader.join().unwrap(), SMALL_OUT);
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    assert_eq!(d.names(), ["a.nc", "pipe"].map(String::from));
}

#[test]
fn dash_is_standard_output_and_a_folder_or_socket_is_refused() {
    let d = Dir::new();
    d.file("a.nc", SMALL);
    let o = run(&["run", "a.nc", "-o", "-"], d.0.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(String::from_utf8_lossy(&o.stdout), SMALL_OUT);
    assert_eq!(d.names(), ["a.nc"].map(String::from));
    std::fs::create_dir(d.path("folder")).unwrap();
    let o = run(&["run", "a.nc", "-o", "folder"], d.0.path());
    assert_eq!(o.status.code(), Some(6));
    assert!(stderr(&o).contains("folder is a folder"), "{}", stderr(&o));
    let _sock = std::os::unix::net::UnixListener::bind(d.path("sock")).unwrap();
    let o = run(&["run", "a.nc", "-o", "sock"], d.0.path());
    assert_eq!(o.status.code(), Some(6));
    assert!(stderr(&o).contains("is a socket"), "{}", stderr(&o));
}

#[test]
fn a_symbolic_link_is_followed_and_stays() {
    let d = Dir::new();
    d.file("a.nc", SMALL);
    std::fs::create_dir(d.path("real")).unwrap();
    d.file("real/target.nc", "old\n");
    std::os::unix::fs::symlink("real/target.nc", d.path("link.nc")).unwrap();
    let o = run(&["run", "a.nc", "-o", "link.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        std::fs::symlink_metadata(d.path("link.nc"))
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(d.read("real/target.nc"), SMALL_OUT);
    // A dangling link: its target is created.
    std::os::unix::fs::symlink("real/new.nc", d.path("dangling.nc")).unwrap();
    let o = run(&["run", "a.nc", "-o", "dangling.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(d.read("real/new.nc"), SMALL_OUT);
    assert!(
        std::fs::symlink_metadata(d.path("dangling.nc"))
            .unwrap()
            .file_type()
            .is_symlink()
    );
}

fn mode(p: &Path) -> u32 {
    std::fs::metadata(p).unwrap().permissions().mode() & 0o7777
}

#[test]
fn new_files_get_the_umask_mode_and_replaced_files_keep_theirs() {
    let d = Dir::new();
    d.file("a.nc", "POPEN\nDPRNT[HI]\nPCLOS\nG0 X1\n");
    let o = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "umask 027 && exec '{}' run a.nc -o new.nc --dump-vars v.txt",
            env!("CARGO_BIN_EXE_fmsvm")
        ))
        .current_dir(d.0.path())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    for name in ["new.nc", "new.prn", "v.txt"] {
        assert_eq!(mode(&d.path(name)), 0o640, "{name}");
    }
    let kept = d.file("kept.nc", "old\n");
    std::fs::set_permissions(&kept, std::fs::Permissions::from_mode(0o604)).unwrap();
    let o = run(&["run", "a.nc", "-o", "kept.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(mode(&kept), 0o604);
    assert!(d.read("kept.nc").contains("G0 X1."));
}

#[test]
fn outputs_are_committed_together_or_not_at_all() {
    let d = Dir::new();
    d.file("a.nc", "POPEN\nDPRNT[HI]\nPCLOS\nG0 X1\n");
    std::fs::create_dir(d.path("dir")).unwrap();
    // A folder as the printed output: refused before anything runs, -o not written.
    let o = run(
        &["run", "a.nc", "-o", "out.nc", "--print", "dir"],
        d.0.path(),
    );
    assert_eq!(o.status.code(), Some(6), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--print: dir is a folder"),
        "{}",
        stderr(&o)
    );
    // A variable store in a folder that does not exist: the same.
    let o = run(
        &["run", "a.nc", "-o", "out.nc", "--dump-vars", "no/v.txt"],
        d.0.path(),
    );
    assert_eq!(o.status.code(), Some(6), "{}", stderr(&o));
    assert_eq!(d.names(), ["a.nc", "dir"].map(String::from));
    // An alarm after printing: neither the program nor the printed output is committed.
    d.file("b.nc", "POPEN\nDPRNT[HI]\nG0 X1\n#3000=1(STOP)\n");
    let o = run(&["run", "b.nc", "-o", "out.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert_eq!(d.names(), ["a.nc", "b.nc", "dir"].map(String::from));
    // Success: all three.
    let o = run(
        &["run", "a.nc", "-o", "out.nc", "--dump-vars", "v.txt"],
        d.0.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(
        d.names(),
        ["a.nc", "b.nc", "dir", "out.nc", "out.prn", "v.txt"].map(String::from)
    );
    assert_eq!(d.read("out.prn"), "\u{12}HI\n\u{14}");
}

#[test]
fn signals_remove_the_temporary_files_and_exit_128_plus_n() {
    for (name, n) in [("INT", 2), ("TERM", 15), ("HUP", 1), ("QUIT", 3)] {
        let d = Dir::new();
        d.file(
            "big.nc",
            "POPEN\n#1=0\nWHILE[1 EQ 1]DO1\nG1 X[#1 MOD 1000]\nDPRNT[X#1[53]]\n#1=#1+1\nEND1\n",
        );
        let child = bin()
            .args([
                "run",
                "big.nc",
                "-o",
                "out.nc",
                "--max-blocks",
                "0",
                "--max-steps",
                "0",
                "--max-bytes",
                "0",
                "--max-print-bytes",
                "0",
            ])
            .current_dir(d.0.path())
            .stderr(Stdio::piped())
            .spawn()
            .expect("spawn");
        // Wait until both temporary files exist (the printed output is opened on first DPRNT).
        let start = Instant::now();
        while d.names().iter().filter(|n| n.ends_with(".partial")).count() < 2 {
            assert!(start.elapsed() < Duration::from_secs(30), "{:?}", d.names());
            std::thread::sleep(Duration::from_millis(20));
        }
        std::thread::sleep(Duration::from_millis(100));
        let killed = Command::new("kill")
            .args([format!("-{name}"), child.id().to_string()])
            .status()
            .unwrap();
        assert!(killed.success());
        let o = child.wait_with_output().unwrap();
        assert_eq!(o.status.code(), Some(128 + n), "SIG{name}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains(&format!("stopped by SIG{name}")) && e.contains("expanding big.nc"),
            "{e}"
        );
        assert!(e.contains("2 temporary files removed"), "{e}");
        assert_eq!(d.names(), ["big.nc"].map(String::from), "SIG{name}");
    }
}

#[test]
fn what_dump_vars_writes_vars_reads() {
    let d = Dir::new();
    d.file("p.nc", "#100=3\n#500=#500+1\n#999=-0.000125\nG0 X#500\n");
    for round in 1..=3 {
        let mut args = vec!["run", "p.nc", "--dump-vars", "v.txt"];
        if round > 1 {
            args.extend(["--vars", "v.txt"]);
        }
        let o = run(&args, d.0.path());
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let v = d.read("v.txt");
        assert!(v.contains(&format!("\n#500={round}\n")), "{v}");
        assert!(v.contains("\n#999=-0.000125\n"), "{v}");
        assert!(v.contains("(#100=3)"), "{v}");
    }
}

/// Runs a shell script (with `$FMSVM` set) in `d`.
fn sh(d: &Dir, script: &str) -> Output {
    Command::new("sh")
        .arg("-c")
        .arg(script)
        .env("FMSVM", env!("CARGO_BIN_EXE_fmsvm"))
        .current_dir(d.0.path())
        .output()
        .unwrap()
}

#[test]
fn a_full_file_system_is_an_io_error_and_leaves_nothing() {
    let d = Dir::new();
    d.file("p.nc", ENDLESS);
    // A file-size limit (works for any user): writes past it fail with EFBIG.
    let o = sh(
        &d,
        "trap '' XFSZ; ulimit -f 64; exec \"$FMSVM\" run p.nc -o out.nc --max-blocks 200000",
    );
    assert_eq!(o.status.code(), Some(6), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("writing out.nc failed"),
        "{}",
        stderr(&o)
    );
    assert!(!stderr(&o).contains(".partial"), "{}", stderr(&o));
    assert_eq!(d.names(), ["p.nc"].map(String::from));
}

/// The same on a full file system: a tmpfs of 64 KiB in a private mount namespace (root, or an
/// unprivileged user namespace), ENOSPC. `.ci/run` runs it where `unshare -m` works.
#[test]
#[ignore = "needs a private mount namespace (unshare -m); .ci/run runs it with --ignored where the system allows one"]
fn a_full_tmpfs_is_an_io_error_and_leaves_nothing() {
    let d = Dir::new();
    d.file("p.nc", ENDLESS);
    std::fs::create_dir(d.path("small")).unwrap();
    let script = "cp p.nc small/ && cd small && \"$FMSVM\" run p.nc -o out.nc --max-blocks 200000; echo \"rc=$?\"; ls -A";
    let o = sh(
        &d,
        &format!(
            "unshare -rm sh -c 'mount -t tmpfs -o size=64k tmpfs small && {s}' 2>&1 || unshare -m sh -c 'mount -t tmpfs -o size=64k tmpfs small && {s}' 2>&1",
            s = script.replace('\'', "'\\''")
        ),
    );
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("rc=6"), "{text}");
    assert!(text.contains("No space left on device"), "{text}");
    assert!(text.trim_end().ends_with("p.nc"), "{text}");
}

#[test]
fn printed_bytes_count_against_max_bytes_and_have_a_bound_of_their_own() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "POPEN\n#1=0\nWHILE[1 EQ 1]DO1\nDPRNT[X#1[53]]\n#1=#1+1\nEND1\n",
    );
    let start = Instant::now();
    let o = run(&["run", "p.nc", "--max-bytes", "1000"], d.0.path());
    assert_eq!(o.status.code(), Some(5), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("limit of 1000 output bytes reached"),
        "{}",
        stderr(&o)
    );
    assert!(start.elapsed() < Duration::from_secs(20));
    let o = run(&["run", "p.nc", "--max-print-bytes", "1K"], d.0.path());
    assert_eq!(o.status.code(), Some(5), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("limit of 1024 printed bytes (DPRNT/BPRNT) reached"),
        "{}",
        stderr(&o)
    );
    // The default bound (64 MiB) stops an endless print loop with no flags at all.
    let long = "A".repeat(500);
    d.file(
        "q.nc",
        &format!("POPEN\nWHILE[1 EQ 1]DO1\nDPRNT[{long}]\nEND1\n"),
    );
    let o = run(&["run", "q.nc", "-o", "q-flat.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(5), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("limit of 67108864 printed bytes"),
        "{}",
        stderr(&o)
    );
    assert!(
        !d.names()
            .iter()
            .any(|n| n.starts_with("q-flat") || n.starts_with("q.prn"))
    );
}

#[test]
fn inputs_are_bounded() {
    let d = Dir::new();
    d.file("a.nc", SMALL);
    // /dev/zero is only read: an endless input.
    let o = run(&["run", "/dev/zero", "--max-input", "1M"], d.0.path());
    assert_eq!(o.status.code(), Some(5), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("cannot read /dev/zero: it is larger than 1 MiB"),
        "{}",
        stderr(&o)
    );
    let o = run(&["run", "a.nc", "--vars", "/dev/zero"], d.0.path());
    assert_eq!(o.status.code(), Some(5), "{}", stderr(&o));
    assert!(stderr(&o).contains("--vars /dev/zero"), "{}", stderr(&o));
    let o = run(&["run", "a.nc", "--max-input", "5"], d.0.path());
    assert_eq!(o.status.code(), Some(5), "{}", stderr(&o));
    let o = run(&["check", "a.nc", "--max-input", "1K"], d.0.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

#[test]
fn every_option_value_is_checked_when_parsed() {
    let d = Dir::new();
    d.file("a.nc", SMALL);
    for (flag, value) in [
        ("--max-seconds", "1e19"),
        ("--max-seconds", "0"),
        ("--max-seconds", "nan"),
        ("--rapid", "0"),
        ("--rapid", "nan"),
        ("--rapid", "-5"),
        ("--rapid", "inf"),
        ("--probe-radius", "nan"),
        ("--probe-radius", "-1"),
        ("--date", "20241399"),
        ("--date", "20230229"),
        ("--date", "2024011"),
        ("--time", "250000"),
        ("--time", "126000"),
        ("--max-input", "0"),
        ("--max-bytes", "12X"),
        ("--max-bytes", "99999999999999999999G"),
        ("--stock", "0,0,0,nan,1,1"),
        ("--renumber", "0"),
        ("--sub-depth", "11"),
        ("--encoding", "ebcdic"),
    ] {
        let o = run(&["run", "a.nc", flag, value], d.0.path());
        assert_eq!(o.status.code(), Some(2), "{flag} {value}: {}", stderr(&o));
        assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    }
    for (flag, value) in [
        ("--date", "20240229"),
        ("--time", "235959"),
        ("--max-seconds", "1e9"),
        ("--rapid", "24000"),
        ("--max-bytes", "2G"),
    ] {
        let o = run(&["run", "a.nc", flag, value], d.0.path());
        assert_eq!(o.status.code(), Some(0), "{flag} {value}: {}", stderr(&o));
    }
    // #3011 reads the date given.
    d.file("date.nc", "#1=#3011\nG0 X[#1-20240000]\n");
    let o = run(&["run", "date.nc", "--date", "20240229"], d.0.path());
    assert!(String::from_utf8_lossy(&o.stdout).contains("X229."));
}

#[test]
fn probe_points_with_a_cyrillic_letter_are_an_error_not_a_panic() {
    let d = Dir::new();
    d.file("p.nc", "G31 Z-10 F100\nM30\n");
    // Х and У are Cyrillic here.
    d.file("touch.txt", "Х1 У2 Z3\n");
    let o = run(&["run", "p.nc", "--probe-points", "touch.txt"], d.0.path());
    // Malformed, not unreadable: the one usage code of every malformed input file (README, "Exit
    // codes"); a missing file below stays a file error.
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("touch.txt:1: expected X Y Z words"),
        "{}",
        stderr(&o)
    );
    let o = run(
        &["run", "p.nc", "--probe-points", "missing.txt"],
        d.0.path(),
    );
    assert_eq!(o.status.code(), Some(6), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("cannot read --probe-points missing.txt"),
        "{}",
        stderr(&o)
    );
    let o = run(&["run", "p.nc", "--lib", "no-such-folder"], d.0.path());
    assert_eq!(o.status.code(), Some(6), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--lib no-such-folder"),
        "{}",
        stderr(&o)
    );
}

fn cp1251(text: &str) -> Vec<u8> {
    let (b, _, _) = encoding_rs::WINDOWS_1251.encode(text);
    b.into_owned()
}

#[test]
fn cyrillic_programs_are_read_and_written_in_their_character_set() {
    let d = Dir::new();
    let program = "O1 (ФРЕЗА Д10 ЧИСТОВАЯ)\nG0 X1 (подвод к контуру)\nM30\n";
    d.bytes("ru.nc", &cp1251(program));
    // Guessed, with a warning; the output's comments come back in CP1251.
    let o = run(&["run", "ru.nc", "--comments"], d.0.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("warning: ru.nc: not UTF-8; the comments were read as CP1251"),
        "{}",
        stderr(&o)
    );
    assert_eq!(
        o.stdout,
        cp1251("%\nO0001 (ФРЕЗА Д10 ЧИСТОВАЯ)\nG0 X1. (подвод к контуру)\nM30\n%\n")
    );
    // Named: no warning; written as UTF-8 when asked.
    let o = run(
        &[
            "run",
            "ru.nc",
            "--comments",
            "--encoding",
            "cp1251",
            "--output-encoding",
            "utf-8",
        ],
        d.0.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("(подвод к контуру)"));
    // Non-UTF-8 outside a comment: the line and column, not "binary file".
    let mut bad = b"G0 X1\nG1 Y".to_vec();
    bad.extend(cp1251("Ж"));
    bad.extend(b"2\n");
    d.bytes("bad.nc", &bad);
    let o = run(&["run", "bad.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("bad.nc:2:5: byte 0xC6 outside a comment is not UTF-8 text"),
        "{}",
        stderr(&o)
    );
    // A UTF-8 byte-order mark is accepted.
    d.bytes("bom.nc", b"\xEF\xBB\xBFG0 X1\nM30\n");
    let o = run(&["run", "bom.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(String::from_utf8_lossy(&o.stdout), SMALL_OUT);
}

#[test]
fn dprnt_of_cyrillic_text_is_written_once_in_the_output_charset() {
    let d = Dir::new();
    d.file("p.nc", "POPEN\nDPRNT[ПРИВЕТ*X#1[31]]\nPCLOS\nM30\n");
    let o = run(&["run", "p.nc", "-o", "out.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(d.path("out.prn")).unwrap(),
        "\u{12}ПРИВЕТ X   0.0\n\u{14}".as_bytes()
    );
    let o = run(
        &["run", "p.nc", "-o", "out.nc", "--output-encoding", "cp1251"],
        d.0.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let mut want = vec![0x12];
    want.extend(cp1251("ПРИВЕТ X   0.0\n"));
    want.push(0x14);
    assert_eq!(std::fs::read(d.path("out.prn")).unwrap(), want);
}

#[test]
fn check_says_so_in_one_line_and_can_deny_warnings() {
    let d = Dir::new();
    d.file("ok.nc", SMALL);
    let o = run(&["check", "ok.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(
        stderr(&o),
        "ok.nc: no errors, 0 warnings; 1 program compiled\n"
    );
    // A GOTO to a missing sequence number is a warning (rule L3).
    d.file("warn.nc", "IF[#1 GT 0]GOTO50\nG0 X1\n");
    let o = run(&["check", "warn.nc"], d.0.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).ends_with("warn.nc: no errors, 1 warning; 1 program compiled\n"),
        "{}",
        stderr(&o)
    );
    let o = run(&["check", "warn.nc", "--deny-warnings"], d.0.path());
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("1 warning, denied by --deny-warnings"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn help_shows_examples_and_exit_codes() {
    let d = Dir::new();
    for args in [&["--help"][..], &["run", "--help"][..]] {
        let o = run(args, d.0.path());
        assert_eq!(o.status.code(), Some(0));
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(text.contains("Examples:"), "{text}");
        assert!(
            text.contains("Exit codes:") && text.contains("5 limit"),
            "{text}"
        );
    }
}

#[test]
fn a_character_device_is_written_directly_and_stays_one() {
    use std::io::Read;
    use std::os::fd::FromRawFd;
    let d = Dir::new();
    d.file("a.nc", SMALL);
    // A pseudo-terminal of the test's own: its slave is a character device nobody else uses.
    // SAFETY: plain libc calls on a descriptor this test owns; the name buffer is large enough.
    let (master, slave) = unsafe {
        let fd = libc::posix_openpt(libc::O_RDWR | libc::O_NOCTTY);
        assert!(fd >= 0, "posix_openpt");
        assert_eq!(libc::grantpt(fd), 0);
        assert_eq!(libc::unlockpt(fd), 0);
        let mut name = [0 as libc::c_char; 128];
        assert_eq!(libc::ptsname_r(fd, name.as_mut_ptr(), name.len()), 0);
        let slave = std::ffi::CStr::from_ptr(name.as_ptr())
            .to_string_lossy()
            .into_owned();
        (std::fs::File::from_raw_fd(fd), slave)
    };
    let o = run(
        &["run", "a.nc", "-o", &slave, "--print", &slave],
        d.0.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        std::fs::metadata(&slave)
            .unwrap()
            .file_type()
            .is_char_device()
    );
    // The terminal turns each \n into \r\n; once fmsvm closed it, reading ends (EIO).
    let mut got = Vec::new();
    let mut master = master;
    let mut buf = [0u8; 4096];
    while let Ok(n) = master.read(&mut buf) {
        if n == 0 {
            break;
        }
        got.extend_from_slice(&buf[..n]);
    }
    assert_eq!(
        String::from_utf8_lossy(&got).replace("\r\n", "\n"),
        SMALL_OUT
    );
    assert_eq!(d.names(), ["a.nc"].map(String::from));
}

#[test]
fn a_folder_that_cannot_be_written_is_named_not_the_temporary_file() {
    let d = Dir::new();
    d.file("a.nc", SMALL);
    std::fs::create_dir(d.path("ro")).unwrap();
    std::fs::set_permissions(d.path("ro"), std::fs::Permissions::from_mode(0o555)).unwrap();
    // SAFETY: geteuid has no preconditions.
    let o = if unsafe { libc::geteuid() } == 0 {
        // Permissions do not stop root: fmsvm runs as nobody (65534), in a folder nobody may enter.
        std::fs::set_permissions(d.0.path(), std::fs::Permissions::from_mode(0o755)).unwrap();
        std::fs::set_permissions(d.path("a.nc"), std::fs::Permissions::from_mode(0o644)).unwrap();
        std::process::Command::new("setpriv")
            .args(["--reuid=65534", "--regid=65534", "--clear-groups", "--"])
            .arg(env!("CARGO_BIN_EXE_fmsvm"))
            .args(["run", "a.nc", "-o", "ro/out.nc"])
            .current_dir(d.0.path())
            .output()
            .expect("setpriv (util-linux) runs fmsvm as nobody")
    } else {
        run(&["run", "a.nc", "-o", "ro/out.nc"], d.0.path())
    };
    std::fs::set_permissions(d.path("ro"), std::fs::Permissions::from_mode(0o755)).unwrap();
    assert_eq!(o.status.code(), Some(6), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("cannot create ro/out.nc: Permission denied"),
        "{e}"
    );
    assert!(
        e.contains("(in folder ro)") && !e.contains(".partial"),
        "{e}"
    );
}
