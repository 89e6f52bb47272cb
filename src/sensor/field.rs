//! The magnetic field along a walk, one reading per step: what a magnetic-field SLAM
//! (MagSLAM, Robertson et al., IPIN 2013) observes of a place.
//!
//! Indoors the Earth's field is bent by a building's steel into a pattern that changes over
//! a metre or two and stays put for years. Its magnitude does not depend on how the sensor
//! is held; its vertical part needs only the direction of gravity. Both are what a map of
//! the field can hold without knowing the walker's heading.

use serde::{Deserialize, Serialize};

/// Largest accepted field magnitude, µT (Earth's is 25–65 µT; steel and motors add some;
/// [`crate::sensor::imu::MAX_MAG`] bounds single axes alike).
pub const MAX_FIELD: f64 = 2_000.0;

/// The magnetic field over one step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StepField {
    /// Mean magnitude over the step, µT.
    pub magnitude: f64,
    /// Mean upward component (negative where the field dips down, as in the northern
    /// hemisphere), µT, when the direction of gravity was known.
    pub vertical: Option<f64>,
}

/// Why a step's field reading is implausible, if it is.
///
/// # Errors
///
/// A message naming the value and the rule when the magnitude or the vertical part is not finite,
/// the magnitude is outside [0, [`MAX_FIELD`]] µT, or the vertical part exceeds the magnitude.
pub fn check_field(field: &StepField) -> Result<(), String> {
    if !field.magnitude.is_finite() || field.vertical.is_some_and(|v| !v.is_finite()) {
        return Err("magnetic field values must be finite numbers (found NaN or infinity)".into());
    }
    if !(0.0..=MAX_FIELD).contains(&field.magnitude) {
        return Err(format!(
            "magnetic field magnitude {} µT is outside [0, {MAX_FIELD}] µT",
            crate::error::short_number(field.magnitude)
        ));
    }
    if let Some(v) = field.vertical
        && v.abs() > field.magnitude + 1e-6 * field.magnitude.max(1.0)
    {
        return Err(format!(
            "vertical magnetic field {} µT exceeds the magnitude {} µT",
            crate::error::short_number(v),
            crate::error::short_number(field.magnitude)
        ));
    }
    Ok(())
}

/// The field at each step of a trace (`None` where a step has no reading).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StepFields {
    fields: Vec<Option<StepField>>,
}

impl StepFields {
    /// Readings checked with [`check_field`]; the error names the 0-based step index.
    ///
    /// # Errors
    ///
    /// The first reading that fails [`check_field`], as its 0-based step index and the message.
    pub fn new(fields: Vec<Option<StepField>>) -> Result<Self, (usize, String)> {
        for (i, f) in fields.iter().enumerate() {
            if let Some(f) = f {
                check_field(f).map_err(|m| (i, m))?;
            }
        }
        Ok(Self { fields })
    }

    /// One entry per step.
    #[must_use]
    pub fn fields(&self) -> &[Option<StepField>] {
        &self.fields
    }

    /// The reading of step `i`, if it has one.
    #[must_use]
    pub fn get(&self, i: usize) -> Option<StepField> {
        self.fields.get(i).copied().flatten()
    }

    /// Steps (entries).
    #[must_use]
    pub fn len(&self) -> usize {
        self.fields.len()
    }

    /// True without entries.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.fields.is_empty()
    }

    /// Steps with a reading.
    #[must_use]
    pub fn observed(&self) -> usize {
        self.fields.iter().flatten().count()
    }

    /// Steps whose reading has a vertical part.
    #[must_use]
    pub fn with_vertical(&self) -> usize {
        self.fields
            .iter()
            .flatten()
            .filter(|f| f.vertical.is_some())
            .count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn implausible_readings_are_named() {
        let ok = StepField {
            magnitude: 45.0,
            vertical: Some(-38.0),
        };
        assert!(check_field(&ok).is_ok());
        let nan = StepField {
            magnitude: f64::NAN,
            vertical: None,
        };
        assert!(check_field(&nan).unwrap_err().contains("finite"));
        let big = StepField {
            magnitude: 5_000.0,
            vertical: None,
        };
        assert!(check_field(&big).unwrap_err().contains("outside"));
        let steep = StepField {
            magnitude: 40.0,
            vertical: Some(-60.0),
        };
        assert!(check_field(&steep).unwrap_err().contains("exceeds"));
        let e = StepFields::new(vec![Some(ok), None, Some(big)]).unwrap_err();
        assert_eq!(e.0, 2);
        let f = StepFields::new(vec![Some(ok), None]).unwrap();
        assert_eq!((f.len(), f.observed(), f.with_vertical()), (2, 1, 1));
        assert_eq!(f.get(1), None);
    }
}
