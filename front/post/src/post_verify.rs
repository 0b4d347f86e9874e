//! `fmsvm post --verify`: output.tmp read back by the control's reader (or, where it holds the
//! control's own Fanuc cycles, expanded by fmsvm's lathe kernel first) and compared, move by move,
//! with the neutral program's motion.

use std::io::Write as _;

use fmsvm_readback::words::WordReader;
use fmsvm_readback::{Motion, Reader};

use crate::Converted;
use crate::cycle_moves::Move;

/// How far a move's end may lie from the neutral program's (the output's rounding, 0.001 mm on
/// the diameter, and the library's two decimals).
const TOLERANCE: f64 = 0.002;

/// Compares output.tmp's motion with the neutral program's.
pub fn verify(done: &Converted, name: &str) -> Result<(), String> {
    stated(done)?;
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
    // The neutral program's F in force at each cut (a cycle's own F while it runs).
    let mut feed: Option<f64> = None;
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
                if let Move::Feed(_, Some(f)) | Move::Arc { f: Some(f), .. } = *w {
                    feed = Some(f);
                }
                if let Err(e) = agree(w, &g).and_then(|()| same_feed(w, &g, feed)) {
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

/// Each block of a cycle fmsvm does not model read back word by word: every word the record
/// makes it state (`Converted::stated`) there with its value, and no other word than N and G.
fn stated(done: &Converted) -> Result<(), String> {
    let lines: Vec<&str> = done.output.lines().collect();
    for (index, want) in &done.stated {
        let Some(line) = lines.get(*index) else {
            return Err(format!(
                "output.tmp: --verify: the output ends before line {}, a cycle's block",
                index + 1
            ));
        };
        let at = |what: String| format!("output.tmp:{}: --verify: {what}", index + 1);
        let mut got: Vec<(String, f64)> = Vec::new();
        for token in line.split_whitespace() {
            let split = token
                .find(|ch: char| ch == '-' || ch == '.' || ch.is_ascii_digit())
                .unwrap_or(token.len());
            let (address, number) = token.split_at(split);
            if matches!(address, "N" | "G") {
                continue;
            }
            let value = number
                .parse::<f64>()
                .map_err(|_| at(format!("`{token}` in the cycle's block is not a word")))?;
            got.push((address.to_string(), value));
        }
        for (address, v) in want {
            match got.iter().position(|(a, _)| a == address) {
                // K is written to four decimals: half its last digit.
                Some(i) if (got[i].1 - v).abs() <= 0.5e-4 + 1e-12 => {
                    got.remove(i);
                }
                Some(i) => {
                    return Err(at(format!(
                        "the cycle's block says {address}{}, the record {address}{v}",
                        got[i].1
                    )));
                }
                None => {
                    return Err(at(format!(
                        "the cycle's block has no {address}, the record says {address}{v}"
                    )));
                }
            }
        }
        if let Some((address, v)) = got.first() {
            return Err(at(format!(
                "the cycle's block says {address}{v}, which the record does not"
            )));
        }
    }
    Ok(())
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

/// A cut's F read back against the neutral program's in force (`feed`, per revolution).
fn same_feed(w: &Move, g: &fmsvm_readback::Move, feed: Option<f64>) -> Result<(), String> {
    let cuts = matches!(w, Move::Feed(..) | Move::Arc { .. });
    match feed {
        Some(f) if cuts && !(g.feed - f).abs().lt(&1e-6) => Err(format!(
            "the output feeds {} to X{:.3} Z{:.3} at F{}, the neutral program at F{f}",
            g.motion.describe(),
            g.to[0] * 2.0,
            g.to[2],
            g.feed
        )),
        _ => Ok(()),
    }
}

/// Fanuc 0i-TD's reading of resolved output.
fn fanuc0itd() -> Result<fmsvm_emit::dialect::Dialect, String> {
    fmsvm_driver::dialects::builtin("fanuc0itd")
        .map(|p| p.dialect)
        .map_err(|e| format!("the fanuc0itd dialect: {e}"))
}

/// The output, a Fanuc lathe program, expanded by fmsvm's own lathe kernel into resolved moves
/// (`run --machine lathe --resolve`, in this process).
fn resolve(output: &str, dir: &std::path::Path) -> Result<String, String> {
    use fmsvm_driver::request::{Input, Machine, Request};
    let input = dir.join("output.nc");
    let resolved = dir.join("resolved.nc");
    std::fs::File::create(&input)
        .and_then(|mut f| f.write_all(output.as_bytes()))
        .map_err(|e| format!("--verify: {}: {e}", input.display()))?;
    let mut run = Request::new(Input {
        quiet: true,
        ..Input::new(&input)
    });
    run.machine = Some(Machine::Lathe);
    run.dialect = Some("fanuc0itd".into());
    run.resolve = true;
    run.output = Some(resolved.clone());
    match fmsvm_driver::run::run(&run, fmsvm_driver::run::Consumer::Flat) {
        fmsvm_driver::exit::Exit::Success => {}
        e => {
            return Err(format!(
                "output.tmp: --verify: fmsvm's lathe kernel refuses the output (exit {}, said above)",
                e as u8
            ));
        }
    }
    std::fs::read_to_string(&resolved).map_err(|e| format!("--verify: {}: {e}", resolved.display()))
}

#[cfg(test)]
mod tests {
    //! Every word of the control's own cycle blocks changed, one at a time: the verification must
    //! reject the output (or fmsvm's model of the control refuse it). A word whose change the
    //! verification missed would be a word the control reads and fmsvm does not check.

    use super::verify;
    use crate::{Converted, PostArgs, convert};

    /// The 0i-TD's five cycles, the record of each as the library writes it (the numbers of the
    /// 0i-TD lathe manual's own G71–G76 examples would do as well; these keep each cycle short).
    const FANUC: &str = "\
N001 T0101
N002 S800 M03 F0.3
N003 G00 X52 Z2
N004 CYCLE 71 U=2 R=0.5 DU=0.4 DW=0.1 F=0.25 _L1=2 _L2=0 _Xbegin=20 _Zbegin=2 _Xend=52 _Zend=-40
N005 G00 X20
N006 G01 Z-20
N007 G01 X40 Z-30
N008 G01 Z-40
N009 G01 X52
N010 G80
N011 G00 X52 Z2
N012 G00 X56 Z2
N013 CYCLE 72 W=2 R=0.5 DU=0.4 DW=0.2 F=0.25 _L1=2 _L2=0 _Xbegin=56 _Zbegin=-6 _Xend=20 _Zend=2
N014 G00 Z-6
N015 G01 X40
N016 G01 X30 Z-1
N017 G01 X20
N018 G01 Z2
N019 G80
N020 G00 X56 Z2
N021 G00 X60 Z4
N022 CYCLE 73 I=4 K=1 D=3 DU=0.4 DW=0.1 F=0.2 _L1=2 _L2=0 _Xbegin=30 _Zbegin=4 _Xend=56 _Zend=-30
N023 G00 X30
N024 G01 Z-10
N025 G01 X50 Z-25
N026 G01 X56
N027 G80
N028 G00 X60 Z4
N029 G00 X0 Z5
N030 CYCLE 74 E=1 Q=5 F=0.1 _D=8 _L1=3 _L2=0 _Angle=118 _Zbegin=5 _Zend=-25
N031 G00 X0 Z5
N032 G00 X42 Z5
N033 CYCLE 76 M=1 A=60 DMIN=0.1 D=0.05 DD=0.4 _FEED=2. _NTHREADS=1 _DEPTH=1.2 _L1=5 _L2=2 _Xbegin=37.6 _Zbegin=5 _Xend=37.6 _Zend=-20
N034 G00 X42 Z5
N035 M30
";

    fn converted(dialect: &str, input: &str) -> Converted {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let path = dir.path().join("input.tmp");
        std::fs::write(&path, input).expect("written");
        let a = PostArgs {
            input: path,
            dialect: Some(dialect.into()),
            dialect_file: None,
            moves: false,
            verify: false,
            no_verify: true,
            max_rpm: None,
        };
        match convert(&a, "input.tmp") {
            Ok(c) => c,
            Err((e, _)) => panic!("{dialect}: {e:?}"),
        }
    }

    /// The line with each word after N and G changed in turn, and left out. A number with a point
    /// moves by one in its last digit and by one whole unit; a whole number (a block number, or a
    /// length in micrometres: G74 Q, G76 P Q) by ten, 0.01 mm: one micrometre is below the
    /// verification's tolerance (`TOLERANCE`, the output's rounding); a packed word (G76 P m r a)
    /// in its last and its first field.
    fn mutants(line: &str) -> Vec<String> {
        let words: Vec<&str> = line.split_whitespace().collect();
        let mut out = Vec::new();
        for (k, w) in words.iter().enumerate() {
            let letter = w.chars().next().unwrap_or(' ');
            if matches!(letter, 'N' | 'G') {
                continue;
            }
            let (head, number) = w.split_at(
                w.find(|c: char| c == '-' || c.is_ascii_digit())
                    .unwrap_or(w.len()),
            );
            let Ok(v) = number.parse::<f64>() else {
                continue;
            };
            let decimals = number.split_once('.').map_or(0, |(_, f)| f.len());
            let last = 10f64.powi(-(decimals as i32));
            let packed = decimals == 0 && number.len() > 1 && number.starts_with('0');
            let mut changed = Vec::new();
            if decimals > 0 {
                changed.push(format!("{head}{:.*}", decimals, v + last));
                changed.push(format!("{head}{:.*}", decimals, v + 1.0));
            } else if packed {
                let width = number.len();
                changed.push(format!("{head}{:0width$}", v as i64 + 1));
                changed.push(format!("{head}{:0width$}", v as i64 + 10_000));
            } else {
                changed.push(format!("{head}{}", v as i64 + 10));
            }
            changed.push(String::new());
            for c in changed {
                let mut m: Vec<&str> = words.clone();
                if c.is_empty() {
                    m.remove(k);
                } else {
                    m[k] = &c;
                }
                out.push(m.join(" "));
            }
        }
        out
    }

    /// Whether the verification rejects `done`'s output with its line `i` replaced by `line`.
    fn caught(done: &Converted, i: usize, line: &str) -> bool {
        let output: String = done
            .output
            .lines()
            .enumerate()
            .flat_map(|(k, l)| [if k == i { line } else { l }, "\n"])
            .collect();
        let mutated = Converted {
            output,
            ..done.clone()
        };
        verify(&mutated, "input.tmp").is_err()
    }

    #[test]
    fn every_word_of_a_fanuc_cycle_block_changed_is_caught() {
        let done = converted("fanuc0itd", FANUC);
        verify(&done, "input.tmp").expect("the output as written verifies");
        let lines: Vec<&str> = done.output.lines().collect();
        let mut tried = 0;
        for (i, line) in lines.iter().enumerate() {
            let is_cycle = line
                .split_whitespace()
                .any(|w| matches!(w, "G71" | "G72" | "G73" | "G74" | "G76"));
            if !is_cycle {
                continue;
            }
            for m in mutants(line) {
                tried += 1;
                assert!(
                    caught(&done, i, &m),
                    "`{line}` changed to `{m}` passes the verification"
                );
            }
        }
        // Ten cycle blocks, every word after N and G: at least three changes each.
        assert!(tried >= 60, "{tried} mutations");
    }

    /// The seed's Маяк-600Т record, and a cone (K computed from the figure).
    const MAYAK: &str = "\
N006 S500 F1.2
N007 G00 X156.31 Z4.31
N008 CYCLE 72 I=5 B=0.5 VP=1 C=95 P=5 _L1=5 _L2=5 _Xbegin=118 _Zbegin=4.31 _Xend=156.31 _Zend=-136.98
N009 Z-136.98
N010 X156.31
N011 G80
N012 G00 X156.31 Z4.31
N013 CYCLE 72 I=5 B=0.5 VP=1 C=95 P=5 _L1=5 _L2=5 _Xbegin=118 _Zbegin=4.31 _Xend=156.31 _Zend=-136.98
N014 X130 Z-136.98
N015 X156.31
N016 G80
N017 G00 X156.31 Z4.31
";

    #[test]
    fn every_word_of_a_mayak_cycle_block_changed_is_caught() {
        let done = converted("mayak600t", MAYAK);
        verify(&done, "input.tmp").expect("the output as written verifies");
        assert!(done.output.contains(" K0.0849 "), "{}", done.output);
        let lines: Vec<&str> = done.output.lines().collect();
        let mut tried = 0;
        for (i, line) in lines.iter().enumerate() {
            if !line.contains(" G72 ") {
                continue;
            }
            for m in mutants(line) {
                tried += 1;
                assert!(
                    caught(&done, i, &m),
                    "`{line}` changed to `{m}` passes the verification"
                );
            }
            // A word the record does not state, added.
            let added = format!("{line} R2");
            assert!(caught(&done, i, &added), "{added}");
        }
        // Two blocks of eight words after N and G (X Z I B VP C K P=): three changes of a number
        // with a point, two of a whole number (the first block's K0 among them): 19 + 20.
        assert_eq!(tried, 39, "{tried} mutations");
    }
}
