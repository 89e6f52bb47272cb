//! Step traces as CSV: header `t,length,dheading[,dz][,heading][,field[,field_up]]`
//! (seconds, metres, radians counter-clockwise, metres, radians from east, and the magnetic
//! field over the step: magnitude and upward component, µT); extra columns are ignored.
//!
//! A trace read from text or a file, written, and bad input refused with its place:
//!
//! ```
//! use footslam::io::read_steps;
//! use footslam::io::steps_csv::{steps_from_str, write_steps};
//!
//! let trace = steps_from_str("t,length,dheading\n0.5,0.7,0\n1.0,0.72,0.1\n", "steps")?;
//! assert_eq!(trace.len(), 2);
//! assert_eq!(trace.steps()[1].dheading, 0.1);
//! assert_eq!(trace.steps()[1].dz, 0.0); // no `dz` column: no height change
//!
//! let dir = tempfile::tempdir().expect("a temporary folder");
//! let path = dir.path().join("steps.csv");
//! write_steps(&path, &trace)?;
//! assert_eq!(read_steps(&path)?, trace);
//!
//! // A file's errors name its line; a text's, its 0-based data row.
//! std::fs::write(&path, "t,length,dheading\n0.5,0.7,0\n0.4,0.7,0\n").expect("written");
//! let err = read_steps(&path).unwrap_err().to_string();
//! assert!(err.contains("steps.csv:3:") && err.contains("not after"), "{err}");
//! let err = steps_from_str("t,length,dheading\n0.5,7.0,0\n", "steps").unwrap_err();
//! assert_eq!(err.to_string(), "steps row 0: step length 7 m is outside [0, 3] m");
//! # Ok::<(), footslam::Error>(())
//! ```

use super::csv_table::CsvTable;
use crate::error::Result;
use crate::sensor::field::{StepField, StepFields, check_field};
use crate::sensor::step::{Step, StepTrace, check_step};
use std::path::Path;

/// Reads and validates a step trace; errors name the file and line.
///
/// # Errors
///
/// As [`read_steps_with_field`].
pub fn read_steps(path: &Path) -> Result<StepTrace> {
    Ok(read_steps_with_field(path)?.0)
}

/// Reads and validates a step trace and, when the file has a `field` column, the magnetic
/// field over each step (an empty cell: no reading); errors name the file and line.
///
/// # Errors
///
/// [`Error::Io`](crate::Error::Io) when `path` cannot be opened, else
/// [`Error::Parse`](crate::Error::Parse) naming the line: a missing `t`, `length` or `dheading`
/// column (or a `field_up` column without `field`), a value that is not a finite number, a time
/// beyond 1e11 s, a step that fails [`check_step`] (length, turn, heading or `dz` out of range,
/// a time not after the previous step's), a reading that fails [`check_field`] or has
/// `field_up` without `field`, or no data rows.
pub fn read_steps_with_field(path: &Path) -> Result<(StepTrace, Option<StepFields>)> {
    steps_from_table(CsvTable::open(path)?)
}

/// Reads and validates a step trace from CSV `text` (the file format's header and rows),
/// as [`read_steps`] reads a file; errors name the table `name` and the 0-based data row.
///
/// # Errors
///
/// As [`read_steps`], as [`Error::InvalidData`](crate::Error::InvalidData) naming `name` and
/// the row.
pub fn steps_from_str(text: &str, name: &str) -> Result<StepTrace> {
    Ok(steps_with_field_from_str(text, name)?.0)
}

/// Reads a step trace and its magnetic field from CSV `text`, as [`read_steps_with_field`]
/// reads a file.
///
/// # Errors
///
/// As [`read_steps_with_field`], as [`Error::InvalidData`](crate::Error::InvalidData) naming
/// `name` and the row.
pub fn steps_with_field_from_str(
    text: &str,
    name: &str,
) -> Result<(StepTrace, Option<StepFields>)> {
    steps_from_table(CsvTable::from_text(text, name)?)
}

fn steps_from_table(mut table: CsvTable) -> Result<(StepTrace, Option<StepFields>)> {
    let t = table.column("t")?;
    let length = table.column("length")?;
    let dheading = table.column("dheading")?;
    let dz = table.optional_column("dz");
    let heading = table.optional_column("heading");
    let field = table.optional_column("field");
    let field_up = table.optional_column("field_up");
    if field.is_none() && field_up.is_some() {
        return Err(table.error(
            1,
            "a `field_up` column needs a `field` column (the field's magnitude) beside it",
        ));
    }
    let mut steps = Vec::new();
    let mut fields = Vec::new();
    let mut previous = None;
    table.for_each_row(|row| {
        let step = Step {
            t: row.time(t, "t")?,
            length: row.number(length, "length")?,
            dheading: row.number(dheading, "dheading")?,
            dz: row.optional_number(dz, "dz")?.unwrap_or(0.0),
            heading: row.optional_number(heading, "heading")?,
        };
        check_step(&step, previous).map_err(|m| row.error(m))?;
        let up = row.optional_number(field_up, "field_up")?;
        let reading = match row.optional_number(field, "field")? {
            Some(magnitude) => {
                let f = StepField {
                    magnitude,
                    vertical: up,
                };
                check_field(&f).map_err(|m| row.error(m))?;
                Some(f)
            }
            None if up.is_some() => {
                return Err(row.error("`field_up` is given but `field` is empty"));
            }
            None => None,
        };
        previous = Some(step.t);
        steps.push(step);
        fields.push(reading);
        Ok(())
    })?;
    if steps.is_empty() {
        return Err(table.error(0, "no steps: the file has a header but no data rows"));
    }
    let trace = StepTrace::new(steps).map_err(|(i, m)| table.error(i + 2, m))?;
    let fields = match field {
        Some(_) => Some(StepFields::new(fields).map_err(|(i, m)| table.error(i + 2, m))?),
        None => None,
    };
    Ok((trace, fields))
}

/// Whether a step trace has height changes: a `dz` column with at least one value (without
/// one every step reads `dz = 0`, which a multi-floor plan must not take for "stayed on the
/// floor"; a column whose every cell is empty says no more than none).
///
/// # Errors
///
/// [`Error::Io`](crate::Error::Io) when `path` cannot be opened;
/// [`Error::Parse`](crate::Error::Parse) when the header cannot be read, is empty, is JSON or
/// names a column twice, or (with a `dz` column) a row is malformed CSV. The values are not
/// checked.
pub fn has_dz_column(path: &Path) -> Result<bool> {
    has_dz_values(CsvTable::open(path)?)
}

/// [`has_dz_column`] of a CSV text named `name` in messages.
///
/// # Errors
///
/// As [`has_dz_column`], as [`Error::InvalidData`](crate::Error::InvalidData) naming `name`.
pub fn has_dz_column_in_str(text: &str, name: &str) -> Result<bool> {
    has_dz_values(CsvTable::from_text(text, name)?)
}

fn has_dz_values(mut table: CsvTable) -> Result<bool> {
    let Some(dz) = table.optional_column("dz") else {
        return Ok(false);
    };
    let mut any = false;
    table.for_each_row(|row| {
        any |= !row.text(dz).trim().is_empty();
        Ok(())
    })?;
    Ok(any)
}

/// Writes a step trace as CSV (`t,length,dheading,dz` and `heading` when any step has one).
///
/// # Errors
///
/// [`Error::Io`](crate::Error::Io) when `path` cannot be written, as
/// [`write_atomically_with`](crate::io::write_atomically_with); an existing file is then left
/// as it was.
pub fn write_steps(path: &Path, trace: &StepTrace) -> Result<()> {
    write_steps_with_field(path, trace, None)
}

/// Writes a step trace as [`write_steps`] does, with the magnetic field over each step
/// (`field`, and `field_up` when any reading has one) when `field` is given; `field` must
/// hold one entry per step.
///
/// # Errors
///
/// [`Error::Io`](crate::Error::Io) when `path` cannot be written, as [`write_steps`]. A `field`
/// that does not hold one entry per step is not an error: it is left out.
pub fn write_steps_with_field(
    path: &Path,
    trace: &StepTrace,
    field: Option<&StepFields>,
) -> Result<()> {
    let with_heading = trace.steps().iter().any(|s| s.heading.is_some());
    let field = field.filter(|f| f.len() == trace.len() && f.observed() > 0);
    let with_up = field.is_some_and(|f| f.with_vertical() > 0);
    crate::io::write_atomically_with(path, |w| {
        w.write_all(b"t,length,dheading,dz")?;
        if with_heading {
            w.write_all(b",heading")?;
        }
        if field.is_some() {
            w.write_all(if with_up {
                b",field,field_up"
            } else {
                b",field"
            })?;
        }
        w.write_all(b"\n")?;
        for (i, s) in trace.steps().iter().enumerate() {
            write!(
                w,
                "{:.3},{:.4},{:.6},{:.4}",
                s.t, s.length, s.dheading, s.dz
            )?;
            match (with_heading, s.heading) {
                (true, Some(h)) => write!(w, ",{h:.6}")?,
                (true, None) => w.write_all(b",")?,
                (false, _) => {}
            }
            if let Some(f) = field {
                match f.get(i) {
                    Some(r) => write!(w, ",{:.3}", r.magnitude)?,
                    None => w.write_all(b",")?,
                }
                if with_up {
                    match f.get(i).and_then(|r| r.vertical) {
                        Some(v) => write!(w, ",{v:.3}")?,
                        None => w.write_all(b",")?,
                    }
                }
            }
            w.write_all(b"\n")?;
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<StepTrace> {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("steps.csv");
        std::fs::write(&p, text).expect("write");
        read_steps(&p)
    }

    #[test]
    fn reads_optional_and_extra_columns() {
        let tr =
            read("t,length,dheading,extra,dz\n0,0.7,0.1,x,0.0\n1,0.8,-0.1,y,0.2\n").expect("ok");
        assert_eq!(tr.len(), 2);
        assert_eq!(tr.steps()[1].dz, 0.2);
        assert!(tr.steps()[0].heading.is_none());
    }

    #[test]
    fn field_columns_round_trip_and_bad_readings_are_named() {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("steps.csv");
        std::fs::write(
            &p,
            "t,length,dheading,dz,field,field_up\n0,0.7,0.1,0,45.5,-38.25\n1,0.8,0,0,,\n2,0.8,0,0,44,\n",
        )
        .unwrap();
        let (trace, field) = read_steps_with_field(&p).expect("ok");
        let field = field.expect("has a field column");
        assert_eq!(
            (field.len(), field.observed(), field.with_vertical()),
            (3, 2, 1)
        );
        assert_eq!(field.get(0).unwrap().vertical, Some(-38.25));
        let out = dir.path().join("out.csv");
        write_steps_with_field(&out, &trace, Some(&field)).unwrap();
        let (again, f2) = read_steps_with_field(&out).unwrap();
        assert_eq!((again, f2), (trace.clone(), Some(field)));
        assert!(read_steps_with_field(&dir.path().join("none.csv")).is_err());
        write_steps(&out, &trace).unwrap();
        assert_eq!(read_steps_with_field(&out).unwrap().1, None);
        for (text, needle) in [
            ("t,length,dheading,field\n0,0.7,0,NaN\n", "finite"),
            ("t,length,dheading,field\n0,0.7,0,-3\n", "outside"),
            (
                "t,length,dheading,field,field_up\n0,0.7,0,40,-50\n",
                "exceeds",
            ),
            (
                "t,length,dheading,field,field_up\n0,0.7,0,,-30\n",
                "`field` is empty",
            ),
            (
                "t,length,dheading,field_up\n0,0.7,0,-30\n",
                "needs a `field` column",
            ),
        ] {
            std::fs::write(&p, text).unwrap();
            let e = read_steps_with_field(&p).unwrap_err().to_string();
            assert!(e.contains("steps.csv") && e.contains(needle), "{text}: {e}");
        }
    }

    #[test]
    fn text_reads_as_a_file_does_and_errors_name_the_row() {
        let text = "t,length,dheading,dz\n0,0.7,0.1,0.0\n1,0.8,-0.1,0.2\n";
        assert_eq!(
            steps_from_str(text, "steps").expect("ok"),
            read(text).expect("ok")
        );
        let e = steps_from_str("t,length,dheading\n0,0.7,0\n1,NaN,0\n", "steps")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "steps row 1: column `length`: `NaN` is not a finite number"
        );
        let e = steps_from_str("t,length,dheading\n1,0.7,0\n0,0.7,0\n", "walk")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("walk row 1: ") && e.contains("increasing"),
            "{e}"
        );
        let e = steps_from_str("t,length\n0,0.7\n", "steps")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("steps header: missing column `dheading`"),
            "{e}"
        );
        let e = steps_from_str("t,length,dheading\n", "steps")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("steps: no steps"), "{e}");
    }

    #[test]
    fn errors_name_the_line_and_problem() {
        let e = read("t,length,dheading\n0,0.7,0\n1,abc,0\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("steps.csv:3") && e.contains("length"), "{e}");
        let e = read("t,length,dheading\n0,0.7,0\n0,0.7,0\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains(":3") && e.contains("increasing"), "{e}");
        let e = read("t,length\n0,0.7\n").unwrap_err().to_string();
        assert!(e.contains("dheading"), "{e}");
        let e = read("").unwrap_err().to_string();
        assert!(e.contains("empty"), "{e}");
        let e = read("t,length,dheading\n").unwrap_err().to_string();
        assert!(e.contains("no steps"), "{e}");
        let e = read("t,length,dheading\n0,NaN,0\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains(":2"), "{e}");
        let e = read("t,length,dheading\n0,0.7\n").unwrap_err().to_string();
        assert!(e.contains(":2"), "{e}");
    }
}
