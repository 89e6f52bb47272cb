//! KLD sizing of the next particle set and systematic resampling into it, with the buffers
//! reused between steps.

use super::memo::Memo;
use super::{CHUNK, TrackParticle, Tracker};
use rand::RngExt;
use rayon::prelude::*;

impl Tracker<'_> {
    /// Turns the proposal's log-weights into weights (relative to the largest), fills the
    /// KLD bins with them and returns the KLD sample size.
    pub(super) fn weigh(&mut self) -> usize {
        let max = self
            .log_weights
            .par_iter()
            .copied()
            .reduce(|| f32::NEG_INFINITY, f32::max);
        self.log_weights.par_chunks_mut(CHUNK).for_each(|chunk| {
            let mut exp = Memo::default();
            for l in chunk {
                *l = exp.get(*l, |l| (l - max).exp());
            }
        });
        self.bins.clear();
        if self.dense_bins {
            for (&b, &w) in self.bin_index.iter().zip(&self.log_weights) {
                if w > 0.0 {
                    self.bins.add(u64::from(b), f64::from(w));
                }
            }
        } else {
            for (p, &w) in self.proposal.iter().zip(&self.log_weights) {
                if w > 0.0 {
                    let level = self.topology.level(p.surface);
                    let b = self.bins.bin(p.x, p.y, p.heading, level);
                    self.bins.add(b, f64::from(w));
                }
            }
        }
        let min = if self.localised_now {
            self.config.kld.min_particles
        } else {
            self.config.ambiguous_min_particles
        };
        self.bins
            .sample_size_at_least(min)
            .min(self.config.kld.step_cap())
    }

    /// Systematic resampling of `n` particles from the weighted proposal into the belief,
    /// chunk by chunk in parallel (each chunk emits the pointers that fall in its share of
    /// the cumulative weight).
    pub(super) fn resample(&mut self, n: usize, salt: u64) {
        let weights = &self.log_weights;
        let sums: Vec<f64> = weights
            .par_chunks(CHUNK)
            .map(|c| c.iter().map(|&w| f64::from(w)).sum())
            .collect();
        let mut starts = Vec::with_capacity(sums.len() + 1);
        let mut total = 0.0;
        for s in &sums {
            starts.push(total);
            total += s;
        }
        debug_assert!(total > 0.0 && total.is_finite());
        let u0: f64 = crate::random::filter_stream(self.config.seed ^ salt, self.steps).random();
        let target = |j: usize| (u0 + j as f64) / n as f64 * total;
        let first_pointer = |s: f64| {
            let mut j = ((s / total * n as f64 - u0).ceil().max(0.0) as usize).min(n);
            while j > 0 && target(j - 1) >= s {
                j -= 1;
            }
            while j < n && target(j) < s {
                j += 1;
            }
            j
        };
        let mut bounds: Vec<usize> = starts.iter().map(|&s| first_pointer(s)).collect();
        bounds.push(n);
        resize(&mut self.particles, n);
        // Ancestors are recorded only for the path tree (an empty slice per chunk otherwise).
        let record = self.tree.is_some();
        resize(&mut self.ancestors, if record { n } else { 0 });
        let mut rest: &mut [TrackParticle] = &mut self.particles;
        let mut rest_ancestors: &mut [u32] = &mut self.ancestors;
        let mut outputs = Vec::with_capacity(sums.len());
        for w in bounds.windows(2) {
            let (head, tail) = rest.split_at_mut(w[1] - w[0]);
            let split = if record { w[1] - w[0] } else { 0 };
            let (a_head, a_tail) = rest_ancestors.split_at_mut(split);
            outputs.push((w[0], head, a_head));
            rest = tail;
            rest_ancestors = a_tail;
        }
        let proposal = &self.proposal;
        outputs
            .into_par_iter()
            .zip(weights.par_chunks(CHUNK))
            .zip(starts.par_iter())
            .enumerate()
            .for_each(|(c, (((j0, out, ancestors), w), &start))| {
                let base = c * CHUNK;
                let mut i = 0;
                let mut cumulative = start + f64::from(w[0]);
                for (k, slot) in out.iter_mut().enumerate() {
                    let t = target(j0 + k);
                    while t >= cumulative && i + 1 < w.len() {
                        i += 1;
                        cumulative += f64::from(w[i]);
                    }
                    *slot = proposal[base + i];
                    if let Some(a) = ancestors.get_mut(k) {
                        *a = (base + i) as u32;
                    }
                }
            });
    }
}

/// Sets `v`'s length to `n` (contents unspecified), keeping its allocation. New slots are
/// filled in parallel: a fresh buffer's pages are first touched by every thread, not one.
///
/// A buffer is never shrunk when the set does: the process has reached that peak already,
/// and releasing a prior's buffers (tens of megabytes) costs more than the step that
/// follows (the allocator hands the pages back to the system and the next large set faults
/// them in again: 25 ms of the bundled walk's 0.5 s).
pub(super) fn resize<T: Copy + Default + Send + Sync>(v: &mut Vec<T>, n: usize) {
    if v.capacity() < n {
        v.reserve_exact(n - v.len());
    }
    if n <= v.len() {
        v.truncate(n);
    } else {
        let extra = n - v.len();
        v.par_extend(rayon::iter::repeat_n(T::default(), extra).with_min_len(CHUNK));
    }
}
