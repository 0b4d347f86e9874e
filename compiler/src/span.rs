//! Source files, byte spans and the byte-offset → line:column index used by every message.

/// Index of a source file in a [`SourceMap`].
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Default)]
pub struct FileId(pub u16);

/// A byte range in one source file.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Default)]
pub struct Span {
    /// The file.
    pub file: FileId,
    /// First byte.
    pub start: u32,
    /// One past the last byte.
    pub end: u32,
}

impl Span {
    /// A span from byte offsets.
    pub fn new(file: FileId, start: usize, end: usize) -> Span {
        Span {
            file,
            start: start as u32,
            end: end as u32,
        }
    }

    /// The smallest span covering both.
    pub fn to(self, other: Span) -> Span {
        Span {
            file: self.file,
            start: self.start.min(other.start),
            end: self.end.max(other.end),
        }
    }
}

/// The span of each op of one function, six bytes an op instead of twelve (a long program holds
/// millions of ops): every op of a function comes from the function's file, and a length is kept up
/// to 65 535 bytes (a longer span keeps its start and is cut there, which only shortens a caret).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct OpSpans {
    file: FileId,
    start: Vec<u32>,
    len: Vec<u16>,
}

impl OpSpans {
    /// No spans yet, for ops of `file`.
    pub fn new(file: FileId) -> OpSpans {
        OpSpans {
            file,
            ..OpSpans::default()
        }
    }

    fn len_of(s: Span) -> u16 {
        s.end.saturating_sub(s.start).min(u32::from(u16::MAX)) as u16
    }

    /// The span of op `i`. Panics when there is no op `i`, as indexing does.
    pub fn get(&self, i: usize) -> Span {
        let start = self.start[i];
        Span {
            file: self.file,
            start,
            end: start + u32::from(self.len[i]),
        }
    }

    /// Appends the span of the next op.
    pub fn push(&mut self, s: Span) {
        self.start.push(s.start);
        self.len.push(Self::len_of(s));
    }

    /// Sets the span of op `i`.
    pub fn set(&mut self, i: usize, s: Span) {
        self.start[i] = s.start;
        self.len[i] = Self::len_of(s);
    }

    /// Inserts a span before op `i`.
    pub fn insert(&mut self, i: usize, s: Span) {
        self.start.insert(i, s.start);
        self.len.insert(i, Self::len_of(s));
    }

    /// Grows or shrinks to `n` spans, new ones `s`.
    pub fn resize(&mut self, n: usize, s: Span) {
        self.start.resize(n, s.start);
        self.len.resize(n, Self::len_of(s));
    }

    /// Removes the last span.
    pub fn pop(&mut self) {
        self.start.pop();
        self.len.pop();
    }

    /// Removes every span.
    pub fn clear(&mut self) {
        self.start.clear();
        self.len.clear();
    }

    /// The number of spans.
    pub fn len(&self) -> usize {
        self.start.len()
    }

    /// No spans.
    pub fn is_empty(&self) -> bool {
        self.start.is_empty()
    }

    /// The span of the first op.
    pub fn first(&self) -> Option<Span> {
        (!self.is_empty()).then(|| self.get(0))
    }
}

/// One loaded source file with its line index.
#[derive(Debug)]
pub struct SourceFile {
    /// The name shown in messages (a path, or `<stdin>`).
    pub name: String,
    /// The text.
    pub text: String,
    line_starts: Vec<u32>,
}

impl SourceFile {
    /// Indexes `text`. CR LF, LF and a lone CR each end a line.
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> SourceFile {
        let text = text.into();
        let bytes = text.as_bytes();
        let mut line_starts = vec![0u32];
        for i in memchr::memchr2_iter(b'\n', b'\r', bytes) {
            if bytes[i] == b'\n' || bytes.get(i + 1) != Some(&b'\n') {
                line_starts.push(i as u32 + 1);
            }
        }
        SourceFile {
            name: name.into(),
            text,
            line_starts,
        }
    }

    /// 1-based line and column (in characters) of byte `offset`.
    pub fn line_col(&self, offset: u32) -> (u32, u32) {
        let line = match self.line_starts.binary_search(&offset) {
            Ok(i) => i,
            Err(i) => i - 1,
        };
        let start = self.line_starts[line] as usize;
        let end = (offset as usize).min(self.text.len());
        let col = self
            .text
            .get(start..end)
            .map_or(end - start, |s| s.chars().count());
        (line as u32 + 1, col as u32 + 1)
    }

    /// The 1-based line of byte `offset`, for offsets that mostly grow from call to call: `cursor`
    /// remembers the last line found (start it at 0), so reading a file in order costs a step a line
    /// instead of a search.
    pub fn line_at(&self, offset: u32, cursor: &mut usize) -> u32 {
        let starts = &self.line_starts;
        if starts.get(*cursor).is_none_or(|&s| s > offset) {
            *cursor = starts.partition_point(|&s| s <= offset).saturating_sub(1);
        }
        while starts.get(*cursor + 1).is_some_and(|&s| s <= offset) {
            *cursor += 1;
        }
        *cursor as u32 + 1
    }

    /// The text of 1-based line `line`, without its line end.
    pub fn line_text(&self, line: u32) -> &str {
        let i = (line as usize).saturating_sub(1);
        let start = self.line_starts.get(i).copied().unwrap_or(0) as usize;
        let end = self
            .line_starts
            .get(i + 1)
            .map_or(self.text.len(), |&e| e as usize);
        self.text
            .get(start..end)
            .unwrap_or("")
            .trim_end_matches(['\r', '\n'])
    }
}

/// All source files of one compilation.
#[derive(Debug, Default)]
pub struct SourceMap {
    files: Vec<SourceFile>,
}

impl SourceMap {
    /// An empty map.
    pub fn new() -> SourceMap {
        SourceMap::default()
    }

    /// Adds a file and returns its id.
    pub fn add(&mut self, name: impl Into<String>, text: impl Into<String>) -> FileId {
        self.files.push(SourceFile::new(name, text));
        FileId((self.files.len() - 1) as u16)
    }

    /// The file with id `id`.
    pub fn file(&self, id: FileId) -> &SourceFile {
        &self.files[id.0 as usize]
    }

    /// All files.
    pub fn files(&self) -> &[SourceFile] {
        &self.files
    }

    /// `name:line:col` of the start of `span`.
    pub fn location(&self, span: Span) -> String {
        let f = self.file(span.file);
        let (l, c) = f.line_col(span.start);
        format!("{}:{}:{}", f.name, l, c)
    }

    /// The source text under `span`.
    pub fn text(&self, span: Span) -> &str {
        self.file(span.file)
            .text
            .get(span.start as usize..span.end as usize)
            .unwrap_or("")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_col_with_mixed_line_ends() {
        let f = SourceFile::new("t", "G1\r\nX1\nY2\rZ3");
        assert_eq!(f.line_col(0), (1, 1));
        assert_eq!(f.line_col(4), (2, 1));
        assert_eq!(f.line_col(5), (2, 2));
        assert_eq!(f.line_col(7), (3, 1));
        assert_eq!(f.line_col(10), (4, 1));
        assert_eq!(f.line_text(2), "X1");
        assert_eq!(f.line_text(4), "Z3");
    }
}
