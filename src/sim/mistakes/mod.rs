//! The usual mistakes, made on purpose: the handout's precomputation, step
//! and loop over steps ([`textbook`](super::textbook)) with one line
//! written wrong, so that a student can see what each mistake does to a
//! cloth, and `masssprings trace --compare` can name the mistake a
//! student's numbers come from.
//!
//! | file | what |
//! |---|---|
//! | [`entry`] | what the gallery says of a mistake: its line, scene, symptom, figure |
//! | [`gallery`] | every mistake, one entry each: the enum [`Mistake`] |
//! | [`precomputation`] | the precomputation's lines (`M`, `A`, `C`, `Q`), each with its mistakes |
//! | [`step`] | the step's lines (`y`, `r`, `d`, `b`), each with its mistakes |
//! | [`simulation`] | the loop over steps (`U_prev ← U_cur`, `U_cur ← U_next`) |
//! | [`figures`] | what a mistaken run looks like beside the handout's, in numbers |
//!
//! Each line is one function that takes the mistake (`None`: the handout's
//! line), so that one definition of each mistake serves the gallery's
//! pictures (`render --mistake`), the student's files (`trace --mistake`)
//! and the diagnosis of `trace --compare`, which recomputes a student's
//! quantity from their own inputs under every mistake.
//!
//! `docs/mistakes.md` pictures every mistake beside the handout's step;
//! several follow slips of the handout's text, which `docs/equations.md`
//! lists. Nothing here is on the path the program runs or the fidelity
//! tests hold: [`precomputation::precomputation`] and
//! [`step::StudentStep`] are copies of the textbook functions, reached
//! only by `render --mistake`, `trace --mistake` and `trace --compare`.

pub mod entry;
pub mod figures;
pub mod gallery;
pub mod precomputation;
pub mod simulation;
pub mod step;

pub use entry::{Entry, Figure, Looks, Measure, Part};
pub use gallery::Mistake;
