//! fmsvm-vm: runs a compiled [`Program`] against a [`Machine`].
//!
//! The VM owns the macro variables (locals per level, commons) and the control flow; everything a G
//! or M code means belongs to the Machine (the runtime's kernel). Alarms come back as data with the
//! op that raised them, so the caller can point at the source; the VM prints nothing.
#![deny(missing_docs)]

#[cfg(feature = "jit")]
mod abi;
mod calls;
pub mod debug;
mod exec;
mod gate;
mod interp;
#[cfg(feature = "jit")]
pub mod jit;
pub mod print;
pub mod value;

use fmsvm_block::alarms::NO_FANUC_NUMBER;
use fmsvm_block::{Machine, Stop, VACANT};
use fmsvm_ir::{COMMONS, Program, Span};

pub use calls::spec_i;
pub use gate::BlockGate;
pub use interp::TIER_UP_STEPS;
pub use print::{MemoryPort, Port};

/// Limits that stop runaway programs.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Branches taken (loop iterations and jumps); 0 = no limit.
    pub max_steps: u64,
    /// NC blocks handed to the Machine; 0 = no limit.
    pub max_blocks: u64,
    /// Wall time; None = no limit.
    pub max_time: Option<std::time::Duration>,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_steps: 1_000_000_000,
            max_blocks: 10_000_000,
            max_time: None,
        }
    }
}

/// Which engine runs the IR. Both give byte-identical output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EngineKind {
    /// The interpreter.
    Interp,
    /// The Cranelift JIT.
    Jit,
    /// The interpreter, moving to the JIT when the program has looped long enough to pay for
    /// compiling (on-stack replacement at a loop head).
    #[default]
    Auto,
}

/// How a run behaves where controls differ, and its limits.
#[derive(Clone, Copy, Debug)]
pub struct RunOptions {
    /// Which engine runs the program.
    pub engine: EngineKind,
    /// Limits that stop runaway programs.
    pub limits: Limits,
    /// DPRNT/BPRNT without POPEN write anyway (Haas: the port is always open) instead of an alarm.
    pub print_without_popen: bool,
    /// `M99` in the main program ends the run and stays in the flat program (the control repeats it),
    /// instead of restarting the expansion (bounded by the step limit), macro-b-rules C9.
    pub main_m99_ends: bool,
    /// Subprogram (M98/M97) nesting allowed, 1–10 (Fanuc: 4, C7).
    pub max_sub_depth: u8,
    /// Arithmetic options (NAT, MOD on integers).
    pub semantics: value::Semantics,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            engine: EngineKind::default(),
            limits: Limits::default(),
            print_without_popen: false,
            main_m99_ends: false,
            max_sub_depth: calls::DEFAULT_SUB_DEPTH,
            semantics: value::Semantics::default(),
        }
    }
}

/// The macro variables that outlive a run: the commons (#100–#999, as the program's `CommonRanges` allow).
#[derive(Clone, Debug)]
pub struct Variables {
    /// Index = `fmsvm_ir::common_index(n)`.
    pub commons: Box<[f64; COMMONS]>,
}

impl Default for Variables {
    fn default() -> Self {
        Variables {
            commons: Box::new([VACANT; COMMONS]),
        }
    }
}

/// What a finished run did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Branches taken.
    pub steps: u64,
    /// NC blocks handed to the Machine.
    pub blocks: u64,
}

/// Why a run stopped early, and where.
#[derive(Debug)]
pub struct RunError {
    /// The reason.
    pub stop: Stop,
    /// The source of the op that stopped.
    pub span: Span,
    /// Work done up to the stop.
    pub stats: Stats,
}

/// The stop (the span is the caller's to render against its sources).
impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.stop.fmt(f)
    }
}

impl std::error::Error for RunError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.stop)
    }
}

/// What a finished run gives its caller.
fn outcome<M: Machine>(mut ctx: exec::Ctx<'_, M>, status: exec::Status) -> Result<Stats, RunError> {
    let stats = ctx.stats;
    match (status, ctx.error.take()) {
        (exec::Status::Error, Some((stop, span))) => Err(RunError {
            stop,
            span: span.unwrap_or_default(),
            stats,
        }),
        _ => Ok(stats),
    }
}

/// Runs the main program on an already compiled JIT (benchmarks keep compile time apart this way).
#[cfg(feature = "jit")]
pub fn run_compiled<M: Machine>(
    program: &Program,
    jit: &jit::Jit<M>,
    machine: &mut M,
    port: &mut dyn Port,
    vars: &mut Variables,
    options: &RunOptions,
) -> Result<Stats, RunError> {
    let mut ctx = exec::Ctx::new(program, machine, port, &mut vars.commons[..], *options);
    let status = ctx.run_main(jit);
    outcome(ctx, status)
}

/// A run that could not start (alarm 0 with the reason, at no source position).
fn refused(message: String) -> RunError {
    RunError {
        stop: Stop::Alarm(fmsvm_block::Alarm::new(NO_FANUC_NUMBER, message)),
        span: Span::default(),
        stats: Stats::default(),
    }
}

/// Runs the main program (`program.functions[0]`) to its end. DPRNT/BPRNT records go to `port`.
/// A program the IR verifier refuses is not run on either engine (alarm 0 with the reason).
pub fn run<M: Machine>(
    program: &Program,
    machine: &mut M,
    port: &mut dyn Port,
    vars: &mut Variables,
    options: &RunOptions,
) -> Result<Stats, RunError> {
    if let Err(e) = program.verify() {
        return Err(refused(e.to_string()));
    }
    let mut ctx = exec::Ctx::new(program, machine, port, &mut vars.commons[..], *options);
    // A debugger needs a place to stop before every op: the interpreter, whatever the engine.
    if let Some(d) = debug::installed() {
        let status = ctx.run_main(&interp::Interpreter::<M, true> {
            tier: None,
            debugger: Some(&*d),
        });
        return outcome(ctx, status);
    }
    let status = match options.engine {
        EngineKind::Interp => ctx.run_main(&interp::Interpreter::<M, false> {
            tier: None,
            debugger: None,
        }),
        #[cfg(feature = "jit")]
        EngineKind::Auto => {
            // Interpret; move to the JIT once the program has looped long enough to pay for it.
            let lazy = jit::Lazy::new(program);
            ctx.run_main(&interp::Interpreter::<M, false> {
                tier: Some(&lazy),
                debugger: None,
            })
        }
        #[cfg(feature = "jit")]
        EngineKind::Jit => match jit::Jit::<M>::compile(program) {
            Ok(j) => ctx.run_main(&j),
            Err(e) => return Err(refused(e.to_string())),
        },
        // Without the JIT, `auto` interprets, and `jit` cannot run.
        #[cfg(not(feature = "jit"))]
        EngineKind::Auto => ctx.run_main(&interp::Interpreter::<M, false> {
            tier: None,
            debugger: None,
        }),
        #[cfg(not(feature = "jit"))]
        EngineKind::Jit => {
            return Err(refused(
                "--engine jit: this fmsvm was built without the JIT (the `jit` feature)".into(),
            ));
        }
    };
    outcome(ctx, status)
}
