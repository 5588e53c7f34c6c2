//! The report page of one or more results folders: for each, the experiment's description and
//! plan, provenance, and per instance the statistics tables, the charts and the best fit.

use super::figures::figure;
use super::{PageError, anchor, document, escape, para, provenance, section, tables};
use crate::analysis::Analysis;
use crate::folder::Folder;

/// The whole report page of `folders` (one section each, in order), each analysed here.
pub fn report_page(folders: &[Folder]) -> Result<String, PageError> {
    let analyses: Vec<Analysis> = folders.iter().map(Folder::analysis).collect();
    let pairs: Vec<(&Folder, &Analysis)> = folders.iter().zip(&analyses).collect();
    report_page_of(&pairs)
}

/// The whole report page of folders with their analyses (computed once, e.g. by a run for its
/// files and its page); each analysis needs the charts of [`crate::analysis::page_kinds`].
pub fn report_page_of(folders: &[(&Folder, &Analysis)]) -> Result<String, PageError> {
    let names: Vec<String> = folders.iter().map(|(f, _)| f.spec.name.clone()).collect();
    let title = format!("brdf-sls report: {}", names.join(", "));
    let mut body = format!("<h1>{}</h1>\n", escape(&title));
    let only: Vec<&Folder> = folders.iter().map(|(f, _)| *f).collect();
    body.push_str(&contents_nav(&only));
    for (i, (f, a)) in folders.iter().enumerate() {
        body.push_str(&folder_section(f, a, &format!("r{}", i + 1))?);
    }
    body.push_str(&para(
        "note",
        &format!("Written by brdf-sls {}.", brdf_experiment::PROGRAM_VERSION),
    ));
    Ok(document(&title, &body))
}

/// Links to each folder's sections.
fn contents_nav(folders: &[&Folder]) -> String {
    let mut s = String::from("<nav>\n<ul>\n");
    for (i, f) in folders.iter().enumerate() {
        let id = format!("r{}", i + 1);
        s.push_str(&format!(
            "<li><a href=\"#{id}\">{} ({})</a></li>\n",
            escape(&f.spec.name),
            escape(&f.dir.display().to_string())
        ));
        for inst in &f.spec.instances {
            s.push_str(&format!(
                "<li><a href=\"#{}\">{}: instance {}</a></li>\n",
                anchor(&[&id, "instance", &inst.name]),
                escape(&f.spec.name),
                escape(&inst.name)
            ));
        }
    }
    s.push_str("</ul>\n</nav>\n");
    s
}

fn folder_section(f: &Folder, analysis: &Analysis, id: &str) -> Result<String, PageError> {
    let mut s = String::new();
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
    s.push_str(&experiment(f, id));
    s.push_str(&section(
        &format!("{id}-provenance"),
        3,
        "Provenance",
        &(provenance::summary(f) + &provenance::sessions(f)),
    ));
    let records = f.records();
    let report = &analysis.stats;
    for inst in &f.spec.instances {
        let mut body = best_known_line(inst);
        body.push_str("<h4>Success, median and ERT</h4>\n");
        body.push_str(&tables::success_table(report, &inst.name));
        body.push_str("<h4>Pairwise tests (Holm over the pairs of each target and measure)</h4>\n");
        body.push_str(&tables::tests_table(report, &inst.name));
        body.push_str("<h4>Final RMSE</h4>\n");
        body.push_str(&tables::finals_table(report, &inst.name));
        body.push_str("<h4>Charts</h4>\n");
        for c in analysis.charts.iter().filter(|c| c.instance == inst.name) {
            body.push_str(&figure(&c.chart, &anchor(&[id, &c.stem]))?);
        }
        body.push_str("<h4>Best fit</h4>\n");
        body.push_str(&tables::best_fit(inst, &records));
        s.push_str(&section(
            &anchor(&[id, "instance", &inst.name]),
            3,
            &format!("Instance {}", inst.name),
            &body,
        ));
    }
    Ok(section(
        id,
        2,
        &format!("{} ({})", f.spec.name, f.dir.display()),
        &s,
    ))
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

fn best_known_line(inst: &brdf_experiment::spec::InstanceSpec) -> String {
    match &inst.best_known {
        Some(b) => para(
            "",
            &format!(
                "Best-known RMSE {} ({} descents from random starts, seed {}); targets {}.",
                b.rmse,
                b.starts,
                b.seed,
                inst.targets
                    .iter()
                    .map(|t| t.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ),
        None => String::new(),
    }
}
