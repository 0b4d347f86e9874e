//! The motion commands through the binary: `run --resolve` with `--offsets`, `stats`, `plot`.

use crate::cli_support;

use cli_support::{Dir, stderr, stdout};

/// A G55 offset set by G10, a G52 shift and a G81 cycle, resolved. Expected by hand: G55 is at
/// machine X100 Y50; `G0 X0 Y0 Z10` goes to X100 Y50 Z10 of the G54 (= machine) frame; under G52 X10
/// the hole X0 Y0 is at X110 Y50: positioning at the start level Z10, rapid to R2, feed to Z-5 (F100
/// on the first feed move), back to the initial level Z10 (G98); after `G52 X0` the G0 X0 goes to X100.
const SHIFTED_HOLE: &str = "G10 L2 P2 X100 Y50 Z0\nG55\nG0 X0 Y0 Z10\nG52 X10\nG81 X0 Y0 Z-5 R2 F100\nG80\nG52 X0\nG0 X0 Y0\nM30\n";

#[test]
fn resolve_writes_the_motion_in_the_g54_frame() {
    let d = Dir::new();
    d.file("p.nc", SHIFTED_HOLE);
    let o = d.run(&["run", "--resolve", "p.nc"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        stdout(&o),
        // The first block states the modes the motion depends on, G54 the frame it is written in.
        "%\nG90 G17 G94 G40 G49 G80 G54\nG21\nG0 X100. Y50. Z10.\nX110.\nZ2.\nG1 Z-5. F100.\nG0 Z10.\nX100.\nM30\n%\n"
    );
    // Literal output is the words as programmed.
    let o = d.run(&["run", "p.nc"]);
    assert_eq!(
        stdout(&o),
        "%\nG10 L2 P2 X100. Y50. Z0.\nG55\nG0 X0. Y0. Z10.\nG52 X10.\nG81 X0. Y0. Z-5. R2. F100.\nG80\nG52 X0.\nG0 X0. Y0.\nM30\n%\n"
    );
}

#[test]
fn offsets_file_and_machine_frame() {
    let d = Dir::new();
    d.file("p.nc", "G0 X1 Y2 Z3\nG55 G0 X0 Y0\nG43 H1 Z0\nM30\n");
    d.file(
        "o.toml",
        "[work.G54]\nX = -200.0\n[work.G55]\nX = -100.0\nY = 10.0\n[tool.1]\nlength = 50.0\n",
    );
    // G54 frame (machine X-200): the start, machine X0, is X200 there; X1 is written as X1; the G55
    // point X0 Y0 is machine X-100 Y10 = G54 X100 Y10; G43 H1 Z0 adds 50 to Z.
    let o = d.run(&["run", "--resolve", "--offsets", "o.toml", "p.nc"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        stdout(&o),
        "%\nG90 G17 G94 G40 G49 G80 G54\nG21\nG0 X1. Y2. Z3.\nX100. Y10.\nZ50.\nM30\n%\n"
    );
    // Machine frame: everything plus the G54 offset; the start is machine X0.
    let o = d.run(&[
        "run",
        "--resolve",
        "--frame",
        "machine",
        "--offsets",
        "o.toml",
        "p.nc",
    ]);
    assert_eq!(
        stdout(&o),
        // No work system selected in machine coordinates (a G54 would add its offset).
        "%\nG90 G17 G94 G40 G49 G80\nG21\nG0 X-199. Y2. Z3.\nX-100. Y10.\nZ50.\nM30\n%\n"
    );
    // A bad offsets file names its line and exits 2.
    d.file("bad.toml", "[work.G54]\nX = 1.0\n[work.G61]\n");
    let o = d.run(&["run", "--resolve", "--offsets", "bad.toml", "p.nc"]);
    assert_eq!(o.status.code(), Some(2));
    // Every TOML file's errors are `file:line:column` (one reader for --params, --offsets, --dialect-file).
    assert!(
        stderr(&o).contains("bad.toml:3:7: [work.G61]"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn stats_report_by_hand() {
    // The tool starts at X0 Y0 Z0 (--start-point: without it the first rapid's length is unknown).
    // Rapids: Z0→Z5 and Z0→Z5 = 10 mm (0.06 s at 10 000 mm/min). Feeds: Z5→Z0 at F100 (3 s), the
    // 10 × 10 square at F600 (40 mm, 4 s). Extents X 0..10 Y 0..10 Z 0..5.
    let d = Dir::new();
    d.file(
        "sq.nc",
        "G0 X0 Y0 Z5\nG1 Z0 F100\nX10 F600\nY10\nX0\nY0\nG0 Z5\nM30\n",
    );
    let o = d.run(&["stats", "sq.nc", "--json", "--start-point", "X0 Y0 Z0"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let json = stdout(&o);
    for needle in [
        "\"rapid\": 2",
        "\"feed\": 5",
        "\"rapid\": 10.0",
        "\"feed\": 45.0",
        "\"total_s\": 7.06",
        "\"feed_s\": 7.0",
    ] {
        assert!(json.contains(needle), "{needle} not in {json}");
    }
    let o = d.run(&[
        "stats",
        "sq.nc",
        "--rapid",
        "5000",
        "--start-point",
        "X0 Y0 Z0",
    ]);
    let text = stdout(&o);
    assert!(
        text.contains("X 0.000 .. 10.000") && text.contains("rapid 0.1 s at 5000 mm/min"),
        "{text}"
    );
    // The report can go to a file, written like every output.
    let o = d.run(&[
        "stats",
        "sq.nc",
        "-o",
        "sq.txt",
        "--start-point",
        "X0 Y0 Z0",
    ]);
    assert!(o.status.success());
    assert!(d.read("sq.txt").contains("feed 45.000 mm"));
}

#[test]
fn plot_writes_svg_and_png_and_refuses_other_names() {
    let d = Dir::new();
    d.file("c.nc", "G0 X10 Y0\nG1 Z-1 F100\nG3 I-10\nG0 Z5\nM30\n");
    let o = d.run(&["plot", "c.nc", "-o", "c.svg"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let svg = d.read("c.svg");
    assert!(
        svg.starts_with("<svg") || svg.contains("<svg"),
        "{svg:.200}"
    );
    assert!(svg.contains("-10.000 .. 10.000"), "extents of the circle");
    let o = d.run(&["plot", "c.nc", "-o", "c.png", "--view", "iso"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let png = std::fs::read(d.path("c.png")).expect("png");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    for bad in [&["plot", "c.nc", "-o", "c.jpg"][..], &["plot", "c.nc"][..]] {
        let o = d.run(bad);
        assert_eq!(o.status.code(), Some(2), "{bad:?}: {}", stderr(&o));
    }
    assert!(!d.path("c.jpg").exists());
}

#[test]
fn resolve_refuses_what_it_cannot_write() {
    let d = Dir::new();
    d.file("p.nc", "G33 Z-10 F1.5\nM30\n");
    let o = d.run(&["run", "--resolve", "p.nc", "-o", "out.nc"]);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(stderr(&o).contains("G33 thread cutting"), "{}", stderr(&o));
    assert!(!d.path("out.nc").exists());
    // Literal output passes it through.
    let o = d.run(&["run", "p.nc"]);
    assert!(stdout(&o).contains("G33 Z-10. F1.5"));
}

#[test]
fn power_on_modal_state_and_its_errors() {
    let d = Dir::new();
    d.file("p.nc", "X10\nX10\n#100=#4003\n#101=#5001\nM30\n");
    // Power-on G91 G1: the two X10 words are increments, feed moves; #4003 reads 91.
    let o = d.run(&[
        "run",
        "--resolve",
        "--modal",
        "G17 G91 G94 G21 G40 G49 G80 G98 G1",
        // Increments need a known start: LinuxCNC's (and the old model's) X0 Y0 Z0.
        "--start-point",
        "X0 Y0 Z0",
        "--dump-vars",
        "v.txt",
        "p.nc",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        stdout(&o),
        // From the declared X0 Y0 Z0 only X moves: only X is written.
        "%\nG90 G17 G94 G40 G49 G80 G54\nG21\nG1 X10.\nX20.\nM30\n%\n"
    );
    let vars = d.read("v.txt");
    assert!(
        vars.contains("(#100=91)") && vars.contains("(#101=20)"),
        "{vars}"
    );
    // A code that is not a power-on state, and one that does not exist: usage errors.
    for bad in ["G4", "G41", "G12"] {
        let o = d.run(&["run", "--modal", bad, "p.nc"]);
        assert_eq!(o.status.code(), Some(2), "{bad}: {}", stderr(&o));
        assert!(stderr(&o).contains(bad), "{}", stderr(&o));
    }
}

#[test]
fn linearize_writes_chords_within_the_tolerance() {
    // A quarter circle R10 from X10 Y0 to X0 Y10: chords of 2·acos(1 − 0.01/10) = 0.0894 rad, 18 of
    // them; every chord end on the circle, every chord's middle within 0.01 of it.
    let d = Dir::new();
    d.file("q.nc", "G0 X10 Y0\nG3 X0 Y10 R10 F100\nM30\n");
    let o = d.run(&["run", "--resolve", "--linearize", "0.01", "q.nc"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(!text.contains("G3"), "{text}");
    let mut points = vec![(10.0f64, 0.0f64)];
    let (mut x, mut y) = (10.0, 0.0);
    for line in text.lines().skip_while(|l| !l.starts_with("G1")) {
        if line.starts_with('M') {
            break;
        }
        for w in line.split_whitespace() {
            if let Some(v) = w.strip_prefix('X') {
                x = v.parse().expect("X");
            } else if let Some(v) = w.strip_prefix('Y') {
                y = v.parse().expect("Y");
            }
        }
        points.push((x, y));
    }
    assert_eq!(points.len(), 19, "{text}");
    assert_eq!(*points.last().expect("end"), (0.0, 10.0));
    for p in points.windows(2) {
        let (a, b) = (p[0], p[1]);
        assert!((a.0.hypot(a.1) - 10.0).abs() < 0.001);
        let mid = ((a.0 + b.0) / 2.0).hypot((a.1 + b.1) / 2.0);
        assert!(10.0 - mid <= 0.01 + 0.001, "chord middle {mid}");
    }
    // A tolerance out of range is a usage error.
    let o = d.run(&["run", "--resolve", "--linearize", "0", "q.nc"]);
    assert_eq!(o.status.code(), Some(2));
}
