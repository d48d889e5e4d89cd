//! The one layout policy of terminal output: tables and text fit a width.
//!
//! Every table command (`stats`, `check`, `coverage`, `place`, `audit`,
//! `history`) builds its tables as a [`Grid`] whose columns say how they give
//! way when the table is too wide: a column with a drop rank is hidden, the
//! highest rank first, until the table fits; if it still does not, the columns
//! marked [`Give::Wrap`] (sentences) wrap their text, and as a last resort any
//! cell wraps. The hidden columns are named once at the end of the output
//! ([`Hidden::note`]), with `--wide` to show them. Lines that are not table
//! lines are wrapped at spaces by [`fit_text`]. [`Width::Wide`] (`--wide`)
//! turns all of it off: every column, every line as long as it takes.
//!
//! Widths are counted in terminal columns (`unicode-width`, as comfy-table and
//! textwrap count them), which for phalanx's text is one per character.

use comfy_table::{CellAlignment, ColumnConstraint, ContentArrangement, Table, presets};

/// How wide terminal output may be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Width {
    /// At most this many columns (at least [`Width::MIN`]).
    Fit(usize),
    /// As wide as it takes: every column, no wrapping (`--wide`).
    Wide,
}

impl Width {
    /// The width when standard output is not a terminal (a file, a pipe).
    pub const DEFAULT: usize = 100;
    /// The narrowest width laid out for; narrower terminals get this.
    pub const MIN: usize = 40;

    /// At most `columns` columns, but never fewer than [`Width::MIN`].
    pub fn fit(columns: usize) -> Width {
        Width::Fit(columns.max(Width::MIN))
    }

    /// The width available after `indent` columns of indentation.
    fn less(self, indent: usize) -> Width {
        match self {
            Width::Fit(w) => Width::Fit(w.saturating_sub(indent).max(1)),
            Width::Wide => Width::Wide,
        }
    }
}

impl Default for Width {
    /// [`Width::DEFAULT`] columns.
    fn default() -> Width {
        Width::Fit(Width::DEFAULT)
    }
}

/// How a column's cells line up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Align {
    Left,
    Right,
}

/// How a column gives way when its table is too wide.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Give {
    /// Always shown, never wrapped unless nothing else fits (numbers, names).
    Keep,
    /// Hidden when the table does not fit: rank 1 goes first, then 2, ...
    Drop(u8),
    /// Its text wraps onto several lines (sentences).
    Wrap,
}

/// One column of a [`Grid`].
#[derive(Debug, Clone)]
struct Column {
    head: String,
    align: Align,
    give: Give,
}

/// A terminal table in Markdown style whose columns know how to give way.
#[derive(Debug, Clone, Default)]
pub struct Grid {
    columns: Vec<Column>,
    rows: Vec<Vec<String>>,
}

impl Grid {
    /// An empty table.
    pub fn new() -> Grid {
        Grid::default()
    }

    /// Adds a column.
    pub fn col(mut self, head: impl Into<String>, align: Align, give: Give) -> Grid {
        self.columns.push(Column {
            head: head.into(),
            align,
            give,
        });
        self
    }

    /// Adds a row (one cell per column; missing cells are empty).
    pub fn row(&mut self, cells: Vec<String>) {
        self.rows.push(cells);
    }

    /// The table, each line indented by `indent` spaces and ending in a line
    /// feed, fitted to `width`; the names of hidden columns are added to `hidden`.
    pub fn render(&self, width: Width, indent: usize, hidden: &mut Hidden) -> String {
        let natural = self.natural_widths();
        let mut shown = vec![true; self.columns.len()];
        if let Width::Fit(max) = width.less(indent) {
            let mut ranks: Vec<(u8, usize)> = self
                .columns
                .iter()
                .enumerate()
                .filter_map(|(i, c)| match c.give {
                    Give::Drop(rank) => Some((rank, i)),
                    _ => None,
                })
                .collect();
            // Rank 1 first; of equal ranks, the rightmost first.
            ranks.sort_by_key(|&(rank, i)| (rank, std::cmp::Reverse(i)));
            for (_, i) in ranks {
                if table_width(&natural, &shown) <= max {
                    break;
                }
                shown[i] = false;
                hidden.add(&self.columns[i].head);
            }
        }
        let mut table = self.table(&shown);
        if let Width::Fit(max) = width.less(indent)
            && table_width(&natural, &shown) > max
        {
            // Still too wide: wrap the sentence columns; if that is not enough, the
            // labels too; numbers only as a last resort.
            let tier = [Tier::Sentences, Tier::Labels, Tier::Everything]
                .into_iter()
                .find(|&tier| self.narrowest(&natural, &shown, tier) <= max)
                .unwrap_or(Tier::Everything);
            let constraints: Vec<ColumnConstraint> = self
                .columns
                .iter()
                .zip(&shown)
                .map(|(c, &s)| {
                    if !s {
                        return ColumnConstraint::Hidden;
                    }
                    match tier.least(c) {
                        Some(w) => ColumnConstraint::LowerBoundary(comfy_table::Width::Fixed(
                            u16::try_from(w).unwrap_or(u16::MAX),
                        )),
                        None => ColumnConstraint::ContentWidth,
                    }
                })
                .collect();
            table
                .set_constraints(constraints)
                .set_content_arrangement(ContentArrangement::Dynamic)
                .set_width(u16::try_from(max).unwrap_or(u16::MAX));
        }
        let pad = " ".repeat(indent);
        let mut out = String::new();
        for line in table.lines() {
            out.push_str(&pad);
            out.push_str(line.trim_end());
            out.push('\n');
        }
        out
    }

    /// The narrowest the shown columns can be when `tier` may wrap.
    fn narrowest(&self, natural: &[usize], shown: &[bool], tier: Tier) -> usize {
        1 + self
            .columns
            .iter()
            .zip(natural)
            .zip(shown)
            .filter(|(_, s)| **s)
            .map(|((c, &w), _)| tier.least(c).map_or(w, |least| least.min(w)) + 3)
            .sum::<usize>()
    }

    /// The comfy-table of the shown columns (hidden ones get the `Hidden` constraint).
    fn table(&self, shown: &[bool]) -> Table {
        let mut t = Table::new();
        t.load_style(presets::ASCII_MARKDOWN)
            .set_content_arrangement(ContentArrangement::Disabled)
            .set_header(
                self.columns
                    .iter()
                    .map(|c| c.head.clone())
                    .collect::<Vec<_>>(),
            );
        for r in &self.rows {
            t.add_row(r.clone());
        }
        for (i, c) in self.columns.iter().enumerate() {
            if let Some(col) = t.column_mut(i) {
                col.set_cell_alignment(match c.align {
                    Align::Left => CellAlignment::Left,
                    Align::Right => CellAlignment::Right,
                });
                if !shown[i] {
                    col.set_constraint(ColumnConstraint::Hidden);
                }
            }
        }
        t
    }

    /// Each column's width on one line: its widest cell or its heading.
    fn natural_widths(&self) -> Vec<usize> {
        self.columns
            .iter()
            .enumerate()
            .map(|(i, c)| {
                self.rows
                    .iter()
                    .filter_map(|r| r.get(i))
                    .map(|s| columns_of(s))
                    .chain(std::iter::once(columns_of(&c.head)))
                    .max()
                    .unwrap_or(0)
            })
            .collect()
    }
}

/// What may wrap when a table is still too wide with its columns dropped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Tier {
    /// The [`Give::Wrap`] columns (sentences).
    Sentences,
    /// Those and the left-aligned columns (labels, names).
    Labels,
    /// Every column, numbers too.
    Everything,
}

impl Tier {
    /// The narrowest `c` may wrap to at this tier; `None` when it keeps its width.
    fn least(self, c: &Column) -> Option<usize> {
        match (self, c.give, c.align) {
            (_, Give::Wrap, _) => Some(12),
            (Tier::Labels, _, Align::Left) => Some(8),
            (Tier::Everything, _, _) => Some(4),
            _ => None,
        }
    }
}

/// Width of a Markdown-style table of the shown columns: `| a | b |`.
fn table_width(natural: &[usize], shown: &[bool]) -> usize {
    1 + natural
        .iter()
        .zip(shown)
        .filter(|(_, s)| **s)
        .map(|(w, _)| w + 3)
        .sum::<usize>()
}

/// Terminal columns of the widest line of `text`.
fn columns_of(text: &str) -> usize {
    text.lines()
        .map(textwrap::core::display_width)
        .max()
        .unwrap_or(0)
}

/// The columns hidden to fit the width, in the order they were first hidden.
#[derive(Debug, Clone, Default)]
pub struct Hidden(Vec<String>);

impl Hidden {
    /// No column hidden yet.
    pub fn new() -> Hidden {
        Hidden::default()
    }

    fn add(&mut self, name: &str) {
        let name = if name.is_empty() { "(unnamed)" } else { name };
        if !self.0.iter().any(|n| n == name) {
            self.0.push(name.to_string());
        }
    }

    /// True when no column was hidden.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Appends the note naming the hidden columns to `out`, after one blank line.
    pub fn append_to(&self, out: &mut String, width: Width) {
        if self.0.is_empty() {
            return;
        }
        while out.ends_with('\n') {
            out.pop();
        }
        out.push('\n');
        out.push_str(&self.note(width));
    }

    /// The paragraph naming the hidden columns (a blank line, then the note), or nothing.
    pub fn note(&self, width: Width) -> String {
        if self.0.is_empty() {
            return String::new();
        }
        let at = match width {
            Width::Fit(w) => format!(" to fit {w} columns"),
            Width::Wide => String::new(),
        };
        fit_text(
            &format!(
                "\n(Not shown{at}: {}. --wide shows every column; --format json has every value.)\n",
                self.0.join(", ")
            ),
            width,
        )
    }
}

/// `text` with every line that is not a table line (one starting with `|`
/// after its indentation) wrapped at spaces to `width`. A wrapped line keeps
/// its indentation and continues two columns further in (past the bullet of
/// a `- ` item). Hyphenated words stay whole; a word longer than the width is broken.
pub fn fit_text(text: &str, width: Width) -> String {
    let Width::Fit(max) = width else {
        return text.to_string();
    };
    let mut out = String::with_capacity(text.len());
    for piece in text.split_inclusive('\n') {
        let (line, eol) = match piece.strip_suffix('\n') {
            Some(l) => (l, "\n"),
            None => (piece, ""),
        };
        let body = line.trim_start();
        if body.starts_with('|') || textwrap::core::display_width(line) <= max {
            out.push_str(line);
            out.push_str(eol);
            continue;
        }
        let indent = &line[..line.len() - body.len()];
        // Two columns in: past the bullet of a "- " item, or a hanging indent.
        let hanging = format!("{indent}  ");
        let options = textwrap::Options::new(max)
            .initial_indent(indent)
            .subsequent_indent(&hanging)
            // Names such as `index-finger-phalanx-distal` stay whole: break at spaces only.
            .word_splitter(textwrap::WordSplitter::NoHyphenation)
            .break_words(true);
        out.push_str(&textwrap::fill(body, options));
        out.push_str(eol);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn widest(text: &str) -> usize {
        text.lines().map(|l| l.chars().count()).max().unwrap_or(0)
    }

    fn grid() -> Grid {
        let mut g = Grid::new()
            .col("name", Align::Left, Give::Keep)
            .col("value", Align::Right, Give::Keep)
            .col("spare", Align::Right, Give::Drop(2))
            .col("extra", Align::Right, Give::Drop(1))
            .col("words", Align::Left, Give::Wrap);
        g.row(vec![
            "alpha".into(),
            "1.0000".into(),
            "[0.1000, 0.2000]".into(),
            "[0.3000, 0.4000]".into(),
            "a sentence long enough to need wrapping when the table is narrow".into(),
        ]);
        g
    }

    #[test]
    fn wide_shows_every_column_on_one_line() {
        let mut hidden = Hidden::new();
        let t = grid().render(Width::Wide, 0, &mut hidden);
        assert_eq!(t.lines().count(), 3, "{t}");
        for h in ["name", "value", "spare", "extra", "words"] {
            assert!(t.contains(h), "{t}");
        }
        assert!(hidden.is_empty());
        assert_eq!(hidden.note(Width::Wide), "");
    }

    #[test]
    fn columns_drop_by_rank_then_sentences_wrap() {
        // Natural width: 1 + (5+3) + (6+3) + (16+3) * 2 + (64+3) = 123.
        let mut hidden = Hidden::new();
        let t = grid().render(Width::fit(105), 0, &mut hidden);
        assert!(widest(&t) <= 105, "{t}");
        assert!(!t.contains("extra") && t.contains("spare"), "{t}");
        assert_eq!(hidden.0, ["extra"]);
        let mut hidden = Hidden::new();
        let t = grid().render(Width::fit(60), 2, &mut hidden);
        assert!(widest(&t) <= 60, "{t}");
        assert!(t.lines().all(|l| l.starts_with("  |")), "{t}");
        assert_eq!(hidden.0, ["extra", "spare"]);
        // The sentence wrapped; the number did not.
        assert!(t.contains("1.0000"), "{t}");
        assert!(t.lines().count() > 3, "{t}");
        let note = hidden.note(Width::fit(60));
        assert!(
            note.contains("Not shown to fit 60 columns: extra, spare"),
            "{note}"
        );
        assert!(widest(&note) <= 60, "{note}");
    }

    #[test]
    fn text_wraps_but_tables_do_not() {
        let text = format!(
            "{}\n| {} |\n  - {}\n",
            "word ".repeat(30).trim_end(),
            "x".repeat(120),
            "item ".repeat(30).trim_end()
        );
        let out = fit_text(&text, Width::fit(50));
        for l in out.lines() {
            assert!(l.chars().count() <= 50 || l.starts_with('|'), "{l}");
        }
        assert!(out.contains(&format!("| {} |", "x".repeat(120))));
        // Continuations are indented: two more, after the bullet.
        assert!(out.lines().any(|l| l.starts_with("    item")), "{out}");
        assert!(out.lines().any(|l| l.starts_with("  word")), "{out}");
        assert_eq!(fit_text(&text, Width::Wide), text);
        assert_eq!(Width::fit(3), Width::Fit(Width::MIN));
    }
}
