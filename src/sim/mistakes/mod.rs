//! The usual mistakes, made on purpose: the handout's precomputation and
//! step ([`textbook`](super::textbook)) with one line written wrong, so
//! that a student can see what each mistake does to a cloth and what
//! `masssprings trace --compare` names first for it.
//!
//! Each [`Mistake`] is one line of the student's code:
//!
//! | name | the student wrote | the handout's line |
//! |---|---|---|
//! | `mass-doubled` | `M = 2 diag(m)` | `M = diag(m)` |
//! | `a-sign` | `A_e,j = +1` | `A_e,j = −1` |
//! | `pins-not-in-q` | `Q = k AᵀA + M/Δt²` | `Q = k AᵀA + M/Δt² + w CᵀC` |
//! | `pins-not-in-b` | `b = k Aᵀd + y` | `b = k Aᵀd + y + w CᵀC V` |
//! | `r-from-deformed` | `rᵢⱼ = ‖U_curᵢ − U_curⱼ‖`, every step | `rᵢⱼ = ‖Vᵢ − Vⱼ‖`, once |
//! | `dt-not-squared` | `M/Δt` in `Q` and `y` | `M/Δt²` |
//! | `prev-cur-swapped` | `y = M (2 U_prev − U_cur)/Δt² + f_ext` | `y = M (2 U_cur − U_prev)/Δt² + f_ext` |
//! | `d-not-normalised` | `dᵢⱼ = rᵢⱼ (pᵢ − pⱼ)` | `dᵢⱼ = rᵢⱼ (pᵢ − pⱼ)/‖pᵢ − pⱼ‖` |
//! | `pins-one-based` | `C` from the file's 1-based `b` | `C` from `b − 1` |
//! | `gravity-times-mass` | `f_ext = mᵢ (0, −9.8, 0)` | `f_ext = (0, −9.8, 0)` |
//! | `d-from-u-cur` | `dᵢⱼ` from `U_cur` in every iteration | from the last iteration's `p` |
//! | `inertia-minus-prev` | `y = M (2 U_cur + U_prev)/Δt² + f_ext` | `− U_prev` |
//! | `inertia-sign` | `− M/Δt²` in `Q`, `− M (2 U_cur − U_prev)/Δt²` in `y` | `+` |
//! | `inertia-half-missing` | `2M/Δt²` in `Q`, `2M (2 U_cur − U_prev)/Δt²` in `y` | `M` |
//!
//! The last three follow slips of the handout's text (its inertial term
//! written with `− pᵗ⁻ᐞᵗ`, its energy with `−` and without the `½`):
//! `docs/equations.md` lists the slips, `docs/mistakes.md` pictures every
//! mistake beside the handout's step.
//!
//! Nothing here is on the path the program runs or the fidelity tests
//! hold: [`precomputation::precomputation`] and [`step::StudentStep`] are
//! copies of the textbook functions with the one line changed, reached
//! only by `render --mistake` and `trace --mistake`.

pub mod precomputation;
pub mod step;

/// One mistake: a line of the handout's functions written wrong.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mistake {
    /// `M = 2 diag(m)`.
    MassDoubled,
    /// `A_e,j = +1`: the signed incidence matrix without its minus signs.
    ASign,
    /// `Q` without `w CᵀC`.
    PinsNotInQ,
    /// `b` without `w CᵀC V`.
    PinsNotInB,
    /// The rest lengths measured on `U_cur` at every step.
    RFromDeformed,
    /// `M/Δt` for `M/Δt²`, in `Q` and in `y`.
    DtNotSquared,
    /// `U_prev` and `U_cur` swapped in `y`.
    PrevCurSwapped,
    /// `d = r (pᵢ − pⱼ)`, not divided by `‖pᵢ − pⱼ‖`.
    DNotNormalised,
    /// The pins taken from the scene's 1-based list as they are.
    PinsOneBased,
    /// Gravity multiplied by each vertex's mass.
    GravityTimesMass,
    /// The local step run on `U_cur` in every iteration.
    DFromUCur,
    /// `y = M (2 U_cur + U_prev)/Δt² + f_ext`.
    InertiaMinusPrev,
    /// The inertial term with a minus sign, in `Q` and `y`.
    InertiaSign,
    /// The inertial term without its `½`: `2M` in `Q` and `y`.
    InertiaHalfMissing,
}

impl Mistake {
    /// Every mistake, in the order of the gallery.
    pub const ALL: [Mistake; 14] = [
        Mistake::MassDoubled,
        Mistake::ASign,
        Mistake::PinsNotInQ,
        Mistake::PinsNotInB,
        Mistake::RFromDeformed,
        Mistake::DtNotSquared,
        Mistake::PrevCurSwapped,
        Mistake::DNotNormalised,
        Mistake::PinsOneBased,
        Mistake::GravityTimesMass,
        Mistake::DFromUCur,
        Mistake::InertiaMinusPrev,
        Mistake::InertiaSign,
        Mistake::InertiaHalfMissing,
    ];

    /// The name on the command line (`--mistake mass-doubled`).
    pub fn name(self) -> &'static str {
        self.lines().0
    }

    /// The mistake called `name`, if any.
    pub fn from_name(name: &str) -> Option<Mistake> {
        Mistake::ALL.into_iter().find(|m| m.name() == name)
    }

    /// The line the student wrote.
    pub fn wrong(self) -> &'static str {
        self.lines().1
    }

    /// The handout's line.
    pub fn right(self) -> &'static str {
        self.lines().2
    }

    /// `(name, the student's line, the handout's line)`.
    fn lines(self) -> (&'static str, &'static str, &'static str) {
        match self {
            Mistake::MassDoubled => ("mass-doubled", "M = 2 diag(m)", "M = diag(m)"),
            Mistake::ASign => ("a-sign", "A(e, j) = +1", "A(e, j) = −1"),
            Mistake::PinsNotInQ => (
                "pins-not-in-q",
                "Q = k AᵀA + M/Δt²",
                "Q = k AᵀA + M/Δt² + w CᵀC",
            ),
            Mistake::PinsNotInB => ("pins-not-in-b", "b = k Aᵀd + y", "b = k Aᵀd + y + w CᵀC V"),
            Mistake::RFromDeformed => (
                "r-from-deformed",
                "r = ‖U_cur,i − U_cur,j‖ every step",
                "r = ‖V_i − V_j‖ once",
            ),
            Mistake::DtNotSquared => ("dt-not-squared", "M/Δt in Q and y", "M/Δt² in Q and y"),
            Mistake::PrevCurSwapped => (
                "prev-cur-swapped",
                "y = M (2 U_prev − U_cur)/Δt² + f_ext",
                "y = M (2 U_cur − U_prev)/Δt² + f_ext",
            ),
            Mistake::DNotNormalised => (
                "d-not-normalised",
                "d = r (p_i − p_j)",
                "d = r (p_i − p_j)/‖p_i − p_j‖",
            ),
            Mistake::PinsOneBased => (
                "pins-one-based",
                "C from the file's pins, counted from 1",
                "C from the file's pins minus 1",
            ),
            Mistake::GravityTimesMass => (
                "gravity-times-mass",
                "f_ext = m_i (0, −9.8, 0)",
                "f_ext = (0, −9.8, 0)",
            ),
            Mistake::DFromUCur => (
                "d-from-u-cur",
                "d from U_cur in every iteration",
                "d from the last iteration's p",
            ),
            Mistake::InertiaMinusPrev => (
                "inertia-minus-prev",
                "y = M (2 U_cur + U_prev)/Δt² + f_ext",
                "y = M (2 U_cur − U_prev)/Δt² + f_ext",
            ),
            Mistake::InertiaSign => (
                "inertia-sign",
                "Q = k AᵀA − M/Δt² + w CᵀC, y = −M (2 U_cur − U_prev)/Δt² + f_ext",
                "+ M/Δt² in Q, + M (2 U_cur − U_prev)/Δt² in y",
            ),
            Mistake::InertiaHalfMissing => (
                "inertia-half-missing",
                "Q = k AᵀA + 2M/Δt² + w CᵀC, y = 2M (2 U_cur − U_prev)/Δt² + f_ext",
                "M, not 2M, in Q and y",
            ),
        }
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
