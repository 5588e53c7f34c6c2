//! A check that the pages' markup is balanced: every element opened is closed, in order.
//! Enough for what the pages emit (HTML, inline SVG, a style sheet); not a general parser.

/// Elements that never have a closing tag in HTML.
const VOID: [&str; 8] = ["meta", "br", "hr", "img", "input", "link", "col", "wbr"];

/// Checks that the tags of `html` are balanced; the error names the first offending tag and
/// its byte offset.
pub fn check(html: &str) -> Result<(), String> {
    let mut stack: Vec<(String, usize)> = Vec::new();
    let mut i = 0;
    while let Some(off) = html[i..].find('<') {
        let at = i + off;
        let rest = &html[at..];
        if let Some(skip) = skipped(rest) {
            i = at + skip;
            continue;
        }
        if !rest[1..].starts_with(|c: char| c.is_ascii_alphabetic() || c == '/') {
            return Err(format!("a bare `<` at byte {at}"));
        }
        let end = rest
            .find('>')
            .ok_or_else(|| format!("unterminated tag at byte {at}"))?;
        let tag = &rest[1..end];
        i = at + end + 1;
        if let Some(name) = tag.strip_prefix('/') {
            let name = name.trim().to_ascii_lowercase();
            match stack.pop() {
                Some((open, _)) if open == name => {}
                Some((open, pos)) => {
                    return Err(format!(
                        "</{name}> at byte {at} closes <{open}> opened at byte {pos}"
                    ));
                }
                None => return Err(format!("</{name}> at byte {at} closes nothing")),
            }
            continue;
        }
        let name: String = tag
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
            .collect::<String>()
            .to_ascii_lowercase();
        if tag.ends_with('/') || VOID.contains(&name.as_str()) {
            continue;
        }
        if name == "style" || name == "script" {
            let close = format!("</{name}>");
            let len = html[i..]
                .find(&close)
                .ok_or_else(|| format!("<{name}> at byte {at} is never closed"))?;
            i += len + close.len();
            continue;
        }
        stack.push((name, at));
    }
    match stack.pop() {
        Some((open, pos)) => Err(format!("<{open}> opened at byte {pos} is never closed")),
        None => Ok(()),
    }
}

/// The length of a comment, doctype or XML declaration at the start of `rest`.
fn skipped(rest: &str) -> Option<usize> {
    let (start, end) = if rest.starts_with("<!--") {
        ("<!--", "-->")
    } else if rest.starts_with("<!") {
        ("<!", ">")
    } else if rest.starts_with("<?") {
        ("<?", "?>")
    } else {
        return None;
    };
    Some(
        rest[start.len()..]
            .find(end)
            .map_or(rest.len(), |e| start.len() + e + end.len()),
    )
}

#[cfg(test)]
mod tests {
    use super::check;

    #[test]
    fn balanced_markup_passes() {
        let page = "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><style>a>b{}</style>\
</head><body><!-- x --><p>1 &lt; 2</p><svg><line x1=\"0\"/></svg></body></html>";
        check(page).unwrap();
    }

    #[test]
    fn unbalanced_markup_is_named() {
        assert!(check("<p><b>x</p></b>").unwrap_err().contains("</p>"));
        assert!(check("<table><tr>").unwrap_err().contains("<tr>"));
        assert!(check("</div>").unwrap_err().contains("closes nothing"));
        assert!(check("a < b").unwrap_err().contains("bare"));
    }
}
