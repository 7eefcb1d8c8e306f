//! What went wrong, not only where: after `--compare` has found the
//! quantities that differ, each is computed again from the student's own
//! inputs (their files, else ours), first by the handout's line, then by
//! each mistake of the gallery (`masssprings::sim::mistakes`):
//!
//! ```text
//! for q in the quantities that differ, in the handout's order:
//!     handout's q from your inputs = your q?  → q differs only because its inputs do: next q
//!     mistake X's q from your inputs = your q? → the diagnosis is X (its line, wrong and right)
//!     else                                     → no mistake of the gallery: the nearest hint (hint.rs)
//! ```
//!
//! The state (`U_prev`, `U_cur`) is the loop's ([`state`]): the student's
//! own steps from rest may have brought it elsewhere, which is no mistake
//! by itself, so the walk goes on to the step's quantities computed from
//! it. So a mistake of the step is named whether the student started from
//! our state or from their own.
//!
//! | file | what |
//! |---|---|
//! | [`inputs`] | the student's files, else ours, in the crate's types and the student's spring rows |
//! | [`recompute`] | one quantity by the handout's line or a mistake's; held to the student's |
//! | [`state`] | `U_prev`, `U_cur`: the loop's mistakes |
//! | [`hint`] | a sign, a factor, a swapped pair, the terms' coefficients, a transpose |
//! | [`fit`] | coefficients fitted to the student's numbers by least squares, and named |
//! | [`text`] | what the diagnosis says: the mistake and its line, or the hint |

mod fit;
mod hint;
pub mod inputs;
mod recompute;
mod state;
mod text;

use crate::app::trace::quantities::Quantity;
use inputs::Inputs;
use masssprings::sim::mistakes::{Mistake, Part};
use recompute::{difference, recompute, reproduces, theirs, Value};
pub use text::Diagnosis;
use text::Earlier;

/// One quantity of the comparison: given or not, and whether it differs.
#[derive(Debug, Clone, Copy)]
pub struct Finding {
    pub quantity: Quantity,
    pub given: bool,
    pub differs: bool,
}

/// The diagnosis of the comparison's `findings` (every quantity, in the
/// handout's order), or `None` when nothing differs.
pub fn diagnose(inputs: &Inputs, findings: &[Finding]) -> Option<Diagnosis> {
    let mut earlier = Earlier::default();
    for (at, finding) in findings.iter().enumerate().filter(|(_, f)| f.differs) {
        let quantity = &finding.quantity;
        let name = quantity.name();
        match quantity.spec.symbol {
            "U_prev" | "U_cur" => match state::diagnose(quantity, inputs) {
                Some(found) => return Some(earlier.before(found)),
                None => {
                    earlier.state.push(name);
                    continue;
                }
            },
            "P" => continue,
            "L" => {
                return Some(earlier.before(Diagnosis::unexplained(&name, &hint::triangle(inputs))))
            }
            _ => {}
        }
        let Some(handout) = recompute(quantity, None, inputs) else {
            let why = "it cannot be computed again here (its line above says why it differs)";
            return Some(earlier.before(Diagnosis::unexplained(&name, why)));
        };
        let Some(yours) = theirs(quantity, inputs) else {
            let hint = hint::shape(quantity, &handout, inputs);
            return Some(earlier.before(Diagnosis::unexplained(&name, &hint)));
        };
        if reproduces(quantity, &handout, &yours, inputs) {
            earlier.explained.push(name);
            continue;
        }
        let diagnosis = match suspect(quantity, &yours, &findings[..at], inputs) {
            Some(mistake) => Diagnosis::named(mistake, &name),
            None => Diagnosis::unexplained(&name, &hint::hint(quantity, &handout, &yours, inputs)),
        };
        return Some(earlier.before(diagnosis));
    }
    findings
        .iter()
        .any(|f| f.differs)
        .then(|| earlier.all_explained())
}

/// The mistake that makes the student's `yours` of `quantity` from their
/// inputs and agrees with every quantity they gave before it (`pins-without-w`
/// changes `Q` too, so a right `Q` rules it out where `b` alone would not);
/// of several, the closest.
fn suspect(
    quantity: &Quantity,
    yours: &Value,
    before: &[Finding],
    inputs: &Inputs,
) -> Option<Mistake> {
    let mut candidates: Vec<(f64, Mistake)> = Mistake::ALL
        .into_iter()
        .filter_map(|mistake| {
            let value = recompute(quantity, Some(mistake), inputs)?;
            let relative = difference(quantity, &value, yours, inputs)?;
            reproduces(quantity, &value, yours, inputs).then_some((relative, mistake))
        })
        .filter(|&(_, mistake)| consistent(mistake, before, inputs))
        .collect();
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    candidates.first().map(|&(_, mistake)| mistake)
}

/// Whether `mistake` reproduces every quantity the student gave before,
/// where it can be computed. A mistake of the step or the loop is held to
/// the step's quantities only: the `r` a step uses (`r-from-deformed`)
/// is not the precomputation's `r.mtx`.
fn consistent(mistake: Mistake, before: &[Finding], inputs: &Inputs) -> bool {
    let of_the_step = mistake.entry().part != Part::Precomputation;
    let checked = |f: &&Finding| f.given && !(of_the_step && in_the_precomputation(&f.quantity));
    before.iter().filter(checked).all(|f| {
        let value = recompute(&f.quantity, Some(mistake), inputs);
        let yours = theirs(&f.quantity, inputs);
        match (value, yours) {
            (Some(value), Some(yours)) => reproduces(&f.quantity, &value, &yours, inputs),
            _ => true,
        }
    })
}

/// `A`, `r`, `M`, `C`, `Q`, `P`, `L`.
fn in_the_precomputation(quantity: &Quantity) -> bool {
    ["A", "r", "M", "C", "Q", "P", "L"].contains(&quantity.spec.symbol)
}
