//! Mean shift's iterations, with the paths of earlier seeds remembered
//! ([`Shifts`](self::Shifts)).

use super::{CONVERGED, ClusterConfig, Grid, MAX_ITERATIONS, Mode, Moments, heading_gap};
use rustc_hash::FxHashMap;

/// A mode's place and heading, bit for bit: what its next shift depends on.
type ModeKey = [u64; 4];

impl Mode {
    pub(super) fn key(&self) -> ModeKey {
        [
            self.x.to_bits(),
            self.y.to_bits(),
            self.z.to_bits(),
            self.heading.to_bits(),
        ]
    }
}

/// Mean shift of the seeds to convergence, remembering where each visited mode ended.
///
/// A shift's next mode depends on the mode's place and heading alone, so two seeds whose
/// paths meet — bit for bit, as they do once both kernels hold the same particles, summed in
/// the same cell order — share the rest of the path. A tight belief's seeds all meet after
/// one or two shifts; the rest is read from `known` (the same modes as shifting each seed on,
/// iteration cap included).
#[derive(Debug, Clone, Default)]
pub(super) struct Shifts {
    /// Each mode visited by a finished shift: where the shift ended and after how many more
    /// iterations (counting the one from this mode).
    pub(super) known: FxHashMap<ModeKey, (Mode, usize)>,
    /// Scratch: the modes of the current shift.
    path: Vec<ModeKey>,
}

impl Shifts {
    /// Every seed shifted to convergence, in order; the paths remembered are this call's
    /// only (another belief's points would end them elsewhere).
    pub(super) fn shift_all(
        &mut self,
        seeds: Vec<Mode>,
        grid: &Grid,
        config: &ClusterConfig,
    ) -> Vec<Mode> {
        self.known.clear();
        seeds
            .into_iter()
            .map(|s| self.shift(s, grid, config))
            .collect()
    }

    /// Mean shift of one mode to convergence (at most [`MAX_ITERATIONS`] iterations).
    pub(super) fn shift(&mut self, mut m: Mode, grid: &Grid, config: &ClusterConfig) -> Mode {
        let r2 = config.radius * config.radius;
        self.path.clear();
        // The iterations left after the end: `Some(k)` when the path met a known mode k
        // iterations from its end; `Some(0)` when it stopped by itself; `None` at the cap.
        let mut after = None;
        for iteration in 0..MAX_ITERATIONS {
            let key = m.key();
            if let Some(&(end, left)) = self.known.get(&key)
                && left <= MAX_ITERATIONS - iteration
            {
                m = end;
                after = Some(left);
                break;
            }
            self.path.push(key);
            let mut s = Moments::default();
            let (cx, cy) = Grid::key(m.x, m.y, grid.cell);
            for dx in -1..=1 {
                for p in grid.column(cx + dx, cy - 1, cy + 1) {
                    let (dx, dy) = (p.x - m.x, p.y - m.y);
                    if dx * dx + dy * dy <= r2
                        && (p.z - m.z).abs() < config.max_dz
                        && heading_gap(p.heading, m.heading) <= config.max_dheading
                    {
                        s.add_member(p);
                    }
                }
            }
            if s.w <= 0.0 {
                after = Some(0);
                break;
            }
            let next = s.mode();
            let moved = (next.x - m.x).hypot(next.y - m.y)
                + (next.z - m.z).abs()
                + heading_gap(next.heading, m.heading);
            m = next;
            if moved < CONVERGED {
                after = Some(0);
                break;
            }
        }
        // A path cut by the cap would end elsewhere from another start: not remembered.
        if let Some(after) = after {
            let n = self.path.len();
            for (j, key) in self.path.drain(..).enumerate() {
                self.known.insert(key, (m, n - j + after));
            }
        }
        m
    }
}
