//! The mutations of the fuzzer: byte-level (flipped bits, truncation,
//! deleted or repeated spans, invalid UTF-8, very long runs), JSON-aware
//! (a number replaced by NaN, an infinity, a huge or negative value or
//! another type; an object member removed or duplicated) and line-level
//! (a line removed, repeated, swapped or split: wrong counts in NDJSON).

use super::Rng;
use rand::RngExt;

/// Values that replace a number: not numbers in JSON (NaN, infinities),
/// out of the range of f64 or u64, negative, zero, at the edges of the
/// types, or of another type.
pub const ODD_VALUES: [&str; 30] = [
    "NaN",
    "Infinity",
    "-Infinity",
    "nan",
    "1e309",
    "-1e309",
    "1.7e308",
    "-1.7e308",
    "1e-320",
    "-1",
    "-0",
    "0",
    "1",
    "0.5",
    "2.5e9",
    "255",
    "256",
    "22",
    "4097",
    "4294967296",
    "9223372036854775808",
    "18446744073709551615",
    "18446744073709551616",
    "123456789012345678901234567890",
    "null",
    "true",
    "\"7\"",
    "[]",
    "{}",
    "[1,2,3,4,5,6,7,8]",
];

/// Byte sequences that are not UTF-8.
const NOT_UTF8: [&[u8]; 4] = [&[0xff], &[0xc3], &[0xed, 0xa0, 0x80], &[0xf8, 0x88, 0x80]];

/// Inside a JSON string at byte `i`: step past the byte (and the one an
/// escape covers), note a closing quote, and return true; else false.
fn inside_string(text: &[u8], i: &mut usize, in_str: &mut bool) -> bool {
    if !*in_str {
        return false;
    }
    match text[*i] {
        b'\\' => *i += 1,
        b'"' => *in_str = false,
        _ => {}
    }
    *i += 1;
    true
}

/// Spans `(start, end)` of the numbers of JSON `text` (outside strings).
pub fn numbers(text: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let (mut i, mut in_str) = (0, false);
    while i < text.len() {
        let c = text[i];
        if inside_string(text, &mut i, &mut in_str) {
            continue;
        }
        if c == b'"' {
            in_str = true;
            i += 1;
        } else if c == b'-' || c.is_ascii_digit() {
            let s = i;
            while i < text.len()
                && matches!(text[i], b'-' | b'+' | b'.' | b'e' | b'E' | b'0'..=b'9')
            {
                i += 1;
            }
            out.push((s, i));
        } else {
            i += 1;
        }
    }
    out
}

/// Spans `(start, end)` of the members `"key": value` of every JSON object
/// in `text`, each with the comma that follows it (if any).
pub fn members(text: &[u8]) -> Vec<(usize, usize)> {
    // stack of containers: true for an object
    let mut stack: Vec<bool> = Vec::new();
    let mut out = Vec::new();
    let mut open: Vec<Option<usize>> = Vec::new(); // start of the current member per level
    let (mut i, mut in_str) = (0, false);
    while i < text.len() {
        let c = text[i];
        if inside_string(text, &mut i, &mut in_str) {
            continue;
        }
        match c {
            b'"' => {
                if stack.last() == Some(&true) && open.last() == Some(&None) {
                    *open.last_mut().expect("a level") = Some(i);
                }
                in_str = true;
            }
            b'{' | b'[' => {
                stack.push(c == b'{');
                open.push(None);
            }
            b'}' | b']' => {
                if let (Some(true), Some(Some(s))) = (stack.last(), open.last()) {
                    out.push((*s, i));
                }
                stack.pop();
                open.pop();
            }
            b',' => {
                if let (Some(true), Some(Some(s))) = (stack.last(), open.last()) {
                    out.push((*s, i + 1));
                    *open.last_mut().expect("a level") = None;
                }
            }
            _ => {}
        }
        i += 1;
    }
    out
}

/// `text` with one to three random mutations.
pub fn mutate(rng: &mut Rng, text: &[u8]) -> Vec<u8> {
    let mut v = text.to_vec();
    for _ in 0..rng.random_range(1..=3) {
        v = mutate_once(rng, &v);
    }
    v
}

/// A position in `0..=n`.
fn at(rng: &mut Rng, n: usize) -> usize {
    rng.random_range(0..=n)
}

/// `text` with one random mutation.
pub fn mutate_once(rng: &mut Rng, text: &[u8]) -> Vec<u8> {
    let mut v = text.to_vec();
    let n = v.len();
    match rng.random_range(0..14) {
        // a flipped bit
        0 if n > 0 => {
            let i = rng.random_range(0..n);
            v[i] ^= 1 << rng.random_range(0..8);
        }
        // a byte replaced
        1 if n > 0 => {
            let i = rng.random_range(0..n);
            v[i] = rng.random_range(0..=255u8);
        }
        // truncated
        2 => v.truncate(at(rng, n)),
        // a span deleted
        3 if n > 0 => {
            let s = rng.random_range(0..n);
            let e = (s + rng.random_range(1..=16)).min(n);
            v.drain(s..e);
        }
        // a span repeated
        4 if n > 0 => {
            let s = rng.random_range(0..n);
            let e = (s + rng.random_range(1..=32)).min(n);
            let span = v[s..e].to_vec();
            v.splice(e..e, span);
        }
        // invalid UTF-8
        5 => {
            let i = at(rng, n);
            let bad = NOT_UTF8[rng.random_range(0..NOT_UTF8.len())];
            v.splice(i..i, bad.iter().copied());
        }
        // a very long run
        6 => {
            let i = at(rng, n);
            let c = [b'9', b' ', b'[', b'"', b'a', b'0'][rng.random_range(0..6)];
            let len = rng.random_range(1_000..=200_000);
            v.splice(i..i, std::iter::repeat_n(c, len));
        }
        // a number replaced by an odd value
        7..=9 => {
            let spans = numbers(&v);
            if !spans.is_empty() {
                let (s, e) = spans[rng.random_range(0..spans.len())];
                let odd = ODD_VALUES[rng.random_range(0..ODD_VALUES.len())];
                v.splice(s..e, odd.bytes());
            }
        }
        // a member removed
        10 => {
            let spans = members(&v);
            if !spans.is_empty() {
                let (s, e) = spans[rng.random_range(0..spans.len())];
                v.drain(s..e);
            }
        }
        // a member duplicated
        11 => {
            let spans = members(&v);
            if !spans.is_empty() {
                let (s, e) = spans[rng.random_range(0..spans.len())];
                let mut m = v[s..e].to_vec();
                if m.last() != Some(&b',') {
                    m.push(b',');
                }
                v.splice(s..s, m);
            }
        }
        // lines: removed, repeated, swapped, blank or split
        _ => {
            let mut lines: Vec<Vec<u8>> = v.split(|&b| b == b'\n').map(<[u8]>::to_vec).collect();
            let k = lines.len();
            let i = rng.random_range(0..k);
            match rng.random_range(0..5) {
                0 => {
                    lines.remove(i);
                }
                1 => lines.insert(i, lines[i].clone()),
                2 => lines.swap(i, rng.random_range(0..k)),
                3 => lines.insert(i, b"   ".to_vec()),
                _ => {
                    let cut = at(rng, lines[i].len());
                    let tail = lines[i].split_off(cut);
                    lines.insert(i + 1, tail);
                }
            }
            v = lines.join(&b'\n');
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_members_are_found_outside_strings() {
        let t = br#"{"a": 1.5, "b": "x-2", "c": [-3, 4e2], "d": {"e": 5}}"#;
        let n: Vec<&[u8]> = numbers(t).iter().map(|&(s, e)| &t[s..e]).collect();
        assert_eq!(n, [&b"1.5"[..], b"-3", b"4e2", b"5"]);
        let m: Vec<String> = members(t)
            .iter()
            .map(|&(s, e)| String::from_utf8_lossy(&t[s..e]).into_owned())
            .collect();
        assert!(m.contains(&r#""a": 1.5,"#.to_string()), "{m:?}");
        assert!(m.contains(&r#""e": 5"#.to_string()), "{m:?}");
        assert!(m.contains(&r#""d": {"e": 5}"#.to_string()), "{m:?}");
    }
}
