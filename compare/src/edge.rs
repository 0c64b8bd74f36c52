//! The edges a coverage allowance is measured from, and the distance rule.

/// A straight edge in pixel units, y down, with pixel `(i, j)` covering `[i, i+1) × [j,
/// j+1)` so that its centre is `(i + ½, j + ½)` (fpgfx's convention, docs/requirements.md
/// §0). Plain numbers rather than a raster command, so that any caller (the C library,
/// a testbench's own geometry) can state where its primitives' boundaries are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Edge {
    /// Start, horizontal.
    pub x0: f64,
    /// Start, vertical.
    pub y0: f64,
    /// End, horizontal.
    pub x1: f64,
    /// End, vertical.
    pub y1: f64,
}

impl Edge {
    /// The edge from `(x0, y0)` to `(x1, y1)`.
    pub const fn new(x0: f64, y0: f64, x1: f64, y1: f64) -> Self {
        Edge { x0, y0, x1, y1 }
    }

    /// Squared Euclidean distance from `(x, y)` to the nearest point of the segment (not
    /// of its infinite line: an edge ends at its vertices). Squared so that the rule
    /// `distance ≤ 2^-bits` is decided without a rounded square root: for axis-aligned
    /// edges on binary fractions it is exact, which the boundary tests rely on.
    pub fn distance_squared(&self, x: f64, y: f64) -> f64 {
        let (dx, dy) = (self.x1 - self.x0, self.y1 - self.y0);
        let (px, py) = (x - self.x0, y - self.y0);
        let len2 = dx * dx + dy * dy;
        let t = if len2 > 0.0 {
            ((px * dx + py * dy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (ex, ey) = (px - t * dx, py - t * dy);
        ex * ex + ey * ey
    }
}

/// Whether the centre of pixel `(i, j)` lies within `radius` of one of `edges`
/// (closed: exactly `radius` away counts as near).
pub(crate) fn centre_near(edges: &[Edge], radius: f64, i: u32, j: u32) -> bool {
    let (x, y) = (f64::from(i) + 0.5, f64::from(j) + 0.5);
    let r2 = radius * radius;
    edges.iter().any(|e| {
        // The bounding-box reject keeps long edge lists cheap: most edges are far away.
        x >= e.x0.min(e.x1) - radius
            && x <= e.x0.max(e.x1) + radius
            && y >= e.y0.min(e.y1) - radius
            && y <= e.y0.max(e.y1) + radius
            && e.distance_squared(x, y) <= r2
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_is_to_the_segment_not_its_line() {
        let e = Edge::new(0.0, 0.0, 4.0, 0.0);
        assert_eq!(e.distance_squared(2.0, 3.0), 9.0);
        // Beyond the end: to the vertex, not to the extended line.
        assert_eq!(e.distance_squared(7.0, 4.0), 25.0);
        assert_eq!(e.distance_squared(-3.0, 0.0), 9.0);
        // A degenerate edge is a point.
        assert_eq!(
            Edge::new(1.0, 1.0, 1.0, 1.0).distance_squared(4.0, 5.0),
            25.0
        );
    }

    #[test]
    fn near_is_closed_and_box_reject_agrees() {
        let e = [Edge::new(0.0, 3.0, 10.0, 3.0)];
        // Centre (2.5, 2.5) is 0.5 from y = 3.
        assert!(centre_near(&e, 0.5, 2, 2));
        assert!(!centre_near(&e, 0.4999, 2, 2));
        // Diagonal edge: the box reject must not refuse what the distance accepts.
        let d = [Edge::new(0.0, 0.0, 10.0, 10.0)];
        assert!(centre_near(&d, 0.01, 4, 4));
        assert!(!centre_near(&d, 0.7, 4, 5));
        assert!(centre_near(&d, 0.71, 4, 5));
    }
}
