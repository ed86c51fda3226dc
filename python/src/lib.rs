//! `c5_kernels`: the generated kernels of the C5 robot and of any mechanism a robot file
//! describes (the Gough–Stewart platform, the rotary hexapod, the Delta), for numpy.
//!
//! Every method takes one state (vectors of shape `(6,)` or `(3,)`) or a batch (`(N, 6)`,
//! `(N, 3)`) and returns arrays of the matching shape. Inputs that are contiguous `float64`
//! arrays are read in place; anything else array-like is converted once by numpy. The work runs
//! without the GIL, in Rust, the inverse and forward dynamics four states at a time through the
//! batch kernels (each lane computing exactly what the single-state kernel does).

use c5_runtime::calibrate::{self, Measurement, Noise, Options};
use c5_runtime::derivatives::SlicedDerivatives;
use c5_runtime::identify::{BaseParameters, Friction, Identifier};
use c5_runtime::plan;
use c5_runtime::platform::Freedom;
use c5_runtime::{
    Acceleration, Description, Error, Mechanism, Model, Pose, SpatialRobot, State, Twist,
    C5 as Robot5,
};
use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{
    AllowTypeChange, IntoPyArray, PyArray1, PyArrayDyn, PyArrayLikeDyn, PyArrayMethods,
    PyUntypedArrayMethods,
};
use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use std::borrow::Cow;
use std::sync::OnceLock;

create_exception!(
    c5_kernels,
    SingularPoseError,
    PyValueError,
    "A pose, or actuator positions, where the kernels would divide by (nearly) zero: a divisor \
     of eq 16 (r11, r22, r33) or the forward singularity term 1 + abc below 1e-9, a hexapod's \
     U joint or legs' hold at its singularity; or a call nearer a singularity than its own \
     bound (the forward dynamics within 1e-2 of eq 16's, 1e-4 in the paper model), where it \
     cannot be served to 1e-8. The message names the term, its value and the row."
);

type Array<'py> = PyArrayLikeDyn<'py, f64, AllowTypeChange>;

/// One argument, read as `n` rows of `width` numbers.
struct Rows<'a> {
    data: Cow<'a, [f64]>,
    width: usize,
}

impl Rows<'_> {
    fn row<const W: usize>(&self, k: usize) -> [f64; W] {
        std::array::from_fn(|i| self.data[k * self.width + i])
    }

    /// Row `k`.
    fn slice(&self, k: usize) -> &[f64] {
        &self.data[k * self.width..(k + 1) * self.width]
    }
}

/// Row `k` of each of `rows` in turn into `out`: a pose, a twist from its parts (`ω`, `v_C`), or
/// an acceleration from its.
fn gather(rows: &[Rows<'_>], k: usize, out: &mut [f64]) {
    let mut at = 0;
    for r in rows {
        let part = r.slice(k);
        out[at..at + part.len()].copy_from_slice(part);
        at += part.len();
    }
}

/// The shape of a call: `n` rows, and whether they came as one vector (returned unbatched).
#[derive(Clone, Copy)]
struct Batch {
    n: usize,
    single: bool,
}

/// Reads `array` as rows of `width`, checking its shape against the call's.
fn rows<'a>(
    name: &str,
    width: usize,
    array: &'a Array<'_>,
    batch: &mut Option<Batch>,
) -> PyResult<Rows<'a>> {
    let shape = array.shape();
    let this = match *shape {
        [w] if w == width => Batch { n: 1, single: true },
        [n, w] if w == width => Batch { n, single: false },
        _ => {
            return Err(PyValueError::new_err(format!(
                "`{name}` must have shape ({width},) or (N, {width}), got {shape:?}"
            )))
        }
    };
    match batch {
        Some(b) if b.single != this.single || b.n != this.n => {
            return Err(PyValueError::new_err(format!(
                "`{name}` has {} row(s) {}, the other arguments {} {}",
                this.n,
                if this.single {
                    "as a vector"
                } else {
                    "as a batch"
                },
                b.n,
                if b.single {
                    "as a vector"
                } else {
                    "as a batch"
                },
            )))
        }
        _ => *batch = Some(this),
    }
    // `as_slice` also takes a Fortran-ordered array, whose memory is not row-major.
    let data = match array.as_slice() {
        Ok(s) if array.is_c_contiguous() => Cow::Borrowed(s),
        // A view with strides, or Fortran order: its elements in row-major order.
        _ => Cow::Owned(array.as_array().iter().copied().collect()),
    };
    Ok(Rows { data, width })
}

/// Rows of zeros for an omitted argument.
fn zeros(width: usize, n: usize) -> Rows<'static> {
    Rows {
        data: Cow::Owned(vec![0.0; width * n]),
        width,
    }
}

/// What to do with a row the kernels refuse.
#[derive(Clone, Copy, PartialEq, Eq)]
enum OnError {
    /// Raise, naming the row.
    Raise,
    /// NaN in its results, and `True` in the mask returned last.
    Nan,
}

fn on_error(errors: &str) -> PyResult<OnError> {
    match errors {
        "raise" => Ok(OnError::Raise),
        "nan" => Ok(OnError::Nan),
        other => Err(PyValueError::new_err(format!(
            "errors must be \"raise\" or \"nan\", got {other:?}"
        ))),
    }
}

/// The Python exception for a refused row.
fn exception(row: usize, single: bool, e: &Error) -> PyErr {
    let at = if single {
        String::new()
    } else {
        format!(" (row {row})")
    };
    match e {
        Error::Singular { .. }
        | Error::Singularity { .. }
        | Error::ForwardSingular { .. }
        | Error::IllConditioned { .. } => SingularPoseError::new_err(format!("{e}{at}")),
        _ => PyValueError::new_err(format!("{e}{at}")),
    }
}

/// The results of a call, written straight into the numpy arrays it returns: `data[j]` is
/// output `j`, row-major, `widths[j]` numbers a row.
struct Outputs<'a> {
    data: Vec<&'a mut [f64]>,
    widths: Vec<usize>,
    bad: Vec<bool>,
    first_error: Option<(usize, Error)>,
}

impl Outputs<'_> {
    /// Row `k` of output `j`.
    fn slot(&mut self, j: usize, k: usize) -> &mut [f64] {
        let w = self.widths[j];
        &mut self.data[j][k * w..(k + 1) * w]
    }

    fn put(&mut self, j: usize, k: usize, values: &[f64]) {
        self.slot(j, k).copy_from_slice(values);
    }

    /// Marks row `k` refused: NaN everywhere, and the error kept if it is the first.
    fn refuse(&mut self, k: usize, e: Error) {
        self.bad[k] = true;
        for j in 0..self.data.len() {
            self.slot(j, k).fill(f64::NAN);
        }
        if self.first_error.is_none() {
            self.first_error = Some((k, e));
        }
    }
}

/// Makes the arrays of a call (`shapes` a row's, unbatched for one vector), fills them by
/// `fill` without the GIL, and returns them, the mask last with `errors="nan"`; with
/// `errors="raise"`, the first refused row's error.
fn call<'py, F>(
    py: Python<'py>,
    batch: Batch,
    mode: OnError,
    shapes: &[&[usize]],
    fill: F,
) -> PyResult<Bound<'py, PyAny>>
where
    F: FnOnce(&mut Outputs) + Send,
{
    let arrays: Vec<Bound<'py, PyArrayDyn<f64>>> = shapes
        .iter()
        .map(|shape| {
            let mut full = if batch.single { vec![] } else { vec![batch.n] };
            full.extend_from_slice(shape);
            PyArrayDyn::zeros(py, IxDyn(&full), false)
        })
        .collect();
    let mut data = Vec::with_capacity(arrays.len());
    for array in &arrays {
        // SAFETY: the arrays were just made, C-contiguous, and nothing else refers to them
        // until they are returned.
        data.push(
            unsafe { array.as_slice_mut() }.map_err(|e| PyValueError::new_err(e.to_string()))?,
        );
    }
    let mut out = Outputs {
        data,
        widths: shapes.iter().map(|s| s.iter().product()).collect(),
        bad: vec![false; batch.n],
        first_error: None,
    };
    py.detach(|| fill(&mut out));
    let Outputs {
        bad, first_error, ..
    } = out;
    if let (OnError::Raise, Some((k, e))) = (mode, &first_error) {
        return Err(exception(*k, batch.single, e));
    }
    let mut items: Vec<Bound<'py, PyAny>> = arrays.into_iter().map(Bound::into_any).collect();
    if mode == OnError::Nan {
        let rows = [batch.n];
        let shape = IxDyn(if batch.single { &[] } else { &rows[..] });
        let mask =
            ArrayD::from_shape_vec(shape, bad).map_err(|e| PyValueError::new_err(e.to_string()))?;
        items.push(mask.into_pyarray(py).into_any());
    }
    Ok(if items.len() == 1 {
        items.swap_remove(0)
    } else {
        PyTuple::new(py, items)?.into_any()
    })
}

/// [`call`] with `f` on every row: its results, or the row refused.
fn each_row<'py, F>(
    py: Python<'py>,
    batch: Batch,
    mode: OnError,
    shapes: &[&[usize]],
    f: F,
) -> PyResult<Bound<'py, PyAny>>
where
    F: Fn(usize, &mut Outputs) -> Result<(), Error> + Sync,
{
    call(py, batch, mode, shapes, |out| {
        for k in 0..batch.n {
            if let Err(e) = f(k, out) {
                out.refuse(k, e);
            }
        }
    })
}

/// The platform state of row `k` of the five motion arguments of a platform free in space
/// (pose, ω, v_C, ω̇, a_C).
fn motion6(r: &[Rows<'_>], k: usize) -> State {
    State {
        pose: Pose::from_array(r[0].row(k)),
        twist: Twist {
            omega: r[1].row(k),
            velocity: r[2].row(k),
        },
        accel: Acceleration {
            omega_dot: r[3].row(k),
            linear: r[4].row(k),
        },
    }
}

/// A numpy vector.
fn vector(py: Python<'_>, values: Vec<f64>) -> Bound<'_, PyArrayDyn<f64>> {
    PyArray1::from_vec(py, values).to_dyn().clone()
}

/// The actuators' motion arguments (`q`, `qd`, `qdd`), as `C5::read` takes them.
fn joint_args<'a, 'py>(
    n: usize,
    q: &'a Array<'py>,
    qd: &'a Option<Array<'py>>,
    qdd: &'a Option<Array<'py>>,
) -> [(&'static str, usize, Option<&'a Array<'py>>); 3] {
    [
        ("q", n, Some(q)),
        ("qd", n, qd.as_ref()),
        ("qdd", n, qdd.as_ref()),
    ]
}

/// A parallel robot from its description: the C5 joint parallel robot (the default, with a
/// model of its legs' mechanism) or any mechanism a robot file names (`mechanism =
/// "gough-stewart"`, `"rus-hexapod"`, `"delta"`).
///
/// Conventions (as the Rust crates): SI units and radians; pose `[α β γ xc yc zc]` with
/// `R = Rx(α) Ry(β) Rz(γ)`; twist `ω`, `v_C` at the platform centre, base frame; classical
/// accelerations `ω̇`, `a_C = d v_C/dt`; actuators in order. The C5's `q` is the ball
/// centre's position along the actuator axis, a positive force pushing the rod along `+n_i`;
/// a Gough–Stewart platform's `q` is the leg's length (plus its encoder offset), a positive
/// force extending the leg; a rotary hexapod's or a Delta's is the motor's angle (plus its
/// encoder offset), a positive torque turning it positive. A Delta's platform only translates:
/// its `dimension` is 3, its pose `[xc yc zc]`, its calls take `velocity` and `acceleration`
/// (no `omega`, `omega_dot`) and three actuators (identification too); what needs six
/// freedoms (the task-space terms, the joint-space dynamics, derivatives) raises a
/// `ValueError` naming it.
#[pyclass(module = "c5_kernels", name = "Robot", frozen)]
struct C5 {
    inner: Box<dyn Mechanism>,
    /// Found on first use: a hexapod's groupings take a few hundred microseconds.
    base: OnceLock<Result<BaseParameters, String>>,
}

/// The robot file `robot`'s description, the chapter's C5 for `None`.
fn read_description(robot: Option<std::path::PathBuf>) -> PyResult<Description> {
    match robot {
        None => Ok(Description::default()),
        Some(path) => {
            Description::from_toml_file(&path).map_err(|e| PyValueError::new_err(e.to_string()))
        }
    }
}

fn load(model: &str, robot: Option<std::path::PathBuf>) -> PyResult<Box<dyn Mechanism>> {
    let model: Model = model
        .parse()
        .map_err(|e: c5_robot::Error| PyValueError::new_err(e.to_string()))?;
    c5_runtime::platform::load(read_description(robot)?, model)
        .map_err(|e| PyValueError::new_err(e.to_string()))
}

/// What only the C5 serves, refused for another mechanism.
fn unsupported(what: &'static str, mechanism: &'static str) -> Error {
    Error::Unsupported {
        what,
        mechanism,
        why: "it is the C5's alone",
    }
}

/// The parts of a platform's twist (or acceleration) as arguments, for its freedom: `ω` and
/// `v_C`, or `v_C` alone, `omega` refused when given to a platform that only translates.
fn parts<'a, 'py>(
    freedom: Freedom,
    mechanism: &'static str,
    [angular, linear]: [(&'static str, &'a Option<Array<'py>>); 2],
) -> PyResult<Vec<(&'static str, usize, Option<&'a Array<'py>>)>> {
    match freedom {
        Freedom::Free => Ok(vec![
            (angular.0, 3, angular.1.as_ref()),
            (linear.0, 3, linear.1.as_ref()),
        ]),
        Freedom::Translations => match angular.1 {
            Some(_) => Err(PyValueError::new_err(format!(
                "this {mechanism}'s platform only translates: it takes no `{}`",
                angular.0
            ))),
            None => Ok(vec![(linear.0, 3, linear.1.as_ref())]),
        },
    }
}

impl C5 {
    /// The robot's mechanism in `format`; the paper model is not a mechanism.
    fn export(&self, format: c5_robot::Format) -> PyResult<String> {
        let model = Model::ALL
            .into_iter()
            .find(|m| m.name() == self.inner.model_name())
            .unwrap_or_default();
        c5_runtime::mechanism::export(&self.inner.description(), model, format)
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// The robot as a platform free in space, for what only six freedoms serve.
    fn spatial(&self, what: &'static str) -> PyResult<&dyn SpatialRobot> {
        self.inner.spatial().ok_or_else(|| {
            PyValueError::new_err(
                Error::Unsupported {
                    what,
                    mechanism: self.inner.mechanism(),
                    why: "its platform only translates, and this is served for platforms free \
                          in space",
                }
                .to_string(),
            )
        })
    }

    /// The platform's dimension: the pose's coordinates, and the actuators.
    fn dimension(&self) -> usize {
        self.inner.freedom().dimension()
    }

    /// The arguments of a platform's motion for this robot's freedom: the pose, the twist's
    /// parts and the acceleration's (`ω`, `v_C`, `ω̇`, `a_C`; `v_C`, `a_C` for a platform
    /// that only translates). The rows read hold them in that order.
    fn motion_spec<'a, 'py>(
        &self,
        pose: &'a Array<'py>,
        [omega, velocity, omega_dot, acceleration]: [&'a Option<Array<'py>>; 4],
    ) -> PyResult<Vec<(&'static str, usize, Option<&'a Array<'py>>)>> {
        let (freedom, name) = (self.inner.freedom(), self.inner.mechanism());
        let mut spec = vec![("pose", self.dimension(), Some(pose))];
        spec.extend(parts(
            freedom,
            name,
            [("omega", omega), ("velocity", velocity)],
        )?);
        spec.extend(parts(
            freedom,
            name,
            [("omega_dot", omega_dot), ("acceleration", acceleration)],
        )?);
        Ok(spec)
    }

    /// The twist's rows among those [`C5::motion_spec`] (or a spec that starts as it does)
    /// reads: after the pose, one or two.
    fn twist_rows(&self) -> std::ops::Range<usize> {
        match self.inner.freedom() {
            Freedom::Free => 1..3,
            Freedom::Translations => 1..2,
        }
    }

    /// The acceleration's rows among those [`C5::motion_spec`] reads.
    fn acceleration_rows(&self) -> std::ops::Range<usize> {
        let twist = self.twist_rows();
        twist.end..twist.end + twist.len()
    }

    /// The shapes of a twist's (or an acceleration's) outputs: `ω` and `v_C`, or `v_C`.
    fn part_shapes(&self) -> &'static [&'static [usize]] {
        match self.inner.freedom() {
            Freedom::Free => &[&[3], &[3]],
            Freedom::Translations => &[&[3]],
        }
    }

    /// `values`, a twist or an acceleration, into its parts' outputs from output `first`.
    fn scatter(&self, out: &mut Outputs, first: usize, k: usize, values: &[f64]) {
        for (j, part) in values.chunks(3).enumerate() {
            out.put(first + j, k, part);
        }
    }

    /// The robot as a C5, for what only the C5 serves.
    fn c5(&self, what: &'static str) -> PyResult<&Robot5> {
        self.spatial(what)?
            .as_any()
            .downcast_ref::<Robot5>()
            .ok_or_else(|| {
                PyValueError::new_err(unsupported(what, self.inner.mechanism()).to_string())
            })
    }

    /// The robot's exact derivatives, refused for a mechanism without them generated.
    fn derivatives(&self) -> PyResult<&dyn SlicedDerivatives> {
        c5_runtime::derivatives::sliced_derivatives_of(&*self.inner)
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// The platform's motion `[pose, twist, acceleration]` of row `k` of rows read by
    /// [`C5::motion_spec`].
    fn motion_row(&self, r: &[Rows<'_>], k: usize) -> [Vec<f64>; 3] {
        let n = self.dimension();
        let (twist, accel) = (self.twist_rows(), self.acceleration_rows());
        let mut motion = [0; 3].map(|_| vec![0.0; n]);
        let [x, v, a] = &mut motion;
        gather(&r[..1], k, x);
        gather(&r[twist], k, v);
        gather(&r[accel], k, a);
        motion
    }

    /// `Γ` from the actuators' positions, rates and accelerations (`joints`' rows), one row at a
    /// time through [`Mechanism::inverse_dynamics_joint`]: for a platform with fewer freedoms,
    /// which has no batch kernels.
    fn joint_forces<'py>(
        &self,
        py: Python<'py>,
        batch: Batch,
        mode: OnError,
        joints: [&Rows<'_>; 3],
    ) -> PyResult<Bound<'py, PyAny>> {
        let n = self.dimension();
        each_row(py, batch, mode, &[&[n]], |k, out| {
            let mut gamma = [0.0; 6];
            let rows = joints.map(|r| r.slice(k));
            self.inner
                .inverse_dynamics_joint(rows, None, &mut gamma[..n])?;
            out.put(0, k, &gamma[..n]);
            Ok(())
        })
    }

    /// The robot to calibrate, refused for a mechanism without legs' geometry to fit.
    fn nominal(&self) -> PyResult<calibrate::Nominal> {
        calibrate::Nominal::new(self.inner.description())
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// The robot's base parameters.
    fn base(&self) -> PyResult<&BaseParameters> {
        self.base
            .get_or_init(|| self.inner.base_parameters().map_err(|e| e.to_string()))
            .as_ref()
            .map_err(|e| PyValueError::new_err(e.clone()))
    }

    /// Row `k`'s motion in the platform's coordinates `[pose, twist, acceleration]`, from the
    /// rows [`C5::motion_spec`] read, handed to `f`.
    fn with_motion<T>(&self, r: &[Rows<'_>], k: usize, f: impl FnOnce([&[f64]; 3]) -> T) -> T {
        let n = self.dimension();
        let [mut x, mut v, mut a] = [[0.0; 6]; 3];
        gather(&r[..1], k, &mut x[..n]);
        gather(&r[self.twist_rows()], k, &mut v[..n]);
        gather(&r[self.acceleration_rows()], k, &mut a[..n]);
        f([&x[..n], &v[..n], &a[..n]])
    }

    /// The standard parameters with the actuators' friction, one coefficient of each kind per
    /// actuator (zero where omitted).
    fn standard_values_of(
        &self,
        viscous: Option<Vec<f64>>,
        coulomb: Option<Vec<f64>>,
    ) -> PyResult<Vec<f64>> {
        let n = self.dimension();
        let [viscous, coulomb] = [("viscous", viscous), ("coulomb", coulomb)].map(|(name, v)| {
            let v = v.unwrap_or_else(|| vec![0.0; n]);
            match v.len() == n {
                true => Ok(v),
                false => Err(PyValueError::new_err(format!(
                    "`{name}` takes one coefficient per actuator ({n}), got {}",
                    v.len()
                ))),
            }
        });
        let (viscous, coulomb) = (viscous?, coulomb?);
        let friction: Vec<Friction> = viscous
            .iter()
            .zip(&coulomb)
            .map(|(&viscous, &coulomb)| Friction { viscous, coulomb })
            .collect();
        self.inner
            .standard_parameters(&friction)
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// Inputs to rows: each given argument checked against the call's shape, each omitted one
    /// zeros.
    fn read<'a>(args: &[(&str, usize, Option<&'a Array<'_>>)]) -> PyResult<(Vec<Rows<'a>>, Batch)> {
        let mut batch = None;
        let mut out = Vec::with_capacity(args.len());
        for &(name, width, array) in args {
            out.push(match array {
                Some(a) => Some(rows(name, width, a, &mut batch)?),
                None => None,
            });
        }
        let batch = batch.ok_or_else(|| PyValueError::new_err("no input given"))?;
        let rows = out
            .into_iter()
            .zip(args)
            .map(|(r, &(_, width, _))| r.unwrap_or_else(|| zeros(width, batch.n)))
            .collect();
        Ok((rows, batch))
    }

    /// An `n×n` matrix per row of `arg` (`n` numbers a row, `n` the platform's dimension),
    /// written by `f` from the row.
    fn matrices<'py, F>(
        &self,
        py: Python<'py>,
        name: &str,
        arg: &Array<'py>,
        errors: &str,
        f: F,
    ) -> PyResult<Bound<'py, PyAny>>
    where
        F: Fn(&[f64], &mut [f64]) -> Result<(), Error> + Sync,
    {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let (r, batch) = Self::read(&[(name, n, Some(arg))])?;
        each_row(py, batch, mode, &[&[n, n]], |k, out| {
            f(r[0].slice(k), out.slot(0, k))
        })
    }
}

#[pymethods]
impl C5 {
    /// The robot of the TOML file `robot` (or the chapter's C5, `None`); a C5 with `model`,
    /// `"consistent"` (the mechanism of eq 16, the default) or `"paper"` (the chapter as
    /// published). A file of another mechanism (`mechanism = "gough-stewart"`) gives that
    /// robot, whose one model is its mechanism's.
    #[new]
    #[pyo3(signature = (model = "consistent", robot = None))]
    fn new(model: &str, robot: Option<std::path::PathBuf>) -> PyResult<Self> {
        Ok(C5 {
            inner: load(model, robot)?,
            base: OnceLock::new(),
        })
    }

    /// The model's name (`consistent`, `paper`, `gough-stewart`).
    #[getter]
    fn model(&self) -> &'static str {
        self.inner.model_name()
    }

    /// The mechanism's name, as robot files spell it (`c5`, `gough-stewart`).
    #[getter]
    fn mechanism(&self) -> &'static str {
        self.inner.mechanism()
    }

    /// The robot as MJCF, for MuJoCo and Pinocchio (docs/export.md): the platform as the
    /// root body, each leg hanging from it and welded to the base, one motor per actuator.
    fn to_mjcf(&self) -> PyResult<String> {
        self.export(c5_robot::Format::Mjcf)
    }

    /// The robot as URDF (docs/export.md): the tree with its loops cut, each closure as
    /// urdfdom's proposed `<constraint>`.
    fn to_urdf(&self) -> PyResult<String> {
        self.export(c5_robot::Format::Urdf)
    }

    /// The robot's parameter vector, as the generated `*_params` kernels take it.
    #[getter]
    fn parameters<'py>(&self, py: Python<'py>) -> Bound<'py, PyArrayDyn<f64>> {
        vector(py, self.inner.parameters().to_vec())
    }

    fn __repr__(&self) -> String {
        format!(
            "Robot(mechanism={:?}, model={:?}, dimension={})",
            self.inner.mechanism(),
            self.inner.model_name(),
            self.dimension()
        )
    }

    /// How many coordinates the platform's pose has, and how many actuators drive it: 6, or 3
    /// for a platform that only translates (the Delta), whose pose is `[xc yc zc]`, twist
    /// `v_C` and acceleration `a_C`, and whose calls take no `omega` or `omega_dot`.
    #[getter(dimension)]
    fn dimension_getter(&self) -> usize {
        self.dimension()
    }

    /// The pose's coordinates' names, in order (`alpha` … `zc`, or `xc yc zc`).
    #[getter]
    fn pose_names(&self) -> Vec<&'static str> {
        self.inner.freedom().pose_names().to_vec()
    }

    /// Actuator positions `q` (m, or rad for a motor that turns), actuator order, of `pose`:
    /// `(n,)` or `(N, n)`, `n` the robot's `dimension`.
    #[pyo3(signature = (pose, *, errors = "raise"))]
    fn inverse_kinematics<'py>(
        &self,
        py: Python<'py>,
        pose: Array<'py>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let (r, batch) = Self::read(&[("pose", n, Some(&pose))])?;
        each_row(py, batch, mode, &[&[n]], |k, out| {
            self.inner.actuator_positions(r[0].slice(k), out.slot(0, k))
        })
    }

    /// `J⁻¹` at `pose`: `(n, n)` or `(N, n, n)`, row `i` for actuator `i+1`, columns the
    /// twist's (`[ωx ωy ωz vx vy vz]`, or `[vx vy vz]`).
    #[pyo3(signature = (pose, *, errors = "raise"))]
    fn inverse_jacobian<'py>(
        &self,
        py: Python<'py>,
        pose: Array<'py>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let (r, batch) = Self::read(&[("pose", n, Some(&pose))])?;
        each_row(py, batch, mode, &[&[n, n]], |k, out| {
            self.inner.inverse_jacobian(r[0].slice(k), out.slot(0, k))
        })
    }

    /// `J` at `pose`: `(n, n)` or `(N, n, n)`, rows the twist's, column `i` for actuator
    /// `i+1`.
    #[pyo3(signature = (pose, *, errors = "raise"))]
    fn jacobian<'py>(
        &self,
        py: Python<'py>,
        pose: Array<'py>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let (r, batch) = Self::read(&[("pose", n, Some(&pose))])?;
        each_row(py, batch, mode, &[&[n, n]], |k, out| {
            self.inner.jacobian(r[0].slice(k), out.slot(0, k))
        })
    }

    /// Actuator rates `q̇ = J⁻¹ V`.
    #[pyo3(signature = (pose, omega = None, velocity = None, *, errors = "raise"))]
    fn joint_velocities<'py>(
        &self,
        py: Python<'py>,
        pose: Array<'py>,
        omega: Option<Array<'py>>,
        velocity: Option<Array<'py>>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let mut spec = self.motion_spec(&pose, [&omega, &velocity, &None, &None])?;
        spec.truncate(1 + self.twist_rows().len());
        let (r, batch) = Self::read(&spec)?;
        let twist_rows = self.twist_rows();
        each_row(py, batch, mode, &[&[n]], |k, out| {
            let mut twist = [0.0; 6];
            gather(&r[twist_rows.clone()], k, &mut twist[..n]);
            self.inner
                .joint_velocities(r[0].slice(k), &twist[..n], out.slot(0, k))
        })
    }

    /// Actuator accelerations `q̈` of the platform's motion.
    #[pyo3(signature = (pose, omega = None, velocity = None, omega_dot = None, acceleration = None, *, errors = "raise"))]
    #[allow(clippy::too_many_arguments)]
    fn joint_accelerations<'py>(
        &self,
        py: Python<'py>,
        pose: Array<'py>,
        omega: Option<Array<'py>>,
        velocity: Option<Array<'py>>,
        omega_dot: Option<Array<'py>>,
        acceleration: Option<Array<'py>>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let spec = self.motion_spec(&pose, [&omega, &velocity, &omega_dot, &acceleration])?;
        let (r, batch) = Self::read(&spec)?;
        let (twist, accel) = (self.twist_rows(), self.acceleration_rows());
        each_row(py, batch, mode, &[&[n]], |k, out| {
            let ([mut v, mut a], x) = ([[0.0; 6]; 2], r[0].slice(k));
            gather(&r[twist.clone()], k, &mut v[..n]);
            gather(&r[accel.clone()], k, &mut a[..n]);
            self.inner
                .joint_accelerations(x, &v[..n], &a[..n], out.slot(0, k))
        })
    }

    /// Actuator forces `Γ` (N, or N·m for a motor that turns), actuator order, for the
    /// platform state: the inverse dynamics. Batches go four states at a time through the
    /// batch kernel where the robot has one.
    #[pyo3(signature = (pose, omega = None, velocity = None, omega_dot = None, acceleration = None, *, errors = "raise"))]
    #[allow(clippy::too_many_arguments)]
    fn inverse_dynamics<'py>(
        &self,
        py: Python<'py>,
        pose: Array<'py>,
        omega: Option<Array<'py>>,
        velocity: Option<Array<'py>>,
        omega_dot: Option<Array<'py>>,
        acceleration: Option<Array<'py>>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let spec = self.motion_spec(&pose, [&omega, &velocity, &omega_dot, &acceleration])?;
        let (r, batch) = Self::read(&spec)?;
        let (twist, accel) = (self.twist_rows(), self.acceleration_rows());
        let motion = |k: usize, [x, v, a]: [&mut [f64]; 3]| {
            gather(&r[..1], k, x);
            gather(&r[twist.clone()], k, v);
            gather(&r[accel.clone()], k, a);
        };
        call(py, batch, mode, &[&[n]], |out| {
            let mut each = |k, gamma: Result<&[f64], Error>| match gamma {
                Ok(gamma) => out.put(0, k, gamma),
                Err(e) => out.refuse(k, e),
            };
            // Six freedoms read their rows as fixed-size arrays, the same results as through
            // `Mechanism` in 10-15 % less time (python/bench.py, a million C5 states).
            match self.inner.spatial() {
                Some(robot) => robot.inverse_dynamics_each(batch.n, &|k| motion6(&r, k), &mut {
                    |k, gamma| match gamma {
                        Ok(gamma) => each(k, Ok(&gamma)),
                        Err(e) => each(k, Err(e)),
                    }
                }),
                None => self
                    .inner
                    .inverse_dynamics_each(batch.n, &motion, &mut each),
            }
        })
    }

    /// The forward dynamics: the platform's classical acceleration under the actuator forces
    /// `gamma`, as `(omega_dot, acceleration)` (the acceleration alone for a platform that only
    /// translates). Batches go four states at a time through the batch kernel where the robot
    /// has one.
    #[pyo3(signature = (pose, omega = None, velocity = None, gamma = None, *, errors = "raise"))]
    fn forward_dynamics<'py>(
        &self,
        py: Python<'py>,
        pose: Array<'py>,
        omega: Option<Array<'py>>,
        velocity: Option<Array<'py>>,
        gamma: Option<Array<'py>>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let mut spec = self.motion_spec(&pose, [&omega, &velocity, &None, &None])?;
        let twist = self.twist_rows();
        spec.truncate(twist.end);
        spec.push(("gamma", n, gamma.as_ref()));
        let (r, batch) = Self::read(&spec)?;
        let input = |k: usize, [x, v, g]: [&mut [f64]; 3]| {
            gather(&r[..1], k, x);
            gather(&r[twist.clone()], k, v);
            gather(&r[twist.end..], k, g);
        };
        call(py, batch, mode, self.part_shapes(), |out| {
            let mut each = |k, accel: Result<&[f64], Error>| match accel {
                Ok(accel) => self.scatter(out, 0, k, accel),
                Err(e) => out.refuse(k, e),
            };
            // As `inverse_dynamics`: six freedoms read their rows as fixed-size arrays.
            let input6 = |k: usize| {
                let twist = Twist {
                    omega: r[1].row(k),
                    velocity: r[2].row(k),
                };
                (Pose::from_array(r[0].row(k)), twist, r[3].row(k))
            };
            match self.inner.spatial() {
                Some(robot) => robot.forward_dynamics_each(batch.n, &input6, &mut {
                    |k, accel| match accel {
                        Ok(accel) => each(k, Ok(&accel.to_array())),
                        Err(e) => each(k, Err(e)),
                    }
                }),
                None => self.inner.forward_dynamics_each(batch.n, &input, &mut each),
            }
        })
    }

    /// The task-space bias `h` of `Γ = Jᵀ (M_x V̇ + h)`: Coriolis, centrifugal and gravity
    /// terms at `C`, `(n,)` or `(N, n)` (`n` the platform's dimension: moment then force, or
    /// the force alone for a platform that only translates). Every mechanism.
    #[pyo3(signature = (pose, omega = None, velocity = None, *, errors = "raise"))]
    fn task_bias<'py>(
        &self,
        py: Python<'py>,
        pose: Array<'py>,
        omega: Option<Array<'py>>,
        velocity: Option<Array<'py>>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let mut spec = self.motion_spec(&pose, [&omega, &velocity, &None, &None])?;
        let twist = self.twist_rows();
        spec.truncate(twist.end);
        let (r, batch) = Self::read(&spec)?;
        each_row(py, batch, mode, &[&[n]], |k, out| {
            let mut v = [0.0; 6];
            gather(&r[twist.clone()], k, &mut v[..n]);
            self.inner.task_bias(r[0].slice(k), &v[..n], out.slot(0, k))
        })
    }

    /// The task-space inertia `M_x` of `Γ = Jᵀ (M_x V̇ + h)`: `(n, n)` or `(N, n, n)`, rows and
    /// columns the acceleration's. Every mechanism.
    #[pyo3(signature = (pose, *, errors = "raise"))]
    fn task_inertia<'py>(
        &self,
        py: Python<'py>,
        pose: Array<'py>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.matrices(py, "pose", &pose, errors, |x, m| {
            self.inner.task_inertia(x, m)
        })
    }

    /// The forward kinematics: the pose of the actuator positions `q`, `(n,)` or `(N, n)`:
    /// the C5's and the Delta's in closed form (raising `SingularPoseError` at or beyond the
    /// forward singularity), a hexapod's by Newton from its home pose.
    #[pyo3(signature = (q, *, errors = "raise"))]
    fn forward_kinematics<'py>(
        &self,
        py: Python<'py>,
        q: Array<'py>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let (r, batch) = Self::read(&[("q", n, Some(&q))])?;
        each_row(py, batch, mode, &[&[n]], |k, out| {
            self.inner
                .forward_kinematics(r[0].slice(k), None, out.slot(0, k))
        })
    }

    /// The platform state from the actuators' positions, rates and accelerations:
    /// `(pose, omega, velocity, omega_dot, acceleration)`, or `(pose, velocity, acceleration)`
    /// for a platform that only translates.
    #[pyo3(signature = (q, qd = None, qdd = None, *, errors = "raise"))]
    fn joint_state<'py>(
        &self,
        py: Python<'py>,
        q: Array<'py>,
        qd: Option<Array<'py>>,
        qdd: Option<Array<'py>>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let (r, batch) = Self::read(&joint_args(n, &q, &qd, &qdd))?;
        let parts = self.part_shapes();
        let pose = [n];
        let shapes: Vec<&[usize]> = std::iter::once(&pose[..])
            .chain(parts.iter().copied())
            .chain(parts.iter().copied())
            .collect();
        each_row(py, batch, mode, &shapes, |k, out| {
            let ([mut x, mut v, mut a], joints) = ([[0.0; 6]; 3], [0, 1, 2].map(|j| r[j].slice(k)));
            let found = [&mut x[..n], &mut v[..n], &mut a[..n]];
            self.inner.joint_state(joints, None, found)?;
            out.put(0, k, &x[..n]);
            self.scatter(out, 1, k, &v[..n]);
            self.scatter(out, 1 + parts.len(), k, &a[..n]);
            Ok(())
        })
    }

    /// Actuator forces `Γ` (N or N·m) from the actuators' positions `q`, rates `qd` and
    /// accelerations `qdd`: the inverse dynamics in joint space, every mechanism. The C5's
    /// batches go four at a time through its batch kernel; the Delta's rows one at a time.
    #[pyo3(signature = (q, qd = None, qdd = None, *, errors = "raise"))]
    fn inverse_dynamics_joint<'py>(
        &self,
        py: Python<'py>,
        q: Array<'py>,
        qd: Option<Array<'py>>,
        qdd: Option<Array<'py>>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let (r, batch) = Self::read(&joint_args(n, &q, &qd, &qdd))?;
        let Some(robot) = self.inner.spatial() else {
            return self.joint_forces(py, batch, mode, [0, 1, 2].map(|j| &r[j]));
        };
        let sample = |k: usize| [r[0].row(k), r[1].row(k), r[2].row(k)];
        call(py, batch, mode, &[&[6]], |out| {
            robot.inverse_dynamics_joint_each(batch.n, &sample, &mut |k, gamma| match gamma {
                Ok(gamma) => out.put(0, k, &gamma),
                Err(e) => out.refuse(k, e),
            })
        })
    }

    /// `M_q` of `Γ = M_q q̈ + c_q`, the joint-space inertia (`Jᵀ M_x J`) at the actuator
    /// positions `q`: `(n, n)` or `(N, n, n)`. Every mechanism.
    #[pyo3(signature = (q, *, errors = "raise"))]
    fn joint_inertia<'py>(
        &self,
        py: Python<'py>,
        q: Array<'py>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.matrices(py, "q", &q, errors, |q, m| {
            self.inner.joint_inertia(q, None, m)
        })
    }

    /// `c_q` of `Γ = M_q q̈ + c_q`: Coriolis, centrifugal and gravity forces (N or N·m) at the
    /// actuator positions `q` and rates `qd`: `(n,)` or `(N, n)`, every mechanism.
    #[pyo3(signature = (q, qd = None, *, errors = "raise"))]
    fn joint_bias<'py>(
        &self,
        py: Python<'py>,
        q: Array<'py>,
        qd: Option<Array<'py>>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let (r, batch) = Self::read(&joint_args(n, &q, &qd, &None))?;
        let Some(robot) = self.inner.spatial() else {
            return self.joint_forces(py, batch, mode, [0, 1, 2].map(|j| &r[j]));
        };
        each_row(py, batch, mode, &[&[6]], |k, out| {
            out.put(0, k, &robot.joint_bias(&r[0].row(k), &r[1].row(k), None)?);
            Ok(())
        })
    }

    /// The inverse dynamics and its exact Jacobians, from one generated kernel: `(gamma,
    /// d_pose, d_twist, d_acceleration)`, `Γ` `(n,)` and three `(n, n)` (or `(N, n)` and
    /// `(N, n, n)`), row `i` actuator `i`, columns the pose's, the twist's and the
    /// acceleration's coordinates (`α β γ xc yc zc`, `ωx ωy ωz vx vy vz`, `ω̇x ω̇y ω̇z ax ay az`
    /// for a platform free in space). `d_acceleration` is `Jᵀ M_x`.
    #[pyo3(signature = (pose, omega = None, velocity = None, omega_dot = None, acceleration = None, *, errors = "raise"))]
    #[allow(clippy::too_many_arguments)]
    fn inverse_dynamics_derivatives<'py>(
        &self,
        py: Python<'py>,
        pose: Array<'py>,
        omega: Option<Array<'py>>,
        velocity: Option<Array<'py>>,
        omega_dot: Option<Array<'py>>,
        acceleration: Option<Array<'py>>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let derivatives = self.derivatives()?;
        let spec = self.motion_spec(&pose, [&omega, &velocity, &omega_dot, &acceleration])?;
        let (r, batch) = Self::read(&spec)?;
        let shapes: [&[usize]; 4] = [&[n], &[n, n], &[n, n], &[n, n]];
        each_row(py, batch, mode, &shapes, |k, out| {
            let [x, v, a] = self.motion_row(&r, k);
            let mut gamma = vec![0.0; n];
            let mut jacobians = [0; 3].map(|_| vec![0.0; n * n]);
            let [d_pose, d_twist, d_accel] = &mut jacobians;
            derivatives.inverse_dynamics_derivatives(
                [&x, &v, &a],
                &mut gamma,
                [d_pose, d_twist, d_accel],
            )?;
            out.put(0, k, &gamma);
            for (j, jacobian) in jacobians.iter().enumerate() {
                out.put(1 + j, k, jacobian);
            }
            Ok(())
        })
    }

    /// The forward dynamics and its exact Jacobians, from one generated kernel: the
    /// acceleration's parts (`omega_dot, acceleration`, or `acceleration` for a platform that
    /// translates), then `d_pose, d_twist, d_gamma`, `(n, n)` each, rows the acceleration's
    /// coordinates, columns the pose's, the twist's and the actuators. `d_gamma` is
    /// `M_x⁻¹ J⁻ᵀ`, the inverse of `inverse_dynamics_derivatives`'s `d_acceleration`.
    #[pyo3(signature = (pose, omega = None, velocity = None, gamma = None, *, errors = "raise"))]
    fn forward_dynamics_derivatives<'py>(
        &self,
        py: Python<'py>,
        pose: Array<'py>,
        omega: Option<Array<'py>>,
        velocity: Option<Array<'py>>,
        gamma: Option<Array<'py>>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let derivatives = self.derivatives()?;
        let mut spec = self.motion_spec(&pose, [&omega, &velocity, &None, &None])?;
        let twist = self.twist_rows();
        spec.truncate(twist.end);
        spec.push(("gamma", n, gamma.as_ref()));
        let (r, batch) = Self::read(&spec)?;
        let parts = self.part_shapes();
        let square = [n, n];
        let mut shapes = parts.to_vec();
        shapes.extend([&square[..]; 3]);
        each_row(py, batch, mode, &shapes, |k, out| {
            let (mut x, mut v, mut g) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
            gather(&r[..1], k, &mut x);
            gather(&r[twist.clone()], k, &mut v);
            gather(&r[twist.end..], k, &mut g);
            let mut accel = vec![0.0; n];
            let mut jacobians = [0; 3].map(|_| vec![0.0; n * n]);
            let [d_pose, d_twist, d_gamma] = &mut jacobians;
            derivatives.forward_dynamics_derivatives(
                &x,
                &v,
                &g,
                &mut accel,
                [d_pose, d_twist, d_gamma],
            )?;
            self.scatter(out, 0, k, &accel);
            for (j, jacobian) in jacobians.iter().enumerate() {
                out.put(parts.len() + j, k, jacobian);
            }
            Ok(())
        })
    }

    /// The joint-space inverse dynamics and its exact Jacobians: `(gamma, d_q, d_qd, d_qdd)`,
    /// row `i` actuator `i`, columns actuators 1..6; `d_qdd` is `M_q`. The C5's only.
    #[pyo3(signature = (q, qd = None, qdd = None, *, errors = "raise"))]
    fn inverse_dynamics_joint_derivatives<'py>(
        &self,
        py: Python<'py>,
        q: Array<'py>,
        qd: Option<Array<'py>>,
        qdd: Option<Array<'py>>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mode = on_error(errors)?;
        let (r, batch) = Self::read(&joint_args(6, &q, &qd, &qdd))?;
        let c5 = self.c5("joint-space derivatives")?;
        let shapes: [&[usize]; 4] = [&[6], &[6, 6], &[6, 6], &[6, 6]];
        each_row(py, batch, mode, &shapes, |k, out| {
            let d =
                c5.inverse_dynamics_joint_derivatives(&r[0].row(k), &r[1].row(k), &r[2].row(k))?;
            out.put(0, k, &d.gamma);
            out.put(1, k, d.d_q.as_flattened());
            out.put(2, k, d.d_qd.as_flattened());
            out.put(3, k, d.d_qdd.as_flattened());
            Ok(())
        })
    }

    /// The margins of the robot's stroke, plate-travel and tilt limits at `pose`: `(stroke,
    /// plate, tilt)`, `(6,)` (m), `(6, 2)` (m, the plate's two axes) and `(6,)` (rad), or with a
    /// leading `N`; positive inside, negative outside, `inf` where the robot file sets no such
    /// limit. The C5's only (a hexapod's limits: `c5 workspace`).
    #[pyo3(signature = (pose, *, errors = "raise"))]
    fn limit_margins<'py>(
        &self,
        py: Python<'py>,
        pose: Array<'py>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let mode = on_error(errors)?;
        let (r, batch) = Self::read(&[("pose", 6, Some(&pose))])?;
        let c5 = self.c5("limit margins")?;
        each_row(py, batch, mode, &[&[6], &[6, 2], &[6]], |k, out| {
            let m = c5.limit_margins(&Pose::from_array(r[0].row(k)))?;
            out.put(0, k, &m.stroke);
            out.put(1, k, m.plate.as_flattened());
            out.put(2, k, &m.tilt);
            Ok(())
        })
    }

    /// The robot's limits as its file gives them: a dict with `stroke` (`(6, 2)`, m, min and
    /// max), `plate_travel` (`(2,)`, m), `tilt` (rad), `speed` (m/s) and `force` (N), each `None`
    /// where the file sets none. The C5's only.
    #[getter]
    fn limits<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let l = &self.c5("limits")?.robot().limits;
        let d = PyDict::new(py);
        d.set_item("stroke", l.stroke.map(|s| s.to_vec()))?;
        d.set_item("plate_travel", l.plate_travel.map(|t| t.to_vec()))?;
        d.set_item("tilt", l.tilt)?;
        d.set_item("speed", l.speed)?;
        d.set_item("force", l.force)?;
        Ok(d)
    }

    /// The base regressor `Y_b` of `Γ = Y_b β` (with friction): `(n, n_b)` or `(N, n, n_b)`
    /// for `n` actuators, the columns those of `base_parameters`.
    #[pyo3(signature = (pose, omega = None, velocity = None, omega_dot = None, acceleration = None, *, errors = "raise"))]
    #[allow(clippy::too_many_arguments)]
    fn base_regressor<'py>(
        &self,
        py: Python<'py>,
        pose: Array<'py>,
        omega: Option<Array<'py>>,
        velocity: Option<Array<'py>>,
        omega_dot: Option<Array<'py>>,
        acceleration: Option<Array<'py>>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let spec = self.motion_spec(&pose, [&omega, &velocity, &omega_dot, &acceleration])?;
        let (r, batch) = Self::read(&spec)?;
        let nb = self.base()?.len();
        each_row(py, batch, mode, &[&[n, nb]], |k, out| {
            self.with_motion(&r, k, |motion| {
                self.inner.base_regressor_into(motion, out.slot(0, k))
            })
        })
    }

    /// The regressor `Y` of `Γ = Y π` (with friction): `(n, p)` or `(N, n, p)` for `n`
    /// actuators, the columns the standard parameters of `standard_parameters` (142 for the
    /// C5, 70 for a hexapod, 76 for a rotary hexapod, 34 for a Delta).
    #[pyo3(signature = (pose, omega = None, velocity = None, omega_dot = None, acceleration = None, *, errors = "raise"))]
    #[allow(clippy::too_many_arguments)]
    fn regressor<'py>(
        &self,
        py: Python<'py>,
        pose: Array<'py>,
        omega: Option<Array<'py>>,
        velocity: Option<Array<'py>>,
        omega_dot: Option<Array<'py>>,
        acceleration: Option<Array<'py>>,
        errors: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (mode, n) = (on_error(errors)?, self.dimension());
        let spec = self.motion_spec(&pose, [&omega, &velocity, &omega_dot, &acceleration])?;
        let (r, batch) = Self::read(&spec)?;
        let p = self.base()?.standard_names().len();
        each_row(py, batch, mode, &[&[n, p]], |k, out| {
            let y = self.with_motion(&r, k, |motion| self.inner.standard_regressor(motion))?;
            // nalgebra stores columns; the array is row-major.
            for (slot, value) in out.slot(0, k).iter_mut().zip(y.transpose().iter()) {
                *slot = *value;
            }
            Ok(())
        })
    }

    /// The standard parameters' names, the columns of `regressor`: per body (the C5's
    /// `platform`, `rod1`, `joint1`, …; a hexapod's `platform`, `cylinder1`, `rod1`, …) mass,
    /// first moment `m c` and inertia (`platform_mass`, `platform_mx`, …, `platform_izz`),
    /// then the actuators' friction `fv1`…, `fc1`….
    #[getter]
    fn standard_parameters(&self) -> PyResult<Vec<String>> {
        Ok(self.base()?.standard_names().to_vec())
    }

    /// This robot's standard parameters `π`, in the order of `standard_parameters`, with the
    /// actuators' viscous (N·s/m, or N·m·s/rad for a motor that turns) and Coulomb (N, or N·m)
    /// friction, one per actuator each, zero if omitted.
    #[pyo3(signature = (viscous = None, coulomb = None))]
    fn standard_values<'py>(
        &self,
        py: Python<'py>,
        viscous: Option<Vec<f64>>,
        coulomb: Option<Vec<f64>>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        Ok(vector(py, self.standard_values_of(viscous, coulomb)?))
    }

    /// This robot's base parameters `β = B π`, in the order of `base_parameters`, with the
    /// actuators' friction as `standard_values` takes it: what `identify` should find.
    #[pyo3(signature = (viscous = None, coulomb = None))]
    fn base_values<'py>(
        &self,
        py: Python<'py>,
        viscous: Option<Vec<f64>>,
        coulomb: Option<Vec<f64>>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let standard = self.standard_values_of(viscous, coulomb)?;
        let beta = self
            .base()?
            .from_standard(&standard)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(vector(py, beta))
    }

    /// The base parameters' names, the columns of `base_regressor`.
    #[getter]
    fn base_parameters(&self) -> PyResult<Vec<String>> {
        Ok(self.base()?.names().to_vec())
    }

    /// Identifies the base parameters (inertial and friction) from measured states (the
    /// platform's motion, as `inverse_dynamics` takes it) and forces `gamma` (`(N, n)`) by
    /// weighted least squares: a dict with `names`, `values`, `std_dev`, `condition_number`,
    /// `residual_rms`, `samples`.
    #[pyo3(signature = (pose, omega = None, velocity = None, omega_dot = None, acceleration = None, gamma = None))]
    #[allow(clippy::too_many_arguments)]
    fn identify<'py>(
        &self,
        py: Python<'py>,
        pose: Array<'py>,
        omega: Option<Array<'py>>,
        velocity: Option<Array<'py>>,
        omega_dot: Option<Array<'py>>,
        acceleration: Option<Array<'py>>,
        gamma: Option<Array<'py>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let gamma =
            gamma.ok_or_else(|| PyValueError::new_err("identify needs the forces `gamma`"))?;
        let mut spec = self.motion_spec(&pose, [&omega, &velocity, &omega_dot, &acceleration])?;
        spec.push(("gamma", self.dimension(), Some(&gamma)));
        let (r, batch) = Self::read(&spec)?;
        let forces = spec.len() - 1;
        let estimate = py.detach(|| -> Result<_, String> {
            let mut identifier = Identifier::new(self.inner.as_ref()).map_err(|e| e.to_string())?;
            for k in 0..batch.n {
                self.with_motion(&r, k, |motion| {
                    identifier.add_motion(motion, r[forces].slice(k))
                })
                .map_err(|e| format!("{e} (row {k})"))?;
            }
            identifier.estimate().map_err(|e| e.to_string())
        });
        let e = estimate.map_err(PyValueError::new_err)?;
        let d = PyDict::new(py);
        d.set_item("model", e.model.clone())?;
        d.set_item("names", e.names.clone())?;
        d.set_item("values", e.values.clone())?;
        d.set_item("std_dev", e.std_dev.clone())?;
        d.set_item("condition_number", e.condition_number)?;
        d.set_item("residual_rms", e.residual_rms.to_vec())?;
        d.set_item("samples", e.samples)?;
        Ok(d)
    }

    /// Kinematic calibration (a Gough-Stewart platform, a rotary hexapod, a Delta): each leg's
    /// fitted geometry (docs/calibration.md: joint centres, a rotary leg's crank and rod
    /// lengths, the encoder offset) fitted to measured poses `(N, d)` and encoder readings
    /// `(N, n)`. Returns a dict: `names`, `units` (`m` or `rad` each), `nominal`, `values`,
    /// `std_dev` (NaN where fixed), `residuals_before`, `residuals_after` (`(N, n)`, m or rad),
    /// `singular_values` (`(n, fitted per leg)`), `unobservable` (a list of dicts),
    /// `variance_factor`, `iterations` and `robot_toml`, the calibrated robot file.
    #[pyo3(signature = (pose, q, *, noise_position = 10e-6, noise_angle = 20e-6,
        noise_encoder = 1e-6, scale = 1e-3, observable = 5e-3, strict = false))]
    #[allow(clippy::too_many_arguments)]
    fn calibrate<'py>(
        &self,
        py: Python<'py>,
        pose: Array<'py>,
        q: Array<'py>,
        noise_position: f64,
        noise_angle: f64,
        noise_encoder: f64,
        scale: f64,
        observable: f64,
        strict: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let robot = &self.nominal()?;
        let n = robot.actuators();
        let (r, batch) = Self::read(&[("pose", n, Some(&pose)), ("q", n, Some(&q))])?;
        let data: Vec<Measurement> = (0..batch.n)
            .map(|k| Measurement {
                pose: r[0].slice(k).to_vec(),
                q: r[1].slice(k).to_vec(),
            })
            .collect();
        let options = Options {
            noise: Noise {
                position: noise_position,
                angle: noise_angle,
                encoder: noise_encoder,
            },
            scale,
            observable,
            strict,
            ..Options::default()
        };
        let report = py
            .detach(|| calibrate::calibrate(robot, &data, &options))
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let d = PyDict::new(py);
        let p = &report.parameters;
        d.set_item(
            "names",
            p.iter().map(|x| x.name.clone()).collect::<Vec<_>>(),
        )?;
        let units: Vec<&str> = p
            .iter()
            .map(|x| if x.angle { "rad" } else { "m" })
            .collect();
        d.set_item("units", units)?;
        d.set_item("nominal", vector(py, p.iter().map(|x| x.nominal).collect()))?;
        d.set_item("values", vector(py, p.iter().map(|x| x.estimate).collect()))?;
        let sigma = p.iter().map(|x| x.std_dev.unwrap_or(f64::NAN)).collect();
        d.set_item("std_dev", vector(py, sigma))?;
        let table = |rows: &[Vec<f64>], width: usize| {
            ArrayD::from_shape_vec(IxDyn(&[rows.len(), width]), rows.concat())
                .map(|a| a.into_pyarray(py))
        };
        let to_py = |e: numpy::ndarray::ShapeError| PyValueError::new_err(e.to_string());
        d.set_item(
            "residuals_before",
            table(&report.residuals_before, n).map_err(to_py)?,
        )?;
        d.set_item(
            "residuals_after",
            table(&report.residuals_after, n).map_err(to_py)?,
        )?;
        let fitted = robot.fitted().len();
        let singular = table(&report.singular_values, fitted).map_err(to_py)?;
        d.set_item("singular_values", singular)?;
        let unobservable = PyList::empty(py);
        for u in &report.unobservable {
            let entry = PyDict::new(py);
            entry.set_item("leg", u.leg)?;
            entry.set_item("combination", u.combination.clone())?;
            entry.set_item("std_dev", u.std_dev)?;
            entry.set_item("fixed", u.fixed.clone())?;
            entry.set_item("text", u.to_string())?;
            unobservable.append(entry)?;
        }
        d.set_item("unobservable", unobservable)?;
        d.set_item("variance_factor", report.variance_factor)?;
        d.set_item("iterations", report.iterations)?;
        d.set_item("robot_toml", report.robot.to_toml())?;
        Ok(d)
    }

    /// A minimum-effort rest-to-rest move from the pose `start` to `goal` (`(n,)` each, the
    /// platform's coordinates) in `duration` seconds, its forces held over each of `steps`
    /// steps and within `force_limit` (N, or N·m where the motors turn) if given, every pose
    /// keeping a singularity clearance of `least_clearance`: iLQR on the forward dynamics and
    /// its exact Jacobians (docs/derivatives.md). Returns a dict: `times` (`(steps + 1,)`),
    /// `pose` (`(steps + 1, n)`), the twist's and the acceleration's parts as
    /// `forward_dynamics` names them (`(steps + 1, 3)` each), `gamma` (`(steps, n)`),
    /// `iterations`, `costs` (per augmented-Lagrangian round, the objective after each
    /// iteration), `goal_error`, `force_excess` and `least_clearance`. Raises `ValueError` for
    /// a problem that cannot be planned, a robot without derivative kernels, or no convergence
    /// in `max_iterations`.
    #[pyo3(signature = (start, goal, duration, steps, *, force_limit = None,
        least_clearance = plan::LEAST_CLEARANCE, goal_tolerance = 1e-8, force_tolerance = 1e-6,
        clearance_tolerance = 1e-6, max_iterations = 500))]
    #[allow(clippy::too_many_arguments)]
    fn plan<'py>(
        &self,
        py: Python<'py>,
        start: Vec<f64>,
        goal: Vec<f64>,
        duration: f64,
        steps: usize,
        force_limit: Option<f64>,
        least_clearance: f64,
        goal_tolerance: f64,
        force_tolerance: f64,
        clearance_tolerance: f64,
        max_iterations: usize,
    ) -> PyResult<Bound<'py, PyDict>> {
        let problem = plan::Problem {
            start,
            goal,
            duration,
            steps,
            force_limit,
            least_clearance,
        };
        let settings = plan::Settings {
            goal_tolerance,
            force_tolerance,
            clearance_tolerance,
            max_iterations,
        };
        let robot = self.inner.as_ref();
        let planned = py
            .detach(|| plan::plan(robot, &problem, &settings))
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let freedom = robot.freedom();
        let n = freedom.dimension();
        let rows = planned
            .states
            .iter()
            .map(|s| robot.coordinates_of(s))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let table = |values: Vec<f64>, width: usize| {
            ArrayD::from_shape_vec(IxDyn(&[values.len() / width, width]), values)
                .map(|a| a.into_pyarray(py))
                .map_err(|e| PyValueError::new_err(e.to_string()))
        };
        let d = PyDict::new(py);
        d.set_item("times", planned.times.clone().into_pyarray(py))?;
        d.set_item(
            "pose",
            table(rows.iter().flat_map(|[x, ..]| x.clone()).collect(), n)?,
        )?;
        for (which, names) in [
            (1, freedom.twist_parts()),
            (2, freedom.acceleration_parts()),
        ] {
            for (j, name) in names.iter().enumerate() {
                let part = rows
                    .iter()
                    .flat_map(|r| r[which][3 * j..3 * j + 3].to_vec());
                d.set_item(name, table(part.collect(), 3)?)?;
            }
        }
        d.set_item("gamma", table(planned.forces.concat(), n)?)?;
        d.set_item("iterations", planned.iterations)?;
        d.set_item("costs", planned.costs.clone())?;
        d.set_item("goal_error", planned.goal_error)?;
        d.set_item("force_excess", planned.force_excess)?;
        d.set_item("least_clearance", planned.least_clearance)?;
        Ok(d)
    }

    /// `n` poses `(n, d)` inside the robot's limits that make its geometry best observable for
    /// calibration (a Gough-Stewart platform, a rotary hexapod, a Delta), drawn with `seed`.
    #[pyo3(signature = (n, *, seed = 1))]
    fn calibration_plan<'py>(
        &self,
        py: Python<'py>,
        n: usize,
        seed: u64,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let robot = &self.nominal()?;
        let poses = py
            .detach(|| calibrate::plan(robot, n, &Options::default(), seed))
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        ArrayD::from_shape_vec(IxDyn(&[poses.len(), robot.actuators()]), poses.concat())
            .map(|a| a.into_pyarray(py))
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }
}

/// The robot of the TOML file `robot` (any mechanism the project describes; the chapter's C5
/// for `None`) as `"mjcf"` or `"urdf"` text, as `c5 export` writes it (docs/export.md).
#[pyfunction]
#[pyo3(signature = (robot = None, format = "mjcf"))]
fn export(robot: Option<std::path::PathBuf>, format: &str) -> PyResult<String> {
    let format: c5_robot::Format = format
        .parse()
        .map_err(|e: c5_robot::Error| PyValueError::new_err(e.to_string()))?;
    c5_runtime::mechanism::export(&read_description(robot)?, Model::Consistent, format)
        .map_err(|e| PyValueError::new_err(e.to_string()))
}

/// The generated kernels of the parallel robots the project describes (the C5 joint parallel
/// robot, the Gough–Stewart platform, the rotary hexapod, the Delta), for numpy. See `Robot`.
#[pymodule]
fn c5_kernels(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<C5>()?;
    m.add_function(wrap_pyfunction!(export, m)?)?;
    // The chapter's robot's name, kept for the programs written before other mechanisms.
    m.add("C5", m.getattr("Robot")?)?;
    m.add("SingularPoseError", m.py().get_type::<SingularPoseError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("SINGULARITY_TOLERANCE", c5_runtime::SINGULARITY_TOLERANCE)?;
    Ok(())
}
