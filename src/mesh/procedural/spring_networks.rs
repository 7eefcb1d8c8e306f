//! The three small teaching scenes made of springs only (2-corner faces, a
//! uniform mass `m = 1`): the first things to get working, with the dense
//! solver, before any cloth.
//!
//! * `single-spring-horizontal`: one spring of length 1 along x, its left end
//!   pinned. Under gravity it swings down and bounces: if this is wrong,
//!   nothing else will be right.
//! * `horizontal-chain`: 11 vertices 0.1 apart along x, both ends pinned. It
//!   sags into a catenary.
//! * `net`: a 9 × 9 square net of springs lying flat in the horizontal plane,
//!   pinned at its 4 corners and the middles of its 4 sides; it sags into a
//!   hammock.
//!
//! They play the roles of the assignment's scenes of the same names (which
//! are not copied: its net, for one, is a hexagon of triangles).
//!
//! Cost: a few hundred numbers each.

use super::{example_description, GeneratedMesh, GeneratedScene};

/// One spring from `(0, 0, 0)` (pinned) to `(1, 0, 0)`; `k = 500`, `m = 1`.
pub fn single_spring_horizontal() -> GeneratedScene {
    spring_network(
        "single-spring-horizontal",
        "one horizontal spring, its left end pinned: it swings and bounces",
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
        vec![[0, 1]],
        vec![0],
        500.0,
    )
}

/// 11 vertices from `x = 0` to `x = 1`, 10 springs, both ends pinned;
/// `k = 500`, `m = 1`.
pub fn horizontal_chain() -> GeneratedScene {
    let count = 11;
    let vertices = (0..count)
        .map(|i| [i as f64 / (count - 1) as f64, 0.0, 0.0])
        .collect();
    let springs = (0..count - 1).map(|i| [i, i + 1]).collect();
    spring_network(
        "horizontal-chain",
        "a chain of 11 masses pinned at both ends: it hangs as a catenary",
        vertices,
        springs,
        vec![0, count - 1],
        500.0,
    )
}

/// A 9 × 9 net in the plane `y = 0`, 1.2 wide, springs between neighbours
/// along x and along z (144 springs), pinned at the corners and the middles
/// of the sides; `k = 1000`, `m = 1`.
pub fn net() -> GeneratedScene {
    let side = 9;
    let spacing = 1.2 / (side - 1) as f64;
    let vertex = |i: usize, j: usize| j * side + i;
    let mut vertices = Vec::with_capacity(side * side);
    for j in 0..side {
        for i in 0..side {
            vertices.push([i as f64 * spacing, 0.0, j as f64 * spacing]);
        }
    }
    let mut springs = Vec::new();
    for j in 0..side {
        for i in 0..side {
            if i + 1 < side {
                springs.push([vertex(i, j), vertex(i + 1, j)]);
            }
            if j + 1 < side {
                springs.push([vertex(i, j), vertex(i, j + 1)]);
            }
        }
    }
    let (first, middle, last) = (0, side / 2, side - 1);
    let pinned = [
        (first, first),
        (middle, first),
        (last, first),
        (first, middle),
        (last, middle),
        (first, last),
        (middle, last),
        (last, last),
    ]
    .map(|(i, j)| vertex(i, j))
    .to_vec();
    spring_network(
        "net",
        "a square net of springs held at 8 points of its border: it sags like a hammock",
        vertices,
        springs,
        pinned,
        1000.0,
    )
}

fn spring_network(
    name: &str,
    description: &str,
    vertices: Vec<[f64; 3]>,
    springs: Vec<[usize; 2]>,
    pinned: Vec<usize>,
    k: f64,
) -> GeneratedScene {
    GeneratedScene {
        name: name.to_string(),
        description: Some(example_description(name, description)),
        mesh: GeneratedMesh {
            vertices,
            corners_per_face: 2,
            faces: springs.into_iter().flatten().collect(),
            ..GeneratedMesh::default()
        },
        k,
        uniform_mass: Some(1.0),
        pinned,
        texture: None,
    }
}
