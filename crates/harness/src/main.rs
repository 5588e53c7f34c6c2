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
tuning instance, AED vs AERS vs RPLS, about a minute on 2 cores) and writes results, \
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

fn cmd_run(a: RunArgs) -> Result<()> {
    let spec = match &a.spec {
        Some(p) => load_spec(p)?,
        None => Spec::default_experiment(),
    };
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| default_out(a.spec.as_deref()));
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
    let (data, rep) = a.data.load()?;
    if data.is_empty() {
        bail!(
            "{}: no samples left after filtering ({rep})",
            a.data.data.display()
        );
    }
    eprintln!("{}: {} samples ({rep})", a.data.data.display(), data.len());
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
    let (data, rep) = a.data.load()?;
    let params = a.params.params()?;
    if data.is_empty() {
        bail!("no samples left after filtering ({rep})");
    }
    let kinds: Vec<LobeKind> = vec![LobeKind::Anisotropic; params.lobes.len()];
    let layout = brdf_model::Layout::builder(&kinds).build()?;
    let x = layout.encode(&params);
    let mut ev = Evaluator::new(&layout);
    let rmse = ev.rmse(&x, &data);
    println!("{} samples ({rep})", data.len());
    println!("RMSE {rmse:.6}");
    Ok(())
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
