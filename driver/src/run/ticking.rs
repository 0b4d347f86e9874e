//! An emitter that tells a `Progress` how many canonical operations pass through it on their way to
//! a report or a picture, a batch at a time (the hot path pays one add and one test an operation).

use std::sync::Arc;

use fmsvm_block::{Code, Stop};
use fmsvm_canon::decode::Decoded;
use fmsvm_canon::{Canon, Context, Emitter, Origin};

use crate::output::Progress;

/// Operations told at once.
const BATCH: u64 = 4096;

/// `inner`, its operations counted for `progress`.
pub struct Ticking<E> {
    inner: E,
    progress: Option<Arc<dyn Progress>>,
    /// Operations not yet told.
    untold: u64,
}

impl<E> Ticking<E> {
    pub fn new(inner: E, progress: Option<Arc<dyn Progress>>) -> Self {
        Ticking {
            inner,
            progress,
            untold: 0,
        }
    }

    /// The emitter, the progress told that the run has ended.
    pub fn into_inner(mut self) -> E {
        if let Some(p) = self.progress.take() {
            p.operations(self.untold);
            p.done();
        }
        self.inner
    }
}

impl<E: Emitter> Emitter for Ticking<E> {
    const CANON: bool = E::CANON;

    fn begin(&mut self, number: Option<u32>, title: &str) -> Result<(), Stop> {
        self.inner.begin(number, title)
    }
    fn block(&mut self, block: &Decoded<'_, '_>, ctx: &Context) -> Result<(), Stop> {
        self.inner.block(block, ctx)
    }
    fn canon(&mut self, op: &Canon<'_>, origin: Origin) -> Result<(), Stop> {
        self.untold += 1;
        if self.untold == BATCH
            && let Some(p) = &self.progress
        {
            p.operations(BATCH);
            self.untold = 0;
        }
        self.inner.canon(op, origin)
    }
    fn native_cycle(&self, code: Code) -> bool {
        self.inner.native_cycle(code)
    }
    fn corners(&self) -> bool {
        self.inner.corners()
    }
    fn written(&self) -> u64 {
        self.inner.written()
    }
    fn end(&mut self) -> Result<(), Stop> {
        self.inner.end()
    }
    fn settle(&mut self) -> Result<(), Stop> {
        self.inner.settle()
    }
    fn message(&mut self, number: u32, text: &str) -> Result<(), Stop> {
        self.inner.message(number, text)
    }
}
