//! Best rigid alignment (rotation + translation, no scale) of two matched 2D point sets.
//!
//! Closed-form least squares in 2D (the planar case of Umeyama 1991 with unit scale):
//! centre both sets, the optimal angle is `atan2(Σ a×b, Σ a·b)`.

/// A 2D rotation by `angle` followed by a translation `(tx, ty)`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RigidTransform {
    /// Rotation, radians counter-clockwise.
    pub angle: f64,
    /// Translation east, metres.
    pub tx: f64,
    /// Translation north, metres.
    pub ty: f64,
}

impl RigidTransform {
    /// Applies the transform to `(x, y)`.
    #[must_use]
    pub fn apply(&self, (x, y): (f64, f64)) -> (f64, f64) {
        let (s, c) = self.angle.sin_cos();
        (c * x - s * y + self.tx, s * x + c * y + self.ty)
    }

    /// The transform that undoes this one: `inverse().apply(apply(p)) = p`.
    #[must_use]
    pub fn inverse(&self) -> Self {
        let (s, c) = self.angle.sin_cos();
        Self {
            angle: -self.angle,
            tx: -(c * self.tx + s * self.ty),
            ty: -(-s * self.tx + c * self.ty),
        }
    }

    /// The transform minimising `Σ |T(from_i) − to_i|²`; `None` for empty or unequal input.
    #[must_use]
    pub fn fit(from: &[(f64, f64)], to: &[(f64, f64)]) -> Option<Self> {
        if from.is_empty() || from.len() != to.len() {
            return None;
        }
        let n = from.len() as f64;
        let mean = |p: &[(f64, f64)]| {
            let (sx, sy) = p
                .iter()
                .fold((0.0, 0.0), |(sx, sy), &(x, y)| (sx + x, sy + y));
            (sx / n, sy / n)
        };
        let (fx, fy) = mean(from);
        let (gx, gy) = mean(to);
        let (mut dot, mut cross) = (0.0, 0.0);
        for (&(ax, ay), &(bx, by)) in from.iter().zip(to) {
            let (ax, ay, bx, by) = (ax - fx, ay - fy, bx - gx, by - gy);
            dot += ax * bx + ay * by;
            cross += ax * by - ay * bx;
        }
        let angle = cross.atan2(dot);
        let (s, c) = angle.sin_cos();
        Some(Self {
            angle,
            tx: gx - (c * fx - s * fy),
            ty: gy - (s * fx + c * fy),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_inverse_undoes_the_transform() {
        let t = RigidTransform {
            angle: 0.7,
            tx: 3.0,
            ty: -2.0,
        };
        let p = (1.5, -4.0);
        let (x, y) = t.inverse().apply(t.apply(p));
        assert!((x - p.0).abs() < 1e-12 && (y - p.1).abs() < 1e-12);
    }

    #[test]
    fn recovers_a_known_transform() {
        let t = RigidTransform {
            angle: 0.7,
            tx: 3.0,
            ty: -2.0,
        };
        let from = [(0.0, 0.0), (1.0, 0.0), (4.0, 2.0), (-1.0, 5.0)];
        let to: Vec<_> = from.iter().map(|&p| t.apply(p)).collect();
        let fit = RigidTransform::fit(&from, &to).expect("fit");
        assert!((fit.angle - 0.7).abs() < 1e-12);
        assert!((fit.tx - 3.0).abs() < 1e-12 && (fit.ty + 2.0).abs() < 1e-12);
        assert!(RigidTransform::fit(&[], &[]).is_none());
    }
}
