//! The gallery: every mistake, one entry each, in the order of the lines
//! of the handout they change (the precomputation's `A`, `M`, `C`, `Q`,
//! the step's `y`, `d`, `b`, then the loop over steps). An entry is all
//! the gallery says of its mistake ([`Entry`]); its code is one arm of the
//! `match` in the function that computes its line
//! ([`precomputation`](super::precomputation), [`step`](super::step),
//! [`simulation`](super::simulation)).
//!
//! `docs/mistakes.md` is written from these entries and `tests/sim/mistakes.rs`
//! holds it to them: its table, its index by symptom, each picture's
//! scene, the figure each section quotes (measured on the picture's run),
//! what `trace --compare` names first and the mistake it diagnoses.

use super::entry::{Entry, Figure, Looks, Measure, Part};

/// The macro that makes the enum [`Mistake`], its list
/// [`Mistake::ALL`] and [`Mistake::entry`] from one list of
/// `Variant => Entry`, so that a mistake is written in one place.
macro_rules! gallery {
    ($($(#[$doc:meta])* $variant:ident => $entry:expr,)*) => {
        /// One mistake of the gallery: a line of the handout written wrong.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Mistake {
            $($(#[$doc])* $variant,)*
        }

        /// The entries, in the order of [`Mistake`]'s variants.
        static ENTRIES: [Entry; Mistake::COUNT] = [$($entry,)*];

        impl Mistake {
            /// How many mistakes the gallery holds.
            pub const COUNT: usize = [$(stringify!($variant),)*].len();

            /// Every mistake, in the gallery's order.
            pub const ALL: [Mistake; Mistake::COUNT] = [$(Mistake::$variant,)*];

            /// What the gallery says of it.
            pub fn entry(self) -> &'static Entry {
                &ENTRIES[self as usize]
            }
        }
    };
}

/// A figure the gallery quotes.
const fn figure(measure: Measure, quoted: &'static str, low: f64, high: f64) -> Figure {
    Figure {
        measure,
        quoted,
        range: [low, high],
    }
}

/// Shows from step 1.
const ALWAYS: (usize, &str) = (1, "");
/// Changes no number on any bundled scene.
const VISIBLE: (&[&str], &str) = (&[], "");
/// The scenes whose masses are all 1.
const UNIT_MASSES: &[&str] = &["single-spring-horizontal", "horizontal-chain", "net"];

gallery! {
    /// `A(e, j) = +1`: the signed incidence matrix without its minus signs.
    ASign => Entry {
        name: "a-sign",
        wrong: "A(e, j) = +1",
        right: "A(e, j) = −1",
        part: Part::Precomputation,
        scene: "flag",
        symptom: "folds into its pole in one step",
        looks: Looks::Shrinks,
        first: "A",
        shows_from: ALWAYS,
        figure: figure(Measure::Extent, "1.4 m across", 1.3, 1.45),
        invisible_on: VISIBLE,
    },
    /// `A` built `n × m` and the products transposed to fit it.
    ATransposed => Entry {
        name: "a-transposed",
        wrong: "A n × m (a row per vertex), Q = k A Aᵀ + …, b = k A d + …",
        right: "A m × n (a row per spring), Q = k AᵀA + …, b = k Aᵀd + …",
        part: Part::Precomputation,
        scene: "flag",
        symptom: "nothing: the products fit the transpose",
        looks: Looks::LooksRight,
        first: "A",
        shows_from: ALWAYS,
        figure: figure(Measure::Apart, "to the last bit", 0.0, 0.0),
        invisible_on: (
            &["single-spring-horizontal", "horizontal-chain", "net", "flag", "skirt"],
            "A Aᵀ of the n × m A is the handout's AᵀA, and A d its Aᵀd",
        ),
    },
    /// `M = 2 diag(m)`.
    MassDoubled => Entry {
        name: "mass-doubled",
        wrong: "M = 2 diag(m)",
        right: "M = diag(m)",
        part: Part::Precomputation,
        scene: "horizontal-chain",
        symptom: "bounces √2 times slower",
        looks: Looks::SlowMotion,
        first: "M",
        shows_from: ALWAYS,
        figure: figure(Measure::BottomRatio, "√2 times slower", 1.3, 1.5),
        invisible_on: VISIBLE,
    },
    /// Every mass 1, whatever the scene says.
    UniformMasses => Entry {
        name: "uniform-masses",
        wrong: "mᵢ = 1",
        right: "mᵢ from the scene (its m, or the Voronoi areas)",
        part: Part::Precomputation,
        scene: "flag",
        symptom: "falls in slow motion, then swings",
        looks: Looks::SlowMotion,
        first: "M",
        shows_from: ALWAYS,
        figure: figure(Measure::BottomRatio, "eight times later", 6.0, 10.0),
        invisible_on: (UNIT_MASSES, "their masses are all 1"),
    },
    /// `mᵢ` half the summed length of the springs at `i`.
    MassesFromLengths => Entry {
        name: "masses-from-lengths",
        wrong: "mᵢ = ½ Σ rₑ over the springs at i",
        right: "mᵢ the Voronoi area of i",
        part: Part::Precomputation,
        scene: "flag",
        symptom: "falls three times slower, then swings",
        looks: Looks::SlowMotion,
        first: "M",
        shows_from: ALWAYS,
        figure: figure(Measure::BottomRatio, "three times later", 2.5, 3.5),
        invisible_on: VISIBLE,
    },
    /// The pins taken from the scene's 1-based list as they are.
    PinsOneBased => Entry {
        name: "pins-one-based",
        wrong: "C from the file's pins, counted from 1",
        right: "C from the file's pins minus 1",
        part: Part::Precomputation,
        scene: "single-spring-horizontal",
        symptom: "hangs from the wrong end",
        looks: Looks::PinsMove,
        first: "C",
        shows_from: ALWAYS,
        figure: figure(Measure::PinsMoved, "1.95 m", 1.9, 2.0),
        invisible_on: VISIBLE,
    },
    /// `Q` without `w CᵀC`.
    PinsNotInQ => Entry {
        name: "pins-not-in-q",
        wrong: "Q = k AᵀA + M/Δt²",
        right: "Q = k AᵀA + M/Δt² + w CᵀC",
        part: Part::Precomputation,
        scene: "flag",
        symptom: "thrown 10⁸ m away in one step",
        looks: Looks::FliesOff,
        first: "Q",
        shows_from: ALWAYS,
        figure: figure(Measure::Farthest, "2 × 10¹¹ m", 1e11, 1e12),
        invisible_on: VISIBLE,
    },
    /// The pins' penalty without its weight: `CᵀC` in `Q`, `CᵀC V` in `b`.
    PinsWithoutW => Entry {
        name: "pins-without-w",
        wrong: "Q = k AᵀA + M/Δt² + CᵀC, b = k Aᵀd + y + CᵀC V",
        right: "w CᵀC in Q, w CᵀC V in b, w = 10¹⁰",
        part: Part::Precomputation,
        scene: "flag",
        symptom: "falls off its pole, 1.4 km in 2 s",
        looks: Looks::PinsMove,
        first: "Q",
        shows_from: ALWAYS,
        figure: figure(Measure::PinsMoved, "1.4 km", 1e3, 2e3),
        invisible_on: VISIBLE,
    },
    /// `M/Δt` for `M/Δt²`, in `Q` and in `y`.
    DtNotSquared => Entry {
        name: "dt-not-squared",
        wrong: "M/Δt in Q and y",
        right: "M/Δt² in Q and y",
        part: Part::Precomputation,
        scene: "horizontal-chain",
        symptom: "drops into place, no bounce",
        looks: Looks::NoBounce,
        first: "Q",
        shows_from: ALWAYS,
        figure: figure(Measure::Swing, "less than a micrometre", 0.0, 1e-6),
        invisible_on: VISIBLE,
    },
    /// `k` multiplying the inertia term of `Q` too.
    KOnInertia => Entry {
        name: "k-on-inertia",
        wrong: "Q = k (AᵀA + M/Δt²) + w CᵀC",
        right: "Q = k AᵀA + M/Δt² + w CᵀC",
        part: Part::Precomputation,
        scene: "horizontal-chain",
        symptom: "pulled onto its left pin, at the origin",
        looks: Looks::Shrinks,
        first: "Q",
        shows_from: ALWAYS,
        figure: figure(Measure::Lowest, "0.2 mm", -1e-3, 0.0),
        invisible_on: VISIBLE,
    },
    /// The inertial term with a minus sign, in `Q` and `y`.
    InertiaSign => Entry {
        name: "inertia-sign",
        wrong: "Q = k AᵀA − M/Δt² + w CᵀC, y = −M (2 U_cur − U_prev)/Δt² + f_ext",
        right: "+ M/Δt² in Q, + M (2 U_cur − U_prev)/Δt² in y",
        part: Part::Precomputation,
        scene: "flag",
        symptom: "looks right; the chain cannot start",
        looks: Looks::LooksRight,
        first: "Q",
        shows_from: ALWAYS,
        figure: figure(Measure::Apart, "4 mm", 0.0, 0.01),
        invisible_on: VISIBLE,
    },
    /// The inertial term without its `½`: `2M` in `Q` and `y`.
    InertiaHalfMissing => Entry {
        name: "inertia-half-missing",
        wrong: "Q = k AᵀA + 2M/Δt² + w CᵀC, y = 2M (2 U_cur − U_prev)/Δt² + f_ext",
        right: "M, not 2M, in Q and y",
        part: Part::Precomputation,
        scene: "horizontal-chain",
        symptom: "as `mass-doubled`",
        looks: Looks::SlowMotion,
        first: "Q",
        shows_from: ALWAYS,
        figure: figure(Measure::BottomRatio, "√2 times slower", 1.3, 1.5),
        invisible_on: VISIBLE,
    },
    /// Gravity pointing up.
    GravitySign => Entry {
        name: "gravity-sign",
        wrong: "f_ext = (0, +9.8, 0)",
        right: "f_ext = (0, −9.8, 0)",
        part: Part::Step,
        scene: "horizontal-chain",
        symptom: "arches up, a catenary upside down",
        looks: Looks::Rises,
        first: "y",
        shows_from: ALWAYS,
        figure: figure(Measure::Highest, "0.54 m above its pins", 0.5, 0.6),
        invisible_on: VISIBLE,
    },
    /// Gravity multiplied by each vertex's mass.
    GravityTimesMass => Entry {
        name: "gravity-times-mass",
        wrong: "f_ext = mᵢ (0, −9.8, 0)",
        right: "f_ext = (0, −9.8, 0)",
        part: Part::Step,
        scene: "flag",
        symptom: "stays up, sagging 3 cm in 2 s",
        looks: Looks::StaysUp,
        first: "y",
        shows_from: ALWAYS,
        figure: figure(Measure::Lowest, "3 cm", -0.04, -0.02),
        invisible_on: (UNIT_MASSES, "their masses are all 1"),
    },
    /// `y` without its division by `Δt²` (`Q` right).
    DtSquaredMissingInY => Entry {
        name: "dt-squared-missing-in-y",
        wrong: "y = M (2 U_cur − U_prev) + f_ext",
        right: "y = M (2 U_cur − U_prev)/Δt² + f_ext",
        part: Part::Step,
        scene: "horizontal-chain",
        symptom: "pulled toward the origin, sagging 5 cm",
        looks: Looks::Shrinks,
        first: "y",
        shows_from: ALWAYS,
        figure: figure(Measure::Lowest, "5 cm", -0.06, -0.04),
        invisible_on: VISIBLE,
    },
    /// `U_prev` and `U_cur` swapped in `y`.
    PrevCurSwapped => Entry {
        name: "prev-cur-swapped",
        wrong: "y = M (2 U_prev − U_cur)/Δt² + f_ext",
        right: "y = M (2 U_cur − U_prev)/Δt² + f_ext",
        part: Part::Step,
        scene: "single-spring-horizontal",
        symptom: "jumps up and down, wider each step",
        looks: Looks::FliesOff,
        first: "y",
        shows_from: (2, "U_prev = U_cur = V"),
        figure: figure(Measure::Farthest, "10¹⁴ m", 1e14, 1e15),
        invisible_on: VISIBLE,
    },
    /// `y = M (2 U_cur + U_prev)/Δt² + f_ext`.
    InertiaMinusPrev => Entry {
        name: "inertia-minus-prev",
        wrong: "y = M (2 U_cur + U_prev)/Δt² + f_ext",
        right: "y = M (2 U_cur − U_prev)/Δt² + f_ext",
        part: Part::Step,
        scene: "single-spring-horizontal",
        symptom: "flies off in the first steps",
        looks: Looks::FliesOff,
        first: "y",
        shows_from: ALWAYS,
        figure: figure(Measure::Farthest, "10²⁰ m", 1e19, 1e21),
        invisible_on: VISIBLE,
    },
    /// The rest lengths measured on `U_cur` at every step.
    RFromDeformed => Entry {
        name: "r-from-deformed",
        wrong: "r = ‖U_cur,i − U_cur,j‖ every step",
        right: "r = ‖V_i − V_j‖ once",
        part: Part::Step,
        scene: "flag",
        symptom: "stretches down without end",
        looks: Looks::Stretches,
        first: "d_1",
        shows_from: (2, "U_cur = V"),
        figure: figure(Measure::Lowest, "8.5 m below its pole", -9.0, -8.0),
        invisible_on: VISIBLE,
    },
    /// `d = r (pᵢ − pⱼ)`, not divided by `‖pᵢ − pⱼ‖`.
    DNotNormalised => Entry {
        name: "d-not-normalised",
        wrong: "d = r (p_i − p_j)",
        right: "d = r (p_i − p_j)/‖p_i − p_j‖",
        part: Part::Step,
        scene: "flag",
        symptom: "shrinks into its pole",
        looks: Looks::Shrinks,
        first: "d_1",
        shows_from: ALWAYS,
        figure: figure(Measure::Extent, "1 m across", 0.99, 1.05),
        invisible_on: VISIBLE,
    },
    /// `d` from `pⱼ − pᵢ` while `A`'s row is `+1` at `i`.
    DAgainstA => Entry {
        name: "d-against-a",
        wrong: "d = r (p_j − p_i)/‖p_j − p_i‖",
        right: "d = r (p_i − p_j)/‖p_i − p_j‖, as A's row: +1 at i, −1 at j",
        part: Part::Step,
        scene: "flag",
        symptom: "crumples up against its pole",
        looks: Looks::Tangles,
        first: "d_1",
        shows_from: ALWAYS,
        figure: figure(Measure::Extent, "1.3 m across", 1.25, 1.45),
        invisible_on: VISIBLE,
    },
    /// The local step run on `U_cur` in every iteration.
    DFromUCur => Entry {
        name: "d-from-u-cur",
        wrong: "d from U_cur in every iteration",
        right: "d from the last iteration's p",
        part: Part::Step,
        scene: "single-spring-horizontal",
        symptom: "creeps down, never swings",
        looks: Looks::SlowMotion,
        first: "d_2",
        shows_from: ALWAYS,
        figure: figure(Measure::Lowest, "0.96 m below its pin", -1.0, -0.9),
        invisible_on: VISIBLE,
    },
    /// `b` without `w CᵀC V`.
    PinsNotInB => Entry {
        name: "pins-not-in-b",
        wrong: "b = k Aᵀd + y",
        right: "b = k Aᵀd + y + w CᵀC V",
        part: Part::Step,
        scene: "flag",
        symptom: "the pole shrinks to a point at the origin",
        looks: Looks::PinsMove,
        first: "b_1",
        shows_from: ALWAYS,
        figure: figure(Measure::PinsMoved, "1 m", 0.99, 1.01),
        invisible_on: VISIBLE,
    },
    /// `w` multiplying `y` instead of `CᵀC V`.
    WOnY => Entry {
        name: "w-on-y",
        wrong: "b = k Aᵀd + w y + CᵀC V",
        right: "b = k Aᵀd + y + w CᵀC V",
        part: Part::Step,
        scene: "flag",
        symptom: "thrown off, farther every step, until the numbers overflow",
        looks: Looks::FliesOff,
        first: "b_1",
        shows_from: ALWAYS,
        figure: figure(Measure::Stopped, "step 38", 30.0, 45.0),
        invisible_on: VISIBLE,
    },
    /// `U_prev` updated after `U_cur`, so that `U_prev = U_cur`.
    VelocityLost => Entry {
        name: "velocity-lost",
        wrong: "U_cur = U_next; U_prev = U_cur",
        right: "U_prev = U_cur; U_cur = U_next",
        part: Part::Loop,
        scene: "single-spring-horizontal",
        symptom: "sinks as through honey, never swings",
        looks: Looks::SlowMotion,
        first: "U_prev",
        shows_from: (2, "your U_prev and ours are both V"),
        figure: figure(Measure::Lowest, "0.76 m below its pin", -0.8, -0.7),
        invisible_on: VISIBLE,
    },
}

impl Mistake {
    /// The name on the command line (`--mistake mass-doubled`).
    pub fn name(self) -> &'static str {
        self.entry().name
    }

    /// The mistake called `name`, if any.
    pub fn from_name(name: &str) -> Option<Mistake> {
        Mistake::ALL.into_iter().find(|m| m.name() == name)
    }

    /// The line the student wrote.
    pub fn wrong(self) -> &'static str {
        self.entry().wrong
    }

    /// The handout's line.
    pub fn right(self) -> &'static str {
        self.entry().right
    }
}

impl std::str::FromStr for Mistake {
    type Err = String;

    fn from_str(name: &str) -> Result<Mistake, String> {
        Mistake::from_name(name).ok_or_else(|| {
            let names: Vec<&str> = Mistake::ALL.iter().map(|m| m.name()).collect();
            format!(
                "no mistake is called '{name}'; the mistakes are {}",
                names.join(", ")
            )
        })
    }
}

impl std::fmt::Display for Mistake {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
