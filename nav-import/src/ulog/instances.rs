//! Several instances of one topic (`multi_id` 0, 1, ...: two magnetometers,
//! two IMUs): the importer reads the lowest instance, and where that one
//! stops before another still has samples, it continues with the other, so
//! that no stretch of the log is dropped without a word (docs/ulog.md,
//! "Several instances").
//!
//! A topic that stops well before the end of the log with no other instance
//! to continue it is said in the warnings too.

use super::decode::Table;

/// A gap after the last sample of an instance, in sample intervals, beyond
/// which the instance is taken to have stopped.
const STOPPED_INTERVALS: f64 = 10.0;
/// ... and at least this long, us.
const STOPPED_MIN_US: f64 = 100_000.0;

/// Sample time of row `r` (us): `timestamp_sample` where set, else `timestamp`.
fn time(t: &Table, r: usize) -> Option<f64> {
    let sample = t.column("timestamp_sample").map(|c| t.at(r, c));
    match (sample, t.column("timestamp")) {
        (Some(s), _) if s > 0.0 => Some(s),
        (_, Some(c)) => Some(t.at(r, c)),
        (s, None) => s,
    }
}

/// The last sample time and the median sample interval of `t`, us.
fn span(t: &Table) -> Option<(f64, f64)> {
    let n = t.rows();
    let last = time(t, n.checked_sub(1)?)?;
    let mut steps: Vec<f64> = (1..n)
        .filter_map(|r| Some(time(t, r)? - time(t, r - 1)?))
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    steps.sort_by(f64::total_cmp);
    let median = steps.get(steps.len() / 2).copied().unwrap_or(0.0);
    Some((last, median))
}

/// `tables` with, for every topic, the lowest instance continued by the
/// rows of the others after it stops (columns matched by name; a column the
/// other instance lacks is an empty cell, which drops the row when the file
/// needs it). `origin_us` is the log's start, for the times in the warnings.
pub fn splice(tables: Vec<Table>, origin_us: f64, warnings: &mut Vec<String>) -> Vec<Table> {
    let mut out = tables;
    let log_end = out
        .iter()
        .filter_map(|t| span(t).map(|(end, _)| end))
        .fold(f64::NEG_INFINITY, f64::max);
    let s = |us: f64| (us - origin_us) * 1e-6;
    let mut topics: Vec<String> = out.iter().map(|t| t.topic.clone()).collect();
    topics.sort_unstable();
    topics.dedup();
    for topic in topics {
        let mut group: Vec<usize> = (0..out.len())
            .filter(|&i| out[i].topic == *topic && out[i].rows() > 0)
            .collect();
        group.sort_by_key(|&i| (out[i].instance, std::cmp::Reverse(out[i].rows())));
        let Some((&primary, others)) = group.split_first() else {
            continue;
        };
        let Some((mut end, interval)) = span(&out[primary]) else {
            continue;
        };
        let stopped = |end: f64, other_end: f64| {
            other_end - end > (STOPPED_INTERVALS * interval).max(STOPPED_MIN_US)
        };
        for &o in others {
            let Some((other_end, _)) = span(&out[o]) else {
                continue;
            };
            if !stopped(end, other_end) {
                continue;
            }
            let from = (0..out[o].rows()).find(|&r| time(&out[o], r).is_some_and(|t| t > end));
            let Some(from) = from else { continue };
            let map: Vec<Option<usize>> = out[primary]
                .columns
                .iter()
                .map(|c| out[o].column(c))
                .collect();
            let mut added = Vec::new();
            for r in from..out[o].rows() {
                added.extend(map.iter().map(|m| m.map_or(f64::NAN, |c| out[o].at(r, c))));
            }
            let rows = out[o].rows() - from;
            let start = time(&out[o], from).unwrap_or(f64::NAN);
            warnings.push(format!(
                "{topic}: multi_id {} stops at t = {:.3} s; continued with multi_id {} from t = {:.3} s ({rows} rows)",
                out[primary].instance,
                s(end),
                out[o].instance,
                s(start),
            ));
            out[primary].values.extend(added);
            end = other_end;
        }
        if stopped(end, log_end) {
            warnings.push(format!(
                "{topic}: stops at t = {:.3} s, {:.1} s before the log's last message (no other instance continues it)",
                s(end),
                (log_end - end) * 1e-6
            ));
        }
    }
    out
}
