//! Input files: read with a size bound (`--max-input`), and text decoded from the character set the shop
//! has: UTF-8 (a BOM accepted), or the single-byte sets of Russian and European controls (CP1251, CP866,
//! KOI8-R, Latin-1), named with `--encoding` or guessed where only comments hold non-ASCII bytes.

use std::fmt;
use std::io::{self, Read};
use std::path::Path;

/// Why an input could not be read.
#[derive(Debug)]
pub enum ReadError {
    /// The file system said no.
    Io(io::Error),
    /// The input is longer than the bound.
    TooBig(u64),
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReadError::Io(e) => e.fmt(f),
            ReadError::TooBig(n) => write!(
                f,
                "it is larger than {} (--max-input {n}); raise --max-input if it is meant to be read",
                human(*n)
            ),
        }
    }
}

/// `n` bytes for people: `256 MiB`, `1000 bytes`.
pub fn human(n: u64) -> String {
    match n {
        n if n >= 1 << 30 && n % (1 << 30) == 0 => format!("{} GiB", n >> 30),
        n if n >= 1 << 20 && n % (1 << 20) == 0 => format!("{} MiB", n >> 20),
        n if n >= 1 << 10 && n % (1 << 10) == 0 => format!("{} KiB", n >> 10),
        1 => "1 byte".into(),
        n => format!("{n} bytes"),
    }
}

/// The most a settings file (a dialect profile, parameters, offsets, probe points) may hold: they
/// are small, and a TOML reader takes many bytes of memory a byte.
pub const MAX_SETTINGS: u64 = 1 << 20;

/// The most bytes an input file may hold unless the request says otherwise (`--max-input`).
pub const DEFAULT_MAX_INPUT: u64 = 256 << 20;

/// Reads a file a flag names that must be a regular file: a FIFO would hold the read until a writer
/// comes, and a device may never end. At most `max` bytes.
pub fn read_regular(path: &Path, max: u64) -> Result<Vec<u8>, ReadError> {
    require_regular(path)?;
    read_bounded(path, max)
}

/// `path` is a regular file (not a folder, a FIFO or a device), else why not.
pub fn require_regular(path: &Path) -> Result<(), ReadError> {
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() => Ok(()),
        Ok(m) if m.is_dir() => Err(ReadError::Io(io::Error::new(
            io::ErrorKind::IsADirectory,
            "it is a folder, not a file",
        ))),
        Ok(_) => Err(ReadError::Io(io::Error::other(
            "it is not a regular file (a FIFO or a device): give a file",
        ))),
        Err(e) => Err(ReadError::Io(e)),
    }
}

/// Reads at most `max` bytes of `path` (`-` = standard input); more is an error, never a bigger buffer.
pub fn read_bounded(path: &Path, max: u64) -> Result<Vec<u8>, ReadError> {
    let mut buf = Vec::new();
    let n = if path.as_os_str() == "-" {
        io::stdin()
            .lock()
            .take(max.saturating_add(1))
            .read_to_end(&mut buf)
    } else {
        let file = std::fs::File::open(path).map_err(ReadError::Io)?;
        if file.metadata().is_ok_and(|m| m.is_dir()) {
            return Err(ReadError::Io(io::Error::new(
                io::ErrorKind::IsADirectory,
                "it is a folder, not a file",
            )));
        }
        file.take(max.saturating_add(1)).read_to_end(&mut buf)
    }
    .map_err(ReadError::Io)?;
    if n as u64 > max {
        return Err(ReadError::TooBig(max));
    }
    Ok(buf)
}

/// A character set of input or output text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Charset {
    /// UTF-8.
    Utf8,
    /// Windows-1251 (Cyrillic, Windows).
    Cp1251,
    /// IBM866 (Cyrillic, DOS).
    Cp866,
    /// KOI8-R.
    Koi8R,
    /// ISO 8859-1.
    Latin1,
    /// 7-bit ASCII: every other character becomes `?`.
    Ascii,
}

impl Charset {
    /// The name the command line uses.
    pub fn name(self) -> &'static str {
        match self {
            Charset::Utf8 => "utf-8",
            Charset::Cp1251 => "cp1251",
            Charset::Cp866 => "cp866",
            Charset::Koi8R => "koi8-r",
            Charset::Latin1 => "latin1",
            Charset::Ascii => "ascii",
        }
    }

    /// The characters of bytes 0x80–0xFF, for a single-byte set.
    fn high_half(self) -> Option<[char; 128]> {
        let enc = match self {
            Charset::Utf8 => return None,
            // No byte above 0x7F: the table holds only NUL, which is ASCII and never looked up.
            Charset::Ascii => return Some(['\0'; 128]),
            Charset::Latin1 => {
                return Some(std::array::from_fn(|i| {
                    char::from_u32(0x80 + i as u32).unwrap_or('?')
                }));
            }
            Charset::Cp1251 => encoding_rs::WINDOWS_1251,
            Charset::Cp866 => encoding_rs::IBM866,
            Charset::Koi8R => encoding_rs::KOI8_R,
        };
        let bytes: Vec<u8> = (0x80..=0xFF).collect();
        let (text, _) = enc.decode_without_bom_handling(&bytes);
        let chars: Vec<char> = text.chars().collect();
        let mut out = ['?'; 128];
        for (o, c) in out.iter_mut().zip(chars) {
            *o = c;
        }
        Some(out)
    }
}

/// Decoded program text.
#[derive(Debug)]
pub struct Decoded {
    /// The text.
    pub text: String,
    /// The character set it was read in.
    pub charset: Charset,
    /// Set when the character set was guessed: the warning to show.
    pub guessed: Option<String>,
}

/// Why bytes are not text.
#[derive(Debug, PartialEq, Eq)]
pub struct NotText {
    /// 1-based line and column (in characters) of the first offending byte.
    pub line: usize,
    /// Column.
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

const CYRILLIC: [Charset; 3] = [Charset::Cp1251, Charset::Cp866, Charset::Koi8R];

/// Decodes `bytes` in `charset`, or (None) as UTF-8, guessing a Cyrillic set when UTF-8 fails and every
/// non-ASCII byte sits inside a `( … )` comment.
/// UTF-8 text takes over the buffer (a large program is not copied).
pub fn decode(mut bytes: Vec<u8>, charset: Option<Charset>) -> Result<Decoded, NotText> {
    if bytes.starts_with(b"\xEF\xBB\xBF") {
        bytes.drain(..3);
    }
    match charset {
        Some(Charset::Utf8) => utf8(bytes)
            .map(|text| Decoded {
                text,
                charset: Charset::Utf8,
                guessed: None,
            })
            .map_err(|(e, _)| e),
        Some(c) => Ok(Decoded {
            text: single_byte(&bytes, c),
            charset: c,
            guessed: None,
        }),
        None => match utf8(bytes) {
            Ok(text) => Ok(Decoded {
                text,
                charset: Charset::Utf8,
                guessed: None,
            }),
            Err((_, bytes)) => {
                let bytes = bytes.as_slice();
                if let Some((line, column, b)) = high_outside_comments(bytes) {
                    let high = bytes.iter().filter(|&&b| b >= 0x80).count();
                    // EIA RS-244 tape code sets the eighth bit on most characters (odd parity).
                    let message = if high * 2 > bytes.len() {
                        format!(
                            "the file looks EIA-coded (RS-244, eighth bit set on {high} of {} bytes); convert it to ISO/ASCII first",
                            bytes.len()
                        )
                    } else {
                        format!(
                            "byte 0x{b:02X} outside a comment is not UTF-8 text; if the file is in CP1251, CP866 or KOI8-R, name it with --encoding"
                        )
                    };
                    return Err(NotText {
                        line,
                        column,
                        message,
                    });
                }
                let best = CYRILLIC
                    .iter()
                    .copied()
                    .max_by(|a, b| score(bytes, *a).total_cmp(&score(bytes, *b)))
                    .unwrap_or(Charset::Cp1251);
                Ok(Decoded {
                    text: single_byte(bytes, best),
                    charset: best,
                    guessed: Some(format!(
                        "not UTF-8; the comments were read as {} (a guess: --encoding utf-8|cp1251|cp866|koi8-r|latin1 names it)",
                        best.name().to_uppercase()
                    )),
                })
            }
        },
    }
}

/// Strict UTF-8, with the position of the first bad byte (and the bytes back, to read otherwise).
fn utf8(bytes: Vec<u8>) -> Result<String, (NotText, Vec<u8>)> {
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let bytes = e.into_bytes();
        let (line, column) = position(&bytes, at);
        let error = NotText {
            line,
            column,
            message: format!(
                "byte 0x{:02X} is not UTF-8 text (--encoding names another character set)",
                bytes[at]
            ),
        };
        (error, bytes)
    })
}

/// Line and column (in characters of the valid prefix) of byte `at`.
fn position(bytes: &[u8], at: usize) -> (usize, usize) {
    let before = &bytes[..at];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    let column = String::from_utf8_lossy(&before[start..]).chars().count() + 1;
    (line, column)
}

/// The first non-ASCII byte that is not inside a `( … )` comment: line, column, byte.
fn high_outside_comments(bytes: &[u8]) -> Option<(usize, usize, u8)> {
    let (mut line, mut column, mut depth) = (1, 1, 0u32);
    for &b in bytes {
        match b {
            b'\n' => {
                line += 1;
                column = 0;
                depth = 0;
            }
            b'(' => depth += 1,
            b')' => depth = depth.saturating_sub(1),
            b if b >= 0x80 && depth == 0 => return Some((line, column, b)),
            _ => {}
        }
        column += 1;
    }
    None
}

fn single_byte(bytes: &[u8], c: Charset) -> String {
    let Some(high) = c.high_half() else {
        return String::from_utf8_lossy(bytes).into_owned();
    };
    bytes
        .iter()
        .map(|&b| {
            if b < 0x80 {
                b as char
            } else {
                high[(b - 0x80) as usize]
            }
        })
        .collect()
}

/// Russian letter frequencies (per mille, lower case а…я then ё).
const FREQUENCY: [f64; 33] = [
    80.1, 15.9, 45.4, 17.0, 29.8, 84.5, 9.4, 16.5, 73.5, 12.1, 34.9, 44.0, 32.1, 67.0, 109.7, 28.1,
    47.3, 54.7, 62.6, 26.2, 2.6, 9.7, 4.8, 14.4, 7.3, 3.6, 0.4, 19.0, 17.4, 3.2, 6.4, 20.1, 0.4,
];

/// How much the non-ASCII bytes read in `c` look like Russian text: a log-likelihood of their letters.
fn score(bytes: &[u8], c: Charset) -> f64 {
    let Some(high) = c.high_half() else {
        return f64::NEG_INFINITY;
    };
    bytes
        .iter()
        .filter(|&&b| b >= 0x80)
        .map(|&b| {
            let ch = high[(b - 0x80) as usize];
            let lower = ch.to_lowercase().next().unwrap_or(ch);
            let i = match lower {
                'а'..='я' => lower as usize - 'а' as usize,
                'ё' => 32,
                _ => return -12.0,
            };
            (FREQUENCY[i] / 1000.0).ln()
        })
        .sum()
}

/// Encodes UTF-8 text into a single-byte set: a writer in front of another, for outputs written in the
/// shop's character set. ASCII passes through; a character the set lacks becomes `?`.
pub struct Encode<W: io::Write> {
    inner: W,
    table: Option<Vec<(char, u8)>>,
    carry: Vec<u8>,
    out: Vec<u8>,
}

impl<W: io::Write> Encode<W> {
    /// Encodes into `charset` (UTF-8: passes everything through).
    pub fn new(inner: W, charset: Charset) -> Self {
        let table = charset.high_half().map(|h| {
            let mut t: Vec<(char, u8)> = h
                .iter()
                .enumerate()
                .map(|(i, &c)| (c, 0x80 + i as u8))
                .collect();
            t.sort();
            t
        });
        Encode {
            inner,
            table,
            carry: Vec::new(),
            out: Vec::new(),
        }
    }
}

impl<W: io::Write> io::Write for Encode<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let Some(table) = &self.table else {
            return self.inner.write(buf);
        };
        if self.carry.is_empty() && buf.is_ascii() {
            self.inner.write_all(buf)?;
            return Ok(buf.len());
        }
        self.carry.extend_from_slice(buf);
        let valid = match std::str::from_utf8(&self.carry) {
            Ok(_) => self.carry.len(),
            Err(e) if e.error_len().is_none() => e.valid_up_to(),
            Err(e) => e.valid_up_to() + e.error_len().unwrap_or(1),
        };
        self.out.clear();
        for c in String::from_utf8_lossy(&self.carry[..valid]).chars() {
            if c.is_ascii() {
                self.out.push(c as u8);
            } else {
                let b = table
                    .binary_search_by(|(k, _)| k.cmp(&c))
                    .map_or(b'?', |i| table[i].1);
                self.out.push(b);
            }
        }
        self.carry.drain(..valid);
        self.inner.write_all(&self.out)?;
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn encode(text: &str, c: Charset) -> Vec<u8> {
        let mut w = Encode::new(Vec::new(), c);
        w.write_all(text.as_bytes()).unwrap();
        w.inner
    }

    #[test]
    fn each_cyrillic_set_is_guessed_from_comments() {
        let program =
            "O1 (ФРЕЗА КОНЦЕВАЯ Д10, ЧИСТОВОЙ ПРОХОД)\nG1 X10. (обработка контура)\nM30\n";
        for c in CYRILLIC {
            let bytes = encode(program, c);
            assert!(std::str::from_utf8(&bytes).is_err());
            let d = decode(bytes, None).unwrap();
            assert_eq!(d.charset, c, "{c:?}");
            assert_eq!(d.text, program);
            assert!(d.guessed.unwrap().contains(&c.name().to_uppercase()));
        }
    }

    #[test]
    fn named_sets_bom_and_errors() {
        assert_eq!(
            decode(b"\xEF\xBB\xBFG1 X1\n".to_vec(), None).unwrap().text,
            "G1 X1\n"
        );
        let bytes = encode("(Привет)\n", Charset::Koi8R);
        assert_eq!(
            decode(bytes, Some(Charset::Koi8R)).unwrap().text,
            "(Привет)\n"
        );
        assert_eq!(
            decode(b"(caf\xE9)\n".to_vec(), Some(Charset::Latin1))
                .unwrap()
                .text,
            "(café)\n"
        );
        // Outside a comment: located error.
        let e = decode(b"G1 X1\nG1 Y\xCF2\n".to_vec(), None).unwrap_err();
        assert_eq!((e.line, e.column), (2, 5));
        assert!(e.message.contains("0xCF"), "{}", e.message);
        // Strict UTF-8 asked for.
        let e = decode(b"(\xCF)\n".to_vec(), Some(Charset::Utf8)).unwrap_err();
        assert_eq!((e.line, e.column), (1, 2));
    }

    #[test]
    fn encoding_writer_splits_and_unmappable() {
        let t = "(ПРИВЕТ €)\n";
        let mut w = Encode::new(Vec::new(), Charset::Cp866);
        let b = t.as_bytes();
        // Split inside a multi-byte character.
        w.write_all(&b[..2]).unwrap();
        w.write_all(&b[2..]).unwrap();
        assert_eq!(
            decode(w.inner, Some(Charset::Cp866)).unwrap().text,
            "(ПРИВЕТ ?)\n"
        );
    }

    #[test]
    fn bounded_reads() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.nc");
        std::fs::write(&p, b"0123456789").unwrap();
        assert_eq!(read_bounded(&p, 10).unwrap().len(), 10);
        assert!(matches!(read_bounded(&p, 9), Err(ReadError::TooBig(9))));
        assert!(matches!(read_bounded(dir.path(), 9), Err(ReadError::Io(_))));
    }
}
