//! `brdf-sls`: run BRDF-fitting experiments (TOML specs), re-plot and summarise stored results,
//! fit a data set once, and generate, evaluate or describe data sets.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context, Result, bail};
use brdf_model::{BrdfParams, DataSet, Evaluator, Lobe, LobeKind};
use clap::{Args, Parser, Subcommand, ValueEnum};
use harness::progress::ProgressMode;
use harness::run::{RunOptions, SlsExecutor, default_threads, run_experiment};
use harness::spec::{DataFormat, FileSpec, ModelSpec, Spec};
use harness::store::read_results;

#[derive(Parser)]
#[command(
    name = "brdf-sls",
    version,
    about = "Stochastic local search for Lafortune BRDF fitting: experiments, statistics, plots",
    long_about = "Stochastic local search for Lafortune BRDF fitting (Backer, Kimberley and \
Skrypnyk).\n\nStart with `brdf-sls run`: it runs the built-in default experiment (the paper's \
tuning instance, AED vs AERS vs RPLS, under a minute on 2 cores) and writes results, \
statistics and plots to results/default/."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run (or resume) an experiment; without SPEC, the built-in default experiment.
    Run(RunArgs),
    /// Validate a spec and print the expanded plan without running anything.
    Check(CheckArgs),
    /// Redraw the plots (and statistics) from stored results without re-running trials.
    Plot(ResultsArgs),
    /// Recompute and print the statistics of stored results.
    Stats(ResultsArgs),
    /// Fit one data set with one algorithm and print the fitted parameters, RMSE and time.
    Fit(FitArgs),
    /// Write a synthetic instance to CSV (a named instance or parameters given as flags).
    Gen(GenArgs),
    /// Print the RMSE of given parameters on a data set.
    Eval(EvalArgs),
    /// Summarise a data set: count, value range, angle coverage, what the filters dropped.
    Info(InfoArgs),
    /// Render a BRDF on a flat square lit by a point light to a PNG (the paper's Figures 8, 12).
    Render(RenderArgs),
    /// Polar plots of measured data and fitted models in the plane of incidence (Figure 18).
    Polar(PolarArgs),
}

#[derive(Clone, Copy, ValueEnum)]
enum ProgressArg {
    /// Bars on a terminal (unless CI=true), plain lines otherwise.
    Auto,
    /// Always bars.
    Bars,
    /// Occasional plain lines.
    Plain,
    /// No progress output.
    Quiet,
}

impl From<ProgressArg> for ProgressMode {
    fn from(p: ProgressArg) -> Self {
        match p {
            ProgressArg::Auto => ProgressMode::Auto,
            ProgressArg::Bars => ProgressMode::Bars,
            ProgressArg::Plain => ProgressMode::Plain,
            ProgressArg::Quiet => ProgressMode::Quiet,
        }
    }
}

#[derive(Args)]
struct RunArgs {
    /// Experiment spec (TOML). Omit to run the built-in default experiment.
    spec: Option<PathBuf>,
    /// Output directory (default: results/<spec file stem>/).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Worker threads (default: the spec's `threads`, else all CPUs).
    #[arg(long)]
    threads: Option<usize>,
    /// Move an existing results file aside (renamed, never deleted) and start over.
    #[arg(long)]
    fresh: bool,
    /// Run at most N new trials, then stop (resume later by running again).
    #[arg(long, value_name = "N")]
    limit: Option<usize>,
    /// Skip the plots (statistics are still written).
    #[arg(long)]
    no_plots: bool,
    /// Progress display.
    #[arg(long, value_enum, default_value = "auto")]
    progress: ProgressArg,
}

#[derive(Args)]
struct CheckArgs {
    /// Experiment spec (TOML).
    spec: PathBuf,
    /// Threads to estimate wall time for (default: the spec's, else all CPUs).
    #[arg(long)]
    threads: Option<usize>,
}

#[derive(Args)]
struct ResultsArgs {
    /// A spec (TOML; results read from --out or results/<stem>/), a results directory, or a
    /// trials.jsonl file (the spec stored in its header is used). Default: results/default/.
    target: Option<PathBuf>,
    /// Results directory when TARGET is a spec.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Where a data set comes from and how it is filtered.
#[derive(Args, Clone)]
struct DataArgs {
    /// Data file: Cornell .brdf, CSV, or MERL binary.
    data: PathBuf,
    /// File format (default: from the extension).
    #[arg(long, value_enum)]
    format: Option<FormatArg>,
    /// Cornell wavelength in nm.
    #[arg(long, default_value_t = brdf_model::DEFAULT_WAVELENGTH_NM)]
    wavelength: f64,
    /// MERL channel.
    #[arg(long, value_enum, default_value = "green")]
    channel: ChannelArg,
    /// Drop values above this (the paper used 1 for the Cornell paint).
    #[arg(long)]
    max_value: Option<f64>,
    /// Keep negative values.
    #[arg(long)]
    keep_negative: bool,
    /// Keep samples with a direction below the horizon.
    #[arg(long)]
    keep_below_horizon: bool,
}

#[derive(Clone, Copy, ValueEnum)]
enum FormatArg {
    Cornell,
    Csv,
    Merl,
}

#[derive(Clone, Copy, ValueEnum)]
enum ChannelArg {
    Red,
    Green,
    Blue,
}

impl DataArgs {
    fn file_spec(&self) -> FileSpec {
        FileSpec {
            path: self.data.clone(),
            format: self.format.map(|f| match f {
                FormatArg::Cornell => DataFormat::Cornell,
                FormatArg::Csv => DataFormat::Csv,
                FormatArg::Merl => DataFormat::Merl,
            }),
            wavelength: Some(self.wavelength),
            channel: Some(match self.channel {
                ChannelArg::Red => brdf_model::Channel::Red,
                ChannelArg::Green => brdf_model::Channel::Green,
                ChannelArg::Blue => brdf_model::Channel::Blue,
            }),
            max_value: self.max_value,
            drop_negative: !self.keep_negative,
            drop_below_horizon: !self.keep_below_horizon,
        }
    }

    /// Loads the data set, refusing one that the filters left empty, and reports on stderr
    /// how many samples were kept.
    fn load_non_empty(&self) -> Result<(DataSet, brdf_model::FilterReport)> {
        let (data, rep) = self.load()?;
        if data.is_empty() {
            bail!(
                "{}: no samples left after filtering ({rep})",
                self.data.display()
            );
        }
        eprintln!("{}: {} samples ({rep})", self.data.display(), data.len());
        Ok((data, rep))
    }

    fn load(&self) -> Result<(DataSet, brdf_model::FilterReport)> {
        let fs = self.file_spec();
        if fs.format.is_none() && DataFormat::from_path(&self.data).is_none() {
            bail!(
                "{}: cannot tell the format from the extension; pass --format cornell|csv|merl",
                self.data.display()
            );
        }
        let (data, rep) = harness::instance::load_file(&fs, &self.data)
            .with_context(|| format!("reading {}", self.data.display()))?;
        if rep.negative > 0 {
            // Noisy synthetic data (brdf-sls gen --sigma) legitimately has negative values.
            eprintln!(
                "note: {} negative values dropped; pass --keep-negative to keep them (noisy synthetic data)",
                rep.negative
            );
        }
        Ok((data, rep))
    }
}

/// The model to fit.
#[derive(Args, Clone)]
struct ModelArgs {
    /// Number of lobes.
    #[arg(long, default_value_t = 1)]
    lobes: usize,
    /// Lobe kind.
    #[arg(long, value_enum, default_value = "anisotropic")]
    kind: KindArg,
    /// Hold a parameter fixed: NAME=VALUE (e.g. lobe1.pan=45); repeatable.
    #[arg(long = "fix", value_name = "NAME=VALUE")]
    fixed: Vec<String>,
    /// Exponent coordinate of the optimiser.
    #[arg(long, value_enum, default_value = "log1p")]
    exponent: ExponentArg,
}

#[derive(Clone, Copy, ValueEnum)]
enum KindArg {
    Anisotropic,
    Isotropic,
}

#[derive(Clone, Copy, ValueEnum)]
enum ExponentArg {
    Log1p,
    Raw,
}

impl ModelArgs {
    fn spec(&self) -> Result<ModelSpec> {
        let kind = match self.kind {
            KindArg::Anisotropic => LobeKind::Anisotropic,
            KindArg::Isotropic => LobeKind::Isotropic,
        };
        let mut m = ModelSpec::simple(self.lobes, kind);
        m.exponent = match self.exponent {
            ExponentArg::Log1p => brdf_model::ExponentCoord::Log1p,
            ExponentArg::Raw => brdf_model::ExponentCoord::Raw,
        };
        for f in &self.fixed {
            let (k, v) = f
                .split_once('=')
                .with_context(|| format!("--fix `{f}`: expected NAME=VALUE"))?;
            let v: f64 = v
                .trim()
                .parse()
                .with_context(|| format!("--fix `{f}`: `{v}` is not a number"))?;
            m.fixed.insert(k.trim().to_string(), v);
        }
        Ok(m)
    }
}

#[derive(Args)]
struct FitArgs {
    #[command(flatten)]
    data: DataArgs,
    #[command(flatten)]
    model: ModelArgs,
    /// Algorithm kind: aed, aers, rpls, ds, sa, sals, avg, asa.
    #[arg(long, default_value = "aed")]
    algorithm: String,
    /// Algorithm parameter NAME=VALUE (TOML value, e.g. phi=1.2); repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    set: Vec<String>,
    /// Stop when the RMSE reaches this (default 0: use the whole budget).
    #[arg(long, default_value_t = 0.0)]
    target: f64,
    /// CPU-time budget in seconds.
    #[arg(long, default_value_t = 10.0)]
    cpu_seconds: f64,
    /// Seed of the run.
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

/// Parameters: a named set or flags.
#[derive(Args, Clone)]
struct ParamArgs {
    /// Named parameters (tuning, cross, paper-bluepaint, pbrt-bluepaint) or JSON
    /// {"kd":0.15,"lobes":[{"cx":-1,"cy":0.8,"cz":0.96,"n":20,"pan_deg":45}]}.
    #[arg(long)]
    params: Option<String>,
    /// Diffuse term kd (with --lobe, instead of --params).
    #[arg(long)]
    kd: Option<f64>,
    /// A lobe CX,CY,CZ,N[,PAN_DEG]; repeatable.
    #[arg(
        long = "lobe",
        value_name = "CX,CY,CZ,N[,PAN]",
        allow_hyphen_values = true
    )]
    lobes: Vec<String>,
}

impl ParamArgs {
    fn params(&self) -> Result<BrdfParams> {
        if let Some(p) = &self.params {
            if self.kd.is_some() || !self.lobes.is_empty() {
                bail!("give either --params or --kd/--lobe, not both");
            }
            if let Some(n) = brdf_model::named_params(p) {
                return Ok(n);
            }
            return serde_json::from_str(p).with_context(|| {
                format!(
                    "--params `{p}`: not a known name ({}) nor JSON parameters",
                    brdf_model::NAMED_PARAMS.join(", ")
                )
            });
        }
        let Some(kd) = self.kd else {
            bail!("give --params NAME|JSON, or --kd and --lobe");
        };
        let mut lobes = Vec::new();
        for l in &self.lobes {
            let v: Vec<f64> = l
                .split(',')
                .map(|s| s.trim().parse::<f64>())
                .collect::<Result<_, _>>()
                .with_context(|| format!("--lobe `{l}`: expected numbers CX,CY,CZ,N[,PAN]"))?;
            if !(v.len() == 4 || v.len() == 5) {
                bail!(
                    "--lobe `{l}`: expected 4 or 5 numbers CX,CY,CZ,N[,PAN], found {}",
                    v.len()
                );
            }
            lobes.push(Lobe {
                cx: v[0],
                cy: v[1],
                cz: v[2],
                n: v[3],
                pan_deg: v.get(4).copied().unwrap_or(0.0),
            });
        }
        Ok(BrdfParams { kd, lobes })
    }
}

#[derive(Args)]
struct GenArgs {
    #[command(flatten)]
    params: ParamArgs,
    /// Number of samples.
    #[arg(long, default_value_t = 10_000)]
    samples: usize,
    /// Gaussian noise standard deviation.
    #[arg(long, default_value_t = 0.0)]
    sigma: f64,
    /// Instance seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Output CSV file (default: standard output).
    #[arg(long, short)]
    out: Option<PathBuf>,
}

#[derive(Args)]
struct EvalArgs {
    #[command(flatten)]
    data: DataArgs,
    #[command(flatten)]
    params: ParamArgs,
}

#[derive(Args)]
struct InfoArgs {
    #[command(flatten)]
    data: DataArgs,
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(a) => cmd_run(a),
        Command::Check(a) => cmd_check(a),
        Command::Plot(a) => cmd_results(a, true),
        Command::Stats(a) => cmd_results(a, false),
        Command::Fit(a) => cmd_fit(a),
        Command::Gen(a) => cmd_gen(a),
        Command::Eval(a) => cmd_eval(a),
        Command::Info(a) => cmd_info(a),
        Command::Render(a) => cmd_render(a),
        Command::Polar(a) => cmd_polar(a),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

fn load_spec(path: &Path) -> Result<Spec> {
    Ok(Spec::from_file(path)?)
}

fn default_out(spec: Option<&Path>) -> PathBuf {
    let stem = spec
        .and_then(|p| p.file_stem())
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "default".into());
    PathBuf::from("results").join(stem)
}

/// The repository's results are committed as `trials.jsonl.gz`; reading or resuming them
/// needs the plain file, and starting a new `trials.jsonl` beside the packed one would leave
/// two disagreeing copies.
fn refuse_packed_results(dir: &Path) -> Result<()> {
    let plain = dir.join("trials.jsonl");
    let packed = dir.join("trials.jsonl.gz");
    if !plain.exists() && packed.exists() {
        bail!(
            "{} holds packed results: unpack them with `gunzip -k {}` to re-plot or resume \
             (or pass --fresh to `run` to start over beside them)",
            dir.display(),
            packed.display()
        );
    }
    Ok(())
}

fn cmd_run(a: RunArgs) -> Result<()> {
    let spec = match &a.spec {
        Some(p) => load_spec(p)?,
        None => Spec::default_experiment(),
    };
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| default_out(a.spec.as_deref()));
    if !a.fresh {
        refuse_packed_results(&out)?;
    }
    let threads = a.threads.or(spec.threads).unwrap_or_else(default_threads);
    if threads == 0 {
        bail!("--threads must be at least 1");
    }
    eprint!("{}", spec.describe(threads));
    eprintln!("results: {}", out.display());
    let machine = harness::machine::MachineInfo::current(threads);
    eprintln!(
        "machine: {}, {} logical CPUs, {} worker thread(s)",
        machine.cpu_model, machine.logical_cpus, threads
    );
    let (executor, built) = SlsExecutor::new(&spec).context("building the instances")?;
    for (i, b) in spec.instances.iter().zip(&built) {
        let rep = b
            .filter_report
            .map(|r| format!(" ({r})"))
            .unwrap_or_default();
        eprintln!("instance {}: {} samples{rep}", i.name, b.data.len());
    }
    let options = RunOptions {
        threads,
        fresh: a.fresh,
        progress: a.progress.into(),
        limit: a.limit,
    };
    let outcome = run_experiment(&spec, &out, &options, &executor)
        .with_context(|| format!("running experiment `{}`", spec.name))?;
    for n in &outcome.notes {
        eprintln!("note: {n}");
    }
    eprintln!(
        "{} new trials in {} wall on {} thread(s) ({} resumed){}",
        outcome.new_trials,
        harness::spec::human_seconds(outcome.wall_seconds),
        threads,
        outcome.resumed,
        if outcome.missing > 0 {
            format!(
                "; {} trials still to run (run again to resume)",
                outcome.missing
            )
        } else {
            String::new()
        }
    );
    let contents = read_results(&out).context("reading back the results")?;
    let report = harness::report::write_report(
        &spec,
        &outcome.records,
        &contents.sessions,
        &out,
        !a.no_plots,
    )
    .context("writing statistics and plots")?;
    println!("{}", report.table);
    println!(
        "wrote {} files to {} (statistics: stats.csv, tests.csv; plots: plots/)",
        report.files.len(),
        out.display()
    );
    Ok(())
}

fn cmd_check(a: CheckArgs) -> Result<()> {
    let spec = load_spec(&a.spec)?;
    let threads = a.threads.or(spec.threads).unwrap_or_else(default_threads);
    print!("{}", spec.describe(threads));
    for i in &spec.instances {
        if let harness::spec::Source::File { resolved, .. } = &i.source
            && !resolved.exists()
        {
            bail!(
                "instance `{}`: data file {} does not exist",
                i.name,
                resolved.display()
            );
        }
    }
    println!("fingerprint {}", spec.fingerprint());
    println!(
        "default results directory: {}",
        default_out(Some(&a.spec)).display()
    );
    Ok(())
}

fn cmd_results(a: ResultsArgs, plots: bool) -> Result<()> {
    let target = a.target.clone().unwrap_or_else(|| default_out(None));
    let is_spec = target.extension().is_some_and(|e| e == "toml");
    let (spec, dir) = if is_spec {
        let spec = load_spec(&target)?;
        let dir = a.out.clone().unwrap_or_else(|| default_out(Some(&target)));
        (Some(spec), dir)
    } else {
        let dir = if target.is_dir() {
            target.clone()
        } else {
            target.parent().map(Path::to_path_buf).unwrap_or_default()
        };
        (None, dir)
    };
    refuse_packed_results(&dir)?;
    let contents =
        read_results(&dir).with_context(|| format!("reading results in {}", dir.display()))?;
    let spec = match spec {
        Some(s) => {
            if s.fingerprint() != contents.header.fingerprint {
                bail!(
                    "{} was written by a different spec (fingerprint {} vs {}): pass the spec that produced it, or the results directory alone",
                    dir.display(),
                    contents.header.fingerprint,
                    s.fingerprint()
                );
            }
            s
        }
        None => {
            if contents.header.spec_text.is_empty() {
                bail!(
                    "{}: the header holds no spec text; pass the spec file",
                    dir.display()
                );
            }
            Spec::parse(
                &contents.header.spec_text,
                &format!("{} (stored spec)", dir.display()),
                &contents.header.experiment,
                &dir,
            )?
        }
    };
    if let Some(t) = &contents.torn {
        eprintln!("note: ignoring a torn last line ({} bytes)", t.len());
    }
    let planned = spec.trials_plan().len();
    let present = harness::report::plan_records(&spec, &contents.records).len();
    if present < planned {
        eprintln!("note: partial results: {present} of {planned} trials present");
    }
    let report =
        harness::report::write_report(&spec, &contents.records, &contents.sessions, &dir, plots)?;
    println!("{}", report.table);
    println!("wrote {} files to {}", report.files.len(), dir.display());
    Ok(())
}

fn cmd_fit(a: FitArgs) -> Result<()> {
    let (data, _) = a.data.load_non_empty()?;
    let model = a.model.spec()?;
    let layout = model.layout().context("model")?;
    let mut table = toml::Table::new();
    table.insert("kind".into(), toml::Value::String(a.algorithm.clone()));
    for s in &a.set {
        let (k, v) = s
            .split_once('=')
            .with_context(|| format!("--set `{s}`: expected NAME=VALUE"))?;
        let doc: toml::Table = toml::from_str(&format!("v = {}", v.trim()))
            .or_else(|_| toml::from_str(&format!("v = \"{}\"", v.trim())))
            .with_context(|| format!("--set `{s}`: bad value"))?;
        if let Some(v) = doc.get("v") {
            table.insert(k.trim().to_string(), v.clone());
        }
    }
    let algorithm: sls::AlgorithmConfig = toml::Value::Table(table)
        .try_into()
        .map_err(|e: toml::de::Error| anyhow::anyhow!("algorithm: {}", e.message()))?;
    algorithm.validate()?;
    let data = Arc::new(data);
    let objective = sls::BrdfObjective::new(data.clone(), layout.clone());
    let budget = sls::Budget {
        cpu_seconds: Some(a.cpu_seconds),
        sample_evaluations: None,
    };
    let r = sls::run_trial(&objective, &algorithm, a.seed, budget, a.target);
    if r.best_x.is_empty() {
        bail!("the run evaluated no candidate (stop: {:?})", r.stop);
    }
    let params = layout.decode(&r.best_x);
    let mut ev = Evaluator::new(&layout);
    let rmse = ev.rmse(&r.best_x, &data);
    println!(
        "algorithm {} (seed {}), stop: {:?}",
        algorithm.kind_name(),
        a.seed,
        r.stop
    );
    println!(
        "RMSE {rmse:.6} after {:.4} CPU s ({:.4} wall s, {} sample-evaluations)",
        r.ended_at.cpu_seconds,
        r.ended_at.wall_seconds,
        r.ended_at.evaluations.total()
    );
    if let Some(at) = r.reached_at {
        println!("target {} reached at {:.4} CPU s", a.target, at.cpu_seconds);
    }
    println!("fitted parameters:");
    for name in layout.all_names() {
        let v = params.get(name).unwrap_or(f64::NAN);
        let tag = if layout.fixed_value(name).is_some() {
            " (fixed)"
        } else {
            ""
        };
        println!("  {name:<10} {v:>12.6}{tag}");
    }
    println!("json: {}", serde_json::to_string(&params)?);
    Ok(())
}

fn cmd_gen(a: GenArgs) -> Result<()> {
    let params = a.params.params()?;
    if !(a.sigma.is_finite() && a.sigma >= 0.0) {
        bail!("--sigma must be >= 0");
    }
    let data = brdf_model::synthetic(&params, a.samples, a.sigma, a.seed);
    match &a.out {
        Some(p) => {
            let mut buf = Vec::new();
            data.write_csv(&mut buf)?;
            harness::store::write_atomic(p, &buf)
                .with_context(|| format!("writing {}", p.display()))?;
            eprintln!("wrote {} samples to {}", data.len(), p.display());
        }
        None => {
            let stdout = std::io::stdout();
            data.write_csv(std::io::BufWriter::new(stdout.lock()))?;
        }
    }
    Ok(())
}

fn cmd_eval(a: EvalArgs) -> Result<()> {
    let params = a.params.params()?;
    let (data, _) = a.data.load_non_empty()?;
    println!("RMSE {:.6}", params_rmse(&params, &data)?);
    Ok(())
}

/// RMSE of `params` on `data`, through the evaluator with a layout of as many anisotropic
/// lobes as `params` has (an isotropic lobe is the anisotropic one with `cx = cy`, pan 0).
fn params_rmse(params: &BrdfParams, data: &DataSet) -> Result<f64> {
    let kinds: Vec<LobeKind> = vec![LobeKind::Anisotropic; params.lobes.len()];
    let layout = brdf_model::Layout::builder(&kinds).build()?;
    let x = layout.encode(params);
    Ok(Evaluator::new(&layout).rmse(&x, data))
}

fn cmd_info(a: InfoArgs) -> Result<()> {
    let (data, rep) = a.data.load()?;
    println!("{}", a.data.data.display());
    println!("samples: {}", data.len());
    println!("filters: {rep}");
    if data.is_empty() {
        return Ok(());
    }
    let n = data.len();
    let mut vals: Vec<f64> = (0..n).map(|i| data.value(i)).collect();
    vals.sort_by(f64::total_cmp);
    let mean = vals.iter().sum::<f64>() / n as f64;
    println!(
        "value: min {:.6}, median {:.6}, mean {:.6}, max {:.6}",
        vals[0],
        vals[n / 2],
        mean,
        vals[n - 1]
    );
    let angles = |d: [f64; 3]| {
        let theta = d[2].clamp(-1.0, 1.0).acos().to_degrees();
        let phi = d[1].atan2(d[0]).to_degrees();
        (theta, phi)
    };
    for (name, which) in [("incident", 0), ("exitant", 1)] {
        let mut tmin = f64::INFINITY;
        let mut tmax = f64::NEG_INFINITY;
        let mut pmin = f64::INFINITY;
        let mut pmax = f64::NEG_INFINITY;
        let mut bins = [0usize; 9];
        for i in 0..n {
            let d = if which == 0 { data.u(i) } else { data.v(i) };
            let (t, p) = angles(d);
            tmin = tmin.min(t);
            tmax = tmax.max(t);
            pmin = pmin.min(p);
            pmax = pmax.max(p);
            bins[((t / 10.0) as usize).min(8)] += 1;
        }
        println!(
            "{name}: theta {tmin:.1}..{tmax:.1} deg, phi {pmin:.1}..{pmax:.1} deg; theta histogram (10-degree bins): {bins:?}"
        );
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// `render` and `polar`: the paper's Figures 8, 12 (renderings) and 18 (polar plots).
// ---------------------------------------------------------------------------------------------

/// Three comma-separated numbers (a point or a colour) as a command-line value.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Triple([f64; 3]);

impl std::str::FromStr for Triple {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let parts: Vec<&str> = s.split(',').collect();
        let expected = || format!("expected three comma-separated numbers X,Y,Z, got `{s}`");
        if parts.len() != 3 {
            return Err(expected());
        }
        let mut v = [0.0; 3];
        for (slot, p) in v.iter_mut().zip(&parts) {
            *slot = p.trim().parse::<f64>().map_err(|_| expected())?;
        }
        Ok(Triple(v))
    }
}

impl std::fmt::Display for Triple {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{},{},{}", self.0[0], self.0[1], self.0[2])
    }
}

#[derive(Clone, Copy, ValueEnum)]
enum ToneMapArg {
    /// min(x, 1): linear up to white, brighter values clip.
    Clamp,
    /// x / (1 + x): never saturates, compresses highlights.
    Reinhard,
}

/// Arguments of `brdf-sls render`. Defaults are those of `harness::render::RenderOptions`
/// (a view chosen to show the anisotropic highlights of the `tuning` and `cross` BRDFs).
#[derive(Args)]
struct RenderArgs {
    #[command(flatten)]
    params: ParamArgs,
    /// Output PNG file (parent directories are created).
    #[arg(long, short, default_value = "render.png")]
    out: PathBuf,
    /// Image width in pixels.
    #[arg(long, default_value_t = harness::render::RenderOptions::default().width)]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = harness::render::RenderOptions::default().height)]
    height: u32,
    /// Supersamples per pixel along each axis (S*S per pixel), 1 to 16.
    #[arg(long, value_name = "S", default_value_t = harness::render::RenderOptions::default().supersampling)]
    supersampling: u32,
    /// Point light position X,Y,Z. The surface is the square |x|, |y| <= --half-size in the
    /// z = 0 plane (normal +z, the BRDF's x axis along world x); the light must have Z > 0.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true,
          default_value_t = Triple(harness::render::RenderOptions::default().light))]
    light: Triple,
    /// Light intensity (>= 0; the image scales linearly with it).
    #[arg(long, allow_hyphen_values = true,
          default_value_t = harness::render::RenderOptions::default().intensity)]
    intensity: f64,
    /// Camera (pinhole) position X,Y,Z, above the surface (Z > 0).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true,
          default_value_t = Triple(harness::render::RenderOptions::default().camera))]
    camera: Triple,
    /// Point the camera looks at.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true,
          default_value_t = Triple(harness::render::RenderOptions::default().look_at))]
    look_at: Triple,
    /// Vertical field of view in degrees, in (0, 180).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true,
          default_value_t = harness::render::RenderOptions::default().fov_deg)]
    fov: f64,
    /// Half the side of the square surface (> 0).
    #[arg(long, allow_hyphen_values = true,
          default_value_t = harness::render::RenderOptions::default().plane_half_size)]
    half_size: f64,
    /// Multiplier of the linear radiance before tone mapping (> 0).
    #[arg(long, allow_hyphen_values = true,
          default_value_t = harness::render::RenderOptions::default().exposure)]
    exposure: f64,
    /// Tone mapping.
    #[arg(long, value_enum, default_value = "clamp")]
    tone_map: ToneMapArg,
    /// Surface colour R,G,B (linear, multiplies the radiance; each >= 0).
    #[arg(long, value_name = "R,G,B", allow_hyphen_values = true,
          default_value_t = Triple(harness::render::RenderOptions::default().tint))]
    tint: Triple,
}

impl RenderArgs {
    fn options(&self) -> harness::render::RenderOptions {
        harness::render::RenderOptions {
            width: self.width,
            height: self.height,
            supersampling: self.supersampling,
            camera: self.camera.0,
            look_at: self.look_at.0,
            fov_deg: self.fov,
            light: self.light.0,
            intensity: self.intensity,
            plane_half_size: self.half_size,
            exposure: self.exposure,
            tone_map: match self.tone_map {
                ToneMapArg::Clamp => harness::render::ToneMap::Clamp,
                ToneMapArg::Reinhard => harness::render::ToneMap::Reinhard,
            },
            tint: self.tint.0,
            ..harness::render::RenderOptions::default()
        }
    }
}

/// Turns a renderer error into one naming the command-line flag: the library's messages name
/// the `RenderOptions` field they are about, first.
fn render_error(e: harness::render::RenderError) -> anyhow::Error {
    use harness::render::RenderError;
    const FLAGS: [(&str, &str); 11] = [
        ("width", "--width/--height"),
        ("supersampling", "--supersampling"),
        ("camera", "--camera"),
        ("light", "--light"),
        ("look_at", "--look-at"),
        ("fov_deg", "--fov"),
        ("intensity", "--intensity"),
        ("plane_half_size", "--half-size"),
        ("exposure", "--exposure"),
        ("tint", "--tint"),
        ("degenerate camera", "--camera/--look-at"),
    ];
    match e {
        RenderError::InvalidOption(m) => match FLAGS.iter().find(|(k, _)| m.starts_with(k)) {
            Some((_, flag)) => anyhow::anyhow!("{flag}: {m}"),
            None => anyhow::anyhow!("invalid render option: {m}"),
        },
        other => other.into(),
    }
}

fn cmd_render(a: RenderArgs) -> Result<()> {
    let params = a.params.params()?;
    if !a
        .out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        bail!(
            "--out {}: the renderer writes PNG; give a file name ending in .png",
            a.out.display()
        );
    }
    // render_png validates the options (render_radiance does) before drawing anything.
    let opts = a.options();
    let img = harness::render::render_png(&params, &opts, &a.out).map_err(render_error)?;
    // Exposure diagnostics: how much of the surface is burnt out (clamp) helps choose
    // --exposure/--intensity without guessing.
    let gain = opts.exposure * opts.tint.iter().copied().fold(0.0, f64::max);
    let on_surface = || (0..img.radiance.len()).filter(|&i| img.coverage[i] > 0.0);
    let covered = on_surface().count();
    let clipped = on_surface()
        .filter(|&i| img.radiance[i] * gain >= 1.0)
        .count();
    let (_, _, peak) = img.brightest();
    let clip_note = match opts.tone_map {
        harness::render::ToneMap::Clamp if covered > 0 => format!(
            "; {:.1}% of the surface clipped at white",
            100.0 * clipped as f64 / covered as f64
        ),
        _ => String::new(),
    };
    println!(
        "wrote {} ({}x{}): peak radiance {peak:.4}, x exposure {} = {:.4}{clip_note}",
        a.out.display(),
        img.width,
        img.height,
        opts.exposure,
        peak * opts.exposure,
    );
    Ok(())
}

#[derive(Clone, Copy, PartialEq, ValueEnum)]
enum ImageFormatArg {
    Png,
    Svg,
}

/// Arguments of `brdf-sls polar`.
#[derive(Args)]
struct PolarArgs {
    #[command(flatten)]
    data: DataArgs,
    /// A model to overlay: LABEL=PARAMS, PARAMS a name (tuning, cross, paper-bluepaint,
    /// pbrt-bluepaint), JSON as printed on the `json:` line of `brdf-sls fit`, or @FILE holding
    /// such JSON; repeatable. Without `LABEL=` the name (or "fit N") labels it.
    #[arg(long = "fit", value_name = "LABEL=PARAMS")]
    fits: Vec<String>,
    /// Also overlay the best trial (lowest RMSE) of --config from the results of `brdf-sls run`
    /// (a results directory or its trials.jsonl).
    #[arg(long, value_name = "DIR", requires = "config")]
    from_results: Option<PathBuf>,
    /// Configuration label for --from-results, e.g. "AED phi=1.2".
    #[arg(long, value_name = "LABEL", requires = "from_results")]
    config: Option<String>,
    /// Instance for --from-results (default: the experiment's only instance).
    #[arg(long, value_name = "NAME", requires = "from_results")]
    instance: Option<String>,
    /// Incident angles in degrees, one panel each, e.g. 10,40,70 (default: three spread over
    /// the angles the data has in-plane samples at, avoiding grazing angles).
    #[arg(
        long,
        value_name = "DEG,...",
        value_delimiter = ',',
        allow_hyphen_values = true
    )]
    incident: Vec<f64>,
    /// Output base: writes BASE.png and/or BASE.svg (an extension of BASE is replaced).
    #[arg(long, short, value_name = "BASE", default_value = "polar")]
    out: PathBuf,
    /// Formats to write, comma-separated.
    #[arg(long, value_enum, value_delimiter = ',', default_values = ["png", "svg"])]
    formats: Vec<ImageFormatArg>,
    /// Radius of each panel (linear in the BRDF value): `auto` (everything drawn fits),
    /// `measured:K` (K times the panel's largest measured value; model curves beyond it are
    /// cut at the rim) or a number (a fixed radius).
    #[arg(long, default_value = "auto")]
    radius: String,
    /// Use one radius for all panels (the largest) instead of one per panel.
    #[arg(long)]
    shared_radius: bool,
    /// Title (default: the data file, wavelength and filter).
    #[arg(long)]
    title: Option<String>,
    /// Legend text of the measured data (default: "measured (FILE NAME)").
    #[arg(long)]
    data_label: Option<String>,
    /// Also show the samples --max-value drops (hollow circles; values beyond the rim sit on it
    /// with their value printed), to see what the fits never saw.
    #[arg(long, requires = "max_value")]
    show_dropped: bool,
    /// Azimuth of the plane of incidence in degrees (0 for Cornell data).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true,
          default_value_t = harness::polar::SliceSelection::default().phi_i_deg)]
    phi_i: f64,
    /// Largest angle in degrees between a sample's incident direction and a panel's.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true,
          default_value_t = harness::polar::SliceSelection::default().incident_tol_deg)]
    incident_tol: f64,
    /// Largest angle in degrees between a sample's exitant direction and the plane.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true,
          default_value_t = harness::polar::SliceSelection::default().plane_tol_deg)]
    plane_tol: f64,
}

/// Curve colours in order: red and black first, as the paper's Figure 18 (measured data is
/// blue), then colours that stay apart from those.
const CURVE_COLORS: [(u8, u8, u8); 6] = [
    (214, 39, 40),
    (0, 0, 0),
    (44, 160, 44),
    (255, 127, 14),
    (148, 103, 189),
    (140, 86, 75),
];

fn parse_radius(s: &str) -> Result<harness::polar::RadiusScale> {
    use harness::polar::RadiusScale;
    let bad = || {
        anyhow::anyhow!(
            "--radius `{s}`: expected `auto`, `measured:K` (K > 0) or a positive number"
        )
    };
    let positive = |t: &str| {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && *v > 0.0)
    };
    let s = s.trim();
    if s.eq_ignore_ascii_case("auto") {
        Ok(RadiusScale::Auto)
    } else if let Some(k) = s.strip_prefix("measured:") {
        positive(k).map(RadiusScale::Measured).ok_or_else(bad)
    } else {
        positive(s).map(RadiusScale::Fixed).ok_or_else(bad)
    }
}

/// Parses one `--fit LABEL=PARAMS` (the label is optional; `index` numbers unlabelled JSON).
fn parse_fit(s: &str, index: usize) -> Result<(String, BrdfParams)> {
    // JSON holds no `=` before its `{`, a label no `{`: split at an `=` before any brace.
    let (label, p) = match s.split_once('=') {
        Some((l, p)) if !l.contains('{') => (l.trim().to_string(), p.trim()),
        _ => (String::new(), s.trim()),
    };
    let params = if let Some(n) = brdf_model::named_params(p) {
        n
    } else if let Some(file) = p.strip_prefix('@') {
        let text = std::fs::read_to_string(file)
            .with_context(|| format!("--fit `{s}`: reading parameters from {file}"))?;
        serde_json::from_str::<BrdfParams>(text.trim()).with_context(|| {
            format!(
                "--fit `{s}`: {file} does not hold JSON parameters as printed by `brdf-sls fit`"
            )
        })?
    } else {
        serde_json::from_str::<BrdfParams>(p).with_context(|| {
            format!(
                "--fit `{s}`: expected LABEL=PARAMS with PARAMS a known name ({}) or JSON \
                 parameters as printed by `brdf-sls fit`",
                brdf_model::NAMED_PARAMS.join(", ")
            )
        })?
    };
    let label = if !label.is_empty() {
        label
    } else if brdf_model::named_params(p).is_some() || p.starts_with('@') {
        p.trim_start_matches('@').to_string()
    } else {
        format!("fit {index}")
    };
    Ok((label, params))
}

/// The best trial (lowest final RMSE) of configuration `config` on `instance` in a results
/// directory (or trials.jsonl), decoded with the instance's model layout from the stored spec.
/// Returns a label for it and the parameters.
fn best_from_results(
    target: &Path,
    config: &str,
    instance: Option<&str>,
) -> Result<(String, BrdfParams)> {
    if !target.exists() {
        bail!(
            "--from-results {}: no such results directory or trials.jsonl file",
            target.display()
        );
    }
    let dir = if target.is_dir() {
        target.to_path_buf()
    } else {
        // A trials.jsonl file: its directory holds the results.
        match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        }
    };
    let contents = read_results(&dir)
        .with_context(|| format!("--from-results: reading results in {}", dir.display()))?;
    if contents.header.spec_text.is_empty() {
        bail!(
            "--from-results {}: the header holds no spec text, so the model layout is unknown",
            dir.display()
        );
    }
    let spec = Spec::parse(
        &contents.header.spec_text,
        &format!("{} (stored spec)", dir.display()),
        &contents.header.experiment,
        &dir,
    )?;
    let names = || {
        spec.instances
            .iter()
            .map(|i| i.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let inst = match instance {
        Some(n) => spec
            .instances
            .iter()
            .find(|i| i.name == n)
            .with_context(|| format!("--instance `{n}`: not in the experiment ({})", names()))?,
        None if spec.instances.len() == 1 => &spec.instances[0],
        None => bail!(
            "--from-results: the experiment has {} instances; choose one with --instance ({})",
            spec.instances.len(),
            names()
        ),
    };
    if !spec.configurations.iter().any(|c| c.label == config) {
        let labels: Vec<&str> = spec
            .configurations
            .iter()
            .map(|c| c.label.as_str())
            .collect();
        bail!(
            "--config `{config}`: not in the experiment (configurations: {})",
            labels.join(", ")
        );
    }
    let best = contents
        .records
        .iter()
        .filter(|r| r.instance == inst.name && r.config == config)
        .filter(|r| r.result.best_rmse.is_finite() && !r.result.best_x.is_empty())
        .min_by(|a, b| a.result.best_rmse.total_cmp(&b.result.best_rmse))
        .with_context(|| {
            format!(
                "--from-results {}: no finished trial of `{config}` on `{}`",
                dir.display(),
                inst.name
            )
        })?;
    let layout = inst
        .model
        .layout()
        .with_context(|| format!("instance `{}`: model", inst.name))?;
    if best.result.best_x.len() != layout.dim() {
        bail!(
            "--from-results: trial {} stores {} parameters, the model of `{}` has {}",
            best.key,
            best.result.best_x.len(),
            inst.name,
            layout.dim()
        );
    }
    let label = format!(
        "{config} best of {} (trial {})",
        contents
            .records
            .iter()
            .filter(|r| r.instance == inst.name && r.config == config)
            .count(),
        best.trial
    );
    Ok((label, layout.decode(&best.result.best_x)))
}

fn cmd_polar(a: PolarArgs) -> Result<()> {
    use harness::polar::{
        PolarCurve, PolarMeasured, PolarPlot, SliceSelection, default_incident_angles, draw_polar,
        incident_angles, select_in_plane,
    };
    use plotters::style::RGBColor;

    for (flag, v, hi) in [
        ("--incident-tol", a.incident_tol, 90.0),
        ("--plane-tol", a.plane_tol, 90.0),
        ("--phi-i", a.phi_i, 360.0),
    ] {
        if !(v.is_finite() && v.abs() <= hi && (flag == "--phi-i" || v >= 0.0)) {
            bail!(
                "{flag} {v}: expected degrees in {}",
                if flag == "--phi-i" {
                    "[-360, 360]"
                } else {
                    "[0, 90]"
                }
            );
        }
    }
    let radius = parse_radius(&a.radius)?;
    let (data, _) = a.data.load_non_empty()?;
    let sel = SliceSelection {
        phi_i_deg: a.phi_i,
        incident_tol_deg: a.incident_tol,
        plane_tol_deg: a.plane_tol,
    };
    let available = incident_angles(&data, &sel);
    let list = |v: &[(f64, usize)]| {
        const SHOWN: usize = 24;
        let mut s: Vec<String> = v.iter().take(SHOWN).map(|a| format!("{}", a.0)).collect();
        if v.len() > SHOWN {
            s.push(format!("... ({} in all)", v.len()));
        }
        if s.is_empty() {
            "none".into()
        } else {
            s.join(", ")
        }
    };
    let incident = if a.incident.is_empty() {
        let d = default_incident_angles(&available, 3);
        if d.is_empty() {
            bail!(
                "{}: no sample has both directions within {} degrees of the plane of incidence \
                 (azimuth {}); widen --plane-tol or give --incident",
                a.data.data.display(),
                sel.plane_tol_deg,
                sel.phi_i_deg
            );
        }
        d
    } else {
        a.incident.clone()
    };
    for &t in &incident {
        if !(t.is_finite() && (0.0..90.0).contains(&t)) {
            bail!("--incident {t}: incident angles must be in [0, 90) degrees");
        }
        if select_in_plane(&data, t, &sel).is_empty() {
            bail!(
                "--incident {t}: {} has no in-plane samples within {} degrees of that incident \
                 angle (and {} degrees of the plane); in-plane incident angles available: {} \
                 (or widen --incident-tol/--plane-tol)",
                a.data.data.display(),
                sel.incident_tol_deg,
                sel.plane_tol_deg,
                list(&available)
            );
        }
    }

    let mut fits = Vec::new();
    for (k, f) in a.fits.iter().enumerate() {
        fits.push(parse_fit(f, k + 1)?);
    }
    if let (Some(dir), Some(config)) = (&a.from_results, &a.config) {
        fits.push(best_from_results(dir, config, a.instance.as_deref())?);
    }
    if fits.len() > CURVE_COLORS.len() {
        bail!(
            "at most {} models per plot (--fit and --from-results), got {}",
            CURVE_COLORS.len(),
            fits.len()
        );
    }
    let mut curves = Vec::new();
    for (k, (label, params)) in fits.into_iter().enumerate() {
        let rmse = params_rmse(&params, &data)?;
        println!(
            "{label}: RMSE {rmse:.6} on {} samples; json: {}",
            data.len(),
            serde_json::to_string(&params)?
        );
        let (r, g, b) = CURVE_COLORS[k];
        curves.push(PolarCurve {
            label: format!("{label} (RMSE {rmse:.4})"),
            params,
            color: RGBColor(r, g, b),
            dashed: false,
        });
    }

    let file_name = a
        .data
        .data
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let is_cornell = match a.data.format {
        Some(f) => matches!(f, FormatArg::Cornell),
        None => DataFormat::from_path(&a.data.data) == Some(DataFormat::Cornell),
    };
    let title = a.title.clone().unwrap_or_else(|| {
        let mut t = file_name.clone();
        if is_cornell {
            t.push_str(&format!(" at {} nm", a.data.wavelength));
        }
        if let Some(m) = a.data.max_value {
            t.push_str(&format!(", values > {m} dropped"));
        }
        t.push_str(": BRDF in the plane of incidence");
        t
    });
    let data_label = a
        .data_label
        .clone()
        .unwrap_or_else(|| format!("measured ({file_name})"));
    // The samples the value cap removed: the same file read without the cap, kept above it.
    let dropped = match (a.show_dropped, a.data.max_value) {
        (true, Some(cap)) => {
            let mut uncapped = a.data.clone();
            uncapped.max_value = None;
            let (raw, _) = uncapped.load()?;
            let mut d = DataSet::new();
            for i in (0..raw.len()).filter(|&i| raw.value(i) > cap) {
                d.push(raw.u(i), raw.v(i), raw.value(i));
            }
            Some((d, format!("dropped (values > {cap})")))
        }
        _ => None,
    };
    const MEASURED_COLOR: RGBColor = RGBColor(31, 119, 180);
    let mut plot = PolarPlot::new(title, incident.clone());
    plot.selection = sel;
    plot.measured = Some(PolarMeasured {
        label: &data_label,
        data: &data,
        color: MEASURED_COLOR,
    });
    plot.dropped = dropped.as_ref().map(|(d, label)| PolarMeasured {
        label,
        data: d,
        color: MEASURED_COLOR,
    });
    plot.curves = curves;
    plot.radius = radius;
    plot.shared_radius = a.shared_radius;
    let mut formats = Vec::new();
    for f in &a.formats {
        let f = match f {
            ImageFormatArg::Png => harness::spec::PlotFormat::Png,
            ImageFormatArg::Svg => harness::spec::PlotFormat::Svg,
        };
        if !formats.contains(&f) {
            formats.push(f);
        }
    }
    for p in harness::polar::polar_panels(&plot) {
        eprintln!(
            "incident {}: {} measured in-plane samples ({} dropped), radius {}",
            p.theta_i_deg,
            p.measured.len(),
            p.dropped.len(),
            harness::plot::tick(p.r_max)
        );
    }
    let files = draw_polar(&plot, &a.out, &formats)?;
    for f in files {
        println!("wrote {}", f.display());
    }
    Ok(())
}
