//! `--verify`: the output read back and its motion proved equal to the kernel's.

use std::io;
use std::path::{Path, PathBuf};

use fmsvm_block::Stop;
use fmsvm_kernel::probe::ProbeModel;
use fmsvm_vm::Variables;

use crate::exit::Exit;
use crate::report::plain;
use crate::request::{Machine, N33G18, Request};

use super::*;

/// A print port that keeps nothing (the second expansion of `--verify` prints nothing again).
pub(super) struct Discard;

impl fmsvm_vm::print::Port for Discard {
    fn open(&mut self) -> Result<(), Stop> {
        Ok(())
    }
    fn write(&mut self, _: &[u8]) -> Result<(), Stop> {
        Ok(())
    }
    fn close(&mut self) -> Result<(), Stop> {
        Ok(())
    }
}

/// What a second expansion for `--verify` runs with.
pub(super) struct Again<'a> {
    pub(super) profile: &'a crate::dialects::Profile,
    pub(super) resolve: bool,
}

/// `--verify` and `--verify-file`: `out` read back and checked, the outcome reported.
pub(super) fn verify(
    job: &Job<'_>,
    again: &Again<'_>,
    out: &Path,
    probe: ProbeModel,
    vars: &mut Variables,
) -> Exit {
    let checked = if again.resolve {
        verify_resolved(job, again, out, probe, vars)
    } else {
        verify_literal(
            job.a,
            out,
            job.rules.second_aux,
            job.settings.lathe.is_some(),
        )
    };
    verified(job, again.profile, out, checked)
}

/// The outcome of `--verify` or `--verify-file` on `out` reported: the moves read back, or the
/// first difference (the output then removed, or kept as a partial file).
pub(super) fn verified(
    job: &Job<'_>,
    profile: &crate::dialects::Profile,
    out: &Path,
    checked: Result<u64, String>,
) -> Exit {
    match checked {
        Ok(moves) => {
            if !job.a.input.quiet {
                plain_info(&format!(
                    "verified: {} of {} read back match the kernel's within the {} dialect's resolution",
                    crate::report::count(moves as usize, "move", "moves"),
                    out.display(),
                    profile.dialect.name
                ));
            }
            Exit::Success
        }
        Err(e) => {
            plain(&format!(
                "--verify: {} does not move as the program does: {e}",
                out.display()
            ));
            // A file that failed its check is not left under the name a user sends to the machine:
            // removed, or kept as OUT.PARTIAL.ext with --keep-partial (`--verify-file` names a file
            // written before: it is the user's, left alone).
            if job.a.verify && job.a.verify_file.is_none() {
                if job.a.keep_partial {
                    let kept = partial_name(out);
                    match std::fs::rename(out, &kept) {
                        Ok(()) => {
                            plain_info(&format!("note: the output is kept as {}", kept.display()))
                        }
                        Err(e) => plain_info(&format!(
                            "note: {} could not be renamed: {e}",
                            out.display()
                        )),
                    }
                } else {
                    remove_output(out);
                }
            }
            Exit::Verify
        }
    }
}

/// `--verify` of resolved output: the program expanded again, each canonical operation checked
/// against what the dialect's reader reads back from `out`. The number of moves read, or the first
/// difference.
pub(super) fn verify_resolved(
    job: &Job<'_>,
    again: &Again<'_>,
    out: &Path,
    probe: ProbeModel,
    vars: &mut Variables,
) -> Result<u64, String> {
    use fmsvm_readback::Verifier;
    let file = std::fs::File::open(out).map_err(|e| format!("cannot read it back: {e}"))?;
    let input = io::BufReader::new(file);
    let dialect = &again.profile.dialect;
    match again.profile.kind {
        crate::dialects::Kind::Text => {
            let v = text_verifier(job, dialect, input);
            check_against(job, v, probe, vars)
        }
        crate::dialects::Kind::N33 => {
            let reader = fmsvm_readback::n33::N33Reader::new(input, [0.0; 6])
                .g18_ccw_is_iso(job.a.n33_g18 == N33G18::Iso);
            // The tape has no reference return: one is written as a move.
            let mut d = dialect.clone();
            d.reference = fmsvm_emit::dialect::ReferenceForm::None;
            let mut v = Verifier::new(reader, d, job.a.linearize.unwrap_or(0.01));
            v.rapid_as_feed = true;
            v.rapid_feed = Some(fmsvm_emit::n33::RAPID_MM_PER_MIN);
            v.dwell_units = 100.0;
            v.respell_after_frame_move = false;
            v.unknown_counted_from_start = true;
            v.zero_dwells_written = false;
            // Two significant digits: half a step of the code is under 5 %.
            v.feed_tolerance = 0.05;
            check_against(job, v, probe, vars)
        }
    }
}

/// The verifier of a text dialect's output read from `input`.
pub(super) fn text_verifier<R: io::BufRead>(
    job: &Job<'_>,
    dialect: &fmsvm_emit::dialect::Dialect,
    input: R,
) -> fmsvm_readback::Verifier<fmsvm_readback::words::WordReader<R>> {
    let mut reader = fmsvm_readback::words::WordReader::new(input, dialect.clone());
    reader.second_aux = job.rules.second_aux;
    fmsvm_readback::Verifier::new(reader, dialect.clone(), job.a.linearize.unwrap_or(0.001))
}

/// The program expanded once more, quietly, each canonical operation checked by `v` against what
/// its reader reads back: the moves read, or the first difference.
pub(super) fn check_against<R: fmsvm_readback::Reader>(
    job: &Job<'_>,
    v: fmsvm_readback::Verifier<R>,
    probe: ProbeModel,
    vars: &mut Variables,
) -> Result<u64, String> {
    let quiet_job = Job {
        quiet: true,
        ..*job
    };
    let (result, v) = quiet_job.expand(v, probe, &mut Discard, vars);
    match (result, v.mismatch.clone()) {
        (_, Some(m)) => Err(m),
        (Ok(_), None) => Ok(v.moves()),
        (Err((stop, _)), None) => Err(format!("the second expansion stopped: {stop}")),
    }
}

/// `--verify` of literal (Fanuc) output: the program and the output, each resolved into a
/// temporary file, read back move by move; they must be the same.
pub(super) fn verify_literal(
    a: &Request,
    out: &Path,
    second_aux: Option<fmsvm_block::Letter>,
    turning: bool,
) -> Result<u64, String> {
    // Both resolved in Fanuc's own dialect: the mill's, or the lathe's for a turning program.
    let fanuc = if turning { "fanuc0itd" } else { "fanuc" };
    let mut reading = crate::dialects::builtin(fanuc)
        .map_err(|e| format!("the {fanuc} dialect: {e}"))?
        .dialect;
    reading.turning = turning;
    use fmsvm_readback::{Motion, Reader, words::WordReader};
    let dir = tempfile::tempdir().map_err(|e| format!("cannot make a temporary folder: {e}"))?;
    let resolve_into = |input: &Path, name: &str| -> Result<PathBuf, String> {
        let mut b = a.clone();
        if input != a.input.file {
            // The output, read from its file (the program may be an editor's text).
            b.input.text = None;
        }
        b.input.file = input.to_path_buf();
        b.input.quiet = true;
        b.output = Some(dir.path().join(name));
        b.print = Some(dir.path().join(format!("{name}.prn")));
        b.dump_vars = None;
        b.resolve = true;
        b.verify = false;
        b.verify_file = None;
        b.stats = false;
        b.compact = false;
        b.renumber = None;
        b.comments = false;
        b.dialect = Some(fanuc.into());
        if turning {
            b.machine = Some(Machine::Lathe);
        }
        b.dialect_file = None;
        match run(&b, Consumer::Flat) {
            Exit::Success => Ok(dir.path().join(name)),
            e => Err(format!(
                "resolving {} for the comparison failed (exit {})",
                input.display(),
                e as u8
            )),
        }
    };
    let program = resolve_into(&a.input.file, "program.nc")?;
    let output = resolve_into(out, "output.nc")?;
    let open = |p: &Path| -> Result<WordReader<io::BufReader<std::fs::File>>, String> {
        let f = std::fs::File::open(p).map_err(|e| format!("cannot read {}: {e}", p.display()))?;
        let mut r = WordReader::new(io::BufReader::new(f), reading.clone());
        r.second_aux = second_aux;
        Ok(r)
    };
    let (mut want, mut got) = (open(&program)?, open(&output)?);
    let mut moves = 0u64;
    loop {
        let w = want.next_move().map_err(|e| e.to_string())?;
        let g = got.next_move().map_err(|e| e.to_string())?;
        match (w, g) {
            (None, None) => return Ok(moves),
            (Some(w), Some(g)) => {
                // A feed move's F means per minute or per revolution (G94/G95, a lathe's G98/G99):
                // the same number in the other mode is another speed.
                let cuts = matches!(w.motion, Motion::Feed | Motion::Arc { .. });
                let same_feed = ((w.feed.is_nan() && g.feed.is_nan()) || w.feed == g.feed)
                    && (!cuts || w.per_rev == g.per_rev);
                let same = w.motion.same(&g.motion)
                    && w.to
                        .iter()
                        .zip(&g.to)
                        .all(|(x, y)| (x.is_nan() && y.is_nan()) || (x - y).abs() < 1e-9);
                if !same || !same_feed {
                    // The feeds are named where they differ (the positions may be the same).
                    let feeds_differ = !same_feed;
                    let at = |f: f64, per_rev: bool| match (feeds_differ, f.is_nan()) {
                        (false, _) => String::new(),
                        (true, true) => " with no feed".to_string(),
                        (true, false) if per_rev => format!(" at F{f} per revolution"),
                        (true, false) => format!(" at F{f} per minute"),
                    };
                    return Err(format!(
                        "move {}: the program resolves to {} to {}{}, the output to {} to {}{}",
                        moves + 1,
                        w.motion.describe(),
                        fmsvm_canon::describe_pose(&w.to),
                        at(w.feed, w.per_rev),
                        g.motion.describe(),
                        fmsvm_canon::describe_pose(&g.to),
                        at(g.feed, g.per_rev)
                    ));
                }
                moves += 1;
            }
            (Some(_), None) => {
                return Err(format!(
                    "the output ends after {moves} moves; the program goes on"
                ));
            }
            (None, Some(_)) => {
                return Err(format!(
                    "the output moves on after the program's {moves} moves"
                ));
            }
        }
    }
}

/// An emitter of canonical operations that writes nothing: what the stock's own pass consumes.
struct Canonical;

impl fmsvm_canon::Emitter for Canonical {
    const CANON: bool = true;
}

/// What the stock's pass after `--verify` starts from: the stock, and the run's starting
/// variables and probe.
pub(super) type StockPass = (Stocked, Variables, ProbeModel);

/// `--verify` (or `--verify-file`) with `--stock`: once the output is proved to move as the
/// program does, move by move within the dialect's resolution, the stock is cut with those moves
/// (the program expanded once more, quietly), its findings said at their source lines. With
/// `--strict-stock` a finding fails the run (exit 4) and an output this run wrote is removed, as a
/// failed check's is.
pub(super) fn stock_after_verify(
    job: &Job<'_>,
    exit: Exit,
    out: &Path,
    wrote: bool,
    pass: Option<StockPass>,
) -> Exit {
    let Some((stocked, mut vars, probe)) = pass else {
        return exit;
    };
    if exit != Exit::Success {
        return exit;
    }
    let quiet_job = Job {
        quiet: true,
        ..*job
    };
    let cut = Cutting {
        job: &quiet_job,
        progress: None,
    };
    let (result, _, _, report) =
        cut.expand(Canonical, stocked, false, probe, &mut Discard, &mut vars);
    if result.is_err() {
        return exit;
    }
    let hits =
        report.rapids_into_material + report.below_floor + report.shank_rubs + report.plunges;
    if !job.a.strict_stock || hits == 0 {
        return exit;
    }
    plain(&format!(
        "--strict-stock: the output {} is proved to move as the program does, and {hits} of those moves hit the stock where they must not",
        out.display()
    ));
    if wrote {
        remove_output(out);
    }
    Exit::Alarm
}

/// Removes an output its own check rejected, and says so.
fn remove_output(out: &Path) {
    match std::fs::remove_file(out) {
        Ok(()) => plain_info(&format!("note: {} was removed", out.display())),
        Err(e) => plain_info(&format!(
            "note: {} could not be removed: {e}",
            out.display()
        )),
    }
}
