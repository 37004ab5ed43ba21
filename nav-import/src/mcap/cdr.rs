//! A bounded reader of CDR-encoded ROS 2 messages (the XCDR1 encoding
//! ROS 2's default middleware writes: a 4-byte encapsulation header, then
//! primitives aligned to their size relative to the end of that header).
//!
//! Only the few standard message layouts of [`super::messages`] are read,
//! field by field: every read checks the remaining length, a string or a
//! sequence is skipped by its declared length after checking that length
//! against the bytes left (nothing is allocated from it), and an error says
//! which field and at which byte.

/// A read failure: the field and what was wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CdrError {
    /// The field being read (`header.stamp.sec`, `angular_velocity.x`).
    pub field: String,
    /// What was wrong.
    pub reason: String,
}

impl std::fmt::Display for CdrError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "field `{}`: {}", self.field, self.reason)
    }
}

/// A cursor over one message's bytes.
pub struct Cdr<'a> {
    data: &'a [u8],
    /// Position in `data` (the encapsulation header included).
    pos: usize,
    little: bool,
}

/// Length of the encapsulation header.
const HEADER: usize = 4;

impl<'a> Cdr<'a> {
    /// Reads the encapsulation header: CDR_BE (0x0000) or CDR_LE (0x0001).
    ///
    /// # Errors
    /// A message shorter than the header or of another encapsulation.
    pub fn new(data: &'a [u8]) -> Result<Self, CdrError> {
        let bad = |reason: String| CdrError {
            field: "encapsulation".into(),
            reason,
        };
        let head = data.get(..HEADER).ok_or_else(|| {
            bad(format!(
                "{} bytes, a CDR message has at least 4",
                data.len()
            ))
        })?;
        let little = match [head[0], head[1]] {
            [0, 0] => false,
            [0, 1] => true,
            [a, b] => {
                return Err(bad(format!(
                    "kind 0x{a:02x}{b:02x}: plain CDR (0x0000 or 0x0001) expected"
                )))
            }
        };
        Ok(Cdr {
            data,
            pos: HEADER,
            little,
        })
    }

    fn take(&mut self, field: &str, size: usize, align: usize) -> Result<&'a [u8], CdrError> {
        let rel = self.pos - HEADER;
        let pad = (align - rel % align) % align;
        let start = self.pos + pad;
        let end = start.checked_add(size);
        match end.and_then(|e| self.data.get(start..e)) {
            Some(b) => {
                self.pos = start + size;
                Ok(b)
            }
            None => Err(CdrError {
                field: field.into(),
                reason: format!(
                    "{size} bytes needed at byte {start}, the message has {}",
                    self.data.len()
                ),
            }),
        }
    }

    /// An `int32`.
    pub fn i32(&mut self, field: &str) -> Result<i32, CdrError> {
        let b: [u8; 4] = self.take(field, 4, 4)?.try_into().unwrap_or([0; 4]);
        Ok(if self.little {
            i32::from_le_bytes(b)
        } else {
            i32::from_be_bytes(b)
        })
    }

    /// A `uint32`.
    pub fn u32(&mut self, field: &str) -> Result<u32, CdrError> {
        let b: [u8; 4] = self.take(field, 4, 4)?.try_into().unwrap_or([0; 4]);
        Ok(if self.little {
            u32::from_le_bytes(b)
        } else {
            u32::from_be_bytes(b)
        })
    }

    /// An `int8` / `uint8`.
    pub fn u8(&mut self, field: &str) -> Result<u8, CdrError> {
        Ok(self.take(field, 1, 1)?[0])
    }

    /// A `uint16`.
    pub fn u16(&mut self, field: &str) -> Result<u16, CdrError> {
        let b: [u8; 2] = self.take(field, 2, 2)?.try_into().unwrap_or([0; 2]);
        Ok(if self.little {
            u16::from_le_bytes(b)
        } else {
            u16::from_be_bytes(b)
        })
    }

    /// A `float32`.
    pub fn f32(&mut self, field: &str) -> Result<f64, CdrError> {
        Ok(f64::from(f32::from_bits(self.u32(field)?)))
    }

    /// A `float64`.
    pub fn f64(&mut self, field: &str) -> Result<f64, CdrError> {
        let b: [u8; 8] = self.take(field, 8, 8)?.try_into().unwrap_or([0; 8]);
        Ok(if self.little {
            f64::from_le_bytes(b)
        } else {
            f64::from_be_bytes(b)
        })
    }

    /// `N` `float64`s.
    pub fn f64s<const N: usize>(&mut self, field: &str) -> Result<[f64; N], CdrError> {
        let mut out = [0.0; N];
        for v in &mut out {
            *v = self.f64(field)?;
        }
        Ok(out)
    }

    /// A `string`: its length (terminating NUL included) checked against
    /// the bytes left; returned when UTF-8 and at most 256 bytes (frame ids),
    /// else skipped and returned empty.
    pub fn string(&mut self, field: &str) -> Result<String, CdrError> {
        let len = self.u32(field)? as usize;
        let left = self.data.len() - self.pos;
        if len > left {
            return Err(CdrError {
                field: field.into(),
                reason: format!("string of {len} bytes, {left} left in the message"),
            });
        }
        let bytes = self.take(field, len, 1)?;
        let text = bytes.strip_suffix(&[0]).unwrap_or(bytes);
        Ok(if text.len() <= 256 {
            String::from_utf8_lossy(text).into_owned()
        } else {
            String::new()
        })
    }

    /// A sequence length, checked against the bytes left for elements of
    /// `element` bytes each.
    pub fn sequence(&mut self, field: &str, element: usize) -> Result<usize, CdrError> {
        let n = self.u32(field)? as usize;
        let left = self.data.len() - self.pos;
        if n.saturating_mul(element.max(1)) > left {
            return Err(CdrError {
                field: field.into(),
                reason: format!("sequence of {n} elements, {left} bytes left in the message"),
            });
        }
        Ok(n)
    }

    /// `std_msgs/Header`: stamp (ns since the epoch) and frame id.
    pub fn header(&mut self) -> Result<(i64, String), CdrError> {
        let sec = self.i32("header.stamp.sec")?;
        let nanosec = self.u32("header.stamp.nanosec")?;
        if nanosec >= 1_000_000_000 {
            return Err(CdrError {
                field: "header.stamp.nanosec".into(),
                reason: format!("{nanosec}, below 1e9 expected"),
            });
        }
        let frame = self.string("header.frame_id")?;
        Ok((i64::from(sec) * 1_000_000_000 + i64::from(nanosec), frame))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_aligned_little_and_big_endian() {
        // header (LE), u8, then an f64 aligned to 8 from the end of the header.
        let mut le = vec![0, 1, 0, 0, 7];
        le.extend([0; 7]);
        le.extend(2.5f64.to_le_bytes());
        let mut c = Cdr::new(&le).expect("header");
        assert_eq!(c.u8("a"), Ok(7));
        assert_eq!(c.f64("b"), Ok(2.5));
        let mut be = vec![0, 0, 0, 0];
        be.extend(3u32.to_be_bytes());
        assert_eq!(Cdr::new(&be).expect("header").u32("n"), Ok(3));
    }

    /// Lengths read in the message are checked before use.
    #[test]
    fn bad_lengths_are_errors_naming_the_field() {
        let cases: [(&str, Vec<u8>, &str); 4] = [
            ("no header", vec![0, 1], "encapsulation"),
            ("XCDR2", vec![0, 7, 0, 0], "plain CDR"),
            (
                "string longer than the message",
                [vec![0, 1, 0, 0], u32::MAX.to_le_bytes().to_vec()].concat(),
                "string of 4294967295 bytes",
            ),
            ("short float", vec![0, 1, 0, 0, 1, 2], "4 bytes needed"),
        ];
        for (name, bytes, part) in cases {
            let r = Cdr::new(&bytes).and_then(|mut c| {
                if name == "short float" {
                    c.f32("x").map(|_| ())
                } else {
                    c.string("s").map(|_| ())
                }
            });
            let e = r.expect_err(name);
            assert!(e.to_string().contains(part), "{name}: {e}");
        }
    }
}
