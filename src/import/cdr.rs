//! A reader of OMG CDR (version 1, as ROS 2 writes it): the 4-byte encapsulation header
//! (`00 00` big endian, `00 01` little endian, then two option bytes), then the fields, each
//! aligned to its own size (at most 8) counted from the end of the header. Strings are a
//! `uint32` length including the terminating NUL, then the bytes.

/// A CDR decoding failure: what was being read and at which byte.
#[derive(Clone, Debug, PartialEq)]
pub struct CdrError {
    /// Byte offset in the message (from its start, header included).
    pub offset: usize,
    /// What went wrong and what was expected.
    pub message: String,
}

/// A cursor over one CDR-encoded message.
pub struct CdrReader<'a> {
    bytes: &'a [u8],
    /// Position, counted from the start of `bytes`.
    pos: usize,
    little: bool,
}

const HEADER: usize = 4;

impl<'a> CdrReader<'a> {
    /// Reads the encapsulation header.
    pub fn new(bytes: &'a [u8]) -> Result<Self, CdrError> {
        if bytes.len() < HEADER {
            return Err(CdrError {
                offset: 0,
                message: format!(
                    "{} bytes: expected at least the 4-byte CDR encapsulation header",
                    bytes.len()
                ),
            });
        }
        let little = match (bytes[0], bytes[1]) {
            (0, 0) => false,
            (0, 1) => true,
            (a, b) => {
                return Err(CdrError {
                    offset: 0,
                    message: format!(
                        "encapsulation {a:02x} {b:02x}: expected plain CDR, 00 00 (big endian) or 00 01 (little endian)"
                    ),
                })
            }
        };
        Ok(Self {
            bytes,
            pos: HEADER,
            little,
        })
    }

    fn take<const N: usize>(&mut self, what: &str) -> Result<[u8; N], CdrError> {
        let aligned = HEADER + (self.pos - HEADER).div_ceil(N) * N;
        let end = aligned.checked_add(N).filter(|&e| e <= self.bytes.len());
        let Some(end) = end else {
            return Err(CdrError {
                offset: self.pos,
                message: format!(
                    "the message ends at byte {}: expected {what} ({N} bytes)",
                    self.bytes.len()
                ),
            });
        };
        let mut out = [0u8; N];
        out.copy_from_slice(&self.bytes[aligned..end]);
        if self.little != cfg!(target_endian = "little") {
            out.reverse();
        }
        self.pos = end;
        Ok(out)
    }

    /// A `uint8`.
    pub fn u8(&mut self, what: &str) -> Result<u8, CdrError> {
        Ok(self.take::<1>(what)?[0])
    }

    /// A `uint32`.
    pub fn u32(&mut self, what: &str) -> Result<u32, CdrError> {
        Ok(u32::from_ne_bytes(self.take::<4>(what)?))
    }

    /// An `int32`.
    pub fn i32(&mut self, what: &str) -> Result<i32, CdrError> {
        Ok(i32::from_ne_bytes(self.take::<4>(what)?))
    }

    /// A `float32`.
    pub fn f32(&mut self, what: &str) -> Result<f32, CdrError> {
        Ok(f32::from_ne_bytes(self.take::<4>(what)?))
    }

    /// A `float64`.
    pub fn f64(&mut self, what: &str) -> Result<f64, CdrError> {
        Ok(f64::from_ne_bytes(self.take::<8>(what)?))
    }

    /// A `string` (lossy UTF-8, NUL dropped).
    pub fn string(&mut self, what: &str) -> Result<String, CdrError> {
        Ok(String::from_utf8_lossy(self.string_bytes(what)?).into_owned())
    }

    /// A `string`'s bytes (NUL dropped), borrowed from the message: nothing is allocated.
    pub fn string_bytes(&mut self, what: &str) -> Result<&'a [u8], CdrError> {
        let at = self.pos;
        let len = self.u32(what)? as usize;
        let end = self.pos.checked_add(len).filter(|&e| e <= self.bytes.len());
        let Some(end) = end else {
            return Err(CdrError {
                offset: at,
                message: format!(
                    "{what}: string length {len} runs past the end of the message ({} bytes)",
                    self.bytes.len()
                ),
            });
        };
        let raw = &self.bytes[self.pos..end];
        let raw = raw.strip_suffix(&[0]).unwrap_or(raw);
        self.pos = end;
        Ok(raw)
    }

    /// Skips `n` `float64` values.
    pub fn skip_f64(&mut self, n: usize, what: &str) -> Result<(), CdrError> {
        for _ in 0..n {
            self.f64(what)?;
        }
        Ok(())
    }
}

/// A `std_msgs/Header`: the stamp in seconds and the frame id.
pub fn header(r: &mut CdrReader) -> Result<(f64, String), CdrError> {
    let (t, frame) = header_bytes(r)?;
    Ok((t, String::from_utf8_lossy(frame).into_owned()))
}

/// A `std_msgs/Header`: the stamp in seconds and the frame id's bytes (borrowed).
pub fn header_bytes<'a>(r: &mut CdrReader<'a>) -> Result<(f64, &'a [u8]), CdrError> {
    let sec = r.i32("header.stamp.sec")?;
    let nanosec = r.u32("header.stamp.nanosec")?;
    let frame = r.string_bytes("header.frame_id")?;
    Ok((sec as f64 + nanosec as f64 * 1e-9, frame))
}

/// Yaw (rotation about z) of a unit quaternion.
pub fn yaw_of(x: f64, y: f64, z: f64, w: f64) -> f64 {
    (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alignment_counts_from_after_the_header() {
        // LE: u8 7, pad 3, f32 1.5, then pad 0 (offset 8 from body start), f64 2.0.
        let mut b = vec![0, 1, 0, 0, 7, 0, 0, 0];
        b.extend_from_slice(&1.5f32.to_le_bytes());
        b.extend_from_slice(&2.0f64.to_le_bytes());
        let mut r = CdrReader::new(&b).unwrap();
        assert_eq!(r.u8("a").unwrap(), 7);
        assert_eq!(r.f32("b").unwrap(), 1.5);
        assert_eq!(r.f64("c").unwrap(), 2.0);
        assert!(r.u8("d").unwrap_err().message.contains("expected d"));
        // BE string "ab".
        let b = [0, 0, 0, 0, 0, 0, 0, 3, b'a', b'b', 0];
        assert_eq!(CdrReader::new(&b).unwrap().string("s").unwrap(), "ab");
    }
}
