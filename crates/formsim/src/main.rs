//! The `formsim` command-line tool.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

mod cli_io;

use clap::{Args, Parser, Subcommand};
use cli_io::{Failure, Outcome, note, say};
use formsim::batch::{self, Engine, journal, local::Local};
use formsim::components::{self, LawSource};
use formsim::plot::{Panel, Series};
use formsim::run::out_dir;
use formsim::{history, point_driver};
use plugins_api::conformance::{self, Options, Subject};
use plugins_api::{FrictionLaw, KinematicFormulation, ParamSpec, Params, TangentMode, registry};

/// formsim: sheet-metal forming simulation with pluggable friction (units: mm, N, MPa, tonne, s).
#[derive(Parser, Debug)]
#[command(name = "formsim", version, about, long_about = None)]
struct Cli {
    /// Worker threads for the simulation's parallel loops (default: the
    /// RAYON_NUM_THREADS environment variable, else one per core). Results
    /// are the same bits on any number; `summary.json` records it.
    #[arg(long, global = true, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=1024))]
    threads: Option<u16>,
    /// More log messages on standard error: -v the run's stages and press
    /// steps, -vv the engine's set-up and mass scaling, -vvv everything.
    /// RUST_LOG (e.g. `RUST_LOG=fem_core=debug`) overrides it.
    #[arg(short, long, global = true, action = clap::ArgAction::Count)]
    verbose: u8,
    /// No progress bars, and log errors only.
    #[arg(short, long, global = true)]
    quiet: bool,
    /// Run scenes whose estimated wall time exceeds 24 hours (refused
    /// otherwise, naming the key that sets the step: usually a slip).
    #[arg(long, global = true)]
    allow_long: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// List the friction laws and formulations with their parameter schemas, or check a law.
    Laws(LawsArgs),
    /// Dynamic plugins (shared libraries): friction laws and user materials.
    Plugin {
        #[command(subcommand)]
        action: PluginAction,
    },
    /// Integrate one contact point along a prescribed history (CSV in, CSV and PNG out).
    FrictionPoint(FrictionPointArgs),
    /// Rigid tools of a scene's tools section: export (VTU, OBJ) or project points.
    Tools {
        #[command(subcommand)]
        action: ToolsAction,
    },
    /// Scene files: check and summarise.
    Scene {
        #[command(subcommand)]
        action: SceneAction,
    },
    /// Run a forming simulation: summary.json, sections, energies, punch force, VTK, plots.
    Run(RunArgs),
    /// Run a scene for several laws and formulations and tabulate the differences.
    Compare(CompareArgs),
    /// Fit scene values (friction parameters first) to measurements: optimiser, journal, uncertainty.
    Identify(IdentifyArgs),
    /// Normalised finite-difference sensitivities of the measured quantities to scene values.
    Sensitivity(SensitivityArgs),
    /// What accuracy costs in time: vary scene values around a reference, tabulate errors and CPU time.
    Study(StudyArgs),
    /// Every registered component: friction laws, formulations, materials, shell elements, tool kinds, scene kinds.
    Components,
}

#[derive(Args, Debug)]
struct IdentifyArgs {
    /// Scene file (TOML; docs/scene-format.md).
    scene: PathBuf,
    /// Measurements: TOML data sets, or the CSV `stroke_mm,quantity,value_mm[,se_mm]` (docs/identification.md).
    #[arg(long, value_name = "FILE")]
    measurements: PathBuf,
    /// A fitted scene value with its bounds and optional start, e.g.
    /// `contact.params.ac.mu=0.05..0.3:0.162` (repeatable).
    #[arg(long = "fit", value_name = "KEY=LO..HI[:START]", required = true)]
    fit: Vec<String>,
    /// Output directory: journal, runs, identification.json/.md, plots. A second
    /// call with the same arguments resumes from its journal.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Objective: `mae` (the thesis's mean absolute error) or `wls` (weighted least squares; needs standard errors).
    #[arg(long, default_value = "mae")]
    objective: String,
    /// Optimiser: `nelder-mead` (argmin), `lm` (Levenberg–Marquardt on finite-difference Jacobians)
    /// or `surrogate` (Gaussian processes over a Latin hypercube sweep, minimised, checked by one run).
    #[arg(long, default_value = "nelder-mead")]
    method: String,
    /// `--method surrogate`: points of the sweep (default 10 per fitted value).
    #[arg(long, value_name = "N")]
    samples: Option<usize>,
    /// Stop after this many evaluations (one evaluation runs every data set once).
    #[arg(long, default_value_t = 40)]
    max_evaluations: usize,
    /// Nelder–Mead: stop when the objective's standard deviation over the simplex is below this.
    #[arg(long, default_value_t = 1e-4)]
    tolerance: f64,
    /// Finite-difference step of the Jacobians, as a fraction of each range.
    #[arg(long, default_value_t = 0.02)]
    fd_step: f64,
    /// Override a scene value for every run (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Start over: forget the journal of an earlier call in --out DIR.
    #[arg(long)]
    fresh: bool,
    /// Runs at a time in a batch of evaluations (default: a batch of one run
    /// on every thread, of several one thread each).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=1024))]
    jobs: Option<u16>,
}

#[derive(Args, Debug)]
struct SensitivityArgs {
    /// Scene file (TOML).
    scene: PathBuf,
    /// Measurements (as for identify).
    #[arg(long, value_name = "FILE")]
    measurements: PathBuf,
    /// A scene value, its bounds (the steps stay inside) and the point, e.g.
    /// `contact.params.ac.mu=0.05..0.3:0.162` (repeatable; without START, the scene's value).
    #[arg(long = "param", value_name = "KEY=LO..HI[:AT]", required = true)]
    param: Vec<String>,
    /// The larger relative step h (the second is h/2).
    #[arg(long, default_value_t = 0.05)]
    step: f64,
    /// Objective of the objective's row: `mae` or `wls`.
    #[arg(long, default_value = "mae")]
    objective: String,
    /// Output directory (journal, runs, sensitivity.json/.md).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Override a scene value for every run (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

#[derive(Subcommand, Debug)]
enum SceneAction {
    /// Validate a scene and print what it would run.
    Check {
        /// Scene file (TOML; docs/scene-format.md).
        scene: PathBuf,
        /// Override a scene value, e.g. contact.law=wvs (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Also print every setting as resolved (defaults filled in, overrides applied).
        #[arg(long)]
        resolved: bool,
    },
}

#[derive(Args, Debug)]
struct RunArgs {
    /// Scene file (TOML; docs/scene-format.md).
    scene: PathBuf,
    /// Output directory (default: results/<scene name>, whose earlier results
    /// are replaced). An explicit DIR that is not empty needs --force.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Replace the results in a non-empty --out DIR (only the files formsim
    /// writes are removed; other files are kept).
    #[arg(long)]
    force: bool,
    /// Override a scene value, e.g. contact.law=wvs, blank.mesh.divisions=25 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Write the blank's whole state to FILE when the run completes, for a
    /// later scene's `blank.initial_state` (docs/stages.md).
    #[arg(long = "save-state", value_name = "FILE")]
    save_state: Option<PathBuf>,
}

#[derive(Args, Debug)]
struct CompareArgs {
    /// Scene file (TOML).
    scene: PathBuf,
    /// Laws, comma-separated (default: ac,wvs,wh,levanov; with --case: the scene's own).
    #[arg(long, value_delimiter = ',')]
    laws: Option<Vec<String>>,
    /// Formulations, comma-separated (default: convective,jaumann; with --case: the scene's own).
    #[arg(long, value_delimiter = ',')]
    formulations: Option<Vec<String>>,
    /// A named variant with its own overrides, e.g.
    /// `--case "bt-100:blank.mesh.divisions=100;solver.mass_scaling_dt=2.5e-7"`
    /// (repeatable; crossed with the laws and formulations; the first row is the reference).
    #[arg(long = "case", value_name = "NAME:KEY=VALUE;…")]
    cases: Vec<String>,
    #[command(flatten)]
    batch: BatchArgs,
}

/// The options every command that runs several scenes into one directory shares.
#[derive(Args, Debug)]
struct BatchArgs {
    /// Output directory. A second call with the same arguments resumes from
    /// its journal (runs only what is missing or failed); another non-empty
    /// DIR needs --force.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Replace the results in a non-empty --out DIR (only the files formsim
    /// writes are removed, the journal too; other files are kept).
    #[arg(long)]
    force: bool,
    /// Start over: forget the journal of an earlier call in --out DIR and
    /// replace its results (as --force).
    #[arg(long)]
    fresh: bool,
    /// Runs at a time (default: as many as fill the cores with --threads
    /// each; `study` one at a time, so that its timings are not shared).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=1024))]
    jobs: Option<u16>,
    /// Override a scene value for every run (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

#[derive(Args, Debug)]
struct StudyArgs {
    /// Scene file (TOML).
    scene: PathBuf,
    /// A knob and its values, most accurate first, e.g.
    /// `--vary blank.mesh.divisions=100,50,25` (repeatable); the value
    /// `default` removes the key (`--vary solver.mass_scaling_dt=5e-7,default`).
    #[arg(
        long = "vary",
        value_name = "KEY=V1,V2,…",
        required_unless_present = "model"
    )]
    vary: Vec<String>,
    /// A model and its values, e.g. `--model contact.law=ac,wvs,wh,levanov`
    /// (repeatable): varied like a knob, but reported apart, since its
    /// values are other models, not approximations of one answer; no part
    /// in the combination, the recommendation or the Pareto front.
    #[arg(long = "model", value_name = "KEY=V1,V2,…")]
    model: Vec<String>,
    /// A refinement sequence, coarse to fine, every key refined by one
    /// ratio at each level (repeatable), e.g. `--converge
    /// blank.mesh.divisions=25,50,100 --converge
    /// solver.mass_scaling_dt=1e-6,5e-7,2.5e-7`: the study runs each level,
    /// extrapolates the converged answer (Richardson) and measures every
    /// variant, the reference too, against it.
    #[arg(long = "converge", value_name = "KEY=V1,V2,V3,…")]
    converge: Vec<String>,
    /// Reference values when not the first listed, e.g. `"blank.mesh.divisions=50;contact.law=ac"`.
    #[arg(long, value_name = "KEY=V;…")]
    reference: Option<String>,
    /// Quantities compared: summary.json keys (draw_in.DX, punch_force_max,
    /// sections.OD.major_max) or section curves SECTION[@STROKE]:COLUMN
    /// (OD:major, OX@40:thinning), comma-separated.
    #[arg(long, value_delimiter = ',', required = true)]
    quantities: Vec<String>,
    /// Every combination of the values instead of one knob at a time.
    #[arg(long)]
    cross: bool,
    /// Rounds over the variants, in alternating order, the reference between
    /// every 4 (medians and spreads are reported).
    #[arg(long, default_value_t = 1, value_name = "N")]
    repeat: usize,
    /// Largest relative error a recommended variant may have on any quantity.
    #[arg(long, default_value_t = 0.02, value_name = "FRACTION")]
    tolerance: f64,
    #[command(flatten)]
    batch: BatchArgs,
}

#[derive(Subcommand, Debug)]
enum ToolsAction {
    /// List the registered tool kinds (a scene's `kind = …`) with their keys.
    Kinds,
    /// Write every tool of SPEC as DIR/NAME.vtu (ParaView) and DIR/NAME.obj.
    Export {
        /// Tools spec (TOML with [tools.NAME] tables; docs/tools.md).
        spec: PathBuf,
        /// Output directory.
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
    },
    /// Project the points of a CSV (columns x,y,z in mm) on one tool.
    Project {
        /// Tools spec (TOML).
        spec: PathBuf,
        /// Tool name (the NAME of [tools.NAME]).
        #[arg(long, value_name = "NAME")]
        tool: String,
        /// Input CSV with columns x,y,z.
        #[arg(long, value_name = "IN.csv")]
        points: PathBuf,
        /// Output CSV: px,py,pz,nx,ny,nz,distance,k1,k2,patch,u,v.
        #[arg(long, value_name = "OUT.csv")]
        out: PathBuf,
    },
}

#[derive(Args, Debug)]
struct LawsArgs {
    /// Describe only this law or formulation.
    #[arg(long, value_name = "NAME")]
    describe: Option<String>,
    #[command(subcommand)]
    action: Option<LawsAction>,
}

#[derive(Subcommand, Debug)]
enum LawsAction {
    /// Run the conformance suite (docs/friction-math.md §5) on a law with every formulation.
    Check {
        /// Law name (`formsim laws` lists them).
        name: String,
        /// Parameter value KEY=VALUE (repeatable); benchmark values otherwise.
        #[arg(long = "param", value_name = "KEY=VALUE", value_parser = parse_param)]
        params: Vec<(String, f64)>,
    },
}

#[derive(Subcommand, Debug)]
enum PluginAction {
    /// Load a plugin (friction law or material), print its schema, run its conformance suite; exit non-zero on failure.
    Check {
        /// Path of the plugin's shared library (`.so`).
        path: PathBuf,
        /// Parameter value KEY=VALUE (repeatable).
        #[arg(long = "param", value_name = "KEY=VALUE", value_parser = parse_param)]
        params: Vec<(String, f64)>,
    },
}

#[derive(Args, Debug)]
#[command(group(clap::ArgGroup::new("source").required(true).args(["law", "plugin"])))]
struct FrictionPointArgs {
    /// Built-in or registered law (`ac`, `wvs`, `wh`, `levanov`).
    #[arg(long, value_name = "NAME")]
    law: Option<String>,
    /// A plugin's shared library instead of a named law.
    #[arg(long, value_name = "PATH")]
    plugin: Option<PathBuf>,
    /// Parameter value KEY=VALUE in scene units (mm, N, MPa, s); repeatable.
    #[arg(long = "param", value_name = "KEY=VALUE", value_parser = parse_param)]
    params: Vec<(String, f64)>,
    /// Kinematic formulation: convective, jaumann, lagrangian, updated-lagrangian.
    #[arg(long, value_name = "NAME", default_value = "convective")]
    formulation: String,
    /// Input history CSV (columns documented in `docs/point-history.md`).
    #[arg(long, value_name = "IN.csv")]
    history: PathBuf,
    /// Output CSV: t,t_x,t_y,t_z,stick,dgamma,dissipation,omega,mu_eff.
    #[arg(long, value_name = "OUT.csv")]
    out: PathBuf,
    /// Also plot the traction history to PNG (default: OUT with extension .png).
    #[arg(long, value_name = "PNG", num_args = 0..=1)]
    plot: Option<Option<PathBuf>>,
}

fn parse_param(text: &str) -> Result<(String, f64), plugins_api::AssignmentError> {
    Params::parse_assignment(text)
}

fn to_params(list: &[(String, f64)]) -> Params {
    let mut p = Params::new();
    for (k, v) in list {
        p.set(k, *v);
    }
    p
}

fn main() -> ExitCode {
    friction_laws::ensure_linked();
    shell_elements::kinds::ensure_linked();
    formsim::run::reference_checks::ensure_linked();
    let cli = Cli::parse();
    cli_io::init_logs(cli.verbose, cli.quiet);
    formsim::scene::estimate::allow_long_runs(cli.allow_long);
    if let Some(n) = cli.threads
        && let Err(e) = rayon::ThreadPoolBuilder::new()
            .num_threads(usize::from(n))
            .build_global()
    {
        note!("error: --threads {n}: {e}");
        return ExitCode::FAILURE;
    }
    // Several copies started by mpirun or srun would each do the whole work,
    // except a command that shares its runs over MPI (docs/scale-out.md).
    let shared = cfg!(feature = "mpi")
        && matches!(
            cli.command,
            Command::Study(_) | Command::Compare(_) | Command::Identify(_)
        );
    if !shared && let Err(e) = formsim::batch::launcher::single_copy(cfg!(feature = "mpi")) {
        note!("error: {e}");
        return ExitCode::FAILURE;
    }
    let result = match cli.command {
        Command::Laws(args) => laws(&args),
        Command::Plugin {
            action: PluginAction::Check { path, params },
        } => plugin_check(&path, &to_params(&params)),
        Command::FrictionPoint(args) => friction_point(&args),
        Command::Tools { action } => tools(&action),
        Command::Scene {
            action:
                SceneAction::Check {
                    scene,
                    set,
                    resolved,
                },
        } => scene_check(&scene, &set, resolved),
        Command::Run(args) => run(&args),
        Command::Compare(args) => compare(&args, cli.threads),
        Command::Identify(args) => identify(&args, cli.threads),
        Command::Sensitivity(args) => sensitivity(&args),
        Command::Study(args) => study(&args, cli.threads),
        Command::Components => components_list(),
    };
    match result {
        Ok(code) => code,
        Err(Failure::ClosedStdout) => ExitCode::SUCCESS,
        Err(Failure::Message(message)) => {
            note!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn tools(action: &ToolsAction) -> Outcome {
    match action {
        ToolsAction::Kinds => {
            tools_nurbs::ensure_linked();
            say!("Tool kinds (units: mm, degrees; every kind also takes origin and facing):");
            for k in tools_nurbs::kinds::all() {
                let facing = match k.default_facing {
                    tools_nurbs::builders::Facing::Up => "up",
                    tools_nurbs::builders::Facing::Down => "down",
                };
                say!(
                    "  {:<20} {} [facing {facing} by default]",
                    k.name,
                    k.summary
                );
                print_tool_keys(k.keys)?;
            }
        }
        ToolsAction::Export { spec, out } => {
            for f in formsim::tools_cli::export(spec, out)? {
                say!("wrote {f}");
            }
        }
        ToolsAction::Project {
            spec,
            tool,
            points,
            out,
        } => {
            let n = formsim::tools_cli::project(spec, tool, points, out)?;
            say!("projected {n} points on `{tool}`; wrote {}", out.display());
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn format_default(spec: &ParamSpec) -> String {
    spec.default
        .map_or_else(|| "required".to_string(), |d| format!("{d}"))
}

fn print_schema(specs: &[ParamSpec]) -> Result<(), Failure> {
    for s in specs {
        say!(
            "    {:<14} {:<14} {:<10} {:<22} {}",
            s.name,
            format!("[{}]", s.unit),
            format_default(s),
            s.range_text(),
            s.doc
        );
    }
    Ok(())
}

fn print_tool_keys(keys: &[tools_nurbs::kinds::ToolKey]) -> Result<(), Failure> {
    for k in keys {
        say!(
            "    {:<16} {:<10} {:<20} {:<26} {}",
            k.name,
            format!("[{}]", k.unit),
            k.default.unwrap_or("required"),
            k.range,
            k.doc
        );
    }
    Ok(())
}

/// `formsim components`: every registry, one line per component.
fn components_list() -> Outcome {
    tools_nurbs::ensure_linked();
    say!("Friction laws (contact.law; `formsim laws --describe NAME` for the parameters):");
    for l in registry::laws() {
        say!("  {:<20} {}", l.description.name, l.description.summary);
    }
    say!("Kinematic formulations (contact.formulation):");
    for f in registry::formulations() {
        say!("  {:<20} {}", f.name, f.summary);
        print_schema(f.params)?;
    }
    say!("Materials (blank.material.model; own keys in blank.material.parameters):");
    for m in shell_elements::kinds::materials() {
        say!("  {:<20} {}", m.name, m.summary);
        print_schema(m.params)?;
    }
    say!("Shell elements (blank.element; own keys in blank.element_parameters):");
    for e in shell_elements::kinds::elements() {
        say!("  {:<20} {}", e.name, e.summary);
        print_schema(e.params)?;
    }
    say!("Tool kinds (tools.NAME.kind; `formsim tools kinds` for their facing):");
    for k in tools_nurbs::kinds::all() {
        say!("  {:<20} {}", k.name, k.summary);
        print_tool_keys(k.keys)?;
    }
    say!(
        "Scene kinds (scene.kind): the presets, then the reference checks with the keys of their [output.KEY] tables:"
    );
    for p in formsim::scene::kind::PRESETS {
        say!("  {:<20} {}", p.name, p.summary);
    }
    for c in formsim::scene::kind::reference_checks() {
        say!("  {:<20} {}", c.name, c.summary);
        for k in c.keys {
            say!(
                "    {:<14} {:<14} {:<10} {:<22} {}",
                k.key(),
                format!("[{}]", k.unit()),
                k.default_text(),
                k.range_text(),
                k.doc()
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn laws(args: &LawsArgs) -> Outcome {
    if let Some(LawsAction::Check { name, params }) = &args.action {
        let entry = registry::law(name).map_err(|e| e.to_string())?;
        let build = |p: &Params| registry::build_law(name, p);
        return run_suite(name, entry.description.params, &build, &to_params(params));
    }
    let laws = registry::laws();
    let forms = registry::formulations();
    if let Some(name) = &args.describe {
        if let Some(l) = laws.iter().find(|l| l.description.name == name) {
            say!("law {}: {}", l.description.name, l.description.summary);
            say!(
                "    {:<8} {:<14} {:<10} {:<22} doc",
                "param",
                "unit",
                "default",
                "range"
            );
            print_schema(l.description.params)?;
            return Ok(ExitCode::SUCCESS);
        }
        if let Some(f) = forms.iter().find(|f| f.name == name) {
            say!(
                "formulation {}: {}\n    reads: {}",
                f.name,
                f.summary,
                formulation_needs(f)
            );
            if !f.params.is_empty() {
                print_schema(f.params)?;
            }
            return Ok(ExitCode::SUCCESS);
        }
        let known: Vec<&str> = laws
            .iter()
            .map(|l| l.description.name)
            .chain(forms.iter().map(|f| f.name))
            .collect();
        return Err(format!(
            "unknown law or formulation `{name}`; known: {}",
            known.join(", ")
        )
        .into());
    }
    say!("Friction laws (units: mm, N, MPa, s; `formsim laws --describe NAME` for one):");
    for l in &laws {
        say!("\n  {} — {}", l.description.name, l.description.summary);
        if let Ok(law) = (l.build)(&defaults_or_benchmark(
            l.description.name,
            l.description.params,
        )) {
            say!("    reads: {}", law.needs());
        }
        print_schema(l.description.params)?;
    }
    say!(
        "\n  {} — normal contact only (scene key contact.law = \"{0}\"): no friction law, no \
         return mapping, no stick springs; no parameters, no formulation",
        contact::FRICTIONLESS
    );
    say!("\nKinematic formulations (any law pairs with any formulation):");
    for f in &forms {
        say!(
            "  {:<20} {}  [reads: {}]",
            f.name,
            f.summary,
            formulation_needs(f)
        );
        if !f.params.is_empty() {
            print_schema(f.params)?;
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// What a registered formulation reads, built with its defaults (or a
/// value inside the range of a required parameter).
fn formulation_needs(f: &registry::FormulationEntry) -> String {
    (f.build)(&defaults_or_benchmark(f.name, f.params))
        .map_or_else(|e| format!("(not built: {e})"), |f| f.needs().to_string())
}

/// Resolved parameter values for listing purposes.
fn defaults_or_benchmark(name: &str, specs: &[ParamSpec]) -> Vec<f64> {
    let (params, _) = components::suite_params(name, specs, &Params::new());
    params.resolve(name, specs).unwrap_or_default()
}

fn run_suite(
    name: &str,
    specs: &[ParamSpec],
    build: &conformance::BuildLaw<'_>,
    given: &Params,
) -> Outcome {
    let (base, chosen) = components::suite_params(name, specs, given);
    base.resolve(name, specs).map_err(|e| e.to_string())?;
    if !chosen.is_empty() {
        say!(
            "note: required parameters not given were set inside their range: {} (use --param to choose)",
            chosen.join(", ")
        );
    }
    let subject = Subject {
        name: name.to_string(),
        params: specs,
        build,
        base,
    };
    let formulations = components::all_formulations();
    let refs: Vec<&dyn KinematicFormulation> = formulations
        .iter()
        .map(|f| f as &dyn KinematicFormulation)
        .collect();
    let report = conformance::check_law(&subject, &refs, &Options::default());
    say!("{report}");
    Ok(if report.passed() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

fn plugin_check(path: &Path, given: &Params) -> Outcome {
    if plugins_api::plugin_kind(path) == Some(plugins_api::PluginKind::Material) {
        return material_plugin_check(path, given);
    }
    let library = plugins_api::loader::PluginLibrary::open(path).map_err(|e| e.to_string())?;
    say!(
        "plugin {} ({}): {}",
        library.name(),
        path.display(),
        library.summary()
    );
    say!("    reads: {}", library.needs());
    print_schema(library.params())?;
    let build = |p: &Params| library.build(p);
    let label = format!("plugin {}", library.name());
    let specs = library.params();
    run_suite(&label, specs, &build, given)
}

/// `formsim plugin check` of a user material: its description, schema and
/// the material conformance suite (docs/materials.md).
fn material_plugin_check(path: &Path, given: &Params) -> Outcome {
    use plugins_api::material::{conformance, loader::MaterialLibrary};
    let library = MaterialLibrary::open(path).map_err(|e| e.to_string())?;
    say!(
        "material plugin {} ({}): {}",
        library.name(),
        path.display(),
        library.summary()
    );
    say!(
        "    state variables per point: {}; response: {}",
        library.n_state(),
        if library.isotropic() {
            "isotropic"
        } else {
            "anisotropic"
        }
    );
    print_schema(library.params())?;
    let material = library.build(given).map_err(|e| e.to_string())?;
    let report = conformance::check_material(&material);
    say!("{report}");
    Ok(if report.passed() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

fn friction_point(args: &FrictionPointArgs) -> Outcome {
    let params = to_params(&args.params);
    let source = match (&args.law, &args.plugin) {
        (Some(name), _) => LawSource::Named(name.clone()),
        (None, Some(path)) => LawSource::Plugin(path.clone()),
        (None, None) => return Err(Failure::Message("give --law NAME or --plugin PATH".into())),
    };
    let integrator = components::point_integrator(
        &source,
        &params,
        &args.formulation,
        &Params::new(),
        TangentMode::None,
    )
    .map_err(|e| e.to_string())?;
    let hist = history::read(&args.history).map_err(|e| e.to_string())?;
    let file = args.history.display().to_string();
    let (records, summary) = point_driver::run(integrator.as_ref(), &hist, &file).map_err(|e| {
        // A plugin that failed inside (a caught panic, an error) says why.
        match plugins_api::loader::take_last_error() {
            Some(why) => format!("{e} ({why})"),
            None => e.to_string(),
        }
    })?;
    point_driver::write_csv(&args.out, &records)?;
    say!(
        "friction-point: law {}, formulation {} (k_t = {} MPa/mm)",
        integrator.law_name(),
        integrator.formulation_name(),
        integrator.stick_stiffness()
    );
    say!(
        "  {} steps: {} stick, {} slip, {} open; final frictional work ω = {:.6e} N/mm; max |t|/τ_c - 1 in slip = {:.1e}",
        summary.steps,
        summary.stick,
        summary.slip,
        summary.open,
        summary.omega,
        summary.max_excess
    );
    if summary.clamped > 0 {
        say!(
            "  note: the law's lower clamp (e.g. WH μ_min) was active in {} steps, first at t = {} s",
            summary.clamped,
            summary.first_clamp_t.unwrap_or(f64::NAN)
        );
    }
    say!("  wrote {}", args.out.display());
    if let Some(plot) = &args.plot {
        let png = plot
            .clone()
            .unwrap_or_else(|| args.out.with_extension("png"));
        plot_point(
            &png,
            &records,
            integrator.law_name(),
            integrator.formulation_name(),
        )?;
        say!("  wrote {}", png.display());
    }
    Ok(ExitCode::SUCCESS)
}

fn plot_point(
    png: &Path,
    records: &[point_driver::Record],
    law: &str,
    formulation: &str,
) -> Result<(), formsim::plot::PlotError> {
    let series = |label: &str, f: &dyn Fn(&point_driver::Record) -> f64| Series {
        label: label.to_string(),
        points: records.iter().map(|r| (r.t, f(r))).collect(),
    };
    let panels = [
        Panel {
            title: format!("Friction traction — law {law}, formulation {formulation}"),
            x_label: "time t [s]".into(),
            y_label: "traction [MPa]".into(),
            series: vec![
                series("t_x", &|r| r.out.t.x),
                series("t_y", &|r| r.out.t.y),
                series("t_z", &|r| r.out.t.z),
                series("|t|", &|r| r.out.t.norm()),
                series("τ_c", &|r| r.out.tau_c),
            ],
        },
        Panel {
            title: "Effective friction coefficient".into(),
            x_label: "time t [s]".into(),
            y_label: "μ_eff = |t|/p [-]".into(),
            series: vec![series("μ_eff", &|r| r.mu_eff())],
        },
        Panel {
            title: "Frictional work".into(),
            x_label: "time t [s]".into(),
            y_label: "ω [N/mm]".into(),
            series: vec![series("ω (cumulative dissipation)", &|r| r.omega)],
        },
    ];
    formsim::plot::draw_panels(png, &panels, 1000, 340)
}

fn scene_check(path: &Path, set: &[String], resolved: bool) -> Outcome {
    use formsim::scene::estimate;
    let loaded = formsim::scene::load(path, set).map_err(|e| e.to_string())?;
    let mut model = formsim::scene::build(&loaded).map_err(|e| e.to_string())?;
    formsim::run::post::check_lines(&loaded, &model.mesh).map_err(|e| e.to_string())?;
    let (setup, notes) = model.set_up().map_err(|e| {
        let key = match model.initial_state {
            Some(_) => "blank.initial_state",
            None => "solver",
        };
        loaded.key_error(key, e.to_string()).to_string()
    })?;
    let s = &loaded.scene;
    let est = estimate::estimate(s, estimate::MeshSize::of_mesh(&model.mesh));
    say!("{}: ok", path.display());
    let mut warnings = formsim::scene::validate::warnings(&loaded);
    warnings.extend(estimate::added_mass_warnings(s, &setup));
    for w in warnings {
        say!("  warning     {w}");
    }
    say!(
        "  scene       {} ({}): {}",
        s.scene.name,
        s.scene.kind,
        s.scene.description
    );
    say!(
        "  blank       {} nodes, {} {} shells, t0 = {} mm, {} points through the thickness",
        model.mesh.nodes.len(),
        model.mesh.quads.len(),
        s.blank.element,
        s.blank.thickness,
        s.blank.integration_points
    );
    if let Some(st) = &model.initial_state {
        say!(
            "  initial     {} (checksum {}): {} nodes, {} {} shells, {} tools; the first step is {:.4e} s",
            st.path.display(),
            st.checksum,
            st.file.nodes(),
            st.file.quads.len(),
            st.file.element,
            st.file.resume.tools.len(),
            st.file.resume.dt_next
        );
        for n in &notes {
            say!("  initial     {n}");
        }
    }
    say!("  tools       {}", model.tool_names.join(", "));
    say!(
        "  friction    {} + {} ({} pairs)",
        model.law,
        model.formulation,
        model.contact().map_or(0, |c| c.pairs().len())
    );
    for line in formsim::scene::drawbeads::describe(s) {
        say!("  drawbead    {line}");
    }
    for (i, st) in s.steps.iter().enumerate() {
        use formsim::scene::schema::StepKind;
        let springback = st.kind == StepKind::Springback;
        let end = match (&st.duration, &st.until) {
            (Some(d), _) if springback => format!("at most {d} s"),
            (Some(d), _) => format!("{d} s"),
            (None, Some(u)) => format!("until {} travels {} mm", u.tool, u.distance),
            _ => String::new(),
        };
        let mut motions: Vec<String> = st.motions.iter().map(|m| m.describe()).collect();
        if springback {
            motions.push(format!(
                "the tools let go; {} until the out-of-balance force is {:e} of its start",
                st.springback_method(),
                st.springback_tolerance()
            ));
        }
        say!(
            "  step {}      {} ({end}): {}",
            i + 1,
            st.name,
            motions.join("; ")
        );
    }
    say!(
        "  solver      end {:.4e} s, safety {}, mass scaling {}",
        model.end_time,
        s.solver.safety_factor,
        s.solver
            .mass_scaling_dt
            .map_or("off".to_string(), |t| format!(
                "dt = {t:e} s ({})",
                match s.solver.mass_scaling {
                    formsim::scene::schema::MassScalingKind::Conventional => "conventional",
                    formsim::scene::schema::MassScalingKind::Selective => "selective",
                }
            ))
    );
    for line in estimate::report_lines(s, &est, &setup) {
        say!("  {line}");
    }
    if let Some(sel) = model.solver.selective_stats() {
        say!(
            "  selective   the shells' deformation modes carry {:.1} % of the physical mass on top ({:.3e} tonne), rigid-body motion none",
            100.0 * sel.added_mass / setup.physical_mass.max(f64::MIN_POSITIVE),
            sel.added_mass
        );
    }
    if let Some(f) = &model.formability {
        let c = f.summary();
        say!(
            "  formability {} curve ({} strain), plane-strain limit {:.4}, margin {}, stretched from {}",
            c.kind,
            c.measure,
            c.plane_strain_limit,
            c.margin,
            c.insufficient_stretch
        );
    }
    if resolved {
        say!("  settings    (every key as resolved; also summary.json's `settings`)");
        for line in formsim::scene::resolved::dotted_lines(s)? {
            say!("    {line}");
        }
    } else {
        say!(
            "  settings    every key as resolved: add --resolved (also summary.json's `settings`)"
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The exit code of an interrupted run (128 + SIGINT, as shells report it).
const INTERRUPTED: i32 = 130;

fn run(args: &RunArgs) -> Outcome {
    let loaded = formsim::scene::load(&args.scene, &args.set).map_err(|e| e.to_string())?;
    // The default directory is formsim's own: its earlier results are replaced.
    let (out, replace) = match &args.out {
        Some(dir) => (dir.clone(), args.force),
        None => (
            PathBuf::from("results").join(&loaded.scene.scene.name),
            true,
        ),
    };
    out_dir::prepare(&out, out_dir::Owner::Run, replace)?;
    let progress = cli_io::bars_wanted();
    // Ctrl-C stops the run at the next step boundary (it writes what it has
    // computed and exits with 130); a second one exits at once.
    if let Err(e) = ctrlc::set_handler(|| {
        if formsim::run::interrupt() {
            std::process::exit(INTERRUPTED);
        }
        note!(
            "interrupt: stopping at the next step and writing the results so far (Ctrl-C again to quit at once)"
        );
    }) {
        tracing::warn!("Ctrl-C will end the run without writing its results: {e}");
    }
    let result = match formsim::run::run_staged(
        &loaded,
        &formsim::run::RunOptions {
            out: out.clone(),
            progress: if progress {
                formsim::run::Progress::Terminal
            } else {
                formsim::run::Progress::Hidden
            },
        },
        args.save_state.as_deref(),
    ) {
        Ok(r) => r,
        Err(e @ formsim::run::RunError::Interrupted { .. }) => {
            note!("{e}");
            return Ok(ExitCode::from(INTERRUPTED as u8));
        }
        Err(e) => return Err(e.to_string().into()),
    };
    // `{:#}` leaves the warnings out (`-q`: the log has them).
    let s = &result.summary;
    let text = if cli_io::quiet() {
        format!("{s:#}")
    } else {
        format!("{s}")
    };
    say!("{}", text.trim_end());
    say!(
        "  results ({:.2} s to write): {}/summary.json, sections/, energy.csv, punch_force.csv, tools.csv{}, blank.pvd (ParaView), plots/*.png",
        result.write_s,
        out.display(),
        if s.formability.is_some() {
            ", fld.csv"
        } else {
            ""
        }
    );
    if let Some(st) = &s.saved_state {
        say!("  state       {} (checksum {})", st.path, st.checksum);
    }
    Ok(ExitCode::SUCCESS)
}

/// The local executor of a batch of `runs`: `jobs` runs of `threads` each,
/// what is not given filling the cores (neither: as many runs as fill them).
fn local_executor(jobs: Option<u16>, threads: Option<u16>, runs: usize) -> Local {
    // Without --threads the global pool has the machine's (or
    // RAYON_NUM_THREADS) threads; with it, count the machine's cores.
    let cores = match threads {
        None => rayon::current_num_threads(),
        Some(_) => std::thread::available_parallelism().map_or(1, usize::from),
    };
    Local::sized(jobs.map(usize::from), threads.map(usize::from), cores, runs)
}

fn compare(args: &CompareArgs, threads: Option<u16>) -> Outcome {
    use formsim::compare::{Case, Matrix};
    let cases = args
        .cases
        .iter()
        .map(|c| Case::parse(c))
        .collect::<Result<Vec<_>, _>>()?;
    let (default_laws, default_forms) = if cases.is_empty() {
        (
            vec!["ac", "wvs", "wh", "levanov"],
            vec!["convective", "jaumann"],
        )
    } else {
        (Vec::new(), Vec::new())
    };
    let own = |v: Vec<&str>| v.into_iter().map(String::from).collect::<Vec<_>>();
    let matrix = Matrix {
        cases,
        laws: args.laws.clone().unwrap_or_else(|| own(default_laws)),
        formulations: args
            .formulations
            .clone()
            .unwrap_or_else(|| own(default_forms)),
        sets: args.batch.set.clone(),
    };
    // With bars on the terminal, each run's bar says when it is done.
    let progress = cli_io::bars_wanted();
    let plan = formsim::compare::plan(&args.scene, &matrix)?;
    let labels: Vec<String> = plan.labels().map(String::from).collect();
    let local = local_executor(args.batch.jobs, threads, labels.len());
    #[cfg(feature = "mpi")]
    let world = batch::mpi::world()?;
    #[cfg(feature = "mpi")]
    if let Some(w) = &world
        && w.rank() > 0
    {
        return worker(w, &args.scene, local.threads, &|r| {
            serde_json::to_value(formsim::compare::RowResult::of(r)).map_err(|e| e.to_string())
        });
    }
    let context = journal::Context::new("compare", &args.scene, vec![format!("{matrix:?}")])?;
    let journal = batch::prepare(
        &args.batch.out,
        out_dir::Owner::Compare(&labels),
        args.batch.fresh || args.batch.force,
        &context,
    )?;
    #[cfg(feature = "mpi")]
    let mpi = world.as_ref().map(|w| w.executor(local.threads, true));
    #[cfg(feature = "mpi")]
    let executor: &dyn batch::Executor = match &mpi {
        Some(m) => m,
        None => &local,
    };
    #[cfg(not(feature = "mpi"))]
    let executor: &dyn batch::Executor = &local;
    let engine = Engine::new(executor, Some(journal));
    let entries = formsim::compare::execute(plan, &args.batch.out, progress, &engine, &mut |e| {
        if progress {
            return;
        }
        let journalled = if e.from_journal {
            " (from the journal)"
        } else {
            ""
        };
        match &e.result {
            Ok(r) => note!(
                "done {}: {} increments, {:.1} s{journalled}",
                e.label,
                r.increments,
                r.wall_time_s
            ),
            Err(m) => note!("failed {}: {m}", e.label),
        }
    })?;
    if progress {
        for e in &entries {
            if let Err(m) = &e.result {
                note!("failed {}: {m}", e.label);
            }
        }
    }
    let failed = entries.iter().filter(|e| e.result.is_err()).count();
    say!(
        "{} runs ({} failed): {}/compare.md, compare.csv, plots/",
        entries.len(),
        failed,
        args.batch.out.display()
    );
    Ok(if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

fn study(args: &StudyArgs, threads: Option<u16>) -> Outcome {
    use formsim::study::{self, Knob, Spec};
    let mut knobs = args
        .vary
        .iter()
        .map(|k| Knob::parse(k))
        .collect::<Result<Vec<_>, _>>()?;
    for m in &args.model {
        let mut k = Knob::parse(m)?;
        k.model = true;
        knobs.push(k);
    }
    let reference = study::parse_reference(args.reference.as_deref().unwrap_or(""))?;
    let quantities = args
        .quantities
        .iter()
        .map(|q| study::quantity::parse(q))
        .collect::<Result<Vec<_>, _>>()?;
    let spec = Spec {
        knobs,
        reference,
        quantities,
        cross: args.cross,
        repeat: args.repeat,
        tolerance: args.tolerance,
        sets: args.batch.set.clone(),
        converge: args
            .converge
            .iter()
            .map(|k| Knob::parse(k))
            .collect::<Result<Vec<_>, _>>()?,
    };
    let progress = cli_io::bars_wanted();
    let context = journal::Context::new("study", &args.scene, vec![format!("{spec:?}")])?;
    let plan = study::plan(&args.scene, spec)?;
    // One run at a time unless asked: a study times its runs.
    let local = local_executor(Some(args.batch.jobs.unwrap_or(1)), threads, 1);
    #[cfg(feature = "mpi")]
    let world = batch::mpi::world()?;
    #[cfg(feature = "mpi")]
    if let Some(w) = &world
        && w.rank() > 0
    {
        let quantities = &plan.spec.quantities;
        return worker(w, &args.scene, local.threads, &|r| {
            let v = formsim::study::VariantRun::of(r, quantities)?;
            serde_json::to_value(v).map_err(|e| e.to_string())
        });
    }
    let labels = plan.labels();
    let journal = batch::prepare(
        &args.batch.out,
        out_dir::Owner::Study(&labels),
        args.batch.fresh || args.batch.force,
        &context,
    )?;
    let resumed = journal.len();
    #[cfg(feature = "mpi")]
    let mpi = world.as_ref().map(|w| w.executor(local.threads, true));
    #[cfg(feature = "mpi")]
    let (executor, at_a_time): (&dyn batch::Executor, usize) = match &mpi {
        Some(m) => (m, m.ranks()),
        None => (&local, local.jobs),
    };
    #[cfg(not(feature = "mpi"))]
    let (executor, at_a_time): (&dyn batch::Executor, usize) = (&local, local.jobs);
    note!(
        "study: {} variants × {} run(s), {} at a time on {} thread(s) each{}",
        plan.variants.len(),
        args.repeat,
        at_a_time,
        executor.threads(),
        if resumed > 0 {
            format!(" ({resumed} runs in the journal of an earlier call)")
        } else {
            String::new()
        }
    );
    let engine = Engine::new(executor, Some(journal));
    let results = study::execute(plan, &args.batch.out, progress, &engine, &|label, r| {
        if progress {
            return;
        }
        match r {
            Ok(r) => note!(
                "done {label}: {} increments, {:.1} s",
                r.increments,
                r.wall_time_s
            ),
            Err(m) => note!("failed {label}: {m}"),
        }
    })?;
    study::report::write(&args.batch.out, &results)?;
    study::pareto::draw(&args.batch.out, &results)?;
    study::bars::draw(&args.batch.out, &results)?;
    if let Some(c) = &results.converged {
        for w in c.warnings(results.spec.tolerance) {
            note!("warning: {w}");
        }
    }
    match study::recommendation(&results) {
        Some(o) => say!(
            "recommended: {} ({:.2} x the reference's speed, largest error {})",
            o.label,
            o.speed_up.median,
            study::report::percent(o.worst)
        ),
        None => say!("no variant within the tolerance is cheaper: keep the reference"),
    }
    say!(
        "{} variants ({} failed): {}/study.md, study.json, pareto.png, times.png",
        results.outcomes.len() + results.failed.len(),
        results.failed.len(),
        args.batch.out.display()
    );
    Ok(if results.failed.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

/// A batch's runs on an MPI rank other than 0: each job rank 0 sends,
/// run from the scene file with the job's overrides and read by `extract`,
/// until rank 0 says stop.
#[cfg(feature = "mpi")]
fn worker(
    world: &batch::mpi::World,
    scene: &Path,
    threads: usize,
    extract: &batch::Extract<'_>,
) -> Outcome {
    let clock = std::time::Instant::now();
    let work = |_: usize, spec: &batch::JobSpec| {
        let scene = batch::Scene::File(scene);
        batch::run_job(scene, spec, formsim::run::Progress::Hidden, clock, extract)
    };
    world.serve(threads, &work)?;
    Ok(ExitCode::SUCCESS)
}

fn identify(args: &IdentifyArgs, threads: Option<u16>) -> Outcome {
    use formsim::identify::{
        self, Method, Options, measurements::Measurements, objective::Objective, params::FitParam,
    };
    let err = |e: identify::IdentifyError| Failure::Message(e.to_string());
    let params = args
        .fit
        .iter()
        .map(|f| FitParam::parse(f))
        .collect::<Result<Vec<_>, _>>()
        .map_err(err)?;
    if !(args.fd_step > 0.0 && args.fd_step < 0.5) {
        return Err(format!(
            "--fd-step {}: must be in (0, 0.5) (a fraction of each range)",
            args.fd_step
        )
        .into());
    }
    if !(args.tolerance >= 0.0 && args.tolerance.is_finite()) {
        return Err(format!(
            "--tolerance {}: must be a non-negative number",
            args.tolerance
        )
        .into());
    }
    let options = Options {
        scene: args.scene.clone(),
        sets: args.set.clone(),
        params,
        objective: Objective::parse(&args.objective).map_err(err)?,
        method: Method::parse(&args.method).map_err(err)?,
        max_evaluations: args.max_evaluations,
        tolerance: args.tolerance,
        fd_step: args.fd_step,
        out: args.out.clone(),
        progress: cli_io::bars_wanted(),
        samples: args.samples,
    };
    let data = Measurements::read(&args.measurements).map_err(err)?;
    // Only the rank that keeps the journal may remove it: a worker rank
    // that did would race rank 0's first records.
    let fresh = || match args.fresh {
        true => identify::journal::remove(&args.out).map_err(err),
        false => Ok(()),
    };
    let executor = formsim::batch::local::PerBatch {
        jobs: args.jobs.map(usize::from),
        threads: threads.map(usize::from),
        cores: match threads {
            None => rayon::current_num_threads(),
            Some(_) => std::thread::available_parallelism().map_or(1, usize::from),
        },
    };
    #[cfg(feature = "mpi")]
    let world = batch::mpi::world()?;
    #[cfg(feature = "mpi")]
    if let Some(w) = &world {
        if w.rank() > 0 {
            return worker(w, &args.scene, batch::Executor::threads(&executor), &|r| {
                let o = identify::observe::Observables::from_run(r).map_err(|e| e.to_string())?;
                serde_json::to_value(o).map_err(|e| e.to_string())
            });
        }
        fresh()?;
        let mpi = w.executor(batch::Executor::threads(&executor), true);
        let report = identify::identify_on(&options, &data, &mpi).map_err(err)?;
        return identify_report(&report, &args.out);
    }
    fresh()?;
    let report = identify::identify_on(&options, &data, &executor).map_err(err)?;
    identify_report(&report, &args.out)
}

/// Print what an identification found.
fn identify_report(report: &formsim::identify::report::Report, out: &Path) -> Outcome {
    for p in &report.params {
        let interval = report
            .uncertainty
            .as_ref()
            .and_then(|u| {
                u.interval95[report
                    .params
                    .iter()
                    .position(|q| q.key == p.key)
                    .unwrap_or(0)]
            })
            .map_or(String::new(), |[a, b]| {
                format!(", 95 % interval {a:.6} .. {b:.6}")
            });
        say!("{} = {:.6} (start {}){interval}", p.key, p.end, p.start);
    }
    say!(
        "objective {}: {} -> {:.6}; {} evaluations, {} runs made, {} from the journal, {:.1} s ({})",
        report.objective,
        report
            .objective_start
            .map_or("-".into(), |v| format!("{v:.6}")),
        report.objective_end,
        report.evaluations,
        report.runs_made,
        report.from_journal,
        report.wall_s,
        report.stop
    );
    if let Some(f) = &report.surrogate {
        say!(
            "surrogate: {} sweep points, objective {:.6} on it at its optimum, {} by the check run; largest error {} % of a measured value",
            f.samples,
            f.objective_surrogate,
            f.objective_check.map_or("-".into(), |v| format!("{v:.6}")),
            f.check_max_relative_error
                .map_or("-".into(), |v| format!("{:.4}", 100.0 * v))
        );
    }
    if let Some(u) = &report.uncertainty {
        for w in &u.warnings {
            note!("warning: {w}");
        }
    }
    say!(
        "report: {}/identification.md, identification.json, objective.png, fit.png",
        out.display()
    );
    Ok(ExitCode::SUCCESS)
}

fn sensitivity(args: &SensitivityArgs) -> Outcome {
    use formsim::identify::{
        self, SensitivityOptions, measurements::Measurements, objective::Objective,
        params::FitParam,
    };
    let err = |e: identify::IdentifyError| Failure::Message(e.to_string());
    let params = args
        .param
        .iter()
        .map(|f| FitParam::parse(f))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| Failure::Message(e.to_string().replacen("--fit", "--param", 1)))?;
    let options = SensitivityOptions {
        scene: args.scene.clone(),
        sets: args.set.clone(),
        params,
        objective: Objective::parse(&args.objective).map_err(err)?,
        step: args.step,
        out: args.out.clone(),
    };
    let data = Measurements::read(&args.measurements).map_err(err)?;
    let table = identify::sensitivity(&options, &data).map_err(err)?;
    say!(
        "{} runs; table: {}/sensitivity.md, sensitivity.json",
        table.runs,
        args.out.display()
    );
    Ok(ExitCode::SUCCESS)
}
