//! The READMEs' `cargo run -p CRATE -- …` commands name no binary, so each
//! such crate must have one binary or a `default-run`: otherwise cargo
//! stops with "could not determine which binary to run" before the
//! command starts (it did for `dataset_gen` and `train`). Read from the
//! files, so the check costs no build.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("eval sits in the workspace")
        .to_path_buf()
}

/// The top README, every crate's README and every crate's docs.
fn documents(root: &Path) -> Vec<PathBuf> {
    let mut found = vec![root.join("README.md")];
    for entry in fs::read_dir(root)
        .expect("the workspace is readable")
        .flatten()
    {
        let crate_dir = entry.path();
        if !crate_dir.join("Cargo.toml").is_file() {
            continue;
        }
        found.push(crate_dir.join("README.md"));
        if let Ok(docs) = fs::read_dir(crate_dir.join("docs")) {
            found.extend(docs.flatten().map(|d| d.path()));
        }
    }
    found.retain(|p| p.is_file() && p.extension().is_some_and(|e| e == "md"));
    found
}

/// The crates that `cargo run [--release] -p CRATE -- …` runs without
/// `--bin` or `--example`, with the document and line that names each.
fn default_runs(root: &Path) -> Vec<(String, String)> {
    let mut runs = Vec::new();
    for doc in documents(root) {
        let text = fs::read_to_string(&doc).expect("a document is UTF-8");
        for (number, line) in text.lines().enumerate() {
            for command in line.split("cargo run ").skip(1) {
                let words: Vec<&str> = command.split_whitespace().collect();
                let Some(end) = words.iter().position(|w| *w == "--") else {
                    continue;
                };
                let flags = &words[..end];
                if flags.iter().any(|w| *w == "--bin" || *w == "--example") {
                    continue;
                }
                let crate_name = flags
                    .iter()
                    .position(|w| *w == "-p")
                    .and_then(|p| flags.get(p + 1));
                if let Some(name) = crate_name {
                    let at = format!("{}:{}", doc.display(), number + 1);
                    runs.push((name.to_string(), at));
                }
            }
        }
    }
    runs
}

/// The crate's binaries (`src/main.rs`, `src/bin/*.rs` and `[[bin]]`
/// names) and its `default-run`, if any.
fn binaries(crate_dir: &Path, name: &str) -> (BTreeSet<String>, Option<String>) {
    let manifest = fs::read_to_string(crate_dir.join("Cargo.toml")).expect("a manifest");
    let mut names = BTreeSet::new();
    if crate_dir.join("src/main.rs").is_file() {
        names.insert(name.to_string());
    }
    if let Ok(bins) = fs::read_dir(crate_dir.join("src/bin")) {
        for bin in bins.flatten() {
            let path = bin.path();
            if path.extension().is_some_and(|e| e == "rs") {
                names.insert(path.file_stem().unwrap().to_string_lossy().into_owned());
            }
        }
    }
    let manifest: toml::Table = manifest.parse().expect("a manifest is TOML");
    let bins = manifest.get("bin").and_then(|b| b.as_array());
    for bin in bins.into_iter().flatten() {
        if let Some(n) = bin.get("name").and_then(|n| n.as_str()) {
            names.insert(n.to_string());
        }
    }
    let default_run = manifest
        .get("package")
        .and_then(|p| p.get("default-run"))
        .and_then(|d| d.as_str())
        .map(str::to_string);
    (names, default_run)
}

#[test]
fn every_readme_cargo_run_finds_its_binary() {
    let root = workspace();
    let runs = default_runs(&root);
    assert!(
        runs.iter().any(|(c, _)| c == "eval"),
        "the top README's first command is read: {runs:?}"
    );
    for (name, at) in runs {
        let (names, default_run) = binaries(&root.join(&name), &name);
        let ok = match &default_run {
            Some(d) => names.contains(d),
            None => names.len() == 1,
        };
        assert!(
            ok,
            "{at}: `cargo run -p {name} --` needs one binary or a default-run \
             naming one; {name} has {names:?}, default-run {default_run:?}"
        );
    }
}
