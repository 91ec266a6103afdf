//! A walk over an MCAP file's records before the `mcap` crate reads it: every declared length
//! (of a record, and of the strings, maps and byte arrays inside the records the crate slices
//! itself) is checked against the bytes actually present, at the top level and inside
//! uncompressed chunks. The `mcap` crate 0.26 trusts some of them and panics on a length near
//! `u64::MAX` (the smallest such file is 17 bytes: the magic, an opcode, eight 0xFF bytes); no
//! length reaches it unchecked. Nothing is allocated here.

use super::error::{at, ImportError};

/// Record opcodes (MCAP specification).
mod op {
    pub const HEADER: u8 = 0x01;
    pub const FOOTER: u8 = 0x02;
    pub const SCHEMA: u8 = 0x03;
    pub const CHANNEL: u8 = 0x04;
    pub const MESSAGE: u8 = 0x05;
    pub const CHUNK: u8 = 0x06;
    pub const MESSAGE_INDEX: u8 = 0x07;
    pub const ATTACHMENT: u8 = 0x09;
    pub const METADATA: u8 = 0x0C;
}

/// The record names, for messages.
fn name(opcode: u8) -> &'static str {
    match opcode {
        0x01 => "Header",
        0x02 => "Footer",
        0x03 => "Schema",
        0x04 => "Channel",
        0x05 => "Message",
        0x06 => "Chunk",
        0x07 => "Message Index",
        0x08 => "Chunk Index",
        0x09 => "Attachment",
        0x0A => "Attachment Index",
        0x0B => "Statistics",
        0x0C => "Metadata",
        0x0D => "Metadata Index",
        0x0E => "Summary Offset",
        0x0F => "Data End",
        _ => "unknown",
    }
}

/// What the walk found: how many Message records (top level and in chunks).
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Walk {
    /// Message records.
    pub messages: usize,
}

/// A cursor over one record's body; `base` is the body's offset in the file, for messages.
struct Body<'a> {
    bytes: &'a [u8],
    pos: usize,
    base: usize,
    opcode: u8,
    record_at: usize,
}

impl<'a> Body<'a> {
    fn fail(&self, field: &str, need: u64, file: &str) -> ImportError {
        at(
            file,
            format!(
                "MCAP {} record at byte {}, field {field} (byte {})",
                name(self.opcode),
                self.record_at,
                self.base + self.pos
            ),
            format!(
                "it declares {need} bytes but the record has {} left: expected lengths that fit in their record",
                self.bytes.len() - self.pos
            ),
        )
    }

    fn take(&mut self, n: u64, field: &str, file: &str) -> Result<&'a [u8], ImportError> {
        let left = (self.bytes.len() - self.pos) as u64;
        if n > left {
            return Err(self.fail(field, n, file));
        }
        let out = &self.bytes[self.pos..self.pos + n as usize];
        self.pos += n as usize;
        Ok(out)
    }

    fn u32(&mut self, field: &str, file: &str) -> Result<u32, ImportError> {
        let b = self.take(4, field, file)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    fn u64(&mut self, field: &str, file: &str) -> Result<u64, ImportError> {
        let b = self.take(8, field, file)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Ok(u64::from_le_bytes(a))
    }

    /// A `uint32`-prefixed string, map or array: its bytes.
    fn prefixed32(&mut self, field: &str, file: &str) -> Result<&'a [u8], ImportError> {
        let n = self.u32(field, file)?;
        self.take(n as u64, field, file)
    }

    /// A map of strings to strings: its byte length, then key and value strings that fill it.
    fn string_map(&mut self, field: &str, file: &str) -> Result<(), ImportError> {
        let start = self.pos;
        let map = self.prefixed32(field, file)?;
        let mut inner = Body {
            bytes: map,
            pos: 0,
            base: self.base + start + 4,
            opcode: self.opcode,
            record_at: self.record_at,
        };
        while inner.pos < map.len() {
            inner.prefixed32(field, file)?;
            inner.prefixed32(field, file)?;
        }
        Ok(())
    }
}

/// Checks the records of `bytes` (which start with the MCAP magic).
pub(crate) fn check(bytes: &[u8], file: &str) -> Result<Walk, ImportError> {
    let mut walk = Walk::default();
    records(bytes, 8, bytes.len(), false, file, &mut walk)?;
    Ok(walk)
}

/// Walks the records in `bytes[from..to]`; `in_chunk` for the records inside a chunk.
fn records(
    bytes: &[u8],
    from: usize,
    to: usize,
    in_chunk: bool,
    file: &str,
    walk: &mut Walk,
) -> Result<(), ImportError> {
    let mut pos = from;
    while pos < to {
        let left = to - pos;
        if left < 9 {
            if in_chunk {
                return Err(at(
                    file,
                    format!("MCAP chunk, byte {pos}"),
                    format!("{left} bytes are left in the chunk: expected a record (an opcode and an 8-byte length)"),
                ));
            }
            // The end magic, or a file cut short: the `mcap` crate says which.
            return Ok(());
        }
        let opcode = bytes[pos];
        let len = declared_length(bytes, pos, left, in_chunk, file)?;
        let body_at = pos + 9;
        let end = body_at + len as usize;
        let mut body = Body {
            bytes: &bytes[body_at..end],
            pos: 0,
            base: body_at,
            opcode,
            record_at: pos,
        };
        match opcode {
            op::CHUNK if in_chunk => {
                return Err(at(
                    file,
                    format!("MCAP Chunk record at byte {pos}"),
                    "a chunk inside a chunk: expected records other than chunks in a chunk",
                ));
            }
            op::CHUNK => chunk(bytes, &mut body, file, walk)?,
            op::FOOTER if !in_chunk => return Ok(()),
            _ => fields(&mut body, file, walk)?,
        }
        pos = end;
    }
    Ok(())
}

/// The length the record at `pos` declares, checked against the `left` bytes from there.
fn declared_length(
    bytes: &[u8],
    pos: usize,
    left: usize,
    in_chunk: bool,
    file: &str,
) -> Result<u64, ImportError> {
    let opcode = bytes[pos];
    let mut len = [0u8; 8];
    len.copy_from_slice(&bytes[pos + 1..pos + 9]);
    let len = u64::from_le_bytes(len);
    if len > (left - 9) as u64 {
        return Err(at(
            file,
            format!(
                "MCAP {} record (opcode 0x{opcode:02x}) at byte {pos}{}",
                name(opcode),
                if in_chunk { " in a chunk" } else { "" }
            ),
            format!(
                "it declares {len} bytes but only {} follow{}: expected a length that fits (the file may be cut short or corrupted)",
                left - 9,
                if in_chunk { " in the chunk" } else { " in the file" }
            ),
        ));
    }
    Ok(len)
}

/// Checks the lengths inside a record other than a chunk (those the `mcap` crate slices
/// itself); counts the messages.
fn fields(body: &mut Body, file: &str, walk: &mut Walk) -> Result<(), ImportError> {
    match body.opcode {
        op::HEADER => {
            body.prefixed32("profile", file)?;
            body.prefixed32("library", file)?;
        }
        op::SCHEMA => {
            body.take(2, "id", file)?;
            body.prefixed32("name", file)?;
            body.prefixed32("encoding", file)?;
            body.prefixed32("data", file)?;
        }
        op::CHANNEL => {
            body.take(4, "id and schema_id", file)?;
            body.prefixed32("topic", file)?;
            body.prefixed32("message_encoding", file)?;
            body.string_map("metadata", file)?;
        }
        op::MESSAGE => {
            body.take(22, "channel_id, sequence, log_time, publish_time", file)?;
            walk.messages += 1;
        }
        op::MESSAGE_INDEX => {
            body.take(2, "channel_id", file)?;
            body.prefixed32("records", file)?;
        }
        op::METADATA => {
            body.prefixed32("name", file)?;
            body.string_map("metadata", file)?;
        }
        op::ATTACHMENT => {
            body.take(16, "log_time and create_time", file)?;
            body.prefixed32("name", file)?;
            body.prefixed32("media_type", file)?;
            let n = body.u64("data (length)", file)?;
            body.take(n, "data", file)?;
            body.take(4, "crc", file)?;
        }
        _ => {}
    }
    Ok(())
}

/// Checks a top-level chunk: uncompressed, its size right, and the records inside it.
fn chunk(bytes: &[u8], body: &mut Body, file: &str, walk: &mut Walk) -> Result<(), ImportError> {
    let (pos, body_at) = (body.record_at, body.base);
    body.take(16, "message_start_time and message_end_time", file)?;
    let uncompressed = body.u64("uncompressed_size", file)?;
    body.take(4, "uncompressed_crc", file)?;
    let compression = body.prefixed32("compression", file)?;
    let n = body.u64("records (length)", file)?;
    let records_at = body.pos;
    body.take(n, "records", file)?;
    if !compression.is_empty() {
        return Err(at(
            file,
            format!("MCAP Chunk record at byte {pos}, field compression"),
            format!(
                "compression {:?}: expected uncompressed chunks (this build reads no compression; write the recording again without it)",
                super::sane::quote(&String::from_utf8_lossy(compression))
            ),
        ));
    }
    if uncompressed != n {
        return Err(at(
            file,
            format!("MCAP Chunk record at byte {pos}, field uncompressed_size"),
            format!("{uncompressed} bytes: expected the size of the uncompressed records, {n}"),
        ));
    }
    let inner = body_at + records_at;
    records(bytes, inner, inner + n as usize, true, file, walk)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mcap(records: &[u8]) -> Vec<u8> {
        let mut b = b"\x89MCAP0\r\n".to_vec();
        b.extend_from_slice(records);
        b
    }

    #[test]
    fn lengths_beyond_the_file_are_refused_with_the_offset() {
        let mut r = vec![0x01];
        r.extend_from_slice(&[0xFF; 8]);
        let e = check(&mcap(&r), "f.mcap").unwrap_err().to_string();
        assert!(
            e.contains("f.mcap: MCAP Header record (opcode 0x01) at byte 8"),
            "{e}"
        );
        assert!(
            e.contains("declares 18446744073709551615 bytes but only 0 follow"),
            "{e}"
        );
    }

    #[test]
    fn an_attachment_ending_before_its_crc_is_refused() {
        let mut body = vec![0u8; 16];
        body.extend_from_slice(&1u32.to_le_bytes());
        body.push(b'a');
        body.extend_from_slice(&0u32.to_le_bytes());
        body.extend_from_slice(&2u64.to_le_bytes());
        body.extend_from_slice(b"xy");
        let mut r = vec![0x09];
        r.extend_from_slice(&(body.len() as u64).to_le_bytes());
        r.extend_from_slice(&body);
        let e = check(&mcap(&r), "f").unwrap_err().to_string();
        assert!(e.contains("Attachment record at byte 8, field crc"), "{e}");
    }
}
