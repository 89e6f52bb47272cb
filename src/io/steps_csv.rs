//! Step traces as CSV: header `t,length,dheading[,dz][,heading]` (seconds, metres, radians
//! counter-clockwise, metres, radians from east); extra columns are ignored.

use super::csv_table::CsvTable;
use crate::error::Result;
use crate::sensor::step::{Step, StepTrace, check_step};
use std::path::Path;

/// Reads and validates a step trace; errors name the file and line.
pub fn read_steps(path: &Path) -> Result<StepTrace> {
    steps_from_table(CsvTable::open(path)?)
}

/// Reads and validates a step trace from CSV `text` (the file format's header and rows),
/// as [`read_steps`] reads a file; errors name the table `name` and the 0-based data row.
pub fn steps_from_str(text: &str, name: &str) -> Result<StepTrace> {
    steps_from_table(CsvTable::from_text(text, name)?)
}

fn steps_from_table(mut table: CsvTable) -> Result<StepTrace> {
    let t = table.column("t")?;
    let length = table.column("length")?;
    let dheading = table.column("dheading")?;
    let dz = table.optional_column("dz");
    let heading = table.optional_column("heading");
    let mut steps = Vec::new();
    let mut previous = None;
    table.for_each_row(|row| {
        let step = Step {
            t: row.number(t, "t")?,
            length: row.number(length, "length")?,
            dheading: row.number(dheading, "dheading")?,
            dz: row.optional_number(dz, "dz")?.unwrap_or(0.0),
            heading: row.optional_number(heading, "heading")?,
        };
        check_step(&step, previous).map_err(|m| row.error(m))?;
        previous = Some(step.t);
        steps.push(step);
        Ok(())
    })?;
    if steps.is_empty() {
        return Err(table.error(0, "no steps: the file has a header but no data rows"));
    }
    StepTrace::new(steps).map_err(|(i, m)| table.error(i + 2, m))
}

/// Whether a step trace's header has a `dz` column (without one every step reads `dz = 0`,
/// which a multi-floor plan must not take for "stayed on the floor").
pub fn has_dz_column(path: &Path) -> Result<bool> {
    Ok(CsvTable::open(path)?.optional_column("dz").is_some())
}

/// Writes a step trace as CSV (`t,length,dheading,dz` and `heading` when any step has one).
pub fn write_steps(path: &Path, trace: &StepTrace) -> Result<()> {
    let with_heading = trace.steps().iter().any(|s| s.heading.is_some());
    crate::io::write_atomically_with(path, |w| {
        w.write_all(if with_heading {
            b"t,length,dheading,dz,heading\n"
        } else {
            b"t,length,dheading,dz\n"
        })?;
        for s in trace.steps() {
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
