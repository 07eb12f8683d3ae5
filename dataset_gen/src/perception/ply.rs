//! PLY point clouds: a small reader (ASCII and binary little-endian; the
//! `vertex` element's float or double `x`, `y`, `z`; other properties and
//! elements skipped, list properties refused in the vertex element) and a
//! binary writer. `ply-rs`, the usual crate, has had no release since 2020
//! and reads whole files into generic property maps; this reader is ~150
//! lines with an error that names the problem.

use super::error::PerceptionError;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Format {
    Ascii,
    BinaryLe,
}

/// A scalar property type and its size in bytes.
fn scalar_size(ty: &str) -> Option<usize> {
    Some(match ty {
        "char" | "uchar" | "int8" | "uint8" => 1,
        "short" | "ushort" | "int16" | "uint16" => 2,
        "int" | "uint" | "int32" | "uint32" | "float" | "float32" => 4,
        "double" | "float64" => 8,
        _ => return None,
    })
}

struct Element {
    name: String,
    count: usize,
    /// (name, type) of each scalar property; None type for a list.
    props: Vec<(String, Option<String>)>,
}

/// Reads the x, y, z of every vertex of a PLY file.
pub fn read_ply(path: &Path) -> Result<Vec<[f32; 3]>, PerceptionError> {
    let file = std::fs::File::open(path).map_err(|e| PerceptionError::io(path, e))?;
    let bad = |detail: String| PerceptionError::BadPly {
        path: path.to_path_buf(),
        detail,
    };
    let mut r = BufReader::new(file);
    let mut line = String::new();
    let next_line =
        |r: &mut BufReader<std::fs::File>, line: &mut String| -> Result<bool, PerceptionError> {
            line.clear();
            let n = r
                .read_line(line)
                .map_err(|e| PerceptionError::io(path, e))?;
            Ok(n > 0)
        };
    if !next_line(&mut r, &mut line)? || line.trim_end() != "ply" {
        return Err(bad("does not start with `ply`".into()));
    }
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        if !next_line(&mut r, &mut line)? {
            return Err(bad("header has no `end_header`".into()));
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["end_header"] => break,
            ["format", "ascii", _] => format = Some(Format::Ascii),
            ["format", "binary_little_endian", _] => format = Some(Format::BinaryLe),
            ["format", f, _] => {
                return Err(bad(format!(
                    "format `{f}` is not supported (ascii or binary_little_endian)"
                )));
            }
            ["comment", ..] | ["obj_info", ..] | [] => {}
            ["element", name, count] => elements.push(Element {
                name: name.to_string(),
                count: count
                    .parse()
                    .map_err(|_| bad(format!("element {name} has count `{count}`")))?,
                props: Vec::new(),
            }),
            ["property", "list", _, _, name] => match elements.last_mut() {
                Some(e) => e.props.push((name.to_string(), None)),
                None => return Err(bad("property before any element".into())),
            },
            ["property", ty, name] => {
                if scalar_size(ty).is_none() {
                    return Err(bad(format!("property {name} has unknown type `{ty}`")));
                }
                match elements.last_mut() {
                    Some(e) => e.props.push((name.to_string(), Some(ty.to_string()))),
                    None => return Err(bad("property before any element".into())),
                }
            }
            _ => {
                return Err(bad(format!(
                    "header line `{}` is not understood",
                    line.trim_end()
                )));
            }
        }
    }
    let format = format.ok_or_else(|| bad("header has no `format` line".into()))?;
    let vi = elements
        .iter()
        .position(|e| e.name == "vertex")
        .ok_or_else(|| bad("no `vertex` element".into()))?;
    // Elements before the vertices must be skipped; only binary files with
    // scalar properties can be skipped here, and real scans put vertices first.
    if vi != 0 {
        return Err(bad("the `vertex` element must come first".into()));
    }
    let v = &elements[0];
    if v.props.iter().any(|(_, t)| t.is_none()) {
        return Err(bad("the vertex element has a list property".into()));
    }
    let col = |axis: &str| {
        v.props
            .iter()
            .position(|(n, _)| n == axis)
            .ok_or_else(|| bad(format!("vertex has no `{axis}` property")))
    };
    let cols = [col("x")?, col("y")?, col("z")?];
    for &c in &cols {
        let ty = v.props[c].1.as_deref().unwrap_or("");
        if !matches!(ty, "float" | "float32" | "double" | "float64") {
            return Err(bad(format!(
                "vertex property {} is `{ty}`, not float or double",
                v.props[c].0
            )));
        }
    }
    let mut points = Vec::with_capacity(v.count.min(50_000_000));
    match format {
        Format::Ascii => {
            for i in 0..v.count {
                if !next_line(&mut r, &mut line)? {
                    return Err(bad(format!("file ends after {i} of {} vertices", v.count)));
                }
                let words: Vec<&str> = line.split_whitespace().collect();
                if words.len() != v.props.len() {
                    return Err(bad(format!(
                        "vertex {i} has {} values, {} expected",
                        words.len(),
                        v.props.len()
                    )));
                }
                let mut p = [0.0f32; 3];
                for (k, &c) in cols.iter().enumerate() {
                    p[k] = words[c]
                        .parse()
                        .map_err(|_| bad(format!("vertex {i}: `{}` is not a number", words[c])))?;
                }
                points.push(p);
            }
        }
        Format::BinaryLe => {
            let sizes: Vec<usize> = v
                .props
                .iter()
                .map(|(_, t)| scalar_size(t.as_deref().unwrap_or("")).unwrap_or(0))
                .collect();
            let offsets: Vec<usize> = sizes
                .iter()
                .scan(0, |o, s| {
                    let at = *o;
                    *o += s;
                    Some(at)
                })
                .collect();
            let stride: usize = sizes.iter().sum();
            let mut rec = vec![0u8; stride];
            for i in 0..v.count {
                r.read_exact(&mut rec)
                    .map_err(|_| bad(format!("file ends after {i} of {} vertices", v.count)))?;
                let mut p = [0.0f32; 3];
                for (k, &c) in cols.iter().enumerate() {
                    let b = &rec[offsets[c]..offsets[c] + sizes[c]];
                    p[k] = match sizes[c] {
                        4 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
                        _ => f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]])
                            as f32,
                    };
                }
                points.push(p);
            }
        }
    }
    Ok(points)
}

/// Writes points as a binary little-endian PLY with float x, y, z.
pub fn write_ply(path: &Path, points: &[[f32; 3]]) -> Result<(), PerceptionError> {
    let file = std::fs::File::create(path).map_err(|e| PerceptionError::io(path, e))?;
    let mut w = std::io::BufWriter::new(file);
    let header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment dataset_gen perceive\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
        points.len()
    );
    let io = |e| PerceptionError::io(path, e);
    w.write_all(header.as_bytes()).map_err(io)?;
    for p in points {
        for v in p {
            w.write_all(&v.to_le_bytes()).map_err(io)?;
        }
    }
    w.flush().map_err(io)
}
