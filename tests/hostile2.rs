//! The second hostile trial of the newer surfaces (profiles, parameters, offsets, verify): each
//! finding it reported, held. Every test works inside its own temporary folder.

use crate::cli_support;

use cli_support::{Dir, stderr};

const SMALL: &str = "O0001\nG0 X1\nM30\n";

#[test]
fn no_output_replaces_a_profile_or_a_file_to_verify() {
    let d = Dir::new();
    d.file("p.nc", SMALL);
    let profile = "base = \"fanuc\"\n";
    for (args, flag) in [
        (
            vec!["run", "p.nc", "--dialect-file", "d.toml", "-o", "d.toml"],
            "-o",
        ),
        (
            vec![
                "run",
                "p.nc",
                "--dialect-file",
                "d.toml",
                "--print",
                "d.toml",
            ],
            "--print",
        ),
        (
            vec![
                "run",
                "p.nc",
                "--dialect-file",
                "d.toml",
                "--dump-vars",
                "d.toml",
            ],
            "--dump-vars",
        ),
        (
            vec!["stats", "p.nc", "--dialect-file", "d.toml", "-o", "d.toml"],
            "-o",
        ),
        (
            vec!["run", "p.nc", "--verify-file", "d.toml", "-o", "d.toml"],
            "-o",
        ),
    ] {
        d.file("d.toml", profile);
        let o = d.run(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains(&format!("{flag} d.toml would replace the")),
            "{args:?}: {}",
            stderr(&o)
        );
        assert_eq!(d.read("d.toml"), profile, "{args:?}");
    }
}

#[test]
fn a_template_width_is_bounded_when_the_profile_is_read() {
    // `{number:065536}` used to panic (the footer's only after the whole expansion).
    let d = Dir::new();
    d.file("p.nc", SMALL);
    for (key, value) in [
        ("number", "\"O{number:065536}\""),
        ("footer", "[\"%\", \"{number:017}\"]"),
        ("header", "[\"%\", \"{name:04}\"]"),
    ] {
        d.file(
            "d.toml",
            &format!("base = \"fanuc\"\n[program]\n{key} = {value}\n"),
        );
        let o = d.run(&["run", "p.nc", "--dialect-file", "d.toml"]);
        assert_eq!(o.status.code(), Some(2), "{key}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("only {number:0N} takes a width, N at most 16"),
            "{key}: {}",
            stderr(&o)
        );
    }
    d.file(
        "d.toml",
        "base = \"fanuc\"\n[program]\nfooter = [\"{number:016}\"]\n",
    );
    let o = d.run(&["run", "p.nc", "--dialect-file", "d.toml"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(cli_support::stdout(&o).ends_with("0000000000000001\n"));
}

#[test]
fn offsets_are_lengths_a_control_holds_and_named_once() {
    let d = Dir::new();
    d.file("p.nc", "G54 G0 X#5221\nM30\n");
    for (text, want) in [
        (
            "[work.G54]\nX = 1e300\n",
            "work.G54.X: not a finite number of at most 99999.999",
        ),
        (
            "[work.G54]\nX = 1000000\n",
            "work.G54.X: not a finite number",
        ),
        (
            "[work.G504]\nX = 1.0\n",
            "[work.G504]: a work offset is G54 to G59",
        ),
        (
            "[work.\"G5+4\"]\nX = 1.0\n",
            "[work.G5+4]: a work offset is G54 to G59",
        ),
        (
            "[work.G55]\nX = 1.0\n[work.\" G55\"]\nX = 2.0\n",
            "this work offset is given twice",
        ),
    ] {
        d.file("o.toml", text);
        let o = d.run(&["run", "p.nc", "--offsets", "o.toml"]);
        assert_eq!(o.status.code(), Some(2), "{text}: {}", stderr(&o));
        assert!(stderr(&o).contains(want), "{text}: {}", stderr(&o));
    }
}

#[test]
fn a_code_binds_one_program_only() {
    let d = Dir::new();
    d.file("p.nc", SMALL);
    for (text, want) in [
        (
            "[calls]\n6050 = 100\n6051 = 100\n",
            "parameter 6051 = 100: G100 is bound by 6050 already",
        ),
        (
            "[calls]\n6071 = 6\n6072 = 6\n",
            "parameter 6072 = 6: M6 is bound by 6071 already",
        ),
        (
            "[calls]\n6071 = 6\n6080 = 6\n",
            "parameter 6080 = 6: M6 is bound by 6071 already",
        ),
    ] {
        d.file("c.toml", text);
        let o = d.run(&["run", "p.nc", "--params", "c.toml"]);
        assert_eq!(o.status.code(), Some(2), "{text}: {}", stderr(&o));
        assert!(stderr(&o).contains(want), "{text}: {}", stderr(&o));
    }
}

#[test]
fn settings_files_are_regular_files_of_bounded_size() {
    let d = Dir::new();
    d.file("p.nc", SMALL);
    d.fifo("f.toml");
    let run = |args: &[&str]| {
        let mut c = cli_support::bin();
        c.args(args).current_dir(d.path("."));
        let start = std::time::Instant::now();
        let o = c.output().expect("runs");
        assert!(start.elapsed().as_secs() < 10, "{args:?} took too long");
        o
    };
    for args in [
        vec!["run", "p.nc", "--params", "f.toml"],
        vec!["run", "p.nc", "--offsets", "f.toml"],
        vec!["run", "p.nc", "--dialect-file", "f.toml"],
        vec!["run", "p.nc", "--verify-file", "f.toml"],
        vec!["dialects", "--show", "f.toml"],
    ] {
        let o = run(&args);
        assert_eq!(o.status.code(), Some(6), "{args:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("it is not a regular file (a FIFO or a device)"),
            "{args:?}: {}",
            stderr(&o)
        );
    }
    // A settings file over 1 MiB is refused before it is parsed.
    let big = format!("# {}\n", "x".repeat(2 << 20));
    d.file("big.toml", &big);
    for args in [
        vec!["run", "p.nc", "--params", "big.toml"],
        vec!["dialects", "--show", "big.toml"],
    ] {
        let o = run(&args);
        assert!(
            stderr(&o).contains("it is larger than 1 MiB, the most a settings file may hold"),
            "{args:?}: {}",
            stderr(&o)
        );
    }
    // `dialects --show` names itself, not a run's flag.
    let o = run(&["dialects", "--show", "f.toml"]);
    assert!(
        stderr(&o).contains("cannot read dialects --show f.toml"),
        "{}",
        stderr(&o)
    );
    // A FIFO in a library folder is no program: the call does not hang.
    d.file("main.nc", "M98 P9010\nM30\n");
    std::fs::create_dir_all(d.path("lib")).expect("lib");
    d.fifo("lib/O9010.nc");
    let o = run(&["run", "main.nc", "--lib", "lib"]);
    assert_ne!(o.status.code(), Some(0), "{}", stderr(&o));
}

#[test]
fn a_run_killed_outright_leaves_nothing_the_next_run_into_its_folder_keeps() {
    // SIGKILL gives a run no chance to remove its temporary output: the next run writing that
    // output removes it (its process is gone), and leaves every other file alone.
    let d = Dir::new();
    d.file("p.nc", SMALL);
    // A process that has certainly ended: a child we waited for.
    let gone = std::process::Command::new("true")
        .spawn()
        .and_then(|mut c| {
            let id = c.id();
            c.wait().map(|_| id)
        })
        .expect("true runs");
    let stale = format!(".out.nc.{gone}.AbC123.partial");
    d.file(&stale, "G0 X9\n");
    d.file(".out.nc.notapid.partial", "keep\n");
    d.file(".other.nc.1.AbC123.partial", "keep\n");
    let o = d.run(&["run", "p.nc", "-o", "out.nc"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let names = d.names();
    if std::path::Path::new("/proc/self").exists() {
        assert!(!names.contains(&stale), "{names:?}");
    }
    assert!(
        names.contains(&".out.nc.notapid.partial".to_string()),
        "{names:?}"
    );
    assert!(
        names.contains(&".other.nc.1.AbC123.partial".to_string()),
        "{names:?}"
    );
    assert_eq!(d.read("out.nc"), "%\nO0001\nG0 X1.\nM30\n%\n");
}

#[test]
fn a_hold_timeout_too_short_to_measure_is_refused_not_read_as_for_ever() {
    // `--hold-timeout 1e-10` rounded to no time at all, which means "wait for ever".
    let d = Dir::new();
    d.file("p.nc", SMALL);
    let o = d.run(&[
        "dnc",
        "p.nc",
        "--tcp",
        "127.0.0.1:9",
        "--hold-timeout",
        "1e-10",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("0 (for ever), or from 0.001 to 1000000"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_profile_s_sections_and_block_limit_are_named_as_written() {
    let d = Dir::new();
    d.file("p.nc", SMALL);
    for (text, want) in [
        (
            "base = \"fanuc\"\n[[blocks]]\nend = \"lf\"\n",
            "[[blocks]] is written [blocks]: only [[cycle]] repeats",
        ),
        (
            "base = \"fanuc\"\n[blocks]\nmax_length = 1\n",
            "[blocks] max_length = 1: 0 (no limit) or at least 16 characters",
        ),
        // Found by the settings fuzz target: a name with a line break made `dialects --show`
        // print a profile that does not read back.
        (
            "base = \"fanuc\"\nname = \"two\\nlines\"\n",
            "name: a dialect's name is one line without control characters",
        ),
    ] {
        d.file("d.toml", text);
        let o = d.run(&["run", "p.nc", "--dialect-file", "d.toml"]);
        assert_eq!(o.status.code(), Some(2), "{text}: {}", stderr(&o));
        assert!(stderr(&o).contains(want), "{text}: {}", stderr(&o));
    }
}

/// One block can make many flat blocks (a canned cycle's pecks, an arc in chords): `--max-blocks`
/// counts the flat program's blocks as they are made, inside the cycle or the arc, in `run`,
/// `stats` and `plot` alike. G83 from R2 to Z-90 with Q0.01 is 9 200 pecks of up to three moves
/// each (a rapid down to the clearance above the last depth, a feed, a rapid out: about 27 600);
/// an R10 circle within 1e-12 mm is millions of chords (θ = 2·acos(1 − 1e-13) ≈ 9e-7 rad, capped
/// by the chord count); either stops at the 101st block with nothing written.
#[test]
fn the_block_limit_counts_the_blocks_a_cycle_or_an_arc_makes() {
    let d = Dir::new();
    d.file(
        "peck.nc",
        "O1\nG17 G21 G90\nG0 X0 Y0 Z5\nG83 X0 Y0 Z-90 R2 Q0.01 F100\nG80\nM30\n",
    );
    d.file(
        "chords.nc",
        "O1\nG17 G21 G90\nG0 X0 Y0 Z5\nG1 Z0 F100\nG2 X0 Y0 I10 J0\nM30\n",
    );
    let mut cases = vec![
        vec![
            "run",
            "peck.nc",
            "--resolve",
            "--max-blocks",
            "100",
            "-o",
            "out.nc",
        ],
        vec![
            "run",
            "chords.nc",
            "--resolve",
            "--linearize",
            "1e-12",
            "--max-blocks",
            "100",
            "-o",
            "out.nc",
        ],
        vec!["stats", "peck.nc", "--max-blocks", "100"],
    ];
    if cfg!(feature = "plot") {
        cases.push(vec![
            "plot",
            "peck.nc",
            "--max-blocks",
            "100",
            "-o",
            "out.svg",
        ]);
    }
    for args in cases {
        let o = d.run(&args);
        assert_eq!(o.status.code(), Some(5), "{args:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("limit of 100 output blocks reached"),
            "{args:?}: {}",
            stderr(&o)
        );
        assert!(!d.0.path().join("out.nc").exists(), "{args:?}");
        assert!(!d.0.path().join("out.svg").exists(), "{args:?}");
    }
    // With room for 3 a peck, the pecks are all there.
    let o = d.run(&[
        "run",
        "peck.nc",
        "--resolve",
        "--max-blocks",
        "27700",
        "-o",
        "out.nc",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(d.read("out.nc").lines().count() > 27_000);
}

/// The clock is looked at inside a block too: a main program restarted by its M99 whose one
/// canned cycle (NCT's incremental pattern, 5 360 holes) makes 21 000 moves a block stops at
/// `--max-seconds`, in `run --resolve` and in `stats`, not at the 10-million-block default.
#[test]
fn the_wall_time_limit_is_looked_at_inside_a_cycle() {
    let d = Dir::new();
    d.file(
        "loop.nc",
        "O1\nG17 G21 G90\nG0 X0 Y0 Z5\nG81 X50 YI10 R2 Z-10 L5360 F100\nG80\nM99\n",
    );
    for args in [
        vec![
            "run",
            "loop.nc",
            "--input",
            "nct",
            "--control",
            "nct",
            "--resolve",
            "--max-blocks",
            "0",
            "--max-seconds",
            "0.5",
            "-o",
            "out.nc",
        ],
        vec![
            "stats",
            "loop.nc",
            "--input",
            "nct",
            "--control",
            "nct",
            "--max-blocks",
            "0",
            "--max-seconds",
            "0.5",
        ],
    ] {
        let o = d.run(&args);
        assert_eq!(o.status.code(), Some(5), "{args:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("limit of 0.5 seconds of wall time reached"),
            "{args:?}: {}",
            stderr(&o)
        );
    }
}

/// `stats` and `plot` hold the motion to the digits the dialect can write, as `run --resolve`
/// does: a local offset of 99 999.999 under a move to 99 999.999 puts X at 199 999.998, which does
/// not fit Fanuc's 8 digits (99 999.999 at 0.001 mm); nothing is reported or drawn, exit 4. And a
/// failed `stats` does not speak of output "above" when it printed nothing.
#[test]
fn stats_and_plot_refuse_a_position_the_output_cannot_hold() {
    let d = Dir::new();
    d.file(
        "far.nc",
        "O1\nG90 G21\nG52 X99999.999\nG1 X99999.999 F100\nG52 X0\nM30\n",
    );
    let mut cases = vec![
        vec!["run", "far.nc", "--resolve", "-o", "out.nc"],
        vec!["stats", "far.nc"],
    ];
    if cfg!(feature = "plot") {
        cases.push(vec!["plot", "far.nc", "-o", "out.svg"]);
    }
    for args in cases {
        let o = d.run(&args);
        assert_eq!(o.status.code(), Some(4), "{args:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains(
                "error[alarm 0003]: too many digits: the resolved X199999.998 does not fit 8 digits"
            ),
            "{args:?}: {}",
            stderr(&o)
        );
        assert!(o.stdout.is_empty(), "{args:?}");
        if args[0] == "stats" {
            assert!(stderr(&o).contains("nothing was written"), "{}", stderr(&o));
        }
    }
    // Within reach the same program is reported: X ends at 49 999.999 + 49 999.999 = 99 999.998.
    d.file(
        "near.nc",
        "O1\nG90 G21\nG52 X49999.999\nG1 X49999.999 F100\nG52 X0\nM30\n",
    );
    let o = d.run(&["stats", "near.nc"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        String::from_utf8_lossy(&o.stdout).contains("X 99999.998 .. 99999.998"),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
}

/// A literal `--verify` that finds the feed written otherwise than programmed says so: a profile
/// whose F has no decimals writes F100.4 as F100, and the message names both feeds, not two equal
/// positions.
#[test]
fn a_feed_written_otherwise_is_named_by_verify() {
    let d = Dir::new();
    d.file(
        "f0.toml",
        "base = \"fanuc\"\n[numbers.address.F]\ndigits = 0\n",
    );
    d.file("f.nc", "O1\nG90 G17 G21\nG1 X10 Y0 F100.4\nG1 X20\nM30\n");
    let o = d.run(&[
        "run",
        "f.nc",
        "--dialect-file",
        "f0.toml",
        "-o",
        "out.nc",
        "--verify",
    ]);
    assert_eq!(o.status.code(), Some(7), "{}", stderr(&o));
    assert!(
        // The feeds are named with their mode (per minute, per revolution): the same number in
        // the other mode is another feed, and the message says which.
        stderr(&o).contains(
            "Z? at F100.4 per minute, the output to Feed to X10.0000 Y0.0000 Z? at F100 per minute"
        ),
        "{}",
        stderr(&o)
    );
}
