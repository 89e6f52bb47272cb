//! A function's last argument and value: one `exp` per run of equal log-weights.

/// The last argument of a function and its value: a run of equal arguments costs one call
/// (and gives the same bits).
#[derive(Debug, Clone, Copy)]
pub(super) struct Memo<T> {
    x: f32,
    y: T,
}

impl<T: Copy + Default> Default for Memo<T> {
    fn default() -> Self {
        Self {
            x: f32::NAN,
            y: T::default(),
        }
    }
}

impl<T: Copy> Memo<T> {
    /// `f(x)`, computed only when `x` differs from the last argument.
    #[inline]
    pub(super) fn get(&mut self, x: f32, f: impl FnOnce(f32) -> T) -> T {
        if x.to_bits() != self.x.to_bits() {
            (self.x, self.y) = (x, f(x));
        }
        self.y
    }
}
