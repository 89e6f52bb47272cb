//! Segment splitting: every surface's boundary edges cut into walls and connections at the
//! ends of the stretches other surfaces share with them (each connection kept once), and
//! the barriers' lines as walls of their level.

use super::config::TopologyConfig;
use super::connections::{MIN_PIECE, SharedEdges, surface_edges};
use crate::error::{Error, Result};
use crate::map::floor_plan::FloorPlan;

/// What a segment does to a walker crossing it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SegmentKind {
    /// A wall of `surface`, which lies to the left of the direction from `a` to `b`.
    Wall {
        /// The surface it bounds.
        surface: u32,
    },
    /// A passage between surfaces `a` (to the left of the direction from the segment's `a`
    /// to its `b`) and `b` (to the right).
    Connection {
        /// One surface.
        a: u32,
        /// The other surface.
        b: u32,
    },
    /// An extra wall for every surface of `level`.
    Barrier {
        /// The level it blocks.
        level: i32,
    },
}

/// A wall, connection or barrier segment, local metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// One end.
    pub a: [f64; 2],
    /// The other end.
    pub b: [f64; 2],
    /// Its role.
    pub kind: SegmentKind,
}

/// Walls and connections of every surface's boundary.
pub(super) fn boundary_segments(plan: &FloorPlan, config: &TopologyConfig) -> Vec<Segment> {
    let edges = surface_edges(plan);
    let mut shared_edges = SharedEdges::new(&edges, config);
    let mut segments = Vec::new();
    for (i, e) in edges.iter().enumerate() {
        // Parameter intervals along `e` shared with other surfaces' edges.
        let shared = shared_edges.of(i, plan, config);
        // Cut points: the edge's ends and the other edges' corners that fall on it, at
        // those corners' own coordinates (so the pieces meet the neighbours' edges exactly).
        let mut cuts: Vec<(f64, [f64; 2])> = vec![(0.0, e.a), (1.0, e.b)];
        cuts.extend(shared.iter().flat_map(|s| s.ends));
        cuts.sort_by(|a, b| a.0.total_cmp(&b.0));
        cuts.dedup_by(|a, b| (a.0 - b.0).abs() < 1e-12);
        let length = (e.b[0] - e.a[0]).hypot(e.b[1] - e.a[1]);
        for w in cuts.windows(2) {
            let ((t0, p0), (t1, p1)) = (w[0], w[1]);
            if (t1 - t0) * length < MIN_PIECE {
                continue;
            }
            let mid = 0.5 * (t0 + t1);
            let other = shared
                .iter()
                .filter(|s| s.ends[0].0 <= mid && mid <= s.ends[1].0)
                .map(|s| s.surface)
                .min();
            let kind = match other {
                None => SegmentKind::Wall { surface: e.surface },
                // Each connection once, from the lower-numbered surface's edge.
                Some(o) if e.surface < o => SegmentKind::Connection { a: e.surface, b: o },
                Some(_) => continue,
            };
            segments.push(Segment { a: p0, b: p1, kind });
        }
    }
    segments
}

/// The walls of every barrier line, for the surfaces of its level; a barrier with a
/// non-finite coordinate is refused.
pub(super) fn barrier_segments(plan: &FloorPlan) -> Result<Vec<Segment>> {
    let mut segments = Vec::new();
    for (i, b) in plan.barriers.iter().enumerate() {
        if b.line
            .coords()
            .any(|c| !(c.x.is_finite() && c.y.is_finite()))
        {
            return Err(Error::invalid(
                format!("barrier {i}"),
                "has a non-finite coordinate",
            ));
        }
        for l in b.line.lines() {
            if (l.end.x - l.start.x).hypot(l.end.y - l.start.y) > MIN_PIECE {
                segments.push(Segment {
                    a: [l.start.x, l.start.y],
                    b: [l.end.x, l.end.y],
                    kind: SegmentKind::Barrier { level: b.level },
                });
            }
        }
    }
    Ok(segments)
}
