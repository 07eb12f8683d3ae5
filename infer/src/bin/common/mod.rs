//! What the command-line tools share.

use serde::de::DeserializeOwned;
use std::path::Path;

/// `T` read from a JSON file (fields left out keep their defaults where
/// `T` says so), or `T::default()` when no file is given; errors name the file.
pub fn json_or_default<T: DeserializeOwned + Default>(path: Option<&Path>) -> Result<T, String> {
    let Some(path) = path else {
        return Ok(T::default());
    };
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
}
