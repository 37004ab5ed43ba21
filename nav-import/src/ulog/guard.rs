//! A framing pass over the whole file before the ULog crate sees it.
//!
//! The `px4-ulog` crate parses messages but indexes some payloads before
//! checking their length (a short `A`, `P`, `I`, `M`, `Q`, `C` message panics),
//! and it flattens every format definition into a list of named fields, so a
//! few bytes declaring nested arrays could make it build millions of entries.
//! This pass walks the message frames (`u16` size, `u8` type, payload), checks
//! each payload against the minimum its type needs, bounds the work the format
//! definitions imply and the subscription ids, and hands the crate only whole,
//! checked messages. A file that ends inside a message (a log cut by power loss)
//! is read up to the last whole message and reported in the warnings. A log
//! continued after such a cut has the offsets of the appended data in its
//! flag bits message (the ULog format's `appended_offsets`): the cut message
//! is skipped and reading goes on at the appended data.

use std::collections::HashMap;

/// The ULog magic bytes and file version 1 (`"ULog"`, 0x01, 0x12, 0x35).
pub const MAGIC: [u8; 7] = [0x55, 0x4c, 0x6f, 0x67, 0x01, 0x12, 0x35];
/// Header length: magic, version byte, start timestamp (u64).
pub const HEADER_LEN: usize = 16;
/// Largest subscription id accepted (PX4 allocates them densely from 0).
pub const MAX_MSG_ID: u16 = 4095;
/// Deepest nesting of message types inside message types.
pub const MAX_NESTING: usize = 16;
/// Bound on the flattened fields of all format definitions together.
pub const MAX_FLATTENED_FIELDS: u64 = 1 << 18;

/// One checked message: its type byte and the byte range of the whole frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Frame {
    /// Message type (`b'D'`, `b'F'`, ...).
    pub kind: u8,
    /// Offset of the frame's first byte (the size field).
    pub offset: usize,
    /// Length of the frame: 3 + payload.
    pub len: usize,
}

/// The result of the framing pass.
#[derive(Debug, Default)]
pub struct Framing {
    /// The checked frames in file order.
    pub frames: Vec<Frame>,
    /// Set when the file ends inside a message: the offset of that message.
    pub truncated_at: Option<usize>,
    /// Messages cut by appended data: (offset of the cut message, offset of
    /// the appended data read instead).
    pub cut: Vec<(usize, usize)>,
}

/// A framing error: byte offset and reason.
pub type FrameError = (usize, String);

/// What a message type is, for messages (`data message `'D'``).
pub fn describe(kind: u8) -> String {
    let what = match kind {
        b'B' => "flag bits",
        b'F' => "format",
        b'I' => "info",
        b'M' => "multi info",
        b'P' => "parameter",
        b'Q' => "parameter default",
        b'A' => "subscription (add logged)",
        b'R' => "remove logged",
        b'D' => "data",
        b'L' => "logged string",
        b'C' => "tagged logged string",
        b'S' => "sync",
        b'O' => "dropout",
        _ => "unknown",
    };
    if kind.is_ascii_graphic() {
        format!("{what} message `{}`", kind as char)
    } else {
        format!("{what} message (type byte {kind})")
    }
}

/// Minimum payload length of a message type, and where a key length byte
/// sits (its key must fit in the payload).
fn minimum(kind: u8) -> (usize, Option<usize>) {
    match kind {
        b'B' => (40, None),
        b'I' | b'P' => (1, Some(0)),
        b'M' | b'Q' => (2, Some(1)),
        b'A' => (3, None),
        b'R' | b'D' | b'O' => (2, None),
        b'L' => (9, None),
        b'C' => (11, None),
        b'S' => (8, None),
        _ => (0, None),
    }
}

/// Walks and checks the frames of `bytes`.
///
/// # Errors
/// The offset and reason of the first bad header, message or definition.
pub fn frames(bytes: &[u8]) -> Result<Framing, FrameError> {
    if bytes.len() < HEADER_LEN {
        return Err((
            0,
            format!(
                "file header: {} bytes, a ULog file starts with {HEADER_LEN}",
                bytes.len()
            ),
        ));
    }
    if bytes[..MAGIC.len()] != MAGIC {
        return Err((
            0,
            "file header: not a ULog file (magic bytes `ULog` 01 12 35 expected)".into(),
        ));
    }
    let mut out = Framing::default();
    let mut formats = Formats::default();
    let mut pos = HEADER_LEN;
    // Where appended data starts (the flag bits message's offsets), in
    // increasing order; the next one ends the section being read.
    let mut appended: Vec<usize> = Vec::new();
    while pos < bytes.len() {
        if let Some(&next) = appended.first() {
            if pos == next {
                // The section ended on a whole message.
                appended.remove(0);
                continue;
            }
        }
        let Some(head) = bytes.get(pos..pos + 3) else {
            out.truncated_at = Some(pos);
            break;
        };
        let size = usize::from(u16::from_le_bytes([head[0], head[1]]));
        let kind = head[2];
        if let Some(&next) = appended.first() {
            if pos + 3 + size > next {
                // A message cut by the appended data: read on from there.
                out.cut.push((pos, next));
                appended.remove(0);
                pos = next;
                continue;
            }
        }
        let Some(payload) = bytes.get(pos + 3..pos + 3 + size) else {
            out.truncated_at = Some(pos);
            break;
        };
        check_payload(kind, payload).map_err(|r| (pos, format!("{}: {r}", describe(kind))))?;
        if kind == b'B' && out.frames.is_empty() {
            appended = appended_offsets(payload, pos + 3 + size, bytes.len())
                .map_err(|r| (pos, format!("{}: {r}", describe(kind))))?;
        }
        if kind == b'F' {
            formats
                .add(payload)
                .map_err(|r| (pos, format!("{}: {r}", describe(kind))))?;
        }
        out.frames.push(Frame {
            kind,
            offset: pos,
            len: 3 + size,
        });
        pos += 3 + size;
    }
    formats
        .check_budget()
        .map_err(|r| (HEADER_LEN, format!("format definitions: {r}")))?;
    Ok(out)
}

/// The flag bits message's appended-data offsets (`appended_offsets[3]`,
/// u64 at payload bytes 16..40), the zero ones left out. Each must lie after
/// the flag bits message (`after`) and after the one before; one past the
/// file's end (`len`, a log cut before its appended data) is left out.
fn appended_offsets(payload: &[u8], after: usize, len: usize) -> Result<Vec<usize>, String> {
    let mut out: Vec<usize> = Vec::new();
    for i in 0..3 {
        let at = 16 + 8 * i;
        let raw = payload
            .get(at..at + 8)
            .and_then(|b| b.try_into().ok())
            .map_or(0, u64::from_le_bytes);
        if raw == 0 {
            continue;
        }
        let offset = usize::try_from(raw).unwrap_or(usize::MAX);
        let floor = out.last().copied().unwrap_or(after);
        if offset < floor {
            return Err(format!(
                "field `appended_offsets[{i}]`: {raw}, before byte {floor}"
            ));
        }
        if offset <= len {
            out.push(offset);
        }
    }
    Ok(out)
}

fn check_payload(kind: u8, payload: &[u8]) -> Result<(), String> {
    let (min, key_at) = minimum(kind);
    if payload.len() < min {
        return Err(format!(
            "payload of {} bytes, at least {min} expected",
            payload.len()
        ));
    }
    if let Some(k) = key_at {
        let key_len = usize::from(payload[k]);
        if k + 1 + key_len > payload.len() {
            return Err(format!(
                "key length {key_len} runs past the {}-byte payload",
                payload.len()
            ));
        }
    }
    if kind == b'A' {
        let msg_id = u16::from_le_bytes([payload[1], payload[2]]);
        if msg_id > MAX_MSG_ID {
            return Err(format!(
                "field `msg_id`: {msg_id}, at most {MAX_MSG_ID} accepted"
            ));
        }
    }
    Ok(())
}

/// The format definitions seen so far, to bound the crate's flattening work.
#[derive(Default)]
struct Formats {
    /// Name -> fields as (element type, count).
    fields: HashMap<String, Vec<(String, u64)>>,
}

const PRIMITIVES: &[&str] = &[
    "int8_t", "uint8_t", "int16_t", "uint16_t", "int32_t", "uint32_t", "int64_t", "uint64_t",
    "float", "double", "bool", "char",
];

impl Formats {
    fn add(&mut self, payload: &[u8]) -> Result<(), String> {
        let text = std::str::from_utf8(payload).map_err(|_| "not UTF-8 text".to_string())?;
        let Some((name, body)) = text.split_once(':') else {
            return Err(format!("`{}`: no `name:` prefix", clip(text)));
        };
        let mut fields = Vec::new();
        for decl in body.split(';').filter(|s| !s.is_empty()) {
            let Some((ty, _field)) = decl.split_once(' ') else {
                return Err(format!(
                    "field declaration `{}`: `type name` expected",
                    clip(decl)
                ));
            };
            let (base, count) = match ty.split_once('[') {
                None => (ty, 1),
                Some((base, rest)) => {
                    let n = rest
                        .strip_suffix(']')
                        .and_then(|n| n.parse::<u16>().ok())
                        .ok_or_else(|| {
                            format!("field declaration `{}`: bad array size", clip(decl))
                        })?;
                    (base, u64::from(n))
                }
            };
            fields.push((base.to_string(), count));
        }
        self.fields.insert(name.to_string(), fields);
        Ok(())
    }

    /// Work of flattening `name`: one unit per field element, nested types
    /// counted with their own work. Unknown nested names cost one (the crate
    /// reports them).
    fn work(
        &self,
        name: &str,
        depth: usize,
        memo: &mut HashMap<String, u64>,
    ) -> Result<u64, String> {
        if let Some(w) = memo.get(name) {
            return Ok(*w);
        }
        if depth > MAX_NESTING {
            return Err(format!(
                "type `{}` nested more than {MAX_NESTING} deep (or defined in terms of itself)",
                clip(name)
            ));
        }
        let Some(fields) = self.fields.get(name) else {
            return Ok(1);
        };
        let mut total: u64 = 0;
        for (base, count) in fields {
            let each = if PRIMITIVES.contains(&base.as_str()) {
                1
            } else {
                1 + self.work(base, depth + 1, memo)?
            };
            total = total.saturating_add(count.saturating_mul(each));
            if total > MAX_FLATTENED_FIELDS {
                break;
            }
        }
        memo.insert(name.to_string(), total);
        Ok(total)
    }

    fn check_budget(&self) -> Result<(), String> {
        let mut memo = HashMap::new();
        let mut total: u64 = 0;
        for name in self.fields.keys() {
            total = total.saturating_add(self.work(name, 0, &mut memo)?);
            if total > MAX_FLATTENED_FIELDS {
                return Err(format!(
                    "more than {MAX_FLATTENED_FIELDS} fields once arrays and nested types are expanded"
                ));
            }
        }
        Ok(())
    }
}

/// At most 60 characters of `s`, for messages.
fn clip(s: &str) -> String {
    let mut out: String = s.chars().take(60).collect();
    if s.chars().count() > 60 {
        out.push_str("...");
    }
    out
}
