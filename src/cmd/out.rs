//! The one writer to standard output: a closed pipe (e.g. `| head`) is not an error.

use crate::error::Error;
use crate::report::layout::Width;
use std::io::{IsTerminal, StdoutLock, Write};
use std::path::Path;

/// The width terminal tables and text are fitted to: everything with `--wide`;
/// else `COLUMNS` when set to a whole number (as GNU tools read it); else the
/// terminal's width when standard output is one; else [`Width::DEFAULT`].
pub(crate) fn width(wide: bool) -> Width {
    if wide {
        return Width::Wide;
    }
    let columns = std::env::var("COLUMNS")
        .ok()
        .and_then(|c| c.trim().parse::<usize>().ok())
        .filter(|&c| c > 0);
    if let Some(c) = columns {
        return Width::fit(c);
    }
    let stdout = std::io::stdout();
    if stdout.is_terminal()
        && let Some((terminal_size::Width(w), _)) = terminal_size::terminal_size_of(&stdout)
    {
        return Width::fit(usize::from(w));
    }
    Width::fit(Width::DEFAULT)
}

/// Writes to standard output.
pub(crate) fn print(bytes: &[u8]) -> Result<(), Error> {
    let mut out = std::io::stdout().lock();
    match out.write_all(bytes).and_then(|_| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(Error::write(Path::new("<stdout>"))(e)),
        Ok(()) => Ok(()),
    }
}

/// Streams a document to standard output (a large one is not held in memory).
pub(crate) fn stream(
    write: impl FnOnce(StdoutLock<'static>) -> Result<(), Error>,
) -> Result<(), Error> {
    match write(std::io::stdout().lock()) {
        Err(e) if is_broken_pipe(&e) => Ok(()),
        other => other,
    }
}

/// True when an error comes from writing to a closed pipe.
fn is_broken_pipe(e: &(dyn std::error::Error + 'static)) -> bool {
    let mut cur: Option<&(dyn std::error::Error + 'static)> = Some(e);
    while let Some(err) = cur {
        if err
            .downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
            || err
                .downcast_ref::<serde_json::Error>()
                .and_then(serde_json::Error::io_error_kind)
                == Some(std::io::ErrorKind::BrokenPipe)
        {
            return true;
        }
        cur = err.source();
    }
    false
}
