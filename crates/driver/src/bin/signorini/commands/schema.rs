//! `signorini schema`: the JSON Schemas of the program's documents.

use anyhow::{Context, Result};
use signorini::exit::Exit;

use crate::console::Console;

/// `signorini schema DOCUMENT`: which schema to print.
#[derive(clap::Args)]
pub(crate) struct SchemaArgs {
    /// Which document.
    #[arg(value_enum)]
    pub(crate) document: signorini::contract::Document,
}

pub(crate) fn schema(args: &SchemaArgs) -> Result<Exit> {
    let text = serde_json::to_string_pretty(&signorini::contract::schema(args.document))
        .context("serialising the schema")?;
    let mut con = Console::new();
    con.line(text)?;
    con.finish()?;
    Ok(Exit::Success)
}
