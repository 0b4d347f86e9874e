//! Every settings file's reader on arbitrary text: a dialect profile (`--dialect-file`), the
//! control's parameters (`--params`), work offsets and tools (`--offsets`), retained commons
//! (`--vars`) and touch points (`--probe-points`). None panics; each gives a value or a message
//! naming the file; a profile fmsvm prints back (`dialects --show`) reads back to the same
//! profile, and parameters printed back (`params --show`, the effective set with the defaults
//! filled in) print the same once read again.
#![no_main]
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Some((&which, rest)) = data.split_first() else {
        return;
    };
    let text = String::from_utf8_lossy(rest);
    let name = "fuzz.toml";
    // A refusal names the file it is about.
    let named = |e: &String| assert!(e.contains(name), "a message without the file's name: {e}");
    match which % 5 {
        0 => match fmsvm_driver::dialects::load(name, &text) {
            Ok(p) => {
                let shown = fmsvm_driver::dialects::show(&p);
                let again = fmsvm_driver::dialects::load("shown.toml", &shown)
                    .unwrap_or_else(|e| panic!("a shown profile does not load: {e}\n{shown}"));
                assert_eq!(again, p, "a shown profile reads back otherwise:\n{shown}");
            }
            Err(e) => named(&e),
        },
        1 => match fmsvm_driver::params::parse(name, &text, fmsvm_driver::params::Params::default()) {
            Ok(p) => {
                let shown = fmsvm_driver::params::to_toml(&p);
                let again =
                    fmsvm_driver::params::parse("shown.toml", &shown, fmsvm_driver::params::Params::default())
                        .unwrap_or_else(|e| panic!("shown parameters do not load: {e}\n{shown}"));
                let twice = fmsvm_driver::params::to_toml(&again);
                assert_eq!(twice, shown, "shown parameters read back otherwise");
            }
            Err(e) => named(&e),
        },
        2 => {
            if let Err(e) = fmsvm_driver::offsets::parse(name, &text) {
                named(&e);
            }
        }
        3 => {
            let mut vars = fmsvm_vm::Variables::default();
            let commons = fmsvm_compiler::ir::CommonRanges::default();
            if let Err(e) = fmsvm_driver::vars::parse(name, &text, &mut vars, &commons) {
                named(&e);
            }
        }
        _ => match fmsvm_driver::run::parse_points(name, &text) {
            Ok(points) => assert!(points.iter().flatten().all(|v| !v.is_nan())),
            Err(e) => named(&e),
        },
    }
});
