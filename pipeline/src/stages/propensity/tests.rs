use super::*;

#[test]
fn value_texts_read_back_as_the_same_number() {
    for x in [0.35, 1.0, 3e-7, 1.2e20, -4.5, 0.1 + 0.2] {
        let t = value_text(x);
        let doc: toml::Table = format!("v = {t}").parse().unwrap();
        assert_eq!(doc["v"].as_float(), Some(x), "{t}");
    }
}

#[test]
fn flags_parse_and_bad_ones_name_the_flag() {
    assert_eq!(
        parse_dist_flag("friction.law.mu=uniform(0.3, 0.5)").unwrap(),
        ("friction.law.mu".into(), "uniform(0.3, 0.5)".into())
    );
    let e = parse_dist_flag("friction.law.mu").unwrap_err().to_string();
    assert!(
        e.contains("--dist friction.law.mu") && e.contains("KEY=DIST"),
        "{e}"
    );
    assert_eq!(
        parse_corr_flag("a.b:c.d=0.5").unwrap(),
        ("a.b".into(), "c.d".into(), 0.5)
    );
    let e = parse_corr_flag("a.b:c.d=x").unwrap_err().to_string();
    assert!(e.contains("--corr a.b:c.d=x") && e.contains("`x`"), "{e}");
}

/// The automatic replicate count uses the most of the budget: d = 2 (4 rows per base point)
/// and 1 000 evaluations: 7 × 32 × 4 = 896 (4 replicates would use 512).
#[test]
fn replicates_fill_the_budget() {
    assert_eq!(auto_replicates(1000, 4), 7);
    assert_eq!(auto_replicates(1024, 2), 4);
}
