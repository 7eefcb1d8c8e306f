//! The quantities `trace` writes, in the handout's order: one table that
//! names each file, says what it holds and how it is compared, read by the
//! writer, the README and `--compare` alike (so the three cannot drift).
//!
//! The order is the order in which a student writes the code: the task
//! `signed_incidence_matrix` (`A`), then the precomputation (`r`, `M`,
//! `C`, `Q` and its factorization), then the step (`y`, then each
//! iteration's `d`, `b`, `p`). The first quantity that fails a comparison
//! is then the first piece of code to look at.

/// What a row or a column of a quantity stands for, to name the place of a
/// difference.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// A spring `e = (i, j)`: rows of `A` and `r`.
    Spring,
    /// A spring's vector, which changes sign with the spring's
    /// orientation: rows of `d` (`dᵢⱼ = −dⱼᵢ`).
    SpringVector,
    /// A vertex: rows of `U`, `y`, `b`, `p`; rows and columns of `M`, `Q`.
    Vertex,
    /// A pinned vertex, in the order of the scene's list `b`: rows of `C`.
    Pin,
    /// x, y or z.
    Coordinate,
    /// A position in the factor's order (`P Q Pᵀ`): rows and columns of
    /// `L` and `P`.
    FactorOrder,
    /// The single column of a vector.
    Single,
}

/// How a student's file is compared with ours.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Check {
    /// `A`: the same springs as ours, in any order and orientation (the
    /// handout leaves both free), each matched to ours by its two
    /// vertices; `r` and `d` are then compared through that matching.
    Incidence,
    /// Entry by entry: `|ours − yours| ≤ tolerance · s`, with `s` the
    /// largest of `|ours|`, `|yours|` and the largest `|ours|` in the row
    /// (`tolerance` 0: the same numbers exactly).
    Entries { tolerance: f64 },
    /// `P`: any permutation is a valid ordering; a different one is
    /// reported, not failed.
    Ordering,
    /// `L`: `L Lᵀ = P Q Pᵀ` with the student's `P` (or ours, or none),
    /// entry by entry to `tolerance · √(Q'ᵢᵢ Q'ⱼⱼ)`, `Q' = P Q Pᵀ`.
    Factor { tolerance: f64 },
    /// `b = k Aᵀd + y + w CᵀC V`: entry by entry to `tolerance · s`, with
    /// `s` the size of its terms, `k (|A|ᵀ|d|)ᵢ + |yᵢ| + |(w CᵀC V)ᵢ|`:
    /// the spring terms cancel to much smaller entries, and a pinned row
    /// is dominated by `w`, where a row's own scale would hide a spring.
    Sum { tolerance: f64 },
}

/// One kind of quantity of the handout (the iterations' `d`, `b` and `p`
/// are one kind each, written once per iteration).
#[derive(Debug)]
pub struct Spec {
    /// The handout's symbol and the file's stem (`d` is written `d_1`, …).
    pub symbol: &'static str,
    /// Its equation, as the handout writes it.
    pub equation: &'static str,
    /// Rows × columns, in the handout's words.
    pub shape: &'static str,
    /// The function of this crate that computes it.
    pub function: &'static str,
    pub rows: Axis,
    pub columns: Axis,
    pub check: Check,
    /// Why the tolerance is what it is, and whether the quantity is unique.
    pub why: &'static str,
    /// Written once per iteration (`d`, `b`, `p`).
    pub per_iteration: bool,
}

/// Entries computed by the same formula in another order of additions:
/// a few units in the last place.
const ROUNDING: f64 = 1e-12;
/// After a solve with `Q`: rounding times `Q`'s condition (the pins'
/// `w = 1e10` against the masses over `Δt²`), whatever the ordering.
const AFTER_SOLVE: f64 = 1e-8;

/// Every kind of quantity, in the handout's order.
pub static SPECS: [Spec; 13] = [
    Spec {
        symbol: "A",
        equation: "row e of spring (i, j): +1 in column i, −1 in column j",
        shape: "m × n: springs × vertices, 2m entries",
        function: "sim::signed_incidence::signed_incidence_matrix_sparse",
        rows: Axis::Spring,
        columns: Axis::Vertex,
        check: Check::Incidence,
        why: "unique up to the order of the springs and the orientation of each, which the \
              handout leaves free (\"an arbitrary (but fixed) ordering of the edges\"; \"we'll \
              pick an orientation for edge anyway\"): each of your rows must be a spring, +1 at \
              one end and −1 at the other, and your springs ours, each once, matched by their two \
              vertices; r and d are compared through that matching, d negated where your spring \
              runs the other way",
        per_iteration: false,
    },
    Spec {
        symbol: "r",
        equation: "rᵢⱼ = ‖Vᵢ − Vⱼ‖",
        shape: "m × 1",
        function: "sim::precomputation::rest_lengths",
        rows: Axis::Spring,
        columns: Axis::Single,
        check: Check::Entries { tolerance: ROUNDING },
        why: "unique; a norm summed in another order differs in the last bits only",
        per_iteration: false,
    },
    Spec {
        symbol: "M",
        equation: "M = diag(m), m the Voronoi masses of the scene",
        shape: "n × n, diagonal; an n × 1 file of the diagonal is read too",
        function: "sim::precomputation::mass_matrix",
        rows: Axis::Vertex,
        columns: Axis::Vertex,
        check: Check::Entries { tolerance: ROUNDING },
        why: "unique; the masses are given, only their place can be wrong",
        per_iteration: false,
    },
    Spec {
        symbol: "C",
        equation: "row k: 1 in column bₖ, the k-th pinned vertex",
        shape: "#b × n: pins × vertices",
        function: "sim::precomputation::selection_matrix",
        rows: Axis::Pin,
        columns: Axis::Vertex,
        check: Check::Entries { tolerance: 0.0 },
        why: "unique and exact (ones), rows in the order of the scene's list b",
        per_iteration: false,
    },
    Spec {
        symbol: "Q",
        equation: "Q = k AᵀA + M/Δt² + w CᵀC, Δt = 1/30, w = 1e10",
        shape: "n × n, both triangles",
        function: "sim::precomputation::assemble_q (Precomputation::Q)",
        rows: Axis::Vertex,
        columns: Axis::Vertex,
        check: Check::Entries { tolerance: ROUNDING },
        why: "unique; sums of a few terms, in any order, agree to the last bits of their row's diagonal",
        per_iteration: false,
    },
    Spec {
        symbol: "P",
        equation: "L Lᵀ = P Q Pᵀ; row r of P has its 1 in column perm[r]",
        shape: "n × n, a permutation",
        function: "linalg::sparse::SymbolicCholesky::permutation (AMD: linalg::sparse::amd)",
        rows: Axis::FactorOrder,
        columns: Axis::Vertex,
        check: Check::Ordering,
        why: "not unique: any fill-reducing ordering is right (Eigen's AMD and ours differ); \
              a different P is reported, never failed, and L is checked with yours",
        per_iteration: false,
    },
    Spec {
        symbol: "L",
        equation: "L Lᵀ = P Q Pᵀ, lower triangular, positive diagonal",
        shape: "n × n, lower triangle",
        function: "linalg::sparse::up_looking (SparseCholesky::l), \
                   by sim::textbook::fast_mass_springs_precomputation_sparse",
        rows: Axis::FactorOrder,
        columns: Axis::FactorOrder,
        check: Check::Factor { tolerance: ROUNDING },
        why: "unique for a given P, but its entries change with the ordering: compared as \
              L Lᵀ against P Q Pᵀ (your P.mtx if given, else ours or none), to the rounding \
              of a Cholesky factorization",
        per_iteration: false,
    },
    Spec {
        symbol: "U_prev",
        equation: "the positions one step before U_cur (step 1: V)",
        shape: "n × 3",
        function: "sim::textbook::fast_mass_springs_step_sparse (the state before U_cur)",
        rows: Axis::Vertex,
        columns: Axis::Coordinate,
        check: Check::Entries {
            tolerance: AFTER_SOLVE,
        },
        why: "unique; after steps from rest it carries the solves' rounding",
        per_iteration: false,
    },
    Spec {
        symbol: "U_cur",
        equation: "the positions at the start of step K (step 1: V, at rest)",
        shape: "n × 3",
        function: "sim::textbook::fast_mass_springs_step_sparse, K − 1 times from rest",
        rows: Axis::Vertex,
        columns: Axis::Coordinate,
        check: Check::Entries {
            tolerance: AFTER_SOLVE,
        },
        why: "unique; after steps from rest it carries the solves' rounding",
        per_iteration: false,
    },
    Spec {
        symbol: "y",
        equation: "y = M (2 U_cur − U_prev)/Δt² + f_ext, f_ext = (0, −9.8, 0) at every vertex",
        shape: "n × 3",
        function: "sim::textbook::inertial_term",
        rows: Axis::Vertex,
        columns: Axis::Coordinate,
        check: Check::Entries {
            tolerance: AFTER_SOLVE,
        },
        why: "unique; made of U_cur and U_prev, so it carries their rounding",
        per_iteration: false,
    },
    Spec {
        symbol: "d",
        equation: "dᵢⱼ = rᵢⱼ (pᵢ − pⱼ)/‖pᵢ − pⱼ‖, from the previous iteration's p (first: p = U_cur)",
        shape: "m × 3",
        function: "sim::local_step::project_springs",
        rows: Axis::SpringVector,
        columns: Axis::Coordinate,
        check: Check::Entries {
            tolerance: AFTER_SOLVE,
        },
        why: "unique; made of the previous p, so it carries the solves' rounding",
        per_iteration: true,
    },
    Spec {
        symbol: "b",
        equation: "b = k Aᵀd + y + w CᵀC V",
        shape: "n × 3",
        function: "sim::textbook::right_hand_side",
        rows: Axis::Vertex,
        columns: Axis::Coordinate,
        check: Check::Sum {
            tolerance: AFTER_SOLVE,
        },
        why: "unique; its spring terms k Aᵀd (of size k r) cancel to entries of the size of y, \
              and a pinned row is of the size of w, so each entry is compared to the size of \
              its terms, k (|A|ᵀ|d|)ᵢ + |yᵢ| + |(w CᵀC V)ᵢ|",
        per_iteration: true,
    },
    Spec {
        symbol: "p",
        equation: "p = Q⁻¹ b = Pᵀ L⁻ᵀ L⁻¹ P b",
        shape: "n × 3",
        function: "sim::textbook::solve_sparse",
        rows: Axis::Vertex,
        columns: Axis::Coordinate,
        check: Check::Entries {
            tolerance: AFTER_SOLVE,
        },
        why: "unique whatever the ordering; each solve's rounding is amplified by Q's condition",
        per_iteration: true,
    },
];

/// One file of a trace: a kind of quantity, and its iteration for `d`,
/// `b`, `p`.
#[derive(Debug, Clone, Copy)]
pub struct Quantity {
    pub spec: &'static Spec,
    /// 1-based iteration, for the per-iteration quantities.
    pub iteration: Option<usize>,
}

impl Quantity {
    /// `A`, `d_1`, …
    pub fn name(&self) -> String {
        match self.iteration {
            Some(k) => format!("{}_{k}", self.spec.symbol),
            None => self.spec.symbol.to_string(),
        }
    }

    /// `A.mtx`, `d_1.mtx`, …
    pub fn file_name(&self) -> String {
        format!("{}.mtx", self.name())
    }
}

/// Every file of a trace of `iterations` iterations, in the handout's order.
pub fn quantities(iterations: usize) -> Vec<Quantity> {
    let once = SPECS.iter().filter(|spec| !spec.per_iteration);
    let mut all: Vec<Quantity> = once
        .map(|spec| Quantity {
            spec,
            iteration: None,
        })
        .collect();
    for k in 1..=iterations {
        let each = SPECS.iter().filter(|spec| spec.per_iteration);
        all.extend(each.map(|spec| Quantity {
            spec,
            iteration: Some(k),
        }));
    }
    all
}
