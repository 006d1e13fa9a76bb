//! Transcribed published data (`validation/published/*.toml`) with provenance.

use serde::Deserialize;

use crate::error::Error;

/// A number transcribed from a paper, exactly as printed.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PublishedValue {
    /// Id unique within the file, e.g. `table2.fc.160`.
    pub id: String,
    /// What it is, e.g. `f_c at ω1 = 160 rad/s (theory)`.
    pub quantity: String,
    /// Unit (`1` for dimensionless).
    pub unit: String,
    /// The digits as printed, as a string so that trailing zeros (precision) survive.
    pub printed: String,
    /// Where: `"Table 2, p. 12"`.
    pub source: String,
    /// A threshold (an onset on a swept parameter): its model side must be an interval
    /// (`cargo xtask validate --check`).
    #[serde(default)]
    pub threshold: bool,
    /// The parsed value (filled in from `printed`).
    #[serde(skip)]
    pub value: f64,
}

/// A statement transcribed from a paper.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PublishedClaim {
    /// Id unique within the file, e.g. `fig11.unilateral-onset`.
    pub id: String,
    /// The quote.
    pub text: String,
    /// Where: `"Sect. 3.4, p. 8"`.
    pub source: String,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PublishedFile {
    paper: String,
    #[serde(default)]
    notes: String,
    #[serde(default)]
    value: Vec<PublishedValue>,
    #[serde(default)]
    claim: Vec<PublishedClaim>,
}

/// The contents of one `validation/published/<paper>.toml` file.
///
/// Format:
///
/// ```toml
/// paper = "Karpov et al. 2017, Mech. Mach. Theory 114:1"
/// notes = "optional remarks on the transcription"
///
/// [[value]]
/// id = "table1.delta"
/// quantity = "speed fluctuation δ of the Table 1 pair"
/// unit = "1"
/// printed = "0.0125"          # a string: keeps the printed precision
/// source = "Table 1, p. 5"
///
/// [[claim]]
/// id = "fig5.monotone"
/// text = "the amplitude decreases as B grows"
/// source = "Sect. 4, p. 7"
/// ```
///
/// Load it with [`published!`](crate::published!) (compile-time include, so studies also run in
/// unit tests).
#[derive(Debug, Clone)]
pub struct Published {
    file: String,
    /// Citation line of the file.
    pub paper: String,
    /// Transcription remarks.
    pub notes: String,
    values: Vec<PublishedValue>,
    claims: Vec<PublishedClaim>,
}

impl Published {
    /// Parse the TOML text of a published-data file; `file` names it in errors.
    pub fn parse(file: &str, text: &str) -> Result<Self, Error> {
        let err = |reason: String| Error::PublishedParse {
            file: file.to_owned(),
            reason,
        };
        let raw: PublishedFile = toml::from_str(text).map_err(|e| err(e.to_string()))?;
        let mut values = raw.value;
        for v in &mut values {
            v.value = v.printed.trim().parse::<f64>().map_err(|_| {
                err(format!(
                    "value `{}`: printed `{}` is not a number",
                    v.id, v.printed
                ))
            })?;
            crate::format::half_last_digit(&v.printed)?;
        }
        let mut ids: Vec<&str> = values.iter().map(|v| v.id.as_str()).collect();
        ids.extend(raw.claim.iter().map(|c| c.id.as_str()));
        ids.sort_unstable();
        if let Some(w) = ids.windows(2).find(|w| w[0] == w[1]) {
            return Err(err(format!("duplicate id `{}`", w[0])));
        }
        Ok(Published {
            file: file.to_owned(),
            paper: raw.paper,
            notes: raw.notes,
            values,
            claims: raw.claim,
        })
    }

    /// The value with this id.
    pub fn value(&self, id: &str) -> Result<&PublishedValue, Error> {
        self.values
            .iter()
            .find(|v| v.id == id)
            .ok_or_else(|| Error::PublishedMissing {
                file: self.file.clone(),
                kind: "value",
                id: id.to_owned(),
            })
    }

    /// The claim with this id.
    pub fn claim(&self, id: &str) -> Result<&PublishedClaim, Error> {
        self.claims
            .iter()
            .find(|c| c.id == id)
            .ok_or_else(|| Error::PublishedMissing {
                file: self.file.clone(),
                kind: "claim",
                id: id.to_owned(),
            })
    }

    /// All values whose id starts with `prefix`, in file order.
    pub fn values_with_prefix<'a>(
        &'a self,
        prefix: &'a str,
    ) -> impl Iterator<Item = &'a PublishedValue> + 'a {
        self.values.iter().filter(move |v| v.id.starts_with(prefix))
    }
}

/// Load `published/<file>` (a link to the repository's `validation/published/`) at compile time and parse it:
/// `published!("karpov2017.toml")` → `Result<Published, Error>`.
#[macro_export]
macro_rules! published {
    ($file:literal) => {
        $crate::Published::parse(
            $file,
            include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/published/", $file)),
        )
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAMPLE: &str = r#"
paper = "Test"
[[value]]
id = "a"
quantity = "q"
unit = "Hz"
printed = "38.60"
source = "Table 2, p. 12"
[[claim]]
id = "c"
text = "it rattles"
source = "p. 9"
"#;

    #[test]
    fn parses_and_looks_up() {
        let p = Published::parse("sample", SAMPLE).unwrap();
        let v = p.value("a").unwrap();
        assert!((v.value - 38.6).abs() < 1e-12);
        assert_eq!(v.printed, "38.60");
        assert_eq!(p.claim("c").unwrap().text, "it rattles");
        assert!(p.value("b").is_err());
        assert!(p.claim("a").is_err());
    }

    #[test]
    fn rejects_bad_files() {
        assert!(Published::parse("x", "paper = 1").is_err());
        let dup = format!("{SAMPLE}\n[[claim]]\nid = \"a\"\ntext = \"t\"\nsource = \"s\"\n");
        assert!(Published::parse("x", &dup).is_err());
        let bad = SAMPLE.replace("38.60", "n/a");
        assert!(Published::parse("x", &bad).is_err());
    }

    #[test]
    fn committed_files_parse() {
        for (name, text) in [
            (
                "karpov2017.toml",
                include_str!("../published/karpov2017.toml"),
            ),
            ("liu2021.toml", include_str!("../published/liu2021.toml")),
            ("yu2021.toml", include_str!("../published/yu2021.toml")),
        ] {
            Published::parse(name, text).unwrap();
        }
    }
}
