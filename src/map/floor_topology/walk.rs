//! A step walked through the topology (Woodman & Harle 2008, Algorithm 1 lines 7–24): from
//! its surface through that surface's own edges, into the next surface at each connection,
//! stopped by a wall or a barrier.

use super::grid::{BARRIER_FLAG, NO_SURFACE, Record};
use super::topology::FloorTopology;

/// Most connections one step may cross (a long step down a steep stair crosses a few).
const MAX_HOPS: usize = 64;
/// Connections are crossed only beyond the step fraction of the previous crossing; walls and
/// barriers from this far before it, so that no wall is lost to rounding at a shared corner.
const WALL_SLACK: f32 = 1e-4;

impl FloorTopology {
    /// Algorithm 1, lines 7–24: walks the straight step from `from` (on `surface`) to `to`
    /// through the surface's edges, into the next surface at each connection, for the rest of
    /// the step. Returns the surface `to` lies on, or `None` when the step crosses a wall or
    /// a barrier (or more than 64 connections).
    #[inline]
    #[must_use]
    pub fn walk(&self, surface: u32, from: [f32; 2], to: [f32; 2]) -> Option<u32> {
        // The step stays one fixed segment; `t_c` is the fraction of it where the last
        // connection was crossed (a start a hair past a connection still crosses it).
        let grid = &self.grid;
        let (sx, sy) = (to[0] - from[0], to[1] - from[1]);
        let (ix0, ix1) = grid.span(from[0].min(to[0]), from[0].max(to[0]), 0);
        let (iy0, iy1) = grid.span(from[1].min(to[1]), from[1].max(to[1]), 1);
        let mut s = surface;
        let mut t_c = -WALL_SLACK;
        for _ in 0..MAX_HOPS {
            // The surface's own walls and connections and its level's barriers, in the
            // cells the step's box covers.
            let level = (self.level[s as usize] - self.levels.0) as u32;
            let barrier = BARRIER_FLAG | level;
            let mut best_t = f32::INFINITY;
            let mut best: Option<(Record, bool, bool)> = None;
            let own = grid.surfaces[s as usize].rows((ix0, ix1), (iy0, iy1));
            let barriers = grid.barriers[level as usize].rows((ix0, ix1), (iy0, iy1));
            for r in own.chain(barriers).flatten() {
                // The nearest crossing; a wall wins a tie (so walls may be met in any order,
                // connections in the order of the plan's cells).
                if let Some((t, on_left, wall)) = crossing(r, s, barrier, from, (sx, sy), t_c)
                    && (t < best_t || (t == best_t && wall))
                {
                    best_t = t;
                    best = Some((*r, on_left, wall));
                }
            }
            let Some((r, on_left, wall)) = best else {
                return Some(s);
            };
            if wall {
                return None; // eq. (14)
            }
            s = if on_left { r.right } else { r.left }; // eq. (13)
            t_c = best_t;
        }
        None
    }
}

/// Where the step from `from` along `(sx, sy)` leaves surface `s` through record `r` (whose
/// level's barriers are flagged `barrier`), as a fraction of the step no later than its end
/// and beyond the last connection crossed (`t_c`; walls from a hair before it), with whether
/// `s` lies on the record's left and whether it is a wall: `(t, on_left, wall)`.
#[inline]
pub(super) fn crossing(
    r: &Record,
    s: u32,
    barrier: u32,
    from: [f32; 2],
    (sx, sy): (f32, f32),
    t_c: f32,
) -> Option<(f32, bool, bool)> {
    let (on_left, on_right) = (r.left == s, r.right == s);
    let is_barrier = r.left == barrier;
    if !(on_left || on_right || is_barrier) {
        return None;
    }
    let (dx, dy) = (r.bx - r.ax, r.by - r.ay);
    // The step leaves the surface's side: left to right is cross(d, S) < 0.
    let denom = dx * sy - dy * sx;
    let leaves = if on_left {
        denom < 0.0
    } else if on_right {
        denom > 0.0
    } else {
        denom != 0.0
    };
    if !leaves {
        return None;
    }
    // The segment's ends lie on both sides of (or on) the step's line.
    let ca = sx * (r.ay - from[1]) - sy * (r.ax - from[0]);
    let cb = sx * (r.by - from[1]) - sy * (r.bx - from[0]);
    if ca * cb > 0.0 {
        return None;
    }
    let t = (dx * (r.ay - from[1]) - dy * (r.ax - from[0])) / denom;
    let wall = is_barrier || r.right == NO_SURFACE || r.left == NO_SURFACE;
    let after = if wall { t >= t_c - WALL_SLACK } else { t > t_c };
    (after && t <= 1.0).then_some((t, on_left, wall))
}
