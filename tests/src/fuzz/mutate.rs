//! Structure-aware mutations of a valid seed file, and arbitrary bytes.
//!
//! A case is a seed (a real file of the format) with 1–8 mutations (mostly one to three) applied
//! in order: bytes set
//! or bit-flipped, lines deleted, duplicated or swapped, a number token replaced by NaN, inf,
//! a huge, negative or zero value, a binary word replaced by a special value (0, −1, huge
//! counts, NaN bits), bytes inserted or deleted, a truncation — or, one case in ten, arbitrary
//! bytes. Positions are fractions of the current length, so mutations stay meaningful as the
//! input changes, and proptest shrinks a failing case to fewer and simpler mutations.

use proptest::prelude::*;

/// Number texts that stress readers: non-finite, huge, tiny, negative, zero, malformed.
pub const SPECIAL_NUMBERS: [&str; 16] = [
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "1e-320",
    "-1",
    "0",
    "-0",
    "4294967296",
    "99999999999999999999",
    "-2147483649",
    "1.5",
    "1e",
    "--1",
];

/// Binary words (little-endian) that stress readers.
const SPECIAL_WORDS: [u64; 10] = [
    0,
    1,
    u64::MAX,
    0x7FF8_0000_0000_0000, // NaN bits
    0x7FF0_0000_0000_0000, // +inf bits
    i32::MAX as u64,
    0x8000_0000,
    1 << 32,
    1 << 40,
    65536,
];

/// One mutation; `at` and the like are fractions in [0, 1) of the current length.
#[derive(Debug, Clone)]
pub enum Mutation {
    SetByte { at: f64, byte: u8 },
    FlipBit { at: f64, bit: u8 },
    DeleteLine { at: f64 },
    DuplicateLine { at: f64 },
    SwapLines { a: f64, b: f64 },
    ReplaceNumber { at: f64, with: usize },
    Word { at: f64, wide: bool, with: usize },
    Insert { at: f64, bytes: Vec<u8> },
    DeleteRange { at: f64, len: usize },
    Truncate { at: f64 },
}

fn index(at: f64, len: usize) -> usize {
    ((at * len as f64) as usize).min(len.saturating_sub(1))
}

/// Byte ranges of the lines (without their `\n`).
fn line_ranges(b: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = 0;
    for (i, &c) in b.iter().enumerate() {
        if c == b'\n' {
            out.push((start, i));
            start = i + 1;
        }
    }
    if start < b.len() {
        out.push((start, b.len()));
    }
    out
}

/// Byte ranges of number-like tokens (digits with signs, dots and exponents).
fn number_ranges(b: &[u8]) -> Vec<(usize, usize)> {
    let numeric = |c: u8| c.is_ascii_digit() || matches!(c, b'.' | b'-' | b'+' | b'e' | b'E');
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if numeric(b[i]) {
            let s = i;
            while i < b.len() && numeric(b[i]) {
                i += 1;
            }
            if b[s..i].iter().any(u8::is_ascii_digit) {
                out.push((s, i));
            }
        } else {
            i += 1;
        }
    }
    out
}

impl Mutation {
    /// Applies the mutation to `b`.
    pub fn apply(&self, b: &mut Vec<u8>) {
        match *self {
            Mutation::SetByte { at, byte } if !b.is_empty() => {
                let i = index(at, b.len());
                b[i] = byte;
            }
            Mutation::FlipBit { at, bit } if !b.is_empty() => {
                let i = index(at, b.len());
                b[i] ^= 1 << (bit % 8);
            }
            Mutation::DeleteLine { at } => {
                let lines = line_ranges(b);
                if let Some(&(s, e)) = lines.get(index(at, lines.len())) {
                    b.drain(s..(e + 1).min(b.len()));
                }
            }
            Mutation::DuplicateLine { at } => {
                let lines = line_ranges(b);
                if let Some(&(s, e)) = lines.get(index(at, lines.len())) {
                    let mut copy = b[s..e].to_vec();
                    copy.push(b'\n');
                    b.splice(s..s, copy);
                }
            }
            Mutation::SwapLines { a, b: c } => {
                let lines = line_ranges(b);
                if lines.len() >= 2 {
                    let (i, j) = (index(a, lines.len()), index(c, lines.len()));
                    let (i, j) = (i.min(j), i.max(j));
                    if i != j {
                        let (li, lj) = (lines[i], lines[j]);
                        let (ti, tj) = (b[li.0..li.1].to_vec(), b[lj.0..lj.1].to_vec());
                        b.splice(lj.0..lj.1, ti);
                        b.splice(li.0..li.1, tj);
                    }
                }
            }
            Mutation::ReplaceNumber { at, with } => {
                let nums = number_ranges(b);
                if let Some(&(s, e)) = nums.get(index(at, nums.len())) {
                    let w = SPECIAL_NUMBERS[with % SPECIAL_NUMBERS.len()];
                    b.splice(s..e, w.bytes());
                }
            }
            Mutation::Word { at, wide, with } => {
                let n = if wide { 8 } else { 4 };
                if b.len() >= n {
                    let i = index(at, b.len() - n + 1);
                    let w = SPECIAL_WORDS[with % SPECIAL_WORDS.len()].to_le_bytes();
                    b[i..i + n].copy_from_slice(&w[..n]);
                }
            }
            Mutation::Insert { at, ref bytes } => {
                let i = ((at * (b.len() + 1) as f64) as usize).min(b.len());
                b.splice(i..i, bytes.iter().copied());
            }
            Mutation::DeleteRange { at, len } if !b.is_empty() => {
                let i = index(at, b.len());
                let e = (i + len).min(b.len());
                b.drain(i..e);
            }
            Mutation::Truncate { at } => {
                let i = (at * b.len() as f64) as usize;
                b.truncate(i);
            }
            _ => {}
        }
    }
}

fn frac() -> impl Strategy<Value = f64> {
    0.0f64..1.0
}

/// Any one mutation.
pub fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        3 => (frac(), any::<u8>()).prop_map(|(at, byte)| Mutation::SetByte { at, byte }),
        2 => (frac(), 0u8..8).prop_map(|(at, bit)| Mutation::FlipBit { at, bit }),
        3 => frac().prop_map(|at| Mutation::DeleteLine { at }),
        3 => frac().prop_map(|at| Mutation::DuplicateLine { at }),
        2 => (frac(), frac()).prop_map(|(a, b)| Mutation::SwapLines { a, b }),
        5 => (frac(), 0..SPECIAL_NUMBERS.len()).prop_map(|(at, with)| Mutation::ReplaceNumber { at, with }),
        2 => (frac(), any::<bool>(), 0..SPECIAL_WORDS.len())
            .prop_map(|(at, wide, with)| Mutation::Word { at, wide, with }),
        1 => (frac(), proptest::collection::vec(any::<u8>(), 1..16))
            .prop_map(|(at, bytes)| Mutation::Insert { at, bytes }),
        1 => (frac(), 1usize..64).prop_map(|(at, len)| Mutation::DeleteRange { at, len }),
        1 => frac().prop_map(|at| Mutation::Truncate { at }),
    ]
}

/// 1 to 8 mutations, mostly few: one mutation keeps most of a file valid, so the reader goes
/// deep into it; many find the interactions.
pub fn mutations() -> impl Strategy<Value = Vec<Mutation>> {
    use proptest::collection::vec;
    prop_oneof![
        4 => vec(mutation(), 1..2),
        3 => vec(mutation(), 2..4),
        1 => vec(mutation(), 4..9),
    ]
}

/// One fuzz input: the bytes, and how they were made (printed on failure).
#[derive(Clone)]
pub struct Input {
    pub bytes: Vec<u8>,
    pub how: String,
}

impl std::fmt::Debug for Input {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} ({} bytes)", self.how, self.bytes.len())
    }
}

/// Inputs for a format: mutated seeds (9 in 10) and arbitrary bytes up to `max_raw` long.
pub fn inputs(seeds: Vec<(String, Vec<u8>)>, max_raw: usize) -> impl Strategy<Value = Input> {
    assert!(!seeds.is_empty(), "a fuzz target needs seeds");
    let n = seeds.len();
    let mutated = (0..n, mutations()).prop_map(move |(k, ms)| {
        let (name, seed) = &seeds[k];
        let mut b = seed.clone();
        for m in &ms {
            m.apply(&mut b);
        }
        Input {
            bytes: b,
            how: format!("seed {name} with {ms:?}"),
        }
    });
    let raw = proptest::collection::vec(any::<u8>(), 0..max_raw).prop_map(|bytes| Input {
        how: "arbitrary bytes".into(),
        bytes,
    });
    prop_oneof![9 => mutated, 1 => raw]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_number_mutations_do_what_they_say() {
        let mut b = b"a 1\nb 2.5e3\nc -4\n".to_vec();
        Mutation::SwapLines { a: 0.0, b: 0.9 }.apply(&mut b);
        assert_eq!(b, b"c -4\nb 2.5e3\na 1\n");
        Mutation::ReplaceNumber { at: 0.5, with: 2 }.apply(&mut b);
        assert_eq!(b, b"c -4\nb inf\na 1\n");
        Mutation::DeleteLine { at: 0.0 }.apply(&mut b);
        assert_eq!(b, b"b inf\na 1\n");
        Mutation::DuplicateLine { at: 0.9 }.apply(&mut b);
        assert_eq!(b, b"b inf\na 1\na 1\n");
        Mutation::Truncate { at: 0.5 }.apply(&mut b);
        assert_eq!(b.len(), 7);
    }
}
