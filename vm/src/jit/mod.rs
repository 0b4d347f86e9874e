//! The Cranelift JIT engine: every IR function becomes one native function, compiled once per run.
//!
//! `Jit<M>` owns the ISA and the `JITModule` (which owns the code). A native function takes
//! `(ctx, engine, regs_view, regs, commons, start_block)` and returns an `abi` status. Slots live in the
//! activation's register array (loads and stores; constant slots are immediates); arithmetic,
//! comparisons, branches, step counting and common variables are inline; everything else calls the
//! `abi` entry points, which run the same `Ctx` services as the interpreter.
//!
//! The JIT trusts nothing it has not checked: `compile` refuses a program the IR verifier refuses
//! (slots become raw offsets here), `exec` checks that the activation's registers and commons are as
//! large as the code was compiled for, a panic in a helper is resumed here once the native code has
//! returned, and dropping a `Jit` frees its code memory.

mod lower;

use std::marker::PhantomData;
use std::mem::ManuallyDrop;

use cranelift_codegen::settings::{self, Configurable};
use cranelift_jit::{JITBuilder, JITModule};
use fmsvm_block::Machine;
use fmsvm_ir::{COMMONS, Program};

use crate::abi::{self, Helper};
use crate::exec::{Ctx, Engine, Status};

/// Why the JIT could not compile a program (the interpreter can still run it).
#[derive(Debug)]
pub struct JitError(pub String);

impl std::fmt::Display for JitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "JIT compilation failed: {}", self.0)
    }
}

impl std::error::Error for JitError {}

/// The native entry point of one IR function.
type Native = unsafe extern "C" fn(
    *mut u8,
    *const u8,
    *mut crate::abi::Registers,
    *mut f64,
    *mut f64,
    u32,
) -> u64;

/// A compiled program for machines of type `M`.
pub struct Jit<M: Machine> {
    /// Owns the machine code the function pointers point into; freed on drop.
    module: ManuallyDrop<JITModule>,
    functions: Vec<Native>,
    /// The slots each function was compiled for (its register array is at least this long).
    slots: Vec<usize>,
    _machine: PhantomData<fn(&mut M)>,
}

impl<M: Machine> Drop for Jit<M> {
    fn drop(&mut self) {
        // SAFETY: the function pointers into this memory live in `self.functions` only, are called
        // only through `&self` (so no call is running now), and are dropped with `self`; nothing
        // else holds a pointer into the module's code or data.
        unsafe { ManuallyDrop::take(&mut self.module).free_memory() };
    }
}

/// The most IR ops of one function the JIT compiles.
pub const MAX_OPS: usize = 20_000;

fn err(e: impl std::fmt::Display) -> JitError {
    JitError(e.to_string())
}

impl<M: Machine> Jit<M> {
    /// Compiles every function of `program`, after the IR verifier accepted it.
    pub fn compile(program: &Program) -> Result<Self, JitError> {
        program.verify().map_err(err)?;
        // Cranelift's time grows faster than the code (a 17 000-statement function: 1.6–2.8 s); a
        // function that long is straight-line code the interpreter runs once at once.
        if let Some(f) = program.functions.iter().find(|f| f.ops.len() > MAX_OPS) {
            return Err(JitError(format!(
                "{} has {} IR ops, more than the JIT compiles ({MAX_OPS}): run it with --engine interp or auto",
                f.name(),
                f.ops.len()
            )));
        }
        let mut flags = settings::builder();
        // No egraph pass: the lowering already emits what it would find (measured: the arithmetic loop
        // and the hemisphere run no slower, the compile takes half the time; docs/performance.md).
        flags.set("opt_level", "none").map_err(err)?;
        // Cranelift's own IR verifier took 40 % of the compile (the hemisphere: 18 M of 45 M
        // instructions). Debug builds — every test — keep it, so each test program's lowering is
        // verified; release builds trust what the tests verified (docs/performance.md).
        flags
            .set(
                "enable_verifier",
                if cfg!(debug_assertions) {
                    "true"
                } else {
                    "false"
                },
            )
            .map_err(err)?;
        flags.set("use_colocated_libcalls", "false").map_err(err)?;
        flags.set("is_pic", "false").map_err(err)?;
        let isa = cranelift_native::builder()
            .map_err(err)?
            .finish(settings::Flags::new(flags))
            .map_err(err)?;
        let mut builder = JITBuilder::with_isa(isa, cranelift_module::default_libcall_names());
        for &h in Helper::ALL {
            builder.symbol(h.name(), h.address::<M>());
        }
        // From here the module owns code memory: `jit` frees it on every path out (Drop).
        let mut jit = Jit {
            module: ManuallyDrop::new(JITModule::new(builder)),
            functions: Vec::new(),
            slots: program
                .functions
                .iter()
                .map(|f| f.n_slots as usize)
                .collect(),
            _machine: PhantomData,
        };
        let module = &mut *jit.module;
        // A panic inside Cranelift would be a bug in the lowering; it must not take the run down: the
        // caller falls back to the interpreter.
        let ids = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            lower::compile_all::<M>(module, program)
        }))
        .map_err(|_| JitError("the code generator failed (a bug in fmsvm's JIT)".into()))??;
        module.finalize_definitions().map_err(err)?;
        jit.functions = ids
            .into_iter()
            .map(|id| {
                let code = module.get_finalized_function(id);
                // SAFETY: `code` was compiled with exactly the `Native` signature (lower::signature),
                // and the module that owns it lives as long as `self`. This is the one transmute.
                unsafe { std::mem::transmute::<*const u8, Native>(code) }
            })
            .collect();
        Ok(jit)
    }
}

/// A JIT compiled on first use (`--engine auto`); a program the JIT cannot compile stays interpreted.
pub struct Lazy<'p, M: Machine> {
    program: &'p Program,
    cell: std::cell::OnceCell<Option<Jit<M>>>,
}

impl<'p, M: Machine> Lazy<'p, M> {
    /// Nothing compiled yet.
    pub fn new(program: &'p Program) -> Self {
        Lazy {
            program,
            cell: std::cell::OnceCell::new(),
        }
    }

    /// The JIT, compiled now if it is the first ask.
    pub fn get(&self) -> Option<&Jit<M>> {
        self.cell
            .get_or_init(|| Jit::compile(self.program).ok())
            .as_ref()
    }
}

impl<M: Machine> Engine<M> for Jit<M> {
    fn exec(&self, ctx: &mut Ctx<'_, M>, fi: usize, regs: &mut [f64], pc: usize) -> Status {
        // The native code indexes registers and commons without checks: make sure they are as large
        // as it was compiled for (a `Ctx` of another program, or a short vector, is a bug).
        let (Some(&native), Some(&slots)) = (self.functions.get(fi), self.slots.get(fi)) else {
            panic!("fmsvm bug: the JIT has no function {fi}");
        };
        assert!(
            regs.len() >= slots && ctx.commons.len() >= COMMONS,
            "fmsvm bug: function {fi} runs with {} registers and {} commons, compiled for {slots} and {COMMONS}",
            regs.len(),
            ctx.commons.len()
        );
        let f = &ctx.program.functions[fi];
        let Ok(start) = f.blocks.binary_search(&(pc as u32)) else {
            panic!(
                "fmsvm bug: {} entered at op {pc}, which starts no block",
                f.name()
            );
        };
        // The registers go to native code as a fixed slice (`abi::Registers`): no entry point can
        // reach the vector that owns them, so none can resize it under the native code's pointer.
        let mut view = abi::Registers::of(regs);
        let regs_ptr = view.ptr();
        let commons = ctx.commons.as_mut_ptr();
        // SAFETY: the pointers are live for the call: `ctx` and `regs` are exclusive borrows held by
        // this frame, `view` describes `regs` and lives on this frame, `commons` points into
        // `ctx.commons`, and the native code only reaches them through `abi`, which restores the
        // same types. The registers are a slice, so their buffer cannot move during the call, and
        // they and the commons are as long as the code indexes (checked above; the verifier checked
        // every slot and common index against them).
        let status = unsafe {
            native(
                ctx as *mut Ctx<'_, M> as *mut u8,
                self as *const Self as *const u8,
                &mut view,
                regs_ptr,
                commons,
                start as u32,
            )
        };
        // A helper panicked: the native code has returned; go on unwinding as the interpreter would.
        if let Some(payload) = ctx.panic.take() {
            std::panic::resume_unwind(payload);
        }
        abi::decode(status)
    }
}
