//! What every dataset file shares, whatever machine its samples are of: a
//! file written under a temporary name and renamed when whole, a
//! `dataset_gen` metadata record, JSON messages with JSON Schemas, and a
//! reader that checks both magics, the footer and every chunk's CRC.

use super::METADATA_NAME;
use crate::error::Error;
use mcap::records::{MessageHeader, Metadata};
use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// An MCAP file being written to `path.tmp`.
pub struct McapFile {
    pub(crate) inner: mcap::Writer<BufWriter<File>>,
    sequence: u32,
    tmp: PathBuf,
    path: PathBuf,
}

impl std::fmt::Debug for McapFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("McapFile")
            .field("path", &self.path)
            .finish()
    }
}

impl McapFile {
    /// Starts `path` (written as `path.tmp` until [`finish`](Self::finish)),
    /// uncompressed, with no profile.
    pub fn create(path: &Path) -> Result<Self, Error> {
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(".tmp");
        let tmp = PathBuf::from(tmp);
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        }
        let file = File::create(&tmp).map_err(|e| Error::io(&tmp, e))?;
        let opts = mcap::WriteOptions::new().compression(None).profile("");
        let inner = opts.create(BufWriter::new(file))?;
        Ok(McapFile {
            inner,
            sequence: 0,
            tmp,
            path: path.to_path_buf(),
        })
    }

    /// Adds a JSON schema; returns its id.
    pub fn add_schema(&mut self, name: &str, schema: &serde_json::Value) -> Result<u16, Error> {
        Ok(self
            .inner
            .add_schema(name, "jsonschema", &serde_json::to_vec(schema)?)?)
    }

    /// Adds a JSON channel; returns its id.
    pub fn add_channel(
        &mut self,
        schema: u16,
        topic: &str,
        metadata: &BTreeMap<String, String>,
    ) -> Result<u16, Error> {
        Ok(self.inner.add_channel(schema, topic, "json", metadata)?)
    }

    /// Writes the `dataset_gen` metadata record.
    pub fn write_metadata(&mut self, metadata: BTreeMap<String, String>) -> Result<(), Error> {
        self.inner.write_metadata(&Metadata {
            name: METADATA_NAME.to_string(),
            metadata,
        })?;
        Ok(())
    }

    /// Writes one message, numbered in file order, published at its log time.
    pub fn write(&mut self, channel: u16, log_time: u64, data: &[u8]) -> Result<(), Error> {
        let header = MessageHeader {
            channel_id: channel,
            sequence: self.sequence,
            log_time,
            publish_time: log_time,
        };
        self.sequence = self.sequence.wrapping_add(1);
        self.inner.write_to_known_channel(&header, data)?;
        Ok(())
    }

    /// Writes the summary and renames the file to its final name.
    pub fn finish(mut self) -> Result<PathBuf, Error> {
        self.inner.finish()?;
        let buf = self.inner.into_inner();
        let file = buf
            .into_inner()
            .map_err(|e| Error::io(&self.tmp, e.into_error()))?;
        file.sync_all().map_err(|e| Error::io(&self.tmp, e))?;
        drop(file);
        std::fs::rename(&self.tmp, &self.path).map_err(|e| Error::io(&self.path, e))?;
        Ok(self.path)
    }
}

pub(crate) fn corrupt(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::CorruptMcap {
        path: path.to_path_buf(),
        detail: e.to_string(),
    }
}

/// Reads the whole file and checks both magics and the footer.
fn load(path: &Path) -> Result<Vec<u8>, Error> {
    let buf = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    const MAGIC: &[u8] = b"\x89MCAP0\r\n";
    if buf.len() < MAGIC.len() || &buf[..MAGIC.len()] != MAGIC {
        return Err(corrupt(path, "missing MCAP magic at the start"));
    }
    if buf.len() < 2 * MAGIC.len() || &buf[buf.len() - MAGIC.len()..] != MAGIC {
        return Err(Error::TruncatedMcap {
            path: path.to_path_buf(),
        });
    }
    mcap::read::footer(&buf).map_err(|e| corrupt(path, e))?;
    Ok(buf)
}

/// One message as stored, with its topic.
#[derive(Debug, Clone, PartialEq)]
pub struct TopicMessage {
    pub topic: String,
    pub log_time: u64,
    pub data: Vec<u8>,
}

/// The `dataset_gen` metadata record and every message of a file, in file order.
pub fn read_messages(path: &Path) -> Result<(BTreeMap<String, String>, Vec<TopicMessage>), Error> {
    let buf = load(path)?;
    let mut metadata = None;
    for rec in mcap::read::LinearReader::new(&buf).map_err(|e| corrupt(path, e))? {
        if let mcap::records::Record::Metadata(m) = rec.map_err(|e| corrupt(path, e))?
            && m.name == METADATA_NAME
        {
            metadata = Some(m.metadata);
        }
    }
    let metadata = metadata.ok_or_else(|| Error::BadDataset {
        path: path.to_path_buf(),
        detail: format!("no `{METADATA_NAME}` metadata record: not a dataset_gen file"),
    })?;
    let mut out = Vec::new();
    // Chunk CRCs are written by our writer; checking them catches flipped bytes anywhere in the data.
    let stream =
        mcap::MessageStream::new_with_options(&buf, mcap::read::Options::ValidateChunkCrcs.into())
            .map_err(|e| corrupt(path, e))?;
    for m in stream {
        let m = m.map_err(|e| corrupt(path, e))?;
        out.push(TopicMessage {
            topic: m.channel.topic.clone(),
            log_time: m.log_time,
            data: m.data.into_owned(),
        });
    }
    Ok((metadata, out))
}
