//! Criterion benchmarks (issue "JIT and the performance case"):
//! - `compile/*`: lexing + parsing + checks + lowering of each corpus program;
//! - `jit-compile/*`: Cranelift compile latency of each corpus program;
//! - `expand/<program>/<engine>`: interpreter and JIT (compile excluded) on (a) the textbook hemisphere
//!   (10 201 raster blocks), (b) a fine hemisphere (step 0.05: 4 004 001 blocks) into a sink, (c) an
//!   arithmetic loop of 1 M iterations without motion, (d) a G65-call-heavy program; output formatting
//!   included (the same kernel and emitter as `fmsvm run`), I/O excluded;
//! - `expand/fine-hemisphere/auto`: `--engine auto` (the interpreter, then the JIT: its compile
//!   included);
//! - `expand/fine-hemisphere/{interp,jit}-pipelined`: the same with the plain blocks formatted by a
//!   second thread (`emit::pipelined`, what `fmsvm run` does on two cores);
//! - `expand/fine-hemisphere/native`: the hand-written Rust ceiling (`benches/ceiling.rs`) for (b),
//!   driving the kernel and emitter; `native-direct`: the same bytes with no VM and no kernel;
//! - `resolve/<program>/{literal,resolved}`: the same JIT run into the literal emitter and into the
//!   resolved one (`fmsvm run --resolve`: canonical operations, frames, cycles) — what resolving costs.

mod ceiling;

use std::hint::black_box;
use std::io;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fmsvm_canon::decode::InputRules;
use fmsvm_compiler::{Options, Program};
use fmsvm_emit::dialect::Dialect;
use fmsvm_emit::literal::{self, LiteralEmitter};
use fmsvm_emit::pipelined::Pipelined;
use fmsvm_emit::resolved::ResolvedEmitter;
use fmsvm_kernel::Kernel;
use fmsvm_vm::jit::Jit;
use fmsvm_vm::{EngineKind, Limits, MemoryPort, RunOptions, Stats, Variables};

const HEMISPHERE: &str = include_str!("../tests/corpus/003-hemisphere.nc");
const SINE: &str = include_str!("../tests/corpus/003-sine.nc");
const DPRNT: &str = include_str!("../tests/corpus/003-hemisphere-dprnt.nc");

/// The hemisphere with raster step `step`.
fn fine_hemisphere(step: &str) -> String {
    HEMISPHERE
        .replace("#2=#2+1", &format!("#2=#2+{step}"))
        .replace("#2=#2-1", &format!("#2=#2-{step}"))
        .replace("#1=#1+1", &format!("#1=#1+{step}"))
}

/// (c) 1 M iterations of arithmetic, no motion.
const ARITHMETIC: &str =
    "O1\n#1=0\n#2=0\nWHILE[#1 LT 1000000]DO1\n#2=#2+SQRT[#1]*2-#1/3\n#1=#1+1\nEND1\nM30\n";

/// (d) a bolt-hole macro called 100 000 times with arguments, one drill point per call.
const CALLS: &str = "%\nO1\n#100=0\nWHILE[#100 LT 100000]DO1\nG65 P9010 X[#100*0.01] Y2. R5.\n#100=#100+1\nEND1\nM30\nO9010\n#30=#24+#18*COS[#100]\n#31=#25+#18*SIN[#100]\nG81 X#30 Y#31 Z-5. R1. F100.\nM99\n%\n";

fn compile(src: &str) -> Program {
    let (p, d, _) = fmsvm_compiler::compile_str(src, &Options::default());
    p.unwrap_or_else(|| panic!("benchmark program must compile: {d:?}"))
}

type K = Kernel<LiteralEmitter<io::Sink>>;

fn kernel() -> K {
    let emitter = LiteralEmitter::new(io::sink(), Dialect::fanuc(), literal::Options::default());
    let mut k = Kernel::new(emitter, InputRules::default());
    k.set_timing(false);
    k
}

fn options(engine: EngineKind) -> RunOptions {
    RunOptions {
        engine,
        limits: Limits {
            max_steps: 0,
            max_blocks: 0,
            ..Default::default()
        },
        ..RunOptions::default()
    }
}

fn interp(p: &Program) -> Stats {
    run_engine(p, EngineKind::Interp)
}

/// A run with `engine` (the interpreter, or auto: the interpreter moving to the JIT, its compile
/// included).
fn run_engine(p: &Program, engine: EngineKind) -> Stats {
    let mut k = kernel();
    let mut port = MemoryPort::default();
    fmsvm_vm::run(
        p,
        &mut k,
        &mut port,
        &mut Variables::default(),
        &options(engine),
    )
    .expect("runs")
}

fn jit(p: &Program, j: &Jit<K>) -> Stats {
    let mut k = kernel();
    let mut port = MemoryPort::default();
    fmsvm_vm::run_compiled(
        p,
        j,
        &mut k,
        &mut port,
        &mut Variables::default(),
        &options(EngineKind::Jit),
    )
    .expect("runs")
}

type P = Kernel<Pipelined<LiteralEmitter<io::Sink>>>;

/// A run of `p` with the plain blocks formatted and written by a second thread.
fn pipelined(p: &Program, j: Option<&Jit<P>>) -> Stats {
    std::thread::scope(|scope| {
        let emitter =
            LiteralEmitter::new(io::sink(), Dialect::fanuc(), literal::Options::default());
        let rules = InputRules::default();
        let Ok(emitter) = Pipelined::new(scope, emitter, &rules.table()) else {
            panic!("the literal emitter takes the plain path");
        };
        let mut k = Kernel::new(emitter, rules);
        k.set_timing(false);
        let mut port = MemoryPort::default();
        let mut vars = Variables::default();
        match j {
            Some(j) => fmsvm_vm::run_compiled(
                p,
                j,
                &mut k,
                &mut port,
                &mut vars,
                &options(EngineKind::Jit),
            ),
            None => fmsvm_vm::run(
                p,
                &mut k,
                &mut port,
                &mut vars,
                &options(EngineKind::Interp),
            ),
        }
        .expect("runs")
    })
}

fn benches(c: &mut Criterion) {
    let corpus = [
        ("hemisphere", HEMISPHERE),
        ("sine", SINE),
        ("hemisphere-dprnt", DPRNT),
    ];
    let mut g = c.benchmark_group("compile");
    for (name, src) in corpus {
        g.throughput(Throughput::Bytes(src.len() as u64));
        g.bench_function(name, |b| b.iter(|| compile(black_box(src))));
    }
    g.finish();

    let mut g = c.benchmark_group("jit-compile");
    for (name, src) in corpus
        .iter()
        .chain([("arithmetic", ARITHMETIC), ("calls", CALLS)].iter())
    {
        let p = compile(src);
        g.bench_function(*name, |b| {
            b.iter(|| Jit::<K>::compile(black_box(&p)).expect("compiles"))
        });
    }
    // Every textbook exercise of the shared corpus that compiles today (the NCT-syntax ones come with
    // the NCT input mode).
    let textbook = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/corpus/textbook");
    // Without the corpus there is nothing to measure: say so instead of measuring nothing.
    let mut files: Vec<_> = match std::fs::read_dir(textbook) {
        Ok(d) => d.filter_map(|e| e.ok().map(|e| e.path())).collect(),
        Err(e) => panic!("{textbook}: {e} (the textbook corpus, ../shared beside the repository)"),
    };
    files.sort();
    g.warm_up_time(std::time::Duration::from_millis(200));
    g.measurement_time(std::time::Duration::from_millis(600));
    for path in files
        .iter()
        .filter(|p| p.extension().is_some_and(|e| e == "nc"))
    {
        let Ok(src) = std::fs::read_to_string(path) else {
            continue;
        };
        let Some(p) = fmsvm_compiler::compile_str(&src, &Options::default()).0 else {
            continue;
        };
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        g.bench_function(format!("textbook-{}", name.get(..2).unwrap_or("")), |b| {
            b.iter(|| Jit::<K>::compile(black_box(&p)).expect("compiles"))
        });
    }
    g.finish();

    let mut g = c.benchmark_group("expand");
    g.sample_size(10);
    let fine = fine_hemisphere("0.05");
    let programs = [
        ("hemisphere", HEMISPHERE.to_string()),
        ("fine-hemisphere", fine),
        ("arithmetic-1M", ARITHMETIC.to_string()),
        ("g65-calls", CALLS.to_string()),
    ];
    for (name, src) in &programs {
        let p = compile(src);
        let j = Jit::<K>::compile(&p).expect("compiles");
        let s = interp(&p);
        // Blocks for the expansions, loop iterations for the arithmetic loop.
        g.throughput(Throughput::Elements(if s.blocks > 10 {
            s.blocks
        } else {
            s.steps
        }));
        g.bench_function(format!("{name}/interp"), |b| {
            b.iter(|| interp(black_box(&p)))
        });
        g.bench_function(format!("{name}/jit"), |b| b.iter(|| jit(black_box(&p), &j)));
        if *name == "fine-hemisphere" {
            g.bench_function(format!("{name}/auto"), |b| {
                b.iter(|| run_engine(black_box(&p), EngineKind::Auto))
            });
            let jp = Jit::<P>::compile(&p).expect("compiles");
            g.bench_function(format!("{name}/interp-pipelined"), |b| {
                b.iter(|| pipelined(black_box(&p), None))
            });
            g.bench_function(format!("{name}/jit-pipelined"), |b| {
                b.iter(|| pipelined(black_box(&p), Some(&jp)))
            });
            g.bench_function(format!("{name}/native"), |b| {
                b.iter(|| {
                    let mut k = kernel();
                    k.begin(Some(7118), "").expect("header");
                    ceiling::hemisphere(&mut k, black_box(0.05));
                    k.end().expect("trailer");
                })
            });
            g.bench_function(format!("{name}/native-direct"), |b| {
                b.iter(|| {
                    ceiling::hemisphere_bytes(&mut io::sink(), "", black_box(0.05)).expect("writes")
                })
            });
        }
    }
    g.finish();
}

type R = Kernel<ResolvedEmitter<io::Sink>>;

fn resolved_kernel() -> R {
    let emitter = ResolvedEmitter::new(io::sink(), Dialect::fanuc(), literal::Options::default());
    let mut k = Kernel::with_settings(
        emitter,
        InputRules::default(),
        fmsvm_kernel::Settings::default(),
    );
    k.set_timing(false);
    k
}

fn resolve_benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("resolve");
    g.sample_size(10);
    for (name, src) in [
        ("fine-hemisphere", fine_hemisphere("0.05")),
        ("g81-calls", CALLS.to_string()),
    ] {
        let p = compile(&src);
        let literal = Jit::<K>::compile(&p).expect("compiles");
        let resolved = Jit::<R>::compile(&p).expect("compiles");
        g.throughput(Throughput::Elements(interp(&p).blocks));
        g.bench_function(format!("{name}/literal"), |b| {
            b.iter(|| jit(black_box(&p), &literal))
        });
        g.bench_function(format!("{name}/resolved"), |b| {
            b.iter(|| {
                let mut k = resolved_kernel();
                let mut port = MemoryPort::default();
                fmsvm_vm::run_compiled(
                    black_box(&p),
                    &resolved,
                    &mut k,
                    &mut port,
                    &mut Variables::default(),
                    &options(EngineKind::Jit),
                )
                .expect("runs")
            })
        });
    }
    g.finish();
}

criterion_group!(expansion, benches, resolve_benches);
criterion_main!(expansion);
