//! Programs as shops write them (docs/semantics.md): what real shop and vendor programs do that
//! fmsvm must read as a control does, or refuse with a clear word. Programs of our own that
//! exercise each rule, on both engines.

mod cli_support;

use cli_support::{Dir, stderr, stdout};

#[test]
fn two_library_files_with_one_program_number_are_both_named_and_neither_taken() {
    // A shop's library folders hold O9010 twice (a copy left behind): which one the control has
    // is not known, so the run stops at the call and names both files.
    let d = Dir::new();
    d.file("a/O9010.nc", "O9010\nG0 X1.\nM99\n");
    d.file("b/probe.nc", "O9010\nG0 X2.\nM99\n");
    d.file("c/O9011.nc", "O9011\nG0 X3.\nM99\n");
    d.file("main.nc", "M98 P9011\nM98 P9010\nM30\n");
    for engine in ["interp", "jit"] {
        let o = d.run(&[
            "run", "main.nc", "--lib", "a", "--lib", "b", "--lib", "c", "--engine", engine,
        ]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(4), "{e}");
        assert!(
            e.contains("O9010 is held by a/O9010.nc and b/probe.nc"),
            "{engine}: {e}"
        );
        assert!(
            !stdout(&o).contains("X1.") && !stdout(&o).contains("X2."),
            "{engine}"
        );
        // The program only one file holds is found as before.
        let o = d.run(&[
            "run", "main.nc", "--lib", "a", "--lib", "c", "--engine", engine,
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(
            stdout(&o).contains("X3.") && stdout(&o).contains("X1."),
            "{}",
            stdout(&o)
        );
    }
}
