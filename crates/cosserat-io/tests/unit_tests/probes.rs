//! `probes.csv`: header and rows at full precision, row length checks, non-finite values refused.

use cosserat_io::{OutputError, ProbeWriter};

use super::test_dir;

const COLUMNS: [&str; 3] = ["tip.ux", "tip.uy", "tip.uz"];

#[test]
fn header_and_rows_read_back_exactly() {
    let dir = test_dir("probes_rows");
    let path = dir.join("probes.csv");
    let mut writer = ProbeWriter::create(&path, &COLUMNS).expect("create");
    let rows = [
        (0.0, [0.0, -0.0, 1e-300]),
        (0.1, [0.1 + 0.2, -1.0 / 3.0, 6.02214076e23]),
        (0.2, [f64::MIN_POSITIVE, 5e-324, -f64::MAX]),
    ];
    for (t, values) in &rows {
        writer.write_row(*t, values).expect("write row");
    }
    assert_eq!(writer.n_rows(), 3);

    let text = std::fs::read_to_string(&path).expect("read");
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,tip.ux,tip.uy,tip.uz"));
    for (t, values) in &rows {
        let parsed: Vec<f64> = lines
            .next()
            .expect("a row")
            .split(',')
            .map(|field| field.parse().expect("a number"))
            .collect();
        let expected: Vec<f64> = std::iter::once(*t).chain(values.iter().copied()).collect();
        assert_eq!(parsed.len(), 4);
        for (p, e) in parsed.iter().zip(&expected) {
            assert_eq!(p.to_bits(), e.to_bits(), "{p:e} != {e:e}");
        }
    }
    assert_eq!(lines.next(), None);
    assert!(text.ends_with('\n'));
}

#[test]
fn rows_of_the_wrong_length_are_refused_without_writing() {
    let dir = test_dir("probes_length");
    let path = dir.join("probes.csv");
    let mut writer = ProbeWriter::create(&path, &COLUMNS).expect("create");
    writer.write_row(0.0, &[1.0, 2.0, 3.0]).expect("valid row");
    let before = std::fs::read(&path).expect("read");
    let error = writer.write_row(1.0, &[1.0, 2.0]).expect_err("two values for three columns");
    assert!(
        matches!(
            error,
            OutputError::ProbeRowLength {
                row: 1,
                expected: 3,
                found: 2
            }
        ),
        "{error:?}"
    );
    assert!(matches!(
        writer.write_row(1.0, &[1.0; 4]),
        Err(OutputError::ProbeRowLength { found: 4, .. })
    ));
    assert_eq!(std::fs::read(&path).expect("read"), before);
    assert_eq!(writer.n_rows(), 1);
}

#[test]
fn non_finite_values_are_refused_naming_the_column() {
    let dir = test_dir("probes_non_finite");
    let path = dir.join("probes.csv");
    let mut writer = ProbeWriter::create(&path, &COLUMNS).expect("create");
    let before = std::fs::read(&path).expect("read");
    let error = writer.write_row(0.5, &[0.0, f64::NAN, 0.0]).expect_err("NaN");
    assert!(
        matches!(&error, OutputError::NonFiniteProbe { column, row: 0, .. } if column == "tip.uy"),
        "{error:?}"
    );
    assert!(error.to_string().contains("tip.uy"));
    let error = writer.write_row(f64::INFINITY, &[0.0; 3]).expect_err("infinite time");
    assert!(
        matches!(&error, OutputError::NonFiniteProbe { column, .. } if column == "t"),
        "{error:?}"
    );
    assert_eq!(std::fs::read(&path).expect("read"), before);
}

#[test]
fn malformed_and_duplicate_columns_are_refused() {
    let dir = test_dir("probes_columns");
    let path = dir.join("probes.csv");
    for bad in ["tip", ".ux", "tip.", "tip.u x", "tip,a.ux", "t"] {
        let error = ProbeWriter::create(&path, &[bad]).expect_err("malformed column");
        assert!(matches!(error, OutputError::InvalidName { .. }), "{bad}: {error:?}");
    }
    let error = ProbeWriter::create(&path, &["tip.ux", "tip.ux"]).expect_err("duplicate");
    assert!(matches!(error, OutputError::DuplicateName { .. }), "{error:?}");
    assert!(!path.exists());
}

#[test]
fn reopening_refuses_a_kept_row_that_is_damaged() {
    let dir = test_dir("probes_reopen_damaged");
    let path = dir.join("probes.csv");
    let mut writer = ProbeWriter::create(&path, &COLUMNS).expect("create");
    for k in 0..3 {
        writer.write_row(f64::from(k), &[1.0, 2.0, 3.0]).expect("write row");
    }
    drop(writer);
    let good = std::fs::read_to_string(&path).expect("read");
    for (damaged, reason) in [
        ("1,1,2,3\n", ""),
        ("1,1,2\n", "3 values where the header names 4"),
        ("1,1,2,3,4\n", "5 values where the header names 4"),
        ("1,1,x,3\n", "`x` is not a finite number"),
        ("1,1,NaN,3\n", "`NaN` is not a finite number"),
    ] {
        let text = good.replacen("1,1,2,3\n", damaged, 1);
        std::fs::write(&path, &text).expect("damage the file");
        let result = ProbeWriter::reopen(&path, &COLUMNS, 2);
        if damaged == "1,1,2,3\n" {
            result.expect("an intact file reopens");
            continue;
        }
        let error = result.expect_err("a damaged row is refused").to_string();
        assert!(error.contains("row 1 (line 3) is damaged"), "{error}");
        assert!(error.contains(reason), "{error}");
        assert_eq!(
            std::fs::read_to_string(&path).expect("read"),
            text,
            "the refusal changed the file"
        );
    }
}
