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

/// The span of each op of one function, about two bytes an op instead of twelve (a long program holds
/// millions of ops). Every op of a function comes from the function's file, and the ops of a line lie
/// within a few hundred bytes of each other: each op keeps its start as an offset (a byte) from an
/// *anchor*, a byte of the file that a run of ops counts from, and its length in a byte; a span that
/// does not fit so is kept whole in a side list. The lowerer sets an anchor as each line begins
/// ([`OpSpans::line`]); a push that falls outside the current one starts another.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct OpSpans {
    file: FileId,
    /// (first op, byte): ops from `first op` on count their starts from `byte`. Sorted, firsts distinct.
    anchors: Vec<(u32, u32)>,
    rel: Vec<u8>,
    len: Vec<u8>,
    /// Spans kept whole (`rel` is `FAR`): (op, start, end), sorted by op.
    far: Vec<(u32, u32, u32)>,
}

/// The offset that marks a span kept whole.
const FAR: u8 = u8::MAX;

impl OpSpans {
    /// No spans yet, for ops of `file`.
    pub fn new(file: FileId) -> OpSpans {
        OpSpans {
            file,
            ..OpSpans::default()
        }
    }

    /// The byte op `i` counts from (the anchor at or before it).
    fn base(&self, i: usize) -> u32 {
        let k = self.anchors.partition_point(|a| a.0 as usize <= i);
        k.checked_sub(1).map_or(0, |k| self.anchors[k].1)
    }

    /// (offset, length) of `s` from `base`, or None when it does not fit in a byte each.
    fn fit(s: Span, base: u32) -> Option<(u8, u8)> {
        let rel = s.start.checked_sub(base)?;
        let len = s.end.saturating_sub(s.start);
        (rel < u32::from(FAR) && len <= 255).then_some((rel as u8, len as u8))
    }

    /// The span of op `i`. Panics when there is no op `i`, as indexing does.
    pub fn get(&self, i: usize) -> Span {
        let (start, end) = if self.rel[i] == FAR {
            let k = self.far.partition_point(|f| (f.0 as usize) < i);
            (self.far[k].1, self.far[k].2)
        } else {
            let start = self.base(i) + u32::from(self.rel[i]);
            (start, start + u32::from(self.len[i]))
        };
        Span {
            file: self.file,
            start,
            end,
        }
    }

    /// The ops that follow come from a line that starts at byte `start`: an anchor there, unless the
    /// current one is close enough before it to count the whole line from (most lines are short).
    pub fn line(&mut self, start: u32) {
        let i = self.rel.len() as u32;
        match self.anchors.last_mut() {
            Some(a) if a.0 == i => a.1 = start,
            Some(a) if start >= a.1 && start - a.1 < 128 => {}
            _ => self.anchors.push((i, start)),
        }
    }

    /// Appends the span of the next op.
    pub fn push(&mut self, s: Span) {
        let i = self.rel.len() as u32;
        let fits = self.anchors.last().and_then(|a| Self::fit(s, a.1));
        let (rel, len) = match fits {
            Some(f) => f,
            None => {
                // Outside the current anchor: one at this op's start.
                match self.anchors.last_mut() {
                    Some(a) if a.0 == i => a.1 = s.start,
                    _ => self.anchors.push((i, s.start)),
                }
                Self::fit(s, s.start).unwrap_or((FAR, 0))
            }
        };
        if rel == FAR {
            self.far.push((i, s.start, s.end));
        }
        self.rel.push(rel);
        self.len.push(len);
    }

    /// Sets the span of op `i` (kept whole when it does not fit its anchor).
    pub fn set(&mut self, i: usize, s: Span) {
        let k = self.far.partition_point(|f| (f.0 as usize) < i);
        let had = self.far.get(k).is_some_and(|f| f.0 as usize == i);
        match Self::fit(s, self.base(i)) {
            Some((rel, len)) => {
                if had {
                    self.far.remove(k);
                }
                self.rel[i] = rel;
                self.len[i] = len;
            }
            None => {
                let entry = (i as u32, s.start, s.end);
                if had {
                    self.far[k] = entry;
                } else {
                    self.far.insert(k, entry);
                }
                self.rel[i] = FAR;
                self.len[i] = 0;
            }
        }
    }

    /// Inserts spans before ops: `inserts` are (op, span) sorted by op, each meaning "a new op before
    /// op `op` as it is now" (several may name the same op, in order). The ops move up in place; an
    /// inserted op counts from the anchor of the op before it.
    pub fn insert_many(&mut self, inserts: &[(u32, Span)]) {
        if inserts.is_empty() {
            return;
        }
        let n = self.rel.len();
        // The number of inserts before old op `i` (at `i` or earlier): where it moves.
        let moved = |i: u32| i as usize + inserts.partition_point(|x| x.0 <= i);
        for a in &mut self.anchors {
            a.0 = moved(a.0) as u32;
        }
        for f in &mut self.far {
            f.0 = moved(f.0) as u32;
        }
        self.rel.resize(n + inserts.len(), 0);
        self.len.resize(n + inserts.len(), 0);
        let mut left = inserts.len();
        for i in (0..n).rev() {
            while left > 0 && inserts[left - 1].0 as usize > i {
                // Inserts after the last op (at `n`) go at the end, in order.
                left -= 1;
            }
            let to = i + left;
            self.rel[to] = self.rel[i];
            self.len[to] = self.len[i];
            while left > 0 && inserts[left - 1].0 as usize == i {
                left -= 1;
                self.rel[i + left] = 0;
                self.len[i + left] = 0;
            }
            if left == 0 {
                break;
            }
        }
        // The inserted spans, each encoded at its new place.
        for (k, &(at, s)) in inserts.iter().enumerate() {
            // Before old op `at` come `k` earlier inserts (those at `at` included, in order).
            let to = at as usize + k;
            if to < self.rel.len() {
                self.set(to, s);
            }
        }
    }

    /// Inserts a span before op `i`.
    pub fn insert(&mut self, i: usize, s: Span) {
        self.insert_many(&[(i as u32, s)]);
    }

    /// Grows or shrinks to `n` spans, new ones `s`.
    pub fn resize(&mut self, n: usize, s: Span) {
        while self.len() > n {
            self.pop();
        }
        while self.len() < n {
            self.push(s);
        }
    }

    /// Removes the last span.
    pub fn pop(&mut self) {
        if self.rel.pop().is_some() {
            self.len.pop();
            let n = self.rel.len() as u32;
            while self.anchors.last().is_some_and(|a| a.0 >= n && a.0 > 0) {
                self.anchors.pop();
            }
            while self.far.last().is_some_and(|f| f.0 >= n) {
                self.far.pop();
            }
        }
    }

    /// Removes every span.
    pub fn clear(&mut self) {
        self.anchors.clear();
        self.rel.clear();
        self.len.clear();
        self.far.clear();
    }

    /// The number of spans.
    pub fn len(&self) -> usize {
        self.rel.len()
    }

    /// No spans.
    pub fn is_empty(&self) -> bool {
        self.rel.is_empty()
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

    /// `OpSpans` against a plain list of spans under random pushes (near the current line, far
    /// before it, longer than a byte), line anchors, inserts (at the end and several before one op),
    /// sets, pops and resizes: every span reads back exactly, in six thousand steps of each of 40 runs.
    #[test]
    fn op_spans_keep_every_span() {
        let mut seed = 0x2545_F491_4F6C_DD1Du64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let file = FileId(3);
        for _ in 0..40 {
            let mut spans = OpSpans::new(file);
            let mut model: Vec<Span> = Vec::new();
            let mut line = 0u32;
            let random_span = |line: u32, r: u64| {
                let start = match r % 10 {
                    0 => (r >> 8) as u32 % 100_000,
                    1 => line + 200 + (r >> 8) as u32 % 2000,
                    _ => line + (r >> 8) as u32 % 90,
                };
                let len = if r.is_multiple_of(13) {
                    300 + (r >> 20) as u32 % 900
                } else {
                    (r >> 20) as u32 % 60
                };
                Span::new(file, start as usize, (start + len) as usize)
            };
            for _ in 0..6_000 {
                let r = next();
                match r % 20 {
                    0..=9 => {
                        let s = random_span(line, next());
                        spans.push(s);
                        model.push(s);
                    }
                    10 | 11 => {
                        line += (r >> 8) as u32 % 300;
                        spans.line(line);
                    }
                    12 => {
                        let mut ins: Vec<(u32, Span)> = (0..1 + (r >> 8) % 4)
                            .map(|_| {
                                let at = (next() % (model.len() as u64 + 1)) as u32;
                                (at, random_span(line, next()))
                            })
                            .collect();
                        ins.sort_by_key(|x| x.0);
                        spans.insert_many(&ins);
                        for (k, &(at, s)) in ins.iter().enumerate() {
                            model.insert(at as usize + k, s);
                        }
                    }
                    13 if !model.is_empty() => {
                        let i = (next() % model.len() as u64) as usize;
                        let s = random_span(line, next());
                        spans.set(i, s);
                        model[i] = s;
                    }
                    14 => {
                        spans.pop();
                        model.pop();
                    }
                    15 if r.is_multiple_of(7) => {
                        let n = (next() % (model.len() as u64 + 3)) as usize;
                        let s = random_span(line, next());
                        spans.resize(n, s);
                        model.resize(n, s);
                    }
                    _ => {}
                }
                assert_eq!(spans.len(), model.len());
                if r % 50 == 0 {
                    for (i, s) in model.iter().enumerate() {
                        assert_eq!(spans.get(i), *s, "op {i}");
                    }
                }
            }
            for (i, s) in model.iter().enumerate() {
                assert_eq!(spans.get(i), *s, "op {i}");
            }
            assert_eq!(spans.first(), model.first().copied());
        }
    }
}
