//! The base protocol's frames, as the language server and the debugger read them: `Content-Length`
//! headers read with bounds, a body of at most [`MAX_BODY`] bytes. A broken frame is said (and the
//! stream read on from the next header); only the end of the input or a failed read ends it.

use std::io::{self, BufRead, Read};

/// The largest body taken (a document of [`MAX_BODY`] is far above any part program).
pub const MAX_BODY: usize = 64 << 20;
/// The longest header line, and the most header lines of one frame.
const MAX_LINE: usize = 4096;
const MAX_HEADERS: usize = 32;

/// What one read gives.
#[derive(Debug)]
pub enum Frame {
    /// A body (its bytes as sent; see [`json`]).
    Body(Vec<u8>),
    /// Not a frame, and why; the stream goes on at the next header.
    Bad(String),
    /// The input ended.
    End,
    /// Reading failed.
    Failed(io::Error),
}

/// Reads one header line (without its end, `\r\n` or `\n`), at most [`MAX_LINE`] bytes of it kept;
/// None at the end of the input.
fn line(input: &mut impl BufRead) -> io::Result<Option<(String, bool)>> {
    let mut buf = Vec::new();
    let mut long = false;
    loop {
        let chunk = input.fill_buf()?;
        if chunk.is_empty() {
            let long = long || buf.len() > MAX_LINE;
            return Ok(
                (!buf.is_empty()).then(|| (String::from_utf8_lossy(&buf).into_owned(), long))
            );
        }
        let (take, done) = match chunk.iter().position(|&b| b == b'\n') {
            Some(i) => (i + 1, true),
            None => (chunk.len(), false),
        };
        // The line's end (`\n`, and a `\r` before it) does not count against its length.
        let text = if done { take - 1 } else { take };
        let room = (MAX_LINE + 1).saturating_sub(buf.len());
        buf.extend_from_slice(&chunk[..text.min(room)]);
        long |= text > room;
        input.consume(take);
        if done {
            if buf.last() == Some(&b'\r') {
                buf.pop();
            }
            long |= buf.len() > MAX_LINE;
            return Ok(Some((String::from_utf8_lossy(&buf).into_owned(), long)));
        }
    }
}

/// Reads the next frame.
pub fn read(input: &mut impl BufRead) -> Frame {
    let mut length: Option<Result<usize, String>> = None;
    let mut headers = 0;
    loop {
        let (text, long) = match line(input) {
            Ok(Some(l)) => l,
            Ok(None) => return Frame::End,
            Err(e) => return Frame::Failed(e),
        };
        if text.is_empty() {
            if headers == 0 {
                continue;
            }
            break;
        }
        headers += 1;
        if long || headers > MAX_HEADERS {
            return Frame::Bad(format!(
                "a header longer than {MAX_LINE} bytes, or more than {MAX_HEADERS} headers"
            ));
        }
        // A broken body before this header runs into it: the header starts where its name does.
        let Some(at) = text.find("Content-Length:") else {
            continue;
        };
        let value = text[at + "Content-Length:".len()..].trim();
        length = Some(
            value
                .parse::<usize>()
                .map_err(|_| format!("Content-Length `{value}` is not a length in bytes")),
        );
    }
    let length = match length {
        None => return Frame::Bad("a frame without Content-Length".into()),
        Some(Err(e)) => return Frame::Bad(e),
        Some(Ok(n)) => n,
    };
    if length > MAX_BODY {
        // Passed by without being held: the stream goes on after it.
        return match io::copy(&mut input.take(length as u64), &mut io::sink()) {
            Ok(_) => Frame::Bad(format!(
                "a body of {length} bytes, above the {MAX_BODY} taken"
            )),
            Err(e) => Frame::Failed(e),
        };
    }
    let mut body = vec![0u8; length];
    match input.read_exact(&mut body) {
        Ok(()) => Frame::Body(body),
        Err(e) if e.kind() == io::ErrorKind::UnexpectedEof => Frame::End,
        Err(e) => Frame::Failed(e),
    }
}

/// A body as JSON. A lone UTF-16 surrogate escape (`\ud800` without its pair, as JavaScript's
/// `JSON.stringify` writes a string cut inside a pair) is read as U+FFFD, not refused.
pub fn json(body: &[u8]) -> Result<serde_json::Value, serde_json::Error> {
    serde_json::from_slice(body).or_else(|e| {
        let mended = mend_surrogates(body);
        if mended == body {
            Err(e)
        } else {
            serde_json::from_slice(&mended)
        }
    })
}

/// `body` with every lone surrogate escape replaced by `\ufffd`.
fn mend_surrogates(body: &[u8]) -> Vec<u8> {
    let unit = |at: usize| -> Option<u16> {
        let hex = body.get(at + 2..at + 6)?;
        (body.get(at) == Some(&b'\\') && body.get(at + 1) == Some(&b'u'))
            .then(|| u16::from_str_radix(std::str::from_utf8(hex).ok()?, 16).ok())
            .flatten()
    };
    let mut out = Vec::with_capacity(body.len());
    let mut i = 0;
    while i < body.len() {
        if body[i] != b'\\' {
            out.push(body[i]);
            i += 1;
            continue;
        }
        match unit(i) {
            Some(high @ 0xD800..=0xDBFF) if matches!(unit(i + 6), Some(0xDC00..=0xDFFF)) => {
                let _ = high;
                out.extend_from_slice(&body[i..i + 12]);
                i += 12;
            }
            Some(0xD800..=0xDFFF) => {
                out.extend_from_slice(b"\\ufffd");
                i += 6;
            }
            // Any other escape, the backslash's own (`\\`) included, as it is.
            _ => {
                out.extend_from_slice(&body[i..(i + 2).min(body.len())]);
                i += 2;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frames(input: &[u8]) -> Vec<String> {
        let mut r = io::BufReader::new(input);
        let mut out = Vec::new();
        loop {
            match read(&mut r) {
                Frame::Body(b) => out.push(format!("body {}", String::from_utf8_lossy(&b))),
                Frame::Bad(why) => out.push(format!("bad {why}")),
                Frame::End => return out,
                Frame::Failed(e) => panic!("{e}"),
            }
        }
    }

    #[test]
    fn frames_with_crlf_or_lf_and_bad_ones_between() {
        let input =
            b"Content-Length: 2\r\n\r\n{}Content-Length: -5\r\n\r\nContent-Length: 5\n\n[1,2]";
        assert_eq!(
            frames(input),
            [
                "body {}",
                "bad Content-Length `-5` is not a length in bytes",
                "body [1,2]",
            ]
        );
        // A body above the bound is passed by, not held: what follows it in the stream is read.
        let mut huge = b"Content-Length: 70000000\r\n\r\n".to_vec();
        huge.resize(huge.len() + 70_000_000, b' ');
        huge.extend_from_slice(b"Content-Length: 2\r\n\r\n{}");
        assert_eq!(
            frames(&huge),
            [
                "bad a body of 70000000 bytes, above the 67108864 taken",
                "body {}"
            ]
        );
        // A header of the most bytes, its line end not counted against it.
        let mut long = b"Content-Length: 2".to_vec();
        long.extend(std::iter::repeat_n(b' ', MAX_LINE - long.len()));
        long.extend_from_slice(b"\r\n\r\n{}");
        assert_eq!(frames(&long), ["body {}"]);
        // A body cut short is the end of the input; a frame without a length is said.
        assert_eq!(frames(b"Content-Length: 9\r\n\r\n{}"), Vec::<String>::new());
        assert_eq!(
            frames(b"X-Other: 1\r\n\r\n"),
            ["bad a frame without Content-Length"]
        );
    }

    #[test]
    fn lone_surrogates_read_as_the_replacement_character() {
        let v = json(br#"{"text":"a\ud800b\ud83d\ude00c\\ud800"}"#).expect("reads");
        assert_eq!(v["text"], "a\u{fffd}b\u{1f600}c\\ud800");
        assert!(json(b"{not json").is_err());
    }
}
