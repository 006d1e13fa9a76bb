//! The record of one solved point: output columns pushed with their name, unit and value
//! together, so that no column is matched to its value by position.

/// One output of a point.
#[derive(Debug, Clone, PartialEq)]
pub struct Output {
    /// Column name.
    pub name: String,
    /// Unit (`1`: dimensionless).
    pub unit: String,
    /// Value.
    pub value: f64,
}

/// The outputs of one solved point, in column order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Record {
    columns: Vec<Output>,
}

impl Record {
    /// An empty record.
    pub fn new() -> Self {
        Record::default()
    }

    /// Append the column `name [unit] = value`.
    pub fn push(&mut self, name: &str, unit: &str, value: f64) -> &mut Self {
        self.columns.push(Output {
            name: name.to_owned(),
            unit: unit.to_owned(),
            value,
        });
        self
    }

    /// Append every column of `other`.
    pub fn append(&mut self, other: Record) -> &mut Self {
        self.columns.extend(other.columns);
        self
    }

    /// The columns in order.
    pub fn columns(&self) -> &[Output] {
        &self.columns
    }

    /// The value of the column `name`, if present.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.columns
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.value)
    }

    /// The values in column order.
    pub fn values(&self) -> Vec<f64> {
        self.columns.iter().map(|c| c.value).collect()
    }

    /// Number of columns.
    pub fn len(&self) -> usize {
        self.columns.len()
    }

    /// True if there is no column.
    pub fn is_empty(&self) -> bool {
        self.columns.is_empty()
    }

    /// The values for the declared `outputs` `(name, unit)`: `Err` (naming the first
    /// difference) unless the record holds exactly those columns, in that order.
    pub fn values_for(&self, outputs: &[(String, String)]) -> Result<Vec<f64>, String> {
        if self.columns.len() != outputs.len() {
            return Err(format!(
                "internal error: {} outputs for {} columns",
                self.columns.len(),
                outputs.len()
            ));
        }
        for (c, (n, u)) in self.columns.iter().zip(outputs) {
            if c.name != *n || c.unit != *u {
                return Err(format!(
                    "internal error: output `{}` [{}] where column `{n}` [{u}] is declared",
                    c.name, c.unit
                ));
            }
        }
        Ok(self.values())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_follow_the_declared_columns_or_fail() {
        let mut r = Record::new();
        r.push("a", "m", 1.0).push("b", "1", 2.0);
        let decl = vec![
            ("a".to_owned(), "m".to_owned()),
            ("b".to_owned(), "1".to_owned()),
        ];
        assert_eq!(r.values_for(&decl).unwrap(), vec![1.0, 2.0]);
        let swapped = vec![decl[1].clone(), decl[0].clone()];
        assert!(r.values_for(&swapped).unwrap_err().contains("`a` [m]"));
        assert!(r.values_for(&decl[..1]).is_err());
        assert_eq!(r.get("b"), Some(2.0));
        assert_eq!(r.get("c"), None);
    }
}
