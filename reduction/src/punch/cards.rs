//! Splitting bulk-data text into DMIG cards: small field (8-character fields), large field
//! (`DMIG*`, 16-character fields, `*` continuations) and free field (commas).

/// One bulk-data card: its first line (1-based), whether it was large-field, and its data
/// fields 2…9 of the first line and of every continuation, in order, trimmed.
#[derive(Debug)]
pub(crate) struct Card {
    pub line: usize,
    pub fields: Vec<String>,
    /// The line (1-based) each field was read from.
    pub field_lines: Vec<usize>,
}

/// Fixed-width field `[a, b)` of a line (clipped to its length), trimmed.
fn field(line: &str, a: usize, b: usize) -> &str {
    let b = b.min(line.len());
    if a >= b || !line.is_char_boundary(a) || !line.is_char_boundary(b) {
        return "";
    }
    line[a..b].trim()
}

/// First field and data fields of one physical line.
fn split_line(line: &str) -> (String, Vec<String>) {
    if line.contains(',') {
        let mut toks = line.split(',').map(|t| t.trim().to_string());
        let first = toks.next().unwrap_or_default();
        let mut data: Vec<String> = toks.collect();
        // Missing trailing fields are blank: pad to whole lines of 8 (large: 4) fields.
        let n = if first.ends_with('*') { 4 } else { 8 };
        let len = data.len().max(1).div_ceil(n) * n;
        data.resize(len, String::new());
        return (first, data);
    }
    let first = field(line, 0, 8).to_string();
    let large = first.ends_with('*');
    let (n, w) = if large { (4, 16) } else { (8, 8) };
    let data = (0..n)
        .map(|k| field(line, 8 + k * w, 8 + (k + 1) * w).to_string())
        .collect();
    (first, data)
}

/// The DMIG cards of a bulk-data text; every other card is skipped.
pub(crate) fn dmig_cards(text: &str) -> Vec<Card> {
    let mut cards = Vec::new();
    let mut current: Option<Card> = None;
    let mut in_other = false;
    for (k, raw) in text.lines().enumerate() {
        let line = raw.trim_end_matches(['\r', '\n']);
        if line.trim().is_empty() || line.starts_with('$') {
            continue;
        }
        let (first, data) = split_line(line);
        let first_up = first.to_ascii_uppercase();
        let is_continuation = first.is_empty() || first.starts_with('+') || first.starts_with('*');
        if is_continuation {
            if let Some(c) = current.as_mut() {
                c.field_lines.extend(std::iter::repeat_n(k + 1, data.len()));
                c.fields.extend(data);
            } else if !in_other {
                // A continuation with nothing to continue: keep it as its own (invalid) card
                // so that the reader reports the line.
                cards.push(Card {
                    line: k + 1,
                    fields: Vec::new(),
                    field_lines: Vec::new(),
                });
            }
            continue;
        }
        if let Some(c) = current.take() {
            cards.push(c);
        }
        if first_up == "DMIG" || first_up == "DMIG*" {
            in_other = false;
            current = Some(Card {
                line: k + 1,
                field_lines: vec![k + 1; data.len()],
                fields: data,
            });
        } else {
            in_other = true;
        }
    }
    if let Some(c) = current.take() {
        cards.push(c);
    }
    cards
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_large_and_free_fields_flatten_alike() {
        // The same column card in the three field formats of the NASTRAN Quick Reference Guide.
        let small = format!(
            "{:<8}{:<8}{:>8}{:>8}{:8}{:>8}{:>8}{:>8}\n{:<8}{:>8}{:>8}{:>8}\n",
            "DMIG", "K", 100, 1, "", 100, 1, "3.5", "+", 100, 2, "-1.2"
        );
        let large = "DMIG*   K                            100               1\n\
                     *                    100               1 3.500000000D+00\n\
                     *                    100               2-1.200000000D+00\n";
        let free = "DMIG,K,100,1,,100,1,3.5\n,100,2,-1.2\n";
        for text in [small.as_str(), large, free] {
            let cards = dmig_cards(text);
            assert_eq!(cards.len(), 1, "{text}");
            let f: Vec<&str> = cards[0]
                .fields
                .iter()
                .map(String::as_str)
                .filter(|s| !s.is_empty())
                .collect();
            assert_eq!(f[..5], ["K", "100", "1", "100", "1"], "{text}");
            assert_eq!(f.len(), 9, "{f:?}");
            // Groups of four (G, C, A, B) start at field 5 of every format.
            assert_eq!(cards[0].fields[8], "100", "{text}");
            assert_eq!(cards[0].fields[9], "2", "{text}");
        }
    }
}
