//! An input of a job with the name its errors and its report give it.

/// A parsed input and the name errors and the report give it (a path, or `<DataFrame>`).
///
/// ```
/// use footslam::pipeline::Named;
/// let steps = Named::new(vec![1.0, 2.0], "walk-1/steps.csv");
/// assert_eq!((steps.value.len(), steps.label.as_str()), (2, "walk-1/steps.csv"));
/// ```
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
