//! The axis-aligned box around a set of points.
//!
//! `min` and `max` are the smallest and largest coordinate along each axis.
//! The wind of the assignment measures x in units of the box's diagonal;
//! the renderer and the viewer frame the scene with its centre and corners.
//!
//! Cost `O(n)`.

/// An axis-aligned box that grows to contain points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundingBox {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl BoundingBox {
    /// The box that contains nothing yet (`min = +∞`, `max = −∞`).
    pub fn empty() -> BoundingBox {
        BoundingBox {
            min: [f64::INFINITY; 3],
            max: [f64::NEG_INFINITY; 3],
        }
    }

    /// The smallest box around `points`.
    pub fn of(points: &[[f64; 3]]) -> BoundingBox {
        let mut bounds = BoundingBox::empty();
        bounds.include(points);
        bounds
    }

    /// Grows the box to contain every point of `points`.
    pub fn include(&mut self, points: &[[f64; 3]]) {
        for p in points {
            for k in 0..3 {
                self.min[k] = self.min[k].min(p[k]);
                self.max[k] = self.max[k].max(p[k]);
            }
        }
    }

    /// The centre of the box.
    pub fn centre(&self) -> [f64; 3] {
        std::array::from_fn(|k| 0.5 * (self.min[k] + self.max[k]))
    }

    /// The eight corners.
    pub fn corners(&self) -> [[f64; 3]; 8] {
        std::array::from_fn(|i| {
            std::array::from_fn(|k| {
                if i >> k & 1 == 0 {
                    self.min[k]
                } else {
                    self.max[k]
                }
            })
        })
    }

    /// The length of the diagonal (0 for a single point, NaN for an empty box).
    pub fn diagonal(&self) -> f64 {
        (0..3)
            .map(|k| (self.max[k] - self.min[k]).powi(2))
            .sum::<f64>()
            .sqrt()
    }

    /// Half the diagonal.
    pub fn radius(&self) -> f64 {
        0.5 * self.diagonal()
    }
}
