//! The small Markdown subset the stress crate writes (pipe tables, `#` headings, `- ` lists,
//! paragraphs, `**bold**` and `` `code` ``) as HTML, so a page shows text that crate renders
//! only as Markdown without a second copy of its wording.

use super::escape;

/// `md` as HTML blocks; every piece of text is escaped.
pub fn blocks(md: &str) -> String {
    let mut out = String::new();
    let mut para: Vec<&str> = Vec::new();
    let mut rows: Vec<&str> = Vec::new();
    let mut items: Vec<&str> = Vec::new();
    for line in md.lines().map(str::trim_end) {
        // Each kind of block ends where a line of another kind (or a blank line) starts.
        if !line.starts_with('|') {
            flush_table(&mut rows, &mut out);
        }
        if !line.starts_with("- ") {
            flush_list(&mut items, &mut out);
        }
        if line.is_empty()
            || line.starts_with('|')
            || line.starts_with("- ")
            || line.starts_with('#')
        {
            flush_para(&mut para, &mut out);
        }
        if line.starts_with('|') {
            rows.push(line);
        } else if let Some(item) = line.strip_prefix("- ") {
            items.push(item);
        } else if line.starts_with('#') {
            let level = line.chars().take_while(|&c| c == '#').count();
            // Headings of embedded text sit below the page's own h2/h3.
            let h = (level + 3).min(6);
            out.push_str(&format!("<h{h}>{}</h{h}>\n", inline(line[level..].trim())));
        } else if !line.is_empty() {
            para.push(line);
        }
    }
    flush_table(&mut rows, &mut out);
    flush_list(&mut items, &mut out);
    flush_para(&mut para, &mut out);
    out
}

/// One line of text: escaped, with `**` pairs as `<strong>` and backtick pairs as `<code>`;
/// an unpaired marker stays as typed (closing tags must balance).
pub fn inline(text: &str) -> String {
    let mut s = escape(text);
    for (mark, tag) in [("**", "strong"), ("`", "code")] {
        if s.matches(mark).count() % 2 == 0 {
            let mut out = String::new();
            for (i, piece) in s.split(mark).enumerate() {
                if i > 0 {
                    let slash = if i % 2 == 1 { "" } else { "/" };
                    out.push_str(&format!("<{slash}{tag}>"));
                }
                out.push_str(piece);
            }
            s = out;
        }
    }
    s
}

/// The cells of a table row `| a | b |`.
fn cells(row: &str) -> Vec<String> {
    let inner = row.trim().trim_start_matches('|').trim_end_matches('|');
    inner.split('|').map(|c| inline(c.trim())).collect()
}

fn flush_table(rows: &mut Vec<&str>, out: &mut String) {
    if rows.is_empty() {
        return;
    }
    let head = cells(rows[0]);
    // The second row of a Markdown table is the `|---|` separator, not data.
    let body: Vec<Vec<String>> = rows
        .iter()
        .skip(1)
        .filter(|r| !r.chars().all(|c| matches!(c, '|' | '-' | ':' | ' ')))
        .map(|r| cells(r))
        .collect();
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    out.push_str(&super::table("md", &head, &body));
    rows.clear();
}

fn flush_list(items: &mut Vec<&str>, out: &mut String) {
    if items.is_empty() {
        return;
    }
    out.push_str("<ul>\n");
    for i in items.iter() {
        out.push_str(&format!("<li>{}</li>\n", inline(i)));
    }
    out.push_str("</ul>\n");
    items.clear();
}

fn flush_para(para: &mut Vec<&str>, out: &mut String) {
    if para.is_empty() {
        return;
    }
    out.push_str(&format!("<p>{}</p>\n", inline(&para.join(" "))));
    para.clear();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_lists_and_paragraphs_become_balanced_html() {
        let md = "Some **bold** text\nand `x<y`.\n\n| a | b |\n|---|---|\n| 1 | <2> |\n\
                  \n- one\n- two\n\n### Head\nOdd ** marker";
        let html = blocks(md);
        assert!(html.contains("<p>Some <strong>bold</strong> text and <code>x&lt;y</code>.</p>"));
        assert!(html.contains("<th>a</th><th>b</th>"));
        assert!(html.contains("<td>1</td><td>&lt;2&gt;</td>"));
        assert!(!html.contains("---"));
        assert!(html.contains("<li>two</li>"));
        assert!(html.contains("<h6>Head</h6>"));
        assert!(html.contains("Odd ** marker"));
        super::super::wellformed::check(&html).unwrap();
    }
}
