//! `phalanx schema` (hidden): writes the JSON Schema of every JSON document
//! phalanx writes, for `docs/schema/`; the list is [`crate::report::schema::DOCUMENTS`].

use crate::error::Error;
use crate::report::{schema, writer};
use std::path::PathBuf;

/// Write the JSON Schema of every JSON document phalanx writes (for docs/schema/)
#[derive(clap::Args, Debug)]
#[command(after_help = "Examples:\n  phalanx schema\n  phalanx schema --out /tmp/schema")]
pub(crate) struct Args {
    /// Directory to write <document>.schema.json into
    #[arg(long, value_name = "DIR", default_value = "docs/schema")]
    out: PathBuf,
}

pub(crate) fn run(args: &Args) -> Result<i32, Error> {
    writer::write_all(&args.out, &schema::files()?)?;
    Ok(0)
}
