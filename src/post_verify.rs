//! `fmsvm post --verify`: output.tmp read back by the control's reader (or, where it holds the
//! control's own Fanuc cycles, expanded by fmsvm's lathe kernel first) and compared, move by move,
//! with the neutral program's motion.

use std::io::Write as _;

use fmsvm_readback::words::WordReader;
use fmsvm_readback::{Motion, Reader};

use crate::cycle_moves::Move;
use crate::post::Converted;

/// How far a move's end may lie from the neutral program's (the output's rounding, 0.001 mm on
/// the diameter, and the library's two decimals).
const TOLERANCE: f64 = 0.002;

/// Compares output.tmp's motion with the neutral program's.
pub fn verify(done: &Converted, name: &str) -> Result<(), String> {
    let dir = tempfile::tempdir().map_err(|e| format!("--verify: a temporary folder: {e}"))?;
    let (text, mut reading) = match (done.native, &done.readable) {
        (None, _) => (done.output.clone(), done.profile.dialect.clone()),
        // The control's own cycle that fmsvm does not model (the Маяк-600Т's G72): written only
        // for a record whose shape its words state exactly, read as its elementary moves; every
        // other line as written.
        (Some(_), Some(readable)) => (readable.clone(), done.profile.dialect.clone()),
        (Some(n), None) => {
            if !expands_own_cycles(&done.profile.dialect) {
                return Err(format!(
                    "{name}: --verify: CYCLE {n} is written as {}'s own cycle, which fmsvm does not model: verify it with --moves",
                    done.profile.dialect.name
                ));
            }
            (resolve(&done.output, dir.path())?, fanuc0itd()?)
        }
    };
    reading.turning = true;
    let mut got = WordReader::new(std::io::Cursor::new(text.into_bytes()), reading);
    let mut want = done.motion.iter().filter(|m| m.to().is_some());
    // Where the output's and the neutral program's last moves ended: a move to there is none.
    let mut at: Option<[f64; 2]> = None;
    let mut wat: Option<[f64; 2]> = None;
    let mut count = 0usize;
    loop {
        let g = loop {
            match got
                .next_move()
                .map_err(|e| format!("output.tmp: --verify: {e}"))?
            {
                None => break None,
                Some(m) => {
                    let to = [m.to[0], m.to[2]];
                    if to.iter().any(|v| v.is_nan()) || matches!(m.motion, Motion::Dwell(_)) {
                        continue;
                    }
                    if at.is_some_and(|a| same(a, to)) {
                        continue;
                    }
                    at = Some(to);
                    break Some(m);
                }
            }
        };
        let w = want.by_ref().find(|m| {
            let to = m.to().unwrap_or([f64::NAN; 2]);
            let moves = !wat.is_some_and(|a| same(a, to));
            wat = Some(to);
            moves
        });
        match (w, g) {
            (None, None) => return Ok(()),
            (Some(w), Some(g)) => {
                count += 1;
                if let Err(e) = agree(w, &g) {
                    return Err(format!(
                        "output.tmp:{}: --verify: move {count}: {e}",
                        g.line
                    ));
                }
            }
            (Some(w), None) => {
                return Err(format!(
                    "output.tmp: --verify: the output ends after {} moves; the neutral program goes on: {}",
                    count,
                    describe(w)
                ));
            }
            (None, Some(g)) => {
                return Err(format!(
                    "output.tmp:{}: --verify: the output moves on after the neutral program's {count} moves",
                    g.line
                ));
            }
        }
    }
}

/// The control's own cycle blocks are a Fanuc's (a lathe's G-code system A or B), which the
/// verification expands with fmsvm's lathe kernel; any other control's are not modelled.
pub fn expands_own_cycles(d: &fmsvm_emit::dialect::Dialect) -> bool {
    d.lathe
        .as_ref()
        .is_some_and(|l| l.codes != fmsvm_canon::modal::CodeSystem::Mill)
}

fn same(a: [f64; 2], b: [f64; 2]) -> bool {
    (a[0] - b[0]).abs() <= TOLERANCE && (a[1] - b[1]).abs() <= TOLERANCE
}

/// A neutral move, for a message.
fn describe(m: &Move) -> String {
    let (what, to) = match *m {
        Move::Rapid(p) => ("a rapid", p),
        Move::Feed(p, _) => ("a feed move", p),
        Move::Arc { to, cw: true, .. } => ("a G02 arc", to),
        Move::Arc { to, .. } => ("a G03 arc", to),
        Move::Thread(p, _) => ("a thread", p),
        Move::Spindle(_) => return "the spindle".into(),
        Move::Codes { .. } => return "a profile block's S and T".into(),
    };
    format!("{what} to X{:.3} Z{:.3}", to[0] * 2.0, to[1])
}

/// The output's move `g` against the neutral program's `w`.
fn agree(w: &Move, g: &fmsvm_readback::Move) -> Result<(), String> {
    let to = [g.to[0], g.to[2]];
    let kind = match (w, g.motion) {
        (Move::Rapid(_), Motion::Rapid) | (Move::Feed(..), Motion::Feed) => true,
        (Move::Thread(_, lead), Motion::Thread { lead: l }) => (lead - l).abs() < 1e-6,
        (
            Move::Arc { centre, cw, .. },
            Motion::Arc {
                centre: c,
                clockwise,
                ..
            },
        ) => *cw == clockwise && same(*centre, [c[1], c[0]]),
        _ => false,
    };
    let end = w.to().is_some_and(|p| same(p, to));
    // The neutral F is per revolution (`F1.2`): every cut must be read in that mode, or the
    // control feeds F mm/min (a G98 for a G99: F0.2 at a crawl, F200. at 200 mm/rev).
    let cuts = matches!(w, Move::Feed(..) | Move::Arc { .. });
    if cuts && !g.per_rev {
        return Err(format!(
            "the output feeds {} to X{:.3} Z{:.3} per minute, where the neutral program's F is per revolution",
            g.motion.describe(),
            to[0] * 2.0,
            to[1]
        ));
    }
    if kind && end {
        Ok(())
    } else {
        Err(format!(
            "the neutral program makes {}, the output {} to X{:.3} Z{:.3}",
            describe(w),
            g.motion.describe(),
            to[0] * 2.0,
            to[1]
        ))
    }
}

/// Fanuc 0i-TD's reading of resolved output.
fn fanuc0itd() -> Result<fmsvm_emit::dialect::Dialect, String> {
    crate::dialects::builtin("fanuc0itd")
        .map(|p| p.dialect)
        .map_err(|e| format!("the fanuc0itd dialect: {e}"))
}

/// The output, a Fanuc lathe program, expanded by fmsvm's own lathe kernel into resolved moves
/// (`run --machine lathe --resolve`, in this process).
fn resolve(output: &str, dir: &std::path::Path) -> Result<String, String> {
    use clap::Parser as _;
    let input = dir.join("output.nc");
    let resolved = dir.join("resolved.nc");
    std::fs::File::create(&input)
        .and_then(|mut f| f.write_all(output.as_bytes()))
        .map_err(|e| format!("--verify: {}: {e}", input.display()))?;
    let args = crate::cli::Args::try_parse_from([
        "fmsvm".as_ref(),
        "run".as_ref(),
        "--machine".as_ref(),
        "lathe".as_ref(),
        "--dialect".as_ref(),
        "fanuc0itd".as_ref(),
        "--resolve".as_ref(),
        "-q".as_ref(),
        "-o".as_ref(),
        resolved.as_os_str(),
        input.as_os_str(),
    ] as [&std::ffi::OsStr; 11])
    .map_err(|e| format!("--verify: {e}"))?;
    let crate::cli::Command::Run(run) = args.command else {
        return Err("--verify: not a run".into());
    };
    match crate::run::run(&run, crate::run::Consumer::Flat) {
        crate::exit::Exit::Success => {}
        e => {
            return Err(format!(
                "output.tmp: --verify: fmsvm's lathe kernel refuses the output (exit {}, said above)",
                e as u8
            ));
        }
    }
    std::fs::read_to_string(&resolved).map_err(|e| format!("--verify: {}: {e}", resolved.display()))
}
