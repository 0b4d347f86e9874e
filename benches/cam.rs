//! A CAM-size program through the whole `fmsvm run` process: a generated file of G1 X Y Z F lines
//! (no macro statement), which runs straight from the file (driver/src/flat.rs) in flat memory. Throughput
//! in lines; `benches/compare.sh` runs the 5 M-line version against LinuxCNC's rs274.
//!
//! `CAM_LINES` sets the size (default 1 000 000: criterion runs it many times).

use std::io::Write;
use std::process::Command;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};

/// Writes `lines` CAM lines to `path`: a deterministic pseudo-random walk, three decimals.
fn cam_file(path: &std::path::Path, lines: u64) {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).expect("create"));
    writeln!(f, "%\nO1000 (CAM)\nG21 G90 G17\nG0 X0 Y0 Z5").expect("write");
    let mut s = 0x2545_F491_4F6C_DD1Du64;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s % 200_000) as i64 - 100_000
    };
    for i in 0..lines {
        let (x, y, z) = (next(), next(), next() / 10);
        let fmt = |v: i64| {
            format!(
                "{}{}.{:03}",
                if v < 0 { "-" } else { "" },
                v.abs() / 1000,
                v.abs() % 1000
            )
        };
        writeln!(
            f,
            "G1 X{} Y{} Z{} F{}",
            fmt(x),
            fmt(y),
            fmt(z),
            800 + (i % 3) * 200
        )
        .expect("write");
    }
    writeln!(f, "M30\n%").expect("write");
}

fn cam(c: &mut Criterion) {
    let lines: u64 = std::env::var("CAM_LINES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1_000_000);
    let dir = tempfile::tempdir().expect("temp dir");
    let input = dir.path().join("cam.nc");
    let output = dir.path().join("out.nc");
    cam_file(&input, lines);
    let mut g = c.benchmark_group("cam");
    g.sample_size(10);
    g.throughput(Throughput::Elements(lines));
    for (name, extra) in [("literal", &[][..]), ("resolved", &["--resolve"][..])] {
        g.bench_function(format!("{lines}-lines/{name}"), |b| {
            b.iter(|| {
                let st = Command::new(env!("CARGO_BIN_EXE_fmsvm"))
                    .arg("run")
                    .arg(&input)
                    .arg("-q")
                    .arg("-o")
                    .arg(&output)
                    .args(extra)
                    .status()
                    .expect("runs");
                assert!(st.success());
            })
        });
    }
    g.finish();
}

criterion_group!(benches, cam);
criterion_main!(benches);
