//! A real client: Neovim's built-in LSP client, headless, configured by nothing but the snippet the
//! documentation gives (`editors/neovim/`), with `fmsvm` found on PATH as an installed binary is:
//! the file type it sets, the diagnostics it shows and a go-to-definition. It needs Neovim, so
//! `cargo test` lists it as ignored with that reason; `.ci/run` installs Neovim and runs it with
//! `--ignored` (the 0.8 snippet only where the Neovim is 0.8 or later).
#![cfg(feature = "lsp")]

use crate::cli_support;

use std::path::{Path, PathBuf};
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

/// What the test asks of the editor once the file is open: its file type, the client and its
/// workspace, the diagnostics, and where GOTO10 goes.
const CHECK: &str = r#"
local out = io.open(vim.env.FMSVM_RESULT, "w")
out:write("filetype " .. vim.bo.filetype .. "\n")
vim.wait(10000, function() return #vim.diagnostic.get(0) >= 2 end, 20)
for _, c in pairs(vim.lsp.get_active_clients()) do
  out:write("client " .. c.name .. " " .. (c.config.root_dir or "") .. "\n")
end
for _, x in ipairs(vim.diagnostic.get(0)) do
  local code = x.code or (x.user_data and x.user_data.lsp and x.user_data.lsp.code) or ""
  out:write(string.format("diagnostic %d:%d %s %s\n", x.lnum, x.col, code, x.message))
end
vim.api.nvim_win_set_cursor(0, { 6, 5 })
local params = vim.lsp.util.make_position_params()
local results = vim.lsp.buf_request_sync(0, "textDocument/definition", params, 10000) or {}
for _, r in pairs(results) do
  local loc = r.result
  if loc and loc.range then
    out:write(string.format("definition %d:%d\n", loc.range.start.line, loc.range.start.character))
  end
end
out:close()
vim.cmd("qa!")
"#;

/// The documented snippet `name` (in `editors/neovim/`).
fn snippet(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("editors/neovim")
        .join(name)
}

/// Opens `sub/main.nc` of a workspace with an `fmsvm.toml` in Neovim configured by `init` alone,
/// `fmsvm` on PATH; what CHECK wrote.
fn open_with(init: &Path) -> String {
    let d = cli_support::Dir::new();
    d.file("fmsvm.toml", "args = []\n");
    std::fs::create_dir(d.path("sub")).expect("a folder");
    d.file("sub/main.nc", PROGRAM);
    let check = d.file("check.lua", CHECK);
    let out = d.path("result.txt");
    let bin = Path::new(env!("CARGO_BIN_EXE_fmsvm"));
    let path = match std::env::var_os("PATH") {
        Some(p) => {
            let mut dirs = vec![bin.parent().expect("a folder").to_path_buf()];
            dirs.extend(std::env::split_paths(&p));
            std::env::join_paths(dirs).expect("a PATH")
        }
        None => bin.parent().expect("a folder").as_os_str().to_owned(),
    };
    let mut child = Command::new("nvim")
        .args(["--headless", "-i", "NONE", "-n", "-u"])
        .arg(init)
        .arg("sub/main.nc")
        .arg("-c")
        .arg(format!("luafile {}", check.display()))
        .env("PATH", path)
        .env("FMSVM_RESULT", &out)
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
    let root = std::fs::canonicalize(d.path("")).expect("the workspace");
    result.replace(&root.display().to_string(), "WORKSPACE")
}

/// What every snippet must give: the file type, one client at the workspace of `fmsvm.toml`, the
/// diagnostics as `fmsvm check` says them, and GOTO10 → N10.
fn assert_attached(result: &str) {
    assert!(result.contains("filetype nc\n"), "{result}");
    assert!(result.contains("client fmsvm WORKSPACE\n"), "{result}");
    // The operator at line 3 column 9, the END without its DO.
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

#[test]
#[ignore = "needs Neovim (nvim); .ci/run runs it with --ignored where Neovim is installed"]
fn the_neovim_0_7_snippet_attaches_and_shows_the_diagnostics() {
    assert_attached(&open_with(&snippet("fmsvm-0.7.lua")));
}

#[test]
#[ignore = "needs Neovim 0.8 or later; .ci/run runs it where the Neovim it installs is that new"]
fn the_neovim_0_8_snippet_attaches_and_shows_the_diagnostics() {
    assert_attached(&open_with(&snippet("fmsvm.lua")));
}

/// The READMEs give the snippets the tests run, word for word.
#[test]
fn the_readmes_give_the_tested_snippets() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let editors = std::fs::read_to_string(root.join("editors/README.md")).expect("README");
    let main = std::fs::read_to_string(root.join("README.md")).expect("README");
    for name in ["fmsvm-0.7.lua", "fmsvm.lua"] {
        let text = std::fs::read_to_string(snippet(name)).expect("the snippet");
        assert!(editors.contains(&text), "editors/README.md lacks {name}");
    }
    let old = std::fs::read_to_string(snippet("fmsvm-0.7.lua")).expect("the snippet");
    assert!(main.contains(&old), "README.md lacks fmsvm-0.7.lua");
}
