//! "Did you mean …?": the known word nearest to a mistyped one.
//!
//! Nearness is the Levenshtein edit distance, the least number of
//! one-character insertions, deletions and substitutions that turn one word
//! into the other, computed by the classic dynamic programme over one row:
//!
//! ```text
//! d(i, j) = min( d(i−1, j) + 1,                 delete a[i]
//!                d(i, j−1) + 1,                 insert b[j]
//!                d(i−1, j−1) + [a[i] ≠ b[j]] )  substitute (or keep)
//! ```
//!
//! Cost `O(|a|·|b|)` time, `O(|b|)` memory. Source: V. I. Levenshtein 1966;
//! Wagner and Fischer 1974, "The string-to-string correction problem".

/// The Levenshtein distance between `a` and `b`, over characters.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    // row[j] = d(i, j) for the prefix of `a` read so far.
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0]; // d(i−1, j−1)
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let substitute = diagonal + usize::from(ca != cb);
            diagonal = row[j + 1];
            row[j + 1] = substitute.min(row[j + 1] + 1).min(row[j] + 1);
        }
    }
    row[b.len()]
}

/// The candidate nearest to `word`, when it is near enough to be a typo:
/// at most 2 edits, and fewer than half the word's length.
pub fn nearest<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let limit = 2.min(word.chars().count().saturating_sub(1) / 2 + 1);
    candidates
        .into_iter()
        .map(|candidate| (edit_distance(word, candidate), candidate))
        .filter(|&(distance, _)| distance <= limit)
        .min_by_key(|&(distance, _)| distance)
        .map(|(_, candidate)| candidate)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_of_the_textbook_examples() {
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("abc", ""), 3);
        assert_eq!(edit_distance("flaw", "lawn"), 2);
        assert_eq!(edit_distance("steps", "steps"), 0);
        assert_eq!(edit_distance("ß", "ss"), 2);
    }

    #[test]
    fn typos_find_their_word_and_nonsense_finds_none() {
        let words = ["simulate", "render", "view", "analyze", "generate"];
        assert_eq!(nearest("simulte", words), Some("simulate"));
        assert_eq!(nearest("analyse", words), Some("analyze"));
        assert_eq!(nearest("veiw", words), Some("view"));
        assert_eq!(nearest("frobnicate", words), None);
        assert_eq!(nearest("x", words), None);
        assert_eq!(nearest("step", ["steps", "every"]), Some("steps"));
    }
}
