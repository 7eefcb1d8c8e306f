//! What the gallery says of one mistake: the shape of an entry of
//! [`gallery`](super::gallery), and the words it is made of (where the
//! line is, what the picture shows, the figure the gallery quotes).
//!
//! An entry is data only: the code of the mistake is its line in
//! [`precomputation`](super::precomputation), [`step`](super::step) or
//! [`simulation`](super::simulation), and `tests/sim/mistakes.rs` holds the
//! page `docs/mistakes.md`, the picture and every figure to the entry.

/// One mistake of the gallery, as `docs/mistakes.md` shows it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Entry {
    /// The name on the command line (`--mistake mass-doubled`) and the
    /// gallery's heading.
    pub name: &'static str,
    /// The line as the student wrote it.
    pub wrong: &'static str,
    /// The handout's line.
    pub right: &'static str,
    /// Where the line is.
    pub part: Part,
    /// The bundled scene that shows it best (`data/SCENE.json`): the
    /// gallery's picture, from rest, without wind.
    pub scene: &'static str,
    /// What the picture shows, in a few words (the gallery's table).
    pub symptom: &'static str,
    /// Which row of the gallery's index by symptom lists it.
    pub looks: Looks,
    /// The quantity `trace --compare` names first for it at step 3 with
    /// 2 iterations (the state from ours for a mistake of the step, from
    /// the student's own steps for a mistake of the loop).
    pub first: &'static str,
    /// The first step whose trace shows it (1, 2 or 3), and why the
    /// steps before it cannot (empty for step 1).
    pub shows_from: (usize, &'static str),
    /// The figure of the picture's run that the gallery quotes.
    pub figure: Figure,
    /// The bundled scenes on which it changes no number at all, and why.
    pub invisible_on: (&'static [&'static str], &'static str),
}

/// Where a line of the student's code is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    /// `fast_mass_springs_precomputation_sparse`: `A`, `r`, `M`, `C`, `Q`.
    Precomputation,
    /// `fast_mass_springs_step_sparse`: `y`, then `d`, `b`, `p`.
    Step,
    /// The loop over steps that calls it (`main.cpp`'s, or the student's
    /// own): `U_prev ← U_cur`, `U_cur ← U_next`.
    Loop,
}

/// What a student sees: the rows of the gallery's index by symptom.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Looks {
    /// Thrown far away, or farther every step.
    FliesOff,
    /// Folds, shrinks or is pulled into a point or its pins.
    Shrinks,
    /// The pins let go, move or hold the wrong vertex.
    PinsMove,
    /// Stretches without end.
    Stretches,
    /// Stays up, or moves far too little.
    StaysUp,
    /// Rises where it should fall.
    Rises,
    /// Moves as in slow motion, or creeps and never swings.
    SlowMotion,
    /// Drops into place without a bounce.
    NoBounce,
    /// Crumples into a tangle.
    Tangles,
    /// Nothing to see: the cloth looks right; only `--compare` tells.
    LooksRight,
}

impl Looks {
    /// Every row, in the index's order.
    pub const ALL: [Looks; 10] = [
        Looks::FliesOff,
        Looks::Shrinks,
        Looks::PinsMove,
        Looks::Stretches,
        Looks::StaysUp,
        Looks::Rises,
        Looks::SlowMotion,
        Looks::NoBounce,
        Looks::Tangles,
        Looks::LooksRight,
    ];

    /// The row's first cell in `docs/mistakes.md`.
    pub fn words(self) -> &'static str {
        match self {
            Looks::FliesOff => "it explodes or flies off",
            Looks::Shrinks => "it folds, shrinks or is pulled into a point",
            Looks::PinsMove => "the pins move or let go",
            Looks::Stretches => "it stretches without end",
            Looks::StaysUp => "it stays up, or hardly moves",
            Looks::Rises => "it rises instead of falling",
            Looks::SlowMotion => "it moves in slow motion, or creeps and never swings",
            Looks::NoBounce => "it drops into place with no bounce",
            Looks::Tangles => "it crumples into a tangle",
            Looks::LooksRight => "it looks right, but `--compare` disagrees",
        }
    }
}

/// A figure of the gallery's run of a mistake (its scene, from rest, the
/// steps of its picture), as `render --mistake NAME --json` prints it:
/// the gallery quotes `quoted`, and the run's `measure` lies in `range`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Figure {
    pub measure: Measure,
    /// The words the gallery's section uses for it.
    pub quoted: &'static str,
    /// The interval the measured value lies in.
    pub range: [f64; 2],
}

/// What is measured of a run (see [`figures`](super::figures)).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Measure {
    /// The height of the lowest vertex at the last step (m).
    Lowest,
    /// The height of the highest vertex at the last step (m).
    Highest,
    /// The largest distance of a vertex from its rest position (m).
    Farthest,
    /// The largest distance of a pinned vertex from its rest position (m).
    PinsMoved,
    /// The diagonal of the bounding box at the last step (m).
    Extent,
    /// The largest distance between a vertex of the mistaken run and the
    /// same vertex of the handout's, at the last step (m).
    Apart,
    /// How far the lowest point rises and falls over the second half of
    /// the run (m).
    Swing,
    /// The step at which the lowest point first stops falling, over the
    /// handout's.
    BottomRatio,
    /// The first step with a position that is not finite (the run's
    /// steps + 1 when there is none).
    Stopped,
}

impl Measure {
    /// Its name in `render --mistake NAME --json`.
    pub fn name(self) -> &'static str {
        match self {
            Measure::Lowest => "lowest",
            Measure::Highest => "highest",
            Measure::Farthest => "farthest",
            Measure::PinsMoved => "pins_moved",
            Measure::Extent => "extent",
            Measure::Apart => "apart",
            Measure::Swing => "swing",
            Measure::BottomRatio => "bottom_ratio",
            Measure::Stopped => "stopped",
        }
    }
}
