//! Criterion benchmarks of the pipeline: compile (lex + parse + check + lower) of the corpus, and the
//! interpreter expanding the textbook hemisphere, a fine hemisphere and an arithmetic loop into a sink
//! (output formatting included, I/O excluded).

use std::hint::black_box;
use std::io;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use fmsvm_compiler::{Options, Program};
use fmsvm_runtime::Kernel;
use fmsvm_runtime::dialect::Dialect;
use fmsvm_runtime::emit::literal::{self, DecimalInput, LiteralEmitter};
use fmsvm_vm::{Limits, MemoryPort, RunOptions, Stats, Variables};

const HEMISPHERE: &str = include_str!("../tests/corpus/003-hemisphere.nc");
const SINE: &str = include_str!("../tests/corpus/003-sine.nc");

/// The textbook hemisphere with a finer raster step (0.05 mm: 2001 × 2001 ≈ 4 M blocks).
fn fine_hemisphere(step: &str) -> String {
    HEMISPHERE
        .replace("#2=#2+1", &format!("#2=#2+{step}"))
        .replace("#2=#2-1", &format!("#2=#2-{step}"))
        .replace("#1=#1+1", &format!("#1=#1+{step}"))
}

const ARITHMETIC: &str =
    "O1\n#1=0\n#2=0\nWHILE[#1 LT 1000000]DO1\n#2=#2+SQRT[#1]*2-#1/3\n#1=#1+1\nEND1\nM30\n";

fn compile(src: &str) -> Program {
    let (p, d, _) = fmsvm_compiler::compile_str(src, &Options::default());
    p.unwrap_or_else(|| panic!("benchmark program must compile: {d:?}"))
}

fn expand(p: &Program) -> Stats {
    let emitter = LiteralEmitter::new(io::sink(), Dialect::fanuc(), literal::Options::default());
    let mut kernel = Kernel::new(emitter, Dialect::fanuc(), DecimalInput::Calculator);
    let options = RunOptions {
        limits: Limits {
            max_steps: 0,
            max_blocks: 0,
        },
        ..RunOptions::default()
    };
    let mut port = MemoryPort::default();
    fmsvm_vm::run(
        p,
        &mut kernel,
        &mut port,
        &mut Variables::default(),
        &options,
    )
    .expect("runs")
}

fn benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("compile");
    for (name, src) in [("hemisphere", HEMISPHERE), ("sine", SINE)] {
        g.throughput(Throughput::Bytes(src.len() as u64));
        g.bench_with_input(BenchmarkId::from_parameter(name), src, |b, s| {
            b.iter(|| compile(black_box(s)))
        });
    }
    g.finish();

    let mut g = c.benchmark_group("interp");
    g.sample_size(10);
    let fine = fine_hemisphere("0.05");
    for (name, src) in [
        ("hemisphere", HEMISPHERE.to_string()),
        ("fine-hemisphere", fine),
        ("arithmetic-1M", ARITHMETIC.to_string()),
    ] {
        let p = compile(&src);
        let s = expand(&p);
        // Blocks for the expansions, loop iterations for the arithmetic loop.
        g.throughput(Throughput::Elements(if s.blocks > 10 {
            s.blocks
        } else {
            s.steps
        }));
        g.bench_function(name, |b| b.iter(|| expand(black_box(&p))));
    }
    g.finish();
}

criterion_group!(expansion, benches);
criterion_main!(expansion);
