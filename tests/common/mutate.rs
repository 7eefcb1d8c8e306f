//! A seeded mutator for the hostile-input tests: it takes a valid file and
//! damages it the way a fuzzer does (flipped, inserted, deleted and
//! repeated bytes, lines swapped or cut, numbers replaced by extreme ones),
//! reproducibly from a seed, on the stable toolchain. Include it with
//! `#[path = ".../tests/common/mutate.rs"] mod mutate;`.
#![allow(dead_code)]

/// Tokens that tend to reach the corners of a parser.
const INTERESTING: &[&[u8]] = &[
    b"0",
    b"-1",
    b"1",
    b"2147483648",
    b"4294967296",
    b"18446744073709551615",
    b"99999999999999999999",
    b"100000000",
    b"1e308",
    b"-1e308",
    b"1e-320",
    b"nan",
    b"inf",
    b"\xef\xbb\xbf",
    b"\r",
    b"\n",
    b"\r\n",
    b"\r\n\r\n",
    b"\0",
    b"\xff",
    b" ",
    b"\t",
    b"%",
    b"%%MatrixMarket",
    b"#",
    b"/",
    b"//",
    b"{",
    b"}",
    b"[",
    b"]",
    b"\"",
    b":",
    b",",
    b"f ",
    b"v ",
    b"vt ",
    b"Content-Length: ",
    b"Host: ",
    b"\xe2\x82\xac",
];

/// A small fast generator (xorshift64*), deterministic from its seed.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    pub fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// A number in `0..bound` (`bound > 0`).
    pub fn below(&mut self, bound: usize) -> usize {
        (self.next() % bound as u64) as usize
    }
}

/// `input` with 1 to 4 random mutations.
pub fn mutate(input: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut bytes = input.to_vec();
    for _ in 0..1 + rng.below(4) {
        mutate_once(&mut bytes, rng);
    }
    bytes
}

fn mutate_once(bytes: &mut Vec<u8>, rng: &mut Rng) {
    let len = bytes.len();
    let at = |rng: &mut Rng| rng.below(len + 1);
    match rng.below(9) {
        0 if len > 0 => {
            let i = rng.below(len);
            bytes[i] ^= 1 << rng.below(8);
        }
        1 => {
            let i = at(rng);
            bytes.insert(i, rng.next() as u8);
        }
        2 if len > 0 => {
            let start = rng.below(len);
            let end = (start + 1 + rng.below(16)).min(len);
            bytes.drain(start..end);
        }
        3 => {
            let token = INTERESTING[rng.below(INTERESTING.len())];
            let i = at(rng);
            bytes.splice(i..i, token.iter().copied());
        }
        4 => replace_a_number(bytes, rng),
        5 if len > 0 => {
            // repeat a slice (up to 64 bytes) a few times
            let start = rng.below(len);
            let end = (start + 1 + rng.below(64)).min(len);
            let piece = bytes[start..end].to_vec();
            for _ in 0..1 + rng.below(3) {
                bytes.splice(end..end, piece.iter().copied());
            }
        }
        6 => {
            let keep = at(rng);
            bytes.truncate(keep);
        }
        7 => swap_lines(bytes, rng),
        _ => {
            let token = INTERESTING[rng.below(INTERESTING.len())];
            bytes.splice(0..0, token.iter().copied());
        }
    }
}

/// Replaces one run of digits by an extreme number.
fn replace_a_number(bytes: &mut Vec<u8>, rng: &mut Rng) {
    let digits: Vec<usize> = (0..bytes.len())
        .filter(|&i| bytes[i].is_ascii_digit())
        .collect();
    if digits.is_empty() {
        return;
    }
    let mut start = digits[rng.below(digits.len())];
    while start > 0 && bytes[start - 1].is_ascii_digit() {
        start -= 1;
    }
    let mut end = start;
    while end < bytes.len() && bytes[end].is_ascii_digit() {
        end += 1;
    }
    let numbers: [&[u8]; 7] = [
        b"0",
        b"2147483648",
        b"18446744073709551615",
        b"99999999999999999999999",
        b"100000000",
        b"65535",
        b"3",
    ];
    let number = numbers[rng.below(numbers.len())];
    bytes.splice(start..end, number.iter().copied());
}

/// Swaps two lines.
fn swap_lines(bytes: &mut Vec<u8>, rng: &mut Rng) {
    let mut lines: Vec<Vec<u8>> = bytes.split(|&b| b == b'\n').map(<[u8]>::to_vec).collect();
    if lines.len() < 2 {
        return;
    }
    let (a, b) = (rng.below(lines.len()), rng.below(lines.len()));
    lines.swap(a, b);
    *bytes = lines.join(&b'\n');
}
