//! Criterion benchmark of the language server's latency: `fmsvm lsp` is started as an editor starts
//! it, a 10 000-line macro program is opened, and each iteration sends one change (the whole text,
//! as full sync does) and waits for its diagnostics: what a user waits for after a keystroke.
//! Target: under 50 ms.

use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use serde_json::json;

#[path = "../tests/framed/mod.rs"]
mod framed;

/// A macro program of `lines` lines: assignments, arithmetic, a loop, jumps and NC blocks.
fn program(lines: usize) -> String {
    let mut s = String::from("O1000 (LATENCY)\n#1=0\n");
    let mut n = 2;
    let mut k = 0;
    while n + 8 <= lines {
        k += 1;
        s += &format!(
            "N{k} #2=#1*0.5+{k}\nWHILE[#2LT{}]DO1\nG1 X[#2*COS[#1]] Y[#2*SIN[#1]] F200\n#2=#2+1\nEND1\nIF[#1GT1000]GOTO{k}\n#1=#1+1\nG0 Z5.\n",
            k + 3
        );
        n += 8;
    }
    while n + 1 < lines {
        s += "G0 Z5.\n";
        n += 1;
    }
    s += "M30\n";
    s
}

/// The diagnostics next published: how many.
fn wait_for_diagnostics(s: &mut framed::Framed) -> usize {
    loop {
        let m = s.receive();
        if m["method"] == "textDocument/publishDiagnostics" {
            return m["params"]["diagnostics"].as_array().map_or(0, Vec::len);
        }
    }
}

fn bench(c: &mut Criterion) {
    let text = program(10_000);
    assert_eq!(text.lines().count(), 10_000);
    let mut s = framed::Framed::start("lsp");
    s.send(&json!({"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"processId": null, "capabilities": {}}}));
    s.receive();
    s.send(&json!({"jsonrpc": "2.0", "method": "initialized", "params": {}}));
    let uri = "file:///bench/latency.nc";
    s.send(&json!({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {"uri": uri, "languageId": "nc", "version": 1, "text": text}}}));
    assert_eq!(wait_for_diagnostics(&mut s), 0, "the program is clean");
    let mut version = 1;
    let mut g = c.benchmark_group("lsp");
    g.measurement_time(Duration::from_secs(10));
    g.bench_function("diagnostics-10000-lines", |b| {
        b.iter(|| {
            version += 1;
            s.send(&json!({"jsonrpc": "2.0", "method": "textDocument/didChange", "params": {"textDocument": {"uri": uri, "version": version}, "contentChanges": [{"text": text}]}}));
            wait_for_diagnostics(&mut s)
        })
    });
    g.finish();
    s.send(&json!({"jsonrpc": "2.0", "id": 2, "method": "shutdown", "params": null}));
    s.receive();
    s.send(&json!({"jsonrpc": "2.0", "method": "exit", "params": null}));
    let _ = s.child.wait();
}

criterion_group!(benches, bench);
criterion_main!(benches);
