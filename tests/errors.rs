//! Every example of `docs/errors.md` gives exactly the message and exit code the catalogue says.

use std::process::Command;

struct Entry {
    title: String,
    message: String,
    exit: i32,
    flags: Vec<String>,
    program: Option<String>,
}

fn entries() -> Vec<Entry> {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/errors.md"))
        .expect("docs/errors.md");
    let mut out = Vec::new();
    for section in doc.split("\n### ").skip(1) {
        let title = section.lines().next().unwrap_or("").to_string();
        let field = |name: &str| {
            section
                .lines()
                .find_map(|l| l.strip_prefix(&format!("- {name}: ")))
                .map(|v| v.trim().to_string())
        };
        let Some(message) = field("message") else {
            continue;
        };
        // `message` is written in backticks; inner backticks are part of it.
        let message = message
            .strip_prefix('`')
            .and_then(|m| m.strip_suffix('`'))
            .unwrap_or(&message)
            .to_string();
        let exit = field("exit").and_then(|e| e.parse().ok()).unwrap_or(-1);
        let flags = field("flags")
            .map(|f| {
                f.trim_matches('`')
                    .split_whitespace()
                    .map(str::to_string)
                    .collect()
            })
            .unwrap_or_default();
        let program = section
            .split("```nc\n")
            .nth(1)
            .and_then(|b| b.split("```").next())
            .map(str::to_string);
        out.push(Entry {
            title,
            message,
            exit,
            flags,
            program,
        });
    }
    out
}

#[test]
fn every_catalogued_error_is_what_the_catalogue_says() {
    let list = entries();
    assert!(list.len() >= 50, "the catalogue has {} entries", list.len());
    let dir = tempfile::tempdir().expect("temp dir");
    let mut checked = 0;
    let mut wrong = Vec::new();
    for e in &list {
        let Some(program) = &e.program else { continue };
        let path = dir.path().join("example.nc");
        std::fs::write(&path, program).expect("write");
        let o = Command::new(env!("CARGO_BIN_EXE_fmsvm"))
            .arg("run")
            .arg(&path)
            .arg("-o")
            .arg(dir.path().join("out.nc"))
            // `{dir}` in a flag is the example's own temporary folder.
            .args(
                e.flags
                    .iter()
                    .map(|f| f.replace("{dir}", dir.path().to_str().unwrap_or("."))),
            )
            .output()
            .expect("runs");
        checked += 1;
        let stderr = String::from_utf8_lossy(&o.stderr)
            .replace(path.to_str().unwrap_or(""), "example.nc")
            .replace(&format!("{}/", dir.path().display()), "");
        if o.status.code() != Some(e.exit) {
            wrong.push(format!(
                "{}: exit {:?}, catalogue says {}\n{stderr}",
                e.title,
                o.status.code(),
                e.exit
            ));
        } else if !stderr.lines().any(|l| l == e.message) {
            wrong.push(format!("{}: no line `{}` in\n{stderr}", e.title, e.message));
        } else if e.exit == 0 && !dir.path().join("out.nc").exists() {
            wrong.push(format!("{}: a warning must not stop the output", e.title));
        } else if e.exit != 0 && dir.path().join("out.nc").exists() {
            wrong.push(format!("{}: an error left an output file", e.title));
        }
        let _ = std::fs::remove_file(dir.path().join("out.nc"));
    }
    assert!(checked >= 48, "{checked} examples run");
    assert!(wrong.is_empty(), "{}", wrong.join("\n\n"));
}
