//! Operation counts of a kernel, and the chapter's `m`/`a` convention beside them.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;

/// Counted operations of one straight-line kernel.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct OpCount {
    pub mul: u32,
    pub div: u32,
    /// Additions and subtractions.
    pub add: u32,
    pub neg: u32,
    /// Calls by function name (`sin`, `cos`, `sqrt`).
    pub calls: BTreeMap<String, u32>,
}

impl OpCount {
    /// Multiplications in the chapter's convention: a division costs one multiplication.
    pub fn chapter_m(&self) -> u32 {
        self.mul + self.div
    }

    /// Additions in the chapter's convention (sign changes are not counted there).
    pub fn chapter_a(&self) -> u32 {
        self.add
    }

    pub fn total_calls(&self) -> u32 {
        self.calls.values().sum()
    }

    /// The scalar cost the optimizer minimises: a division weighs a little under two
    /// multiplications (so two divisions beat a shared reciprocal and two multiplications, but
    /// three do not), a call twenty, a sign change a quarter.
    pub fn weight(&self) -> f64 {
        f64::from(self.mul + self.add)
            + 1.9 * f64::from(self.div)
            + 0.25 * f64::from(self.neg)
            + 20.0 * f64::from(self.total_calls())
    }
}

impl fmt::Display for OpCount {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} mul, {} div, {} add, {} neg",
            self.mul, self.div, self.add, self.neg
        )?;
        for (name, n) in &self.calls {
            write!(f, ", {n} {name}")?;
        }
        write!(
            f,
            " (chapter convention: {}m + {}a)",
            self.chapter_m(),
            self.chapter_a()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn division_counts_as_multiplication_in_chapter_convention() {
        let c = OpCount {
            mul: 4,
            div: 3,
            add: 9,
            neg: 6,
            calls: BTreeMap::from([("sin".to_string(), 3)]),
        };
        assert_eq!((c.chapter_m(), c.chapter_a(), c.total_calls()), (7, 9, 3));
        assert_eq!(
            c.to_string(),
            "4 mul, 3 div, 9 add, 6 neg, 3 sin (chapter convention: 7m + 9a)"
        );
    }
}
