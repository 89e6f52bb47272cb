//! IMU recordings as CSV: header `t,ax,ay,az,gx,gy,gz` (seconds, m/s² with gravity, rad/s,
//! sensor frame) and optionally `mx,my,mz` (µT), `qx,qy,qz,qw` (orientation sensor → ENU,
//! as Android's rotation vector) and `pressure` (hPa); extra columns are ignored.
//!
//! Real logs are uneven. A row that repeats the previous row's time is dropped (counted in
//! the [`crate::sensor::SamplingReport`]); a time before the previous row's is an error. An
//! optional channel logged more slowly than the accelerometer may leave cells empty: each
//! empty cell holds the channel's previous value (its first value before it starts); a
//! channel whose column is present but empty throughout counts as absent. Errors name the
//! file, line and problem.

use super::csv_table::{CsvRow, CsvTable};
use crate::error::Result;
use crate::sensor::imu::{ImuRecording, ImuSample, check_sample, diagnose_columns};
use std::path::Path;

/// Units of an IMU file's accelerometer and gyroscope columns, as factors to SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuUnits {
    /// Factor from the file's acceleration unit to m/s² (1, or 9.80665 for g).
    pub accel: f64,
    /// Factor from the file's angular-rate unit to rad/s (1, or π/180 for deg/s).
    pub gyro: f64,
}

impl ImuUnits {
    /// m/s² and rad/s, the format's units.
    pub const SI: Self = Self {
        accel: 1.0,
        gyro: 1.0,
    };
    /// Standard gravity, m/s² per g.
    pub const G: f64 = 9.806_65;
}

/// Reads and validates an IMU recording in the format's units (m/s², rad/s).
///
/// # Errors
///
/// As [`read_imu_in`] with [`ImuUnits::SI`].
pub fn read_imu(path: &Path) -> Result<ImuRecording> {
    read_imu_in(path, ImuUnits::SI)
}

/// Reads and validates an IMU recording whose acceleration and angular-rate columns are in
/// `units`, converting them to m/s² and rad/s. The converted recording's median specific
/// force must look like gravity ([`ImuRecording::new`]): a file in g (median ≈ 1) is an
/// error that says so, rather than a walk integrated with a tenth of gravity.
///
/// # Errors
///
/// [`Error::Io`](crate::Error::Io) when `path` cannot be opened, else
/// [`Error::Parse`](crate::Error::Parse) naming the line (or the whole file):
/// * a column of `t,ax,ay,az,gx,gy,gz` is missing, or only some of `mx,my,mz` or `qx,qy,qz,qw`
///   are present, or filled on a row;
/// * a value is not a finite number, or a time comes before the previous row's;
/// * there are no data rows, or a sample is out of range ([`check_sample`]);
/// * the columns look swapped or in other `units`, or the recording fails
///   [`ImuRecording::new`]: fewer than two samples, a median acceleration not gravity's, or a
///   sampling rate no IMU has (times not in seconds).
pub fn read_imu_in(path: &Path, units: ImuUnits) -> Result<ImuRecording> {
    imu_from_table(CsvTable::open(path)?, units)
}

/// Reads and validates an IMU recording from CSV `text` (the file format's header and
/// rows) in `units`, as [`read_imu_in`] reads a file; errors name the table `name` and the
/// 0-based data row.
///
/// # Errors
///
/// As [`read_imu_in`], as [`Error::InvalidData`](crate::Error::InvalidData) naming `name` and
/// the row.
pub fn imu_from_str(text: &str, name: &str, units: ImuUnits) -> Result<ImuRecording> {
    imu_from_table(CsvTable::from_text(text, name)?, units)
}

fn imu_from_table(mut table: CsvTable, units: ImuUnits) -> Result<ImuRecording> {
    const REQUIRED: [&str; 7] = ["t", "ax", "ay", "az", "gx", "gy", "gz"];
    let mut required = [0usize; 7];
    for (slot, name) in required.iter_mut().zip(REQUIRED) {
        *slot = table.column(name)?;
    }
    let group = |names: &[&str]| -> Result<Option<Vec<usize>>> {
        let found: Vec<_> = names.iter().map(|n| table.optional_column(n)).collect();
        match found.iter().filter(|c| c.is_some()).count() {
            0 => Ok(None),
            n if n == names.len() => Ok(Some(found.into_iter().flatten().collect())),
            _ => Err(table.error(
                1,
                format!(
                    "columns {} go together: found only some of them",
                    names.join(",")
                ),
            )),
        }
    };
    let mag_cols = group(&["mx", "my", "mz"])?;
    let quat_cols = group(&["qx", "qy", "qz", "qw"])?;
    let pressure_cols = table.optional_column("pressure").map(|c| vec![c]);

    let mut samples: Vec<ImuSample> = Vec::new();
    let mut duplicates = 0usize;
    let mut lines: Vec<usize> = Vec::new();
    let mut mag = Channel::<3>::default();
    let mut quat = Channel::<4>::default();
    let mut pressure = Channel::<1>::default();
    table.for_each_row(|row| {
        let mut v = [0.0; 7];
        for ((slot, &c), name) in v.iter_mut().zip(&required).zip(REQUIRED) {
            *slot = row.number(c, name)?;
        }
        let t = v[0];
        if let Some(last) = samples.last() {
            if t == last.t {
                duplicates += 1;
                return Ok(());
            }
            if t < last.t {
                return Err(row.error(format!(
                    "time {t} s is before the previous row's {} s (rows must be sorted by time)",
                    last.t
                )));
            }
        }
        let index = samples.len();
        mag.read(row, mag_cols.as_deref(), &["mx", "my", "mz"], index)?;
        quat.read(row, quat_cols.as_deref(), &["qx", "qy", "qz", "qw"], index)?;
        pressure.read(row, pressure_cols.as_deref(), &["pressure"], index)?;
        samples.push(ImuSample {
            t,
            accel: [v[1], v[2], v[3]].map(|a| a * units.accel),
            gyro: [v[4], v[5], v[6]].map(|w| w * units.gyro),
            mag: mag.current(),
            orientation: quat.current(),
            pressure: pressure.current().map(|[p]| p),
        });
        lines.push(row.line());
        Ok(())
    })?;
    if samples.is_empty() {
        return Err(table.error(0, "no samples: the file has a header but no data rows"));
    }
    mag.backfill(&mut samples, |s, v| s.mag = Some(v));
    quat.backfill(&mut samples, |s, v| s.orientation = Some(v));
    pressure.backfill(&mut samples, |s, [v]| s.pressure = Some(v));
    if let Some(problem) = diagnose_columns(&samples, units.accel) {
        return Err(table.error(0, problem));
    }
    for (s, &line) in samples.iter().zip(&lines) {
        check_sample(s).map_err(|m| table.error(line, m))?;
    }
    ImuRecording::new(samples, duplicates)
        .map_err(|(i, m)| table.error(lines.get(i).copied().unwrap_or(0), m))
}

/// An optional channel read row by row, holding its last value over empty cells.
#[derive(Default)]
struct Channel<const N: usize> {
    last: Option<[f64; N]>,
    /// Index of the first sample with a value, and that value.
    first: Option<(usize, [f64; N])>,
}

impl<const N: usize> Channel<N> {
    fn read(
        &mut self,
        row: &CsvRow<'_>,
        columns: Option<&[usize]>,
        names: &[&str],
        index: usize,
    ) -> Result<()> {
        let Some(columns) = columns else {
            return Ok(());
        };
        let empty = columns.iter().filter(|&&c| row.text(c).is_empty()).count();
        if empty == N {
            return Ok(());
        }
        if empty > 0 {
            return Err(row.error(format!(
                "columns {} go together: some are empty on this row",
                names.join(",")
            )));
        }
        let mut value = [0.0; N];
        for (slot, (&c, name)) in value.iter_mut().zip(columns.iter().zip(names)) {
            *slot = row.number(c, name)?;
        }
        self.last = Some(value);
        self.first.get_or_insert((index, value));
        Ok(())
    }

    fn current(&self) -> Option<[f64; N]> {
        self.last
    }

    /// Gives the samples before the channel's first value that first value.
    fn backfill(&self, samples: &mut [ImuSample], set: impl Fn(&mut ImuSample, [f64; N])) {
        if let Some((first, value)) = self.first {
            for s in &mut samples[..first] {
                set(s, value);
            }
        }
    }
}

/// Writes an IMU recording as CSV with the optional columns it carries.
///
/// # Errors
///
/// [`Error::Io`](crate::Error::Io) when `path` cannot be written, as
/// [`write_atomically_with`](crate::io::write_atomically_with); an existing file is then left
/// as it was.
pub fn write_imu(path: &Path, recording: &ImuRecording) -> Result<()> {
    let mut header = String::from("t,ax,ay,az,gx,gy,gz");
    if recording.has_magnetometer() {
        header.push_str(",mx,my,mz");
    }
    if recording.has_orientation() {
        header.push_str(",qx,qy,qz,qw");
    }
    if recording.has_pressure() {
        header.push_str(",pressure");
    }
    crate::io::write_atomically_with(path, |w| {
        writeln!(w, "{header}")?;
        for s in recording.samples() {
            write!(w, "{:.4}", s.t)?;
            for v in s.accel.iter().chain(&s.gyro) {
                write!(w, ",{v:.6}")?;
            }
            for v in s.mag.iter().flatten() {
                write!(w, ",{v:.4}")?;
            }
            for v in s.orientation.iter().flatten() {
                write!(w, ",{v:.7}")?;
            }
            if let Some(p) = s.pressure {
                write!(w, ",{p:.4}")?;
            }
            w.write_all(b"\n")?;
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<ImuRecording> {
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("imu.csv");
        std::fs::write(&p, text).expect("write");
        read_imu(&p)
    }

    const HEAD: &str = "t,ax,ay,az,gx,gy,gz";

    #[test]
    fn reads_unix_times_drops_duplicates_and_holds_slow_channels() {
        let r = read(&format!(
            "{HEAD},pressure,extra\n\
             1700000000.00,0,0,9.8,0,0,0,,a\n\
             1700000000.01,0,0,9.8,0,0,0,1013.2,b\n\
             1700000000.01,0,0,9.8,0,0,0,1013.2,b\n\
             1700000000.02,0,0,9.8,0,0,0,,c\n"
        ))
        .expect("valid");
        assert_eq!(r.samples().len(), 3);
        assert_eq!(r.report().duplicate_times, 1);
        assert_eq!(r.samples()[0].t, 1_700_000_000.0);
        assert!(r.samples().iter().all(|s| s.pressure == Some(1013.2)));
        assert!(!r.has_magnetometer() && !r.has_orientation());
    }

    #[test]
    fn errors_name_line_and_problem() {
        let e = |text: &str| read(text).unwrap_err().to_string();
        let msg = e(&format!("{HEAD}\n0,0,0,9.8,0,0,0\n-1,0,0,9.8,0,0,0\n"));
        assert!(msg.contains("imu.csv:3") && msg.contains("sorted"), "{msg}");
        let msg = e(&format!("{HEAD}\n0,0,0,9.8,0,0,0\n1,0,NaN,9.8,0,0,0\n"));
        assert!(msg.contains(":3") && msg.contains("ay"), "{msg}");
        let msg = e("t,ax,ay,az,gx,gy\n0,0,0,9.8,0,0\n");
        assert!(msg.contains("gz"), "{msg}");
        let msg = e(&format!("{HEAD},mx,my\n0,0,0,9.8,0,0,0,1,2\n"));
        assert!(msg.contains("mx,my,mz"), "{msg}");
        let msg = e(&format!("{HEAD}\n"));
        assert!(msg.contains("no samples"), "{msg}");
        let msg = e(&format!("{HEAD}\n0,0,0,9.8,0,0\n"));
        assert!(msg.contains(":2"), "{msg}");
        let msg = e(&format!("{HEAD}\n0,0,0,9.8,0,0,0\n1,0,0,900,0,0,0\n"));
        assert!(msg.contains(":3") && msg.contains("acceleration"), "{msg}");
        let msg = e(&format!(
            "{HEAD},qx,qy,qz,qw\n0,0,0,9.8,0,0,0,0,0,0,2\n1,0,0,9.8,0,0,0,0,0,0,1\n"
        ));
        assert!(msg.contains(":2") && msg.contains("norm"), "{msg}");
    }

    #[test]
    fn round_trips() {
        let r = read(&format!(
            "{HEAD},mx,my,mz,qx,qy,qz,qw\n0,0.1,0.2,9.8,0.01,0.02,0.03,20,5,-40,0,0,0,1\n\
             0.01,0.1,0.2,9.8,0.01,0.02,0.03,20,5,-40,0,0,0.7071068,0.7071068\n"
        ))
        .expect("valid");
        let dir = tempfile::tempdir().expect("tempdir");
        let p = dir.path().join("out.csv");
        write_imu(&p, &r).expect("write");
        assert_eq!(read_imu(&p).expect("read back"), r);
    }
}
