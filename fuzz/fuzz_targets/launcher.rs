//! The launcher writer on arbitrary catalogue text: a profile built on the Маяк-600Т's with one
//! `[[cycle]]` whose name, comment and parameter texts come from the input. Either the profile
//! is refused, or the launcher holds the catalogue in its one raw string (exactly two `'''`) with
//! one `BEGIN_CYCLE` a cycle: no text of it can change the script's code or the library's catalogue.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let mut parts = text.splitn(4, '\u{1}');
    let (name, comment, param, ptext) = (
        parts.next().unwrap_or(""),
        parts.next().unwrap_or(""),
        parts.next().unwrap_or("P"),
        parts.next().unwrap_or(""),
    );
    let quote = |s: &str| toml_string(s);
    let profile = format!(
        "base = \"mayak600t\"\n\n[[cycle]]\nnumber = 81\nname = {}\ncomment = {}\ntype = \"Drilling\"\nblock = \"G81 Z{{_Zend}}\"\nparameters = [{{ name = {}, kind = \"S\", text = {} }}]\n",
        quote(name),
        quote(comment),
        quote(param),
        quote(ptext)
    );
    let Ok(p) = fmsvm_driver::dialects::load("fuzz.toml", &profile) else {
        return;
    };
    let Ok(script) = fmsvm_post::launcher("mayak600t", &p) else {
        return;
    };
    assert_eq!(script.matches("'''").count(), 2, "{script}");
    let cycles = p.offered().len();
    assert_eq!(script.matches("\nBEGIN_CYCLE ").count(), cycles, "{script}");
});

/// `s` as a TOML basic string (every character escaped that needs it).
fn toml_string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => out.push_str(&format!("\\u{:04X}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}
