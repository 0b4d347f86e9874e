//! Shared helpers of the integration tests: expand a program in-process, read its variables, and
//! reduce flat G-code to canonical moves (a Rust port of `shared/tools/ncmotion.py`).
#![allow(dead_code)]

use fmsvm_block::{Stop, is_vacant};
use fmsvm_canon::decode::InputRules;
use fmsvm_compiler::ir::common_index;
use fmsvm_compiler::{Diagnostic, Options};
use fmsvm_emit::dialect::Dialect;
use fmsvm_emit::literal::{self, LiteralEmitter};
use fmsvm_emit::resolved::ResolvedEmitter;
use fmsvm_kernel::{Kernel, Settings};
use fmsvm_vm::{EngineKind, Limits, MemoryPort, RunOptions, Variables};

/// Why an expansion failed.
#[derive(Debug)]
pub enum Failure {
    /// Compile errors.
    Compile(Vec<Diagnostic>),
    /// A run-time alarm: number, message, source line.
    Alarm(u32, String, u32),
    /// A limit.
    Limit(String),
}

impl PartialEq for Failure {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Failure::Alarm(a, b, c), Failure::Alarm(d, e, f)) => (a, b, c) == (d, e, f),
            (Failure::Limit(a), Failure::Limit(b)) => a == b,
            _ => false,
        }
    }
}

impl Failure {
    /// The alarm number (run time or first compile error).
    pub fn alarm(&self) -> Option<u32> {
        match self {
            Failure::Compile(d) => d.iter().find(|d| d.is_error()).and_then(|d| d.alarm),
            Failure::Alarm(n, ..) => Some(*n),
            Failure::Limit(_) => None,
        }
    }
}

/// A finished expansion.
pub struct Expansion {
    /// The flat program.
    pub text: String,
    /// The variables at the end.
    pub vars: Variables,
    /// Warnings.
    pub warnings: Vec<Diagnostic>,
    /// What DPRNT/BPRNT printed (DC2/DC4 included).
    pub printed: Vec<u8>,
}

impl std::fmt::Debug for Expansion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Expansion:\n{}", self.text)
    }
}

impl Expansion {
    /// Common variable `#n` at the end (None = vacant).
    pub fn var(&self, n: u32) -> Option<f64> {
        let v = self.vars.commons[common_index(n).expect("a common variable") as usize];
        (!is_vacant(v)).then_some(v)
    }

    /// The output blocks between the `%`/O header and the closing `%`.
    pub fn body(&self) -> Vec<&str> {
        self.text
            .lines()
            .filter(|l| *l != "%" && !l.starts_with('O'))
            .collect()
    }
}

/// How a test expands: output options, the input's number rules, and resolving (None = literal).
#[derive(Clone, Default)]
pub struct Setup {
    /// Output options.
    pub literal: literal::Options,
    /// The program's number rules.
    pub rules: InputRules,
    /// Resolve (`--resolve`) with these kernel settings.
    pub resolve: Option<Settings>,
    /// Work offsets and tool registers before the run.
    pub frames: Option<fmsvm_kernel::frames::Frames>,
    /// Kernel settings of a literal run.
    pub literal_settings: Settings,
}

impl From<literal::Options> for Setup {
    fn from(literal: literal::Options) -> Self {
        Setup {
            literal,
            ..Setup::default()
        }
    }
}

/// Expands `src` with the given output options and limits.
pub fn expand_with(
    src: &str,
    options: impl Into<Setup>,
    limits: Limits,
    compile: Options,
) -> Result<Expansion, Failure> {
    let run = RunOptions {
        limits,
        ..RunOptions::default()
    };
    expand_full(src, &[], options, run, compile)
}

/// Expands `src` with more program files (`(name, text)`, a library) and every option.
pub fn expand_full(
    src: &str,
    library: &[(&str, &str)],
    options: impl Into<Setup>,
    run: RunOptions,
    compile: Options,
) -> Result<Expansion, Failure> {
    let options = options.into();
    struct Lib<'a>(&'a [(&'a str, &'a str)]);
    impl fmsvm_compiler::Library for Lib<'_> {
        fn find(&mut self, number: u32) -> Option<(String, String)> {
            self.0
                .iter()
                .find(|(_, text)| {
                    text.lines().any(|l| {
                        let t = l.trim();
                        let rest = t
                            .strip_prefix(&format!("O{number}"))
                            .or_else(|| t.strip_prefix(&format!("O{number:04}")));
                        rest.is_some_and(|r| r.is_empty() || r.starts_with([' ', '(']))
                    })
                })
                .map(|(n, t)| (n.to_string(), t.to_string()))
        }
    }
    let mut sources = fmsvm_compiler::SourceMap::new();
    let id = sources.add("<input>", src);
    let (program, diags) = fmsvm_compiler::compile(&mut sources, id, &compile, &mut Lib(library));
    let Some(program) = program else {
        return Err(Failure::Compile(diags));
    };
    // Every expansion of the tests runs on both engines, which must agree byte for byte (output,
    // printed records, variables, the alarm and where it was raised): the differential test.
    let interp = run_engine(
        &program,
        &sources,
        &options,
        RunOptions {
            engine: EngineKind::Interp,
            ..run
        },
    );
    let jit = run_engine(
        &program,
        &sources,
        &options,
        RunOptions {
            engine: EngineKind::Jit,
            ..run
        },
    );
    assert_eq!(interp, jit, "the interpreter and the JIT differ on {src:?}");
    interp.map(|(text, commons, printed)| Expansion {
        text,
        vars: {
            let mut v = Variables::default();
            for (slot, bits) in v.commons.iter_mut().zip(commons) {
                *slot = f64::from_bits(bits);
            }
            v
        },
        warnings: diags,
        printed,
    })
}

/// What one engine made of a program: output text, commons (as bits, so vacant compares), printed bytes.
type Outcome = Result<(String, Vec<u64>, Vec<u8>), Failure>;

fn run_engine(
    program: &fmsvm_compiler::Program,
    sources: &fmsvm_compiler::SourceMap,
    options: &Setup,
    run: RunOptions,
) -> Outcome {
    let mut out = Vec::new();
    let mut vars = Variables::default();
    let result = match &options.resolve {
        None => {
            let emitter = LiteralEmitter::new(&mut out, Dialect::fanuc(), options.literal.clone());
            let kernel = Kernel::with_settings(
                emitter,
                options.rules.clone(),
                options.literal_settings.clone(),
            );
            run_kernel(program, sources, kernel, &mut vars, options, run)
        }
        Some(settings) => {
            // A return to a reference position is written as the move to it (the test declares
            // where it is), so that the motion compares with LinuxCNC's trace; the control's own
            // `G91 G28` form is held by tests/safety.rs.
            let dialect = Dialect {
                reference: fmsvm_emit::dialect::ReferenceForm::None,
                ..Dialect::fanuc()
            };
            let emitter = ResolvedEmitter::new(&mut out, dialect, options.literal.clone());
            let kernel = Kernel::with_settings(emitter, options.rules.clone(), settings.clone());
            run_kernel(program, sources, kernel, &mut vars, options, run)
        }
    };
    let printed = result?;
    let commons = vars.commons.iter().map(|v| v.to_bits()).collect();
    Ok((
        String::from_utf8(out).expect("ASCII output"),
        commons,
        printed,
    ))
}

fn run_kernel<E: fmsvm_canon::Emitter>(
    program: &fmsvm_compiler::Program,
    sources: &fmsvm_compiler::SourceMap,
    mut kernel: Kernel<E>,
    vars: &mut Variables,
    options: &Setup,
    run: RunOptions,
) -> Result<Vec<u8>, Failure> {
    if let Some(f) = &options.frames {
        *kernel.frames_mut() = f.clone();
    }
    let main = &program.functions[0];
    kernel
        .begin(main.number, program.string(main.title))
        .expect("header");
    let mut port = MemoryPort::default();
    match fmsvm_vm::run(program, &mut kernel, &mut port, vars, &run) {
        Ok(_) => kernel.end().map_err(|s| Failure::Limit(s.to_string()))?,
        Err(e) => {
            let line = sources.file(e.span.file).line_col(e.span.start).0;
            return Err(match e.stop {
                Stop::Alarm(a) => Failure::Alarm(a.number, a.message.into_owned(), line),
                other => Failure::Limit(other.to_string()),
            });
        }
    }
    Ok(port.bytes)
}

/// Expands `src` with default options.
pub fn expand(src: &str) -> Result<Expansion, Failure> {
    expand_with(
        src,
        literal::Options::default(),
        Limits::default(),
        Options::default(),
    )
}

/// Expands and unwraps, printing the failure.
pub fn ok(src: &str) -> Expansion {
    match expand(src) {
        Ok(e) => e,
        Err(f) => panic!("expansion of {src:?} failed: {f:?}"),
    }
}

/// The value of `#100` after running `src` (which assigns it).
pub fn value(src: &str) -> Option<f64> {
    ok(src).var(100)
}

/// Asserts `#100` after `src` equals `expected` within 1e-9.
#[track_caller]
pub fn assert_value(src: &str, expected: f64) {
    match value(src) {
        Some(v) => assert!(
            (v - expected).abs() <= 1e-9 * expected.abs().max(1.0),
            "{src:?}: #100 = {v}, expected {expected}"
        ),
        None => panic!("{src:?}: #100 is vacant, expected {expected}"),
    }
}

/// The alarm number `src` stops with.
#[track_caller]
pub fn alarm_of(src: &str) -> u32 {
    match expand(src) {
        Ok(e) => panic!("{src:?} ran without an alarm:\n{}", e.text),
        Err(f) => f
            .alarm()
            .unwrap_or_else(|| panic!("{src:?}: no alarm number: {f:?}")),
    }
}

/// One canonical move: kind, end point, arc centre and plane.
#[derive(Clone, Debug, PartialEq)]
pub struct Move {
    /// G0, G1, G2, G3.
    pub kind: u8,
    /// End point X Y Z.
    pub end: [f64; 3],
    /// Arc centre (arcs only) on the two axes of its plane, in X Y Z order: X Y (G17), X Z (G18),
    /// Y Z (G19).
    pub centre: Option<[f64; 2]>,
    /// The plane of an arc: 17, 18 or 19 (17 for straight moves).
    pub plane: u8,
}

/// The axes (indices into X Y Z) of plane `g` (17, 18, 19) in its right-handed order (first, second,
/// normal): G17 X Y Z, G18 Z X Y, G19 Y Z X. An arc is clockwise (G2) in that order.
fn plane_axes(plane: u8) -> (usize, usize, usize) {
    match plane {
        18 => (2, 0, 1),
        19 => (1, 2, 0),
        _ => (0, 1, 2),
    }
}

/// The centre of an arc given by R from `from` to `to` in plane coordinates (first, second axis): for
/// a clockwise arc of positive R (at most 180 degrees) to the right of the chord, left for G3; a
/// negative R takes the other centre (`ncmotion.py centre_from_r`).
fn centre_from_r(from: [f64; 2], to: [f64; 2], r: f64, clockwise: bool) -> [f64; 2] {
    let (dx, dy) = (to[0] - from[0], to[1] - from[1]);
    let d = dx.hypot(dy);
    assert!(
        d > 0.0 && r.abs() * 2.0 >= d - 1e-6,
        "arc radius R{r} cannot reach an end point {d} away"
    );
    let h = (r * r - d * d / 4.0).max(0.0).sqrt();
    let (mx, my) = (from[0] + dx / 2.0, from[1] + dy / 2.0);
    let (nx, ny) = (-dy / d, dx / d);
    let mut sign = if clockwise { -1.0 } else { 1.0 };
    if r < 0.0 {
        sign = -sign;
    }
    [mx + sign * h * nx, my + sign * h * ny]
}

/// Canonical moves of a flat program, as `ncmotion.py moves` computes them (G0–G3, G90/G91; zero-length
/// moves dropped; dwell and data-setting blocks skipped), extended to arcs in every plane: G17 I J,
/// G18 I K, G19 J K, or R (an arc without end point but with its centre words is a full circle).
pub fn moves_of_flat(text: &str) -> Vec<Move> {
    // LinuxCNC's start, which the oracle's traces assume; an axis the output has not said stays
    // there, as it does in the trace.
    let mut pos = [0.0f64; 3];
    let mut motion = 0u8;
    let mut absolute = true;
    let mut plane = 17u8;
    let mut out = Vec::new();
    for raw in text.lines() {
        let mut line = String::new();
        let mut depth = 0;
        for c in raw.to_ascii_uppercase().chars() {
            match c {
                '(' => depth += 1,
                ')' => depth = (depth - 1).max(0),
                ';' if depth == 0 => break,
                _ if depth == 0 => line.push(c),
                _ => {}
            }
        }
        let line = line.trim().trim_start_matches('/');
        if line.is_empty() || line.starts_with('%') {
            continue;
        }
        assert!(
            !line.contains('#') && !line.contains('['),
            "not flat: {raw}"
        );
        let mut gs = Vec::new();
        let mut vals: [Option<f64>; 26] = [None; 26];
        let b = line.as_bytes();
        let mut i = 0;
        while i < b.len() {
            if b[i].is_ascii_uppercase() {
                let letter = b[i];
                let mut j = i + 1;
                while j < b.len() && b[j] == b' ' {
                    j += 1;
                }
                let start = j;
                while j < b.len()
                    && (b[j].is_ascii_digit() || b[j] == b'.' || b[j] == b'-' || b[j] == b'+')
                {
                    j += 1;
                }
                if let Ok(v) = line[start..j].parse::<f64>() {
                    if letter == b'G' {
                        gs.push((v * 10.0).round() as i64);
                    } else {
                        vals[(letter - b'A') as usize] = Some(v);
                    }
                }
                i = j.max(i + 1);
            } else {
                i += 1;
            }
        }
        for &g in &gs {
            match g {
                0 | 10 | 20 | 30 => motion = (g / 10) as u8,
                900 => absolute = true,
                910 => absolute = false,
                170 | 180 | 190 => plane = (g / 10) as u8,
                _ => {}
            }
        }
        let axis = |c: u8| vals[(c - b'A') as usize];
        let (pa, pb, _) = plane_axes(plane);
        let offset_letters = [b'I', b'J', b'K'];
        let full_circle = motion >= 2
            && (axis(offset_letters[pa]).is_some() || axis(offset_letters[pb]).is_some());
        if axis(b'X').is_none() && axis(b'Y').is_none() && axis(b'Z').is_none() && !full_circle {
            continue;
        }
        if gs.iter().any(|&g| g == 40 || g == 100) {
            continue;
        }
        let mut target = pos;
        for (k, c) in [b'X', b'Y', b'Z'].into_iter().enumerate() {
            if let Some(v) = axis(c) {
                target[k] = if absolute { v } else { pos[k] + v };
            }
        }
        if motion <= 1 {
            if target
                .iter()
                .zip(pos.iter())
                .any(|(t, p)| (t - p).abs() > 1e-9 || (p.is_nan() && !t.is_nan()))
            {
                out.push(Move {
                    kind: motion,
                    end: target,
                    centre: None,
                    plane: 17,
                });
            }
        } else {
            let c = match axis(b'R') {
                Some(r)
                    if axis(offset_letters[pa]).is_none() && axis(offset_letters[pb]).is_none() =>
                {
                    centre_from_r([pos[pa], pos[pb]], [target[pa], target[pb]], r, motion == 2)
                }
                _ => [
                    pos[pa] + axis(offset_letters[pa]).unwrap_or(0.0),
                    pos[pb] + axis(offset_letters[pb]).unwrap_or(0.0),
                ],
            };
            // In X Y Z order: G18's (Z, X) centre is stored as X Z.
            let centre = if pa < pb { c } else { [c[1], c[0]] };
            out.push(Move {
                kind: motion,
                end: target,
                centre: Some(centre),
                plane,
            });
        }
        pos = target;
    }
    out
}

/// Moves stored by `ncmotion.py moves` (`G1 x y z [cx cy]` a line), or by `tests/kernel/kmoves.py`,
/// which adds the plane of an arc outside G17 after its centre (`G2 x y z cx cz G18`, `… cy cz G19`).
pub fn moves_of_list(text: &str) -> Vec<Move> {
    text.lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let mut it = l.split_whitespace();
            let kind = it
                .next()
                .and_then(|k| k.strip_prefix('G'))
                .and_then(|k| k.parse().ok())
                .expect("move kind");
            let mut plane = 17;
            let mut v: Vec<f64> = Vec::new();
            for x in it {
                match x {
                    "G18" => plane = 18,
                    "G19" => plane = 19,
                    x => v.push(x.parse().expect("number")),
                }
            }
            Move {
                kind,
                end: [v[0], v[1], v[2]],
                centre: (v.len() >= 5).then(|| [v[3], v[4]]),
                plane,
            }
        })
        .collect()
}

/// Compares two move lists within `tol`; Err describes the first difference.
pub fn diff_moves(got: &[Move], want: &[Move], tol: f64) -> Result<(), String> {
    for (i, (a, b)) in got.iter().zip(want).enumerate() {
        // An axis fmsvm's output had not yet positioned (NaN) is where the oracle assumed it
        // started: the comparison counts from the program's first positioning of each axis.
        let close = |x: &[f64], y: &[f64]| {
            x.iter()
                .zip(y)
                .all(|(p, q)| p.is_nan() || (p - q).abs() <= tol)
        };
        let same = a.kind == b.kind
            && close(&a.end, &b.end)
            && match (a.centre, b.centre) {
                (Some(c), Some(d)) => a.plane == b.plane && close(&c, &d),
                (None, None) => true,
                _ => false,
            };
        if !same {
            return Err(format!(
                "move {} differs: got {a:?}, want {b:?} (first {i} equal)",
                i + 1
            ));
        }
    }
    if got.len() != want.len() {
        return Err(format!(
            "move counts differ: got {}, want {}",
            got.len(),
            want.len()
        ));
    }
    Ok(())
}
