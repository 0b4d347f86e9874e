//! The program's comments in the output: kept by default in each dialect that has a comment syntax,
//! said once and left out where it has none, dropped by `--no-comments`, and always safe to send:
//! never a line past the dialect's length, never a `%` that ends the transfer, never a comment the
//! control acts on.

use crate::cli_support::{Dir, stderr};

/// A tool description and a note on a move, as shops write them.
const PROGRAM: &str =
    "%\nO12 (BRACKET)\nT1 (T1 D10 FLAT END MILL)\nG0 X10 Z5 (APPROACH)\nG1 Z0 F100\nM30\n%\n";

/// How each built-in dialect writes a comment: the lines the two comments become (the manuals'
/// syntax: `( )` for Fanuc, ISO 6983, LinuxCNC, Fagor and Haas; `;` to the line's end for the
/// SINUMERIK 802D), or None where the control has no comments.
const DIALECTS: [(&str, Option<[&str; 2]>); 11] = [
    (
        "fanuc",
        Some(["T1 (T1 D10 FLAT END MILL)", "G0 X10. Z5. (APPROACH)"]),
    ),
    (
        "fanuc0itd",
        Some(["T0001 (T1 D10 FLAT END MILL)", "G0 X10. Z5. (APPROACH)"]),
    ),
    (
        "haaslathe",
        Some(["T0001 (T1 D10 FLAT END MILL)", "G0 X10. Z5. (APPROACH)"]),
    ),
    // Resolved dialects write a block's comment on a line of its own before its words.
    (
        "iso",
        Some(["N20 (T1 D10 FLAT END MILL)", "N40 (APPROACH)"]),
    ),
    ("linuxcnc", Some(["(T1 D10 FLAT END MILL)", "(APPROACH)"])),
    ("fagor8035t", Some(["(T1 D10 FLAT END MILL)", "(APPROACH)"])),
    (
        "sinumerik802d",
        Some(["N30 ; T1 D10 FLAT END MILL", "N50 ; APPROACH"]),
    ),
    ("fms3000", None),
    ("mayak600t", None),
    ("nc31", None),
    ("n33", None),
];

/// Runs PROGRAM (or `text`) in `dialect` with `--verify` and `flags`: the output and standard error.
fn expand(d: &Dir, text: &str, dialect: &str, flags: &[&str]) -> (String, String) {
    d.file("p.nc", text);
    let mut args = vec![
        "run",
        "p.nc",
        "-o",
        "out.nc",
        "--verify",
        "--dialect",
        dialect,
    ];
    // The Н33-2М tape is incremental from where the operator sets the tool.
    args.extend_from_slice(&["--start-point", "X0 Z0"]);
    args.extend_from_slice(flags);
    let o = d.run(&args);
    assert!(o.status.success(), "{dialect}: {}", stderr(&o));
    assert!(
        stderr(&o).contains("verified:"),
        "{dialect}: {}",
        stderr(&o)
    );
    (d.read("out.nc"), stderr(&o))
}

#[test]
fn every_built_in_dialect_is_listed_here() {
    let d = Dir::new();
    let o = d.run(&["dialects"]);
    let listed: Vec<String> = String::from_utf8_lossy(&o.stdout)
        .lines()
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .collect();
    let here: Vec<&str> = DIALECTS.iter().map(|(n, _)| *n).collect();
    assert_eq!(listed.len(), here.len(), "{listed:?}");
    for name in &listed {
        assert!(here.contains(&name.as_str()), "{name} has no comment test");
    }
}

#[test]
fn comments_are_kept_where_the_dialect_has_them_and_said_once_where_not() {
    let d = Dir::new();
    for (dialect, lines) in DIALECTS {
        let (out, err) = expand(&d, PROGRAM, dialect, &[]);
        match lines {
            Some(lines) => {
                for line in lines {
                    assert!(
                        out.lines().any(|l| l.trim_end_matches('\r') == line),
                        "{dialect}: `{line}` in\n{out}"
                    );
                }
                assert!(!err.contains("has no comments"), "{dialect}: {err}");
            }
            None => {
                assert!(!out.contains("FLAT END MILL"), "{dialect}: {out}");
                assert_eq!(
                    err.matches("has no comments: the program's 2 comments are left out")
                        .count(),
                    1,
                    "{dialect}: {err}"
                );
            }
        }
    }
}

#[test]
fn no_comments_drops_them_everywhere_without_a_word() {
    let d = Dir::new();
    for (dialect, _) in DIALECTS {
        let (out, err) = expand(&d, PROGRAM, dialect, &["--no-comments"]);
        assert!(
            !out.contains("FLAT END MILL") && !out.contains("APPROACH"),
            "{dialect}: {out}"
        );
        assert!(!err.contains("comment"), "{dialect}: {err}");
    }
    // The program's name on the O line is the control's directory entry, not a block's comment.
    let (out, _) = expand(&d, PROGRAM, "fanuc", &["--no-comments"]);
    assert!(out.contains("O0012 (BRACKET)"), "{out}");
}

#[test]
fn a_comment_linuxcnc_would_act_on_is_made_inert_and_only_there() {
    let d = Dir::new();
    let text = "G0 X1 (MSG, CHECK THE CLAMP)\n( logopen,/tmp/part.log)\n(PROBEOPEN points.txt)\n(MESSAGE FOR THE OPERATOR)\nM30\n";
    let (out, err) = expand(&d, text, "linuxcnc", &[]);
    // LinuxCNC's G-code overview, "Comments": `(MSG,` shows a message, `(LOGOPEN,` opens a file,
    // `(PROBEOPEN` a probe file; matched without spaces and in any case (Kramer's RS274/NGC §3.3.4).
    for line in [
        "(-MSG, CHECK THE CLAMP)",
        "(- logopen,/tmp/part.log)",
        "(-PROBEOPEN points.txt)",
        "(MESSAGE FOR THE OPERATOR)",
    ] {
        assert!(out.lines().any(|l| l == line), "`{line}` in\n{out}");
    }
    assert!(err.contains("3 comments are written with a `-`"), "{err}");
    // A Fanuc acts on none of them: the text is kept as written.
    let (out, err) = expand(&d, text, "fanuc", &[]);
    assert!(out.contains("G0 X1. (MSG, CHECK THE CLAMP)"), "{out}");
    assert!(!err.contains("`-`"), "{err}");
}

#[test]
fn a_percent_in_a_comment_never_ends_the_transfer() {
    let d = Dir::new();
    let (out, _) = expand(
        &d,
        "O12 (DOME 5%)\nG0 X1 (STEP 40% OF D)\nM30\n",
        "fanuc",
        &[],
    );
    assert!(out.contains("G0 X1. (STEP 40  OF D)"), "{out}");
    // The program's name on the O line too.
    assert!(out.contains("O0012 (DOME 5)"), "{out}");
    // `%` stands only on its own lines, at the two ends.
    let percents: Vec<&str> = out.lines().filter(|l| l.contains('%')).collect();
    assert_eq!(percents, ["%", "%"], "{out}");
}

#[test]
fn a_comment_too_long_for_the_line_is_cut_to_fit() {
    let d = Dir::new();
    let long = "A".repeat(300);
    let text = format!("G0 X1 ({long})\nM30\n");
    // LinuxCNC takes 255 characters and the end of line (its `[blocks] max_length` 256).
    let (out, err) = expand(&d, &text, "linuxcnc", &[]);
    let line = out
        .lines()
        .find(|l| l.starts_with("(AAA"))
        .expect("the comment");
    assert_eq!(line.len() + 1, 256, "{line}");
    assert!(line.ends_with("A)"), "{line}");
    assert!(
        err.contains("1 comment is cut to fit linuxcnc's line of 256"),
        "{err}"
    );
    // The FMS-3000 has none to cut (254 characters, no comments).
    let (out, _) = expand(&d, &text, "fms3000", &[]);
    assert!(!out.contains("AAA"), "{out}");
}
