//! Base parameters from a regressor: which standard parameters fold into each base one, and
//! with what coefficients, found numerically where they depend on the robot's geometry.

use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;
use nalgebra::DMatrix;

/// A column the base columns reproduce to less than this, relative to the largest column of
/// the regressor, depends on them; more, and the robot has a base parameter they lack.
const SPAN_TOLERANCE: f64 = 1e-9;

/// A coefficient this close to an integer is that integer (the groupings are structural:
/// equal columns mostly), and one this small is zero.
const ROUNDING: f64 = 1e-9;

/// Per base parameter (column `leads[j]` of `y`), its terms `(standard index, coefficient)`,
/// the lead first with 1: each other column `k` of `y` is `Σ_j c_jk y_leads[j]`, and the base
/// parameter `j` gathers `c_jk π_k`. `None` when a column is not in the leads' span.
pub fn groups(y: &DMatrix<f64>, leads: &[usize]) -> Option<Vec<Vec<(usize, f64)>>> {
    let largest = (0..y.ncols())
        .map(|k| y.column(k).norm())
        .fold(0.0, f64::max);
    // Unit columns: the solve's tolerance means the same for masses and inertias.
    let scale: Vec<f64> = leads
        .iter()
        .map(|&k| 1.0 / y.column(k).norm().max(f64::MIN_POSITIVE))
        .collect();
    let yb = DMatrix::from_fn(y.nrows(), leads.len(), |r, j| y[(r, leads[j])] * scale[j]);
    let svd = yb.clone().svd(true, true);
    let mut groups: Vec<Vec<(usize, f64)>> = leads.iter().map(|&k| vec![(k, 1.0)]).collect();
    for k in (0..y.ncols()).filter(|k| !leads.contains(k)) {
        let column = y.column(k).into_owned();
        let c = svd.solve(&column, 1e-12).ok()?;
        if (&yb * &c - &column).norm() > SPAN_TOLERANCE * largest {
            return None;
        }
        for (j, group) in groups.iter_mut().enumerate() {
            let coefficient = tidy(c[j] * scale[j]);
            if coefficient != 0.0 {
                group.push((k, coefficient));
            }
        }
    }
    for group in &mut groups {
        group[1..].sort_by_key(|&(k, _)| k);
    }
    Some(groups)
}

/// `c` rounded to the integer it is within [`ROUNDING`] of.
fn tidy(c: f64) -> f64 {
    let nearest = c.round();
    if (c - nearest).abs() < ROUNDING {
        nearest
    } else {
        c
    }
}

/// A base parameter's name: its lead's, with `_R` (regrouped) when others fold into it.
pub fn name(standard: &[String], group: &[(usize, f64)]) -> String {
    let lead = &standard[group[0].0];
    if group.len() > 1 {
        format!("{lead}_R")
    } else {
        lead.clone()
    }
}

/// A base parameter as a readable relation, `platform_mass_R = platform_mass + leg1_rod_mass`.
pub fn relation(standard: &[String], group: &[(usize, f64)]) -> String {
    let mut out = format!("{} = {}", name(standard, group), standard[group[0].0]);
    for &(k, c) in &group[1..] {
        let (sign, magnitude) = if c < 0.0 { ("-", -c) } else { ("+", c) };
        if magnitude == 1.0 {
            out.push_str(&format!(" {sign} {}", standard[k]));
        } else {
            out.push_str(&format!(" {sign} {magnitude:.12}·{}", standard[k]));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dependent_columns_fold_into_their_leads_with_their_coefficients() {
        // Columns: a, b, 2a - 0.3b, a zero column, b.
        let a = [1.0, 2.0, -1.0, 0.5];
        let b = [0.0, 1.0, 3.0, -2.0];
        let y = DMatrix::from_fn(4, 5, |r, k| match k {
            0 => a[r],
            1 => b[r],
            2 => 2.0 * a[r] - 0.3 * b[r],
            3 => 0.0,
            _ => b[r],
        });
        let groups = groups(&y, &[0, 1]).unwrap();
        assert_eq!(groups[0], vec![(0, 1.0), (2, 2.0)]);
        assert_eq!(groups[1].len(), 3);
        assert!((groups[1][1].1 + 0.3).abs() < 1e-14 && groups[1][2] == (4, 1.0));
        let names: Vec<String> = ["a", "b", "c", "d", "e"].map(String::from).to_vec();
        assert_eq!(relation(&names, &groups[0]), "a_R = a + 2.000000000000·c");
        assert_eq!(
            relation(&names, &groups[1]),
            "b_R = b - 0.300000000000·c + e"
        );
    }

    #[test]
    fn a_column_outside_the_leads_span_is_refused() {
        let y = DMatrix::from_row_slice(3, 2, &[1.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
        assert!(groups(&y, &[0]).is_none());
    }
}
