//! Finding the line of a dotted key path (`contact.pairs[0].law`) in the scene text.

use toml::de::{DeTable, DeValue};

/// A path segment: a table key or an array index.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Segment {
    /// `key`.
    Key(String),
    /// `[i]`.
    Index(usize),
}

/// Split `a.b[2].c` into segments.
pub fn split_path(path: &str) -> Vec<Segment> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let mut rest = part;
        if let Some(open) = rest.find('[') {
            let key = &rest[..open];
            if !key.is_empty() {
                out.push(Segment::Key(key.to_string()));
            }
            rest = &rest[open..];
            while let Some(stripped) = rest.strip_prefix('[') {
                let Some(close) = stripped.find(']') else {
                    break;
                };
                if let Ok(i) = stripped[..close].parse() {
                    out.push(Segment::Index(i));
                }
                rest = &stripped[close + 1..];
            }
        } else if !rest.is_empty() {
            out.push(Segment::Key(rest.to_string()));
        }
    }
    out
}

/// 1-based line of the deepest part of `path` found in `text` (the key itself,
/// or the table that should hold a missing key); `None` if not even the first
/// segment is in the file.
pub fn line_of(text: &str, path: &str) -> Option<usize> {
    let root = DeTable::parse(text).ok()?;
    let segments = split_path(path);
    let mut offset: Option<usize> = None;
    let mut table: Option<&DeTable> = Some(root.get_ref());
    let mut array: Option<&[toml::Spanned<DeValue>]> = None;
    for seg in &segments {
        let value = match (seg, table, array) {
            (Segment::Key(k), Some(t), _) => {
                let Some((key, value)) = t.iter().find(|(key, _)| key.get_ref().as_ref() == k)
                else {
                    break;
                };
                offset = Some(key.span().start);
                value
            }
            (Segment::Index(i), _, Some(a)) => {
                let Some(value) = a.get(*i) else { break };
                offset = Some(value.span().start);
                value
            }
            _ => break,
        };
        table = None;
        array = None;
        match value.get_ref() {
            DeValue::Table(t) => table = Some(t),
            DeValue::Array(a) => array = Some(a),
            _ => {}
        }
    }
    offset.map(|o| text[..o.min(text.len())].matches('\n').count() + 1)
}

/// 1-based line of a byte offset.
pub fn line_at(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_keys_tables_and_array_entries() {
        let text = "[scene]\nname = \"x\"\n\n[contact]\nlaw = \"ac\"\n\n[[contact.pairs]]\ntool = \"punch\"\n\n[[contact.pairs]]\ntool = \"die\"\n";
        assert_eq!(line_of(text, "scene.name"), Some(2));
        assert_eq!(line_of(text, "contact.law"), Some(5));
        assert_eq!(line_of(text, "contact.pairs[1].tool"), Some(11));
        // A missing key points at the deepest table found.
        assert_eq!(line_of(text, "contact.formulation"), Some(4));
        assert_eq!(line_of(text, "solver.dt"), None);
    }
}
