//! The common-variable store: `--vars FILE` loads the retained commons (#500–#999 unless the
//! parameters' `common_retained` says otherwise; macro-b-rules V4, S6), `--dump-vars FILE` writes them
//! back, one `#n=value` a line, in a form `--vars` reads: the volatile ones (#100–#199), which start
//! vacant at every run, are listed as comments.

use fmsvm_compiler::ir::{COMMONS, CommonRanges, common_index, common_number};
use fmsvm_vm::Variables;

/// Parses a store of the control's retained commons. Errors name the line.
pub fn parse(
    name: &str,
    text: &str,
    vars: &mut Variables,
    commons: &CommonRanges,
) -> Result<(), String> {
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.is_empty() || line.starts_with('(') || line.starts_with(';') || line == "%" {
            continue;
        }
        let err = |what: &str| format!("{name}:{}: {what}: `{line}`", i + 1);
        let rest = line
            .strip_prefix('#')
            .ok_or_else(|| err("expected `#n=value`"))?;
        let (n, v) = rest
            .split_once('=')
            .ok_or_else(|| err("expected `#n=value`"))?;
        let n: u32 = n.trim().parse().map_err(|_| err("not a variable number"))?;
        if !commons.is_retained(n) {
            let retained = commons
                .retained
                .map_or("none here".to_string(), |(a, b)| format!("#{a}-#{b}"));
            let volatile = commons
                .volatile
                .map_or(String::new(), |(a, b)| format!("; #{a}-#{b} start vacant"));
            return Err(err(&format!(
                "only the retained commons can be loaded ({retained}{volatile}; docs/semantics.md, row S6)"
            )));
        }
        let v = v.trim();
        let value = if v.is_empty() || v.eq_ignore_ascii_case("vacant") {
            fmsvm_block::VACANT
        } else {
            let x: f64 = v.parse().map_err(|_| err("not a number"))?;
            if !x.is_finite() {
                return Err(err("not a finite number"));
            }
            x
        };
        if let Some(idx) = common_index(n) {
            vars.commons[idx as usize] = value;
        }
    }
    Ok(())
}

/// Renders the non-vacant commons: the retained as assignments, the volatile as comments.
pub fn dump(vars: &Variables, commons: &CommonRanges) -> String {
    let mut out = match commons.volatile {
        Some((a, b)) => {
            format!("(fmsvm common variables; #{a}-#{b} are volatile and not reloaded)\n")
        }
        None => "(fmsvm common variables)\n".to_string(),
    };
    for i in 0..COMMONS {
        let v = vars.commons[i];
        let n = common_number(i as u16);
        if fmsvm_block::is_vacant(v) || !commons.contains(n) {
            continue;
        }
        if commons.is_retained(n) {
            out.push_str(&format!("#{n}={v}\n"));
        } else {
            out.push_str(&format!("(#{n}={v})\n"));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn load_and_dump_round_trip() {
        let mut v = Variables::default();
        let c = CommonRanges::default();
        parse("s", "(store)\n#500=1.25\n#501 = -3\n#502=\n", &mut v, &c).unwrap();
        let at = |n| common_index(n).unwrap() as usize;
        assert_eq!(v.commons[at(500)], 1.25);
        assert_eq!(v.commons[at(501)], -3.0);
        assert!(fmsvm_block::is_vacant(v.commons[at(502)]));
        v.commons[0] = 7.5; // #100
        let text = dump(&v, &c);
        assert_eq!(
            text,
            "(fmsvm common variables; #100-#199 are volatile and not reloaded)\n(#100=7.5)\n#500=1.25\n#501=-3\n"
        );
        // What is dumped reloads.
        let mut w = Variables::default();
        parse("d", &text, &mut w, &c).unwrap();
        assert_eq!(w.commons[at(500)], 1.25);
        assert!(fmsvm_block::is_vacant(w.commons[0]));
        assert!(
            parse("s", "#100=1\n", &mut v, &c)
                .unwrap_err()
                .contains("s:1")
        );
        assert!(parse("s", "#500=abc\n", &mut v, &c).is_err());
    }

    #[test]
    fn the_store_follows_the_ranges() {
        // NCT: #100-#199 and #500-#599; #600 is not a common there.
        let c = CommonRanges {
            volatile: Some((100, 149)),
            retained: Some((500, 599)),
        };
        let mut v = Variables::default();
        parse("s", "#599=2\n", &mut v, &c).unwrap();
        let e = parse("s", "#600=2\n", &mut v, &c).unwrap_err();
        assert!(e.starts_with("s:1:") && e.contains("#500-#599"), "{e}");
        v.commons[common_index(120).unwrap() as usize] = 1.0;
        v.commons[common_index(150).unwrap() as usize] = 9.0; // not a common here: not dumped
        assert_eq!(
            dump(&v, &c),
            "(fmsvm common variables; #100-#149 are volatile and not reloaded)\n(#120=1)\n#599=2\n"
        );
    }
}
