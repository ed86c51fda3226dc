//! The workspace and its dexterity (feature `workspace`): over a grid of centres at one
//! orientation, or of orientations at one centre, which poses the robot reaches (within every
//! limit of its description, and regular) and how well conditioned it is there.
//!
//! Two measures at each reachable pose (Merlet's): the inverse condition number of `J⁻¹`, its
//! angular columns divided by a characteristic length (the C5's half-spacing `L`, a hexapod's
//! platform radius) so that every column is in m/s (1 is isotropic, 0 singular), and the largest actuator
//! force per newton of load on the platform, `max_i |J_v,i|` (column `i` of `J`'s linear rows:
//! `Γ = Jᵀ (0; f)` for a unit force `f`).

use crate::{Error, ParallelRobot, Pose};
use nalgebra::{Matrix6, SymmetricEigen};

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

    /// The pose of grid point `index`.
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

/// The dexterity at `pose`, or `None` if the robot does not reach it (a limit broken, a
/// singular pose).
pub fn dexterity(robot: &dyn ParallelRobot, pose: &Pose) -> Option<(f64, f64)> {
    robot.check_limits(pose).ok()?;
    let jinv = robot.inverse_jacobian(pose).ok()?;
    let jac = robot.jacobian(pose).ok()?;
    let l = robot.characteristic_length();
    let n = Matrix6::from_fn(|i, j| jinv[i][j] / if j < 3 { l } else { 1.0 });
    let eigen = SymmetricEigen::new(n.transpose() * n).eigenvalues;
    let (lo, hi) = eigen
        .iter()
        .fold((f64::INFINITY, 0.0_f64), |(a, b), &e| (a.min(e), b.max(e)));
    let inverse_condition = (lo.max(0.0) / hi).sqrt();
    let force_ratio = (0..6)
        .map(|i| (jac[3][i] * jac[3][i] + jac[4][i] * jac[4][i] + jac[5][i] * jac[5][i]).sqrt())
        .fold(0.0, f64::max);
    (inverse_condition.is_finite() && force_ratio.is_finite())
        .then_some((inverse_condition, force_ratio))
}

/// Maps the grid on every core; `progress` is called with the number of points done so far
/// (from any thread), about a hundred times.
///
/// # Errors
/// [`Error::Invalid`] for a grid of fewer than 2 points per axis, a box that is empty or not
/// finite, or more than 10⁸ points.
pub fn map(
    robot: &dyn ParallelRobot,
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
    if grid.points < 2 || grid.points > 464 {
        return Err(Error::Invalid {
            what: "workspace grid",
            rule: "2 to 464 points per axis (at most 10⁸ poses)",
        });
    }
    let n = grid.points;
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
                                    dexterity(robot, &grid.pose(index))
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
