//! A tiny ULog writer for tests (this crate's and the replay tests of
//! other crates): header, flag bits, format definitions,
//! parameters, subscriptions and data messages, byte for byte as PX4 writes them.

/// Builds a ULog file in memory.
pub struct Writer {
    bytes: Vec<u8>,
}

impl Default for Writer {
    fn default() -> Self {
        Self::new()
    }
}

impl Writer {
    /// Header (version 1, start time 0) and an empty flag-bits message.
    pub fn new() -> Self {
        let mut bytes = super::guard::MAGIC.to_vec();
        bytes.push(1);
        bytes.extend(0u64.to_le_bytes());
        let mut w = Writer { bytes };
        w.message(b'B', &[0u8; 40]);
        w
    }

    /// Any message: size, type, payload.
    pub fn message(&mut self, kind: u8, payload: &[u8]) -> &mut Self {
        let size = u16::try_from(payload.len()).expect("test payload fits a ULog message");
        self.bytes.extend(size.to_le_bytes());
        self.bytes.push(kind);
        self.bytes.extend_from_slice(payload);
        self
    }

    /// A format definition `name:type field;...`.
    pub fn format(&mut self, text: &str) -> &mut Self {
        self.message(b'F', text.as_bytes())
    }

    /// A float parameter of the definitions section.
    pub fn parameter(&mut self, name: &str, value: f32) -> &mut Self {
        let key = format!("float {name}");
        let mut p = vec![u8::try_from(key.len()).expect("short key")];
        p.extend(key.as_bytes());
        p.extend(value.to_le_bytes());
        self.message(b'P', &p)
    }

    /// Subscribes `msg_id` to topic `name`, instance `multi_id`.
    pub fn subscribe(&mut self, multi_id: u8, msg_id: u16, name: &str) -> &mut Self {
        let mut p = vec![multi_id];
        p.extend(msg_id.to_le_bytes());
        p.extend(name.as_bytes());
        self.message(b'A', &p)
    }

    /// A data message of `msg_id` with the fields `payload`.
    pub fn data(&mut self, msg_id: u16, payload: &Payload) -> &mut Self {
        let mut p = msg_id.to_le_bytes().to_vec();
        p.extend(&payload.0);
        self.message(b'D', &p)
    }

    /// The file.
    pub fn bytes(&self) -> Vec<u8> {
        self.bytes.clone()
    }
}

/// The fields of one data message, appended in declaration order.
#[derive(Default)]
pub struct Payload(Vec<u8>);

impl Payload {
    /// A `uint64_t`.
    pub fn u64(mut self, v: u64) -> Self {
        self.0.extend(v.to_le_bytes());
        self
    }
    /// A `uint32_t`.
    pub fn u32(mut self, v: u32) -> Self {
        self.0.extend(v.to_le_bytes());
        self
    }
    /// An `int32_t`.
    pub fn i32(mut self, v: i32) -> Self {
        self.0.extend(v.to_le_bytes());
        self
    }
    /// A `uint16_t`.
    pub fn u16(mut self, v: u16) -> Self {
        self.0.extend(v.to_le_bytes());
        self
    }
    /// A `uint8_t`.
    pub fn u8(mut self, v: u8) -> Self {
        self.0.push(v);
        self
    }
    /// `float`s.
    pub fn f32s(mut self, v: &[f32]) -> Self {
        for x in v {
            self.0.extend(x.to_le_bytes());
        }
        self
    }
    /// `double`s.
    pub fn f64s(mut self, v: &[f64]) -> Self {
        for x in v {
            self.0.extend(x.to_le_bytes());
        }
        self
    }
}
