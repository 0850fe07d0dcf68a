//! Gait metrics, allocation-free over slices of poses: inter-limb distances (the paper's
//! Eqs 18-20) and statistics of a joint's path in each anatomical plane.

use crate::{BilateralPose, Joint, Real, Side, Vec3};

/// Distances between the two legs' points in one frame (metres).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Distances<T> {
    /// Knee centre to knee centre (Eq 18).
    pub knee: T,
    /// Ankle centre to ankle centre (Eq 19).
    pub ankle: T,
    /// Toe tip to toe tip (Eq 20).
    pub toe: T,
}

impl<T: Real> Distances<T> {
    /// `[knee, ankle, toe]`.
    pub fn to_array(self) -> [T; 3] {
        [self.knee, self.ankle, self.toe]
    }
}

/// Euclidean distances knee-knee, ankle-ankle and toe-toe (the hip-hip distance is constant by
/// construction in the stick models).
pub fn distances<T: Real>(pose: &BilateralPose<T>) -> Distances<T> {
    let d = |j| Vec3::distance(pose.point(Side::Right, j), pose.point(Side::Left, j));
    Distances {
        knee: d(Joint::Knee),
        ankle: d(Joint::Ankle),
        toe: d(Joint::Toe),
    }
}

/// An anatomical plane and the 2-D coordinates a point has in it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Plane {
    /// Side view, `(x, y)`: forward to the right of the page, up.
    Sagittal,
    /// Front view, `(z, y)`: the subject's right to the right of the page, up.
    Frontal,
    /// Top view, `(x, z)`: forward, right.
    Transverse,
}

impl Plane {
    /// The three planes.
    pub const ALL: [Plane; 3] = [Plane::Sagittal, Plane::Frontal, Plane::Transverse];
    /// The point's two in-plane coordinates, in the order of [`axes`](Self::axes).
    pub fn project<T: Real>(self, v: Vec3<T>) -> [T; 2] {
        match self {
            Plane::Sagittal => [v.x, v.y],
            Plane::Frontal => [v.z, v.y],
            Plane::Transverse => [v.x, v.z],
        }
    }
    /// Names of the two in-plane axes.
    pub fn axes(self) -> (&'static str, &'static str) {
        match self {
            Plane::Sagittal => ("x", "y"),
            Plane::Frontal => ("z", "y"),
            Plane::Transverse => ("x", "z"),
        }
    }
    /// Lower-case name: `"sagittal"`, `"frontal"`, `"transverse"`.
    pub fn name(self) -> &'static str {
        match self {
            Plane::Sagittal => "sagittal",
            Plane::Frontal => "frontal",
            Plane::Transverse => "transverse",
        }
    }
}

/// Statistics of a 2-D path (a joint's trajectory projected on a plane), in metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathStats<T> {
    /// Number of points.
    pub n: usize,
    /// Per-axis minimum.
    pub min: [T; 2],
    /// Per-axis maximum.
    pub max: [T; 2],
    /// Per-axis mean of the points.
    pub mean: [T; 2],
    /// Per-axis range (`max - min`).
    pub range: [T; 2],
    /// Centroid of the closed polygon the path encloses (last point joined to the first) when
    /// the path winds one way; the mean of the points when it does not (a figure of eight,
    /// whose lobes cancel, or a path that retraces a line), where a polygon centroid would be
    /// meaningless and can even fall outside the path.
    pub centroid: [T; 2],
    /// Net area enclosed by the closed path (shoelace formula, absolute value), square metres.
    /// For a figure of eight the lobes' areas subtract.
    pub area: T,
    /// Whether the path winds one way (net area at least half the area swept from the first
    /// point), so that `centroid` is the polygon's centroid rather than the mean.
    pub winds_one_way: bool,
}

impl<T: Real> PathStats<T> {
    /// Statistics of the points in order, in one pass; `None` for no points.
    pub fn from_points(points: impl IntoIterator<Item = [T; 2]>) -> Option<Self> {
        let mut it = points.into_iter();
        let first = it.next()?;
        let (mut min, mut max, mut sum) = (first, first, first);
        let mut n = 1usize;
        // Shoelace sums relative to the first point (better conditioned; the closing edge back to
        // the first point then contributes nothing).
        let (mut a2, mut swept2, mut cx, mut cy) = (T::ZERO, T::ZERO, T::ZERO, T::ZERO);
        let mut prev = [T::ZERO, T::ZERO];
        for p in it {
            for k in 0..2 {
                min[k] = min[k].min(p[k]);
                max[k] = max[k].max(p[k]);
                sum[k] += p[k];
            }
            let cur = [p[0] - first[0], p[1] - first[1]];
            let cross = prev[0] * cur[1] - cur[0] * prev[1];
            a2 += cross;
            swept2 += cross.abs();
            cx += (prev[0] + cur[0]) * cross;
            cy += (prev[1] + cur[1]) * cross;
            prev = cur;
            n += 1;
        }
        let count = T::from_f64(n as f64);
        let mean = [sum[0] / count, sum[1] / count];
        let range = [max[0] - min[0], max[1] - min[1]];
        let area = (a2 * T::HALF).abs();
        // Polygon centroid only when the fan of triangles from the first point mostly has one
        // orientation, and never outside the bounding box (rounding on slivers).
        let k = T::ONE / (T::from_f64(3.0) * a2);
        let polygon = [first[0] + cx * k, first[1] + cy * k];
        let inside = (0..2).all(|i| polygon[i] >= min[i] && polygon[i] <= max[i]);
        let winds_one_way = area > T::ZERO && a2.abs() >= T::HALF * swept2 && inside;
        let centroid = if winds_one_way { polygon } else { mean };
        Some(Self {
            n,
            min,
            max,
            mean,
            range,
            centroid,
            area,
            winds_one_way,
        })
    }
}

/// Statistics of one joint's path through `frames` on `plane`; `None` for no frames.
pub fn path_stats<T: Real>(
    frames: &[BilateralPose<T>],
    side: Side,
    joint: Joint,
    plane: Plane,
) -> Option<PathStats<T>> {
    PathStats::from_points(frames.iter().map(|f| plane.project(f.point(side, joint))))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_square_has_area_one_and_centroid_half() {
        for pts in [
            [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]],
        ] {
            let s = PathStats::<f64>::from_points(pts).unwrap();
            assert!((s.area - 1.0).abs() < 1e-15);
            assert_eq!(s.centroid, [0.5, 0.5]);
            assert_eq!(s.range, [1.0, 1.0]);
            assert_eq!(s.n, 4);
            assert!(s.winds_one_way);
        }
    }

    #[test]
    fn triangle_centroid_differs_from_vertex_mean_when_points_cluster() {
        // Extra collinear points on one edge move the mean but not the polygon centroid.
        let s = PathStats::<f64>::from_points([
            [0.0, 0.0],
            [1.0, 0.0],
            [2.0, 0.0],
            [3.0, 0.0],
            [0.0, 3.0],
        ])
        .unwrap();
        assert!((s.area - 4.5).abs() < 1e-12);
        assert!((s.centroid[0] - 1.0).abs() < 1e-12 && (s.centroid[1] - 1.0).abs() < 1e-12);
        assert!((s.mean[0] - 1.2).abs() < 1e-12);
    }

    #[test]
    fn figure_of_eight_uses_the_mean_not_a_runaway_centroid() {
        // Two lobes of nearly equal area, opposite orientation (like a hip path in gait).
        let pts = [
            [0.0, 0.0],
            [1.0, 1.0],
            [2.0, 0.0],
            [1.0, -1.0],
            [0.0, 0.0],
            [-1.0, 1.0],
            [-2.0, 0.0],
            [-1.01, -1.0],
        ];
        let s = PathStats::<f64>::from_points(pts).unwrap();
        assert!(!s.winds_one_way);
        assert_eq!(s.centroid, s.mean);
        assert!(s.area < 0.05, "net area {}", s.area);
    }

    #[test]
    fn degenerate_path_falls_back_to_mean_and_empty_is_none() {
        let s = PathStats::<f64>::from_points([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [1.0, 1.0]])
            .unwrap();
        assert_eq!(s.area, 0.0);
        assert_eq!(s.centroid, s.mean);
        assert!(PathStats::<f64>::from_points([]).is_none());
    }
}
