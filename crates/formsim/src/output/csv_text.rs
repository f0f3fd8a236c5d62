//! CSV text written with the `csv` crate, the one way formsim writes its CSV
//! files (`sections/*.csv`, `energy.csv`, `punch_force.csv`, `tools.csv`,
//! `compare.csv`, `friction-point` and `tools project` outputs, the
//! `die_shoulder_history` example's point history).
//!
//! The caller formats every field (`{}` or `{:e}`), so each file keeps its
//! number format; the `csv` crate separates the fields by `,`, ends each
//! record by `\n` and quotes a field only if it holds a `,`, a `"` or a line
//! break. The text is built in memory and written whole, so that a value
//! refused half-way leaves no partial file.

use std::io;
use std::path::Path;

/// CSV text being built: a header record, then the rows.
pub struct CsvText(csv::Writer<Vec<u8>>);

impl Default for CsvText {
    fn default() -> Self {
        Self::new()
    }
}

impl CsvText {
    /// Text whose records all have as many fields as the first (the header).
    pub fn new() -> Self {
        Self(csv::Writer::from_writer(Vec::new()))
    }

    /// Text whose records may have fewer or more fields than the header
    /// (`compare.csv`: a failed run's row ends with `failed`).
    pub fn flexible() -> Self {
        Self(
            csv::WriterBuilder::new()
                .flexible(true)
                .from_writer(Vec::new()),
        )
    }

    /// Append one record of formatted fields.
    ///
    /// # Errors
    /// The record's length differs from the header's (not [`Self::flexible`]).
    pub fn record<I, T>(&mut self, fields: I) -> io::Result<()>
    where
        I: IntoIterator<Item = T>,
        T: AsRef<[u8]>,
    {
        Ok(self.0.write_record(fields)?)
    }

    /// The text as bytes.
    ///
    /// # Errors
    /// None in practice (the text is in memory); the `csv` writer's flush.
    pub fn into_bytes(self) -> io::Result<Vec<u8>> {
        self.0.into_inner().map_err(|e| e.into_error())
    }

    /// Write the text to `path` (created or replaced).
    ///
    /// # Errors
    /// I/O.
    pub fn write_to(self, path: &Path) -> io::Result<()> {
        std::fs::write(path, self.into_bytes()?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fields as formatted, `,` between them, `\n` after each record, quotes
    /// only around a field that needs them; an empty field stays empty.
    #[test]
    fn fields_are_written_as_formatted_and_quoted_only_when_needed() {
        let mut csv = CsvText::new();
        csv.record(["a", "b", "c"]).unwrap();
        csv.record([
            format!("{}", 0.1 + 0.2),
            format!("{:e}", 1500.0),
            String::new(),
        ])
        .unwrap();
        csv.record(["x,y", "say \"hi\"", "-0"]).unwrap();
        let text = String::from_utf8(csv.into_bytes().unwrap()).unwrap();
        assert_eq!(
            text,
            "a,b,c\n0.30000000000000004,1.5e3,\n\"x,y\",\"say \"\"hi\"\"\",-0\n"
        );
    }

    /// A record of another length is an error, unless the text is flexible.
    #[test]
    fn a_short_record_needs_a_flexible_text() {
        let mut csv = CsvText::new();
        csv.record(["a", "b"]).unwrap();
        assert!(csv.record(["failed"]).is_err());
        let mut csv = CsvText::flexible();
        csv.record(["a", "b"]).unwrap();
        csv.record(["failed"]).unwrap();
        assert_eq!(csv.into_bytes().unwrap(), b"a,b\nfailed\n");
    }
}
