//! The precomputation: everything that does not change from step to step.
//!
//! ```text
//! rₑ = ‖Vᵢ − Vⱼ‖                  rest length of spring e = (i, j)
//! M  = diag(m)                    n × n mass matrix
//! A                               m × n signed incidence matrix
//! C                               |b| × n selection of the pinned vertices
//! Q  = k AᵀA + M/Δt² + w CᵀC      n × n, symmetric positive definite
//! ```
//!
//! `Q` is factored here, once (`L Lᵀ = Q`): the key observation of Liu et
//! al. is that `Q` is the same in every iteration of every time step. The
//! pinning penalty `w/2 Σ ‖pᵢ − Vᵢ‖²` also puts a constant term into the
//! right-hand side, `w CᵀC V`, computed here too. The fast path's
//! precomputation is [`MassSpringSystem::new`]; the handout's own
//! `fast_mass_springs_precomputation_{dense,sparse}`, written out as the
//! handout writes them from the same pieces, are in
//! [`textbook`](super::textbook). The output is constant:
//! the step's work arrays live in the step's own workspace
//! ([`StepWorkspace`](super::step::StepWorkspace)).
//!
//! What is kept: the handout's step takes `M` and `A` as matrices; here
//! `M` is kept as its diagonal `m`, and `A` as the spring list, which is
//! all of `A` (row `e` is `+1` at `springs[e][0]`, `−1` at `springs[e][1]`;
//! the step's `k Aᵀd` is taken from it,
//! [`incidence_transpose_mul_points`](super::signed_incidence::incidence_transpose_mul_points)).
//! Both are built as matrices here to assemble `Q` the way the handout
//! writes it ([`assemble_q`]), then dropped: a sparse `A` and `M` held 160 MB at a million
//! vertices (`docs/performance.md`). `Q` itself is kept, unless a
//! [`Simulation`](super::Simulation) whose method never multiplies by it
//! releases it ([`MassSpringSystem::holds_q`]): only its factorization is
//! needed to solve.
//!
//! Pins can be changed later ([`MassSpringSystem::set_pins`], e.g. to drag a
//! vertex): only `C`, `Q`'s values and `w CᵀC V` change, and the sparse
//! factorization is redone numerically on the pattern it already analysed.
//!
//! Source: Liu et al. 2013, §3–4; the assignment, "Matrices" and "Pinned
//! Vertices" (`fast_mass_springs_precomputation_dense.cpp` / `_sparse.cpp`).

use super::backend::{LinearAlgebra, Sparse, SparseFactorization};
use super::error::SimulationError;
use super::exact_pins::{ExactPins, PinnedNetwork};
use super::signed_incidence::signed_incidence_matrix;
use crate::linalg::sparse::CscMatrix;
use crate::linalg::{Cancel, LinalgError};
use crate::mesh::Scene;

/// The pinning penalty weight `w` (large: pins move by about `f/w`).
pub const PIN_WEIGHT: f64 = 1e10;

/// The assignment's time step, one frame at 30 frames per second.
pub const DELTA_T: f64 = 1.0 / 30.0;

/// What the precomputation produces: constant from step to step (until
/// the pins or the parameters are changed).
#[allow(non_snake_case)] // the handout's names: r, M, A, C, Q
#[derive(Debug, Clone)]
pub struct MassSpringSystem<B: LinearAlgebra> {
    /// Rest length of every spring.
    pub r: Vec<f64>,
    /// The masses `m`, one per vertex: the mass matrix `M = diag(m)`.
    pub m: Vec<f64>,
    /// The selection matrix of the pinned vertices.
    pub C: B::Matrix,
    /// `k AᵀA + M/Δt² + w CᵀC`; an empty (0 × 0) matrix while released
    /// ([`MassSpringSystem::holds_q`]; [`MassSpringSystem::q`] builds it).
    pub Q: B::Matrix,
    /// The Cholesky factorization of `Q`.
    pub prefactorization: B::Factorization,
    /// The springs `(i, j)`, 0-based: the signed incidence matrix `A`
    /// (row `e` is `+1` in column `i`, `−1` in column `j`).
    pub springs: Vec<[usize; 2]>,
    /// Spring stiffness.
    pub k: f64,
    /// Time step.
    pub delta_t: f64,
    /// Pinning penalty weight.
    pub w: f64,
    /// `w Cᵀ (C V)`: the pins' constant part of `b`.
    pub pin_rhs: Vec<[f64; 3]>,
    /// The pinned vertices, in the order of `C`'s rows, and where each
    /// is pinned (`C V` at rest; moved by dragging).
    pub pinned: Vec<usize>,
    pub pin_targets: Vec<[f64; 3]>,
    /// `is_pinned[i]`: is vertex `i` one of `pinned`?
    pub is_pinned: Vec<bool>,
    /// The reduced system when pins are exact constraints
    /// ([`MassSpringSystem::use_exact_pins`]); `None`: the penalty.
    pub exact_pins: Option<ExactPins<B>>,
    /// Is `Q` held (not released)?
    q_held: bool,
}

impl<B: LinearAlgebra> MassSpringSystem<B> {
    /// Number of vertices.
    pub fn n(&self) -> usize {
        self.pin_rhs.len()
    }

    /// Pins the vertices `pinned` (0-based) at `targets` instead of the
    /// current pins: rebuilds `C`, `Q` and `w CᵀC V` and refactors `Q`.
    ///
    /// # Errors
    /// [`SimulationError::InvalidInput`] for a pin out of range or a
    /// different number of targets; a factorization error.
    pub fn set_pins(
        &mut self,
        pinned: &[usize],
        targets: &[[f64; 3]],
    ) -> Result<(), SimulationError> {
        let n = self.n();
        check_pins(n, pinned, targets.len())?;
        self.C = selection_matrix::<B>(n, pinned);
        self.set_pinned(pinned, targets);
        self.assemble_and_refactor()?;
        self.pin_rhs = pin_right_hand_side::<B>(&self.C, n, targets, self.w);
        if let Some(how) = self.exact_pins.as_ref().map(|e| e.how) {
            self.use_exact_pins(how)?;
        }
        Ok(())
    }

    /// Holds the pins exactly instead of by the penalty (see
    /// [`exact_pins`](super::exact_pins)): factors the free vertices'
    /// `Q_ff`.
    ///
    /// # Errors
    /// [`SimulationError::Linalg`] when `Q_ff` is not positive definite.
    pub fn use_exact_pins(&mut self, how: SparseFactorization) -> Result<(), SimulationError> {
        let network = PinnedNetwork {
            springs: &self.springs,
            m: &self.m,
            k: self.k,
            delta_t: self.delta_t,
            pinned: &self.pinned,
            targets: &self.pin_targets,
        };
        self.exact_pins = Some(ExactPins::new(&network, how)?);
        Ok(())
    }

    /// New stiffness `k`, time step `delta_t` and masses `m`: rebuilds `M`
    /// and `Q` (same pattern, new values) and refactors `Q` numerically on
    /// the analysis already done, as a drag does. When the refactorization
    /// fails, the previous parameters are restored.
    ///
    /// # Errors
    /// [`SimulationError::InvalidInput`] for `k`, `delta_t` or a mass not
    /// positive and finite, or not one mass per vertex; a factorization
    /// error.
    pub fn set_parameters(
        &mut self,
        k: f64,
        delta_t: f64,
        m: &[f64],
    ) -> Result<(), SimulationError> {
        let positive = |x: f64| x > 0.0 && x.is_finite();
        if !positive(k)
            || !positive(delta_t)
            || m.len() != self.n()
            || !m.iter().all(|&x| positive(x))
        {
            return Err(SimulationError::InvalidInput(format!(
                "k = {k} and Δt = {delta_t} must be positive and finite, with {} positive masses",
                self.n()
            )));
        }
        check_q_fits(&self.springs, m, k, delta_t)?;
        let previous = (self.k, self.delta_t, self.m.clone());
        self.install_parameters(k, delta_t, m);
        if let Err(error) = self.assemble_and_refactor() {
            self.install_parameters(previous.0, previous.1, &previous.2);
            self.assemble_and_refactor()?;
            return Err(error.into());
        }
        if let Some(how) = self.exact_pins.as_ref().map(|e| e.how) {
            self.use_exact_pins(how)?;
        }
        Ok(())
    }

    /// Sets `k`, `Δt` and `m` (not `Q`, not the factorization).
    fn install_parameters(&mut self, k: f64, delta_t: f64, m: &[f64]) {
        self.k = k;
        self.delta_t = delta_t;
        self.m.copy_from_slice(m);
    }

    /// Assembles `Q` for the current springs, masses, pins and parameters
    /// and refactors it (numerically, on the analysis already done); keeps
    /// `Q` when it is held.
    fn assemble_and_refactor(&mut self) -> Result<(), crate::linalg::LinalgError> {
        let q = self.assemble_q();
        let refactored = B::refactor(&mut self.prefactorization, &q);
        if self.q_held {
            self.Q = q;
        }
        refactored
    }

    /// `Q = k AᵀA + M/Δt² + w CᵀC` for the current values.
    fn assemble_q(&self) -> B::Matrix {
        network_q::<B>(
            &self.springs,
            &self.m,
            &self.C,
            self.k,
            self.delta_t,
            self.w,
            Cancel::NEVER,
        )
        .expect(NOTHING_CANCELS)
    }

    /// Is `Q` held? It is after the precomputation; a
    /// [`Simulation`](super::Simulation) releases it when its method only
    /// solves with `Q` (the factorization) and never multiplies by it, and
    /// holds it again for a method that does (L-BFGS).
    pub fn holds_q(&self) -> bool {
        self.q_held
    }

    /// `Q`: the held matrix, or a new one assembled when it was released.
    pub fn q(&self) -> std::borrow::Cow<'_, B::Matrix> {
        if self.q_held {
            std::borrow::Cow::Borrowed(&self.Q)
        } else {
            std::borrow::Cow::Owned(self.assemble_q())
        }
    }

    /// Keeps `Q` from now on, assembling it again if it was released.
    pub fn hold_q(&mut self) {
        if !self.q_held {
            self.Q = self.assemble_q();
            self.q_held = true;
        }
    }

    /// Frees `Q` (its factorization stays): `n × n` values and indices
    /// that the step does not read unless it multiplies by `Q`. Only a
    /// [`Simulation`](super::Simulation), which holds it again before such
    /// a step, releases it.
    pub(crate) fn release_q(&mut self) {
        self.Q = B::from_entries(0, 0, std::iter::empty());
        self.q_held = false;
    }

    /// Moves the current pins to `targets` (one per row of `C`): only the
    /// right-hand side `w Cᵀ targets` changes, `Q` and its factorization
    /// stay.
    ///
    /// # Errors
    /// [`SimulationError::InvalidInput`] when the number of targets is not
    /// the number of pins.
    pub fn set_pin_targets(&mut self, targets: &[[f64; 3]]) -> Result<(), SimulationError> {
        let n = self.n();
        let pins = self.pinned.len();
        if targets.len() != pins {
            return Err(SimulationError::InvalidInput(format!(
                "{} targets for {pins} pinned vertices",
                targets.len()
            )));
        }
        self.pin_rhs = pin_right_hand_side::<B>(&self.C, n, targets, self.w);
        self.pin_targets.copy_from_slice(targets);
        if let Some(exact) = &mut self.exact_pins {
            exact.set_targets(&self.springs, self.k, &self.pinned, targets);
        }
        Ok(())
    }

    /// What the system holds, in bytes (arrays' lengths), item by item:
    /// the memory figures of `docs/performance.md` and their test (the
    /// step's work arrays are counted by
    /// [`StepWorkspace::bytes`](super::step::StepWorkspace::bytes)).
    pub fn bytes(&self) -> Vec<(&'static str, usize)> {
        use std::mem::size_of_val as bytes;
        let exact = self.exact_pins.as_ref().map_or(0, |e| {
            B::matrix_bytes(&e.q_without_pins)
                + B::factorization_bytes(&e.factorization)
                + bytes(&e.free[..])
                + 2 * bytes(&e.pin_rhs[..])
        });
        vec![
            (
                "factorization of Q",
                B::factorization_bytes(&self.prefactorization),
            ),
            ("Q (when held)", B::matrix_bytes(&self.Q)),
            ("springs (A)", bytes(&self.springs[..])),
            (
                "rest lengths r, masses m",
                bytes(&self.r[..]) + bytes(&self.m[..]),
            ),
            (
                "pins: C, w CᵀC V, pinned, targets, mask",
                B::matrix_bytes(&self.C)
                    + bytes(&self.pin_rhs[..])
                    + bytes(&self.pinned[..])
                    + bytes(&self.pin_targets[..])
                    + bytes(&self.is_pinned[..]),
            ),
            ("exact pins: Q without pins, Q_ff factor", exact),
        ]
    }

    /// Records which vertices are pinned, and where.
    fn set_pinned(&mut self, pinned: &[usize], targets: &[[f64; 3]]) {
        self.pinned = pinned.to_vec();
        self.pin_targets = targets.to_vec();
        self.is_pinned = pinned_mask(self.n(), pinned);
    }
}

/// `mask[i]`: is vertex `i` in `pinned`?
fn pinned_mask(n: usize, pinned: &[usize]) -> Vec<bool> {
    let mut mask = vec![false; n];
    for &i in pinned {
        mask[i] = true;
    }
    mask
}

impl<B: LinearAlgebra> MassSpringSystem<B> {
    /// The fast path's precomputation for rest positions `v`, springs `springs`, stiffness
    /// `k`, masses `m`, pinned vertices `pinned` and time step `delta_t`, with
    /// the default factorization (sparse: AMD, supernodal).
    ///
    /// # Errors
    /// [`SimulationError::InvalidInput`] for inconsistent sizes or indices;
    /// [`SimulationError::QOverflow`] when `k` or a mass is so large that
    /// `Q` would overflow `f64` ([`check_q_fits`]: the vertex and the
    /// largest value that fits); [`SimulationError::Linalg`] when `Q` is
    /// not positive definite.
    pub fn new(
        v: &[[f64; 3]],
        springs: &[[usize; 2]],
        k: f64,
        m: &[f64],
        pinned: &[usize],
        delta_t: f64,
    ) -> Result<Self, SimulationError> {
        let how = SparseFactorization::default();
        Self::with_factorization(v, springs, k, m, pinned, delta_t, how, Cancel::NEVER)
    }

    /// [`MassSpringSystem::new`], factoring `Q` the way `how` says
    /// (the ordering and the numeric method of the sparse backend), and
    /// given up once `cancel` is set (the dense backend looks at it while
    /// it forms `AᵀA` and factors `Q`, which take minutes on a large
    /// scene).
    ///
    /// # Errors
    /// As [`MassSpringSystem::new`]; [`SimulationError::Cancelled`].
    #[allow(clippy::too_many_arguments)] // the handout's six inputs, how Q is factored, what stops it
    pub fn with_factorization(
        v: &[[f64; 3]],
        springs: &[[usize; 2]],
        k: f64,
        m: &[f64],
        pinned: &[usize],
        delta_t: f64,
        how: SparseFactorization,
        cancel: Cancel<'_>,
    ) -> Result<Self, SimulationError> {
        let n = v.len();
        check_inputs(v, springs, m)?;
        check_pins(n, pinned, pinned.len())?;
        check_q_fits(springs, m, k, delta_t)?;
        let r = rest_lengths(v, springs);
        let c = selection_matrix::<B>(n, pinned);
        let q = network_q::<B>(springs, m, &c, k, delta_t, PIN_WEIGHT, cancel)?;
        let prefactorization = B::factor_cancellable(&q, how, cancel)?;
        let mut pinned_rest = vec![[0.0; 3]; pinned.len()];
        B::mul_points(&c, v, &mut pinned_rest); // C V
        let pin_rhs = pin_right_hand_side::<B>(&c, n, &pinned_rest, PIN_WEIGHT);
        Ok(MassSpringSystem {
            r,
            m: m.to_vec(),
            C: c,
            Q: q,
            prefactorization,
            springs: springs.to_vec(),
            k,
            delta_t,
            w: PIN_WEIGHT,
            pin_rhs,
            pinned: pinned.to_vec(),
            pin_targets: pinned_rest,
            is_pinned: pinned_mask(n, pinned),
            exact_pins: None,
            q_held: true,
        })
    }
}

/// `rₑ = ‖Vᵢ − Vⱼ‖`, the rest length of every spring.
pub fn rest_lengths(v: &[[f64; 3]], springs: &[[usize; 2]]) -> Vec<f64> {
    springs
        .iter()
        .map(|&[i, j]| {
            (0..3)
                .map(|c| (v[i][c] - v[j][c]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .collect()
}

/// `C`, the `|b| × n` selection matrix: row `p` has a 1 in column
/// `pinned[p]`, so that `C V` lists the pinned vertices' positions.
pub fn selection_matrix<B: LinearAlgebra>(n: usize, pinned: &[usize]) -> B::Matrix {
    B::from_entries(
        pinned.len(),
        n,
        pinned.iter().enumerate().map(|(p, &i)| (p, i, 1.0)),
    )
}

/// `M = diag(m)`, the `n × n` mass matrix.
pub fn mass_matrix<B: LinearAlgebra>(m: &[f64]) -> B::Matrix {
    let n = m.len();
    B::from_entries(n, n, m.iter().enumerate().map(|(i, &mi)| (i, i, mi)))
}

/// `Q = k AᵀA + M/Δt² + w CᵀC`, each term as the handout writes it (so the
/// rounding matches a direct transcription: `mᵢ/Δt²`, not `mᵢ·(1/Δt²)`).
#[allow(non_snake_case)] // the handout's A, M, C
pub fn assemble_q<B: LinearAlgebra>(
    k: f64,
    A: &B::Matrix,
    M: &B::Matrix,
    delta_t: f64,
    w: f64,
    C: &B::Matrix,
) -> B::Matrix {
    assemble_q_cancellable::<B>(k, A, M, delta_t, w, C, Cancel::NEVER).expect(NOTHING_CANCELS)
}

/// [`assemble_q`], given up once `cancel` is set: the dense products
/// `AᵀA` and `CᵀC` look at it between their rows.
///
/// # Errors
/// [`LinalgError::Cancelled`] (what was assembled is dropped).
#[allow(non_snake_case)] // the handout's A, M, C
pub fn assemble_q_cancellable<B: LinearAlgebra>(
    k: f64,
    A: &B::Matrix,
    M: &B::Matrix,
    delta_t: f64,
    w: f64,
    C: &B::Matrix,
    cancel: Cancel<'_>,
) -> Result<B::Matrix, LinalgError> {
    let AtA = B::gram_cancellable(A, cancel)?;
    cancel.check()?; // each term below is a pass over n × n values
    let m_over_dt2 = B::divide(M, delta_t * delta_t);
    cancel.check()?;
    let springs_and_mass = B::combine(k, &AtA, 1.0, &m_over_dt2);
    drop((AtA, m_over_dt2));
    let CtC = B::gram_cancellable(C, cancel)?;
    cancel.check()?;
    Ok(B::combine(1.0, &springs_and_mass, w, &CtC))
}

/// Why [`Cancel::NEVER`] unwraps.
const NOTHING_CANCELS: &str = "nothing cancels it";

/// [`assemble_q`] for the network `springs` with masses `m`: `A` and `M`
/// are built for it and dropped once `Q` is made (the fast path keeps the
/// spring list and the masses instead); given up once `cancel` is set.
///
/// # Errors
/// [`LinalgError::Cancelled`].
#[allow(non_snake_case)] // the handout's A and M
pub fn network_q<B: LinearAlgebra>(
    springs: &[[usize; 2]],
    m: &[f64],
    c: &B::Matrix,
    k: f64,
    delta_t: f64,
    w: f64,
    cancel: Cancel<'_>,
) -> Result<B::Matrix, LinalgError> {
    let A = signed_incidence_matrix::<B>(m.len(), springs);
    let M = mass_matrix::<B>(m);
    assemble_q_cancellable::<B>(k, &A, &M, delta_t, w, c, cancel)
}

/// [`network_q`] of a scene at the time step `delta_t`, pins weighted by
/// [`PIN_WEIGHT`], on the sparse backend: the `Q` a simulation of the
/// scene factors, without factoring it (`export-q`, `spy`, `etree` and the
/// benchmarks read it).
pub fn scene_q(scene: &Scene, delta_t: f64) -> CscMatrix {
    let c = selection_matrix::<Sparse>(scene.vertices.len(), &scene.pinned);
    network_q::<Sparse>(
        &scene.springs,
        &scene.masses,
        &c,
        scene.k,
        delta_t,
        PIN_WEIGHT,
        Cancel::NEVER,
    )
    .expect(NOTHING_CANCELS)
}

/// `y = M x` for the diagonal mass matrix `M = diag(m)`: `yᵢ = mᵢ xᵢ`.
pub fn mass_mul_points(m: &[f64], x: &[[f64; 3]], y: &mut [[f64; 3]]) {
    for ((y, x), &mi) in y.iter_mut().zip(x).zip(m) {
        *y = x.map(|xc| mi * xc);
    }
}

/// `w Cᵀ targets`, where `targets` are the pinned positions (`C V` at rest,
/// computed from `C` by the precomputation). Rows of vertices that are not
/// pinned are `+0.0` (an empty column's sum times `w > 0`), which the plain
/// loop in the factor's order relies on (`methods::factor_order`).
pub fn pin_right_hand_side<B: LinearAlgebra>(
    c: &B::Matrix,
    n: usize,
    targets: &[[f64; 3]],
    w: f64,
) -> Vec<[f64; 3]> {
    let mut out = vec![[0.0; 3]; n];
    B::transpose_mul_points(c, targets, &mut out);
    for row in &mut out {
        *row = row.map(|x| w * x);
    }
    out
}

/// Sizes and indices consistent, values finite?
pub(crate) fn check_inputs(
    v: &[[f64; 3]],
    springs: &[[usize; 2]],
    m: &[f64],
) -> Result<(), SimulationError> {
    let n = v.len();
    let invalid = |why: String| Err(SimulationError::InvalidInput(why));
    if m.len() != n {
        return invalid(format!("{} masses for {n} vertices", m.len()));
    }
    if let Some(e) = springs.iter().position(|s| s[0] >= n || s[1] >= n) {
        return invalid(format!("spring {e} joins a vertex beyond the {n} vertices"));
    }
    if let Some(i) = v.iter().position(|p| p.iter().any(|x| !x.is_finite())) {
        return invalid(format!("vertex {i} has a non-finite coordinate"));
    }
    if let Some(i) = m.iter().position(|&mi| !(mi > 0.0 && mi.is_finite())) {
        return invalid(format!(
            "vertex {i} has mass {}, not positive and finite",
            m[i]
        ));
    }
    Ok(())
}

/// Refuses a stiffness `k`, time step `delta_t` or masses `m` whose
/// `Q = k AᵀA + M/Δt² + w CᵀC` would overflow `f64` on its diagonal
/// (`k` times the springs at a vertex, plus `mᵢ/Δt²`, plus `w` per pin),
/// naming the quantity, its vertex (1-based, as a file's line) and the
/// largest value that works; otherwise the factorization would only say
/// "not positive definite: pivot inf". Each term may take half of the
/// largest `f64`, so that their sum is finite too.
///
/// # Errors
/// [`SimulationError::QOverflow`] with that sentence.
pub fn check_q_fits(
    springs: &[[usize; 2]],
    m: &[f64],
    k: f64,
    delta_t: f64,
) -> Result<(), SimulationError> {
    let mut springs_at = vec![0u64; m.len()];
    for spring in springs {
        for &vertex in spring {
            if let Some(count) = springs_at.get_mut(vertex) {
                *count += 1;
            }
        }
    }
    let room = f64::MAX / 2.0;
    let refuse = |why: String| Err(SimulationError::QOverflow(why));
    if let Some((vertex, &count)) = springs_at.iter().enumerate().max_by_key(|(_, &c)| c) {
        let count = count.max(1) as f64;
        if k * count > room {
            return refuse(format!(
                "k = {k:e} overflows Q: its diagonal holds k × {count} (the springs at vertex \
                 {}), more than f64 holds (1.8e308); Q fits with k up to {} here",
                vertex + 1,
                rounded_down(room / count)
            ));
        }
    }
    let per_second_squared = 1.0 / (delta_t * delta_t);
    if let Some(vertex) = m.iter().position(|&mi| mi * per_second_squared > room) {
        return refuse(format!(
            "the mass {:e} of vertex {} overflows Q: its diagonal holds m / Δt² = m × {}, more \
             than f64 holds (1.8e308); Q fits with masses up to {}",
            m[vertex],
            vertex + 1,
            crate::files::number(per_second_squared),
            rounded_down(room / per_second_squared)
        ));
    }
    Ok(())
}

/// `x` (> 0) rounded down to two significant digits, as `2.9e307`: a bound
/// that is within the limit as printed.
fn rounded_down(x: f64) -> String {
    let exponent = x.log10().floor();
    let mantissa = (x / 10f64.powf(exponent) * 10.0).floor() / 10.0;
    format!("{mantissa:.1}e{exponent}")
}

/// Every pin is a vertex, and there is one target per pin.
pub(crate) fn check_pins(
    n: usize,
    pinned: &[usize],
    targets: usize,
) -> Result<(), SimulationError> {
    if let Some(&i) = pinned.iter().find(|&&i| i >= n) {
        return Err(SimulationError::InvalidInput(format!(
            "pinned vertex {i} is beyond the {n} vertices"
        )));
    }
    if targets != pinned.len() {
        return Err(SimulationError::InvalidInput(format!(
            "{targets} targets for {} pinned vertices",
            pinned.len()
        )));
    }
    Ok(())
}
