//! Templates (tera): the HTML and Markdown renderers. Pure: view in, bytes out.
//!
//! The templates in `templates/` are built into the binary; a directory given
//! with `--templates` overrides either of them.

use super::view::ReportView;
use crate::error::Error;
use std::collections::HashMap;
use std::path::Path;
use tera::{Context, Tera, Value};

/// Template names (the HTML name ends in `.html`, so tera escapes every value).
const HTML: &str = "report.html";
const MARKDOWN: &str = "report.md";
/// File names of the templates in `templates/` or a `--templates` directory.
pub const HTML_FILE: &str = "report.html.tera";
pub const MARKDOWN_FILE: &str = "report.md.tera";

const BUILTIN_HTML: &str = include_str!("../../templates/report.html.tera");
const BUILTIN_MARKDOWN: &str = include_str!("../../templates/report.md.tera");

/// The report templates, ready to render.
pub struct Templates {
    tera: Tera,
}

impl Templates {
    /// The templates built into the binary.
    pub fn builtin() -> Result<Templates, Error> {
        Templates::from_sources(BUILTIN_HTML, BUILTIN_MARKDOWN)
    }

    /// Templates from a directory; a file it lacks falls back to the built-in one.
    pub fn from_dir(dir: &Path) -> Result<Templates, Error> {
        if !dir.is_dir() {
            return Err(Error::Usage(format!(
                "--templates {}: not a directory; give a directory holding {HTML_FILE} and/or {MARKDOWN_FILE}",
                dir.display()
            )));
        }
        let read = |name: &str, builtin: &str| -> Result<String, Error> {
            let path = dir.join(name);
            if path.exists() {
                std::fs::read_to_string(&path).map_err(|e| {
                    Error::Usage(format!("cannot read template {}: {e}", path.display()))
                })
            } else {
                Ok(builtin.to_string())
            }
        };
        Templates::from_sources(
            &read(HTML_FILE, BUILTIN_HTML)?,
            &read(MARKDOWN_FILE, BUILTIN_MARKDOWN)?,
        )
    }

    fn from_sources(html: &str, markdown: &str) -> Result<Templates, Error> {
        let mut tera = Tera::default();
        tera.add_raw_templates(vec![(HTML, html), (MARKDOWN, markdown)])
            .map_err(|e| Error::render("cannot parse the report templates", e))?;
        tera.autoescape_on(vec![".html"]);
        tera.register_filter("md", md_filter);
        tera.register_filter("md_code", md_code_filter);
        Ok(Templates { tera })
    }

    fn render(&self, name: &str, view: &ReportView) -> Result<Vec<u8>, Error> {
        let context = Context::from_serialize(view)
            .map_err(|e| Error::render("cannot prepare the report view", e))?;
        self.tera
            .render(name, &context)
            .map(String::into_bytes)
            .map_err(|e| Error::render(format!("cannot render template {name}"), e))
    }

    /// The self-contained HTML report.
    pub fn html(&self, view: &ReportView) -> Result<Vec<u8>, Error> {
        self.render(HTML, view)
    }

    /// The GitHub-flavoured Markdown report.
    pub fn markdown(&self, view: &ReportView) -> Result<Vec<u8>, Error> {
        self.render(MARKDOWN, view)
    }
}

/// Escapes text for GitHub-flavoured Markdown, inside or outside a table:
/// HTML is shown as text, `|` cannot end a cell, line breaks cannot end a row,
/// and emphasis, code, link and heading syntax is neutralised.
pub(crate) fn escape_markdown(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for ch in text.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '\r' => {}
            '\n' => out.push(' '),
            '\\' | '|' | '*' | '_' | '`' | '[' | ']' | '#' | '!' | '~' => {
                out.push('\\');
                out.push(ch);
            }
            c => out.push(c),
        }
    }
    out
}

/// Escapes text for a Markdown code span inside a table cell.
pub(crate) fn escape_markdown_code(text: &str) -> String {
    text.replace(['`', '\r', '\n'], " ").replace('|', "\\|")
}

fn string_arg(value: &Value, filter: &str) -> tera::Result<String> {
    match value {
        Value::String(s) => Ok(s.clone()),
        other => Err(tera::Error::msg(format!(
            "filter {filter} takes text, got {other}"
        ))),
    }
}

fn md_filter(value: &Value, _: &HashMap<String, Value>) -> tera::Result<Value> {
    Ok(Value::String(escape_markdown(&string_arg(value, "md")?)))
}

fn md_code_filter(value: &Value, _: &HashMap<String, Value>) -> tera::Result<Value> {
    Ok(Value::String(escape_markdown_code(&string_arg(
        value, "md_code",
    )?)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markdown_escaping() {
        assert_eq!(
            escape_markdown("<script>alert(1)</script>"),
            "&lt;script&gt;alert(1)&lt;/script&gt;"
        );
        assert_eq!(escape_markdown("a|b\nc"), "a\\|b c");
        assert_eq!(
            escape_markdown("*x* _y_ [l](u)"),
            "\\*x\\* \\_y\\_ \\[l\\](u)"
        );
        assert_eq!(escape_markdown_code("a|b`c"), "a\\|b c");
    }

    #[test]
    fn builtin_templates_parse() {
        assert!(Templates::builtin().is_ok());
    }
}
