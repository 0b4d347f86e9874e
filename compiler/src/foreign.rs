//! Programs in another control's language, recognised at their first telling line, so that they
//! are refused with the language named instead of a bare format error further on.
//!
//! Only what no Fanuc-style program writes counts, outside comments: a Swiss-type lathe's path
//! headers and waits (Citizen Cincom, Star: `$1`, `!2L10`), Okuma OSP's variables and statements
//! (`VC1=`, `CALL O…`, `MODIN`, `NLAP`), Heidenhain's conversational `BEGIN PGM`, a SINUMERIK
//! cycle call (`CYCLE95(`).

use crate::{Diagnostic, FileId, Span};

/// A line's text without its comments (`( … )` and what follows `;`), upper case.
fn code_part(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut depth = 0usize;
    for c in line.chars() {
        match c {
            '(' => depth += 1,
            ')' => depth = depth.saturating_sub(1),
            ';' if depth == 0 => break,
            c if depth == 0 => out.push(c.to_ascii_uppercase()),
            _ => {}
        }
    }
    out
}

/// The language a line's code looks like, and the words that tell.
fn looks_like(code: &str) -> Option<(&'static str, &'static str)> {
    let t = code.trim();
    let digits_after = |s: &str, prefix: &str| {
        s.strip_prefix(prefix)
            .is_some_and(|r| !r.is_empty() && r.chars().all(|c| c.is_ascii_digit()))
    };
    const SWISS: &str = "a multi-path Swiss-type lathe program (Citizen Cincom, Star)";
    const OKUMA: &str = "an Okuma OSP program";
    if digits_after(t, "$") {
        return Some((SWISS, "a path header `$n`"));
    }
    if let Some(rest) = t.strip_prefix('!')
        && rest.starts_with(|c: char| c.is_ascii_digit())
        && rest.contains('L')
    {
        return Some((SWISS, "a path wait `!nLm`"));
    }
    let words: Vec<&str> = t
        .split(|c: char| c.is_whitespace() || c == '=' || c == '[' || c == ']')
        .filter(|w| !w.is_empty())
        .collect();
    if t.contains('=') && words.iter().any(|w| digits_after(w, "VC")) {
        return Some((OKUMA, "a common variable `VCn`"));
    }
    if words
        .windows(2)
        .any(|w| w[0] == "CALL" && w[1].starts_with('O'))
    {
        return Some((OKUMA, "a subprogram `CALL O…`"));
    }
    if words.iter().any(|w| *w == "MODIN" || *w == "MODOUT") {
        return Some((OKUMA, "a modal call `MODIN`"));
    }
    if words.iter().any(|w| digits_after(w, "NLAP")) {
        return Some((OKUMA, "a LAP cycle's label `NLAPn`"));
    }
    if t.contains("BEGIN PGM") {
        return Some((
            "a Heidenhain conversational (Klartext) program",
            "`BEGIN PGM`",
        ));
    }
    // The call's own parentheses read as a comment here: the name stands alone.
    if words.iter().any(|w| digits_after(w, "CYCLE")) {
        return Some(("a SINUMERIK program", "a cycle call `CYCLEnn(…)`"));
    }
    None
}

/// The first line of `text` that tells another control's language, as an error at that line.
pub fn detect(file: FileId, text: &str) -> Option<Diagnostic> {
    let mut at = 0usize;
    for line in text.split_inclusive('\n') {
        let start = at;
        at += line.len();
        let body = line.trim_end_matches(['\n', '\r']);
        if let Some((language, telling)) = looks_like(&code_part(body)) {
            let span = Span::new(file, start, start + body.len());
            return Some(
                Diagnostic::error(
                    span,
                    None,
                    format!("this looks like {language}: {telling}"),
                )
                .note("fmsvm reads Fanuc-style Custom Macro B programs (and Haas's, with --control haas or haas-lathe); a program in another control's language is refused at its first line that tells"),
            );
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn language(text: &str) -> Option<(String, u32)> {
        let d = detect(FileId(0), text)?;
        let line = text[..d.span.start as usize].matches('\n').count() as u32 + 1;
        Some((d.message, line))
    }

    #[test]
    fn other_languages_are_named_at_their_first_telling_line() {
        let swiss = "O1000\n(PART)\n$1\nG50 Z0\n!2L10\n$2\nM30\n";
        assert_eq!(
            language(swiss),
            Some((
                "this looks like a multi-path Swiss-type lathe program (Citizen Cincom, Star): a path header `$n`".into(),
                3
            ))
        );
        let okuma = "O1\nG50 S2000\nVC1=10\nIF [VC1 EQ 10] N100\nM02\n";
        assert_eq!(language(okuma).map(|l| l.1), Some(3));
        assert!(language(okuma).is_some_and(|l| l.0.contains("Okuma OSP")));
        assert!(language("O2\nCALL OSUB1\n").is_some_and(|l| l.0.contains("CALL O")));
        assert!(language("0 BEGIN PGM P1 MM\n").is_some_and(|l| l.0.contains("Heidenhain")));
        assert!(
            language("N10 CYCLE95(\"KONTUR\",2,0,0.5)\n")
                .is_some_and(|l| l.0.contains("SINUMERIK"))
        );
    }

    #[test]
    fn fanuc_and_haas_programs_and_comments_are_not_mistaken() {
        for text in [
            "O1\n#1=10 (VC1=10 in a comment)\nG65 P9010 A1.\nM30\n",
            "O1\n#100=[#1+2]\nIF [#100 EQ 3] GOTO 10\nN10 M30\n",
            "%\nO0001 ($1 PATH)\nG0 X0 ; $1\nM30\n%\n",
            "O1\nDPRNT[X#5001[44]]\nM30\n",
            "O1\nG1 X10. F100 (CYCLE81(1))\nM30\n",
        ] {
            assert_eq!(language(text), None, "{text}");
        }
    }
}
