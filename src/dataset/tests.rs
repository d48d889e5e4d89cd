//! Validation tests: each problem the loader must catch, with its line and column.

use super::*;

const HEADER: &str = "xray,finger,j1,j2,j3\n";

fn load(text: &str) -> Result<Dataset, DataError> {
    Dataset::from_bytes("t.csv", text.as_bytes())
}

fn problems(text: &str) -> Vec<Problem> {
    load(text).expect_err("expected a data error").problems
}

/// Asserts exactly one problem at (line, column) whose message contains `needle`.
fn one(text: &str, line: u64, column: Option<usize>, needle: &str) {
    let p = problems(text);
    assert_eq!(p.len(), 1, "{p:#?}");
    assert_eq!(p[0].line, Some(line), "{p:#?}");
    assert_eq!(p[0].column, column, "{p:#?}");
    assert!(
        p[0].message.contains(needle),
        "{:?} lacks {needle:?}",
        p[0].message
    );
}

#[test]
fn reads_the_paper_table() {
    let d = Dataset::load(Path::new("data/measurements.csv")).unwrap();
    assert_eq!(d.rows.len(), 25);
    assert_eq!(d.xray_count(), 5);
    let first = &d.rows[0];
    assert_eq!(&*first.xray, "1a");
    assert_eq!(first.finger, Finger::Index);
    // Table 1, Figure 1a, grooming: 339.96 188.83 169.67 (as printed).
    assert_eq!(first.segments(), &[339.96, 188.83, 169.67]);
    assert_eq!(first.meta.unit.as_deref(), Some("image units"));
    assert_eq!(d.rows_of(Finger::Thumb).count(), 5);
    assert!(d.rows_of(Finger::Thumb).all(|r| r.segments().len() == 2));
    assert_eq!(d.sha256.len(), 64);
}

#[test]
fn accepts_bom_crlf_quotes_blank_lines_and_aliases() {
    let text = "\u{feff}XRay,Finger,J1,J2,J3\r\n\"a\",Grooming,\"1.5\",2,3\r\n\r\nb,PINKY,1,2,3\r\nc,thumb,1,2,\r\n\r\n\r\n";
    let d = load(text).unwrap();
    assert_eq!(d.rows.len(), 3);
    assert_eq!(d.rows[0].finger, Finger::Index);
    assert_eq!(d.rows[0].lengths[0], 1.5);
    assert_eq!(d.rows[1].finger, Finger::Little);
    assert_eq!(d.rows[1].line, 4);
    assert_eq!(d.rows[2].segments(), &[1.0, 2.0]);
}

#[test]
fn missing_header_column() {
    let p = problems("xray,finger,j1,j2\na,thumb,1,2\n");
    assert_eq!(p.len(), 1);
    assert_eq!(p[0].line, Some(1));
    assert!(p[0].message.contains("'j3'"));
}

#[test]
fn unknown_header_column_and_duplicate_column() {
    let p = problems("xray,finger,j1,j2,j3,colour,j1\na,index,1,2,3,red,1\n");
    assert_eq!(p.len(), 2, "{p:#?}");
    assert_eq!(p[0].column, Some(6));
    assert!(p[0].message.contains("unknown column 'colour'"));
    assert_eq!(p[1].column, Some(7));
    assert!(p[1].message.contains("twice"));
}

#[test]
fn unknown_finger() {
    one(
        &format!("{HEADER}a,toe,1,2,3\n"),
        2,
        Some(2),
        "unknown finger 'toe'",
    );
}

#[test]
fn non_numeric_and_empty_lengths() {
    one(
        &format!("{HEADER}a,index,abc,2,3\n"),
        2,
        Some(3),
        "is not a number",
    );
    one(&format!("{HEADER}a,index,1,,3\n"), 2, Some(4), "is empty");
    one(
        &format!("{HEADER}a,index,1,2,\n"),
        2,
        Some(5),
        "three segments",
    );
}

#[test]
fn non_positive_lengths() {
    one(&format!("{HEADER}a,index,0,2,3\n"), 2, Some(3), "is zero");
    one(&format!("{HEADER}a,index,1,-2,3\n"), 2, Some(4), "negative");
}

#[test]
fn nan_infinity_and_overflow() {
    one(&format!("{HEADER}a,index,NaN,2,3\n"), 2, Some(3), "NaN");
    one(
        &format!("{HEADER}a,index,1,inf,3\n"),
        2,
        Some(4),
        "infinite",
    );
    one(
        &format!("{HEADER}a,index,1,2,-Infinity\n"),
        2,
        Some(5),
        "infinite",
    );
    one(
        &format!("{HEADER}a,index,1e400,2,3\n"),
        2,
        Some(3),
        "too large",
    );
    one(
        &format!("{HEADER}a,index,1e308,1e308,3\n"),
        2,
        None,
        "add up to more than",
    );
}

#[test]
fn decimal_comma_gets_a_hint() {
    one(
        &format!("{HEADER}a,index,\"339,96\",2,3\n"),
        2,
        Some(3),
        "write it with a point: 339.96",
    );
}

#[test]
fn thumb_with_j3() {
    one(
        &format!("{HEADER}a,thumb,1,2,3\n"),
        2,
        Some(5),
        "leave j3 empty",
    );
}

#[test]
fn duplicate_xray_finger() {
    one(
        &format!("{HEADER}a,index,1,2,3\nb,index,1,2,3\na,grooming,1,2,3\n"),
        4,
        Some(1),
        "already has an index row on line 2",
    );
}

#[test]
fn cr_only_line_ends_count_lines() {
    one(
        "xray,finger,j1,j2,j3\r\ra,index,1,2,3\rb,index,x,2,3\r",
        4,
        Some(3),
        "not a number",
    );
}

#[test]
fn empty_file_and_header_only() {
    for text in ["", "\n\n", "\u{feff}"] {
        let p = problems(text);
        assert_eq!(p.len(), 1);
        assert!(p[0].message.contains("is empty"), "{p:?}");
        assert_eq!(p[0].line, None);
    }
    let p = problems(HEADER);
    assert!(p[0].message.contains("no data rows"));
}

#[test]
fn non_utf8_bytes() {
    let mut bytes = HEADER.as_bytes().to_vec();
    bytes.extend_from_slice(b"a,index,1,2,3\nb\xff,index,1,2,3\n");
    let p = Dataset::from_bytes("t.csv", &bytes).unwrap_err().problems;
    assert_eq!(p.len(), 1);
    assert_eq!((p[0].line, p[0].column), (Some(3), Some(1)));
    assert_eq!(p[0].field.as_deref(), Some("xray"));
    assert!(p[0].message.contains("not UTF-8"));
}

#[test]
fn utf16_is_refused_whole() {
    let bytes = b"\xFF\xFEx\0r\0a\0y\0";
    let p = Dataset::from_bytes("t.csv", bytes).unwrap_err().problems;
    assert!(p[0].message.contains("UTF-16"));
}

#[test]
fn field_count_mismatch() {
    one(
        &format!("{HEADER}a,index,339,96,2,3\n"),
        2,
        None,
        "has 6 fields",
    );
    one(&format!("{HEADER}a,index,1,2\n"), 2, None, "has 4 fields");
}

#[test]
fn all_problems_are_reported_together() {
    let text = format!(
        "{HEADER}a,toe,1,2,3\nb,index,x,2,3\nc,thumb,1,2,3\nd,index,1,2,3\nd,index,1,2,3\n"
    );
    let p = problems(&text);
    let lines: Vec<u64> = p.iter().filter_map(|p| p.line).collect();
    assert_eq!(lines, vec![2, 3, 4, 6]);
    let shown = load(&text).unwrap_err().to_string();
    assert!(shown.starts_with("4 problems in t.csv:"), "{shown}");
    assert!(
        shown.contains("t.csv:3:3: j1: 'x' is not a number"),
        "{shown}"
    );
}

#[test]
fn metadata_is_validated_and_consistent_per_xray() {
    let h = "xray,finger,j1,j2,j3,sex,age,side\n";
    one(
        &format!("{h}a,index,1,2,3,f,abc,left\n"),
        2,
        Some(7),
        "not an age",
    );
    one(
        &format!("{h}a,index,1,2,3,f,30,up\n"),
        2,
        Some(8),
        "not a side",
    );
    one(
        &format!("{h}a,index,1,2,3,f,30,left\na,ring,1,2,3,m,30,left\n"),
        3,
        Some(6),
        "line 2 gives 'female'",
    );
    let d = load(&format!("{h}a,index,1,2,3,F,30,R\n")).unwrap();
    assert_eq!(d.rows[0].meta.sex.as_deref(), Some("female"));
    assert_eq!(d.rows[0].meta.side.as_deref(), Some("right"));
    assert_eq!(d.rows[0].meta.age, Some(30.0));
}

#[test]
fn long_values_are_shortened_in_messages() {
    let long = "x".repeat(1_000_000);
    let p = problems(&format!("{HEADER}a,index,{long},2,3\n"));
    assert!(p[0].message.len() < 200, "{}", p[0].message.len());
}

#[test]
fn spreadsheet_formulas_are_refused_in_text_fields() {
    let h = "xray,finger,j1,j2,j3,source\n";
    one(
        &format!("{h}=1+2,index,1,2,3,x\n"),
        2,
        Some(1),
        "spreadsheet formula; remove the leading '='",
    );
    one(
        &format!("{h}a,index,1,2,3,\"=HYPERLINK(\"\"http://x\"\")\"\n"),
        2,
        Some(6),
        "spreadsheet formula",
    );
    one(&format!("{h}@a,index,1,2,3,\n"), 2, Some(1), "leading '@'");
    // A leading minus is an ordinary id.
    assert!(load(&format!("{h}-1,index,1,2,3,\n")).is_ok());
}

#[test]
fn metacarpal_and_tip_columns() {
    let h = "xray,finger,j1,j2,j3,mc,unit,tip\n";
    let d = load(&format!(
        "{h}a,index,40,25,20,64.5,px,bone\na,thumb,30,25,,41,px,BONE\nb,ring,40,25,20,,px,skin\n"
    ))
    .unwrap();
    assert_eq!(d.rows[0].mc, Some(64.5));
    assert_eq!(d.rows[1].mc, Some(41.0));
    assert_eq!(d.rows[2].mc, None);
    assert_eq!(d.rows[0].meta.tip, Some(TipKind::Bone));
    assert_eq!(d.rows[1].meta.tip, Some(TipKind::Bone));
    let tips = d.tips();
    assert_eq!((tips.bone, tips.skin, tips.unknown), (2, 1, 0));
    assert_eq!(tips.single(), None);
    assert_eq!(
        tips.describe(),
        "mixed: 2 rows at the bone, 1 row at the skin"
    );
    assert_eq!(d.unit(), Some("px"));
    // The metacarpal is a length like the others; the tip is bone or skin.
    one(
        &format!("{h}a,index,1,2,3,-4,px,\n"),
        2,
        Some(6),
        "is negative",
    );
    one(
        &format!("{h}a,index,1,2,3,abc,px,\n"),
        2,
        Some(6),
        "is not a number",
    );
    one(
        &format!("{h}a,index,1,2,3,4,px,nail\n"),
        2,
        Some(8),
        "'nail' is not a fingertip kind; use bone",
    );
    // One hand has one kind of tip.
    one(
        &format!("{h}a,index,1,2,3,,px,bone\na,ring,1,2,3,,px,skin\n"),
        3,
        Some(8),
        "is 'skin', but line 2 gives 'bone' for the same X-ray 'a'",
    );
    // A file without the columns has neither.
    let d = load(&format!("{HEADER}a,index,1,2,3\n")).unwrap();
    assert_eq!((d.rows[0].mc, d.rows[0].meta.tip), (None, None));
    assert_eq!(d.tips().describe(), "not recorded");
    assert_eq!(d.unit(), None);
}

#[test]
fn units_are_per_row_and_one_hand_has_one() {
    let h = "xray,finger,j1,j2,j3,unit\n";
    // Rows of different X-rays in different units load; the dataset then has no one unit.
    let d = load(&format!(
        "{h}a,index,1,2,3,image units\nb,index,1,2,3,mm\nc,index,1,2,3,mm\nd,index,1,2,3,\n"
    ))
    .unwrap();
    assert_eq!(
        d.units(),
        [(Some("image units"), 1), (Some("mm"), 2), (None, 1)]
    );
    assert_eq!(d.unit(), None);
    assert_eq!(
        load(&format!("{h}a,index,1,2,3,mm\nb,ring,1,2,3,mm\n"))
            .unwrap()
            .unit(),
        Some("mm")
    );
    // The rows of one X-ray: one unit.
    let p = problems(&format!(
        "{h}a,index,1,2,3,mm\na,ring,1,2,3,px\nb,toe,1,2,3,mm\n"
    ));
    assert_eq!(p.len(), 2, "{p:#?}");
    assert_eq!((p[0].line, p[0].column), (Some(3), Some(6)));
    assert!(
        p[0].message
            .contains("is 'px', but line 2 gives 'mm' for the same X-ray 'a'"),
        "{}",
        p[0].message
    );
    assert_eq!(p[1].line, Some(4));
    assert!(is_pixel_unit("px") && is_pixel_unit(" Pixels ") && !is_pixel_unit("image units"));
}

#[test]
fn sex_age_and_side_may_be_left_empty_on_some_rows_of_a_hand() {
    let h = "xray,finger,j1,j2,j3,sex,age,side\n";
    let d = load(&format!(
        "{h}a,index,4,3,3,,,\na,ring,4,3,3,f,30,\na,thumb,4,3,,,30,left\nb,index,5,3,3,m,,\n"
    ))
    .unwrap();
    let hand = d.hand("a");
    assert_eq!(
        (hand.sex.as_deref(), hand.age, hand.side.as_deref()),
        (Some("female"), Some(30.0), Some("left"))
    );
    assert_eq!(d.hands()["b"].sex.as_deref(), Some("male"));
    assert_eq!(d.hand("zz"), Meta::default());
    // Two values given for one hand conflict, naming the line that gave the first.
    let p = problems(&format!(
        "{h}a,index,4,3,3,,,\na,ring,4,3,3,f,30,\na,thumb,4,3,,m,31,\n"
    ));
    assert_eq!(p.len(), 2, "{p:#?}");
    assert!(
        p[0].message
            .contains("is 'male', but line 3 gives 'female' for the same X-ray 'a'"),
        "{}",
        p[0].message
    );
    assert!(
        p[1].message.contains("is 31, but line 3 gives 30"),
        "{}",
        p[1].message
    );
}

#[test]
fn an_unquoted_decimal_comma_is_named_as_one() {
    let h = "xray,finger,j1,j2,j3,sex,age,side,source,unit\n";
    let p = problems(&format!(
        "{h}D1,index,346,65,201.4,178.0,,,right,lab,image units\n"
    ));
    assert_eq!(p.len(), 1, "{p:#?}");
    assert_eq!(
        p[0].message,
        "has 11 fields but the header has 10; j1 '346,65' looks like a number with a decimal comma: unquoted, the comma splits it in two fields; write it with a point (346.65)"
    );
    // Two of them, in j2 and j3.
    let p = problems(&format!(
        "{h}D1,index,346.6,201,4,178,0,,,right,lab,image units\n"
    ));
    assert!(
        p[0].message
            .contains("j2 '201,4' looks like a number with a decimal comma, j3 '178,0' looks like"),
        "{}",
        p[0].message
    );
    // Integers only and an extra field: more than one way to join them, so no such claim.
    let p = problems("xray,finger,j1,j2,j3\n9a,index,350,190,170,\n");
    assert!(
        p[0].message
            .ends_with("remove the extra fields, or quote a value that contains a comma"),
        "{}",
        p[0].message
    );
    // A join that leaves a non-number in a numeric column is no reading either.
    let p = problems("xray,finger,j1,j2,j3\n9a,index,350,190,170,x\n");
    assert!(!p[0].message.contains("decimal comma"), "{}", p[0].message);
}

#[test]
fn problems_across_the_reading_threads_batches() {
    // 3,000 records read in batches of 1,024 on the reading thread: problems on the
    // records either side of each batch boundary (lines 1025 and 1026: records 1024 and
    // 1025 after the header; lines 2049 and 2050), one found by the reading thread (a byte
    // that is not UTF-8) and the others by the table's code, come back together, each at
    // its own line and column, in file order. The row with the byte that is not UTF-8
    // is not read further: its J3 is not taken as 0 (no "lengths differ" problem too).
    let mut bytes = HEADER.as_bytes().to_vec();
    for i in 0..3000 {
        let line = i + 2;
        let row: Vec<u8> = match line {
            1025 => format!("x{i},index,1,-2,3\n").into_bytes(),
            1026 => [format!("x{i},index,1,2,").into_bytes(), b"3\xff\n".to_vec()].concat(),
            2049 => format!("x{i},index,1,2\n").into_bytes(),
            2050 => format!("x{i},indx,1,2,3\n").into_bytes(),
            _ => format!("x{i},index,1,2,3\n").into_bytes(),
        };
        bytes.extend_from_slice(&row);
    }
    let p = Dataset::from_bytes("t.csv", &bytes).unwrap_err().problems;
    let at: Vec<(Option<u64>, Option<usize>)> = p.iter().map(|p| (p.line, p.column)).collect();
    assert_eq!(
        at,
        [
            (Some(1025), Some(4)),
            (Some(1026), Some(5)),
            (Some(2049), None),
            (Some(2050), Some(2)),
        ],
        "{p:#?}"
    );
    assert!(p[1].message.contains("not UTF-8"), "{:?}", p[1].message);
    assert_eq!(p[1].field.as_deref(), Some("j3"));
    // The rows without problems are read, in order, when nothing is wrong.
    let fine: String = (0..3000).map(|i| format!("x{i},index,1,2,3\n")).collect();
    let d = load(&format!("{HEADER}{fine}")).unwrap();
    assert_eq!(d.rows.len(), 3000);
    assert!(
        d.rows
            .iter()
            .enumerate()
            .all(|(i, r)| r.line == i as u64 + 2)
    );
    assert_eq!(&*d.rows[2999].xray, "x2999");
}
