//! The files of an imported flight log (`mag.csv`, `baro.csv`, `gnss.csv`,
//! `reference.csv`): written and read back strictly with empty cells where a
//! value is not given, merged into the event stream after the IMU at equal
//! times, and range-checked like the other position files.

use std::path::PathBuf;

use nav_runtime::log::{
    BaroRow, Event, EventStream, GnssRow, ImuRow, LogDir, LogError, LogFiles, MagRow, Meta,
    Prefetched, ReferenceRow, Strictness,
};

fn tmp(tag: &str) -> PathBuf {
    let p = std::env::temp_dir().join(format!("nav-imported-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&p);
    p
}

fn log() -> LogDir {
    let mut log = LogDir::new(Meta::at(0.8, 0.15, -488.0));
    log.imu = (0..5)
        .map(|i| ImuRow::new(f64::from(i) * 0.1, 0.0, 0.0, 0.0, 0.0, 0.0, -9.8))
        .collect();
    log.mag = Some(vec![
        MagRow::new(0.1, 0.21, 0.01, 0.42),
        MagRow::new(0.3, 0.2, 0.0, 0.4),
    ]);
    log.baro = Some(vec![BaroRow::new(0.2, 488.1)]);
    log.gnss = Some(vec![
        GnssRow::new(
            0.1,
            0.8,
            0.15,
            488.0,
            Some(2.9),
            Some(3.0),
            Some(0.0),
            Some(0.1),
            Some(0.0),
            Some(0.25),
        ),
        GnssRow::new(0.2, 0.8, 0.15, 488.0, None, None, None, None, None, None),
    ]);
    log.reference = Some(vec![ReferenceRow::new(
        0.1,
        None,
        None,
        None,
        Some(0.0),
        Some(0.0),
        Some(0.0),
        Some(0.01),
        Some(0.02),
        Some(0.03),
    )]);
    log
}

#[test]
fn the_imported_files_round_trip_strictly() {
    let dir = tmp("roundtrip");
    let log = log();
    log.write(&dir).unwrap();
    let gnss = std::fs::read_to_string(dir.join("gnss.csv")).unwrap();
    assert_eq!(
        gnss.lines().next(),
        Some("t,lat,lon,height,eph,epv,vn,ve,vd,speed_accuracy")
    );
    assert_eq!(gnss.lines().nth(2), Some("0.2,0.8,0.15,488,,,,,,"));
    let back = LogDir::read(&dir, Strictness::Strict).unwrap();
    assert_eq!(back, log);
    let r = back.reference.as_ref().unwrap()[0];
    assert_eq!(r.position(), None);
    assert_eq!(r.attitude(), Some([0.01, 0.02, 0.03]));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_event_streams_merge_the_new_sensors_with_the_others() {
    let log = log();
    let kinds: Vec<(f64, &str)> = log
        .events()
        .map(|e| {
            let k = match e {
                Event::Imu(_) => "imu",
                Event::Mag(_) => "mag",
                Event::Baro(_) => "baro",
                Event::Gnss(_) => "gnss",
                _ => "other",
            };
            (e.t(), k)
        })
        .collect();
    let at = |t: f64| -> Vec<&str> {
        kinds
            .iter()
            .filter(|(s, _)| (*s - t).abs() < 1e-12)
            .map(|(_, k)| *k)
            .collect()
    };
    assert_eq!(at(0.1), ["imu", "mag", "gnss"]);
    assert_eq!(at(0.2), ["imu", "baro", "gnss"]);
    assert_eq!(kinds.len(), 5 + 2 + 1 + 2);
    // The streaming reader over the written files sees the same events.
    let dir = tmp("stream");
    log.write(&dir).unwrap();
    let files = LogFiles::open(&dir, Strictness::Strict).unwrap();
    let mut stream = EventStream::open(&files).unwrap();
    let mut streamed = Vec::new();
    while let Some(e) = stream.next_event().unwrap() {
        streamed.push(e.event);
    }
    // The stream of files and the stream of the log in memory agree; the
    // stream orders ties with the IMU last (every measurement stamped up to
    // an IMU sample's time comes before it), the in-memory iterator with the
    // IMU first: the same events.
    let mut memory = EventStream::of(&log);
    let mut in_memory = Vec::new();
    while let Some(e) = memory.next_event().unwrap() {
        in_memory.push(e.event);
    }
    assert_eq!(streamed, in_memory);
    let stream_at = |t: f64| -> Vec<&str> {
        streamed
            .iter()
            .filter(|e| (e.t() - t).abs() < 1e-12)
            .map(|e| match e {
                Event::Imu(_) => "imu",
                Event::Mag(_) => "mag",
                Event::Baro(_) => "baro",
                Event::Gnss(_) => "gnss",
                _ => "other",
            })
            .collect()
    };
    assert_eq!(stream_at(0.1), ["mag", "gnss", "imu"]);
    assert_eq!(stream_at(0.2), ["baro", "gnss", "imu"]);
    assert_eq!(streamed.len(), kinds.len());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_stream_continuing_a_prefetched_imu_gives_every_event_once() {
    let dir = tmp("prefetched");
    log().write(&dir).unwrap();
    let files = LogFiles::open(&dir, Strictness::Strict).unwrap();
    let all = |mut stream: EventStream<'_>| {
        let mut events = Vec::new();
        while let Some(e) = stream.next_event().unwrap() {
            events.push(e);
        }
        events
    };
    let plain = all(EventStream::open(&files).unwrap());
    // Read ahead 0, some and more than all of the 5 IMU rows.
    for ahead in [0, 2, 9] {
        let imu = files.imu().unwrap();
        let mut pre = Prefetched::new(Box::new(imu));
        let read: Vec<f64> = (0..ahead)
            .map_while(|_| pre.read_ahead().unwrap())
            .map(|r| r.t)
            .collect();
        assert_eq!(read.len(), ahead.min(5));
        // The magnetometer and GNSS files read ahead as well.
        let mut mag = Prefetched::new(Box::new(files.rows::<MagRow>().unwrap().unwrap()));
        let mut gnss = Prefetched::new(Box::new(files.rows::<GnssRow>().unwrap().unwrap()));
        for _ in 0..ahead.min(1) {
            assert!(mag.read_ahead().unwrap().is_some());
            assert!(gnss.read_ahead().unwrap().is_some());
        }
        assert_eq!(mag.read().count(), ahead.min(1));
        let continued = all(EventStream::open(&files)
            .unwrap()
            .with_rows(pre)
            .with_rows(mag)
            .with_rows(gnss));
        assert_eq!(continued, plain, "read ahead {ahead}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_stopped_log_ends_its_streams_with_an_error() {
    let dir = tmp("stopped");
    log().write(&dir).unwrap();
    let files = LogFiles::open(&dir, Strictness::Strict).unwrap();
    let mut stream = EventStream::open(&files).unwrap();
    assert!(stream.next_event().unwrap().is_some());
    // A clone shares the flag: a check holding a clone stops this stream.
    let checker = files.clone();
    assert!(!files.stopped());
    checker.stop();
    assert!(files.stopped());
    let err = stream.next_event().unwrap_err();
    assert!(matches!(err, LogError::Stopped { .. }), "{err}");
    assert!(err.to_string().contains("reading stopped"), "{err}");
    // A stream opened afterwards is stopped from its first event.
    let mut later = EventStream::open(&files).unwrap();
    assert!(matches!(later.next_event(), Err(LogError::Stopped { .. })));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_cells_name_file_line_and_column() {
    let cases = [
        (
            "gnss.csv",
            "t,lat,lon,height,eph,epv,vn,ve,vd,speed_accuracy\n0.1,47.4,8.5,488,,,,,,\n",
            "lat",
        ),
        (
            "gnss.csv",
            "t,lat,lon,height,eph,epv,vn,ve,vd,speed_accuracy\n0.1,0.8,0.15,488,-1,,,,,\n",
            "eph",
        ),
        (
            "gnss.csv",
            "t,lat,lon,height,eph,epv,vn,ve,vd,speed_accuracy\n0.1,0.8,0.15,,,,,,,\n",
            "height",
        ),
        (
            "reference.csv",
            "t,lat,lon,height,vn,ve,vd,roll,pitch,yaw\n0.1,,20,,,,,,,\n",
            "lon",
        ),
        ("mag.csv", "t,mx,my\n0.1,0.2,0.0\n", "mz"),
    ];
    for (i, (file, text, column)) in cases.into_iter().enumerate() {
        let dir = tmp(&format!("bad{i}"));
        log().write(&dir).unwrap();
        std::fs::write(dir.join(file), text).unwrap();
        let e = LogDir::read(&dir, Strictness::Strict).expect_err(text);
        match &e {
            LogError::Csv {
                file: f, column: c, ..
            } => {
                assert_eq!((f.as_str(), c.as_str()), (file, column), "{e}");
            }
            other => panic!("{file}: {other}"),
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
