//! Reading the wanted fields of the wanted topics out of the data messages,
//! as `f64` columns, one table per topic instance (`multi_id`).

use std::collections::HashMap;

use px4_ulog::stream_parser::model::{DataMessage, FlattenedFieldType};

use super::topics::WANTED;

/// The rows of one topic instance: the wanted fields it has, in [`WANTED`] order.
#[derive(Debug, Clone, Default)]
pub struct Table {
    /// Topic name.
    pub topic: String,
    /// The instance (`multi_id`).
    pub instance: u8,
    /// Names of the columns present.
    pub columns: Vec<&'static str>,
    /// Row-major values, `columns.len()` per row.
    pub values: Vec<f64>,
}

impl Table {
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.values
            .len()
            .checked_div(self.columns.len())
            .unwrap_or(0)
    }

    /// Index of a column.
    pub fn column(&self, name: &str) -> Option<usize> {
        self.columns.iter().position(|c| *c == name)
    }

    /// Whether every one of `names` is a column.
    pub fn has_all(&self, names: &[&str]) -> bool {
        names.iter().all(|n| self.column(n).is_some())
    }

    /// The value of column `c` in row `r`.
    pub fn at(&self, r: usize, c: usize) -> f64 {
        self.values[r * self.columns.len() + c]
    }
}

/// How to read one column: its field type and byte offset in the message.
#[derive(Debug, Clone)]
struct Reader {
    kind: FlattenedFieldType,
    offset: usize,
}

impl Reader {
    fn read(&self, data: &[u8]) -> f64 {
        fn bytes<const K: usize>(data: &[u8], at: usize) -> Option<[u8; K]> {
            data.get(at..at + K)?.try_into().ok()
        }
        let at = self.offset;
        let v = match self.kind {
            FlattenedFieldType::Int8 => {
                bytes::<1>(data, at).map(|b| f64::from(i8::from_le_bytes(b)))
            }
            FlattenedFieldType::UInt8 | FlattenedFieldType::Bool | FlattenedFieldType::Char => {
                bytes::<1>(data, at).map(|b| f64::from(b[0]))
            }
            FlattenedFieldType::Int16 => {
                bytes::<2>(data, at).map(|b| f64::from(i16::from_le_bytes(b)))
            }
            FlattenedFieldType::UInt16 => {
                bytes::<2>(data, at).map(|b| f64::from(u16::from_le_bytes(b)))
            }
            FlattenedFieldType::Int32 => {
                bytes::<4>(data, at).map(|b| f64::from(i32::from_le_bytes(b)))
            }
            FlattenedFieldType::UInt32 => {
                bytes::<4>(data, at).map(|b| f64::from(u32::from_le_bytes(b)))
            }
            FlattenedFieldType::Int64 => bytes::<8>(data, at).map(|b| i64::from_le_bytes(b) as f64),
            FlattenedFieldType::UInt64 => {
                bytes::<8>(data, at).map(|b| u64::from_le_bytes(b) as f64)
            }
            FlattenedFieldType::Float => {
                bytes::<4>(data, at).map(|b| f64::from(f32::from_le_bytes(b)))
            }
            FlattenedFieldType::Double => bytes::<8>(data, at).map(f64::from_le_bytes),
        };
        v.unwrap_or(f64::NAN)
    }
}

/// Per subscription: the table it feeds and how to read its columns.
struct Subscription {
    table: usize,
    readers: Vec<Reader>,
}

/// Collects [`Table`]s from data messages (the parser's data callback).
#[derive(Default)]
pub struct Collector {
    by_msg_id: HashMap<u16, Option<Subscription>>,
    /// The tables, in the order their topics first appeared.
    pub tables: Vec<Table>,
}

impl Collector {
    /// Takes one data message.
    pub fn take(&mut self, msg: &DataMessage) {
        if !self.by_msg_id.contains_key(&msg.msg_id) {
            let sub = self.subscribe(msg);
            self.by_msg_id.insert(msg.msg_id, sub);
        }
        let Some(Some(sub)) = self.by_msg_id.get(&msg.msg_id) else {
            return;
        };
        let table = &mut self.tables[sub.table];
        table
            .values
            .extend(sub.readers.iter().map(|r| r.read(msg.data)));
    }

    fn subscribe(&mut self, msg: &DataMessage) -> Option<Subscription> {
        let format = msg.flattened_format;
        let name = format.message_name();
        let (_, wanted) = WANTED.iter().find(|(topic, _)| *topic == name)?;
        let mut columns = Vec::new();
        let mut readers = Vec::new();
        for column in wanted.iter() {
            if let Some(f) = format
                .field_iter()
                .find(|f| f.flattened_field_name == *column)
            {
                columns.push(*column);
                readers.push(Reader {
                    kind: f.field_type.clone(),
                    offset: usize::from(f.offset),
                });
            }
        }
        let instance = msg.multi_id.value();
        // A topic re-subscribed under a new msg_id keeps filling its table when
        // the layout is the same; another layout gets a table of its own.
        let existing = self
            .tables
            .iter()
            .position(|t| t.topic == name && t.instance == instance && t.columns == columns);
        let table = match existing {
            Some(i) => i,
            None => {
                self.tables.push(Table {
                    topic: name.to_string(),
                    instance,
                    columns,
                    values: Vec::new(),
                });
                self.tables.len() - 1
            }
        };
        Some(Subscription { table, readers })
    }
}
