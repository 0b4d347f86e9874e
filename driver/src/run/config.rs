//! A request and its files made into one configuration: the outputs planned, the dialect and
//! machine, the kernel's and the VM's settings, the clock.

use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use fmsvm_canon::decode::InputRules;
use fmsvm_compiler::{Program, SourceMap};
use fmsvm_emit::literal::{self};
use fmsvm_kernel::probe::ProbeModel;
use fmsvm_kernel::{OutputFrame, Settings};
use fmsvm_vm::{Limits, RunOptions, Variables};

use fmsvm_block::OutputBudget;

use crate::exit::{Exit, Failure};
use crate::input::Charset;
use crate::library::Folders;
use crate::output::{Named, Target, check_distinct};
use crate::report::plain;
use crate::request::{FastPath, GCodeSystem, InputSyntax, LatheX, Machine, MainM99, Request};

use super::*;

/// `OUT` with `.PARTIAL` before its extension.
pub(super) fn partial_name(out: &Path) -> PathBuf {
    let stem = out
        .file_stem()
        .map_or("out".into(), |s| s.to_string_lossy().into_owned());
    let name = match out.extension() {
        Some(e) => format!("{stem}.PARTIAL.{}", e.to_string_lossy()),
        None => format!("{stem}.PARTIAL"),
    };
    out.with_file_name(name)
}

/// The date and time #3011/#3012 read: the flags, else SOURCE_DATE_EPOCH, else now (UTC).
pub fn clock(a: &Request) -> (u32, u32) {
    let secs = std::env::var("SOURCE_DATE_EPOCH")
        .ok()
        .and_then(|s| s.parse::<u64>().ok())
        .unwrap_or_else(|| {
            SystemTime::now()
                .duration_since(UNIX_EPOCH)
                .map_or(0, |d| d.as_secs())
        });
    let days = (secs / 86_400) as i64;
    // Civil date from days since 1970-01-01 (Howard Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    let s = secs % 86_400;
    let date = (y * 10_000 + m * 100 + d) as u32;
    let time = ((s / 3600) * 10_000 + (s / 60 % 60) * 100 + s % 60) as u32;
    (a.date.unwrap_or(date), a.time.unwrap_or(time))
}

/// Where the outputs of a run go, decided before anything runs.
pub(super) struct Outputs {
    pub(super) program: Target,
    pub(super) print: Target,
    pub(super) dump: Option<Target>,
}

/// Plans every output and refuses a run that would write over an input or write one file twice.
pub(super) fn plan_outputs(
    a: &Request,
    temps: &std::sync::Arc<crate::output::Temporaries>,
) -> Result<Outputs, Exit> {
    let plan = |flag: &str, p: &Path| {
        Target::plan(p, temps).map_err(|e| {
            plain(&format!("{flag}: {e}"));
            Exit::Io
        })
    };
    let program = match &a.output {
        Some(p) => plan("-o", p)?,
        None => Target::Stdout,
    };
    let print = match (&a.print, &program) {
        (Some(p), _) => plan("--print", p)?,
        // Beside the output, else beside the input.
        (None, Target::File { path, .. }) => plan("--print", &path.with_extension("prn"))?,
        (None, _) if a.input.file.as_os_str() == "-" => plan("--print", Path::new("stdin.prn"))?,
        (None, _) => plan("--print", &a.input.file.with_extension("prn"))?,
    };
    let dump = match &a.dump_vars {
        Some(p) => Some(plan("--dump-vars", p)?),
        None => None,
    };
    let mut inputs: Vec<(&str, PathBuf)> = Vec::new();
    if a.input.file.as_os_str() != "-" {
        inputs.push(("the program", a.input.file.clone()));
    }
    if let Some(v) = &a.vars {
        inputs.push(("--vars", v.clone()));
    }
    if let Some(p) = &a.probe_points {
        inputs.push(("--probe-points", p.clone()));
    }
    if let Some(p) = &a.offsets {
        inputs.push(("--offsets", p.clone()));
    }
    if let Some(p) = &a.input.params {
        inputs.push(("--params", p.clone()));
    }
    if let Some(p) = &a.dialect_file {
        inputs.push(("--dialect-file", p.clone()));
    }
    if let Some(p) = &a.verify_file {
        // Read back whole: a regular file (a FIFO would hold the run, a device never end).
        if let Err(e) = crate::input::require_regular(p) {
            plain(&format!("cannot read --verify-file {}: {e}", p.display()));
            return Err(Exit::Io);
        }
        inputs.push(("--verify-file", p.clone()));
    }
    for f in Folders::files(&a.input.libs) {
        inputs.push(("--lib", f));
    }
    let mut named = vec![
        Named {
            flag: "-o",
            target: &program,
        },
        Named {
            flag: "--print",
            target: &print,
        },
    ];
    if let Some(d) = &dump {
        named.push(Named {
            flag: "--dump-vars",
            target: d,
        });
    }
    // The variable store may be updated in place: it is read whole before the run and replaced
    // atomically after it.
    check_distinct(&inputs, &named, &[("--dump-vars", "--vars")]).map_err(|e| {
        plain(&e);
        Exit::Usage
    })?;
    Ok(Outputs {
        program,
        print,
        dump,
    })
}

/// Everything a run takes from its arguments and input files, read and merged in one place: the
/// outputs planned, the dialect profile, the compiled program, the starting variables, offsets and
/// probe model, and the emitter's, the kernel's and the VM's settings.
pub(super) struct Config {
    pub(super) outputs: Outputs,
    pub(super) profile: crate::dialects::Profile,
    /// The output is resolved motion (asked for, or the dialect is not a literal one).
    pub(super) resolve: bool,
    pub(super) program: Program,
    pub(super) sources: SourceMap,
    pub(super) params: crate::params::Params,
    pub(super) flat: Option<crate::flat::FlatProgram>,
    pub(super) out_charset: Charset,
    pub(super) vars: Variables,
    pub(super) options: literal::Options,
    pub(super) rules: InputRules,
    pub(super) settings: Settings,
    pub(super) frames: fmsvm_kernel::frames::Frames,
    pub(super) run_options: RunOptions,
    pub(super) date: u32,
    pub(super) time: u32,
    pub(super) probe: ProbeModel,
    /// The stock `stats` cuts, and the tools that cut it (None: no simulation).
    pub(super) stock: Option<Stocked>,
}

/// A stock and the shapes of the tools that cut it.
pub(super) struct Stocked {
    pub(super) stock: fmsvm_stock::Stock,
    pub(super) tools: std::collections::BTreeMap<u32, fmsvm_stock::Tool>,
}

/// What the run adds to the kernel: tolerances, the output frame, the compensation style, the
/// power-on state, the start point, the cycle parameters (flags over `--params`).
pub(super) fn kernel_settings(
    a: &Request,
    params: &crate::params::Params,
    plain_paths: bool,
    lathe: Option<fmsvm_kernel::Lathe>,
    power_on: fmsvm_canon::modal::ModalState,
) -> Settings {
    Settings {
        lathe,
        arc_tolerance: a.arc_tolerance,
        linearize: a.linearize,
        frame: a.frame,
        comp_style: a.comp_style,
        power_on,
        start_point: a
            .start_point
            .or(params.start_point)
            .unwrap_or([f64::NAN; 6]),
        strict_axes: a.strict_axes,
        arc_intersections: a.input.input_syntax.or(params.input) == Some(InputSyntax::Nct),
        plain_moves: plain_paths,
        variables: params.variables.clone(),
        arc_centre: params.arc_centre.unwrap_or_default(),
        mill_threads: false,
        control_offsets: fmsvm_kernel::ControlOffsets::default(),
        tool_tip: false,
        // G51's P I J K without a point: Fanuc's least increment of magnification (0.001 unless
        // the parameters say 0.00001); the NCT textbook writes the factor itself (`P2`: ×2).
        scaling_unit: if a.input.input_syntax.or(params.input) == Some(InputSyntax::Nct) {
            0.0
        } else {
            params.scaling_unit.unwrap_or(0.001)
        },
        haas_codes: haas_program(&a.input, params),
        // Set where the dialect is known (`configure`).
        haas_output: false,
        // The run's own, set where it is made (`configure`).
        budget: fmsvm_block::OutputBudget::default(),
        cycles: {
            let mut c = fmsvm_kernel::cycles::CycleParams::default();
            if let Some(v) = params.g73_retract {
                c.g73_retract = v;
            }
            if let Some(v) = params.g83_clearance {
                c.g83_clearance = v;
            }
            c.stock_retract = params.haas_setting_73;
            c.thread_allowance = params.haas_setting_86;
            c.thread_least = params.haas_setting_99;
            c.thread_chamfer = params.haas_setting_95;
            c
        },
    }
}

/// How the VM runs: the engine, the limits, the print and M99 rules, the arithmetic's options
/// (flags over `--params`).
pub(super) fn run_options(a: &Request, params: &crate::params::Params) -> RunOptions {
    RunOptions {
        engine: a.engine,
        limits: Limits {
            max_steps: a.max_steps,
            max_blocks: a.max_blocks,
            // Bounded when parsed (MAX_SECONDS), so the conversion cannot fail.
            max_time: a
                .max_seconds
                .and_then(|s| std::time::Duration::try_from_secs_f64(s).ok()),
        },
        print_without_popen: a.print_without_popen || haas_program(&a.input, params),
        main_m99_ends: a.main_m99 == MainM99::End,
        max_sub_depth: a.sub_depth,
        semantics: fmsvm_vm::value::Semantics {
            nat: a.nat || params.nat.unwrap_or(false),
            mod_integers: a.mod_integers || params.mod_integers.unwrap_or(false),
        },
    }
}

/// The machine the program is for (`--machine`, else the parameters', else the dialect's: a
/// lathe-only dialect makes a lathe) and its power-on modal state (`--modal` read in its codes);
/// the dialect is told when it writes a turning program. A lathe program for a milling dialect, or
/// the reverse, is a usage error.
pub(super) fn machine(
    a: &Request,
    params: &crate::params::Params,
    profile: &mut crate::dialects::Profile,
) -> Result<(Option<fmsvm_kernel::Lathe>, fmsvm_canon::modal::ModalState), Exit> {
    use fmsvm_canon::modal::{CodeSystem, ModalState};
    use fmsvm_emit::dialect::MachineKind;
    let asked = a.machine.or(params.machine);
    if asked == Some(Machine::Lathe) && a.dialect.is_none() && a.dialect_file.is_none() {
        // A turning program without a dialect named: Fanuc's lathe, or a Haas's for a Haas
        // program (`--control haas-lathe`).
        let name = if haas_program(&a.input, params) {
            "haaslathe"
        } else {
            "fanuc0itd"
        };
        *profile = load_dialect(Some(name), None, a.input.max_input).map_err(Failure::say)?;
        if a.resolve {
            profile.dialect.native_cycles.clear();
        }
    }
    let d = &mut profile.dialect;
    let machine = asked.unwrap_or(match d.machine {
        MachineKind::Lathe => Machine::Lathe,
        _ => Machine::Mill,
    });
    let lathe = machine == Machine::Lathe;
    match (lathe, d.machine) {
        (true, MachineKind::Mill) => {
            plain(&format!(
                "the {} dialect writes for a milling machine, and this is a turning program (--machine lathe): choose a lathe dialect (fanuc0itd, haaslathe, mayak600t, nc31, sinumerik802d, fagor8035t) or linuxcnc or iso",
                d.name
            ));
            return Err(Exit::Usage);
        }
        (false, MachineKind::Lathe) => {
            plain(&format!(
                "the {} dialect writes for a lathe, and this is a milling program: say --machine lathe (or --control fanuc-0i-t) for a turning program",
                d.name
            ));
            return Err(Exit::Usage);
        }
        _ => {}
    }
    if lathe && a.renumber.is_some() && !a.resolve && d.literal {
        plain(
            "--renumber with literal output of a turning program: G70–G73 name their profile by its N numbers; resolve it (--resolve) or keep the numbers",
        );
        return Err(Exit::Usage);
    }
    if lathe && a.compact {
        plain("--compact is not yet written for turning programs");
        return Err(Exit::Usage);
    }
    if lathe && (d.control_work || d.control_length) {
        plain(&format!(
            "the {} profile leaves work offsets or tool lengths to the control ([motion] work_offsets, tool_length = \"control\"): that is a milling rule; a lathe's offsets are its tool offsets by T",
            d.name
        ));
        return Err(Exit::Usage);
    }
    if d.control_work && a.frame == OutputFrame::Machine {
        plain(&format!(
            "--frame machine writes machine coordinates, and the {} profile leaves work offsets to the control ([motion] work_offsets = \"control\"): choose one",
            d.name
        ));
        return Err(Exit::Usage);
    }
    d.turning = lathe;
    if !lathe && (a.gcode_system.is_some() || a.lathe_x.is_some()) {
        plain(
            "--gcode-system and --lathe-x are a lathe's: say --machine lathe (or --control fanuc-0i-t)",
        );
        return Err(Exit::Usage);
    }
    let system = match (lathe, a.gcode_system.or(params.gcode_system)) {
        (false, _) => CodeSystem::Mill,
        (true, Some(GCodeSystem::B)) => CodeSystem::LatheB,
        (true, _) => CodeSystem::LatheA,
    };
    // A Fanuc lathe's output is in the G-code system the control is set to (the program's).
    if let Some(l) = d.lathe.as_mut()
        && lathe
        && l.codes != CodeSystem::Mill
    {
        l.codes = system;
    }
    let power_on = match &a.modal {
        None => ModalState::power_on(system),
        Some(text) => ModalState::parse_in(system, text).map_err(|e| {
            plain(&format!("--modal: {e}"));
            Exit::Usage
        })?,
    };
    let diameter = a.lathe_x.or(params.lathe_x) != Some(LatheX::Radius);
    Ok((
        lathe.then_some(fmsvm_kernel::Lathe {
            diameter,
            max_rpm: params.max_rpm,
            y_axis: params.y_axis,
        }),
        power_on,
    ))
}

/// Reads and merges a run's configuration (stage one of `run`); a usage, compile or file error
/// is reported here, with its exit code.
pub(super) fn configure(
    a: &Request,
    temps: &std::sync::Arc<crate::output::Temporaries>,
    simulate: bool,
) -> Result<Config, Exit> {
    let outputs = plan_outputs(a, temps)?;
    let mut profile = load_dialect(
        a.dialect.as_deref(),
        a.dialect_file.as_deref().map(|p| ("--dialect-file", p)),
        a.input.max_input,
    )
    .map_err(Failure::say)?;
    // Asked to resolve: the cycles too.
    if a.resolve {
        profile.dialect.native_cycles.clear();
    }
    if let Some(travel) = a.travel {
        profile.dialect.travel = travel;
    }
    // Output in machine coordinates selects no work system at its start: the positions are the
    // machine's, and a G54 would add its offset to every one of them.
    if a.frame == OutputFrame::Machine {
        profile
            .dialect
            .start_modes
            .retain(|c| !(54..=59).contains(&c.whole()));
    }
    // A control that does not read Fanuc's language gets the motion.
    let resolve = a.resolve || !profile.dialect.literal;
    if a.tape && profile.kind != crate::dialects::Kind::N33 {
        plain("--tape writes the Н33-2М punched tape: it goes with --dialect n33");
        return Err(Exit::Usage);
    }
    if a.verify && !matches!(outputs.program, Target::File { .. }) {
        plain("--verify reads the output back: give it as a file with -o FILE");
        return Err(Exit::Usage);
    }
    let Compiled {
        program,
        sources,
        charset: input_charset,
        params,
        flat,
        ..
    } = compile(&a.input, true)?;
    let out_charset = a
        .output_encoding
        .or(profile.charset)
        .unwrap_or(input_charset);
    let mut vars = Variables::default();
    if let Some(path) = &a.vars {
        parse_input("--vars", path, a.input.max_input, |name, text| {
            crate::vars::parse(name, text, &mut vars, &params.commons)
        })
        .map_err(Failure::say)?;
    }
    // The tests compare the plain paths with the general ones (tests/plain.rs).
    let plain_paths = !a.input.without.contains(&FastPath::Plain);
    let run_options = run_options(a, &params);
    // The blocks and the clock are looked at as lines are made too: one cycle or arc in chords
    // can be many lines.
    let budget = OutputBudget::with_limits(a.max_bytes, a.max_blocks, run_options.limits.max_time);
    let options = literal::Options {
        comments: a.comments,
        renumber: a.renumber,
        compact: a.compact || profile.dialect.compact,
        source: a.input.file.display().to_string(),
        arc_tolerance: a.linearize.unwrap_or(0.001),
        budget,
        plain_path: plain_paths,
        second_aux: params.calls.b_sub,
    };
    let rules = InputRules {
        decimal: a.decimal_input.or(params.decimal_input).unwrap_or_default(),
        second_aux: params.calls.b_sub,
        ..InputRules::default()
    };
    let (lathe, power_on) = machine(a, &params, &mut profile)?;
    // A dialect whose lathes may have a Y axis writes Y only for a machine that declares one (the
    // kernel's Y of a lathe without one is the spindle's plane, never written).
    if let Some(l) = &mut profile.dialect.lathe {
        l.y_axis &= lathe.is_some_and(|l| l.y_axis);
    }
    let mut settings = kernel_settings(a, &params, plain_paths, lathe, power_on);
    settings.budget = options.budget.clone();
    // A milling thread is applied where the output can write it (FMS-3000 §2.7).
    settings.mill_threads = settings.lathe.is_none()
        && profile.dialect.mill_thread != fmsvm_emit::dialect::MillThread::None;
    settings.control_offsets = fmsvm_kernel::ControlOffsets {
        work: profile.dialect.control_work,
        length: profile.dialect.control_length,
    };
    // Literal output for a Haas keeps the Haas's own forms as written.
    settings.haas_output = profile.dialect.haas && !resolve;
    let crate::offsets::Offsets {
        mut frames,
        cutters,
    } = match &a.offsets {
        None => crate::offsets::Offsets {
            frames: fmsvm_kernel::frames::Frames::default(),
            cutters: Default::default(),
        },
        Some(path) => parse_input(
            "--offsets",
            path,
            a.input.max_input,
            crate::offsets::parse_all,
        )
        .map_err(Failure::say)?,
    };
    // Every X a user gives on a diameter lathe is a diameter, as the program's X is (docs/lathe.md):
    // the start point and the reference positions; the kernel keeps radii.
    if let Some(l) = settings.lathe {
        let k = l.radius_per_x_word();
        settings.start_point[0] *= k;
        for r in &mut frames.reference {
            r[0] *= k;
        }
    }
    let (date, time) = clock(a);
    let probe = match (stock_box(a, settings.lathe), &a.probe_points) {
        // A round blank is not the box G31's model touches.
        (Some([min, max]), _) if !a.stock_round => ProbeModel::Stock {
            min,
            max,
            radius: a.probe_radius,
        },
        (_, Some(path)) => ProbeModel::Points {
            points: parse_input("--probe-points", path, a.input.max_input, parse_points)
                .map_err(Failure::say)?,
            next: 0,
        },
        (_, None) => ProbeModel::None,
    };
    // The stock: `--stock`, else the parameters file's.
    let simulated = a
        .stock
        .or(params.stock)
        .map(|b| scaled_box(b, settings.lathe));
    let stock = match simulated {
        Some(b) if simulate => Some(
            stocked(a, b, settings.lathe.is_some(), &frames, cutters).map_err(|e| {
                Failure {
                    exit: Exit::Usage,
                    message: format!("--stock: {e}"),
                }
                .say()
            })?,
        ),
        _ => None,
    };
    Ok(Config {
        stock,
        outputs,
        profile,
        resolve,
        program,
        sources,
        params,
        flat,
        out_charset,
        vars,
        options,
        rules,
        settings,
        frames,
        run_options,
        date,
        time,
        probe,
    })
}

/// `--stock` as least and greatest X Y Z in the kernel's terms: on a lathe its X is read as the
/// program's X (a diameter on a diameter lathe), so it is halved there.
/// The stock `--stock` gives, in cells of `--stock-cell`, and the tools' shapes: a mill's cutters
/// from `--offsets` (`[tool.N] type`, by tool number), a lathe's noses from its offset registers
/// (radius and tip, by offset number).
fn stocked(
    a: &Request,
    [lo, hi]: [[f64; 3]; 2],
    lathe: bool,
    frames: &fmsvm_kernel::frames::Frames,
    cutters: std::collections::BTreeMap<u32, fmsvm_stock::Cutter>,
) -> Result<Stocked, String> {
    use fmsvm_stock::{HalfSection, HeightField, MAX_CELLS, Nose, Stock, Tool};
    if !lathe {
        let cell = a.stock_cell.unwrap_or(0.1);
        let field = HeightField::new([lo, hi], cell, MAX_CELLS)?;
        let field = if a.stock_round {
            let centre = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
            field.round(centre, (hi[0] - lo[0]) / 2.0)
        } else {
            field
        };
        let stock = Stock::Mill(field);
        let tools = cutters
            .into_iter()
            .map(|(n, c)| (n, Tool::Mill(c)))
            .collect();
        return Ok(Stocked { stock, tools });
    }
    let cell = a.stock_cell.unwrap_or(0.05);
    let bar = HalfSection::new([lo[2], hi[2]], [lo[0].max(0.0), hi[0]], cell, MAX_CELLS)?;
    let tools = frames
        .tools
        .iter()
        .enumerate()
        .filter(|(_, r)| r.set && r.radius() > 0.0)
        .map(|(i, r)| {
            let off = fmsvm_kernel::imaginary_tip(r.tip, r.radius());
            (
                i as u32 + 1,
                Tool::Lathe(Nose::new(r.radius(), r.tip, [off[0], off[2]])),
            )
        })
        .collect();
    Ok(Stocked {
        stock: Stock::Lathe(bar),
        tools,
    })
}

pub(super) fn stock_box(a: &Request, lathe: Option<fmsvm_kernel::Lathe>) -> Option<[[f64; 3]; 2]> {
    a.stock.map(|b| scaled_box(b, lathe))
}

/// A stock box in the kernel's terms: a diameter lathe's X halved.
fn scaled_box(b: [f64; 6], lathe: Option<fmsvm_kernel::Lathe>) -> [[f64; 3]; 2] {
    let k = lathe.map_or(1.0, |l| l.radius_per_x_word());
    [[b[0] * k, b[1], b[2]], [b[3] * k, b[4], b[5]]]
}
