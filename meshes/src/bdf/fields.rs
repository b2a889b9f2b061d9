//! One physical line of bulk data split into its fields, and Nastran numbers.
//!
//! Formats (MSC Nastran Quick Reference Guide, "Bulk Data Entry Format"):
//! - **small field**: columns 1–8 the name (or a continuation marker), 9–72 eight data fields
//!   of 8 columns, 73–80 the continuation field (ignored: continuations follow their card);
//! - **large field**: a name ending in `*`; 9–72 four data fields of 16 columns; its
//!   continuation lines start with `*`;
//! - **free field**: fields separated by commas (a line with a comma is free field); a line
//!   has at most 8 data fields (4 for a large-field card) between its first field and an
//!   optional continuation field.
//!
//! Tabs expand to the next multiple of 8 columns. A continuation line starts with `+` (small
//! field), `*` (large field) or a blank first field.

/// What a line starts.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Head {
    /// A new card named `name` (upper case, without the large-field `*`).
    Card { name: String, large: bool },
    /// A continuation of the card before it.
    Continuation { large: bool },
}

/// A physical line's head and its data fields (trimmed; blank fields are empty strings),
/// padded to the line's full count (8 small, 4 large).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Split {
    pub head: Head,
    pub data: Vec<String>,
}

/// Splits `line` (comment already removed, not blank).
pub(crate) fn split(line: &str) -> Result<Split, String> {
    if line.contains(',') {
        split_free(line)
    } else {
        split_fixed(line)
    }
}

fn head_of(first: &str) -> Result<Head, String> {
    let f = first.trim();
    if f.is_empty() || f.starts_with('+') {
        return Ok(Head::Continuation { large: false });
    }
    if f.starts_with('*') {
        return Ok(Head::Continuation { large: true });
    }
    let (name, large) = match f.strip_suffix('*') {
        Some(n) => (n.trim(), true),
        None => (f, false),
    };
    if name.is_empty()
        || !name.starts_with(|c: char| c.is_ascii_alphabetic())
        || !name.chars().all(|c| c.is_ascii_alphanumeric())
    {
        return Err(format!(
            "`{}` is not a card name",
            super::super::deck::shorten(f)
        ));
    }
    Ok(Head::Card {
        name: name.to_ascii_uppercase(),
        large,
    })
}

fn split_free(line: &str) -> Result<Split, String> {
    let parts: Vec<&str> = line.split(',').collect();
    let head = head_of(parts[0])?;
    let large = match head {
        Head::Card { large, .. } | Head::Continuation { large } => large,
    };
    let per_line = if large { 4 } else { 8 };
    let mut data: Vec<String> = parts[1..].iter().map(|s| s.trim().to_string()).collect();
    // An optional continuation field after the data fields.
    if data.len() == per_line + 1 {
        data.pop();
    }
    // Trailing empty fields (a line ending in commas) are padding.
    while data.len() > per_line && data.last().is_some_and(|s| s.is_empty()) {
        data.pop();
    }
    if data.len() > per_line {
        return Err(format!(
            "free-field line has {} data fields; at most {per_line} (then a continuation field) \
             per line",
            data.len()
        ));
    }
    data.resize(per_line, String::new());
    check_fields(&data)?;
    Ok(Split { head, data })
}

fn split_fixed(line: &str) -> Result<Split, String> {
    // Expand tabs to the next multiple of 8 columns.
    let mut cols: Vec<char> = Vec::with_capacity(80);
    for c in line.chars() {
        if c == '\t' {
            cols.push(' ');
            while !cols.len().is_multiple_of(8) {
                cols.push(' ');
            }
        } else {
            cols.push(c);
        }
        if cols.len() >= 80 {
            break;
        }
    }
    let field = |a: usize, b: usize| -> String {
        if a >= cols.len() {
            return String::new();
        }
        cols[a..b.min(cols.len())]
            .iter()
            .collect::<String>()
            .trim()
            .to_string()
    };
    let head = head_of(&field(0, 8))?;
    let large = match head {
        Head::Card { large, .. } | Head::Continuation { large } => large,
    };
    let data: Vec<String> = if large {
        (0..4).map(|k| field(8 + 16 * k, 24 + 16 * k)).collect()
    } else {
        (0..8).map(|k| field(8 + 8 * k, 16 + 8 * k)).collect()
    };
    check_fields(&data)?;
    Ok(Split { head, data })
}

/// Fields may not hold blanks inside them, nor the free-field replication forms.
fn check_fields(data: &[String]) -> Result<(), String> {
    for f in data {
        if f.contains(char::is_whitespace) {
            return Err(format!("field `{f}` has a blank inside it"));
        }
        if f.starts_with('=') || (f.starts_with('*') && f.len() > 1) || f.starts_with('(') {
            return Err(format!(
                "field `{f}`: the free-field replication forms (=, ==, *n, (n)) are not read"
            ));
        }
    }
    Ok(())
}

/// A Nastran integer: optional sign and digits.
pub(crate) fn int(s: &str) -> Option<i64> {
    let digits = s.strip_prefix(['+', '-']).unwrap_or(s);
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    s.parse().ok()
}

/// A Nastran real: `1.0`, `1.`, `.5`, `-1.5E+3`, `1.5D3`, and the exponent without its letter
/// (`1.5+3`, `-.5-2`); an integer is read as a real too. Only finite values.
pub(crate) fn real(s: &str) -> Option<f64> {
    let u = s.to_ascii_uppercase().replace('D', "E");
    if u.is_empty()
        || !u
            .bytes()
            .all(|b| b.is_ascii_digit() || matches!(b, b'.' | b'E' | b'+' | b'-'))
    {
        return None;
    }
    let text = if u.contains('E') {
        u
    } else {
        // An exponent sign after the first character starts the exponent.
        match u[1..].find(['+', '-']) {
            Some(i) => format!("{}E{}", &u[..i + 1], &u[i + 1..]),
            None => u,
        }
    };
    // Rust accepts what Nastran does from here on (and "inf"/"nan" are excluded above).
    let mantissa_has_digit = text
        .split('E')
        .next()
        .is_some_and(|m| m.bytes().any(|b| b.is_ascii_digit()));
    if !mantissa_has_digit {
        return None;
    }
    text.parse::<f64>().ok().filter(|v| v.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        for (s, v) in [
            ("1.0", 1.0),
            ("1.", 1.0),
            (".5", 0.5),
            ("-.5", -0.5),
            ("+2.5", 2.5),
            ("1.5E+3", 1500.0),
            ("1.5e3", 1500.0),
            ("1.5D3", 1500.0),
            ("1.5+3", 1500.0),
            ("1.5-3", 1.5e-3),
            ("-.5-2", -0.005),
            ("7", 7.0),
            ("7.-1", 0.7),
        ] {
            assert_eq!(real(s), Some(v), "{s}");
        }
        for s in [
            "", "E3", ".", "1.0.0", "inf", "nan", "1e999", "1.0E", "--1", "1,0",
        ] {
            assert_eq!(real(s), None, "{s}");
        }
        assert_eq!(int("12"), Some(12));
        assert_eq!(int("-3"), Some(-3));
        assert_eq!(int("1.0"), None);
        assert_eq!(int("+"), None);
    }

    #[test]
    fn small_large_free() {
        let s = split("GRID    1       0       1.0     2.0     3.0     0").unwrap();
        assert_eq!(
            s.head,
            Head::Card {
                name: "GRID".into(),
                large: false
            }
        );
        assert_eq!(s.data[..6], ["1", "0", "1.0", "2.0", "3.0", "0"]);
        assert_eq!(s.data.len(), 8);
        let s = split("GRID*   1               0               1.0             2.0").unwrap();
        assert_eq!(
            s.head,
            Head::Card {
                name: "GRID".into(),
                large: true
            }
        );
        assert_eq!(s.data, ["1", "0", "1.0", "2.0"]);
        let s = split("*       3.0").unwrap();
        assert_eq!(s.head, Head::Continuation { large: true });
        assert_eq!(s.data[0], "3.0");
        let s = split("grid,1,,1.,2.,3.").unwrap();
        assert_eq!(s.data, ["1", "", "1.", "2.", "3.", "", "", ""]);
        let s = split("CHEXA,1,2,3,4,5,6,7,8,+C1").unwrap();
        assert_eq!(s.data, ["1", "2", "3", "4", "5", "6", "7", "8"]);
        let s = split("+C1,9,10").unwrap();
        assert_eq!(s.head, Head::Continuation { large: false });
        let s = split("\t9\t10").unwrap();
        assert_eq!(s.head, Head::Continuation { large: false });
        assert_eq!(s.data[..2], ["9", "10"]);
        assert!(split("GRID,1,2,3,4,5,6,7,8,9,10").is_err());
        assert!(split("GR-D    1").is_err());
        assert!(split("GRID,=,1").is_err());
    }
}
