//! The common-variable store: `--vars FILE` loads the retained #500–#999 (macro-b-rules V4, S6),
//! `--dump-vars FILE` writes them back, one `#n=value` a line, in a form `--vars` reads: the volatile
//! #100–#199, which start vacant at every run, are listed as comments.

use fmsvm_compiler::ir::{COMMONS, common_index, common_number};
use fmsvm_vm::Variables;

/// Parses a store. Errors name the line.
pub fn parse(name: &str, text: &str, vars: &mut Variables) -> Result<(), String> {
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
        if !(500..=999).contains(&n) {
            return Err(err(
                "only the retained commons #500-#999 can be loaded (#100-#199 start vacant, macro-b-rules S6)",
            ));
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

/// Renders the non-vacant commons: #500 and up as assignments, #100–#199 as comments (volatile).
pub fn dump(vars: &Variables) -> String {
    let mut out =
        String::from("(fmsvm common variables; #100-#199 are volatile and not reloaded)\n");
    for i in 0..COMMONS {
        let v = vars.commons[i];
        if !fmsvm_block::is_vacant(v) {
            let n = common_number(i as u16);
            if n < 500 {
                out.push_str(&format!("(#{n}={v})\n"));
            } else {
                out.push_str(&format!("#{n}={v}\n"));
            }
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
        parse("s", "(store)\n#500=1.25\n#501 = -3\n#502=\n", &mut v).unwrap();
        assert_eq!(v.commons[100], 1.25);
        assert_eq!(v.commons[101], -3.0);
        assert!(fmsvm_block::is_vacant(v.commons[102]));
        v.commons[0] = 7.5; // #100
        let text = dump(&v);
        assert_eq!(
            text,
            "(fmsvm common variables; #100-#199 are volatile and not reloaded)\n(#100=7.5)\n#500=1.25\n#501=-3\n"
        );
        // What is dumped reloads.
        let mut w = Variables::default();
        parse("d", &text, &mut w).unwrap();
        assert_eq!(w.commons[100], 1.25);
        assert!(fmsvm_block::is_vacant(w.commons[0]));
        assert!(parse("s", "#100=1\n", &mut v).unwrap_err().contains("s:1"));
        assert!(parse("s", "#500=abc\n", &mut v).is_err());
    }
}
