//! The `.fit` reader: a small lexer and recursive-descent parser for bbm's one-line model
//! expressions, turned into [`PublishedFit`]s. The grammar and the limits are documented in
//! the [module](super) page.

use super::{FitParam, PublishedFit};
use std::io::Read;
use std::path::{Path, PathBuf};

/// Largest `.fit` file read, in bytes: 4 MiB (the largest published file, `bagher_sgd.fit`,
/// has 47,821 bytes). A longer input is refused with [`FitError::Limit`].
pub const MAX_FIT_BYTES: u64 = 4 << 20;
/// Longest line, in bytes (without the line break): 64 KiB (the longest published line has
/// 504 bytes).
pub const MAX_FIT_LINE_BYTES: usize = 64 << 10;
/// Most materials in one file: 10,000 (the published files have 86 or 100).
pub const MAX_FIT_MATERIALS: usize = 10_000;
/// Deepest nesting of calls and lists: 8 (the published files nest 3 deep:
/// `Aggregate(Bagher(eta = [[...]]))`).
pub const MAX_FIT_DEPTH: usize = 8;
/// Most arguments of one call or items of one list: 64.
pub const MAX_FIT_ITEMS: usize = 64;
/// Longest material, model or parameter name, in bytes: 256.
pub const MAX_FIT_NAME_BYTES: usize = 256;

/// Errors reading a `.fit` file. Each names the file; parse errors also name the line and the
/// column (both from 1) and what was expected.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// File.
        path: PathBuf,
        /// Underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The text does not follow the grammar, or a value is not what the structure needs.
    #[error("{path}:{line}:{column}: expected {expected}, found {found}")]
    Parse {
        /// File.
        path: PathBuf,
        /// Line, from 1.
        line: usize,
        /// Column (in characters), from 1.
        column: usize,
        /// What was expected.
        expected: String,
        /// What was found.
        found: String,
    },
    /// The input exceeds one of the limits ([`MAX_FIT_BYTES`], [`MAX_FIT_LINE_BYTES`],
    /// [`MAX_FIT_MATERIALS`], [`MAX_FIT_DEPTH`], [`MAX_FIT_ITEMS`], [`MAX_FIT_NAME_BYTES`]).
    #[error("{path}:{line}: {message}")]
    Limit {
        /// File.
        path: PathBuf,
        /// Line, from 1 (0 when not tied to a line).
        line: usize,
        /// What was exceeded.
        message: String,
    },
}

/// A parsed `.fit` file: its comment header and its materials in file order.
#[derive(Clone, Debug, PartialEq)]
pub struct FitFile {
    /// The comment lines (text after `#`, trimmed), in order; bbm's files name the paper here.
    pub comments: Vec<String>,
    /// One entry per material line, in file order.
    pub fits: Vec<PublishedFit>,
}

impl FitFile {
    /// The fit of `material`, if the file has it.
    pub fn get(&self, material: &str) -> Option<&PublishedFit> {
        self.fits.iter().find(|f| f.material == material)
    }
}

/// Reads and parses a `.fit` file (at most [`MAX_FIT_BYTES`]); see [`parse_fits`].
pub fn read_fits(path: impl AsRef<Path>) -> Result<FitFile, FitError> {
    let path = path.as_ref();
    let io = |source| FitError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::new();
    file.take(MAX_FIT_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > MAX_FIT_BYTES {
        return Err(too_long(path, None));
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let good = &e.as_bytes()[..at];
        let line = 1 + good.iter().filter(|&&b| b == b'\n').count();
        let column = 1 + good.iter().rev().take_while(|&&b| b != b'\n').count();
        FitError::Parse {
            path: path.to_path_buf(),
            line,
            column,
            expected: "UTF-8 text".into(),
            found: format!("the byte 0x{:02x}", e.as_bytes()[at]),
        }
    })?;
    parse_fits(&text, path)
}

fn too_long(path: &Path, len: Option<u64>) -> FitError {
    FitError::Limit {
        path: path.to_path_buf(),
        line: 0,
        message: format!(
            "expected at most {MAX_FIT_BYTES} bytes (MAX_FIT_BYTES), found {}",
            len.map_or("more".to_string(), |l| l.to_string())
        ),
    }
}

/// Parses the text of a `.fit` file; `path` only names the file in errors. Never panics; the
/// first problem is returned.
pub fn parse_fits(text: &str, path: impl AsRef<Path>) -> Result<FitFile, FitError> {
    let path = path.as_ref();
    if text.len() as u64 > MAX_FIT_BYTES {
        return Err(too_long(path, Some(text.len() as u64)));
    }
    let mut out = FitFile {
        comments: Vec::new(),
        fits: Vec::new(),
    };
    for (i, raw) in text.split('\n').enumerate() {
        let line_no = i + 1;
        let line = raw.strip_suffix('\r').unwrap_or(raw);
        if line.len() > MAX_FIT_LINE_BYTES {
            return Err(FitError::Limit {
                path: path.to_path_buf(),
                line: line_no,
                message: format!(
                    "expected at most {MAX_FIT_LINE_BYTES} bytes per line (MAX_FIT_LINE_BYTES), \
                     found {}",
                    line.len()
                ),
            });
        }
        let trimmed = line.trim();
        if trimmed.is_empty() {
            continue;
        }
        if let Some(c) = trimmed.strip_prefix('#') {
            out.comments.push(c.trim().to_string());
            continue;
        }
        if out.fits.len() == MAX_FIT_MATERIALS {
            return Err(FitError::Limit {
                path: path.to_path_buf(),
                line: line_no,
                message: format!(
                    "expected at most {MAX_FIT_MATERIALS} materials (MAX_FIT_MATERIALS), found more"
                ),
            });
        }
        let p = LineParser {
            path,
            line_no,
            text: line,
            pos: 0,
        };
        let fit = p.material_line()?;
        if let Some(first) = out.fits.iter().find(|f| f.material == fit.material) {
            return Err(FitError::Parse {
                path: path.to_path_buf(),
                line: line_no,
                column: 1 + line.len() - line.trim_start().len(),
                expected: format!(
                    "a material not given before (`{}` is on line {})",
                    fit.material, first.line
                ),
                found: format!("`{}` again", fit.material),
            });
        }
        out.fits.push(fit);
    }
    Ok(out)
}

/// A parsed expression: a number, a list, or a call `Name(arg, name = arg, ...)`.
#[derive(Debug)]
enum Expr {
    Num(f64),
    List(Vec<(usize, Expr)>),
    Call(Call),
}

#[derive(Debug)]
struct Call {
    name: String,
    column: usize,
    /// `(name, column of the value, value)`; the name is `None` for a positional argument.
    args: Vec<(Option<String>, usize, Expr)>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Tok<'a> {
    Ident(&'a str),
    Num(&'a str),
    Open,
    Close,
    OpenList,
    CloseList,
    Comma,
    Equals,
    Other(char),
    End,
}

fn describe(t: Tok) -> String {
    match t {
        Tok::Ident(s) => format!("`{s}`"),
        Tok::Num(s) => format!("the number `{s}`"),
        Tok::Open => "`(`".into(),
        Tok::Close => "`)`".into(),
        Tok::OpenList => "`[`".into(),
        Tok::CloseList => "`]`".into(),
        Tok::Comma => "`,`".into(),
        Tok::Equals => "`=`".into(),
        Tok::Other(c) => format!("the character {c:?}"),
        Tok::End => "the end of the line".into(),
    }
}

struct LineParser<'a> {
    path: &'a Path,
    line_no: usize,
    text: &'a str,
    /// Byte offset of the next unread character.
    pos: usize,
}

impl<'a> LineParser<'a> {
    /// Column (in characters, from 1) of byte offset `at`.
    fn column(&self, at: usize) -> usize {
        1 + self.text[..at.min(self.text.len())].chars().count()
    }

    fn err_at(&self, at: usize, expected: impl Into<String>, found: impl Into<String>) -> FitError {
        FitError::Parse {
            path: self.path.to_path_buf(),
            line: self.line_no,
            column: self.column(at),
            expected: expected.into(),
            found: found.into(),
        }
    }

    fn limit(&self, message: String) -> FitError {
        FitError::Limit {
            path: self.path.to_path_buf(),
            line: self.line_no,
            message,
        }
    }

    fn skip_space(&mut self) {
        let rest = &self.text[self.pos..];
        self.pos += rest.len() - rest.trim_start().len();
    }

    /// The next token and its byte offset, without consuming it.
    fn peek(&mut self) -> (usize, Tok<'a>, usize) {
        self.skip_space();
        let at = self.pos;
        let rest = &self.text[at..];
        let Some(c) = rest.chars().next() else {
            return (at, Tok::End, at);
        };
        let single = |t| (at, t, at + 1);
        match c {
            '(' => single(Tok::Open),
            ')' => single(Tok::Close),
            '[' => single(Tok::OpenList),
            ']' => single(Tok::CloseList),
            ',' => single(Tok::Comma),
            '=' => single(Tok::Equals),
            c if c.is_ascii_alphabetic() || c == '_' => {
                let len = rest
                    .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                    .unwrap_or(rest.len());
                (at, Tok::Ident(&rest[..len]), at + len)
            }
            c if c.is_ascii_digit() || matches!(c, '.' | '+' | '-') => {
                let len = rest
                    .find(|c: char| !(c.is_ascii_alphanumeric() || matches!(c, '.' | '+' | '-')))
                    .unwrap_or(rest.len());
                (at, Tok::Num(&rest[..len]), at + len)
            }
            c => (at, Tok::Other(c), at + c.len_utf8()),
        }
    }

    fn next(&mut self) -> (usize, Tok<'a>) {
        let (at, t, end) = self.peek();
        self.pos = end;
        (at, t)
    }

    fn expect(&mut self, want: Tok, what: &str) -> Result<(), FitError> {
        let (at, t) = self.next();
        if t == want {
            Ok(())
        } else {
            Err(self.err_at(at, what, describe(t)))
        }
    }

    /// `material = Expr` up to the end of the line.
    fn material_line(mut self) -> Result<PublishedFit, FitError> {
        let Some(eq) = self.text.find('=') else {
            self.skip_space();
            return Err(self.err_at(
                self.pos,
                "`material = Model(...)` or a `#` comment",
                "no `=`",
            ));
        };
        let name_start = self.text.len() - self.text.trim_start().len();
        let material = self.text[..eq].trim();
        let bad = material
            .char_indices()
            .find(|&(_, c)| !(c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.' | '+')));
        if material.is_empty() {
            return Err(self.err_at(name_start, "a material name before `=`", "nothing"));
        }
        if let Some((i, c)) = bad {
            return Err(self.err_at(
                name_start + i,
                "a material name of letters, digits and `-_.+`",
                format!("the character {c:?}"),
            ));
        }
        if material.len() > MAX_FIT_NAME_BYTES {
            return Err(self.limit(format!(
                "expected a material name of at most {MAX_FIT_NAME_BYTES} bytes \
                 (MAX_FIT_NAME_BYTES), found {}",
                material.len()
            )));
        }
        self.pos = eq + 1;
        let (value_at, _, _) = self.peek();
        let expr = self.expr(1)?;
        let (at, t) = self.next();
        if t != Tok::End {
            return Err(self.err_at(at, "the end of the line after the model", describe(t)));
        }
        let Expr::Call(top) = expr else {
            return Err(self.err_at(value_at, "a model call such as `Aggregate(...)`", "a value"));
        };
        self.build(material.to_string(), top)
    }

    fn expr(&mut self, depth: usize) -> Result<Expr, FitError> {
        if depth > MAX_FIT_DEPTH {
            return Err(self.limit(format!(
                "expected calls and lists nested at most {MAX_FIT_DEPTH} deep (MAX_FIT_DEPTH), \
                 found deeper"
            )));
        }
        let (at, t) = self.next();
        match t {
            Tok::Num(s) => match s.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(Expr::Num(v)),
                Ok(_) => Err(self.err_at(at, "a finite number", format!("`{s}`"))),
                Err(_) => Err(self.err_at(at, "a number", format!("`{s}`"))),
            },
            Tok::OpenList => {
                let mut items = Vec::new();
                if self.peek().1 == Tok::CloseList {
                    self.next();
                    return Ok(Expr::List(items));
                }
                loop {
                    if items.len() == MAX_FIT_ITEMS {
                        return Err(self.too_many());
                    }
                    let (item_at, _, _) = self.peek();
                    items.push((item_at, self.expr(depth + 1)?));
                    let (at, t) = self.next();
                    match t {
                        Tok::Comma => {}
                        Tok::CloseList => return Ok(Expr::List(items)),
                        t => return Err(self.err_at(at, "`,` or `]`", describe(t))),
                    }
                }
            }
            Tok::Ident(name) => {
                self.expect(Tok::Open, &format!("`(` after the model name `{name}`"))?;
                self.call(name, at, depth)
            }
            t => Err(self.err_at(at, "a number, a list `[...]` or a model call", describe(t))),
        }
    }

    fn too_many(&self) -> FitError {
        self.limit(format!(
            "expected at most {MAX_FIT_ITEMS} arguments or list items (MAX_FIT_ITEMS), found more"
        ))
    }

    /// The arguments of a call, after its `(`.
    fn call(&mut self, name: &str, name_at: usize, depth: usize) -> Result<Expr, FitError> {
        if name.len() > MAX_FIT_NAME_BYTES {
            return Err(self.limit(format!(
                "expected a model name of at most {MAX_FIT_NAME_BYTES} bytes \
                 (MAX_FIT_NAME_BYTES), found {}",
                name.len()
            )));
        }
        let mut call = Call {
            name: name.to_string(),
            column: self.column(name_at),
            args: Vec::new(),
        };
        if self.peek().1 == Tok::Close {
            self.next();
            return Ok(Expr::Call(call));
        }
        loop {
            if call.args.len() == MAX_FIT_ITEMS {
                return Err(self.too_many());
            }
            // `name = value` or a positional value.
            let save = self.pos;
            let (_, t) = self.next();
            let arg_name = match (t, self.peek().1) {
                (Tok::Ident(n), Tok::Equals) => {
                    self.next();
                    Some(n.to_string())
                }
                _ => {
                    self.pos = save;
                    None
                }
            };
            let (value_at, _, _) = self.peek();
            let value = self.expr(depth + 1)?;
            call.args.push((arg_name, self.column(value_at), value));
            let (at, t) = self.next();
            match t {
                Tok::Comma => {}
                Tok::Close => return Ok(Expr::Call(call)),
                t => return Err(self.err_at(at, "`,` or `)`", describe(t))),
            }
        }
    }

    fn err_col(
        &self,
        column: usize,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> FitError {
        FitError::Parse {
            path: self.path.to_path_buf(),
            line: self.line_no,
            column,
            expected: expected.into(),
            found: found.into(),
        }
    }

    /// Turns `Aggregate(Lambertian(albedo = [...]), Model(...))` (or a lone `Model(...)`) into
    /// a [`PublishedFit`].
    fn build(&self, material: String, top: Call) -> Result<PublishedFit, FitError> {
        let top_column = top.column;
        let components: Vec<(usize, Call)> = if top.name == "Aggregate" {
            let mut v = Vec::new();
            for (name, col, e) in top.args {
                match (name, e) {
                    (None, Expr::Call(c)) => v.push((col, c)),
                    (Some(n), _) => {
                        return Err(self.err_col(
                            col,
                            "a model as an argument of Aggregate",
                            format!("the named argument `{n}`"),
                        ));
                    }
                    (None, _) => {
                        return Err(self.err_col(
                            col,
                            "a model as an argument of Aggregate",
                            "a value",
                        ));
                    }
                }
            }
            v
        } else {
            vec![(top.column, top)]
        };
        let mut diffuse = None;
        let mut specular: Option<(String, Vec<FitParam>)> = None;
        for (col, c) in components {
            if c.name == "Lambertian" {
                if diffuse.is_some() {
                    return Err(self.err_col(col, "one Lambertian term", "a second one"));
                }
                let params = self.params(&c)?;
                match params.as_slice() {
                    [p] if p.name == "albedo" => diffuse = Some(p.rgb),
                    _ => {
                        return Err(self.err_col(
                            col,
                            "`Lambertian(albedo = [r, g, b])`",
                            format!("parameters {:?}", names(&params)),
                        ));
                    }
                }
            } else {
                if let Some((first, _)) = &specular {
                    return Err(self.err_col(
                        col,
                        format!("one specular model besides Lambertian (found `{first}`)"),
                        format!("a second one, `{}`", c.name),
                    ));
                }
                let params = self.params(&c)?;
                specular = Some((c.name, params));
            }
        }
        let Some((model, params)) = specular else {
            return Err(self.err_col(
                top_column,
                "a specular model besides Lambertian",
                "only a Lambertian term",
            ));
        };
        Ok(PublishedFit {
            material,
            model,
            line: self.line_no,
            diffuse,
            params,
        })
    }

    /// The named arguments of a model as parameters: a number (shared by the channels), a
    /// list of 3 numbers (red, green, blue), or a list of lists of 3 numbers (`name.0`,
    /// `name.1`, ...).
    fn params(&self, c: &Call) -> Result<Vec<FitParam>, FitError> {
        let mut out: Vec<FitParam> = Vec::new();
        for (name, col, e) in &c.args {
            let Some(name) = name else {
                return Err(self.err_col(
                    *col,
                    format!("a named parameter `name = value` of {}", c.name),
                    "a positional argument",
                ));
            };
            if out
                .iter()
                .any(|p| p.name == *name || p.name.starts_with(&format!("{name}.")))
            {
                return Err(self.err_col(
                    *col,
                    format!("each parameter of {} once", c.name),
                    format!("`{name}` again"),
                ));
            }
            match e {
                Expr::Num(v) => out.push(FitParam {
                    name: name.clone(),
                    rgb: [*v; 3],
                    shared: true,
                }),
                Expr::List(items) if !items.is_empty() && matches!(items[0].1, Expr::List(_)) => {
                    for (k, (at, item)) in items.iter().enumerate() {
                        let rgb = self.rgb(*at, item, &format!("{name}.{k}"))?;
                        out.push(FitParam {
                            name: format!("{name}.{k}"),
                            rgb,
                            shared: false,
                        });
                    }
                }
                e => out.push(FitParam {
                    name: name.clone(),
                    rgb: self.rgb_col(*col, e, name)?,
                    shared: false,
                }),
            }
        }
        Ok(out)
    }

    fn rgb(&self, at: usize, e: &Expr, name: &str) -> Result<[f64; 3], FitError> {
        self.rgb_col(self.column(at), e, name)
    }

    fn rgb_col(&self, col: usize, e: &Expr, name: &str) -> Result<[f64; 3], FitError> {
        let what = format!("`{name}`: a number or a list of 3 numbers [r, g, b]");
        match e {
            Expr::List(items) if items.len() == 3 => {
                let mut rgb = [0.0; 3];
                for (slot, (at, item)) in rgb.iter_mut().zip(items) {
                    match item {
                        Expr::Num(v) => *slot = *v,
                        _ => return Err(self.err_at(*at, what, "a list or a call")),
                    }
                }
                Ok(rgb)
            }
            Expr::List(items) => Err(self.err_col(col, what, format!("a list of {}", items.len()))),
            Expr::Call(c) => Err(self.err_col(col, what, format!("the call `{}(...)`", c.name))),
            Expr::Num(_) => Err(self.err_col(col, what, "a number inside a list of lists")),
        }
    }
}

fn names(p: &[FitParam]) -> Vec<&str> {
    p.iter().map(|p| p.name.as_str()).collect()
}
