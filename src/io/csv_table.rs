//! Header-addressed numeric CSV reading shared by the CSV readers: columns are found by
//! name (extra columns are ignored), every value is parsed with the file, line and column
//! named in the error.
//!
//! A table is read from a file ([`CsvTable::open`]) or from text held in memory
//! ([`CsvTable::from_text`], for callers whose data is not in a file, such as the Python
//! package's arrays): the same parsing and checks, errors naming the file and line, or the
//! table's name and 0-based data row.

use crate::error::{Error, Result};
use std::io::Read;
use std::path::{Path, PathBuf};

/// The farthest a place in a local frame may lie from its origin, metres: local frames
/// hold one building or campus, and 1,000 km keeps every distance computed from them
/// finite and exact to well under a millimetre.
pub const MAX_LOCAL_COORDINATE_M: f64 = 1e6;

/// Where a table's rows come from, for error messages.
#[derive(Debug, Clone)]
pub enum CsvSource {
    /// A file: errors name it and the 1-based line.
    File(PathBuf),
    /// Text in memory under a name (e.g. `steps`): errors name it and the 0-based data row
    /// (`steps row 3: …`, the header `steps header: …`, the whole table `steps: …`).
    Memory(String),
}

impl CsvSource {
    /// An error at 1-based `line` of the text (0: the whole table, 1: the header).
    pub fn error(&self, line: usize, message: impl Into<String>) -> Error {
        match self {
            CsvSource::File(path) => Error::parse(path, line, message),
            CsvSource::Memory(name) => {
                let item = match line {
                    0 => name.clone(),
                    1 => format!("{name} header"),
                    l => format!("{name} row {}", l - 2),
                };
                Error::invalid(item, message)
            }
        }
    }
}

/// A CSV file (or text) opened for reading by column name.
pub struct CsvTable {
    source: CsvSource,
    reader: csv::Reader<Box<dyn Read + Send>>,
    headers: Vec<String>,
}

/// One data row with its 1-based line number.
pub struct CsvRow<'a> {
    source: &'a CsvSource,
    line: usize,
    record: csv::StringRecord,
}

impl CsvTable {
    /// Opens `path` and reads its header row.
    ///
    /// # Errors
    ///
    /// [`Error::Io`] when `path` cannot be opened; [`Error::Parse`] on line 1 when the header row
    /// cannot be read, is empty, is JSON rather than CSV, or names a column twice.
    pub fn open(path: &Path) -> Result<Self> {
        let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
        Self::from_reader(Box::new(file), CsvSource::File(path.to_path_buf()))
    }

    /// Reads `text` (a header row, then data rows) as a table called `name` in errors.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidData`] on `<name> header` when the header row is empty, is JSON rather than
    /// CSV, or names a column twice.
    pub fn from_text(text: impl Into<String>, name: &str) -> Result<Self> {
        let bytes = std::io::Cursor::new(text.into().into_bytes());
        Self::from_reader(Box::new(bytes), CsvSource::Memory(name.to_owned()))
    }

    fn from_reader(input: Box<dyn Read + Send>, source: CsvSource) -> Result<Self> {
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(true)
            .trim(csv::Trim::All)
            .flexible(false)
            .from_reader(input);
        let headers = reader
            .headers()
            .map_err(|e| source.error(1, format!("cannot read the header row: {e}")))?
            .iter()
            .map(|h| h.trim_start_matches('\u{feff}').to_ascii_lowercase())
            .collect::<Vec<_>>();
        if headers.iter().all(|h| h.is_empty()) {
            return Err(source.error(1, "the file is empty: expected a header row"));
        }
        if headers
            .first()
            .is_some_and(|h| h.starts_with('{') || h.starts_with('['))
        {
            return Err(source.error(
                1,
                "this is JSON (a GeoJSON map or plan?), not a CSV table with a header row: \
                 check which file goes to which option",
            ));
        }
        for (i, h) in headers.iter().enumerate() {
            if !h.is_empty() && headers[..i].contains(h) {
                return Err(source.error(
                    1,
                    format!("column `{h}` appears twice in the header: which one is meant?"),
                ));
            }
        }
        Ok(Self {
            source,
            reader,
            headers,
        })
    }

    /// An error at 1-based `line` (0: the whole table), naming the file or the table.
    pub fn error(&self, line: usize, message: impl Into<String>) -> Error {
        self.source.error(line, message)
    }

    /// Where the rows come from.
    #[must_use]
    pub fn source(&self) -> &CsvSource {
        &self.source
    }

    /// Index of a required column.
    ///
    /// # Errors
    ///
    /// The header has no column `name`: an error on the header line that lists the columns it has.
    pub fn column(&self, name: &str) -> Result<usize> {
        self.optional_column(name).ok_or_else(|| {
            self.error(
                1,
                format!(
                    "missing column `{name}` (header has: {})",
                    self.headers.join(",")
                ),
            )
        })
    }

    /// Index of an optional column.
    #[must_use]
    pub fn optional_column(&self, name: &str) -> Option<usize> {
        self.headers.iter().position(|h| h == name)
    }

    /// Calls `f` on every data row, in order; stops at the first error.
    ///
    /// # Errors
    ///
    /// A row that cannot be read or is malformed CSV (more or fewer fields than the header, bytes
    /// that are not UTF-8): an error naming its line. Otherwise the first error `f` returns,
    /// unchanged.
    pub fn for_each_row(&mut self, mut f: impl FnMut(&CsvRow<'_>) -> Result<()>) -> Result<()> {
        let mut record = csv::StringRecord::new();
        loop {
            let line = self.reader.position().line() as usize;
            match self.reader.read_record(&mut record) {
                Ok(false) => return Ok(()),
                Ok(true) => {
                    let line = record.position().map_or(line, |p| p.line() as usize);
                    if record.iter().all(str::is_empty) {
                        continue;
                    }
                    let row = CsvRow {
                        source: &self.source,
                        line,
                        record: std::mem::take(&mut record),
                    };
                    f(&row)?;
                    record = row.record;
                }
                Err(e) => {
                    let line = e.position().map_or(line, |p| p.line() as usize);
                    return Err(self.error(line, format!("malformed CSV: {e}")));
                }
            }
        }
    }
}

impl CsvRow<'_> {
    /// 1-based line number of this row.
    #[must_use]
    pub fn line(&self) -> usize {
        self.line
    }

    /// A parse error at this row.
    pub fn error(&self, message: impl Into<String>) -> Error {
        self.source.error(self.line, message)
    }

    /// Fails unless time `t` is a plausible time in seconds
    /// ([`crate::sensor::step::check_time`]) and comes strictly after `previous` (the
    /// previous row's time).
    ///
    /// # Errors
    ///
    /// An error at this row when `t` is NaN, beyond
    /// ±[`MAX_TIME_S`](crate::sensor::step::MAX_TIME_S) (not seconds) or not after `previous`.
    pub fn ensure_after(&self, previous: Option<f64>, t: f64) -> Result<()> {
        if t.is_nan() {
            return Err(self.error("the time is not a number".to_owned()));
        }
        crate::sensor::step::check_time(t).map_err(|m| self.error(m))?;
        match previous {
            Some(p) if t <= p => Err(self.error(format!(
                "time {t} s is not after the previous row's {p} s (times must be strictly increasing)"
            ))),
            _ => Ok(()),
        }
    }

    /// The raw text of column `index`.
    #[must_use]
    pub fn text(&self, index: usize) -> &str {
        self.record.get(index).unwrap_or("")
    }

    /// A required finite number in column `index` named `name`.
    ///
    /// # Errors
    ///
    /// An error at this row naming column `name` when the cell is empty, is not a number, or is
    /// NaN or infinite.
    pub fn number(&self, index: usize, name: &str) -> Result<f64> {
        let text = self.text(index);
        let v: f64 = text
            .parse()
            .map_err(|_| self.error(format!("column `{name}`: `{text}` is not a number")))?;
        if !v.is_finite() {
            return Err(self.error(format!("column `{name}`: `{text}` is not a finite number")));
        }
        Ok(v)
    }

    /// A required coordinate of the local frame in column `index` named `name`: a finite
    /// number of metres no farther than [`MAX_LOCAL_COORDINATE_M`] from the origin.
    ///
    /// # Errors
    ///
    /// As [`number`](Self::number), and when the value lies more than [`MAX_LOCAL_COORDINATE_M`]
    /// from the origin.
    pub fn coordinate(&self, index: usize, name: &str) -> Result<f64> {
        let v = self.number(index, name)?;
        if v.abs() > MAX_LOCAL_COORDINATE_M {
            return Err(self.error(format!(
                "column `{name}`: {} m is {} km from the origin: not a place in a local \
                 frame (metres east, north and up of the origin; at most {} km)",
                crate::error::short_number(v),
                crate::error::short_number(v.abs() / 1000.0),
                MAX_LOCAL_COORDINATE_M / 1000.0
            )));
        }
        Ok(v)
    }

    /// A required time stamp in column `index` named `name`: a finite number of seconds no
    /// larger than [`crate::sensor::step::MAX_TIME_S`].
    ///
    /// # Errors
    ///
    /// As [`number`](Self::number), and when the value is beyond
    /// ±[`MAX_TIME_S`](crate::sensor::step::MAX_TIME_S) (milliseconds, or a corrupt value).
    pub fn time(&self, index: usize, name: &str) -> Result<f64> {
        let t = self.number(index, name)?;
        crate::sensor::step::check_time(t)
            .map_err(|m| self.error(format!("column `{name}`: {m}")))?;
        Ok(t)
    }

    /// An optional number: `None` when the column is absent or the cell empty.
    ///
    /// # Errors
    ///
    /// As [`number`](Self::number) when the column is present and the cell not empty: the cell is
    /// not a finite number.
    pub fn optional_number(&self, index: Option<usize>, name: &str) -> Result<Option<f64>> {
        match index {
            Some(i) if !self.text(i).is_empty() => self.number(i, name).map(Some),
            _ => Ok(None),
        }
    }
}
