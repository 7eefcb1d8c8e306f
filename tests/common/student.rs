//! A student's solution of the handout, written here from the handout
//! alone and apart from the crate's functions, to feed `trace --compare`:
//! the scene's inputs (`V`, `E`, `m`, `b`, `k`, as the assignment's
//! `read_json` gives them) in, every file of a trace out, in the student's
//! own choices:
//!
//! * the springs in another order (the last first) and every other one
//!   reversed;
//! * dense matrices (nalgebra), `Q` ordered by reversing the vertices and
//!   factored by nalgebra's Cholesky; its own Matrix Market writer;
//! * step K from our `U_prev.mtx` and `U_cur.mtx`, or from its own steps
//!   from rest;
//! * any mistake of the gallery, each written here again by its name, from
//!   the gallery's line (a mistake unknown here panics: add it).
//!

use masssprings::matrix_market::{read, MatrixMarket};
use masssprings::mesh::Scene;
use nalgebra::{Cholesky, DMatrix};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

const DT: f64 = 1.0 / 30.0;
const W: f64 = 1e10;

/// Where step K starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Start<'a> {
    /// From our `U_prev.mtx` and `U_cur.mtx` in this folder.
    Ours(&'a Path),
    /// From the student's own K − 1 steps from rest.
    OwnRun,
}

/// The student: the scene's inputs and one mistake (or none).
pub struct Student<'a> {
    scene: &'a Scene,
    mistake: Option<&'a str>,
    /// Their springs: `(i, j)` is `+1` at `i`, `−1` at `j` in their `A`.
    springs: Vec<[usize; 2]>,
    /// Writes into `r.mtx` the rest lengths the step uses (which
    /// `r-from-deformed` measures on `U_cur`), not the precomputation's.
    pub step_r_written: bool,
}

/// What the precomputation makes.
struct Pre {
    r: Vec<f64>,
    m: Vec<f64>,
    pins: Vec<usize>,
    a: DMatrix<f64>,
    q: DMatrix<f64>,
    /// `perm[new] = old`, and the factor of `P Q Pᵀ`.
    perm: Vec<usize>,
    factor: Cholesky<f64, nalgebra::Dyn>,
}

impl<'a> Student<'a> {
    pub fn new(scene: &'a Scene, mistake: Option<&'a str>) -> Student<'a> {
        let springs = scene
            .springs
            .iter()
            .rev()
            .enumerate()
            .map(|(e, &[i, j])| if e % 2 == 1 { [j, i] } else { [i, j] })
            .collect();
        Student {
            scene,
            mistake,
            springs,
            step_r_written: false,
        }
    }

    fn is(&self, name: &str) -> bool {
        self.mistake == Some(name)
    }

    /// Writes every file of step `step` with `iterations` iterations into `out`.
    pub fn write(&self, start: Start, step: usize, iterations: usize, out: &Path) {
        std::fs::create_dir_all(out).unwrap();
        let pre = self.precompute();
        let a = match self.is("a-transposed") {
            true => pre.a.transpose(),
            false => pre.a.clone(),
        };
        write_sparse(&out.join("A.mtx"), &a);
        write_dense(
            &out.join("r.mtx"),
            &DMatrix::from_column_slice(pre.r.len(), 1, &pre.r),
        );
        write_sparse(
            &out.join("M.mtx"),
            &DMatrix::from_diagonal(&pre.m.clone().into()),
        );
        write_sparse(&out.join("C.mtx"), &selection(self.n(), &pre.pins));
        write_sparse(&out.join("Q.mtx"), &pre.q);
        let n = self.n();
        let p = DMatrix::from_fn(n, n, |new, old| f64::from(pre.perm[new] == old));
        write_sparse(&out.join("P.mtx"), &p);
        write_sparse(&out.join("L.mtx"), &pre.factor.l());
        let (u_prev, u_cur) = match start {
            Start::Ours(ours) => (
                read_points(&ours.join("U_prev.mtx")),
                read_points(&ours.join("U_cur.mtx")),
            ),
            Start::OwnRun => self.own_run(&pre, step),
        };
        write_dense(&out.join("U_prev.mtx"), &u_prev);
        write_dense(&out.join("U_cur.mtx"), &u_cur);
        if self.step_r_written && self.is("r-from-deformed") {
            let r = self
                .springs
                .iter()
                .map(|&[i, j]| (u_cur.row(i) - u_cur.row(j)).norm());
            let r: Vec<f64> = r.collect();
            write_dense(
                &out.join("r.mtx"),
                &DMatrix::from_column_slice(r.len(), 1, &r),
            );
        }
        let y = self.y(&pre, &u_prev, &u_cur);
        write_dense(&out.join("y.mtx"), &y);
        let mut p = u_cur.clone();
        for k in 1..=iterations {
            let d = self.d(&pre, &p, &u_cur);
            let b = self.b(&pre, &d, &y);
            p = solve(&pre, &b);
            for (name, value) in [("d", &d), ("b", &b), ("p", &p)] {
                write_dense(&out.join(format!("{name}_{k}.mtx")), value);
            }
        }
    }

    fn n(&self) -> usize {
        self.scene.vertices.len()
    }

    fn v(&self) -> DMatrix<f64> {
        DMatrix::from_fn(self.n(), 3, |i, c| self.scene.vertices[i][c])
    }

    fn precompute(&self) -> Pre {
        let (n, v) = (self.n(), self.v());
        let r: Vec<f64> = self
            .springs
            .iter()
            .map(|&[i, j]| (v.row(i) - v.row(j)).norm())
            .collect();
        let mut m = self.scene.masses.clone();
        if self.is("mass-doubled") {
            m.iter_mut().for_each(|x| *x *= 2.0);
        } else if self.is("uniform-masses") {
            m.iter_mut().for_each(|x| *x = 1.0);
        } else if self.is("masses-from-lengths") {
            m = vec![0.0; n];
            for (&[i, j], &length) in self.springs.iter().zip(&r) {
                m[i] += 0.5 * length;
                m[j] += 0.5 * length;
            }
        }
        let pins: Vec<usize> = match self.is("pins-one-based") {
            true => self.scene.pinned.iter().map(|&i| i + 1).collect(),
            false => self.scene.pinned.clone(),
        };
        let mut a = DMatrix::zeros(self.springs.len(), n);
        for (e, &[i, j]) in self.springs.iter().enumerate() {
            a[(e, i)] = 1.0;
            a[(e, j)] = if self.is("a-sign") { 1.0 } else { -1.0 };
        }
        let q = self.q(&a, &m, &pins);
        let perm: Vec<usize> = (0..n).rev().collect();
        let pqp = DMatrix::from_fn(n, n, |i, j| q[(perm[i], perm[j])]);
        let factor = Cholesky::new(pqp).expect("Q is positive definite");
        Pre {
            r,
            m,
            pins,
            a,
            q,
            perm,
            factor,
        }
    }

    fn q(&self, a: &DMatrix<f64>, m: &[f64], pins: &[usize]) -> DMatrix<f64> {
        let k = self.scene.k;
        let mass = DMatrix::from_diagonal(&nalgebra::DVector::from_column_slice(m));
        let c = selection(self.n(), pins);
        let mut springs = a.transpose() * a * k;
        if self.is("springs-doubled-in-q") {
            springs *= 2.0; // no mistake of the gallery: for the hints
        }
        let inertia = match self.mistake {
            Some("dt-not-squared") => &mass / DT,
            Some("k-on-inertia") => &mass * (k / (DT * DT)),
            Some("inertia-sign") => -&mass / (DT * DT),
            Some("inertia-half-missing") => &mass * (2.0 / (DT * DT)),
            _ => &mass / (DT * DT),
        };
        let weight = match self.mistake {
            Some("pins-not-in-q") => 0.0,
            Some("pins-without-w") => 1.0,
            _ => W,
        };
        springs + inertia + c.transpose() * c * weight
    }

    /// `y = M (2 U_cur − U_prev)/Δt² + f_ext`, or the mistake's.
    fn y(&self, pre: &Pre, u_prev: &DMatrix<f64>, u_cur: &DMatrix<f64>) -> DMatrix<f64> {
        let n = self.n();
        let mut f = DMatrix::from_fn(n, 3, |_, c| if c == 1 { -9.8 } else { 0.0 });
        let mut inertia = u_cur * 2.0 - u_prev;
        let mut over = 1.0 / (DT * DT);
        match self.mistake {
            Some("gravity-sign") => f = -f,
            Some("gravity-times-mass") => f = DMatrix::from_fn(n, 3, |i, c| pre.m[i] * f[(i, c)]),
            Some("dt-not-squared") => over = 1.0 / DT,
            Some("dt-squared-missing-in-y") => over = 1.0,
            Some("prev-cur-swapped") => inertia = u_prev * 2.0 - u_cur,
            Some("inertia-minus-prev") => inertia = u_cur * 2.0 + u_prev,
            Some("inertia-sign") => over = -over,
            Some("inertia-half-missing") => over *= 2.0,
            _ => {}
        }
        DMatrix::from_fn(n, 3, |i, c| pre.m[i] * inertia[(i, c)] * over + f[(i, c)])
    }

    /// The local step from `p`, or the mistake's.
    fn d(&self, pre: &Pre, p: &DMatrix<f64>, u_cur: &DMatrix<f64>) -> DMatrix<f64> {
        let from = if self.is("d-from-u-cur") { u_cur } else { p };
        DMatrix::from_fn(self.springs.len(), 3, |e, c| {
            let [i, j] = self.springs[e];
            let spring = from.row(i) - from.row(j);
            let rest = match self.is("r-from-deformed") {
                true => (u_cur.row(i) - u_cur.row(j)).norm(),
                false => pre.r[e],
            };
            match self.mistake {
                Some("d-not-normalised") => rest * spring[c],
                Some("d-against-a") => -rest * spring[c] / spring.norm(),
                _ => rest * spring[c] / spring.norm(),
            }
        })
    }

    /// `b = k Aᵀd + y + w CᵀC V`, or the mistake's.
    fn b(&self, pre: &Pre, d: &DMatrix<f64>, y: &DMatrix<f64>) -> DMatrix<f64> {
        let c = selection(self.n(), &pre.pins);
        let pinned = c.transpose() * &c * self.v();
        let springs = pre.a.transpose() * d * self.scene.k;
        match self.mistake {
            Some("pins-not-in-b") => springs + y,
            Some("pins-without-w") => springs + y + pinned,
            Some("w-on-y") => springs + y * W + pinned,
            _ => springs + y + pinned * W,
        }
    }

    /// Step after step from rest, the loop written by the student.
    fn own_run(&self, pre: &Pre, step: usize) -> (DMatrix<f64>, DMatrix<f64>) {
        let (mut u_prev, mut u_cur) = (self.v(), self.v());
        for _ in 1..step {
            let y = self.y(pre, &u_prev, &u_cur);
            let mut p = u_cur.clone();
            for _ in 0..50 {
                let d = self.d(pre, &p, &u_cur);
                p = solve(pre, &self.b(pre, &d, &y));
            }
            if self.is("velocity-lost") {
                u_cur = p; // U_cur = U_next
                u_prev = u_cur.clone(); // U_prev = U_cur
            } else {
                u_prev = std::mem::replace(&mut u_cur, p);
            }
        }
        (u_prev, u_cur)
    }
}

/// `p = Q⁻¹ b` through the student's factor of `P Q Pᵀ`.
fn solve(pre: &Pre, b: &DMatrix<f64>) -> DMatrix<f64> {
    let n = b.nrows();
    let pb = DMatrix::from_fn(n, 3, |new, c| b[(pre.perm[new], c)]);
    let x = pre.factor.solve(&pb);
    let mut p = DMatrix::zeros(n, 3);
    for new in 0..n {
        for c in 0..3 {
            p[(pre.perm[new], c)] = x[(new, c)];
        }
    }
    p
}

/// `C`: row `k` has a 1 in column `pins[k]`.
fn selection(n: usize, pins: &[usize]) -> DMatrix<f64> {
    DMatrix::from_fn(pins.len(), n, |k, j| f64::from(pins[k] == j))
}

/// A coordinate file of the nonzeros of `a`.
pub fn write_sparse(path: &Path, a: &DMatrix<f64>) {
    let mut entries = String::new();
    let mut count = 0;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            if a[(i, j)] != 0.0 {
                let _ = writeln!(entries, "{} {} {:.16e}", i + 1, j + 1, a[(i, j)]);
                count += 1;
            }
        }
    }
    let header = format!(
        "%%MatrixMarket matrix coordinate real general\n{} {} {count}\n",
        a.nrows(),
        a.ncols()
    );
    std::fs::write(path, header + &entries).unwrap();
}

/// An array file, column by column.
pub fn write_dense(path: &Path, a: &DMatrix<f64>) {
    let mut text = format!(
        "%%MatrixMarket matrix array real general\n{} {}\n",
        a.nrows(),
        a.ncols()
    );
    for x in a.iter() {
        let _ = writeln!(text, "{x:.16e}");
    }
    std::fs::write(path, text).unwrap();
}

/// Our `n × 3` array file.
fn read_points(path: &Path) -> DMatrix<f64> {
    match read(path).unwrap() {
        MatrixMarket::Dense(a) => DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)]),
        MatrixMarket::Sparse(_) => panic!("{} is an array file", path.display()),
    }
}

/// Writes a small cloth of the tests' own into `folder`, `cloth.obj` and
/// `cloth.json` (6 × 5 vertices, Voronoi masses, one edge pinned, not the
/// last vertex: every mistake of the gallery shows on it), and returns the
/// JSON's path.
pub fn small_cloth(folder: &Path) -> PathBuf {
    let (columns, rows) = (6, 5);
    let mut obj = String::new();
    for j in 0..rows {
        for i in 0..columns {
            let _ = writeln!(obj, "v {} {} 0", 0.2 * i as f64, 0.8 - 0.2 * j as f64);
        }
    }
    let vertex = |i: usize, j: usize| j * columns + i + 1;
    for j in 0..rows - 1 {
        for i in 0..columns - 1 {
            let corners = [
                vertex(i, j),
                vertex(i, j + 1),
                vertex(i + 1, j + 1),
                vertex(i + 1, j),
            ];
            let _ = writeln!(
                obj,
                "f {} {} {} {}",
                corners[0], corners[1], corners[2], corners[3]
            );
        }
    }
    std::fs::write(folder.join("cloth.obj"), obj).unwrap();
    let pins: Vec<String> = (0..rows).map(|j| vertex(0, j).to_string()).collect();
    let json = format!(
        r#"{{"obj":"cloth.obj","k":10000,"b":[{}]}}"#,
        pins.join(",")
    );
    let path = folder.join("cloth.json");
    std::fs::write(&path, json).unwrap();
    path
}
