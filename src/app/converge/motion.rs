//! `masssprings converge SCENE --steps S --accuracy assignment --motion
//! FILE.png`: how much the cloth moves when each step is solved by
//! plain-50, by the accuracy's settings, or to convergence.
//!
//! The three runs start from rest and each goes its own way. After every
//! step it records the kinetic energy of the step's velocities
//!
//! ```text
//! K = ½ Σᵢ mᵢ ‖(pᵢᵗ⁺¹ − pᵢᵗ) / Δt‖²
//! ```
//!
//! and the speed of the centroid. Fifty plain iterations leave most of each
//! step's energy decrease undone, and what they leave is the part along the
//! slow, soft modes (bending, swinging) where the motion is: the iterate
//! stays near `pᵗ`, so the step's velocity comes out too small. The
//! damping this adds is numerical, not physical, and it shrinks as the
//! step is solved better: the converged run keeps swinging after plain-50
//! has come to rest.

use super::request::Request;
use super::steps_plot::{StepPlot, StepSeries};
use crate::app::draw::plot::Scale;
use crate::app::error::AppError;
use crate::app::limits::precompute;
use masssprings::mesh::Scene;
use masssprings::sim::{SimulationOptions, Sparse, StepControl, StepMethod};
use std::path::Path;

/// The converged run's relative gradient at the end of each step.
const CONVERGED: f64 = 1e-6;

/// The converged run's most iterations a step.
const CONVERGED_ITERATIONS: usize = 500;

/// Runs plain-50, the request's accuracy and a converged solve for
/// `steps` steps each, and draws their kinetic energy and centroid speed.
pub fn run(request: &Request, scene: &Scene, steps: usize, path: &Path) -> Result<(), AppError> {
    let converged = StepControl {
        method: StepMethod::Newton,
        iterations: CONVERGED_ITERATIONS,
        tolerance: Some(CONVERGED),
        ..StepControl::default()
    };
    let runs = [
        ("plain-50", request.canonical.step),
        ("--accuracy assignment", request.control),
        ("converged (Newton, relative gradient 1e-6)", converged),
    ];
    let mut series: Vec<StepSeries> = Vec::new();
    for (name, control) in runs {
        series.push((name.to_string(), motion(request, scene, steps, control)?));
        eprintln!("converge --motion: {name} done");
    }
    for (name, points) in &series {
        let kinetic: Vec<f64> = points.iter().map(|p| p.1).collect();
        let mean = kinetic.iter().sum::<f64>() / kinetic.len().max(1) as f64;
        println!("{name}: mean kinetic energy {mean:.4e} J over {steps} steps");
    }
    let plot = StepPlot {
        title: format!(
            "{}: how much the cloth moves, by how each step is solved",
            scene.name
        ),
        caption: "each run from rest on its own; 50 plain iterations leave the slow modes' \
                  part of each step undone, which damps the motion"
            .into(),
        left: ("kinetic energy", "kinetic energy (J, log)", Scale::Log10),
        right: ("centroid", "speed of the centroid (m/s, log)", Scale::Log10),
        plain_50_line: false,
    };
    super::steps_plot::draw(path, &plot, &series)
}

/// `(step, kinetic energy, centroid speed)` after each of `steps` steps
/// solved by `control`.
fn motion(
    request: &Request,
    scene: &Scene,
    steps: usize,
    control: StepControl,
) -> Result<Vec<(f64, f64, f64)>, AppError> {
    let options = SimulationOptions {
        step: control,
        ..request.canonical
    };
    let mut simulation = precompute::<Sparse>(scene, &request.scene, options)?;
    let dt = options.delta_t;
    let mut points = Vec::with_capacity(steps);
    for step in 1..=steps {
        simulation
            .step()
            .map_err(|e| AppError::Failed(format!("step {step}: {e}")))?;
        let masses = &scene.masses;
        let (now, before) = (simulation.positions(), simulation.previous_positions());
        let (mut kinetic, mut momentum, mut mass) = (0.0, [0.0; 3], 0.0);
        for ((p, q), &m) in now.iter().zip(before).zip(masses) {
            let v: [f64; 3] = std::array::from_fn(|c| (p[c] - q[c]) / dt);
            kinetic += 0.5 * m * v.iter().map(|x| x * x).sum::<f64>();
            (0..3).for_each(|c| momentum[c] += m * v[c]);
            mass += m;
        }
        let speed = momentum.iter().map(|x| x * x).sum::<f64>().sqrt() / mass;
        points.push((step as f64, kinetic, speed));
    }
    Ok(points)
}
