//! NASTRAN real numbers: reading every form the bulk data accepts, writing the shortest form
//! that fits a field.

/// Parses a NASTRAN real: `1.5`, `1.5E+3`, `1.5D+3`, the compressed exponent forms `1.-3`,
/// `-.5+2`, and plain integers. `None` for anything else, and for non-finite values (a file
/// never holds NaN or infinity legitimately).
pub(crate) fn parse_real(field: &str) -> Option<f64> {
    let t = field.trim();
    if t.is_empty() || t.len() > 64 {
        return None;
    }
    let ok_chars = t
        .bytes()
        .all(|b| b.is_ascii_digit() || matches!(b, b'.' | b'+' | b'-' | b'E' | b'e' | b'D' | b'd'));
    if !ok_chars {
        return None;
    }
    let mut s: String = t
        .chars()
        .map(|c| if c == 'D' || c == 'd' { 'E' } else { c })
        .collect();
    if !s.contains(['E', 'e']) {
        // Compressed exponent: a sign after the first character starts the exponent.
        if let Some(k) = s[1..].find(['+', '-']) {
            s.insert(k + 1, 'E');
        }
    }
    let v: f64 = s.parse().ok()?;
    v.is_finite().then_some(v)
}

/// Formats `v` in at most `width` characters as a NASTRAN real, with as many significant
/// digits as fit (exactly, when the shortest round-trip representation fits). `exp_char` is
/// `'E'` or `'D'`; the compressed form (`1.2345-7`) is used when it buys a digit.
pub(crate) fn format_real(v: f64, width: usize, exp_char: char) -> Option<String> {
    if !v.is_finite() {
        return None;
    }
    if v == 0.0 {
        return Some("0.".to_string());
    }
    // Shortest round-trip digits first, then fewer and fewer.
    let shortest = format!("{v:e}");
    let mantissa_digits = shortest
        .split('e')
        .next()
        .map(|m| m.bytes().filter(u8::is_ascii_digit).count())
        .unwrap_or(17);
    for digits in (1..=mantissa_digits.min(17)).rev() {
        for cand in candidates(v, digits, exp_char) {
            if cand.len() <= width {
                return Some(cand);
            }
        }
    }
    None
}

/// Representations of `v` rounded to `digits` significant digits, shortest-looking first.
fn candidates(v: f64, digits: usize, exp_char: char) -> Vec<String> {
    let sci = format!("{:.*e}", digits - 1, v);
    let (mant, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let mant = if mant.contains('.') {
        mant.to_string()
    } else {
        format!("{mant}.")
    };
    let mut out = Vec::with_capacity(3);
    // Plain decimal when the exponent is modest.
    if (-6..=15).contains(&exp) {
        let rounded: f64 = sci.parse().unwrap_or(v);
        let mut plain = format!("{rounded}");
        if !plain.contains('.') {
            plain.push('.');
        }
        if let Some(rest) = plain.strip_prefix("0.") {
            plain = format!(".{rest}");
        } else if let Some(rest) = plain.strip_prefix("-0.") {
            plain = format!("-.{rest}");
        }
        out.push(plain);
    }
    let sign = if exp < 0 { '-' } else { '+' };
    out.push(format!("{mant}{exp_char}{sign}{:02}", exp.abs()));
    out.push(format!("{mant}{sign}{}", exp.abs()));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nastran_forms_parse() {
        // Forms from the NASTRAN Quick Reference Guide, "bulk data real numbers".
        assert_eq!(parse_real("1.-3"), Some(1.0e-3));
        assert_eq!(parse_real("-.5+2"), Some(-50.0));
        assert_eq!(parse_real(" 7. "), Some(7.0));
        assert_eq!(parse_real("1.5D+03"), Some(1500.0));
        assert_eq!(parse_real("-2.5e-1"), Some(-0.25));
        assert_eq!(parse_real("12"), Some(12.0));
        assert_eq!(parse_real("1.0+100"), Some(1.0e100));
        assert_eq!(parse_real("NaN"), None);
        assert_eq!(parse_real("inf"), None);
        assert_eq!(parse_real("1.0E+999"), None);
        assert_eq!(parse_real(""), None);
        assert_eq!(parse_real("abc"), None);
    }

    #[test]
    fn formats_fit_and_round_trip() {
        for &v in &[
            1.0,
            -0.5,
            0.1,
            -1234.5678,
            1.0 / 3.0,
            6.02214076e23,
            -1.602176634e-19,
            1e-300,
            123456789.0,
        ] {
            for &w in &[8usize, 16] {
                let s = format_real(v, w, 'D').unwrap();
                assert!(s.len() <= w, "{s} longer than {w}");
                let back = parse_real(&s).unwrap();
                // 8 characters keep at least 3 significant digits, 16 at least 10.
                let tol = if w == 8 { 5e-3 } else { 5e-10 };
                assert!((back - v).abs() <= tol * v.abs(), "{v} -> {s} -> {back}");
            }
        }
        // Values whose shortest form fits are exact.
        assert_eq!(format_real(-12.375, 8, 'E').unwrap(), "-12.375");
        assert_eq!(parse_real(&format_real(0.1, 8, 'E').unwrap()), Some(0.1));
    }
}
