//! A bag writer for tests (cargo feature `bag-writer`): a little-endian CDR
//! encoder, encoders of the standard messages the import reads, and a bag
//! of topics written with the `mcap` crate's writer. The import's own tests
//! and the command line's round-trip test (a survey as a bag and as CSV)
//! share it; it is not part of the library's interface otherwise.

use std::collections::BTreeMap;
use std::io::Cursor;

/// A little-endian CDR encoder (alignment from the end of the 4-byte header).
#[derive(Clone)]
pub struct Enc(pub Vec<u8>);

impl Default for Enc {
    fn default() -> Self {
        Self::new()
    }
}

impl Enc {
    /// An empty message (the encapsulation header only).
    pub fn new() -> Self {
        Enc(vec![0, 1, 0, 0])
    }
    fn align(mut self, n: usize) -> Self {
        while !(self.0.len() - 4).is_multiple_of(n) {
            self.0.push(0);
        }
        self
    }
    /// A byte.
    pub fn u8(mut self, v: u8) -> Self {
        self.0.push(v);
        self
    }
    /// An aligned u16.
    pub fn u16(self, v: u16) -> Self {
        let mut s = self.align(2);
        s.0.extend(v.to_le_bytes());
        s
    }
    /// An aligned u32.
    pub fn u32(self, v: u32) -> Self {
        let mut s = self.align(4);
        s.0.extend(v.to_le_bytes());
        s
    }
    /// An aligned f32.
    pub fn f32(self, v: f32) -> Self {
        let mut s = self.align(4);
        s.0.extend(v.to_le_bytes());
        s
    }
    /// Aligned f64s.
    pub fn f64s(self, v: &[f64]) -> Self {
        let mut s = self;
        for x in v {
            s = s.align(8);
            s.0.extend(x.to_le_bytes());
        }
        s
    }
    /// A string (length with the terminating zero, bytes, zero).
    pub fn string(self, v: &str) -> Self {
        let n = u32::try_from(v.len() + 1).unwrap_or(u32::MAX);
        let mut s = self.u32(n);
        s.0.extend(v.as_bytes());
        s.0.push(0);
        s
    }
    /// A `std_msgs/Header` stamped `ns` (since the epoch) in `frame`.
    pub fn header(self, ns: i64, frame: &str) -> Self {
        let sec = ns.div_euclid(1_000_000_000) as i32;
        let nsec = ns.rem_euclid(1_000_000_000) as u32;
        self.u32(sec as u32).u32(nsec).string(frame)
    }
}

/// A 3x3 covariance with `v` on the diagonal.
pub fn diag9(v: f64) -> [f64; 9] {
    [v, 0.0, 0.0, 0.0, v, 0.0, 0.0, 0.0, v]
}

/// `sensor_msgs/Imu`: orientation (x, y, z, w; `None`: covariance -1),
/// rate (rad/s) and specific force (m/s^2) with their variances.
pub fn imu(
    ns: i64,
    frame: &str,
    q: Option<[f64; 4]>,
    rate: [f64; 3],
    accel: [f64; 3],
    rate_variance: f64,
    accel_variance: f64,
) -> Vec<u8> {
    let (q, qc) = match q {
        Some(q) => (q, diag9(1e-4)),
        None => ([0.0, 0.0, 0.0, 1.0], [-1.0; 9]),
    };
    Enc::new()
        .header(ns, frame)
        .f64s(&q)
        .f64s(&qc)
        .f64s(&rate)
        .f64s(&diag9(rate_variance))
        .f64s(&accel)
        .f64s(&diag9(accel_variance))
        .0
}

/// `sensor_msgs/MagneticField`, tesla.
pub fn mag(ns: i64, frame: &str, tesla: [f64; 3], variance: f64) -> Vec<u8> {
    Enc::new()
        .header(ns, frame)
        .f64s(&tesla)
        .f64s(&diag9(variance))
        .0
}

/// `sensor_msgs/FluidPressure`, Pa.
pub fn pressure(ns: i64, frame: &str, pa: f64, variance: f64) -> Vec<u8> {
    Enc::new().header(ns, frame).f64s(&[pa, variance]).0
}

/// `sensor_msgs/NavSatFix`: lat, lon (deg), altitude (m), the diagonal
/// covariance (type 2) `variance`.
pub fn fix(ns: i64, frame: &str, lat_lon_alt: [f64; 3], status: i8, variance: f64) -> Vec<u8> {
    Enc::new()
        .header(ns, frame)
        .u8(status as u8)
        .u16(1)
        .f64s(&lat_lon_alt)
        .f64s(&diag9(variance))
        .u8(2)
        .0
}

/// `geometry_msgs/TwistWithCovarianceStamped`: linear velocity (m/s).
pub fn twist(ns: i64, frame: &str, v: [f64; 3], variance: f64) -> Vec<u8> {
    let mut cov = [0.0; 36];
    cov[0] = variance;
    Enc::new()
        .header(ns, frame)
        .f64s(&v)
        .f64s(&[0.0; 3])
        .f64s(&cov)
        .0
}

/// `nav_msgs/Odometry`: position (m) and orientation in `frame`, linear
/// velocity (m/s) in the child frame.
pub fn odometry(ns: i64, frame: &str, position: [f64; 3], q: [f64; 4], v: [f64; 3]) -> Vec<u8> {
    Enc::new()
        .header(ns, frame)
        .string("base_link")
        .f64s(&position)
        .f64s(&q)
        .f64s(&[0.0; 36])
        .f64s(&v)
        .f64s(&[0.0; 3])
        .f64s(&[0.0; 36])
        .0
}

/// `tf2_msgs/TFMessage`: (parent, child, translation m, rotation x y z w).
pub fn tf_message(list: &[(&str, &str, [f64; 3], [f64; 4])]) -> Vec<u8> {
    let mut e = Enc::new().u32(u32::try_from(list.len()).unwrap_or(u32::MAX));
    for (parent, child, t, q) in list {
        e = e.header(1, parent).string(child).f64s(t).f64s(q);
    }
    e.0
}

/// One topic of a bag: name, ROS type, messages as (log time ns, CDR bytes).
pub type Topic = (String, String, Vec<(u64, Vec<u8>)>);

/// The bag of `topics`, messages in log-time order.
///
/// # Panics
/// When the `mcap` writer fails on memory (a test helper).
pub fn bag(topics: &[Topic]) -> Vec<u8> {
    let mut w = mcap::Writer::new(Cursor::new(Vec::new())).expect("writer");
    let mut all = Vec::new();
    for (topic, ty, msgs) in topics {
        let schema = w.add_schema(ty, "ros2msg", b"").expect("schema");
        let ch = w
            .add_channel(schema, topic, "cdr", &BTreeMap::new())
            .expect("channel");
        for (t, data) in msgs {
            all.push((*t, ch, data));
        }
    }
    all.sort_by_key(|(t, ch, _)| (*t, *ch));
    for (i, (t, ch, data)) in all.iter().enumerate() {
        let header = mcap::records::MessageHeader {
            channel_id: *ch,
            sequence: i as u32,
            log_time: *t,
            publish_time: *t,
        };
        w.write_to_known_channel(&header, data).expect("message");
    }
    w.finish().expect("finish");
    w.into_inner().into_inner()
}
