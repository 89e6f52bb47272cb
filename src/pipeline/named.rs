//! An input of a job with the name its errors and its report give it.

/// A parsed input and the name errors and the report give it (a path, or `<DataFrame>`).
#[derive(Debug, Clone)]
pub struct Named<T> {
    /// The input.
    pub value: T,
    /// Its name.
    pub label: String,
}

impl<T> Named<T> {
    /// `value` named `label`.
    pub fn new(value: T, label: impl Into<String>) -> Self {
        Self {
            value,
            label: label.into(),
        }
    }
}
