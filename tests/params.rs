//! The control's parameters through the binary: `--params`, `--control`, flags over both, and
//! `fmsvm params --show` reloading to the same behaviour.

mod cli_support;

use cli_support::{Dir, stderr, stdout};

/// A program whose output depends on the parameters: the G100 macro call (6050), MOD on integers,
/// NAT (ATAN in −180…180), decimal-point input (X10 = 10 µm under increment input).
const PROGRAM: &str = "#100=[7.5 MOD 2]\n#101=ATAN[-1]/[-1]\nG100 X10\nG0 X10\nM30\n";
const MACRO: &str = "O9010\nG1 X#24 F100.\nM99\n";

fn run(d: &Dir, args: &[&str]) -> (String, String) {
    let mut all = vec!["run", "p.nc", "--lib", "lib", "--dump-vars", "v.txt"];
    all.extend_from_slice(args);
    let o = d.run(&all);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    (stdout(&o), d.read("v.txt"))
}

#[test]
fn the_file_sets_the_control_and_flags_override_it() {
    let d = Dir::new();
    d.file("p.nc", PROGRAM);
    d.file("lib/O9010.nc", MACRO);
    d.file(
        "p.toml",
        "[macro]\nnat = true\nmod_integers = true\ndecimal_input = \"increment\"\n[calls]\n6050 = 100\n",
    );
    let (out, vars) = run(&d, &["--params", "p.toml"]);
    // G100 calls O9010 with X10 (no point: 0.010 under increment input); X10 likewise.
    assert_eq!(out, "%\nG1 X0.01 F100.\nG0 X0.01\nM30\n%\n");
    // MOD on integers: 8 MOD 2 = 0; NAT: ATAN[-1]/[-1] = -135.
    assert!(
        vars.contains("(#100=0)") && vars.contains("(#101=-135)"),
        "{vars}"
    );
    // A flag overrides the file.
    let (out, _) = run(&d, &["--params", "p.toml", "--decimal-input", "calculator"]);
    assert_eq!(out, "%\nG1 X10. F100.\nG0 X10.\nM30\n%\n");
    // The printed parameters reload to the same behaviour.
    let o = d.run(&["params", "--show", "--params", "p.toml"]);
    assert!(o.status.success(), "{}", stderr(&o));
    d.file("shown.toml", &stdout(&o));
    let (again, vars_again) = run(&d, &["--params", "shown.toml"]);
    assert_eq!(again, "%\nG1 X0.01 F100.\nG0 X0.01\nM30\n%\n");
    assert_eq!(vars_again, vars);
    // A bad key names its file and line, exit 2.
    d.file("bad.toml", "[macro]\nnat = true\nnatt = true\n");
    let o = d.run(&["run", "p.nc", "--params", "bad.toml"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("bad.toml:3: [macro] natt"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_control_profile_selects_its_syntax() {
    let d = Dir::new();
    d.file("h.nc", "G0 X0\nG81 XI10 Y50 R2 Z-10\nG80\nM30\n");
    // Fanuc syntax refuses XI; the nct profile reads it (XI10 from X0: X10).
    let o = d.run(&["run", "h.nc"]);
    assert_eq!(o.status.code(), Some(3));
    let o = d.run(&["run", "h.nc", "--control", "nct"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("G81 X10. Y50. R2. Z-10."),
        "{}",
        stdout(&o)
    );
    let o = d.run(&["params", "--show", "--control", "nct"]);
    assert!(stdout(&o).contains("input = \"nct\""), "{}", stdout(&o));
}

#[test]
fn an_output_never_replaces_the_parameter_or_offsets_file() {
    let d = Dir::new();
    d.file("p.nc", "G0 X1\nM30\n");
    d.file("p.toml", "[macro]\nnat = true\n");
    d.file("o.toml", "[tool.1]\nradius = 2.0\n");
    for (flag, file) in [("--params", "p.toml"), ("--offsets", "o.toml")] {
        let before = d.read(file);
        let o = d.run(&["run", "p.nc", flag, file, "-o", file]);
        assert_eq!(o.status.code(), Some(2), "{flag}: {}", stderr(&o));
        assert_eq!(d.read(file), before, "{flag}: the file is untouched");
    }
}
