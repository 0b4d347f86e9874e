//! The plain move: a raster's or a CAM file's block (only N, G0/G1, axis and F words in G90)
//! taken by a shorter way to exactly the general path's state, canonical operations and bytes
//! (`--without plain` turns it off; tests/plain.rs holds the two together).

use super::*;

/// The letters of a plain move: N, G (G0 or G1), the axes, F.
pub(super) const PLAIN_LETTERS: u32 = 1 << Letter::N as u32
    | 1 << Letter::G as u32
    | 1 << Letter::F as u32
    | 1 << Letter::X as u32
    | 1 << Letter::Y as u32
    | 1 << Letter::Z as u32
    | 1 << Letter::A as u32
    | 1 << Letter::B as u32
    | 1 << Letter::C as u32;

/// Each letter's place in `AXES`, or `NOT_AN_AXIS`.
const AXIS_OF: [u8; Letter::COUNT] = {
    let mut t = [NOT_AN_AXIS; Letter::COUNT];
    let mut i = 0;
    while i < AXES.len() {
        t[AXES[i] as usize] = i as u8;
        i += 1;
    }
    t
};
const NOT_AN_AXIS: u8 = u8::MAX;
impl<E: Emitter> Kernel<E> {
    /// The plain move: a block of only N, G0/G1, axis and F words in G90, with no canned cycle or
    /// polar coordinates in effect (a raster's or a CAM file's every block). It has the general
    /// path's effects (the modal motion, the literal words or the canonical operations, the last
    /// values, the position, the time) in fewer steps; None when the block is not one, and nothing
    /// has changed.
    #[inline]
    pub(super) fn plain_move(&mut self, block: &Block<'_>) -> Option<Result<Flow, Stop>> {
        if !self.settings.plain_moves
            // A lathe reads X as a diameter and U W as increments: the general path.
            || self.settings.lathe.is_some()
            || self.modal.get(Group::CannedCycle) != Code::G80
            || self.modal.get(Group::Polar) == Code::G16
            || self.modal.incremental()
            || (E::CANON && !self.canon_plain_ready(block))
        {
            return None;
        }
        let mut letters = 0u32;
        let mut motion = self.modal.get(Group::Motion);
        // Decoded on the way (a plain block cannot change the units); a word that does not decode
        // sends the block to the general path, which raises its alarm in its order.
        let inch = self.modal.inch();
        let mut fits = true;
        let words = block.words();
        let slots = &mut self.decoded[..words.len()];
        for (slot, word) in slots.iter_mut().zip(words) {
            letters |= 1 << word.letter as u32;
            if word.letter == Letter::G {
                // Exactly G0 or G1 (G0.5, G01.0 by an expression and the rest: the general path).
                motion = if word.value == 0.0 {
                    Code::G0
                } else if word.value == 1.0 {
                    Code::G1
                } else {
                    return None;
                };
            }
            let v = self.rules.value(word, inch);
            fits &= self.rules.fits(word, v, inch);
            *slot = v;
        }
        if letters & self.not_plain != 0
            || block.any_flags().has(WordFlags::INCREMENTAL)
            || !fits
            || !matches!(motion, Code::G0 | Code::G1)
        {
            return None;
        }
        let names_motion = letters & (1 << Letter::G as u32) != 0;
        if E::CANON {
            return self.plain_move_canon(block, motion, names_motion);
        }
        Some(self.plain_move_words(block, inch, motion, names_motion))
    }

    /// Under canonical output, whether nothing in force takes a plain block off the straight way
    /// from its words to one move: no transform, compensation, held move or operation, lathe
    /// cycle or profile being read, and the block has no comment and no block delete.
    #[inline]
    fn canon_plain_ready(&self, block: &Block<'_>) -> bool {
        self.capture.is_none()
            && self.transform.is_identity()
            && !self.comp.is_active()
            && self.pending.is_none()
            && self.held.is_empty()
            && self.single_cycle.is_none()
            && block.comment.is_empty()
            && !block.block_delete
    }

    /// `plain_move` under canonical output, its words decoded into `self.decoded`: the general
    /// path's F, then its one rapid or feed (`programmed_motion`, `out_target`, `canon`, `contour`
    /// and `emit_move` with nothing in force). None, with nothing changed, where the general path
    /// has more to say: the output frame moved (`follow_frame`), an axis is unknown, or an axis
    /// the block does not name moves (its warning).
    #[inline]
    fn plain_move_canon(
        &mut self,
        block: &Block<'_>,
        motion: Code,
        names_motion: bool,
    ) -> Option<Result<Flow, Stop>> {
        if self.output_origin() != self.frame_origin {
            return None;
        }
        let words = block.words();
        let values = &self.decoded[..words.len()];
        let mut to = self.position;
        let mut named = 0u8;
        let mut feed = None;
        for (word, &v) in words.iter().zip(values) {
            let axis = AXIS_OF[word.letter.index()];
            if axis != NOT_AN_AXIS {
                to[axis as usize] = v;
                named |= 1 << axis;
            } else if word.letter == Letter::F {
                feed = Some(v);
            }
        }
        // `out_target`: an axis the block does not name whose output is unknown stays where the
        // tool is; a named one is the general path's alarm, an unnamed one that moves its warning.
        let mut out = self.out_point(&to);
        if named != 0 {
            for (i, (v, &from)) in out.iter_mut().zip(&self.path_from).enumerate() {
                let is_named = named & (1 << i) != 0;
                if v.is_nan() {
                    if is_named {
                        return None;
                    }
                    *v = from;
                } else if !is_named && !from.is_nan() && (*v - from).abs() >= 5e-4 {
                    return None;
                }
            }
        }
        if names_motion {
            self.modal.set(motion);
        }
        if self.hole_step != [0.0; 2] {
            self.hole_step = [0.0; 2];
        }
        for (word, &v) in words.iter().zip(&self.decoded[..words.len()]) {
            self.last[word.letter.index()] = v;
        }
        self.warned_axes = 0;
        self.stage = Stage::default();
        let origin = Origin {
            block_delete: false,
            ..Origin::of(block, !named & 0b11_1111)
        };
        Some(self.plain_canon_ops(block, motion, feed, (to, out), origin, named != 0))
    }

    /// The canonical operations of a plain move `plain_move_canon` has taken: F, then the move to
    /// `to` (programmed) at `out` (output frame).
    #[inline]
    fn plain_canon_ops(
        &mut self,
        block: &Block<'_>,
        motion: Code,
        feed: Option<f64>,
        (to, out): (Pose, Pose),
        origin: Origin,
        moves: bool,
    ) -> Result<Flow, Stop> {
        if let Some(f) = feed {
            self.emitter.canon(&Canon::FeedRate(f), origin)?;
        }
        if !moves {
            return Ok(Flow::Continue);
        }
        self.path_from = out;
        self.out_position = out;
        let op = if motion == Code::G0 {
            Canon::Rapid(out)
        } else {
            Canon::Feed(out)
        };
        self.emitter.canon(&op, origin)?;
        let start = self.position;
        self.position = to;
        self.timing
            .motion(&self.modal, &start, &self.position, block, &self.last);
        Ok(Flow::Moved)
    }

    /// `plain_move` once the block is known to be one, its words decoded into `self.decoded`.
    #[inline]
    pub(super) fn plain_move_words(
        &mut self,
        block: &Block<'_>,
        inch: bool,
        motion: Code,
        names_motion: bool,
    ) -> Result<Flow, Stop> {
        if names_motion {
            self.modal.set(motion);
        }
        let decoded = Decoded::view(block, &self.decoded);
        if self.hole_step != [0.0; 2] {
            self.hole_step = [0.0; 2];
        }
        let ctx = Context {
            inch,
            absolute: true,
            motion,
            pq_integers: false,
            per_rev: self.modal.get(Group::FeedMode) == Code::G95,
        };
        self.emitter.block(&decoded, &ctx)?;
        let start = self.position;
        let mut moved = false;
        let (words, values) = (block.words(), decoded.values());
        for i in 0..words.len().min(values.len()) {
            let (word, v) = (&words[i], values[i]);
            self.last[word.letter.index()] = v;
            let axis = AXIS_OF[word.letter.index()];
            if axis != NOT_AN_AXIS {
                self.position[axis as usize] = v;
                moved = true;
            }
        }
        if !moved {
            return Ok(Flow::Continue);
        }
        self.timing
            .motion(&self.modal, &start, &self.position, block, &self.last);
        Ok(Flow::Moved)
    }
}
