//! The pipelined emitter (plain blocks formatted and written by a second thread) writes exactly what
//! the literal emitter writes on the run's thread: the same bytes, messages, exit codes and partial
//! output, on programs long enough to cross its batches, stopped mid-batch by every kind of limit
//! and alarm, with `--without pipeline` for the single-threaded run.

use crate::cli_support;

use std::path::Path;
use std::process::Output;

use cli_support::{Dir, Rng, bin, messages, stderr};

fn run(args: &[&str], cwd: &Path, pipelined: bool) -> Output {
    let mut c = bin();
    c.args(args).current_dir(cwd);
    if !pipelined {
        c.args(["--without", "pipeline"]);
    }
    c.output().expect("runs")
}

/// Runs `args` both ways in `d`; every file the runs leave (an output, a partial output) is
/// compared too. Returns the pipelined run.
fn same(d: &Dir, args: &[&str], what: &str) -> Output {
    let clean = |d: &Dir| {
        for n in d.names() {
            if !n.ends_with(".nc") && !n.ends_with(".toml") {
                let _ = std::fs::remove_file(d.path(&n));
            }
        }
    };
    let files = |d: &Dir| -> Vec<(String, Vec<u8>)> {
        d.names()
            .into_iter()
            .map(|n| (n.clone(), std::fs::read(d.path(&n)).expect("read")))
            .collect()
    };
    clean(d);
    let p = run(args, d.0.path(), true);
    let p_files = files(d);
    clean(d);
    let s = run(args, d.0.path(), false);
    let s_files = files(d);
    assert_eq!(
        p.status.code(),
        s.status.code(),
        "{what}: exit\n{}\n{}",
        stderr(&p),
        stderr(&s)
    );
    assert_eq!(messages(&p), messages(&s), "{what}: messages");
    assert!(
        p.stdout == s.stdout,
        "{what}: output differs ({} against {} bytes)",
        p.stdout.len(),
        s.stdout.len()
    );
    assert_eq!(
        p_files.iter().map(|f| &f.0).collect::<Vec<_>>(),
        s_files.iter().map(|f| &f.0).collect::<Vec<_>>(),
        "{what}: files left"
    );
    for (a, b) in p_files.iter().zip(&s_files) {
        assert!(a.1 == b.1, "{what}: {} differs", a.0);
    }
    p
}

/// A raster of `n` plain blocks (several of the emitter's 1 024-block batches), with now and then a
/// block that is not plain (a tool change, a dwell, G91 moves), a unit change, block delete, a
/// comment, and `extra` at block `at`.
fn raster(n: u32, at: u32, extra: &str) -> String {
    format!(
        "%\nO100 (RASTER)\nG21 G90 G17\nG0 X0 Y0 Z5\n#1=0\nWHILE[#1LT{n}]DO1\n\
         IF[#1NE{at}]GOTO10\n{extra}\n\
         N10 G1 X[#1*0.013] Y[SIN[#1*7]*50] Z[-#1/7000] F[800+[#1 MOD 3]*100]\n\
         IF[[#1 MOD 997] EQ 5] THEN #2=1\n\
         IF[#2EQ1]GOTO20\n\
         N15 G1 Y[COS[#1]*10]\n\
         N20 #2=0\n\
         IF[[#1 MOD 1500] EQ 700] THEN #3=1\n\
         IF[#3NE1]GOTO30\n\
         G20 X[#1/1000] (INCH)\nG21\nG91 X0.1\nG90\nT2 M6\nG4 P100\n/G1 X1 Y1\n#3=0\n\
         N30 #1=#1+1\nEND1\nM30\n%\n"
    )
}

#[test]
fn a_long_raster_writes_the_same_bytes_either_way() {
    let d = Dir::new();
    d.file("r.nc", &raster(5000, 1_000_000, "#9=0"));
    let o = same(&d, &["run", "r.nc", "-o", "-"], "raster to stdout");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    // Hand-derived: block 4321's move (X 56.173, Y 50·sin(30247°) = 50·sin(7°) = 6.093,
    // Z −0.617 to 0.001 mm, F 800 + 1·100).
    assert!(
        text.contains("\nN10 G1 X56.173 Y6.093 Z-0.617 F900.\n"),
        "{}",
        &text[..400]
    );
    assert_eq!(text.matches("\nN10 G1 ").count(), 5000);
    same(&d, &["run", "r.nc", "-o", "out.nc"], "raster to a file");
    let o = same(
        &d,
        &["run", "r.nc", "-o", "-", "--block-delete", "--stats"],
        "block delete, stats",
    );
    // The comparison is not of one path with itself: a second thread wrote (on two cores).
    if std::thread::available_parallelism().is_ok_and(|n| n.get() >= 2) {
        assert!(
            stderr(&o).contains("written by a second thread"),
            "{}",
            stderr(&o)
        );
        let one = run(&["run", "r.nc", "-o", "-", "--stats"], d.0.path(), false);
        assert!(!stderr(&one).contains("second thread"), "{}", stderr(&one));
    }
    same(
        &d,
        &["run", "r.nc", "-o", "-", "--comments", "--engine", "interp"],
        "comments, interpreter",
    );
    same(
        &d,
        &["run", "r.nc", "-o", "-", "--dialect", "fms3000"],
        "FMS-3000",
    );
    // Resolved output hands its moves to the second thread too.
    for dialect in ["fanuc", "linuxcnc", "iso"] {
        let o = same(
            &d,
            &[
                "run",
                "r.nc",
                "-o",
                "-",
                "--dialect",
                dialect,
                "--resolve",
                "--stats",
            ],
            &format!("resolved, {dialect}"),
        );
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        if std::thread::available_parallelism().is_ok_and(|n| n.get() >= 2) {
            assert!(
                stderr(&o).contains("written by a second thread"),
                "{}",
                stderr(&o)
            );
        }
    }
    same(
        &d,
        &["run", "r.nc", "-o", "-", "--dialect", "fms3000", "--stats"],
        "FMS-3000 resolved",
    );
}

#[test]
fn limits_and_alarms_mid_batch_stop_at_the_same_block() {
    let d = Dir::new();
    d.file("r.nc", &raster(6000, 1_000_000, "#9=0"));
    // The byte budget runs out inside a batch, at a batch's edge, and near the end; literal and
    // resolved output.
    for (max, resolve) in ["100", "30000", "65536", "123457", "180000"]
        .into_iter()
        .flat_map(|m| [(m, "--comments"), (m, "--resolve")])
    {
        let o = same(
            &d,
            &[
                "run",
                "r.nc",
                "-o",
                "out.nc",
                "--max-bytes",
                max,
                "--keep-partial",
                resolve,
            ],
            &format!("--max-bytes {max} {resolve}"),
        );
        assert_eq!(o.status.code(), Some(5), "{}", stderr(&o));
        assert!(
            d.names().iter().any(|n| n.contains("PARTIAL")),
            "{:?}",
            d.names()
        );
    }
    same(
        &d,
        &["run", "r.nc", "-o", "-", "--max-blocks", "3001"],
        "--max-blocks",
    );
    same(
        &d,
        &[
            "run",
            "r.nc",
            "-o",
            "-",
            "--max-blocks",
            "3001",
            "--resolve",
        ],
        "--max-blocks, resolved",
    );
    // An alarm raised by the program, one by decoding (too many digits), and a block longer than
    // the dialect takes (`short.toml`: 100 bytes; the raster's lines take about 40).
    d.file(
        "short.toml",
        "base = \"fanuc\"\n[blocks]\nmax_length = 100\n",
    );
    let long = "G1 X-11111.111 Y-22222.222 Z-33333.333 A-44444.444 B-55555.555 C-66666.666 \
                U-11111.111 V-22222.222 W-33333.333 F100.123";
    for (i, extra) in ["#3000=7(STOP HERE)", "G1 X123456789", long]
        .iter()
        .enumerate()
    {
        d.file("a.nc", &raster(6000, 4321, extra));
        for (dialect, resolve) in [["--dialect", "fanuc"], ["--dialect-file", "short.toml"]]
            .into_iter()
            .flat_map(|d| [(d, "--comments"), (d, "--resolve")])
        {
            let mut args = vec!["run", "a.nc", "-o", "out.nc", "--keep-partial", resolve];
            args.extend_from_slice(&dialect);
            let o = same(
                &d,
                &args,
                &format!("stop {i} ({dialect:?} {resolve}): {extra}"),
            );
            // Resolved, the long block's line leaves out U V W (no axes of a mill) and fits.
            let stops = i < 2 || (dialect[1] == "short.toml" && resolve != "--resolve");
            assert_eq!(
                o.status.code() == Some(4),
                stops,
                "{extra} {dialect:?} {resolve}: {}",
                stderr(&o)
            );
            if stops && resolve != "--resolve" {
                // The partial output ends with the block before the stop.
                let partial = d.read("out.PARTIAL.nc");
                let last = partial
                    .lines()
                    .rev()
                    .find(|l| l.starts_with("N10"))
                    .unwrap_or("");
                assert!(last.starts_with("N10 G1 X56.16 Y"), "{i}: {last}");
            }
        }
    }
}

#[test]
fn a_dialect_with_fewer_digits_raises_its_alarm_at_the_same_block() {
    // The language takes 8 digits; this control 6 (±999.999): X passes 1000 at block 76 923, after
    // which every word of X must be looked at on the run's thread.
    let d = Dir::new();
    d.file(
        "six.toml",
        "base = \"fanuc\"\n[numbers]\nmax_digits = 6\nplus = true\nwidth = 3\ntrailing_zeros = true\n",
    );
    let mut r = Rng(0x1234_5678_9ABC_DEF1);
    for _ in 0..3 {
        let step = 0.1 + (r.next() % 1000) as f64 / 1000.0;
        d.file(
            "s.nc",
            &format!(
                "%\nO7\nG90 G1 F500\n#1=0\nWHILE[#1LT3000]DO1\nN5 X[#1*{step}] Y[#1*-0.25]\n#1=#1+1\nEND1\nM30\n%\n"
            ),
        );
        let resolved = same(
            &d,
            &[
                "run",
                "s.nc",
                "-o",
                "-",
                "--dialect-file",
                "six.toml",
                "--resolve",
            ],
            &format!("six digits, resolved, step {step}"),
        );
        let o = same(
            &d,
            &["run", "s.nc", "-o", "-", "--dialect-file", "six.toml"],
            &format!("six digits, step {step}"),
        );
        assert_eq!(
            resolved.status.code(),
            o.status.code(),
            "{}",
            stderr(&resolved)
        );
        let reached = (2999.0 * step) >= 999.9995;
        assert_eq!(
            o.status.code() == Some(0),
            !reached,
            "step {step}: {}",
            stderr(&o)
        );
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(
            text.contains("\nN5 X+000.000 Y+000.000\n"),
            "{}",
            &text[..200]
        );
    }
}

#[test]
fn a_program_that_prints_runs_on_one_thread_and_writes_the_same() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "%\nO9\nPOPEN\n#1=0\nWHILE[#1LT3000]DO1\nG1 X#1 Y[#1/3]\nDPRNT[X#1[53]]\n#1=#1+1\nEND1\nPCLOS\nM30\n%\n",
    );
    for max in ["0", "50000"] {
        let o = same(
            &d,
            &[
                "run",
                "p.nc",
                "-o",
                "out.nc",
                "--print",
                "print.txt",
                "--max-bytes",
                max,
                "--stats",
            ],
            &format!("prints, --max-bytes {max}"),
        );
        assert!(!stderr(&o).contains("second thread"), "{}", stderr(&o));
    }
}

#[test]
fn an_incremental_word_past_the_digits_stops_at_its_own_block() {
    // NCT's incremental operator makes X absolute after decoding: 99 999.9 + 0.2 passes the eight
    // digits (alarm 0003) at that block, on either path.
    let d = Dir::new();
    d.file(
        "i.nc",
        "%\nO5\nG90 G0 X99999.9\n#1=0\nWHILE[#1LT2000]DO1\nG1 Y[#1/10] F100\n#1=#1+1\nEND1\nG1 XI0.2\nY1\nM30\n%\n",
    );
    let o = same(
        &d,
        &[
            "run",
            "i.nc",
            "-o",
            "out.nc",
            "--keep-partial",
            "--input",
            "nct",
        ],
        "incremental past the digits",
    );
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(stderr(&o).contains("0003"), "{}", stderr(&o));
}

/// An output error the writer thread meets is the run's stop even when the run stops for another
/// reason before that error comes back to the run's thread: here standard output is a pipe closed
/// before anything is written (the first 64 KiB chunk, near pass 1 260 of the raster's loop, fails),
/// and `#3000` is raised a little later, before the next block that waits for the writer (the tool
/// change at pass 2 200; the one at pass 700 comes before the chunk is full), while the failed batch,
/// or the blocks that fill the chunk, are still with the writer. On one thread the broken pipe stops
/// the run at once, which ends quietly with exit 0 (`fmsvm run | head`).
#[test]
fn an_output_error_on_the_writer_is_not_lost_to_a_later_alarm() {
    use std::process::Stdio;
    let d = Dir::new();
    for at in [1_600, 1_800, 1_990] {
        d.file("r.nc", &raster(10_000, at, "#3000=1(LATER)"));
        for pipelined in [true, false] {
            let mut c = bin();
            c.args(["run", "r.nc"])
                .current_dir(d.0.path())
                .stdin(Stdio::null())
                .stdout(Stdio::piped())
                .stderr(Stdio::piped());
            if !pipelined {
                c.args(["--without", "pipeline"]);
            }
            let mut child = c.spawn().expect("runs");
            drop(child.stdout.take());
            let o = child.wait_with_output().expect("ends");
            assert_eq!(
                o.status.code(),
                Some(0),
                "alarm at pass {at}, pipelined {pipelined}: {}",
                stderr(&o)
            );
            assert!(
                !stderr(&o).contains("LATER"),
                "alarm at pass {at}: {}",
                stderr(&o)
            );
        }
    }
}

/// Blocks of every size a batch holds: none (a comment line, which writes nothing with
/// `--no-comments`), one word, eight (one whole piece), nine (a second piece), and sixteen and
/// seventeen, between ordinary moves, over several batches.
#[test]
fn blocks_of_every_piece_count_are_written_in_order() {
    let d = Dir::new();
    d.file(
        "w.nc",
        "%\nO12\nG21 G90\n#1=0\nWHILE[#1LT2500]DO1\n(A COMMENT LINE)\nG1 X#1\n\
         N1 G1 X1 Y2 Z3 A4 B5 C6 F100\n\
         N2 G1 X1 Y2 Z3 A4 B5 C6 U7 F100\n\
         N3 G1 X1 Y2 Z3 A4 B5 C6 U7 V8 W9 I1 J2 K3 R4 F100\n\
         N4 G1 X1 Y2 Z3 A4 B5 C6 U7 V8 W9 I1 J2 K3 R4 Q5 F100\n\
         (ANOTHER)\n#1=#1+1\nEND1\nM30\n%\n",
    );
    let o = same(
        &d,
        &["run", "w.nc", "-o", "-", "--no-comments"],
        "piece counts",
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    // Pass 1234, written out by hand.
    let pass = "\nG1 X1234.\nN1 G1 X1. Y2. Z3. A4. B5. C6. F100.\n\
                N2 G1 X1. Y2. Z3. A4. B5. C6. U7. F100.\n\
                N3 G1 X1. Y2. Z3. A4. B5. C6. U7. V8. W9. I1. J2. K3. R4. F100.\n\
                N4 G1 X1. Y2. Z3. A4. B5. C6. U7. V8. W9. I1. J2. K3. R4. Q5. F100.\nG1 X1235.\n";
    assert!(text.contains(pass), "{}", &text[..600.min(text.len())]);
    assert_eq!(text.matches("\nN4 G1 ").count(), 2500);
    assert!(
        !text.contains("COMMENT"),
        "{}",
        &text[..300.min(text.len())]
    );
    let o = same(
        &d,
        &["run", "w.nc", "-o", "-", "--comments"],
        "with comments",
    );
    assert_eq!(
        String::from_utf8_lossy(&o.stdout)
            .matches("\n(A COMMENT LINE)\n")
            .count(),
        2500
    );
}
