//! Self-contained HTML pages: a results report ([`report_page`]), a before/after comparison
//! ([`compare_page`]) and a stress report ([`stress_page`]; `brdf-sls bench` builds its page
//! from the blocks here). One file each, with inline CSS and inline SVG charts (drawn by
//! `brdf_graphics` with its embedded font); no script, no network, no external font.
//!
//! Every string taken from results (names, labels, descriptions, spec text, machine names) is
//! escaped with [`escape`]; the building blocks here take cells and captions that callers have
//! already escaped or built from escaped parts.

mod compare;
mod figures;
pub mod format;
mod markdown;
mod provenance;
mod report;
mod stress;
mod summary;
mod tables;
pub mod wellformed;

pub use compare::compare_page;
pub use figures::{figure, legend};
pub use provenance::machine_text;
pub use report::{report_page, report_page_of};
pub use stress::stress_page;

/// Errors building a page.
#[derive(Debug, thiserror::Error)]
pub enum PageError {
    /// A chart could not be drawn.
    #[error("drawing `{title}`: {message}")]
    Chart {
        /// The chart's title.
        title: String,
        /// plotters' message.
        message: String,
    },
}

/// `s` with the characters that mean something in HTML (`& < > " '`) replaced by references.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// The page's style: readable tables, charts as wide as the text, verdicts in colour.
const STYLE: &str = include_str!("style.css");

/// A whole HTML document with `title` (plain text) and `body` (HTML).
pub fn document(title: &str, body: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
<title>{}</title>\n<style>\n{STYLE}</style>\n</head>\n<body>\n{body}</body>\n</html>\n",
        escape(title)
    )
}

/// A table with a header row; `head` and `rows` are HTML. It scrolls sideways in its own box
/// when wider than the page.
pub fn table(class: &str, head: &[&str], rows: &[Vec<String>]) -> String {
    let mut s = format!("<div class=\"scroll\">\n<table class=\"{class}\">\n<thead><tr>");
    for h in head {
        s.push_str(&format!("<th>{h}</th>"));
    }
    s.push_str("</tr></thead>\n<tbody>\n");
    for r in rows {
        s.push_str("<tr>");
        for c in r {
            s.push_str(&format!("<td>{c}</td>"));
        }
        s.push_str("</tr>\n");
    }
    s.push_str("</tbody>\n</table>\n</div>\n");
    s
}

/// A table with a caption (HTML), a header row and numeric columns (right-aligned, digits
/// aligned, never wrapped), in a box that scrolls sideways on its own when it is wider than
/// the page: the page itself never does.
pub fn data_table(
    class: &str,
    caption: &str,
    head: &[&str],
    rows: &[Vec<String>],
    numeric: &[usize],
) -> String {
    let td = |i: usize| {
        if numeric.contains(&i) {
            "<td class=\"num\">"
        } else {
            "<td>"
        }
    };
    let mut s = format!("<div class=\"scroll\">\n<table class=\"{class}\">\n");
    if !caption.is_empty() {
        s.push_str(&format!("<caption>{caption}</caption>\n"));
    }
    s.push_str("<thead><tr>");
    for (i, h) in head.iter().enumerate() {
        let class = if numeric.contains(&i) {
            " class=\"num\""
        } else {
            ""
        };
        s.push_str(&format!("<th{class}>{h}</th>"));
    }
    s.push_str("</tr></thead>\n<tbody>\n");
    for r in rows {
        s.push_str("<tr>");
        for (i, c) in r.iter().enumerate() {
            s.push_str(&format!("{}{c}</td>", td(i)));
        }
        s.push_str("</tr>\n");
    }
    s.push_str("</tbody>\n</table>\n</div>\n");
    s
}

/// A two-column table of (key, value) pairs, both HTML.
pub fn key_values(pairs: &[(&str, String)]) -> String {
    let mut s = String::from("<table class=\"kv\">\n<tbody>\n");
    for (k, v) in pairs {
        s.push_str(&format!("<tr><th>{k}</th><td>{v}</td></tr>\n"));
    }
    s.push_str("</tbody>\n</table>\n");
    s
}

/// A `<section>` with an `id` and a heading of `level` (2 or 3); `title` is plain text.
pub fn section(id: &str, level: u8, title: &str, content: &str) -> String {
    format!(
        "<section id=\"{}\">\n<h{level}>{}</h{level}>\n{content}</section>\n",
        escape(id),
        escape(title)
    )
}

/// A paragraph of plain text with an optional class.
pub fn para(class: &str, text: &str) -> String {
    if class.is_empty() {
        format!("<p>{}</p>\n", escape(text))
    } else {
        format!("<p class=\"{class}\">{}</p>\n", escape(text))
    }
}

/// The last second ISO 8601 writes with a four-digit year (9999-12-31T23:59:59Z).
const LAST_DATE_UNIX: u64 = 253_402_300_799;

/// A Unix time as an ISO 8601 UTC date and time (`2026-12-03T17:40:08Z`); a time after the
/// year 9999 (a results file is input: its header may hold anything) is given as the number
/// of seconds it is.
pub fn date(unix: u64) -> String {
    if unix > LAST_DATE_UNIX {
        return format!("{unix} s after 1970 (after the year 9999: not a date)");
    }
    let t = std::time::UNIX_EPOCH + std::time::Duration::from_secs(unix);
    humantime::format_rfc3339_seconds(t).to_string()
}

/// A fragment identifier made of `parts` (letters, digits and `-` only).
pub fn anchor(parts: &[&str]) -> String {
    parts
        .iter()
        .map(|p| brdf_graphics::chart::slug(p))
        .collect::<Vec<_>>()
        .join("-")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escape_replaces_every_markup_character() {
        assert_eq!(
            escape(r#"<a href="x">Tom & 'Jerry'</a>"#),
            "&lt;a href=&quot;x&quot;&gt;Tom &amp; &#39;Jerry&#39;&lt;/a&gt;"
        );
        assert_eq!(escape("plain"), "plain");
    }

    #[test]
    fn date_is_utc_iso_8601() {
        assert_eq!(date(0), "1970-01-01T00:00:00Z");
        assert_eq!(date(1_764_780_000), "2025-12-03T16:40:00Z");
        assert_eq!(date(LAST_DATE_UNIX), "9999-12-31T23:59:59Z");
        // Headers are input: any u64 must give text, not a panic.
        for unix in [LAST_DATE_UNIX + 1, 1_000_000_000_000, u64::MAX] {
            let d = date(unix);
            assert!(
                d.contains(&unix.to_string()) && d.contains("not a date"),
                "{d}"
            );
        }
    }

    #[test]
    fn a_document_is_well_formed_and_escapes_its_title() {
        let body = section("s", 2, "A <b>", &table("t", &["x"], &[vec!["1".into()]]));
        let page = document("T & <U>", &body);
        assert!(page.contains("<title>T &amp; &lt;U&gt;</title>"));
        assert!(page.contains("<h2>A &lt;b&gt;</h2>"));
        wellformed::check(&page).unwrap();
    }
}
