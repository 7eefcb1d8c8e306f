//! The energy a time step minimises, and its gradient.
//!
//! With `p⁰ = U_cur` (where the step starts), `ŷ = 2 U_cur − U_prev` (where
//! inertia alone would carry each vertex) and the pins `t_c` of the pinned
//! vertices `c`, the positions at `t + Δt` minimise (the handout's energy,
//! plus the pinning penalty)
//!
//! ```text
//! E(p) = Σₑ ½ k (‖pᵢ − pⱼ‖ − rₑ)²                  springs, e = (i, j)
//!      + 1/(2Δt²) Σᵢ mᵢ ‖pᵢ − ŷᵢ‖²                  inertia: tr((p − ŷ)ᵀ M (p − ŷ)) / (2Δt²)
//!      − Σᵢ pᵢ · fᵢ                                 external forces
//!      + ½ w Σ_c ‖p_c − t_c‖²                       pins, w = 1e10
//! ```
//!
//! and its gradient, one row per vertex,
//!
//! ```text
//! ∇E(p)ᵢ = Σ_{e ∋ i} ± k (1 − rₑ/‖vₑ‖) vₑ   (vₑ = pᵢ − pⱼ; + at i, − at j)
//!        + mᵢ (pᵢ − ŷᵢ) / Δt² − fᵢ  (+ w (pᵢ − tᵢ) when i is pinned).
//! ```
//!
//! The gradient is `Q p − b(p)`, with `b(p)` the right-hand side the global
//! step builds from the local step's `d(p)`: the plain local/global
//! iteration is `p ← p − Q⁻¹ ∇E(p)`, a gradient step preconditioned by `Q`.
//!
//! **Differences, not values.** `E` itself is useless for telling iterates
//! apart: the pin term alone is `½ w ‖drift‖²` with `w = 1e10`, and the
//! inertia and gravity terms are large and nearly constant, so `E(p) −
//! E(p⁰)` computed as a difference of two totals loses every digit that
//! matters. Each term is instead written as a product of a small difference
//! and a sum, which rounds to nearly full relative precision:
//!
//! ```text
//! a² − b² = (a − b)(a + b)         for ‖p − ŷ‖², ‖p − t‖², (l − r)²
//! ```
//!
//! with `l − l⁰` exact to the rounding of the lengths themselves.
//!
//! so `E(p) − E(p⁰)` is `0` at `p⁰` exactly and negative where a method has
//! made progress. The gradient needs no such care: its terms are computed
//! from `p` directly, never as `Q p − b` (whose two parts are each ~1e10 at
//! a pin).
//!
//! Both cost `O(m + n)` (a pass over the springs like the local step's, in
//! [`spring_pass`](super::spring_pass), and one over the vertices) and allocate nothing.
//!
//! Source: the assignment's "Time integration" and "Pinned vertices"
//! sections (the energy); Liu et al. 2013, §3–4 (the local/global iteration
//! as block coordinate descent on it); Liu, Bouaziz & Kavan 2017, §3 (the
//! same iteration as a quasi-Newton step with `Q` as the Hessian guess).

use super::simd::energy::{vertex_sums as vertex_sums_four_at_a_time, Vertices};
use super::spring_pass::{Outputs, Springs};

/// Everything that fixes one step's energy: the network, the start of the
/// step, inertia, forces and pins. Borrowed, so it costs nothing to make.
#[derive(Debug, Clone, Copy)]
pub struct StepEnergy<'a> {
    /// The springs `(i, j)`.
    pub springs: &'a [[usize; 2]],
    /// Rest length of every spring.
    pub r: &'a [f64],
    /// Spring stiffness.
    pub k: f64,
    /// Mass of every vertex.
    pub m: &'a [f64],
    /// Time step.
    pub delta_t: f64,
    /// Pinning penalty weight (0 when pins are exact constraints).
    pub w: f64,
    /// The pinned vertices and their targets `t_c`.
    pub pinned: &'a [usize],
    pub pin_targets: &'a [[f64; 3]],
    /// `ŷ = 2 U_cur − U_prev`.
    pub inertial_target: &'a [[f64; 3]],
    /// `f_ext`, one force per vertex.
    pub f_ext: &'a [[f64; 3]],
    /// `p⁰ = U_cur`, where the step starts.
    pub start: &'a [[f64; 3]],
    /// `l⁰ₑ = ‖p⁰ᵢ − p⁰ⱼ‖`, every spring's length at the start
    /// ([`start_lengths`]), kept so that an evaluation takes one square
    /// root per spring, not two.
    pub start_lengths: &'a [f64],
}

/// `l⁰ₑ = ‖p⁰ᵢ − p⁰ⱼ‖` for every spring, into `lengths`.
pub fn start_lengths(springs: &[[usize; 2]], start: &[[f64; 3]], lengths: &mut [f64]) {
    for (l, &[i, j]) in lengths.iter_mut().zip(springs) {
        *l = norm(difference(start[i], start[j]));
    }
}

/// `E(p) − E(p⁰)`, term by term.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EnergyChange {
    pub springs: f64,
    pub inertia: f64,
    pub external: f64,
    pub pins: f64,
}

impl EnergyChange {
    /// The whole change `E(p) − E(p⁰)`.
    pub fn total(&self) -> f64 {
        self.springs + self.inertia + self.external + self.pins
    }
}

impl StepEnergy<'_> {
    /// `E(p) − E(p⁰)`, each term as a difference times a sum.
    ///
    /// # Panics
    /// When `p` does not have one row per vertex.
    pub fn change(&self, p: &[[f64; 3]]) -> EnergyChange {
        self.change_given_springs(p, self.springs().measure(p, Outputs::default()))
    }

    /// `E(p) − E(p⁰)` when a [`spring_pass`](super::spring_pass) at `p` has
    /// already measured `S = Σₑ (l − l⁰) ((l − r) + (l⁰ − r))` (the local
    /// step's pass can: then the energy costs only the pass over the
    /// vertices).
    ///
    /// # Panics
    /// When `p` does not have one row per vertex.
    pub fn change_given_springs(&self, p: &[[f64; 3]], spring_sum: f64) -> EnergyChange {
        assert_eq!(p.len(), self.start.len());
        let (inertia, external) = self.inertia_and_external_change(p);
        EnergyChange {
            springs: 0.5 * self.k * spring_sum,
            inertia,
            external,
            pins: self.pin_change(p),
        }
    }

    /// The springs as the [`spring_pass`](super::spring_pass) sees them.
    pub fn springs(&self) -> Springs<'_> {
        Springs {
            springs: self.springs,
            r: self.r,
            start_lengths: self.start_lengths,
            k: self.k,
        }
    }

    /// `Σᵢ mᵢ/(2Δt²) (pᵢ − p⁰ᵢ)·((pᵢ − ŷᵢ) + (p⁰ᵢ − ŷᵢ))` and
    /// `−Σᵢ (pᵢ − p⁰ᵢ)·fᵢ`, in one pass over the vertices.
    fn inertia_and_external_change(&self, p: &[[f64; 3]]) -> (f64, f64) {
        let [inertia, external] = self.vertex_sums(p);
        (inertia / (2.0 * self.delta_t * self.delta_t), -external)
    }

    /// `[Σᵢ mᵢ (pᵢ − p⁰ᵢ)·((pᵢ − ŷᵢ) + (p⁰ᵢ − ŷᵢ)), Σᵢ (pᵢ − p⁰ᵢ)·fᵢ]`,
    /// the vertices' part of `E(p) − E(p⁰)` before its constant factors.
    /// On a CPU with AVX2 (checked at run time) four vertices at a time
    /// ([`simd::energy`](super::simd::energy)), the rest as
    /// [`StepEnergy::vertex_sums_portable`]; the two agree to rounding.
    ///
    /// # Panics
    /// When `p` does not have one row per vertex.
    pub fn vertex_sums(&self, p: &[[f64; 3]]) -> [f64; 2] {
        assert_eq!(p.len(), self.start.len());
        let vertices = Vertices {
            start: self.start,
            inertial_target: self.inertial_target,
            f_ext: self.f_ext,
            m: self.m,
        };
        let (head, done) = vertex_sums_four_at_a_time(&vertices, p);
        if done == 0 {
            return self.vertex_sums_portable(p, 0);
        }
        let tail = self.vertex_sums_portable(p, done);
        [head[0] + tail[0], head[1] + tail[1]]
    }

    /// [`StepEnergy::vertex_sums`] one vertex at a time, from vertex
    /// `first` on (each sum split between even and odd vertices, so that
    /// the additions overlap).
    ///
    /// # Panics
    /// When `p` does not have one row per vertex.
    pub fn vertex_sums_portable(&self, p: &[[f64; 3]], first: usize) -> [f64; 2] {
        assert_eq!(p.len(), self.start.len());
        let (mut inertia, mut external) = ([0.0; 2], [0.0; 2]);
        let pairs = p[first..]
            .chunks(2)
            .zip(self.start[first..].chunks(2))
            .zip(self.inertial_target[first..].chunks(2))
            .zip(self.f_ext[first..].chunks(2).zip(self.m[first..].chunks(2)));
        for (((p, p0), y), (f, m)) in pairs {
            for lane in 0..p.len() {
                let moved = difference(p[lane], p0[lane]);
                let (here, start) = (difference(p[lane], y[lane]), difference(p0[lane], y[lane]));
                inertia[lane] += m[lane] * dot(moved, sum3(here, start));
                external[lane] += dot(moved, f[lane]);
            }
        }
        [inertia[0] + inertia[1], external[0] + external[1]]
    }

    /// `½ w Σ_c (p_c − p⁰_c)·((p_c − t_c) + (p⁰_c − t_c))`.
    fn pin_change(&self, p: &[[f64; 3]]) -> f64 {
        let mut sum = 0.0;
        for (&c, &t) in self.pinned.iter().zip(self.pin_targets) {
            let (pc, p0) = (p[c], self.start[c]);
            sum += dot(
                difference(pc, p0),
                sum3(difference(pc, t), difference(p0, t)),
            );
        }
        0.5 * self.w * sum
    }

    /// How far rounding alone moves a computed `E(p) − E(p⁰)` for `p` near
    /// `p⁰`: about
    ///
    /// ```text
    /// η = ε k √( Σₑ (l⁰ₑ (l⁰ₑ − rₑ))² )
    /// ```
    ///
    /// Each term's change is a small difference times a sum. The
    /// differences of nearby positions, `p − p⁰` and `p − t`, are exact
    /// (Sterbenz's lemma), so the inertia, force and pin terms round only
    /// relative to their own small changes. The lengths are not: each `l`
    /// carries the rounding `ε l` of its square root, which a spring's term
    /// turns into energy at the rate of its force `k |l − r|`. These
    /// roundings are independent, so they add like a random walk, as a root
    /// of the sum of squares. On a 32 × 32 cloth at rest (step 30 of
    /// `grid-32`) `η` is `2.2·10⁻¹³`, and the energies of plain's
    /// iterates 20–200 spread over `2.3·10⁻¹³` (`masssprings converge
    /// grid-32.json --step 30 --methods plain --iterations 200 --csv F`
    /// prints `η` and writes them). A decrease below `η` cannot be told
    /// from rounding. One pass over the springs, without a square root per
    /// spring.
    ///
    /// # Panics
    /// When the network's arrays do not match.
    pub fn rounding(&self) -> f64 {
        let squares: f64 = self
            .start_lengths
            .iter()
            .zip(self.r)
            .map(|(&l, &r)| (l * (l - r)).powi(2))
            .sum();
        f64::EPSILON * self.k * squares.sqrt()
    }

    /// `g = ∇E(p)`, one row per vertex.
    ///
    /// # Panics
    /// When `p` or `g` does not have one row per vertex.
    pub fn gradient(&self, p: &[[f64; 3]], g: &mut [[f64; 3]]) {
        self.gradient_and_spring_sum(p, g, None);
    }

    /// `E(p) − E(p⁰)` and `g = ∇E(p)` together: the springs' part of both
    /// comes from one pass, which a line search that needs both at each
    /// trial point (L-BFGS) pays once instead of twice.
    ///
    /// # Panics
    /// When `p` or `g` does not have one row per vertex.
    pub fn change_and_gradient(&self, p: &[[f64; 3]], g: &mut [[f64; 3]]) -> EnergyChange {
        let spring_sum = self.gradient_and_spring_sum(p, g, None);
        self.change_given_springs(p, spring_sum)
    }

    /// The local step at `p`, kept as what the global step reads of it,
    /// `a_t_d = Aᵀd` (the `dₑ` bit for bit
    /// [`project_springs`](super::local_step::project_springs)'s, summed
    /// as [`incidence_transpose_mul_points`](super::signed_incidence::incidence_transpose_mul_points)
    /// sums them), and `E(p) − E(p⁰)`, with `g = ∇E(p)` too when `g` is
    /// given: a method that tests every iterate against a tolerance gets
    /// the gradient from the pass over the springs that its next global
    /// step needs anyway.
    ///
    /// # Panics
    /// When `p`, `a_t_d` or `g` does not have one row per vertex.
    pub fn change_with_local_step(
        &self,
        p: &[[f64; 3]],
        a_t_d: &mut [[f64; 3]],
        g: Option<&mut [[f64; 3]]>,
    ) -> EnergyChange {
        a_t_d.fill([0.0; 3]);
        let spring_sum = match g {
            Some(g) => self.gradient_and_spring_sum(p, g, Some(a_t_d)),
            None => self.springs().measure(
                p,
                Outputs {
                    transpose: Some(a_t_d),
                    ..Outputs::default()
                },
            ),
        };
        self.change_given_springs(p, spring_sum)
    }

    /// `g = ∇E(p)` (and the local step's `Aᵀd` added into `a_t_d`, when
    /// asked), returning the spring pass's `S` on the way.
    fn gradient_and_spring_sum(
        &self,
        p: &[[f64; 3]],
        g: &mut [[f64; 3]],
        a_t_d: Option<&mut [[f64; 3]]>,
    ) -> f64 {
        assert!(p.len() == self.start.len() && g.len() == p.len());
        let inverse_dt2 = 1.0 / (self.delta_t * self.delta_t);
        for (((gi, pi), y), (&mi, f)) in g
            .iter_mut()
            .zip(p)
            .zip(self.inertial_target)
            .zip(self.m.iter().zip(self.f_ext))
        {
            *gi = std::array::from_fn(|c| mi * (pi[c] - y[c]) * inverse_dt2 - f[c]);
        }
        let gradient = Some(&mut *g);
        let outputs = Outputs {
            d: None,
            gradient,
            transpose: a_t_d,
        };
        let spring_sum = self.springs().measure(p, outputs);
        for (&c, t) in self.pinned.iter().zip(self.pin_targets) {
            g[c] = std::array::from_fn(|x| g[c][x] + self.w * (p[c][x] - t[x]));
        }
        spring_sum
    }
}

/// `√(Σᵢ ‖gᵢ‖²)` over the vertices that are not pinned (`pinned[i]` false):
/// the norm the stopping rule measures (at a pin the gradient is the
/// penalty's, `w` times a drift, and says nothing about the cloth).
pub fn free_norm(g: &[[f64; 3]], pinned: &[bool]) -> f64 {
    g.iter()
        .zip(pinned)
        .filter(|(_, &is_pinned)| !is_pinned)
        .map(|(gi, _)| dot(*gi, *gi))
        .sum::<f64>()
        .sqrt()
}

/// `a − b`.
pub(crate) fn difference(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn sum3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
