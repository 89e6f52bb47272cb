//! `walks.csv`: one row per walk of a batch (`learn` with several walks, `survey`), the
//! walk's figures from `summary.json` flattened into columns, so a batch of a hundred walks
//! reads in a spreadsheet or one line of pandas.
//!
//! Nested members become dotted columns (`heading.source`), lists of numbers or words are
//! joined with `;`, a list of reasons (objects with a `code`) becomes their codes joined with
//! `;`; other lists are left out (they stay in `summary.json`). After `walk`, columns are in
//! alphabetical order; a member only some walks have is an empty cell in the others.

use anyhow::{Context, Result};
use serde::Serialize;
use serde_json::Value;

/// Adds `value`'s scalar members to `row` under `prefix`.
fn flatten(prefix: &str, value: &Value, row: &mut Vec<(String, String)>) {
    let key = |k: &str| {
        if prefix.is_empty() {
            k.to_owned()
        } else {
            format!("{prefix}.{k}")
        }
    };
    match value {
        Value::Object(members) => {
            for (k, v) in members {
                flatten(&key(k), v, row);
            }
        }
        Value::Array(items) => {
            let cells: Option<Vec<String>> = items
                .iter()
                .map(|item| match item {
                    Value::Object(o) => o.get("code").and_then(Value::as_str).map(str::to_owned),
                    Value::Array(_) | Value::Null => None,
                    scalar => Some(scalar_text(scalar)),
                })
                .collect();
            if let Some(cells) = cells {
                row.push((prefix.to_owned(), cells.join(";")));
            }
        }
        scalar => row.push((prefix.to_owned(), scalar_text(scalar))),
    }
}

/// A scalar as a cell: strings bare, null empty, numbers and booleans as JSON writes them.
fn scalar_text(value: &Value) -> String {
    match value {
        Value::String(s) => s.clone(),
        Value::Null => String::new(),
        other => other.to_string(),
    }
}

/// A batch's row under the walk's name (`track --walks`, `fingerprint --walks`): a `name`
/// column beside the report's.
#[derive(Debug, Serialize)]
pub(super) struct NamedRow<'a, T: Serialize> {
    /// The walk's name (its folder).
    pub name: &'a str,
    /// Its report.
    #[serde(flatten)]
    pub row: &'a T,
}

/// The CSV text of `walks`: a `walk` column (1-based), then each walk's flattened figures.
pub(super) fn walks_table<T: Serialize>(walks: &[T]) -> Result<Vec<u8>> {
    let mut rows: Vec<Vec<(String, String)>> = Vec::with_capacity(walks.len());
    for (i, w) in walks.iter().enumerate() {
        let value = serde_json::to_value(w).context("walk summary")?;
        let mut row = vec![("walk".to_owned(), (i + 1).to_string())];
        flatten("", &value, &mut row);
        rows.push(row);
    }
    let mut columns: Vec<String> = Vec::new();
    for row in &rows {
        for (k, _) in row {
            if !columns.contains(k) {
                columns.push(k.clone());
            }
        }
    }
    let mut out = csv::Writer::from_writer(Vec::new());
    out.write_record(&columns)?;
    for row in &rows {
        out.write_record(columns.iter().map(|c| {
            row.iter()
                .find(|(k, _)| k == c)
                .map_or("", |(_, v)| v.as_str())
        }))?;
    }
    out.into_inner().context("walks.csv")
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn nested_figures_become_dotted_columns() {
        let walks = [
            json!({"steps": 10, "quality": {"verdict": "ok", "reasons": []},
                   "heading": {"source": "gyro, fused"}, "spread": [1.5, 2.0]}),
            json!({"steps": 12, "quality": {"verdict": "poor",
                   "reasons": [{"code": "deaths", "message": "…"}, {"code": "climb"}]},
                   "extra": null}),
        ];
        let text = String::from_utf8(walks_table(&walks).expect("table")).expect("utf-8");
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[0],
            "walk,heading.source,quality.reasons,quality.verdict,spread,steps,extra"
        );
        assert_eq!(lines[1], "1,\"gyro, fused\",,ok,1.5;2.0,10,");
        assert_eq!(lines[2], "2,,deaths;climb,poor,,12,");
    }
}
