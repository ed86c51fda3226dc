//! The workspace and its dexterity (feature `workspace`): over a grid of centres at one
//! orientation, or of orientations at one centre, which poses the robot reaches (within every
//! limit of its description, and regular) and how well conditioned it is there. Every
//! mechanism is served through [`Mechanism`], whatever its freedom: a platform that only
//! translates (the Delta) sweeps its centres, level.
//!
//! Two measures at each reachable pose (Merlet's): the inverse condition number of `J⁻¹`, its
//! angular columns divided by a characteristic length (the C5's half-spacing `L`, a hexapod's
//! platform radius) so that every column is in m/s (1 is isotropic, 0 singular), and the largest actuator
//! force per newton of load on the platform, `max_i |J_v,i|` (column `i` of `J`'s linear rows:
//! `Γ = Jᵀ (0; f)` for a unit force `f`).

use crate::platform::{Freedom, Mechanism};
use crate::{Error, Pose};
use nalgebra::{DMatrix, Matrix3, Matrix6, SymmetricEigen};

/// What a grid sweeps: the centre at a fixed orientation, or the orientation at a fixed centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sweep {
    /// Centres `(xc, yc, zc)` (m) at the RPY angles given (rad).
    Centres { orientation: [f64; 3] },
    /// RPY angles `(α, β, γ)` (rad) at the centre given (m).
    Orientations { centre: [f64; 3] },
}

/// A regular grid of `points³` poses over the box `[lower, upper]` of the swept coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    pub sweep: Sweep,
    pub lower: [f64; 3],
    pub upper: [f64; 3],
    /// Points per axis, at least 2.
    pub points: usize,
}

impl Grid {
    /// The spacing along each axis.
    pub fn step(&self) -> [f64; 3] {
        core::array::from_fn(|a| (self.upper[a] - self.lower[a]) / (self.points - 1) as f64)
    }

    /// The swept coordinates of grid point `index`.
    pub fn coordinates(&self, index: [usize; 3]) -> [f64; 3] {
        let h = self.step();
        core::array::from_fn(|a| self.lower[a] + index[a] as f64 * h[a])
    }

    /// The pose of grid point `index`, `[α β γ xc yc zc]`.
    pub fn pose(&self, index: [usize; 3]) -> Pose {
        let c = self.coordinates(index);
        match self.sweep {
            Sweep::Centres { orientation: o } => {
                Pose::from_array([o[0], o[1], o[2], c[0], c[1], c[2]])
            }
            Sweep::Orientations { centre: p } => {
                Pose::from_array([c[0], c[1], c[2], p[0], p[1], p[2]])
            }
        }
    }

    /// Grid point `index` in the coordinates of a platform of `freedom` ([`Freedom::pose_names`]):
    /// the whole pose, or the centre of a level platform.
    pub fn platform_pose(&self, index: [usize; 3], freedom: Freedom) -> alloc::vec::Vec<f64> {
        let pose = self.pose(index).to_array();
        pose[pose.len() - freedom.dimension()..].to_vec()
    }

    /// Whether a platform of `freedom` can take every pose of the grid: one that only
    /// translates takes level poses alone.
    fn fits(&self, freedom: Freedom) -> bool {
        freedom.turns()
            || matches!(self.sweep, Sweep::Centres { orientation } if orientation == [0.0; 3])
    }

    /// The volume a grid point stands for (m³, or rad³ for orientations).
    pub fn cell_volume(&self) -> f64 {
        self.step().iter().product()
    }
}

/// A reachable grid point and its dexterity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    pub index: [usize; 3],
    /// Inverse condition number of the normalised `J⁻¹`, in `(0, 1]`.
    pub inverse_condition: f64,
    /// The largest actuator force per newton of force on the platform (N/N).
    pub force_ratio: f64,
}

/// The reachable part of a grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Map {
    pub grid: Grid,
    /// The reachable points, in grid order (first axis slowest).
    pub reachable: Vec<Cell>,
    /// Every point of the grid.
    pub total: usize,
}

impl Map {
    /// The reachable volume: the points times the volume each stands for.
    pub fn volume(&self) -> f64 {
        self.reachable.len() as f64 * self.grid.cell_volume()
    }
}

/// The dexterity at `pose` (in the platform's coordinates), or `None` if the robot does not
/// reach it (a limit broken, a singular pose). A platform free in space has its angular
/// columns scaled by its characteristic length; one that only translates has none.
pub fn dexterity(robot: &dyn Mechanism, pose: &[f64]) -> Option<(f64, f64)> {
    let n = robot.freedom().dimension();
    robot.check_limits(pose).ok()?;
    let length = robot.spatial().map(|s| s.characteristic_length());
    let (mut jinv, mut jac) = (alloc::vec![0.0; n * n], alloc::vec![0.0; n * n]);
    robot.inverse_jacobian(pose, &mut jinv).ok()?;
    robot.jacobian(pose, &mut jac).ok()?;
    // The twist's angular part, where it has one, comes first.
    let angular = n - 3;
    if let Some(l) = length {
        for (k, x) in jinv.iter_mut().enumerate() {
            if k % n < angular {
                *x /= l;
            }
        }
    }
    let (lo, hi) = extreme_eigenvalues(&jinv, n);
    let inverse_condition = (lo.max(0.0) / hi).sqrt();
    let column = |i: usize| {
        (angular..n)
            .map(|r| jac[r * n + i] * jac[r * n + i])
            .sum::<f64>()
    };
    let force_ratio = (0..n).map(|i| column(i).sqrt()).fold(0.0, f64::max);
    (inverse_condition.is_finite() && force_ratio.is_finite())
        .then_some((inverse_condition, force_ratio))
}

/// The smallest and the largest eigenvalue of `NᵀN`, `N` the `n×n` row-major `m`: on the stack
/// for the freedoms' dimensions (a map solves a million), on the heap for any other.
fn extreme_eigenvalues(m: &[f64], n: usize) -> (f64, f64) {
    let extremes = |e: &mut dyn Iterator<Item = &f64>| {
        e.fold((f64::INFINITY, 0.0_f64), |(a, b), &e| (a.min(e), b.max(e)))
    };
    match n {
        3 => {
            let m = Matrix3::from_row_slice(m);
            extremes(&mut SymmetricEigen::new(m.transpose() * m).eigenvalues.iter())
        }
        6 => {
            let m = Matrix6::from_row_slice(m);
            extremes(&mut SymmetricEigen::new(m.transpose() * m).eigenvalues.iter())
        }
        _ => {
            let m = DMatrix::from_row_slice(n, n, m);
            extremes(&mut SymmetricEigen::new(m.transpose() * &m).eigenvalues.iter())
        }
    }
}

/// Maps the grid on every core; `progress` is called with the number of points done so far
/// (from any thread), about a hundred times.
///
/// # Errors
/// [`Error::Invalid`] for a grid of fewer than 2 points per axis, a box that is empty or not
/// finite, more than 10⁸ points, or poses the platform cannot take (a turned one, or
/// orientations swept, for a platform that only translates).
pub fn map(
    robot: &dyn Mechanism,
    grid: &Grid,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Map, Error> {
    let ok = (0..3).all(|a| {
        grid.lower[a].is_finite() && grid.upper[a].is_finite() && grid.lower[a] < grid.upper[a]
    });
    if !ok {
        return Err(Error::Invalid {
            what: "workspace grid",
            rule: "each axis needs finite bounds with lower < upper",
        });
    }
    if !grid.fits(robot.freedom()) {
        return Err(Error::Invalid {
            what: "workspace grid",
            rule: "a platform that only translates sweeps its centres, level",
        });
    }
    if grid.points < 2 || grid.points > 464 {
        return Err(Error::Invalid {
            what: "workspace grid",
            rule: "2 to 464 points per axis (at most 10⁸ poses)",
        });
    }
    let n = grid.points;
    let freedom = robot.freedom();
    let threads = std::thread::available_parallelism()
        .map_or(1, |t| t.get())
        .min(n);
    let next = std::sync::atomic::AtomicUsize::new(0);
    let done = std::sync::atomic::AtomicUsize::new(0);
    let slices: Vec<(usize, Vec<Cell>)> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        if i >= n {
                            break mine;
                        }
                        let mut cells = Vec::new();
                        for j in 0..n {
                            for k in 0..n {
                                let index = [i, j, k];
                                if let Some((inverse_condition, force_ratio)) =
                                    dexterity(robot, &grid.platform_pose(index, freedom))
                                {
                                    cells.push(Cell {
                                        index,
                                        inverse_condition,
                                        force_ratio,
                                    });
                                }
                            }
                        }
                        mine.push((i, cells));
                        let total = done.fetch_add(n * n, std::sync::atomic::Ordering::Relaxed);
                        progress(total + n * n);
                    }
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("a workspace thread does not panic"))
            .collect()
    });
    let mut slices = slices;
    slices.sort_by_key(|(i, _)| *i);
    Ok(Map {
        grid: *grid,
        reachable: slices.into_iter().flat_map(|(_, c)| c).collect(),
        total: n * n * n,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::platform::load;
    use crate::Model;
    use alloc::boxed::Box;
    use alloc::vec::Vec;
    use c5_robot::Description;

    fn delta() -> Box<dyn Mechanism> {
        load(
            Description::Delta(c5_robot::Delta::example()),
            Model::Consistent,
        )
        .unwrap()
    }

    /// A grid of centres about the Delta's home, level, symmetric in `y` about its base's
    /// mirror plane.
    fn about_home(robot: &dyn Mechanism, points: usize) -> Grid {
        let home = robot.home();
        let c = [home[0], home[1], home[2]];
        Grid {
            sweep: Sweep::Centres {
                orientation: [0.0; 3],
            },
            lower: core::array::from_fn(|k| c[k] - 0.3),
            upper: core::array::from_fn(|k| c[k] + 0.3),
            points,
        }
    }

    /// `∂f/∂x` by central differences, row-major: `f` maps 3 numbers to 3.
    fn differenced(x: &[f64], f: impl Fn(&[f64]) -> Vec<f64>) -> Vec<f64> {
        let h = 1e-6;
        let mut d = alloc::vec![0.0; 9];
        for j in 0..3 {
            let (mut up, mut down) = (x.to_vec(), x.to_vec());
            up[j] += h;
            down[j] -= h;
            let (a, b) = (f(&up), f(&down));
            for i in 0..3 {
                d[i * 3 + j] = (a[i] - b[i]) / (2.0 * h);
            }
        }
        d
    }

    /// The Delta's measures from its kinematics alone, differenced: `J⁻¹ = ∂θ/∂C` from the
    /// inverse kinematics, its singular values' ratio; `J = ∂C/∂θ` from the closed-form
    /// forward kinematics, the longest of its columns (a unit force's largest torque,
    /// `Γ = Jᵀ f`, by virtual work).
    #[test]
    fn the_deltas_measures_are_its_kinematics_differenced() {
        let robot = delta();
        let grid = about_home(robot.as_ref(), 7);
        let mut checked = 0;
        for index in [[3, 3, 3], [1, 4, 2], [5, 0, 4], [2, 6, 1], [0, 2, 6]] {
            let pose = grid.platform_pose(index, robot.freedom());
            let Some((inverse_condition, force_ratio)) = dexterity(robot.as_ref(), &pose) else {
                continue;
            };
            let angles = |x: &[f64]| {
                let mut q = alloc::vec![0.0; 3];
                robot.actuator_positions(x, &mut q).unwrap();
                q
            };
            let jinv = differenced(&pose, angles);
            let sv = nalgebra::Matrix3::from_row_slice(&jinv).singular_values();
            let expected = sv.min() / sv.max();
            assert!(
                (inverse_condition - expected).abs() < 1e-6 * expected,
                "{index:?}: {inverse_condition} against {expected}"
            );
            let q = angles(&pose);
            let near = |t: &[f64]| {
                let (mut position, mut twist, mut accel) = ([0.0; 3], [0.0; 3], [0.0; 3]);
                robot
                    .joint_state(
                        [t, &[0.0; 3], &[0.0; 3]],
                        Some(&pose),
                        [&mut position, &mut twist, &mut accel],
                    )
                    .unwrap();
                position.to_vec()
            };
            let jac = differenced(&q, near);
            let longest = (0..3)
                .map(|i| (0..3).map(|r| jac[r * 3 + i].powi(2)).sum::<f64>().sqrt())
                .fold(0.0, f64::max);
            assert!(
                (force_ratio - longest).abs() < 1e-6 * longest,
                "{index:?}: {force_ratio} against {longest}"
            );
            checked += 1;
        }
        assert!(checked >= 4, "only {checked} of the poses reached");
    }

    /// The example Delta is its own mirror image in `y` (its first arm in the plane `y = 0`,
    /// the other two each other's image), so is its map: a centre is reached exactly where
    /// its image is, with the same measures. A centre left out is one the inverse kinematics
    /// refuses or where the legs cannot hold the platform.
    #[test]
    fn the_deltas_map_is_mirror_symmetric_and_leaves_out_only_what_it_cannot_reach() {
        let robot = delta();
        let n = 15;
        let grid = about_home(robot.as_ref(), n);
        let m = map(robot.as_ref(), &grid, &|_| {}).unwrap();
        assert_eq!(m.total, n * n * n);
        assert!(m.reachable.len() > m.total / 4 && m.reachable.len() < m.total);
        let at = |index: [usize; 3]| m.reachable.iter().find(|c| c.index == index);
        for cell in &m.reachable {
            let [i, j, k] = cell.index;
            let image = at([i, n - 1 - j, k]).expect("the mirror image is reached");
            assert!((image.inverse_condition - cell.inverse_condition).abs() < 1e-9);
            assert!((image.force_ratio - cell.force_ratio).abs() < 1e-9);
        }
        let mut refused = 0;
        for index in (0..n * n * n).map(|p| [p / (n * n), p / n % n, p % n]) {
            if at(index).is_some() {
                continue;
            }
            let pose = grid.platform_pose(index, robot.freedom());
            let (mut q, mut jac) = ([0.0; 3], [0.0; 9]);
            let out_of_reach = robot.actuator_positions(&pose, &mut q).is_err()
                || robot.jacobian(&pose, &mut jac).is_err();
            assert!(out_of_reach, "{index:?} is reachable but left out");
            refused += 1;
        }
        assert_eq!(refused + m.reachable.len(), m.total);
    }

    #[test]
    fn a_platform_that_only_translates_is_not_turned_by_the_grid() {
        let robot = delta();
        let level = about_home(robot.as_ref(), 3);
        let turned = Grid {
            sweep: Sweep::Centres {
                orientation: [0.1, 0.0, 0.0],
            },
            ..level
        };
        let orientations = Grid {
            sweep: Sweep::Orientations {
                centre: [0.0, 0.0, -0.5],
            },
            ..level
        };
        for grid in [turned, orientations] {
            let refused = map(robot.as_ref(), &grid, &|_| {}).unwrap_err();
            assert!(refused.to_string().contains("only translates"), "{refused}");
        }
        assert_eq!(map(robot.as_ref(), &level, &|_| {}).unwrap().total, 27);
    }
}
