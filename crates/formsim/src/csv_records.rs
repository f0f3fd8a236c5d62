//! Reading CSV text with the `csv` crate, each record with the line it
//! starts on: the history of `friction-point` and the points of
//! `tools project` ([`records`]); the lines of `identify`'s CSV measurements
//! ([`start_line`]).

/// A record of a CSV text and the 1-based line it starts on.
pub(crate) type Numbered = (usize, csv::StringRecord);

/// What is wrong with the CSV text (one line) and the 1-based line it is on
/// (0 if unknown).
pub(crate) type LineError = (usize, String);

/// The records of `text`, each with the line it starts on, read by the `csv`
/// crate: no header record (the caller's first record is its header), records
/// of any length, fields trimmed of blanks and unquoted, `\n` or `\r\n` line
/// ends. Empty lines and lines of blanks are skipped, and with `comments`,
/// lines starting with `#`, also after blanks. A quoted field that runs over
/// a line end (most likely a `"` left unclosed) is an error, so that no
/// field, nor any message quoting it, holds a line break.
pub(crate) fn records(
    text: &str,
    comments: bool,
) -> impl Iterator<Item = Result<Numbered, LineError>> + '_ {
    csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .comment(comments.then_some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes())
        .into_records()
        .filter_map(move |record| match record {
            Ok(r) if is_skipped(&r, comments) => None,
            Ok(r) => {
                let line = start_line(text, r.position(), comments);
                Some(if r.iter().any(|f| f.contains(['\n', '\r'])) {
                    Err((
                        line,
                        "a quoted field runs over the end of its line (a `\"` not closed?)".into(),
                    ))
                } else {
                    Ok((line, r))
                })
            }
            Err(e) => Some(Err((error_line(&e), e.to_string()))),
        })
}

/// The 1-based line a `csv` reading error is on (0 if unknown).
pub(crate) fn error_line(e: &csv::Error) -> usize {
    e.position().map_or(0, |p| p.line() as usize)
}

/// Whether `record` is a line of blanks (one empty field once trimmed) or,
/// with `comments`, a comment indented by blanks (the `csv` reader skips only
/// a `#` at the start of a line).
fn is_skipped(record: &csv::StringRecord, comments: bool) -> bool {
    match record.get(0) {
        Some(first) => {
            (record.len() == 1 && first.is_empty()) || (comments && first.starts_with('#'))
        }
        None => true,
    }
}

/// The 1-based line a record read from `text` starts on.
///
/// The `csv` crate gives a record the position where its reader began to
/// look for it, before the empty lines and `#` comment lines it skipped
/// (BurntSushi/rust-csv#208, "`Position::line` reports inaccurate line
/// following blank lines"); those lines are counted here.
pub(crate) fn start_line(text: &str, position: Option<&csv::Position>, comments: bool) -> usize {
    let Some(position) = position else {
        return 0;
    };
    let mut line = position.line() as usize;
    let rest = usize::try_from(position.byte())
        .ok()
        .and_then(|at| text.get(at..))
        .unwrap_or("");
    for l in rest.split('\n') {
        let l = l.strip_suffix('\r').unwrap_or(l);
        if !(l.is_empty() || (comments && l.starts_with('#'))) {
            break;
        }
        line += 1;
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(text: &str, comments: bool) -> Vec<(usize, Vec<String>)> {
        records(text, comments)
            .map(|r| {
                let (line, record) = r.unwrap();
                (line, record.iter().map(String::from).collect())
            })
            .collect()
    }

    /// Each record is numbered by the line it is on, across empty lines,
    /// lines of blanks and comments, with `\n` or `\r\n` line ends.
    #[test]
    fn records_carry_the_line_they_start_on() {
        let text = "\n# c\na, b\n\n  \n # indented\n\n1,2\n#c\n3,\"4\"\n";
        let expect = vec![
            (3, vec!["a".to_string(), "b".to_string()]),
            (8, vec!["1".to_string(), "2".to_string()]),
            (10, vec!["3".to_string(), "4".to_string()]),
        ];
        assert_eq!(lines(text, true), expect);
        assert_eq!(lines(&text.replace('\n', "\r\n"), true), expect);
    }

    /// A quote left open takes the lines after it into its field: an error
    /// at the line it opens on, in one line.
    #[test]
    fn a_field_over_a_line_end_is_an_error() {
        let mut r = records("a,b\n1,\"2\n3,4\n", true);
        assert!(r.next().unwrap().is_ok());
        let (line, message) = r.next().unwrap().unwrap_err();
        assert_eq!(line, 2);
        assert!(message.contains("quoted field") && !message.contains('\n'));
    }

    /// Without comments a `#` line is a record like any other.
    #[test]
    fn without_comments_a_hash_line_is_a_record() {
        let got = lines("\nx\n# y\n\nz\n", false);
        let got: Vec<(usize, &str)> = got.iter().map(|(l, r)| (*l, r[0].as_str())).collect();
        assert_eq!(got, vec![(2, "x"), (3, "# y"), (5, "z")]);
    }
}
