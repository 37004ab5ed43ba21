//! The aiding rows of a replay on their way to the navigator: each row of the
//! depth meter, DVL, compass, USBL, GNSS, barometer and magnetometer files,
//! as the log stream hands it over,
//! is counted in its sensor's health and, if usable, queued with its delivery
//! time (its measurement time plus the delivery delay: the acoustic travel
//! time of a USBL fix, injected delays of the others). The queue holds only
//! what is still travelling, so memory is bounded by the latency window, not
//! by the log.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use nav_runtime::earth::{Geodetic, LocalNed};
use nav_runtime::log::{
    Event as LogEvent, Located, LogError, LogSource, UsblRow, Warning, WarningKind,
};
use nav_runtime::nalgebra::Vector3;

use super::setup::{FilterOptions, UsblDelivery};
use nav_ins::{
    BaroReading, CompassForm, DepthReading, DvlReading, GnssFix, Handle, HeadingReading,
    InsVehicle, MagReading, Navigator, SensorHealth, UsblFix, SENSORS, SENSOR_NAMES,
};

/// Speed of sound for the acoustic travel time of a USBL fix, m/s.
pub const SOUND_SPEED: f64 = 1500.0;
/// DVL bottom-lock range, m above the sea floor: above it (`altitude.csv`)
/// a DVL row is not used.
pub const DVL_MAX_ALTITUDE: f64 = 100.0;

/// A reading of one aiding row.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Reading {
    Depth(f64),
    Dvl(Vector3<f64>),
    Heading(f64),
    Usbl { lat: f64, lon: f64 },
    Gnss(GnssFix),
    Baro(f64),
    Mag(Vector3<f64>),
}

/// An aiding row on its way: when it was measured and when it arrives.
#[derive(Clone, Copy, Debug)]
pub(super) struct Travelling {
    delivery: f64,
    time: f64,
    /// Index in [`SENSOR_NAMES`].
    sensor: usize,
    /// Row index within its file (0-based, after the header).
    row: usize,
    line: Option<u64>,
    reading: Reading,
}

impl Travelling {
    /// Where the row is, for messages.
    pub(super) fn place(&self) -> String {
        place(
            &format!("{}.csv", SENSOR_NAMES[self.sensor]),
            self.line,
            self.row,
        )
    }

    /// Pushes the reading into `nav` under its sensor's handle.
    pub(super) fn push<V: InsVehicle<N>, const N: usize>(
        &self,
        nav: &mut Navigator<V, N>,
        handles: &Handles,
    ) {
        let t = self.time;
        match self.reading {
            Reading::Depth(d) => {
                if let Some(h) = handles.depth {
                    nav.push(h, t, DepthReading(d));
                }
            }
            Reading::Dvl(v) => {
                if let Some(h) = handles.dvl {
                    nav.push(h, t, DvlReading(v));
                }
            }
            Reading::Heading(psi) => {
                if let Some(h) = handles.heading {
                    nav.push(h, t, HeadingReading(psi));
                }
            }
            Reading::Usbl { lat, lon } => {
                if let Some(h) = handles.usbl {
                    nav.push(h, t, UsblFix { lat, lon });
                }
            }
            Reading::Gnss(fix) => {
                if let Some(h) = handles.gnss {
                    nav.push(h, t, fix);
                }
            }
            Reading::Baro(altitude) => {
                if let Some(h) = handles.baro {
                    nav.push(h, t, BaroReading(altitude));
                }
            }
            Reading::Mag(m) => {
                if let Some(h) = handles.mag {
                    nav.push(h, t, MagReading(m));
                }
            }
        }
    }

    fn key(&self) -> (f64, usize, usize) {
        (self.delivery, self.sensor, self.row)
    }
}

impl PartialEq for Travelling {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Travelling {}

impl PartialOrd for Travelling {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Travelling {
    /// Reversed (the heap is a max-heap): earliest delivery first, then by
    /// sensor and row, the order of a stable sort by delivery of the rows
    /// listed sensor by sensor.
    fn cmp(&self, other: &Self) -> Ordering {
        let (a, b) = (self.key(), other.key());
        b.0.total_cmp(&a.0).then(b.1.cmp(&a.1)).then(b.2.cmp(&a.2))
    }
}

/// Where row `row` (0-based) of `file` is: its line when known.
pub(super) fn place(file: &str, line: Option<u64>, row: usize) -> String {
    match line {
        Some(l) => format!("{file} line {l}"),
        None => format!("{file} data row {}", row + 1),
    }
}

/// The handles of the sensors a vehicle has.
#[derive(Clone, Copy, Debug)]
pub(super) struct Handles {
    pub(super) depth: Option<Handle<DepthReading>>,
    pub(super) dvl: Option<Handle<DvlReading>>,
    pub(super) heading: Option<Handle<HeadingReading>>,
    pub(super) usbl: Option<Handle<UsblFix>>,
    pub(super) gnss: Option<Handle<GnssFix>>,
    pub(super) baro: Option<Handle<BaroReading>>,
    pub(super) mag: Option<Handle<MagReading>>,
}

/// The aiding rows of a run: health counts and the rows still travelling.
pub(super) struct Aiding {
    queue: BinaryHeap<Travelling>,
    pub(super) health: [SensorHealth; SENSORS],
    /// Rows seen per sensor.
    rows: [usize; SENSORS],
    /// The vehicle has the sensor (in the form the options choose).
    pub(super) present: [bool; SENSORS],
    /// The options use the sensor.
    used: [bool; SENSORS],
    /// Latest echo-sounder altitude (m).
    altitude: Option<f64>,
    frame: LocalNed,
    options: FilterOptions,
    pub(super) warnings: Vec<Warning>,
    /// A GNSS fix carried the receiver's `eph` or `epv` (its sigma is then
    /// theirs, the section's only a floor).
    pub(super) receiver_sigmas: bool,
}

impl Aiding {
    pub(super) fn new<V: InsVehicle<N>, const N: usize>(
        options: &FilterOptions,
        transducer: Geodetic,
    ) -> Self {
        let has = nav_ins::vehicle::Present::of::<V, N>();
        let has_heading = match options.compass {
            CompassForm::Exact => has.compass,
            CompassForm::SmallAngle => has.compass_small_angle,
        };
        Aiding {
            queue: BinaryHeap::new(),
            health: [SensorHealth::default(); SENSORS],
            rows: [0; SENSORS],
            present: [
                has.depth,
                has.dvl,
                has_heading,
                has.usbl,
                has.gnss,
                has.baro,
                has.mag,
            ],
            used: [
                options.use_depth,
                options.use_dvl,
                options.use_compass,
                options.use_usbl,
                options.use_gnss,
                options.use_baro,
                options.use_mag,
            ],
            altitude: None,
            frame: LocalNed::new(transducer),
            options: *options,
            warnings: Vec::new(),
            receiver_sigmas: false,
        }
    }

    /// Log sensors (with a file) that the vehicle lacks: their rows are
    /// counted as skipped.
    pub(super) fn ignored(&self, has_file: [bool; SENSORS]) -> Vec<&'static str> {
        (0..SENSORS)
            .filter(|&i| has_file[i] && !self.present[i])
            .map(|i| SENSOR_NAMES[i])
            .collect()
    }

    /// USBL travel time of a fix (s), by the options' delivery.
    fn travel_time(&self, r: &UsblRow) -> f64 {
        match self.options.usbl_delivery {
            UsblDelivery::OnTime => 0.0,
            UsblDelivery::Acoustic => {
                self.frame
                    .geodetic_to_ned(&Geodetic::new(r.lat, r.lon, -r.depth))
                    .norm()
                    / SOUND_SPEED
            }
        }
    }

    /// The largest USBL travel time over the log's fixes (s), and whether
    /// the run uses any fix: the navigator's history must span it.
    pub(super) fn usbl_latency(&self, source: &LogSource<'_>) -> Result<(f64, bool), LogError> {
        let (mut latency, mut any) = (0.0f64, false);
        if !(self.used[3] && self.present[3]) {
            return Ok((latency, any));
        }
        let Some(mut rows) = source.rows::<UsblRow>()? else {
            return Ok((latency, any));
        };
        while let Some((_, r)) = rows.next_row()? {
            let delay = self.travel_time(&r);
            if delay.is_infinite() {
                continue;
            }
            any = true;
            // `max` ignores a NaN delay: that fix goes last and is refused.
            latency = latency.max(delay);
        }
        Ok((latency, any))
    }

    /// Takes one non-IMU event of the log stream.
    pub(super) fn take(&mut self, located: &Located) {
        let (sensor, time, reading) = match located.event {
            LogEvent::Altitude(r) => {
                self.altitude = Some(r.altitude);
                return;
            }
            LogEvent::Depth(r) => (0, r.t, Some(Reading::Depth(r.depth))),
            LogEvent::Dvl(r) => {
                let in_range = self.altitude.is_none_or(|a| a <= DVL_MAX_ALTITUDE);
                let v = r.velocity().filter(|_| in_range).map(Vector3::from);
                (1, r.t, v.map(Reading::Dvl))
            }
            LogEvent::Heading(r) => (2, r.t, Some(Reading::Heading(r.heading))),
            LogEvent::Usbl(r) => {
                let delay = self.travel_time(&r);
                let row = self.rows[3];
                if self.used[3] && self.present[3] && delay.is_infinite() {
                    self.rows[3] += 1;
                    self.health[3].rows += 1;
                    self.health[3].rejected += 1;
                    let mut w = Warning::about(
                        WarningKind::Suspicious,
                        "usbl.csv",
                        format!(
                            "{}: the fix (lat {}, lon {}, depth {}) gives an infinite acoustic travel time; not used",
                            place("usbl.csv", located.line, row),
                            r.lat,
                            r.lon,
                            r.depth
                        ),
                    );
                    w.line = located.line;
                    self.warnings.push(w);
                    return;
                }
                (
                    3,
                    r.t,
                    Some(Reading::Usbl {
                        lat: r.lat,
                        lon: r.lon,
                    }),
                )
            }
            LogEvent::Gnss(r) => {
                self.receiver_sigmas |= r.eph.is_some() || r.epv.is_some();
                let fix = GnssFix {
                    lat: r.lat,
                    lon: r.lon,
                    height: r.height,
                    eph: r.eph,
                    epv: r.epv,
                };
                (4, r.t, Some(Reading::Gnss(fix)))
            }
            LogEvent::Baro(r) => (5, r.t, Some(Reading::Baro(r.altitude))),
            LogEvent::Mag(r) => (6, r.t, Some(Reading::Mag(Vector3::new(r.mx, r.my, r.mz)))),
            _ => return,
        };
        let row = self.rows[sensor];
        self.rows[sensor] += 1;
        let h = &mut self.health[sensor];
        if !self.present[sensor] {
            // A log sensor the vehicle lacks: its rows are counted and skipped.
            h.rows += 1;
            h.skipped += 1;
            return;
        }
        if !self.used[sensor] {
            return;
        }
        h.rows += 1;
        let Some(reading) = reading else {
            // DVL without bottom lock or above its range.
            h.skipped += 1;
            return;
        };
        let delay = match reading {
            Reading::Usbl { .. } => match located.event {
                LogEvent::Usbl(r) => self.travel_time(&r),
                _ => 0.0,
            },
            _ => self.options.delivery.delay(sensor, row),
        };
        self.queue.push(Travelling {
            delivery: time + delay,
            time,
            sensor,
            row,
            line: located.line,
            reading,
        });
    }

    /// The next row delivered by time `t`, earliest delivery first.
    pub(super) fn due(&mut self, t: f64) -> Option<Travelling> {
        if self.queue.peek().is_some_and(|e| e.delivery <= t) {
            self.queue.pop()
        } else {
            None
        }
    }

    /// The next row still travelling, whatever its delivery time.
    pub(super) fn next(&mut self) -> Option<Travelling> {
        self.queue.pop()
    }
}
