//! The student's springs matched to ours, whatever their order and
//! orientation. The handout leaves both free: "the rows of A correspond to
//! an arbitrary (but fixed) ordering of the edges", and "for convenience,
//! we'll pick an orientation for each edge anyway". So row `e′` of the
//! student's `A`, with `+1` at `i` and `−1` at `j`, is the spring
//! `(i, j)`, and it matches our spring `e` that joins the same two
//! vertices, in either direction:
//!
//! ```text
//! A′ = S Π A      Π a permutation of the rows, S = diag(±1) the orientations
//! r′ = Π r        d′ = S Π d      (d changes sign with the orientation, r does not)
//! ```
//!
//! A spring set that is not a permutation of ours (a spring we do not
//! have, one of ours missing, one repeated, or a row that is no spring at
//! all) is a difference, named by the student's spring number and
//! vertices and ours beside it. Springs are matched by their vertex pair
//! in a hash map, `O(m)`; a pair listed twice in the scene (a two-corner
//! face repeated) matches twice.
//!
//! This file uses the library only, so that the fuzz target
//! `trace_compare` includes it as it is.

use masssprings::linalg::sparse::CscMatrix;
use masssprings::memory;
use std::collections::HashMap;

/// A row of a signed incidence matrix read as a spring.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Row {
    /// `+1` at vertex `i`, `−1` at vertex `j`: the spring `(i, j)`.
    Spring([usize; 2]),
    /// Not a spring, and why (`+1 at vertices 4 and 9`).
    NotASpring(String),
}

/// The rows of `a` as springs.
///
/// # Errors
/// The memory rule's refusal of a row list as long as `a`'s rows.
pub fn springs_of(a: &CscMatrix) -> Result<Vec<Row>, String> {
    let rows = a.nrows();
    memory::check(
        memory::bytes_for(rows as u64, 96), // three lists of ends and problems, then the rows
        || format!("the springs of an A of {rows} rows"),
        "",
    )
    .map_err(|e| e.to_string())?;
    let mut plus: Vec<Option<usize>> = vec![None; rows];
    let mut minus: Vec<Option<usize>> = vec![None; rows];
    let mut problem: Vec<Option<String>> = vec![None; rows];
    for vertex in 0..a.ncols() {
        let (springs, values) = a.column(vertex);
        for (&e, &v) in springs.iter().zip(values).filter(|(_, &v)| v != 0.0) {
            let end = if v == 1.0 {
                &mut plus[e]
            } else if v == -1.0 {
                &mut minus[e]
            } else {
                let why =
                    format!("it holds {v} at vertex {vertex} (a spring's entries are +1 and −1)");
                problem[e].get_or_insert(why);
                continue;
            };
            if let Some(first) = end.replace(vertex) {
                let sign = if v > 0.0 { "+1" } else { "−1" };
                let why = format!(
                    "{sign} at vertices {first} and {vertex} (a spring has one +1 and one −1)"
                );
                problem[e].get_or_insert(why);
            }
        }
    }
    Ok((0..rows)
        .map(|e| match (problem[e].take(), plus[e], minus[e]) {
            (Some(why), _, _) => Row::NotASpring(why),
            (None, Some(i), Some(j)) => Row::Spring([i, j]),
            (None, None, None) => Row::NotASpring("it is empty".into()),
            (None, Some(i), None) => {
                Row::NotASpring(format!("it has a +1 at vertex {i} and no −1"))
            }
            (None, None, Some(j)) => {
                Row::NotASpring(format!("it has a −1 at vertex {j} and no +1"))
            }
        })
        .collect())
}

/// The two ends of a spring, in increasing order (its key, whatever its
/// orientation).
fn key([i, j]: [usize; 2]) -> [usize; 2] {
    [i.min(j), i.max(j)]
}

/// Which of our springs each of the student's is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Matching {
    /// Their spring `e′` → our spring `e`, and whether it runs the other
    /// way (`(j, i)` for our `(i, j)`).
    pub ours_of: Vec<Option<(usize, bool)>>,
    /// Our spring `e` → theirs.
    pub theirs_of: Vec<Option<usize>>,
}

impl Matching {
    /// Every spring matched one to one.
    pub fn is_permutation(&self) -> bool {
        self.ours_of.iter().all(Option::is_some) && self.theirs_of.iter().all(Option::is_some)
    }

    /// The same springs in the same rows and directions.
    pub fn is_identity(&self) -> bool {
        self.ours_of.len() == self.theirs_of.len()
            && self
                .ours_of
                .iter()
                .enumerate()
                .all(|(e, m)| *m == Some((e, false)))
    }

    /// How many springs are in other rows than ours, and how many reversed.
    pub fn moved_and_reversed(&self) -> (usize, usize) {
        let matched = self
            .ours_of
            .iter()
            .enumerate()
            .filter_map(|(e, m)| Some((e, (*m)?)));
        matched.fold((0, 0), |(moved, reversed), (e, (ours, flip))| {
            (moved + usize::from(e != ours), reversed + usize::from(flip))
        })
    }
}

/// Matches `theirs` to `ours` by vertex pair; a spring of theirs whose
/// own row number is a candidate keeps it, so the same order matches as
/// the identity even with repeated springs.
///
/// # Errors
/// The memory rule's refusal of the matching's two lists.
pub fn match_springs(ours: &[Row], theirs: &[Row]) -> Result<Matching, String> {
    let entries = (ours.len() as u64).saturating_add(theirs.len() as u64);
    memory::check(
        memory::bytes_for(entries, 3 * 8),
        || format!("matching {} springs to our {}", theirs.len(), ours.len()),
        "",
    )
    .map_err(|e| e.to_string())?;
    let mut by_ends: HashMap<[usize; 2], Vec<usize>> = HashMap::with_capacity(ours.len());
    for (e, row) in ours.iter().enumerate() {
        if let Row::Spring(ends) = row {
            by_ends.entry(key(*ends)).or_default().push(e);
        }
    }
    let mut matching = Matching {
        ours_of: vec![None; theirs.len()],
        theirs_of: vec![None; ours.len()],
    };
    for (e_theirs, row) in theirs.iter().enumerate() {
        let Row::Spring(ends) = row else { continue };
        let Some(candidates) = by_ends.get(&key(*ends)) else {
            continue;
        };
        let free = |e: &&usize| matching.theirs_of[**e].is_none();
        let same_row = candidates.iter().filter(free).find(|&&e| e == e_theirs);
        let Some(&e) = same_row.or_else(|| candidates.iter().find(free)) else {
            continue; // every spring of ours with these ends is taken: a repeat
        };
        let reversed = matches!(ours[e], Row::Spring(our_ends) if our_ends != *ends);
        matching.ours_of[e_theirs] = Some((e, reversed));
        matching.theirs_of[e] = Some(e_theirs);
    }
    Ok(matching)
}

/// `spring 17 = (4, 9)`, or `spring 17` for a row that is no spring.
pub fn spring_name(e: usize, row: Option<&Row>) -> String {
    match row {
        Some(Row::Spring([i, j])) => format!("spring {e} = ({i}, {j})"),
        _ => format!("spring {e}"),
    }
}

/// What is wrong with a spring set that is not a permutation of ours: the
/// first wrong spring of theirs in their order (or else the first of ours
/// they lack), and how many of each there are.
pub fn mismatch(ours: &[Row], theirs: &[Row], matching: &Matching) -> Option<String> {
    let extra = matching.ours_of.iter().filter(|m| m.is_none()).count();
    let missing = matching.theirs_of.iter().filter(|m| m.is_none()).count();
    if extra == 0 && missing == 0 {
        return None;
    }
    let lacking = matching.theirs_of.iter().position(Option::is_none);
    let lacking =
        lacking.map(|e| format!("our {} is in no row of yours", spring_name(e, ours.get(e))));
    let first = match matching.ours_of.iter().position(Option::is_none) {
        Some(e) => {
            let first = not_ours(ours, theirs, matching, e);
            lacking.map_or(first.clone(), |lacking| format!("{first}; {lacking}"))
        }
        None => lacking?,
    };
    Some(format!(
        "{first} (in all, {extra} of your {} springs are not ours and {missing} of our {} not yours)",
        theirs.len(),
        ours.len()
    ))
}

/// Why their spring `e` matched none of ours: no spring, a pair we do not
/// have, or a repeat.
fn not_ours(ours: &[Row], theirs: &[Row], matching: &Matching, e: usize) -> String {
    let yours = format!(
        "your {} (file row {})",
        spring_name(e, theirs.get(e)),
        e + 1
    );
    let ends = match &theirs[e] {
        Row::NotASpring(why) => {
            return format!("your row {} (spring {e}) is not a spring: {why}", e + 1)
        }
        Row::Spring(ends) => key(*ends),
    };
    let same = |row: &Row| matches!(row, Row::Spring(other) if key(*other) == ends);
    let Some(ours_e) = ours.iter().position(same) else {
        let [i, j] = ends;
        return format!("{yours} is not a spring of ours: none joins vertices {i} and {j}");
    };
    let earlier = matching.theirs_of[ours_e].map_or(String::new(), |t| {
        format!(" {} (file row {}),", spring_name(t, theirs.get(t)), t + 1)
    });
    format!(
        "{yours} repeats your{earlier} our {}",
        spring_name(ours_e, ours.get(ours_e))
    )
}
