//! `signorini schema`: the JSON Schemas of the program's documents.

use anyhow::{Context, Result};
use signorini::exit::Exit;

use crate::console::Console;

pub(crate) fn schema(document: signorini::contract::Document) -> Result<Exit> {
    let text = serde_json::to_string_pretty(&signorini::contract::schema(document))
        .context("serialising the schema")?;
    let mut con = Console::new();
    con.line(text)?;
    con.finish()?;
    Ok(Exit::Success)
}
