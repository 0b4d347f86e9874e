//! `stats --stock`: the material a program removes and the moves that hit it where they must not,
//! through the binary, each finding at its source line: a rapid into the stock, a G28 whose
//! intermediate point leaves the tool low, a shank above short flutes, a lathe's rapid into the
//! bar; `--strict-stock` stops there; a stock too fine for the budget is refused with its figure.

use crate::cli_support::{Dir, stderr, stdout};

/// A 6 mm flat end mill with 4 mm of flutes, T1.
const TOOLS: &str = "[tool.1]\ntype = \"flat\"\ndiameter = 6.0\nflute_length = 4.0\n\n[work.G54]\nX = 0.0\nY = 0.0\nZ = 0.0\n\n[reference.G28]\nX = 0.0\nY = 0.0\nZ = 0.0\n";

/// The stock: 100 × 100 × 20 below Z0.
const STOCK: &str = "0,0,-20,100,100,0";

fn stats(d: &Dir, program: &str, extra: &[&str]) -> std::process::Output {
    d.file("p.nc", program);
    d.file("tools.toml", TOOLS);
    let mut args = vec![
        "stats",
        "p.nc",
        "--stock",
        STOCK,
        "--offsets",
        "tools.toml",
        "--json",
    ];
    args.extend_from_slice(extra);
    d.run(&args)
}

fn json(o: &std::process::Output) -> serde_json::Value {
    serde_json::from_str(&stdout(o)).expect("one JSON document")
}

#[test]
fn a_slot_removes_its_width_times_its_depth_and_nothing_is_said() {
    let d = Dir::new();
    // Across the whole stock at Y25, 2 deep: 100 × 6 × 2 at the cell centres.
    let o = stats(
        &d,
        "T1 M6\nG0 G90 X-10 Y25 Z5\nG1 Z-2 F300\nG1 X110 F600\nG0 Z5\nM30\n",
        &[],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stderr(&o), "");
    let v = json(&o);
    let removed = v["stock"]["removed"].as_f64().expect("removed");
    assert!((removed - 1200.0).abs() < 1e-6, "{removed}");
    assert_eq!(v["stock"]["rapids_into_material"], 0);
    let t1 = &v["stock"]["tools"][0];
    assert_eq!(t1["tool"], 1);
    // 120 of feed through material (the pass), 7 down through air; 12 s and 1.4 s.
    assert!(
        (t1["cutting_length"].as_f64().unwrap_or(0.0) - 120.0).abs() < 1e-9,
        "{t1}"
    );
    assert!(
        (t1["air_length"].as_f64().unwrap_or(0.0) - 7.0).abs() < 1e-9,
        "{t1}"
    );
    assert!(
        (t1["cutting_s"].as_f64().unwrap_or(0.0) - 12.0).abs() < 1e-9,
        "{t1}"
    );
}

#[test]
fn a_rapid_at_z_minus_1_into_the_stock_is_said_at_its_line_and_strict_stops_there() {
    let d = Dir::new();
    let program = "T1 M6\nG0 G90 X50 Y50 Z5\nG0 Z-1\nG1 Z5 F300\nM30\n";
    let o = stats(&d, program, &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("p.nc:3:1: warning: a rapid (G0) into the stock: the cutter goes 1.000 below the material's top"),
        "{}",
        stderr(&o)
    );
    assert_eq!(json(&o)["stock"]["rapids_into_material"], 1);
    let o = stats(&d, program, &["--strict-stock"]);
    assert_eq!(o.status.code(), Some(4), "{}", stderr(&o));
    assert!(stderr(&o).contains("--> p.nc:3:1"), "{}", stderr(&o));
}

#[test]
fn a_g28_that_leaves_the_tool_low_goes_through_the_part() {
    let d = Dir::new();
    // A hole 5 deep at X50 Y50, then G28 naming only X and Y: the intermediate point keeps Z−5,
    // and the way there goes through 50 of material.
    let o = stats(
        &d,
        "T1 M6\nG0 G90 X50 Y50 Z5\nG1 Z-5 F100\nG28 X0 Y0\nM30\n",
        &[],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains(
            "p.nc:4:1: warning: a rapid (G0) into the stock: the cutter goes 5.000 below"
        ),
        "{}",
        stderr(&o)
    );
    // The same return with Z first is safe.
    let o = stats(
        &d,
        "T1 M6\nG0 G90 X50 Y50 Z5\nG1 Z-5 F100\nG28 Z5\nG28 X0 Y0\nM30\n",
        &[],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("into the stock"), "{}", stderr(&o));
}

#[test]
fn a_shank_above_short_flutes_rubs_a_wall_deeper_than_they_reach() {
    let d = Dir::new();
    // 6 deep with 4 of flutes: the 2 above them meet the shank.
    let o = stats(
        &d,
        "T1 M6\nG0 G90 X-10 Y25 Z5\nG1 Z-6 F300\nG1 X50 F600\nG0 Z5\nM30\n",
        &[],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains(
            "p.nc:4:1: warning: T1's shank above its 4 of flutes rubs the material, 2.000 deep"
        ),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_tool_without_a_shape_is_said_once_and_not_simulated() {
    let d = Dir::new();
    let o = stats(&d, "T2 M6\nG0 G90 X50 Y50 Z5\nG0 Z-1\nG0 Z-2\nM30\n", &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        stderr(&o).matches("T2 has no shape").count(),
        1,
        "{}",
        stderr(&o)
    );
    assert!(!stderr(&o).contains("into the stock"), "{}", stderr(&o));
}

#[test]
fn a_lathe_rapid_into_the_bar_is_said_at_its_line() {
    let d = Dir::new();
    d.file("lathe.toml", "[tool.1]\nradius = 0.8\ntip = 3\n");
    d.file(
        "t.nc",
        "G18 G21 G99\nT0101\nG0 X45 Z5\nG0 Z0\nG1 X-1.6 F0.2\nG0 Z2\nG0 X36\nG1 Z-20 F0.25\nG0 X45\nG0 Z5\nG0 X30\nG0 Z-10\nM30\n",
    );
    // A bar Ø40 from Z−50 to Z2 (X as the program writes it, a diameter).
    let o = d.run(&[
        "stats",
        "t.nc",
        "--dialect",
        "fanuc0itd",
        "--stock",
        "0,0,-50,40,0,2",
        "--offsets",
        "lathe.toml",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("t.nc:12:1: warning: a rapid (G0) into the stock: the tool passes through"),
        "{err}"
    );
    assert_eq!(err.matches("into the stock").count(), 1, "{err}");
    let v = json(&o);
    // Before: π·20²·52 of bar.
    let before = v["stock"]["before"].as_f64().unwrap_or(0.0);
    assert!(
        (before - std::f64::consts::PI * 400.0 * 52.0).abs() < 1e-6,
        "{before}"
    );
}

#[test]
fn a_stock_of_a_thousand_million_cells_is_refused_with_the_figure() {
    let d = Dir::new();
    d.file("p.nc", "G0 X0 Y0 Z5\nM30\n");
    let o = d.run(&[
        "stats",
        "p.nc",
        "--stock",
        "0,0,-20,1000,1000,0",
        "--stock-cell",
        "0.03",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("is 1.111e9 cells, more than the 5.000e7"),
        "{}",
        stderr(&o)
    );
}

/// Every textbook exercise and corpus program on a solid block: the box of its motion grown by the
/// tool's radius (the textbook's 4 mm flat end mill, T1), from 1 below its lowest Z to Z0, the
/// part's top in all of them. No rapid goes into material but in the two exercises whose printed
/// programs do on such a block: 29 feeds down at the part's centre and leaves at Z−19 with a G0
/// (N170), 30 rapids to Z−50 at X0 Y0 and on to Y−35 (N150, N160, "as printed").
#[test]
fn the_textbook_and_the_corpus_on_a_solid_block_rapid_into_it_only_where_their_listings_do() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let textbook = root.join("tests/textbook");
    let d = Dir::new();
    d.file(
        "tools.toml",
        "[tool.1]\ntype = \"flat\"\ndiameter = 4.0\nradius = 2.0\n",
    );
    let lib = textbook.display().to_string();
    let mut programs: Vec<std::path::PathBuf> = std::fs::read_dir(&textbook)
        .expect("tests/textbook")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "nc"))
        .collect();
    programs.sort();
    programs.push(root.join("tests/corpus/003-hemisphere.nc"));
    programs.push(root.join("tests/corpus/003-sine.nc"));
    let subprogram = |n: &str| {
        ["15-", "24-", "31-", "35-"]
            .iter()
            .any(|s| n.starts_with(s))
    };
    let mut checked = 0;
    for path in programs {
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        if subprogram(&name) {
            continue;
        }
        let file = path.display().to_string();
        let common = [
            "--input",
            "nct",
            "--lib",
            &lib,
            "--start-point",
            "X0 Y0 Z0",
            "--offsets",
            "tools.toml",
            "--json",
            "-q",
        ];
        let mut args = vec!["stats", &file];
        args.extend_from_slice(&common);
        let o = d.run(&args);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let e = &json(&o)["extents"];
        let v = |a: &str, k: &str| e[a][k].as_f64().unwrap_or(f64::NAN);
        let stock = format!(
            "--stock={},{},{},{},{},0",
            v("min", "x") - 2.0,
            v("min", "y") - 2.0,
            v("min", "z").min(0.0) - 1.0,
            v("max", "x") + 2.0,
            v("max", "y") + 2.0
        );
        let mut args = vec!["stats", &file, &stock];
        args.extend_from_slice(&common[..common.len() - 1]);
        let o = d.run(&args);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let lines: Vec<String> = stderr(&o)
            .lines()
            .filter(|l| l.contains("warning: a rapid (G0) into the stock"))
            .filter_map(|l| {
                l.strip_prefix(&format!("{file}:"))
                    .and_then(|r| r.split(':').next())
                    .map(str::to_string)
            })
            .collect();
        let expected: &[&str] = match &name[..3] {
            "29-" => &["12"],
            "30-" => &["12", "13"],
            _ => &[],
        };
        assert_eq!(lines, expected, "{name} with {stock}: {}", stderr(&o));
        assert!(
            !stderr(&o).contains("below the stock's floor"),
            "{name}: {}",
            stderr(&o)
        );
        checked += 1;
    }
    assert_eq!(checked, 34);
}

/// `run --verify --stock`: the output is proved to move as the program does, then the stock is cut
/// with those moves; a finding is said at its source line, and with `--strict-stock` the run fails
/// (exit 4) and the output is removed. Every dialect's output the same way (the FMS-3000's here).
#[test]
fn verify_with_a_stock_checks_what_was_written_and_strict_removes_it() {
    let d = Dir::new();
    d.file(
        "p.nc",
        "T1 M6\nG0 G90 X50 Y50 Z5\nG0 Z-1\nG1 Z5 F300\nM30\n",
    );
    d.file("tools.toml", TOOLS);
    for dialect in ["fanuc", "fms3000"] {
        let base = [
            "run",
            "p.nc",
            "--stock",
            STOCK,
            "--offsets",
            "tools.toml",
            "-o",
            "out.nc",
            "--verify",
            "--dialect",
            dialect,
        ];
        let o = d.run(&base);
        assert!(o.status.success(), "{dialect}: {}", stderr(&o));
        let err = stderr(&o);
        assert!(err.contains("verified:"), "{err}");
        assert!(
            err.contains("p.nc:3:1: warning: a rapid (G0) into the stock"),
            "{dialect}: {err}"
        );
        assert!(d.path("out.nc").exists());
        let mut strict = base.to_vec();
        strict.push("--strict-stock");
        let o = d.run(&strict);
        assert_eq!(o.status.code(), Some(4), "{dialect}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("1 of those moves hit the stock"),
            "{}",
            stderr(&o)
        );
        assert!(!d.path("out.nc").exists(), "{dialect}: the output stays");
    }
}

/// The parameters file's `[machine] stock` is the stock when `--stock` gives none; `params --show`
/// writes it back.
#[test]
fn the_parameters_file_gives_the_stock() {
    let d = Dir::new();
    d.file("p.nc", "T1 M6\nG0 G90 X50 Y50 Z5\nG0 Z-1\nM30\n");
    d.file("tools.toml", TOOLS);
    d.file("shop.toml", "[machine]\nstock = \"0,0,-20,100,100,0\"\n");
    let o = d.run(&[
        "stats",
        "p.nc",
        "--params",
        "shop.toml",
        "--offsets",
        "tools.toml",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("p.nc:3:1: warning: a rapid (G0) into the stock"),
        "{}",
        stderr(&o)
    );
    // 100 × 100 × 20, summed over 10⁶ cells.
    let before = json(&o)["stock"]["before"].as_f64().unwrap_or(0.0);
    assert!((before - 200_000.0).abs() < 1e-4, "{before}");
    let o = d.run(&["params", "--show", "--params", "shop.toml"]);
    assert!(
        stdout(&o).contains("stock = \"0,0,-20,100,100,0\""),
        "{}",
        stdout(&o)
    );
    d.file("bad.toml", "[machine]\nstock = \"0,0,-20,100\"\n");
    let o = d.run(&["stats", "p.nc", "--params", "bad.toml"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("bad.toml:2:9: [machine] stock: give six numbers"),
        "{}",
        stderr(&o)
    );
}

/// `--stock-cylinder`: a round blank Ø50 × 20 standing on Z at X50 Y50; a rapid at Z−1 over the
/// corner of its box is in the air, over its centre into material; the volume is the cylinder's to
/// within the cells along its edge.
#[test]
fn a_round_blank_has_material_only_within_its_diameter() {
    let d = Dir::new();
    d.file("tools.toml", TOOLS);
    let cylinder = [
        "--stock-cylinder",
        "50,50,50,-20,0",
        "--offsets",
        "tools.toml",
        "--json",
    ];
    d.file("corner.nc", "T1 M6\nG0 G90 X27 Y27 Z5\nG0 Z-1\nM30\n");
    let mut args = vec!["stats", "corner.nc"];
    args.extend_from_slice(&cylinder);
    let o = d.run(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("into the stock"), "{}", stderr(&o));
    let before = json(&o)["stock"]["before"].as_f64().unwrap_or(0.0);
    let exact = std::f64::consts::PI * 25.0 * 25.0 * 20.0;
    // The cells along the circle: its length × a cell × the height, at most.
    assert!(
        (before - exact).abs() < std::f64::consts::PI * 50.0 * 0.1 * 20.0,
        "{before} {exact}"
    );
    d.file("centre.nc", "T1 M6\nG0 G90 X50 Y50 Z5\nG0 Z-1\nM30\n");
    let mut args = vec!["stats", "centre.nc"];
    args.extend_from_slice(&cylinder);
    let o = d.run(&args);
    assert!(
        stderr(&o).contains("centre.nc:3:1: warning: a rapid (G0) into the stock"),
        "{}",
        stderr(&o)
    );
}
