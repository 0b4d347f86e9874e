//! The VM's trust rules from outside: a panic in the Machine under the JIT unwinds like one under the
//! interpreter (never an abort through native frames), a program the IR verifier refuses runs on no
//! engine, and compiled code memory is given back when a `Jit` is dropped.

use std::panic::{AssertUnwindSafe, catch_unwind};

use fmsvm_block::{Block, Flow, Letter, Machine, Stop};
use fmsvm_compiler::ir::{Op, Program};
use fmsvm_compiler::{Options, compile_str};
use fmsvm_vm::jit::Jit;
use fmsvm_vm::{EngineKind, Limits, MemoryPort, RunError, RunOptions, Stats, Variables};

/// A machine that panics on the `at`-th block (0-based) and on reading #5000; otherwise counts.
struct Faulty {
    at: usize,
    blocks: usize,
}

impl Machine for Faulty {
    fn block(&mut self, block: &Block<'_>) -> Result<Flow, Stop> {
        if self.blocks == self.at {
            panic!(
                "the machine broke at block {} (line {})",
                self.blocks, block.line
            );
        }
        self.blocks += 1;
        Ok(Flow::Continue)
    }
    fn read_system(&mut self, number: u32) -> Result<f64, Stop> {
        if number == 5000 {
            panic!("the machine broke reading #5000");
        }
        Ok(0.0)
    }
    fn write_system(&mut self, _: u32, _: f64) -> Result<(), Stop> {
        Ok(())
    }
    fn increment(&self, _: Letter) -> f64 {
        0.001
    }
}

fn compile(src: &str) -> Program {
    let (p, d, _) = compile_str(src, &Options::default());
    p.unwrap_or_else(|| panic!("{d:?}"))
}

fn run_on(p: &Program, m: &mut Faulty, engine: EngineKind) -> Result<Stats, RunError> {
    let options = RunOptions {
        engine,
        limits: Limits {
            max_steps: 100_000,
            ..Limits::default()
        },
        ..RunOptions::default()
    };
    fmsvm_vm::run(
        p,
        m,
        &mut MemoryPort::default(),
        &mut Variables::default(),
        &options,
    )
}

/// Runs `src` on `engine` with a machine failing at block `at`; returns the panic's message.
fn panic_message(src: &str, at: usize, engine: EngineKind) -> String {
    let p = compile(src);
    let mut m = Faulty { at, blocks: 0 };
    let payload = catch_unwind(AssertUnwindSafe(|| run_on(&p, &mut m, engine)))
        .expect_err("the machine's panic must reach the caller");
    match payload.downcast::<String>() {
        Ok(s) => *s,
        Err(p) => p
            .downcast::<&str>()
            .map(|s| s.to_string())
            .unwrap_or_default(),
    }
}

/// The tests of this file one at a time, so the memory measurement sees no other test's allocations.
static ALONE: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn alone() -> std::sync::MutexGuard<'static, ()> {
    ALONE.lock().unwrap_or_else(|e| e.into_inner())
}

const ENGINES: [EngineKind; 3] = [EngineKind::Interp, EngineKind::Jit, EngineKind::Auto];

#[test]
fn a_panic_in_the_machine_unwinds_out_of_every_engine() {
    let _alone = alone();
    let src = "%\nO1\nG1 X1\nG1 X2\nG1 X3\nM30\n%\n";
    for engine in ENGINES {
        assert_eq!(
            panic_message(src, 1, engine),
            "the machine broke at block 1 (line 4)",
            "{engine:?}"
        );
    }
}

#[test]
fn a_panic_under_nested_calls_unwinds_through_every_native_frame() {
    let _alone = alone();
    // Main → G65 O9001 → M98 O9002, which emits the failing block inside a loop: three native
    // activations are on the stack when the machine panics.
    let src = "%\nO1\nG1 X0\nG65 P9001 A2.\nM30\nO9001\nM98 P9002\nM99\nO9002\n#1=0\nWHILE[#1 LT 5]DO1\nG1 X#1\n#1=#1+1\nEND1\nM99\n%\n";
    for engine in ENGINES {
        assert_eq!(
            panic_message(src, 3, engine),
            "the machine broke at block 3 (line 12)",
            "{engine:?}"
        );
    }
}

#[test]
fn a_panic_in_a_system_variable_read_unwinds_too() {
    let _alone = alone();
    let src = "%\nO1\n#1=#5000\nG1 X#1\nM30\n%\n";
    for engine in ENGINES {
        assert_eq!(
            panic_message(src, usize::MAX, engine),
            "the machine broke reading #5000",
            "{engine:?}"
        );
    }
}

#[test]
fn the_same_program_runs_again_after_a_caught_panic() {
    let _alone = alone();
    let p = compile("%\nO1\nG1 X1\nG1 X2\nM30\n%\n");
    let jit = Jit::<Faulty>::compile(&p).expect("compiles");
    let mut broken = Faulty { at: 0, blocks: 0 };
    let caught = catch_unwind(AssertUnwindSafe(|| {
        fmsvm_vm::run_compiled(
            &p,
            &jit,
            &mut broken,
            &mut MemoryPort::default(),
            &mut Variables::default(),
            &RunOptions::default(),
        )
    }));
    assert!(caught.is_err());
    let mut fine = Faulty {
        at: usize::MAX,
        blocks: 0,
    };
    let stats = fmsvm_vm::run_compiled(
        &p,
        &jit,
        &mut fine,
        &mut MemoryPort::default(),
        &mut Variables::default(),
        &RunOptions::default(),
    )
    .expect("runs");
    assert_eq!((stats.blocks, fine.blocks), (3, 3));
}

#[test]
fn a_program_the_verifier_refuses_runs_on_no_engine() {
    let _alone = alone();
    let mut p = compile("%\nO1\n#1=2\n#2=#1*3\nG1 X#2\nM30\n%\n");
    // A slot far outside the registers: trusted, the JIT would write out of bounds.
    let f = &mut p.functions[0];
    let pc = f
        .ops
        .iter()
        .position(|op| matches!(op, Op::Word { .. }))
        .expect("a word op");
    f.ops.insert(
        pc,
        Op::Copy {
            dst: 60_000,
            src: 1,
        },
    );
    f.spans.insert(pc, Default::default());
    for engine in ENGINES {
        let mut m = Faulty {
            at: usize::MAX,
            blocks: 0,
        };
        let e = run_on(&p, &mut m, engine).expect_err("refused");
        let text = e.stop.to_string();
        assert!(
            text.contains("invalid IR") && text.contains("slot 60000 out of range"),
            "{engine:?}: {text}"
        );
        assert_eq!(m.blocks, 0, "nothing ran");
    }
    let e = Jit::<Faulty>::compile(&p)
        .err()
        .expect("the JIT refuses it");
    assert!(e.to_string().contains("slot 60000 out of range"), "{e}");
}

fn resident_pages() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/statm").ok()?;
    s.split_whitespace().nth(1)?.parse().ok()
}

#[test]
fn dropping_a_jit_gives_its_code_memory_back() {
    let _alone = alone();
    // A small program: its code memory is a few pages per compile, against no growth at all.
    let src = "%\nO1\n#1=0\nWHILE[#1 LT 3]DO1\nG1 X[SIN[#1]*2] Y#1\n#1=#1+1\nEND1\nM30\n%\n";
    let p = compile(src);
    // Warm up (allocator arenas, Cranelift's lazily built tables).
    for _ in 0..20 {
        drop(Jit::<Faulty>::compile(&p).expect("compiles"));
    }
    let Some(before) = resident_pages() else {
        return; // not Linux: nothing to measure
    };
    for _ in 0..150 {
        drop(Jit::<Faulty>::compile(&p).expect("compiles"));
    }
    let after = resident_pages().unwrap_or(before);
    // Without freeing, each compile keeps its code pages: about 160 pages here; freed, about 16.
    let grown = after.saturating_sub(before);
    assert!(
        grown < 80,
        "resident memory grew by {grown} pages over 150 compiles"
    );
}
