//! Property tests: arbitrary bytes never panic the reader; random mutations of valid
//! files give either clean data or an error that points at a real line and column.

use nav_runtime::log::*;
use proptest::prelude::*;

fn parse_all(bytes: &[u8], s: Strictness) {
    let _ = parse_csv::<ImuRow>(bytes, s);
    let _ = parse_csv::<DvlRow>(bytes, s);
    let _ = parse_csv::<DepthRow>(bytes, s);
    let _ = parse_csv::<UsblRow>(bytes, s);
    let _ = parse_csv::<AltitudeRow>(bytes, s);
    let _ = parse_csv::<TruthRow>(bytes, s);
}

const VALID_DVL: &str = "t,vx,vy,vz\n0.0,1.0,0.1,0.0\n0.2,,,\n0.4,1.1,0.05,-0.01\n0.6,1.2,0.0,0.0\n0.8,1e-3,2.5,3\n1.0,1,1,1\n";

#[derive(Debug, Clone)]
enum Mutation {
    Delete(usize),
    Insert(usize, u8),
    Replace(usize, u8),
    DuplicateLine(usize),
    SwapLines(usize, usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let byte = prop::sample::select(b",.-+e0123456789nainf \n\rx".to_vec());
    prop_oneof![
        any::<usize>().prop_map(Mutation::Delete),
        (any::<usize>(), byte.clone()).prop_map(|(i, b)| Mutation::Insert(i, b)),
        (any::<usize>(), byte).prop_map(|(i, b)| Mutation::Replace(i, b)),
        any::<usize>().prop_map(Mutation::DuplicateLine),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
    ]
}

fn apply(text: &mut Vec<u8>, m: &Mutation) {
    let n = text.len().max(1);
    match *m {
        Mutation::Delete(i) => {
            if !text.is_empty() {
                text.remove(i % n);
            }
        }
        Mutation::Insert(i, b) => text.insert(i % (text.len() + 1), b),
        Mutation::Replace(i, b) => {
            if !text.is_empty() {
                text[i % n] = b;
            }
        }
        Mutation::DuplicateLine(i) | Mutation::SwapLines(i, _) => {
            let mut lines: Vec<Vec<u8>> = text.split(|&b| b == b'\n').map(<[u8]>::to_vec).collect();
            let k = i % lines.len();
            if let Mutation::SwapLines(_, j) = *m {
                let j = j % lines.len();
                lines.swap(k, j);
            } else {
                let l = lines[k].clone();
                lines.insert(k, l);
            }
            *text = lines.join(&b'\n');
        }
    }
}

/// Number of non-blank lines (what the reader sees as header + rows).
fn nonblank_lines(text: &[u8]) -> usize {
    text.split(|&b| b == b'\n')
        .filter(|l| !l.iter().all(u8::is_ascii_whitespace))
        .count()
}

fn total_lines(text: &[u8]) -> u64 {
    text.split(|&b| b == b'\n').count() as u64
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_bytes_as_csv_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        parse_all(&bytes, Strictness::Strict);
        parse_all(&bytes, Strictness::Lenient);
    }

    #[test]
    fn arbitrary_csv_like_text_never_panics(text in "[t,vxyzdephlaonr0-9.eE+\\-\n\r \"]{0,300}") {
        parse_all(text.as_bytes(), Strictness::Strict);
        parse_all(text.as_bytes(), Strictness::Lenient);
    }

    #[test]
    fn arbitrary_bytes_as_meta_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let _ = Meta::parse(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn arbitrary_toml_like_meta_never_panics(
        text in "(\\[(initial|initial_sigma|sensors|sensors\\.(imu|dvl|usbl|sonar)|usbl)\\]\n|(lat|lon|depth|roll|noise_sigma|bias_sigma|x) = (-?[0-9]{1,3}(\\.[0-9]{1,3})?|nan|inf|\"s\"|\\[1\\]|\\{\\})\n){0,12}"
    ) {
        match Meta::parse(&text) {
            Ok(m) => {
                // Whatever is accepted is in range and survives a round trip.
                // An attitude-only `[initial]` (no position) has NaN position
                // fields, which compare unequal: its text round-trips instead.
                if m.initial.has_position() {
                    prop_assert!(m.initial.lat.abs() <= std::f64::consts::FRAC_PI_2);
                    prop_assert_eq!(Meta::parse(&m.to_toml()).unwrap(), m);
                } else {
                    let back = Meta::parse(&m.to_toml()).unwrap();
                    prop_assert!(!back.initial.has_position());
                    prop_assert_eq!(back.to_toml(), m.to_toml());
                }
            }
            Err(e) => {
                prop_assert!(e.to_string().starts_with("meta.toml"));
                prop_assert!(!e.to_string().contains('\n'));
                if let Some(line) = e.line() {
                    prop_assert!(line >= 1 && line <= text.lines().count().max(1) as u64 + 1);
                }
            }
        }
    }

    #[test]
    fn mutated_rows_are_rejected_precisely_or_accepted_cleanly(
        mutations in prop::collection::vec(mutation(), 1..6)
    ) {
        let mut text = VALID_DVL.as_bytes().to_vec();
        for m in &mutations {
            apply(&mut text, m);
        }
        let lines = total_lines(&text);
        match parse_csv::<DvlRow>(&text[..], Strictness::Strict) {
            Ok(table) => {
                prop_assert_eq!(table.skipped, 0);
                prop_assert_eq!(table.rows.len() + 1, nonblank_lines(&text));
                for w in table.rows.windows(2) {
                    prop_assert!(w[0].t < w[1].t);
                }
                for r in &table.rows {
                    prop_assert!(r.t.is_finite());
                    for v in [r.vx, r.vy, r.vz].into_iter().flatten() {
                        prop_assert!(v.is_finite());
                    }
                }
            }
            Err(LogError::Csv { file, line, column, .. }) => {
                prop_assert_eq!(file, "dvl.csv");
                prop_assert!(line >= 1 && line <= lines, "line {} of {}", line, lines);
                prop_assert!(
                    DvlRow::COLUMNS.contains(&column.as_str()) || column.starts_with("<column "),
                    "column {}", column
                );
            }
            Err(LogError::EmptyFile { .. }) => prop_assert_eq!(nonblank_lines(&text), 0),
            Err(other) => prop_assert!(false, "unexpected error {:?}", other),
        }
        match parse_csv::<DvlRow>(&text[..], Strictness::Lenient) {
            Ok(table) => {
                // Every data line is either accepted or counted as skipped.
                prop_assert_eq!(table.rows.len() + table.skipped + 1, nonblank_lines(&text));
                for w in table.rows.windows(2) {
                    prop_assert!(w[0].t < w[1].t);
                }
            }
            Err(LogError::Csv { line, problem: CsvProblem::WrongHeader { .. }, .. }) => {
                prop_assert!(line >= 1 && line <= lines);
            }
            // A header naming a column twice is the header's error (lenient
            // reading skips bad rows, not a bad header).
            Err(LogError::Csv { line, problem: CsvProblem::DuplicateColumn { .. }, .. }) => {
                prop_assert!(line >= 1 && line <= lines);
            }
            Err(LogError::EmptyFile { .. }) => {}
            Err(other) => prop_assert!(false, "unexpected lenient error {:?}", other),
        }
    }
}

/// The case the mutation test found: a header naming `t` twice is refused
/// by the lenient reader as the header's error, at line 1 and the column.
#[test]
fn a_header_naming_a_column_twice_is_refused_in_lenient_reading() {
    let text = b"t,vx,vy,vz,t\n0.5,1.0,0.0,0.0,0.5\n";
    match parse_csv::<DvlRow>(&text[..], Strictness::Lenient) {
        Err(LogError::Csv {
            line: 1,
            column,
            problem: CsvProblem::DuplicateColumn { .. },
            ..
        }) => assert_eq!(column, "t"),
        other => panic!("{other:?}"),
    }
}
