//! The debugger's view of a run: with a [`Debugger`] installed on the thread, `run` interprets (the
//! JIT has no place to stop) and calls it before every op with where the op is, how deep the calls
//! go, the activation's locals and the commons; the debugger may block there (a breakpoint) and read
//! system variables through the machine. Without one, nothing changes.

use std::cell::RefCell;
use std::rc::Rc;

use fmsvm_ir::Span;

/// What the debugger sees before an op.
pub struct Stop<'a> {
    /// The op's source.
    pub span: Span,
    /// The program running (its O number; None for lines before the first O word).
    pub program: Option<u32>,
    /// Macro and subprogram levels: 0 in the main program.
    pub depth: u8,
    /// The activation's #1–#33 (index 0 unused).
    pub locals: &'a [f64],
    /// The common variables (`fmsvm_ir::common_index`).
    pub commons: &'a [f64],
    /// Reads system variable `n` as the machine has it now (None: it cannot be read).
    pub system: &'a mut dyn FnMut(u32) -> Option<f64>,
}

/// A debugger: told of every op before it runs.
pub trait Debugger {
    /// Called before each op (a debugger that pauses blocks inside); false stops the run there
    /// (alarm 0, "stopped by the debugger").
    fn before(&self, at: &mut Stop<'_>) -> bool;
}

thread_local! {
    static INSTALLED: RefCell<Option<Rc<dyn Debugger>>> = const { RefCell::new(None) };
}

/// Runs `f` with `debugger` installed on this thread: every `run` inside it interprets and calls it.
pub fn with_debugger<R>(debugger: Rc<dyn Debugger>, f: impl FnOnce() -> R) -> R {
    let _restore = Installed::replace(Some(debugger));
    f()
}

/// Runs `f` with no debugger on this thread (a debugger's own evaluation of an expression).
pub fn without_debugger<R>(f: impl FnOnce() -> R) -> R {
    let _restore = Installed::replace(None);
    f()
}

/// The debugger that was installed before, put back when dropped: also when `f` panics (a
/// caller that catches the panic finds the thread as it was).
struct Installed(Option<Rc<dyn Debugger>>);

impl Installed {
    fn replace(debugger: Option<Rc<dyn Debugger>>) -> Installed {
        Installed(INSTALLED.with(|d| d.replace(debugger)))
    }
}

impl Drop for Installed {
    fn drop(&mut self) {
        let before = self.0.take();
        INSTALLED.with(|d| *d.borrow_mut() = before);
    }
}

/// The debugger installed on this thread, if any.
pub(crate) fn installed() -> Option<Rc<dyn Debugger>> {
    INSTALLED.with(|d| d.borrow().clone())
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Never;
    impl Debugger for Never {
        fn before(&self, _: &mut Stop<'_>) -> bool {
            false
        }
    }

    /// A panic inside `with_debugger`, caught by its caller, leaves no debugger on the thread:
    /// the next run on it is not stopped by a session that has ended.
    #[test]
    fn a_panic_inside_leaves_the_thread_as_it_was() {
        let caught = std::panic::catch_unwind(|| {
            with_debugger(Rc::new(Never), || panic!("inside the run"));
        });
        assert!(caught.is_err());
        assert!(installed().is_none());
        with_debugger(Rc::new(Never), || {
            without_debugger(|| assert!(installed().is_none()));
            assert!(installed().is_some());
        });
        assert!(installed().is_none());
    }
}
