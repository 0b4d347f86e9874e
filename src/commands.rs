//! The subcommands: each turns its flags into a request, runs the driver and maps the outcome to an
//! exit code.

use std::io;
use std::path::Path;
use std::sync::Arc;

use fmsvm_driver::exit::Exit;
use fmsvm_driver::report::plain;
use fmsvm_driver::run::{Consumer, Hooks, check_one, compile_program, load_dialect, load_params};

use crate::cli::{self, Args, CheckArgs, Command, RunArgs};
use crate::progress::Counted;
use crate::signals::Handler;

/// Runs `a` into `consumer` under the signal handler (told what is being done, its temporary files
/// listed where it removes them), its progress shown on a terminal.
fn expand(a: &RunArgs, consumer: Consumer<'_>) -> Exit {
    let counted = match consumer {
        Consumer::Stats { .. } | Consumer::Render(_) => Counted::Operations,
        Consumer::Flat | Consumer::Into(_) => Counted::Bytes,
    };
    let handler = Arc::new(Handler::default());
    crate::signals::install(&handler);
    let request = a.request();
    handler.doing(format!("expanding {}", request.input.file.display()));
    let hooks = Hooks {
        progress: crate::progress::on_terminal(request.input.quiet, counted),
        temporaries: Some(Arc::clone(&handler.temporaries)),
        ..Hooks::default()
    };
    fmsvm_driver::run::expand(&request, consumer, hooks).exit
}

/// Runs one command.
pub fn main(args: Args) -> Exit {
    match args.command {
        Command::Check(a) => check(&a),
        Command::Ir(a) => match compile_program(&a.input()) {
            Ok(p) => {
                use std::io::Write;
                let mut out = io::stdout().lock();
                match write!(out, "{p}") {
                    Ok(()) => Exit::Success,
                    Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Exit::Success,
                    Err(e) => {
                        plain(&format!("writing the IR: {e}"));
                        Exit::Io
                    }
                }
            }
            Err(e) => e,
        },
        Command::Run(a) => expand(&a, Consumer::Flat),
        Command::Params(a) => match load_params(a.control, a.params.as_deref(), a.max_input) {
            Ok(p) => {
                use std::io::Write;
                let _ = io::stdout().write_all(fmsvm_driver::params::to_toml(&p).as_bytes());
                Exit::Success
            }
            Err(f) => f.say(),
        },
        Command::Stats(a) => {
            if let Err(e) = no_text_flags("stats", &a.run) {
                return e;
            }
            expand(&a.run, Consumer::Stats { json: a.json })
        }
        #[cfg(feature = "dnc")]
        Command::Dnc(a) => {
            let handler = Arc::new(Handler::default());
            crate::signals::install(&handler);
            fmsvm_dnc::main(*a, handler)
        }
        #[cfg(feature = "plot")]
        Command::Plot(a) => {
            if let Err(e) = no_text_flags("plot", &a.run) {
                return e;
            }
            let Some(format) = a.run.output.as_deref().and_then(fmsvm_plot::Format::of) else {
                plain("fmsvm plot: give the picture with -o NAME.svg or -o NAME.png");
                return Exit::Usage;
            };
            let mut picture = fmsvm_plot::Picture::new(format, a.view, a.colour, a.size);
            expand(&a.run, Consumer::Render(&mut picture))
        }
        Command::Dialects(a) => dialects(&a),
        Command::Post(a) => fmsvm_post::main(&a),
        #[cfg(feature = "lsp")]
        Command::Lsp => fmsvm_editor::lsp(),
        #[cfg(feature = "lsp")]
        Command::Dap => fmsvm_editor::dap(),
    }
}

/// `stats` and `plot` write no flat program: a flag about its text is a usage error there (their
/// help hides those flags).
fn no_text_flags(command: &str, a: &RunArgs) -> Result<(), Exit> {
    match cli::text_flag_used(a) {
        Some(flag) => {
            plain(&format!(
                "fmsvm {command} writes no flat program: {flag} applies to `fmsvm run`"
            ));
            Err(Exit::Usage)
        }
        None => Ok(()),
    }
}

/// `fmsvm dialects [--show NAME|FILE]`.
fn dialects(a: &cli::DialectsArgs) -> Exit {
    use std::io::Write;
    let mut out = io::stdout().lock();
    let cycles_of = a.cycles.as_ref().or(a.launcher.as_ref());
    let text = match (&a.show, cycles_of) {
        (_, Some(name)) => {
            let profile = if fmsvm_driver::dialects::BUILT_IN
                .iter()
                .any(|(n, _)| n == name)
            {
                fmsvm_driver::dialects::builtin(name).map_err(|e| {
                    plain(&e);
                    Exit::Usage
                })
            } else {
                let flag = if a.launcher.is_some() {
                    "dialects --launcher"
                } else {
                    "dialects --cycles"
                };
                load_dialect(None, Some((flag, Path::new(name))), u64::MAX).map_err(|f| f.say())
            };
            match profile {
                Ok(p) if p.offered().is_empty() => {
                    plain(&format!(
                        "{name}: the dialect declares no machine cycles ([[cycle]])"
                    ));
                    return Exit::Usage;
                }
                Ok(p) if a.launcher.is_some() => match fmsvm_post::launcher(name, &p) {
                    Ok(text) => text,
                    Err(e) => {
                        plain(&format!("{name}: {e}"));
                        return Exit::Usage;
                    }
                },
                Ok(p) => fmsvm_driver::catalogue::machine_cycles_block(&p.offered()),
                Err(e) => return e,
            }
        }
        (None, None) => {
            let list = fmsvm_driver::dialects::list();
            let width = list.iter().map(|(n, _)| n.len()).max().unwrap_or(0);
            list.iter()
                .map(|(n, s)| format!("{n:width$}  {s}\n"))
                .collect::<String>()
        }
        (Some(name), None) => {
            if let Some((_, text)) = fmsvm_driver::dialects::BUILT_IN
                .iter()
                .find(|(n, _)| n == name)
            {
                text.to_string()
            } else if name == "n33" {
                format!(
                    "# n33: {}\n# Written by code, not by a profile: its options are --tape and the run's flags.\nname = \"n33\"\n",
                    fmsvm_driver::dialects::N33_SUMMARY
                )
            } else {
                match load_dialect(None, Some(("dialects --show", Path::new(name))), u64::MAX) {
                    Ok(p) => fmsvm_driver::dialects::show(&p),
                    Err(f) => return f.say(),
                }
            }
        }
    };
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Exit::Success,
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Exit::Success,
        Err(e) => {
            plain(&format!("cannot write to standard output: {e}"));
            Exit::Io
        }
    }
}

/// `fmsvm check`: compile, report, and say so in one line.
fn check(a: &CheckArgs) -> Exit {
    if a.more.is_empty() {
        return check_one(&a.input.input(), a.deny_warnings).0;
    }
    // Several programs: each on its own, then one summary; the exit is the first failure's.
    let mut first_failure = None;
    let (mut clean, mut failed, mut warnings) = (0usize, 0usize, 0usize);
    for file in std::iter::once(&a.input.file).chain(&a.more) {
        let input = fmsvm_driver::request::Input {
            file: file.clone(),
            ..a.input.input()
        };
        let (exit, w) = check_one(&input, a.deny_warnings);
        warnings += w;
        if exit == Exit::Success {
            clean += 1;
        } else {
            failed += 1;
            first_failure.get_or_insert(exit);
        }
    }
    let files = clean + failed;
    if !a.input.quiet || failed > 0 {
        fmsvm_driver::report::info(&format!(
            "checked {}: {clean} without errors, {failed} with errors; {}",
            fmsvm_driver::report::count(files, "file", "files"),
            fmsvm_driver::report::count(warnings, "warning", "warnings")
        ));
    }
    first_failure.unwrap_or(Exit::Success)
}
