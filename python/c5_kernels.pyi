"""The C5 joint parallel robot's generated kernels for numpy.

Conventions (those of the Rust crates): SI units and radians. A pose is
``[alpha, beta, gamma, xc, yc, zc]`` with ``R = Rx(alpha) Ry(beta) Rz(gamma)`` and ``C`` the
platform centre; the twist is ``omega`` and ``velocity`` (of ``C``), base frame; accelerations
are classical, ``omega_dot`` and ``acceleration = d velocity / dt``. Actuators come in segment
order 1..6; ``q`` is the ball centre's position along the actuator axis (m) and a positive
force pushes the rod along ``+n_i`` (N).

Every method takes one state (vectors of shape ``(6,)`` or ``(3,)``) or a batch (``(N, 6)``,
``(N, 3)``) and returns arrays of the matching shape. Omitted motion arguments are zero.
With ``errors="raise"`` (the default) a refused row raises ``ValueError`` (bad shape,
non-finite value) or ``SingularPoseError`` naming the divisor and the row; with
``errors="nan"`` the refused rows come back as NaN and a boolean mask (``True`` = refused) is
returned last.
"""

from __future__ import annotations

from os import PathLike
from typing import Literal, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np
import numpy.typing as npt

__version__: str
SINGULARITY_TOLERANCE: float
"""Divisors (``r11``, ``r22``, ``r33``, ``1 + abc``) below this are refused."""

ArrayLike = npt.ArrayLike
Array = npt.NDArray[np.float64]
Mask = npt.NDArray[np.bool_]
Errors = Literal["raise", "nan"]
Result = Union[Array, Tuple[Array, Mask]]
"""An array, or with ``errors=\"nan\"`` the array and the mask of refused rows."""

class SingularPoseError(ValueError):
    """A pose, or actuator positions, where the kernels would divide by (nearly) zero."""

class Identification(TypedDict):
    model: str
    names: list[str]
    values: list[float]
    std_dev: list[float]
    condition_number: float
    residual_rms: list[float]
    samples: int

class Plan(TypedDict, total=False):
    """``Robot.plan``'s result; ``omega`` and ``omega_dot`` only where the platform turns."""
    times: Array
    pose: Array
    omega: Array
    velocity: Array
    omega_dot: Array
    acceleration: Array
    gamma: Array
    iterations: int
    costs: list[list[float]]
    goal_error: float
    force_excess: float
    least_clearance: float

class Unobservable(TypedDict):
    leg: int
    combination: list[tuple[str, float]]
    std_dev: float
    fixed: str
    text: str

class Calibration(TypedDict):
    names: list[str]
    units: list[str]
    nominal: Array
    values: Array
    std_dev: Array
    residuals_before: Array
    residuals_after: Array
    singular_values: Array
    unobservable: list[Unobservable]
    variance_factor: float
    iterations: int
    robot_toml: str

class Limits(TypedDict):
    stroke: Optional[list[list[float]]]
    plate_travel: Optional[list[float]]
    tilt: Optional[float]
    speed: Optional[float]
    force: Optional[float]

class Robot:
    """A parallel robot: the C5 joint parallel robot (the default, with a model of its legs'
    mechanism) or the robot of a file's ``mechanism`` (``"gough-stewart"``, ``"rus-hexapod"``,
    ``"delta"``). Its ``dimension`` is its platform's freedoms and its actuators' number: 6, or
    3 for the Delta, whose pose is ``[xc yc zc]`` and whose calls take ``velocity`` and
    ``acceleration`` alone; what needs six freedoms raises ``ValueError`` for it."""

    def __init__(
        self,
        model: Literal["consistent", "paper"] = "consistent",
        robot: Optional[Union[str, PathLike[str]]] = None,
    ) -> None:
        """``robot``: a robot TOML file, or ``None`` for the chapter's robot. ``model``:
        ``"consistent"`` (the mechanism of eq 16, the default) or ``"paper"`` (the chapter as
        published, right only at zero orientation)."""

    @property
    def model(self) -> str: ...
    @property
    def mechanism(self) -> str: ...
    @property
    def dimension(self) -> int:
        """The pose's coordinates and the actuators: 6, or 3 for a platform that only
        translates."""
    @property
    def pose_names(self) -> list[str]:
        """The pose's coordinates' names, in order."""
    def to_mjcf(self) -> str:
        """The robot as MJCF for MuJoCo and Pinocchio (docs/export.md); the paper model is
        refused (``ValueError``), it is not a mechanism."""
    def to_urdf(self) -> str:
        """The robot as URDF, loops cut, closures as ``<constraint>`` (docs/export.md)."""
    @property
    def parameters(self) -> Array:
        """The robot's parameter vector, as the generated ``*_params`` kernels take it."""

    def inverse_kinematics(self, pose: ArrayLike, *, errors: Errors = "raise") -> Result:
        """Actuator positions ``q`` (m), eq 16: ``(6,)`` or ``(N, 6)``."""

    def inverse_jacobian(self, pose: ArrayLike, *, errors: Errors = "raise") -> Result:
        """``J^-1``: ``(6, 6)`` or ``(N, 6, 6)``, row ``i`` for segment ``i+1``, columns
        ``[wx wy wz vx vy vz]``."""

    def jacobian(self, pose: ArrayLike, *, errors: Errors = "raise") -> Result:
        """``J = J1 Pi1``: ``(6, 6)`` or ``(N, 6, 6)``, rows ``[wx wy wz vx vy vz]``, column ``i``
        for segment ``i+1``."""

    def joint_velocities(
        self,
        pose: ArrayLike,
        omega: Optional[ArrayLike] = None,
        velocity: Optional[ArrayLike] = None,
        *,
        errors: Errors = "raise",
    ) -> Result:
        """Actuator rates ``qd = J^-1 V`` (m/s)."""

    def joint_accelerations(
        self,
        pose: ArrayLike,
        omega: Optional[ArrayLike] = None,
        velocity: Optional[ArrayLike] = None,
        omega_dot: Optional[ArrayLike] = None,
        acceleration: Optional[ArrayLike] = None,
        *,
        errors: Errors = "raise",
    ) -> Result:
        """Actuator accelerations ``qdd`` of the platform's motion."""

    def inverse_dynamics(
        self,
        pose: ArrayLike,
        omega: Optional[ArrayLike] = None,
        velocity: Optional[ArrayLike] = None,
        omega_dot: Optional[ArrayLike] = None,
        acceleration: Optional[ArrayLike] = None,
        *,
        errors: Errors = "raise",
    ) -> Result:
        """Actuator forces ``gamma`` (N): ``(6,)`` or ``(N, 6)``. Batches go four states at a
        time through the batch kernel, without the GIL."""

    def forward_dynamics(
        self,
        pose: ArrayLike,
        omega: Optional[ArrayLike] = None,
        velocity: Optional[ArrayLike] = None,
        gamma: Optional[ArrayLike] = None,
        *,
        errors: Errors = "raise",
    ) -> Union[Array, Tuple[Array, Mask], Tuple[Array, Array], Tuple[Array, Array, Mask]]:
        """The platform's classical acceleration ``(omega_dot, acceleration)`` under the actuator
        forces ``gamma`` (N); ``acceleration`` alone for the Delta."""

    def task_bias(
        self,
        pose: ArrayLike,
        omega: Optional[ArrayLike] = None,
        velocity: Optional[ArrayLike] = None,
        *,
        errors: Errors = "raise",
    ) -> Result:
        """``h`` of ``gamma = J^T (M_x (omega_dot; acceleration) + h)``: the Coriolis, centrifugal
        and gravity terms at ``C``, ``(n,)`` or ``(N, n)``; the Delta's (``n = 3``) takes no
        ``omega``. Every mechanism."""

    def task_inertia(self, pose: ArrayLike, *, errors: Errors = "raise") -> Result:
        """``M_x`` of ``gamma = J^T (M_x (omega_dot; acceleration) + h)``: ``(n, n)`` or
        ``(N, n, n)``, ``n`` the platform's dimension (3 for the Delta: ``M_x`` of ``a_C``).
        Every mechanism."""

    def forward_kinematics(self, q: ArrayLike, *, errors: Errors = "raise") -> Result:
        """The pose of the actuator positions ``q`` (m), in closed form. Raises
        ``SingularPoseError`` at or beyond the forward singularity (``1 + abc < 1e-9``)."""

    def joint_state(
        self,
        q: ArrayLike,
        qd: Optional[ArrayLike] = None,
        qdd: Optional[ArrayLike] = None,
        *,
        errors: Errors = "raise",
    ) -> Union[Tuple[Array, Array, Array, Array, Array], Tuple[Array, Array, Array, Array, Array, Mask]]:
        """``(pose, omega, velocity, omega_dot, acceleration)`` from the actuators' positions,
        rates and accelerations; ``(pose, velocity, acceleration)`` for the Delta."""

    def inverse_dynamics_joint(
        self,
        q: ArrayLike,
        qd: Optional[ArrayLike] = None,
        qdd: Optional[ArrayLike] = None,
        *,
        errors: Errors = "raise",
    ) -> Result:
        """Actuator forces (N, or N·m for motors that turn) from the actuators' positions, rates
        and accelerations: ``(n,)`` or ``(N, n)`` for the robot's ``n`` actuators, every
        mechanism (the Delta's one row at a time, the others' through their kernels)."""

    def joint_inertia(self, q: ArrayLike, *, errors: Errors = "raise") -> Result:
        """``M_q`` of ``gamma = M_q qdd + c_q`` (``J^T M_x J``): ``(n, n)`` or ``(N, n, n)``.
        Every mechanism."""

    def joint_bias(
        self, q: ArrayLike, qd: Optional[ArrayLike] = None, *, errors: Errors = "raise"
    ) -> Result:
        """``c_q`` of ``gamma = M_q qdd + c_q`` (N, or N·m): Coriolis, centrifugal and gravity
        forces at the actuators' positions and rates, ``(n,)`` or ``(N, n)``, every mechanism."""

    def inverse_dynamics_derivatives(
        self,
        pose: ArrayLike,
        omega: Optional[ArrayLike] = None,
        velocity: Optional[ArrayLike] = None,
        omega_dot: Optional[ArrayLike] = None,
        acceleration: Optional[ArrayLike] = None,
        *,
        errors: Errors = "raise",
    ) -> Tuple[Array, ...]:
        """``(gamma, d_pose, d_twist, d_acceleration)``: the forces ``(n,)`` and their exact
        Jacobians ``(n, n)`` (with a leading ``N`` for a batch), row ``i`` actuator ``i``,
        columns the platform's coordinates (``alpha beta gamma xc yc zc``,
        ``wx wy wz vx vy vz``, ``w_dot_x .. az`` for six freedoms). ``d_acceleration`` is
        ``J^T M_x``. Raises ``ValueError`` naming the mechanism where its derivative kernels
        are not generated (the rotary hexapod's). With ``errors="nan"``, the mask
        last."""

    def forward_dynamics_derivatives(
        self,
        pose: ArrayLike,
        omega: Optional[ArrayLike] = None,
        velocity: Optional[ArrayLike] = None,
        gamma: Optional[ArrayLike] = None,
        *,
        errors: Errors = "raise",
    ) -> Tuple[Array, ...]:
        """``(omega_dot, acceleration, d_pose, d_twist, d_gamma)`` (``omega_dot`` absent for a
        platform that translates): the forward dynamics and its exact Jacobians ``(n, n)``, rows
        the acceleration's coordinates (``w_dot_x w_dot_y w_dot_z ax ay az`` for six
        freedoms); ``d_gamma`` is ``M_x^-1 J^-T``. With ``errors="nan"``, the mask last."""

    def inverse_dynamics_joint_derivatives(
        self,
        q: ArrayLike,
        qd: Optional[ArrayLike] = None,
        qdd: Optional[ArrayLike] = None,
        *,
        errors: Errors = "raise",
    ) -> Tuple[Array, ...]:
        """``(gamma, d_q, d_qd, d_qdd)``: the joint-space inverse dynamics and its exact
        Jacobians, columns actuators 1..6; ``d_qdd`` is ``M_q``. With ``errors="nan"``, the mask
        last."""

    def limit_margins(self, pose: ArrayLike, *, errors: Errors = "raise") -> Tuple[Array, ...]:
        """``(stroke, plate, tilt)`` margins of the robot's limits at ``pose``: ``(6,)`` (m),
        ``(6, 2)`` (m) and ``(6,)`` (rad), with a leading ``N`` for a batch; positive inside,
        negative outside, ``inf`` where the robot file sets no such limit."""

    @property
    def limits(self) -> Limits:
        """The robot file's ``[limits]``; ``None`` where it sets none."""

    def regressor(
        self,
        pose: ArrayLike,
        omega: Optional[ArrayLike] = None,
        velocity: Optional[ArrayLike] = None,
        omega_dot: Optional[ArrayLike] = None,
        acceleration: Optional[ArrayLike] = None,
        *,
        errors: Errors = "raise",
    ) -> Result:
        """``Y`` of ``gamma = Y pi`` with friction: ``(6, 142)`` or ``(N, 6, 142)``."""

    def base_regressor(
        self,
        pose: ArrayLike,
        omega: Optional[ArrayLike] = None,
        velocity: Optional[ArrayLike] = None,
        omega_dot: Optional[ArrayLike] = None,
        acceleration: Optional[ArrayLike] = None,
        *,
        errors: Errors = "raise",
    ) -> Result:
        """``Y_b`` of ``gamma = Y_b beta`` with friction: ``(6, n_b)`` or ``(N, 6, n_b)``."""

    @property
    def standard_parameters(self) -> list[str]:
        """The names of ``pi``, the columns of ``regressor``."""

    @property
    def base_parameters(self) -> list[str]:
        """The names of ``beta``, the columns of ``base_regressor``."""

    def standard_values(
        self, viscous: Optional[Sequence[float]] = None, coulomb: Optional[Sequence[float]] = None
    ) -> Array:
        """This robot's ``pi``, with the actuators' friction (zero if omitted)."""

    def base_values(
        self, viscous: Optional[Sequence[float]] = None, coulomb: Optional[Sequence[float]] = None
    ) -> Array:
        """This robot's ``beta = B pi``: what ``identify`` should find."""

    def identify(
        self,
        pose: ArrayLike,
        omega: ArrayLike,
        velocity: ArrayLike,
        omega_dot: ArrayLike,
        acceleration: ArrayLike,
        gamma: ArrayLike,
    ) -> Identification:
        """The base parameters (inertial and friction) by weighted least squares from measured
        states ``(N, ...)`` and forces ``(N, 6)``."""

    def calibrate(
        self,
        pose: ArrayLike,
        q: ArrayLike,
        *,
        noise_position: float = 10e-6,
        noise_angle: float = 20e-6,
        noise_encoder: float = 1e-6,
        scale: float = 1e-3,
        observable: float = 5e-3,
        strict: bool = False,
    ) -> Calibration:
        """Kinematic calibration of a Gough-Stewart platform, a rotary hexapod or a Delta: each
        leg's fitted geometry (joint centres, a rotary leg's crank and rod lengths, the encoder
        offset) fitted to measured poses ``(N, d)`` and readings ``(N, n)``
        (docs/calibration.md); ``units`` says ``m`` or ``rad`` per parameter. ``std_dev`` is
        NaN for a parameter fixed as unobservable."""

    def plan(
        self,
        start: ArrayLike,
        goal: ArrayLike,
        duration: float,
        steps: int,
        *,
        force_limit: Optional[float] = None,
        least_clearance: float = 0.01,
        goal_tolerance: float = 1e-8,
        force_tolerance: float = 1e-6,
        clearance_tolerance: float = 1e-6,
        max_iterations: int = 500,
    ) -> Plan:
        """A minimum-effort rest-to-rest move from ``start`` to ``goal`` (the platform's
        coordinates) in ``duration`` s over ``steps`` held forces, ``|gamma| <= force_limit``
        if given, every pose's singularity clearance at least ``least_clearance``: iLQR on the
        forward dynamics' exact Jacobians (docs/derivatives.md). A dict:
        ``times`` ``(steps + 1,)``, ``pose`` ``(steps + 1, n)``, the twist's and acceleration's
        parts (``omega``, ``velocity``, ``omega_dot``, ``acceleration``; ``(steps + 1, 3)``
        each, the angular ones absent for a platform that translates), ``gamma``
        ``(steps, n)``, ``iterations``, ``costs``, ``goal_error``, ``force_excess``,
        ``least_clearance``. Raises
        ``ValueError`` for a problem that cannot be planned, a robot without derivative
        kernels, or no convergence."""

    def calibration_plan(self, n: int, *, seed: int = 1) -> Array:
        """``n`` poses ``(n, d)`` inside the limits that make the geometry best observable."""

C5 = Robot

def export(
    robot: Optional[Union[str, PathLike[str]]] = None,
    format: Literal["mjcf", "urdf"] = "mjcf",
) -> str:
    """The robot of a file, any mechanism (the chapter's C5 for ``None``), as MJCF or URDF
    text, as ``c5 export`` writes it; also for the Delta, whose kernels are not generated yet
    (docs/export.md)."""
"""The chapter's robot's name for :class:`Robot`."""
