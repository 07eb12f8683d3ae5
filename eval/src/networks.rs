//! The two trained networks as the planner loads them
//! (`network_downward.json`, `network_backward.json`, format `dig-network/2`).

use crate::error::EvalError;
use infer::network::NetworkFile;
use infer::{DigType, NetworkPair};
use std::path::{Path, PathBuf};

/// Both networks, read from one directory.
#[derive(Debug, Clone)]
pub struct Networks {
    pub dir: PathBuf,
    pub downward: NetworkFile,
    pub backward: NetworkFile,
}

impl Networks {
    /// Reads and checks `network_<type>.json` of both dig types in `dir`.
    pub fn load(dir: &Path) -> Result<Self, EvalError> {
        let read = |kind: DigType| -> Result<NetworkFile, EvalError> {
            let path = dir.join(format!("network_{}.json", kind.name()));
            let bad = |detail: String| EvalError::Network {
                path: path.clone(),
                detail,
            };
            let text = std::fs::read_to_string(&path)
                .map_err(|e| bad(format!("{e} (trained networks are needed: run `eval pipeline`, or give the directory that holds them)")))?;
            let file = NetworkFile::from_json(&text).map_err(bad)?;
            if file.dig_type != kind {
                return Err(bad(format!(
                    "holds a {} network, expected {kind}",
                    file.dig_type
                )));
            }
            Ok(file)
        };
        Ok(Networks {
            dir: dir.to_path_buf(),
            downward: read(DigType::Downward)?,
            backward: read(DigType::Backward)?,
        })
    }

    /// The planner's predictor over these weights.
    pub fn pair(&self) -> Result<NetworkPair<'_>, EvalError> {
        Ok(NetworkPair {
            downward: self.downward.network()?,
            backward: self.backward.network()?,
        })
    }
}
