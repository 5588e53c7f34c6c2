//! Text for a terminal: labels and names come from specs and results files, which are input,
//! so their control characters (an escape sequence such as `\u{1b}[2J` clears the screen) are
//! written escaped, never raw.

use std::borrow::Cow;

/// True for characters a terminal would act on rather than show: control characters other
/// than the line break and the tab, and the bidirectional overrides and isolates, which
/// reorder what follows them.
fn acts_on_terminal(c: char) -> bool {
    (c.is_control() && c != '\n' && c != '\t')
        || matches!(c, '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

/// `text` with every character a terminal would act on written as its Rust escape
/// (`\u{1b}`, `\r`); borrowed unchanged when there is none. Line breaks and tabs are kept.
pub fn safe(text: &str) -> Cow<'_, str> {
    if !text.chars().any(acts_on_terminal) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if acts_on_terminal(c) {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

#[cfg(test)]
mod tests {
    use super::safe;

    #[test]
    fn escapes_what_a_terminal_acts_on_and_keeps_the_rest() {
        assert_eq!(safe("AED phi=1.4\n\ttable"), "AED phi=1.4\n\ttable");
        assert_eq!(safe("a\u{1b}[2Jb"), "a\\u{1b}[2Jb");
        assert_eq!(safe("x\ry\u{7f}\u{9b}"), "x\\ry\\u{7f}\\u{9b}");
        assert_eq!(safe("\u{202e}evil"), "\\u{202e}evil");
        assert!(matches!(safe("plain"), std::borrow::Cow::Borrowed(_)));
    }
}
