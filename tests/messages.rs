//! What the messages say: never an empty text or note, what was probably meant, the right file and
//! column, long lines cut around the error, counts in the right number, the O line's program name in the
//! output.

use std::path::Path;

use crate::cli_support;

use cli_support::Dir;

/// Runs `text` as `p.nc` to standard output: exit code, standard output, standard error.
fn program(d: &Dir, text: &str, flags: &[&str]) -> (Option<i32>, String, String) {
    d.file("p.nc", text);
    let mut args = vec!["run", "p.nc"];
    args.extend_from_slice(flags);
    let o = d.run(&args);
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// No headline without text, no note without text.
fn assert_no_empty_text(stderr: &str) {
    for line in stderr.lines() {
        let t = line.trim_end();
        assert!(
            !t.ends_with("note:") && !t.ends_with("note: expected") && !t.ends_with("]:"),
            "an empty text in `{line}`:\n{stderr}"
        );
    }
}

#[test]
fn no_message_or_note_is_empty() {
    let d = Dir::new();
    // A statement followed by more text: LALRPOP expects nothing but the end of the block there.
    for src in [
        "DO1 2\n",
        "POPEN 1\n",
        "END1 X\nDO1\n",
        "GOTO5 X1\nN5 M30\n",
        "#1=[2+3]]\n",
        "#3000=5\n",
        "#3000=5()\n",
        "#3006=1\nM30\n",
    ] {
        let (code, _, err) = program(&d, src, &[]);
        assert!(code.is_some(), "{src}");
        assert_no_empty_text(&err);
    }
    let (code, _, err) = program(&d, "DO1 2\n", &[]);
    assert_eq!(code, Some(3));
    assert!(
        err.contains("= note: this cannot continue the block"),
        "{err}"
    );
    let (_, _, err) = program(&d, "#1=[2+3]]\n", &[]);
    assert!(err.contains("this `]` closes nothing"), "{err}");
}

#[test]
fn macro_alarm_and_message_without_text() {
    let d = Dir::new();
    let (code, _, err) = program(&d, "#3000=5\n", &[]);
    assert_eq!(code, Some(4));
    assert!(
        err.lines()
            .any(|l| l == "error[alarm 3005]: macro alarm (no message)"),
        "{err}"
    );
    // Two comments make one message, each without its parentheses.
    let (code, _, err) = program(&d, "#3000=7(TOOL)(BROKEN)\n", &[]);
    assert_eq!(code, Some(4));
    assert!(
        err.lines().any(|l| l == "error[alarm 3007]: TOOL BROKEN"),
        "{err}"
    );
    let (code, out, err) = program(&d, "#3006=1\nM30\n", &[]);
    assert_eq!(code, Some(0));
    assert!(err.contains("message 1: (no message)"), "{err}");
    assert!(out.contains("M0 (MESSAGE 1: no message)"), "{out}");
}

#[test]
fn relational_operator_misspellings_say_what_was_meant() {
    let d = Dir::new();
    for (word, meant) in [
        ("LTE", "LE"),
        ("GTE", "GE"),
        ("GEQ", "GE"),
        ("LEQ", "LE"),
        ("NEQ", "NE"),
        ("EQU", "EQ"),
        ("LTT", "LT"),
        ("gte", "GE"),
    ] {
        let (code, _, err) = program(&d, &format!("IF[#1 {word} 2]GOTO5\nN5 M30\n"), &[]);
        assert_eq!(code, Some(3), "{word}");
        let want = format!(
            "error[alarm 0114]: format error: `{}` is not an operator; did you mean `{meant}`?",
            word.to_ascii_uppercase()
        );
        assert!(err.lines().any(|l| l == want), "{word}: {err}");
        // The caret runs under the whole word.
        assert!(err.contains(" --> p.nc:1:7\n"), "{word}: {err}");
        assert!(err.contains("  |       ^^^ here"), "{word}: {err}");
    }
    // Glued to its operands as Fanuc allows.
    let (_, _, err) = program(&d, "IF[#1LTE2]GOTO5\nN5 M30\n", &[]);
    assert!(err.contains("did you mean `LE`?"), "{err}");
    // A separate letter after a correct operator is no misspelling.
    let (code, _, err) = program(&d, "IF[#1 LT E2]GOTO5\nN5 M30\n", &[]);
    assert_eq!(code, Some(3));
    assert!(!err.contains("did you mean"), "{err}");
    assert!(err.contains("unexpected address `E`"), "{err}");
}

#[test]
fn an_unclosed_bracket_is_pointed_at() {
    let d = Dir::new();
    let (code, _, err) = program(&d, "#1=[2+3\n", &[]);
    assert_eq!(code, Some(3));
    assert!(
        err.contains(
            "error[alarm 0114]: format error: `[` is not closed: the block ends before its `]`\n --> p.nc:1:4\n  |\n1 | #1=[2+3\n  |    ^ here\n"
        ),
        "{err}"
    );
    // The innermost open bracket.
    let (_, _, err) = program(&d, "#1=[1+[2+3]*[4\n", &[]);
    assert!(err.contains(" --> p.nc:1:13\n"), "{err}");
    // Stopped by another token: the message names it, a note the open bracket.
    let (_, _, err) = program(&d, "IF[#1 EQ 2 GOTO5\nN5 M30\n", &[]);
    assert!(err.contains("unexpected `GOTO`"), "{err}");
    assert!(err.contains("the `[` at column 3 is not closed"), "{err}");
}

#[test]
fn the_nct_hint_names_the_word_written() {
    let d = Dir::new();
    let (code, _, err) = program(&d, "G0 YI10\n", &[]);
    assert_eq!(code, Some(3));
    assert!(
        err.contains("`YI10` is NCT's incremental operator"),
        "{err}"
    );
    assert!(err.contains("G91 Y10"), "{err}");
    assert!(!err.contains("XI"), "{err}");
    let (_, _, err) = program(&d, "G81 ZI-5. R1.\n", &[]);
    assert!(err.contains("`ZI-5.`") && err.contains("G91 Z-5."), "{err}");
}

#[test]
fn errors_in_a_library_program_name_its_file() {
    let d = Dir::new();
    d.file("lib/O9001.nc", "%\nO9001\nG0 X1\n#1=[2+\nM99\n%\n");
    d.file("lib/O9002.nc", "%\nO9002\nG0 X1\n#1=SQRT[-1]\nM99\n%\n");
    d.file("a.nc", "M98 P9001\nM30\n");
    d.file("b.nc", "M98 P9002\nM30\n");
    // A library program fmsvm cannot read stops the run only when it is called (a control reads
    // a program when it runs it: docs/semantics.md, "Library programs"): the error is a warning
    // at its line, and the call raises its alarm, naming the file, line and column.
    let o = d.run(&["run", "a.nc", "--lib", "lib"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(4), "{err}");
    let lib = Path::new("lib").join("O9001.nc");
    let lib = lib.display();
    assert!(err.contains(&format!(" --> {lib}:4:4\n")), "{err}");
    assert!(
        err.contains(&format!("O9001 cannot be read: {lib}:4:4:")),
        "{err}"
    );
    let o = d.run(&["run", "b.nc", "--lib", "lib"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(4), "{err}");
    let lib = Path::new("lib").join("O9002.nc");
    assert!(
        err.contains(&format!(" --> {}:4:4\n", lib.display())),
        "{err}"
    );
    assert!(err.contains("SQRT[-1]"), "{err}");
}

#[test]
fn a_negative_program_number_is_alarm_0006() {
    let d = Dir::new();
    let (code, _, err) = program(&d, "M98 P-2\n", &[]);
    assert_eq!(code, Some(3), "a literal is refused before running");
    assert!(
        err.contains("error[alarm 0006]: illegal use of minus sign: P takes no sign"),
        "{err}"
    );
    let (code, _, err) = program(&d, "G65 P-9000 A1.\n", &[]);
    assert_eq!(code, Some(3), "{err}");
    let (code, _, err) = program(&d, "M98 P100 L-1\nM30\nO100\nM99\n", &[]);
    assert_eq!(code, Some(3), "{err}");
    assert!(err.contains("L takes no sign"), "{err}");
    // A computed one when the call runs.
    let (code, _, err) = program(&d, "#1=-2\nM98 P#1\n", &[]);
    assert_eq!(code, Some(4));
    assert!(
        err.contains("error[alarm 0006]: illegal use of minus sign: P-2"),
        "{err}"
    );
    let (code, _, err) = program(&d, "#2=-1\nM98 P100 L#2\nM30\nO100\nM99\n", &[]);
    assert_eq!(code, Some(4));
    assert!(err.contains("illegal use of minus sign: L-1"), "{err}");
}

#[test]
fn counts_are_singular_for_one() {
    let d = Dir::new();
    let (code, _, err) = program(&d, "WHILE[1 EQ 1]DO1\nEND1\n", &["--max-steps", "1"]);
    assert_eq!(code, Some(5));
    assert!(
        err.contains("error: limit of 1 step (branch taken) reached"),
        "{err}"
    );
    let (code, _, err) = program(
        &d,
        "WHILE[1 EQ 1]DO1\nEND1\n",
        &["--max-steps", "0", "--max-seconds", "1"],
    );
    assert_eq!(code, Some(5));
    assert!(
        err.contains("error: limit of 1 second of wall time reached"),
        "{err}"
    );
    let (code, _, err) = program(
        &d,
        "WHILE[1 EQ 1]DO1\nG1 X1\nEND1\n",
        &["--max-blocks", "1"],
    );
    assert_eq!(code, Some(5));
    assert!(err.contains("limit of 1 output block reached"), "{err}");
    // The block refused is not counted as written.
    assert!(err.contains("stopped after 1 block;"), "{err}");
    let (code, _, err) = program(&d, "G0 X1\n#3000=1(STOP)\n", &[]);
    assert_eq!(code, Some(4));
    assert!(err.contains("stopped after 1 block;"), "{err}");
    let (code, _, err) = program(&d, "G0 X1\nG0 X2\n#1=1000000\nG1 X[#1*#1]\n", &[]);
    assert_eq!(code, Some(4));
    assert!(err.contains("stopped after 2 blocks;"), "{err}");
    let (code, _, err) = program(&d, "#1=[1\n", &[]);
    assert_eq!(code, Some(3));
    assert!(err.contains("error: 1 error in p.nc"), "{err}");
    let (_, _, err) = program(&d, "#1=[1\n#2=[2\n", &[]);
    assert!(err.contains("error: 2 errors in p.nc"), "{err}");
}

/// The shown source line and the caret line of a rendered message (without their gutters).
fn source_and_caret(err: &str, line: usize) -> (String, String) {
    let prefix = format!("{line} | ");
    let lines: Vec<&str> = err.lines().collect();
    let i = lines
        .iter()
        .position(|l| l.starts_with(&prefix))
        .unwrap_or_else(|| panic!("no source line in {err}"));
    let pad = " ".repeat(line.to_string().len());
    let caret = lines[i + 1]
        .strip_prefix(&format!("{pad} | "))
        .unwrap_or_else(|| panic!("no caret line in {err}"));
    (lines[i][prefix.len()..].to_string(), caret.to_string())
}

#[test]
fn long_lines_are_cut_around_the_error() {
    let d = Dir::new();
    // A 400-character line of which the error is at character 301 (after multi-byte characters).
    let long_comment = format!("({})", "ÄÖ".repeat(149));
    let src = format!("G1 X1 {long_comment} $ {}\n", "Y2 ".repeat(30));
    let col = long_comment.chars().count() + 8;
    let (code, _, err) = program(&d, &src, &[]);
    assert_eq!(code, Some(3));
    assert!(err.contains(&format!(" --> p.nc:1:{col}\n")), "{err}");
    let (shown, caret) = source_and_caret(&err, 1);
    assert!(
        shown.chars().count() <= 102,
        "{} characters shown",
        shown.chars().count()
    );
    assert!(shown.starts_with('…') && shown.ends_with('…'), "{shown}");
    let dollar = shown.chars().position(|c| c == '$');
    let hat = caret.chars().position(|c| c == '^');
    assert!(dollar.is_some());
    assert_eq!(dollar, hat, "\n{shown}\n{caret}");
    // Near the start of a long line: cut at the end only.
    let src = format!("G1 X1 $ {}\n", "Y2 ".repeat(60));
    let (_, _, err) = program(&d, &src, &[]);
    let (shown, caret) = source_and_caret(&err, 1);
    assert!(
        shown.starts_with("G1 X1 $") && shown.ends_with('…'),
        "{shown}"
    );
    assert_eq!(caret.find('^'), Some(6));
    // Short lines are shown whole.
    let (_, _, err) = program(&d, "G1 X1 $\n", &[]);
    assert_eq!(source_and_caret(&err, 1).0, "G1 X1 $");
}

#[test]
fn after_fifty_errors_the_rest_are_counted() {
    let d = Dir::new();
    let src = "#34=1\n".repeat(53);
    let (code, _, err) = program(&d, &src, &[]);
    assert_eq!(code, Some(3));
    let shown = err
        .lines()
        .filter(|l| l.starts_with("error[alarm 0115]"))
        .count();
    assert_eq!(shown, 50, "{err}");
    assert!(
        err.lines()
            .any(|l| l == "error: 3 more errors not shown (only the first 50 errors are)"),
        "{err}"
    );
    assert!(
        err.contains("error: 53 errors in p.nc; nothing was run"),
        "{err}"
    );
    // Exactly fifty: no such line.
    let (_, _, err) = program(&d, &"#34=1\n".repeat(50), &[]);
    assert!(!err.contains("not shown"), "{err}");
}

#[test]
fn percent_inside_a_line_and_files_without_blocks() {
    let d = Dir::new();
    for src in [
        "G0 X1 % G1 X2\nM30\n",
        "G0 X1\nM30 %\n",
        "%G0 X1\nM30\n%\n",
        "G0 X1\nM30\n% G1\n",
    ] {
        let (code, _, err) = program(&d, src, &[]);
        assert_eq!(code, Some(3), "{src}");
        assert!(
            err.contains("error: `%` inside a block: the tape marker stands on a line of its own"),
            "{src}: {err}"
        );
    }
    // A comment after `%`, and text on the lines after the closing `%`, are fine.
    let (code, out, err) = program(
        &d,
        "% (PART 12)\nG0 X1\nM30\n% (END)\nNOTES ]]] 1.2\n",
        &["--no-comments"],
    );
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(out, "%\nG0 X1.\nM30\n%\n");
    let (code, _, err) = program(&d, "(SETUP SHEET)\n\n(ONLY COMMENTS)\n", &[]);
    assert_eq!(code, Some(3));
    assert!(err.contains("the file holds no program"), "{err}");
}

/// True when no comment in `text` nests another or is left open.
fn comments_are_flat(text: &str) -> bool {
    text.lines().all(|l| {
        let mut open = false;
        for c in l.chars() {
            match c {
                '(' if open => return false,
                '(' => open = true,
                ')' if !open => return false,
                ')' => open = false,
                _ => {}
            }
        }
        !open
    })
}

#[test]
fn the_program_name_comment_is_kept() {
    let d = Dir::new();
    let (code, out, err) = program(
        &d,
        "%\nO7118 (HEMISPHERE)\nG0 X1 (RAPID)\nM30\n%\n",
        &["--no-comments"],
    );
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(out, "%\nO7118 (HEMISPHERE)\nG0 X1.\nM30\n%\n");
    let (_, out, _) = program(
        &d,
        "%\nO7118 (HEMISPHERE)\nG0 X1 (RAPID)\nM30\n%\n",
        &["--comments"],
    );
    assert_eq!(out, "%\nO7118 (HEMISPHERE)\nG0 X1. (RAPID)\nM30\n%\n");
    // Nested and several comments become one flat comment.
    let (_, out, _) = program(
        &d,
        "%\nO5 (PART (A) (REV 2)\nG0 X1 (A (B)\nM30\n%\n",
        &["--comments"],
    );
    assert!(out.starts_with("%\nO0005 (PART A REV 2)\n"), "{out}");
    assert!(comments_are_flat(&out), "{out}");
    // An empty title adds nothing.
    let (_, out, _) = program(&d, "%\nO5 ()\nM30\n%\n", &[]);
    assert_eq!(out, "%\nO0005\nM30\n%\n");
}
