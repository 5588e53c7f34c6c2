//! The report page of one or more results folders, answer first: for each folder the summary
//! (best configuration per instance and target, ratios, significance, one sentence per
//! instance), the view across instances (ranking, significance matrix, runtime ECDFs), a short
//! "how to read this", then per instance the tables and charts, and at the end the plan and
//! provenance. A collapsed table of contents reaches every section and chart.

use std::path::{Component, Path, PathBuf};

use super::figures::figure;
use super::summary::{self, Targets};
use super::{PageError, anchor, document, escape, para, provenance, section, tables};
use crate::analysis::{Analysis, NamedChart};
use crate::folder::Folder;
use crate::stats::Measure;

/// The whole report page of `folders` (one section each, in order), each analysed here, for a
/// page written into the first folder.
pub fn report_page(folders: &[Folder]) -> Result<String, PageError> {
    let analyses: Vec<Analysis> = folders.iter().map(Folder::analysis).collect();
    let pairs: Vec<(&Folder, &Analysis)> = folders.iter().zip(&analyses).collect();
    let dir = folders
        .first()
        .map_or_else(PathBuf::new, |f| folder_dir(&f.dir));
    report_page_of(&pairs, &dir)
}

/// The whole report page of folders with their analyses (computed once, e.g. by a run for its
/// files and its page; each needs the charts of [`crate::analysis::ChartSet::Page`]), for a
/// page written into `page_dir` (links to the data files are relative to it).
pub fn report_page_of(
    folders: &[(&Folder, &Analysis)],
    page_dir: &Path,
) -> Result<String, PageError> {
    let names: Vec<String> = folders.iter().map(|(f, _)| f.spec.name.clone()).collect();
    let title = format!("brdf-sls report: {}", names.join(", "));
    let mut toc = Toc::default();
    let mut sections = String::new();
    let several = folders.len() > 1;
    if several {
        toc.add(2, "suite", "Across the folders");
        sections.push_str(&suite_section(folders));
    }
    for (i, (f, a)) in folders.iter().enumerate() {
        sections.push_str(&folder_section(
            f,
            a,
            &format!("r{}", i + 1),
            several,
            page_dir,
            &mut toc,
        )?);
    }
    let mut body = format!("<h1>{}</h1>\n", escape(&title));
    if !several && let Some((f, _)) = folders.first() {
        body.push_str(&lede(f, page_dir));
    }
    body.push_str(&toc.html());
    body.push_str(&sections);
    body.push_str(&para(
        "note",
        &format!("Written by brdf-sls {}.", brdf_experiment::PROGRAM_VERSION),
    ));
    Ok(document(&title, &body))
}

/// For several folders, one summary over all of them in sample-evaluations (a configuration
/// label is one configuration in every folder; each test stays Holm-adjusted within its
/// folder), with its ranking and significance matrix.
fn suite_section(folders: &[(&Folder, &Analysis)]) -> String {
    let mut merged = crate::stats::StatsReport {
        bootstrap: 0,
        configs: Vec::new(),
        tests: Vec::new(),
        finals: Vec::new(),
    };
    let (mut instances, mut labels, mut targets) = (Vec::new(), Vec::new(), Targets::none());
    for (f, a) in folders {
        let prefix = format!("{}/", f.dir.display());
        targets.add(&f.spec, &prefix);
        instances.extend(
            f.spec
                .instances
                .iter()
                .map(|i| format!("{prefix}{}", i.name)),
        );
        for l in f.spec.config_labels() {
            if !labels.contains(&l) {
                labels.push(l);
            }
        }
        merged.configs.extend(a.stats.configs.iter().map(|c| {
            let mut c = c.clone();
            c.instance = format!("{prefix}{}", c.instance);
            c
        }));
        merged.tests.extend(a.stats.tests.iter().map(|t| {
            let mut t = t.clone();
            t.instance = format!("{prefix}{}", t.instance);
            t
        }));
    }
    let sm =
        crate::analysis::summary::summarise(&merged, &instances, &labels, Measure::Evaluations);
    let mut s = summary::how_to_read_tables();
    s.push_str(&summary::table(&sm, &targets, true));
    if sm.configs.len() > 1 {
        s.push_str(&summary::ranking(&sm));
        s.push_str(&summary::matrix(&sm));
    }
    section("suite", 2, "Across the folders", &s)
}

/// The table of contents, filled while the sections are built.
#[derive(Default)]
struct Toc {
    /// (level, id, text) in page order.
    entries: Vec<(u8, String, String)>,
}

impl Toc {
    fn add(&mut self, level: u8, id: &str, text: &str) {
        self.entries.push((level, id.to_string(), text.to_string()));
    }

    /// A collapsed list of links, nested by level.
    fn html(&self) -> String {
        let figures = self.entries.iter().filter(|e| e.0 == 4).count();
        let mut s = format!(
            "<details class=\"toc\">\n<summary>Contents: {} sections, {figures} charts</summary>\n<ul>\n",
            self.entries.len() - figures
        );
        for (level, id, text) in &self.entries {
            s.push_str(&format!(
                "<li class=\"l{level}\"><a href=\"#{}\">{}</a></li>\n",
                escape(id),
                escape(text)
            ));
        }
        s.push_str("</ul>\n</details>\n");
        s
    }
}

/// The folder a results path names (the folder itself, or the folder of a results file).
fn folder_dir(dir: &Path) -> PathBuf {
    if dir.is_file() {
        dir.parent().map_or_else(PathBuf::new, Path::to_path_buf)
    } else {
        dir.to_path_buf()
    }
}

/// `to` relative to `from` (both folders), through their canonical forms; `to` as given when
/// either cannot be resolved.
fn relative(to: &Path, from: &Path) -> PathBuf {
    let base = if from.as_os_str().is_empty() {
        Path::new(".")
    } else {
        from
    };
    let (Ok(to_c), Ok(from_c)) = (to.canonicalize(), base.canonicalize()) else {
        return to.to_path_buf();
    };
    let (t, f): (Vec<Component>, Vec<Component>) =
        (to_c.components().collect(), from_c.components().collect());
    let common = t.iter().zip(&f).take_while(|(a, b)| a == b).count();
    let mut out = PathBuf::new();
    for _ in common..f.len() {
        out.push("..");
    }
    for c in &t[common..] {
        out.push(c.as_os_str());
    }
    out
}

/// Links to the folder's data files that exist, relative to the page.
fn data_links(f: &Folder, page_dir: &Path) -> String {
    let dir = folder_dir(&f.dir);
    let rel = relative(&dir, page_dir);
    let names = [
        "stats.csv",
        "tests.csv",
        "finals.csv",
        "stats.json",
        "summary.json",
        "table.txt",
        "trials.jsonl",
        "trials.jsonl.gz",
        "plots",
    ];
    let links: Vec<String> = names
        .iter()
        .filter(|n| dir.join(n).exists())
        .map(|n| {
            let href = rel.join(n).display().to_string().replace('\\', "/");
            let slash = if *n == "plots" { "/" } else { "" };
            format!("<a href=\"{}{slash}\">{n}{slash}</a>", escape(&href))
        })
        .collect();
    if links.is_empty() {
        String::new()
    } else {
        format!("Data beside this page: {}.", links.join(" &middot; "))
    }
}

/// What the run is, in two lines: description, scope, budget, completeness, data files.
fn lede(f: &Folder, page_dir: &Path) -> String {
    let spec = &f.spec;
    let (present, planned) = f.progress();
    let mut s = String::new();
    if let Some(d) = &spec.description {
        s.push_str(&format!("{}. ", escape(d.trim_end_matches('.'))));
    }
    s.push_str(&format!(
        "{} instance(s) &times; {} configuration(s) &times; {} trials, budget {} per trial; \
         {present} of {planned} trials present. ",
        spec.instances.len(),
        spec.configurations.len(),
        spec.trials,
        escape(&crate::compare::budget_text(&spec.budget)),
    ));
    s.push_str(&data_links(f, page_dir));
    format!("<p class=\"lede\">{s}</p>\n")
}

/// Configurations that run in Python (their CPU seconds include the interpreter).
fn python_configs(f: &Folder) -> Vec<&str> {
    f.spec
        .configurations
        .iter()
        .filter(|c| c.algorithm.kind_name() == brdf_experiment::python_kind::KIND)
        .map(|c| c.label.as_str())
        .collect()
}

/// The caveats of this run, as list items (HTML).
fn caveats(f: &Folder, a: &Analysis) -> Vec<String> {
    let mut out = Vec::new();
    let python = python_configs(f);
    if !python.is_empty() {
        out.push(format!(
            "{} run in Python: their CPU seconds include the interpreter's overhead, so compare \
             them in sample-evaluations.",
            escape(&python.join(", "))
        ));
    }
    let (present, planned) = f.progress();
    if present < planned {
        out.push(format!(
            "Partial results: {present} of {planned} trials; the statistics cover those."
        ));
    }
    let km = a
        .stats
        .configs
        .iter()
        .any(|c| c.cpu.km_censoring || c.evaluations.km_censoring);
    if km {
        out.push(
            "Trials were censored at different times (e.g. cut by the CPU budget at different \
             sample-evaluation counts): the RTDs and quantiles are Kaplan-Meier estimates."
                .into(),
        );
    }
    out.extend(a.warnings.iter().map(|w| escape(w)));
    out
}

/// The summary section: both measures' tables, a sentence per instance, the caveats.
fn summary_section(f: &Folder, a: &Analysis, id: &str) -> String {
    let targets = Targets::new(&f.spec, "");
    let several = f.spec.instances.len() > 1;
    let mut s = String::new();
    s.push_str(&summary::how_to_read_tables());
    for (k, sm) in a.summaries.iter().enumerate() {
        s.push_str(&summary::table(sm, &targets, several));
        if k == 0 {
            s.push_str("<ul class=\"verdicts\">\n");
            for inst in &f.spec.instances {
                let mut line = summary::sentence(sm, &inst.name, &targets);
                if let Some(cpu) = a.summaries.get(1) {
                    line.push_str(&cpu_note(sm, cpu, &inst.name));
                }
                s.push_str(&format!("<li>{line}</li>\n"));
            }
            s.push_str("</ul>\n");
        }
    }
    let caveats = caveats(f, a);
    if !caveats.is_empty() {
        s.push_str("<ul class=\"caveats\">\n");
        for c in caveats {
            s.push_str(&format!("<li>{c}</li>\n"));
        }
        s.push_str("</ul>\n");
    }
    section(
        &format!("{id}-summary"),
        3,
        "Summary: which configuration is best where, by how much, and is it significant",
        &s,
    )
}

/// A remark when the best configurations in CPU seconds differ from those in
/// sample-evaluations on `instance`.
fn cpu_note(
    evals: &crate::analysis::Summary,
    cpu: &crate::analysis::Summary,
    instance: &str,
) -> String {
    let bests = |s: &crate::analysis::Summary| -> Vec<String> {
        let mut v: Vec<String> = Vec::new();
        for r in s.instance_rows(instance) {
            if let Some(b) = r.best
                && !v.contains(&s.configs[b])
            {
                v.push(s.configs[b].clone());
            }
        }
        v
    };
    let (e, c) = (bests(evals), bests(cpu));
    if e == c || c.is_empty() {
        return String::new();
    }
    format!(
        " In CPU seconds the lowest ERT is {}'s.",
        escape(&c.join("'s or "))
    )
}

/// Ranking, significance matrix and (several instances) the runtime ECDFs over all pairs.
/// (Two or more configurations: the caller checks.)
fn across_section(a: &Analysis, id: &str, toc: &mut Toc) -> Result<String, PageError> {
    let Some(sm) = a.summaries.first() else {
        return Ok(String::new());
    };
    let mut s = summary::ranking(sm);
    s.push_str(&summary::matrix(sm));
    for c in a.charts.iter().filter(|c| c.instance.is_none()) {
        s.push_str(&chart(c, id, toc)?);
    }
    let sid = format!("{id}-across");
    Ok(section(
        &sid,
        3,
        "Across instances and targets: ranking and significance",
        &s,
    ))
}

/// A chart as a figure, listed in the table of contents.
fn chart(c: &NamedChart, id: &str, toc: &mut Toc) -> Result<String, PageError> {
    let fid = anchor(&[id, &c.stem]);
    toc.add(4, &fid, &c.chart.title);
    figure(&c.chart, &fid, &c.caption)
}

/// "How to read this page": the measures, ERT, Kaplan-Meier, the interval, the tests.
fn how_to_read(f: &Folder, id: &str) -> String {
    let items = [
        format!(
            "<b>Two measures.</b> {} counts the worker thread's CPU time (it depends on the \
             machine and the kernel); {} counts the rows of data evaluated (residuals, Jacobian \
             rows and whole-data RMSEs, the paper's count), the same on every machine.",
            Measure::CpuSeconds.label(),
            Measure::Evaluations.label()
        ),
        "<b>ERT</b> (expected run time with restarts, COCO's aRT): the time all trials spent, \
         successful ones up to the target and the others up to where they stopped, divided by \
         the successes. A configuration that rarely succeeds has a high ERT even when its \
         successes are quick; none has no ERT."
            .to_string(),
        format!(
            "<b>[10%, 90%]</b>: the 10th and 90th percentiles of the ERT over {} bootstrap \
             resamples of the trials (how much the ERT would move with other trials).",
            f.spec.stats.bootstrap
        ),
        "<b>RTD curves are Kaplan-Meier estimates</b> of the time-to-target distribution: a \
         trial that did not reach the target is <i>censored</i> where it stopped. With one \
         shared cutoff this is the plain ECDF; in sample-evaluations, trials cut by a CPU budget \
         stop at different counts, so a curve can reach 1 although a trial failed. Bands are \
         pointwise 95% (Greenwood)."
            .to_string(),
        "<b>Significance</b>: each pair of configurations gets a log-rank test per target and \
         measure (censored trials at their own censoring times); p-values are Holm-adjusted \
         over the pairs of one target and measure and marked at 0.05. Its <b>hazard ratio</b> \
         (O<sub>A</sub>/E<sub>A</sub>)/(O<sub>B</sub>/E<sub>B</sub>) above 1 means A reaches \
         the target sooner. Mann-Whitney, Kolmogorov-Smirnov and RTD domination are in each \
         instance's collapsed pairwise table."
            .to_string(),
        "<b>Targets</b> read as RMSE (and, where the instance's best-known RMSE is recorded, how \
         far above it: +1% is 1.01 times the best-known)."
            .to_string(),
    ];
    let mut s = String::from("<ul class=\"howto\">\n");
    for i in items {
        s.push_str(&format!("<li>{i}</li>\n"));
    }
    s.push_str("</ul>\n");
    section(&format!("{id}-howto"), 3, "How to read this page", &s)
}

fn folder_section(
    f: &Folder,
    a: &Analysis,
    id: &str,
    several: bool,
    page_dir: &Path,
    toc: &mut Toc,
) -> Result<String, PageError> {
    let mut s = String::new();
    if several {
        s.push_str(&lede(f, page_dir));
    }
    let (present, planned) = f.progress();
    if present < planned {
        let text = format!(
            "Partial results: {present} of {planned} trials present; the statistics and charts \
below cover those only (run the spec again to resume)."
        );
        s.push_str(&para("partial", &text));
    }
    for n in f.notes.iter().filter(|n| !n.starts_with("partial results")) {
        s.push_str(&para("note", &format!("Note: {n}.")));
    }
    let heading = format!("{} ({})", f.spec.name, f.dir.display());
    let prefix = if several {
        toc.add(2, id, &heading);
        format!("{}: ", f.spec.name)
    } else {
        String::new()
    };
    toc.add(3, &format!("{id}-summary"), &format!("{prefix}Summary"));
    s.push_str(&summary_section(f, a, id));
    if a.summaries.first().is_some_and(|sm| sm.configs.len() > 1) {
        let text = format!("{prefix}Across instances and targets");
        toc.add(3, &format!("{id}-across"), &text);
        s.push_str(&across_section(a, id, toc)?);
    }
    toc.add(
        3,
        &format!("{id}-howto"),
        &format!("{prefix}How to read this page"),
    );
    s.push_str(&how_to_read(f, id));
    let records = f.records();
    let report = &a.stats;
    let targets = Targets::new(&f.spec, "");
    for inst in &f.spec.instances {
        let iid = anchor(&[id, "instance", &inst.name]);
        toc.add(3, &iid, &format!("{prefix}Instance {}", inst.name));
        let mut body = best_known_line(inst, &targets);
        body.push_str("<h4>Success, median and ERT</h4>\n");
        body.push_str(&tables::success_table(report, &inst.name, &targets));
        body.push_str("<h4>Charts</h4>\n");
        for c in a
            .charts
            .iter()
            .filter(|c| c.instance.as_deref() == Some(&inst.name))
        {
            body.push_str(&chart(c, id, toc)?);
        }
        let pairs = report
            .tests
            .iter()
            .filter(|t| t.instance == inst.name)
            .count();
        body.push_str(&format!(
            "<details class=\"tests\">\n<summary>Pairwise tests: {pairs} pairs (log-rank with \
             hazard ratio, Mann-Whitney, Kolmogorov-Smirnov, RTD domination; Holm over the pairs \
             of each target and measure)</summary>\n{}</details>\n",
            tables::tests_table(report, &inst.name, &targets)
        ));
        body.push_str("<h4>Final RMSE</h4>\n");
        body.push_str(&tables::finals_table(report, &inst.name));
        body.push_str("<h4>Best fit</h4>\n");
        body.push_str(&tables::best_fit(inst, &records));
        s.push_str(&section(&iid, 3, &format!("Instance {}", inst.name), &body));
    }
    toc.add(
        3,
        &format!("{id}-experiment"),
        &format!("{prefix}Experiment and plan"),
    );
    s.push_str(&experiment(f, id));
    toc.add(
        3,
        &format!("{id}-provenance"),
        &format!("{prefix}Provenance"),
    );
    let about = "<p class=\"tcap\">Where these results come from, as the results file's header \
                 and session lines record it: the program and its commit, kernels, machines, \
                 dates, shard and the hashes of the instances' data; then one row per session \
                 (each start of <code>run</code> on the folder).</p>\n";
    s.push_str(&section(
        &format!("{id}-provenance"),
        3,
        "Provenance",
        &(about.to_string() + &provenance::summary(f) + &provenance::sessions(f)),
    ));
    if several {
        Ok(section(id, 2, &heading, &s))
    } else {
        Ok(format!("<div id=\"{}\">\n{s}</div>\n", escape(id)))
    }
}

/// The description, the plan as `brdf-sls check` prints it, and the spec's text.
fn experiment(f: &Folder, id: &str) -> String {
    let mut s = String::new();
    if let Some(d) = &f.spec.description {
        s.push_str(&para("", d));
    }
    let threads = f.contents.header.machine.threads.max(1);
    s.push_str(&format!(
        "<pre class=\"plan\">{}</pre>\n",
        escape(f.spec.describe(threads).trim_end())
    ));
    s.push_str(&format!(
        "<details>\n<summary>The spec (TOML)</summary>\n<pre class=\"spec\">{}</pre>\n</details>\n",
        escape(f.spec.text.trim_end())
    ));
    section(&format!("{id}-experiment"), 3, "Experiment and plan", &s)
}

fn best_known_line(inst: &brdf_experiment::spec::InstanceSpec, targets: &Targets) -> String {
    match &inst.best_known {
        Some(b) => para(
            "",
            &format!(
                "Best-known RMSE {} ({} descents from random starts, seed {}); targets {}.",
                super::format::significant(b.rmse, 6),
                b.starts,
                b.seed,
                inst.targets
                    .iter()
                    .map(|&t| targets.text(&inst.name, t))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ),
        None => String::new(),
    }
}
