//! A real client: Neovim's built-in LSP client, headless, against `fmsvm lsp` on a program with an
//! error: the diagnostics it shows and a go-to-definition. It needs Neovim, so `cargo test` lists it
//! as ignored with that reason; `.ci/run` installs Neovim and runs it with `--ignored`.
#![cfg(feature = "lsp")]

use crate::cli_support;

use std::process::Command;
use std::time::Duration;

const PROGRAM: &str = "O1000
N10 #1=0
WHILE[#1LTE3]DO1
#1=#1+1
END1
GOTO10
M30
";

#[test]
#[ignore = "needs Neovim (nvim); .ci/run runs it with --ignored where Neovim is installed"]
fn neovim_shows_the_diagnostics_and_goes_to_the_definition() {
    let d = cli_support::Dir::new();
    let file = d.file("main.nc", PROGRAM);
    let out = d.path("result.txt");
    let script = format!(
        r#"
local out = io.open("{out}", "w")
local id = vim.lsp.start_client({{ name = "fmsvm", cmd = {{ "{bin}", "lsp" }}, root_dir = "{dir}" }})
vim.cmd("edit {file}")
vim.lsp.buf_attach_client(0, id)
vim.wait(10000, function() return #vim.diagnostic.get(0) >= 2 end, 20)
for _, x in ipairs(vim.diagnostic.get(0)) do
  local code = x.code or (x.user_data and x.user_data.lsp and x.user_data.lsp.code) or ""
  out:write(string.format("diagnostic %d:%d %s %s\n", x.lnum, x.col, code, x.message))
end
vim.api.nvim_win_set_cursor(0, {{ 6, 5 }})
local params = vim.lsp.util.make_position_params()
local results = vim.lsp.buf_request_sync(0, "textDocument/definition", params, 10000) or {{}}
for _, r in pairs(results) do
  local loc = r.result
  if loc and loc.range then
    out:write(string.format("definition %d:%d\n", loc.range.start.line, loc.range.start.character))
  end
end
out:close()
vim.lsp.stop_client(id)
vim.cmd("qa!")
"#,
        out = out.display(),
        bin = env!("CARGO_BIN_EXE_fmsvm"),
        dir = d.path("").display(),
        file = file.display(),
    );
    let lua = d.file("test.lua", &script);
    let mut child = Command::new("nvim")
        .args(["--headless", "-u", "NONE", "-i", "NONE", "-n", "-c"])
        .arg(format!("luafile {}", lua.display()))
        .current_dir(d.path(""))
        .spawn()
        .expect("nvim starts");
    // Neovim quits itself; it is stopped if it hangs.
    let started = std::time::Instant::now();
    while child.try_wait().ok().flatten().is_none() {
        if started.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("nvim did not finish in 60 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let result = std::fs::read_to_string(&out).expect("nvim wrote its result");
    // As fmsvm check says it: the operator at line 3 column 9, the END without its DO.
    assert!(
        result.contains(
            "diagnostic 2:8 0114 format error: `LTE` is not an operator; did you mean `LE`?"
        ),
        "{result}"
    );
    assert!(
        result.contains("diagnostic 4:0 0126 END1 without a DO1 before it"),
        "{result}"
    );
    // GOTO10 → N10, line 2 (0-based 1).
    assert!(result.contains("definition 1:0"), "{result}");
}
