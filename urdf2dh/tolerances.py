"""Every number urdf2dh decides by, named for what it decides, in one place: the tolerances of
its judgements and the bounds on what it reads.

* :class:`Tolerances`: the judgements of one conversion, overridable per call (keyword) and per
  command (CLI flag); :data:`DEFAULT` and :data:`EXACT`.
* Named thresholds of ``diff``, calibration and the exports.
* Bounds on input: what urdf2dh reads at most, so that no input makes it run for minutes, take
  gigabytes or crash; beyond each, a one-line error naming the bound (``docs/limits.md`` lists
  them with the error each gives).

No bare tolerance literal appears in the geometry modules.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, fields, replace

__all__ = [
    "BARELY_MOVED",
    "BEYOND_LIMITS",
    "BOUNDS",
    "CALIBRATION_COST",
    "CALIBRATION_GRADIENT",
    "CALIBRATION_STEP",
    "CHOLESKY_RIDGE",
    "DEFAULT",
    "DIFF_ANGLE_DEG",
    "DIFF_LENGTH_M",
    "DIFF_PARALLEL_DEG",
    "DIFF_ROUND_OFF",
    "EXACT",
    "FILE_BYTES",
    "FK_ROUNDING",
    "GROSS_POSITION",
    "GROSS_ROTATION",
    "HASH_DECIMALS",
    "JOINTS",
    "JOINT_POSITIONS",
    "JOINT_SCALES",
    "LARGEST_NUMBER",
    "LARGEST_URDF_ANGLE",
    "LARGEST_URDF_NUMBER",
    "LAYOUT_MISFIT",
    "MAPPING_DEPTH",
    "MAPPING_VALUES",
    "MATCH_ROUND_OFF",
    "MAX_SAMPLES",
    "MAX_SEED",
    "MEASUREMENT_BYTES",
    "MJCF_INCLUDES",
    "NOISE_BALANCE",
    "NOISE_FLOOR",
    "NOISE_MISMATCH",
    "NOISE_OVER",
    "NOISE_RATIO",
    "OUTLIER_CHANCE",
    "OUTLIER_GAIN",
    "OUTLIER_SHARE",
    "POORLY_IDENTIFIED",
    "POSITION_ROTATION",
    "QUATERNION_NORM",
    "RANK_RELATIVE",
    "RIGID_INPUT",
    "SCALE_FACTOR",
    "SMALLEST_SIZE",
    "SPREAD",
    "VERIFY_JOINTS",
    "WORSE_CONFIGURATIONS",
    "WORSE_RATIO",
    "WORSE_THAN_BEFORE",
    "Tolerances",
]

EPS = sys.float_info.epsilon  # float64's; not numpy's, so that `urdf2dh --help` needs no numpy

# A robot size below this (1e-292) would make every relative tolerance (round-off, eps x size) a
# subnormal float or 0: a chain within it of the base origin is all at the origin (size 1), so
# that its tolerances are round-off and not an underflow (a tip 4.9e-324 m away).
SMALLEST_SIZE = sys.float_info.min / EPS

# Decimals kept of each D-H value before Universal Robots' calibration hash is taken
# (emit/export/ur.py): an exact table carries round-off (theta = -4.9e-12 where UR writes 0, a
# length one ulp off its decimal) that would change the hash's %g text; 1e-10 is far below the 6
# significant digits the hash sees and far above round-off.
HASH_DECIMALS = 10
# Exported files write a length as the shortest decimal within this x robot size of it: the
# arithmetic's last few ulps (0.03500000000000003 -> 0.035), far below every tolerance, so that a
# whole file's lengths move its forward kinematics by less than about 1e-14 x size.
DECIMAL_ROUND_OFF = 4 * EPS

# `diff` (and the calibration report's diff) marks changes beyond these by default: what a
# calibration corrects beyond its measuring noise (0.1 mm, 0.01 deg at typical accuracies of
# 10-50 um); Wu 2019 Table II marks jumps instead (60 deg, 30 mm).
DIFF_ANGLE_DEG = 0.01
DIFF_LENGTH_M = 1e-4
# ... and names consecutive axes this close to parallel (deg) in either model as ill-conditioned
# for D-H: there the common normal, and with it d, a and theta, jump under small changes.
DIFF_PARALLEL_DEG = 5.0
# ... and shows a change too small for its printed precision in full (``+2e-09 m``) only beyond
# this (rad, or x robot size): a table read back and converted again moves its parameters by
# round-off of up to ~1e-14 x size, which is no change.
DIFF_ROUND_OFF = 1e-12

# `match` judges a table against its source at the precision the table is written in, plus this
# (x robot size for positions, rad for rotations) for the source's own rounding: URDFs write pi/2
# to 10 or 11 digits (1.57079632679 is 4.9e-12 rad off), UR's kinematics files 1.570796327
# (2e-10 rad).
MATCH_ROUND_OFF = 1e-9

# ----------------------------------------------------------------------------- calibration

# A measured quaternion (x, y, z, w) must be a unit quaternion within this (it is then
# normalised): files that round to 3 decimals (norm off by up to ~1e-3) pass, a quaternion that is
# scaled, truncated to fewer digits or not one at all does not.
QUATERNION_NORM = 1e-2

# Identification (urdf2dh/calibration/identify.py) has converged when the next Gauss-Newton step
# would move no modelled tool point by more than CALIBRATION_STEP x robot size and no tool
# orientation by more than CALIBRATION_STEP rad (below that, steps only chase round-off: forward
# kinematics is itself good to ~1e-15 relative), or when every column of the (column-normalised)
# Jacobian is within CALIBRATION_GRADIENT of orthogonal to the residual (a minimum with noise).
# It has converged too when the next step is predicted to lower the weighted sum of squares by
# no more than CALIBRATION_COST of it (MINPACK's and scipy's ftol, 1.5e-8 and 1e-8): the fit's
# RMS residual would not change in its eighth digit. In a flat valley of parameters the data
# barely see, steps that still move them would otherwise creep on for hundreds of iterations.
CALIBRATION_STEP = 1e-11
CALIBRATION_GRADIENT = 1e-10
CALIBRATION_COST = 1e-8

# Numerical rank of the column-scaled, weighted identification Jacobian: singular values below
# RANK_RELATIVE x the largest count as zero. Identifiable directions of well-spread data lie
# at 1e-4 and above; unidentifiable ones at round-off (1e-15). The left-out errors
# (calibration.select.hat_basis) apply it to the eigenvalues of the scaled normal matrix, the
# singular values squared: there directions below sqrt(RANK_RELATIVE) = 1e-5 count as zero.
RANK_RELATIVE = 1e-10

# A symmetric matrix whose Cholesky factor calibration takes (the prior's covariance, the
# evidence's normal matrix) has CHOLESKY_RIDGE x its mean diagonal added to its diagonal first:
# far below any variance that matters, it keeps a merely semi-definite matrix factorable.
CHOLESKY_RIDGE = 1e-12

# Float64 evaluation of a table's forward kinematics rounds by about FK_ROUNDING x eps x the
# sum of its lengths (every |d|, |a|, |l| and base and tool length) at most: negligible for a
# table whose lengths are the robot's own, but a D-H row 300 m long (axes a few milliradians from
# parallel, with --exact or beyond sane_factor) rounds to ~1e-13 m, which such a table declares.
# Measured on 1,048 chains of real robot descriptions (scripts/written_exactness.py): at most
# 1.04 eps x the sum.
FK_ROUNDING = 2.0

# Noise levels estimated from residuals (or given as 0) are raised to this x robot size
# (position) and this (rad, rotation), so that noise-free data keeps finite weights.
NOISE_FLOOR = 1e-14

# A joint whose measured positions span less than BARELY_MOVED (rad; for a sliding joint, x the
# robot's size) barely moved: how its line lies and how far it scales can hardly be seen (a
# line's tilt shows at the tool in proportion to the joint's motion), and what is identified of
# them holds near the measured positions only. Calibration names the joint and flags those
# parameters.
BARELY_MOVED = 0.1

# An identified parameter is flagged as poorly identified when one standard deviation of it moves
# some measured tool point by more than POORLY_IDENTIFIED x the position noise level (rotations
# counted at the robot's size): the measurements leave it uncertain by more than a few of their
# own errors, so its value in the output means little.
POORLY_IDENTIFIED = 3.0

# A measurement whose standardised residual a chi-square variable (3 or 6 degrees of freedom)
# would exceed with a chance below OUTLIER_CHANCE is an outlier suspect (about 5.5 sigma for a
# position): listed, and rejected when asked, or when without the suspects the other
# configurations are predicted better by more than OUTLIER_GAIN standard errors of the paired
# differences (a three-sigma test: measurements are not thrown away on weak evidence; on the
# Franka data set its two suspects are the model's error at an unusual configuration, 2.6 standard
# errors, and rejecting them costs 14% held out; a TALOS set's first row, 79 mm off, 4.5).
OUTLIER_CHANCE = 1e-6
OUTLIER_GAIN = 3.0

# Noise levels (estimated or given) never weigh one kind of residual more than 1 / NOISE_RATIO
# times the other (rotation in rad against position over the robot's size): with exact
# rotations the weights would otherwise drown every position below RANK_RELATIVE, and the
# parameters only positions see would look undetermined. 1e-6 keeps them 1e4 above it.
NOISE_RATIO = 1e-6

# More outlier suspects than OUTLIER_SHARE of the fitted measurements are not outliers: the
# noise levels are wrong (given too small) or the model misses something, and rejecting them
# would leave the fit to the few that agree with a wrong noise. They are kept and the
# plausibility judgement below names it. (The real data sets have at most 2.5%.)
OUTLIER_SHARE = 0.2

# The plausibility judgement of a calibration (urdf2dh/calibration/plausible.py): what the
# measurements contradict. On the ten real data sets of benchmarks/calibration.py the largest
# values seen are given in brackets; each threshold is several times beyond them and far below
# what the mistakes it names produce.
# - RMS position residual of the fit beyond GROSS_POSITION x the robot's size [0.011]: no
#   measuring device is that poor; millimetres read as metres leave hundreds of robot sizes,
#   joint angles in degrees read as radians about one.
GROSS_POSITION = 0.1
# - RMS rotation residual beyond GROSS_ROTATION rad [0.035]: a quaternion in another order, a
#   wrong rotation sequence or angles in another unit leave about 1 rad.
GROSS_ROTATION = 0.2
# - A residual level (RMS per coordinate) more than NOISE_MISMATCH times the noise given: the
#   noise is under-stated, or the model misses something (real robots leave residuals a few
#   times a tracker's noise: unmodelled compliance and backlash); or less than 1 / NOISE_OVER
#   times it, over the fit's redundancy (sqrt(m / (m - p)) for m equations and p parameters):
#   over-stated, the noise weighs the prior's nominal geometry over the measurements and the
#   residuals grow toward it (30 times over-stated left 0.12 times it, a model ten times less
#   accurate).
NOISE_MISMATCH = 10.0
NOISE_OVER = 3.0
# - Noise levels given for poses whose ratio (position against rotation) is more than
#   NOISE_BALANCE times, or less than its inverse, the residuals' ratio: the fit weighs one kind
#   that much too much (a position noise 11 times over-stated with a rotation noise 2 times
#   under-stated left a model 3.7 times less accurate).
NOISE_BALANCE = 5.0
# - Estimated noise levels of poses whose position residuals (the median) exceed POSITION_ROTATION
#   x the rotation residuals (the median) at the robot's size [0.35]: a device measures an
#   orientation from points a baseline apart, so its rotations are never that much finer than
#   its positions; the positions carry the model's error (a helical joint taken for a revolute
#   one: 1.2e3 on the PUMA of Wu 2019). It is refused where helical joints explain the positions,
#   and said where they do not (the device's own position noise, maybe).
POSITION_ROTATION = 10.0
# - Measured points that spread more than SPREAD times as far as the nominal's tool points at the
#   same configurations, or less than 1 / SPREAD times [1.1], where the nominal joints with base
#   and tool fitted leave gross residuals (GROSS_POSITION): another length unit (2.54 between
#   inches and centimetres, at the least) or another robot.
SPREAD = 2.0
# - A joint identified with a scale beyond SCALE_FACTOR times the nominal's or below its
#   inverse [1.002 with the default prior; up to 8.1 overfitted without one]: joint values in
#   another unit (57 between degrees and radians); or negative: a joint counted the other way.
SCALE_FACTOR = 10.0
# - A calibrated model that predicts configurations it was not fitted to (held out, validation,
#   or each left out of the fit in turn) worse than the nominal joints with base and tool
#   fitted, by more than WORSE_THAN_BEFORE standard errors of the paired per-configuration
#   differences, or WORSE_RATIO times in RMS over WORSE_CONFIGURATIONS configurations or more
#   [the defaults are never worse; explicit levels at most 1.14 times]: a level the
#   measurements do not support (the TIAGo's full level without a prior: 5.3 times held out).
WORSE_THAN_BEFORE = 3.0
WORSE_RATIO = 2.0
WORSE_CONFIGURATIONS = 5
# - Markers whose identified positions on the tool miss the layout given (after the best rigid
#   fit) by more than LAYOUT_MISFIT x the layout's spread [7e-5 on the TIAGo's three markers]:
#   markers numbered otherwise, or a layout in another unit.
LAYOUT_MISFIT = 0.1
# - Joint values beyond their limits by more than BEYOND_LIMITS rad (a revolute joint) are
#   named (a warning; the judgement above decides whether they are degrees).
BEYOND_LIMITS = 0.5

# ----------------------------------------------------------------------------- bounds on input
# Set from measurements (benchmarks/scale.py): ``convert`` takes about 0.5 ms and 8 kB per joint
# (a chain of JOINTS joints in ~5 s and 200 MB); Pinocchio's URDF parser, which ``verify`` runs,
# takes time that grows faster than the links.

# Bytes of any file urdf2dh reads (SOURCE, a measurement CSV, a marker layout, a xacro file's
# expansion): a URDF of JOINTS joints is ~3 MB, a POE or table file of as many joints under 2 MB.
FILE_BYTES = 16 * 2**20

# Bytes of a measurement CSV (calibrate's, plan's): sized for a million poses of a 7-joint arm
# (about 300 bytes a row); the rows read are bounded again by calibration's own count
# (:data:`urdf2dh.calibration.measurements.MAX_MEASUREMENTS`), so that a bigger file is refused
# in one line, not after minutes.
MEASUREMENT_BYTES = 512 * 2**20

# Joints of a URDF (all its joints, on the chain or not), of a POE or table file, of a xacro
# file's expansion, and of the chains of one run over several tips.
JOINTS = 10_000

# Files one MJCF SOURCE may include (<include>, nested ones too; each file at most once): their
# text together holds at most FILE_BYTES.
MJCF_INCLUDES = 1_000

# Values of a parsed POE or table file, aliases counted each time they are used: a YAML file of
# a few hundred bytes can otherwise alias its way to billions ("billion laughs").
MAPPING_VALUES = 1_000_000

# Levels of nesting of a POE or table file (lists and mappings in one another): a POE file has
# four.
MAPPING_DEPTH = 1_000

# Configurations x joints of one self-check, verify run or synthesized set of poses: 80 MB for
# each array of joint positions (a check of 1,000 configurations of a JOINTS-joint chain).
JOINT_POSITIONS = 10_000_000

# Joints of a URDF (or of a POE or table chain) that `verify` hands to Pinocchio: building its
# model of 2,000 joints takes ~1 s and 200 MB, of 8,000 joints 25 s and 2 GB.
VERIFY_JOINTS = 2_000

# Configurations of a self-check or a verify run (about 1 GB of poses at most), and the largest
# random seed (numpy's seeds are non-negative integers).
MAX_SAMPLES = 1_000_000
MAX_SEED = 2**63 - 1

# Markers on one tool in position measurements (more add nothing a calibration could use).
MAX_MARKERS = 100

# No number a POE or table file holds is larger: 1e12 of any length unit urdf2dh knows is over a
# million kilometres, and angles, scales and limits are far smaller. Beyond it, products and sums
# of squares in the geometry would overflow, so such a number is an input error.
LARGEST_NUMBER = 1e12

# The largest magnitude read from a URDF for a length (origin ``xyz``), a joint limit or a mimic
# factor: far beyond any robot (1e50 m; URDFs place world joints far away, and urdfdom reads
# them), and small enough that the product of two such values (a helical joint's travel, pitch x
# limit) and its square stay finite in float64.
LARGEST_URDF_NUMBER = 1e50

# The largest magnitude read from a URDF for a revolute joint's limit, in radians (1592 turns).
# A D-H angle is ``q + theta``: where float64's spacing of ``q`` nears the exactness urdf2dh
# promises (1e-10 rad), the sum loses ``theta`` (at 1e6 rad the spacing is 1.2e-10 rad, at 1e16
# rad it is 2 rad), in our table's forward kinematics and in every controller's. Here it is
# 1.8e-12.
LARGEST_URDF_ANGLE = 1e4

# A joint's scale in a POE file (|w|, or |v| of a prismatic joint) is a gear ratio or a unit:
# within these.
JOINT_SCALES = (1e-9, 1e9)

#: The bounds on input by name, as ``docs/limits.md`` lists them.
BOUNDS = (
    "FILE_BYTES",
    "MEASUREMENT_BYTES",
    "JOINTS",
    "MAPPING_VALUES",
    "MAPPING_DEPTH",
    "JOINT_POSITIONS",
    "VERIFY_JOINTS",
    "MAX_SAMPLES",
    "MAX_SEED",
    "MJCF_INCLUDES",
    "LARGEST_NUMBER",
    "LARGEST_URDF_NUMBER",
    "LARGEST_URDF_ANGLE",
    "JOINT_SCALES",
)

# ----------------------------------------------------------------------------- the Python API

# A joint axis given to the Python API (urdf2dh.model.poe.Joint) is a unit vector, and a pose
# (PoeModel.home) a rigid transform, within this: what float arithmetic leaves of one (1e-15),
# far below any typed-in rounding (0.7071 is 1e-5 off), which the files' readers orthonormalise
# with a warning instead (Tolerances.rotation_input).
RIGID_INPUT = 1e-9


@dataclass(frozen=True, slots=True)
class Tolerances:
    """Tolerances of one conversion.

    Attributes
    ----------
    parallel_angle
        Radians. Consecutive lines (joint axes, the base z and the tool z) whose directions are
        within this angle of parallel or anti-parallel, and whose exact common normal lies farther
        than ``far_factor`` x the robot's size, are treated as exactly parallel by the D-H
        conventions (``dh``, ``mdh``). Rounded URDF angles (``rpy="0 1.5708 0"``) leave such pairs
        1e-9 to 1e-4 rad apart, where the exact common normal lies 10^3 to 10^8 lengths away. (Pairs
        tilted about their common perpendicular keep a near normal and stay exact.) Each such
        judgement is listed in the table's ``warnings`` with the forward kinematics deviation it
        caused. 0 means exact (``--exact``): then only float round-off (``noise``) is treated as
        parallel. The OPW export (:mod:`urdf2dh.conventions.opw`) takes the right angles and the
        parallel its model assumes (axes 1-2, 3-4, 4-5, 5-6 perpendicular, 2-3 parallel) as holding
        within this angle, with a warning and the deviation measured; beyond it the arm is refused,
        naming the pair.
    meet_angle
        Radians. Below this angle from parallel the common-normal formula is ill-conditioned;
        a line that passes within ``intersect_distance`` of the pivot (the previous frame's
        origin, or for the tool z the tool origin on the previous axis) is then taken to meet
        the previous axis there: ``a = 0`` and its exact direction is kept. This is exact, so it
        applies with ``--exact`` too.
    intersect_distance
        Source length unit, or ``None`` for ``intersect_relative`` x the robot's size. Lines
        closer than this count as intersecting: non-parallel pairs get ``alpha > 0`` (their
        tiny ``a`` is kept, exactly), parallel pairs are treated as coincident (``a = 0``,
        ``theta = 0``). The OPW export takes wrist axes 4, 5, 6 that pass within this distance of
        one point as meeting there (farther: "offset wrist", refused), and axes 2 and 3 closer
        than it as coincident (refused); its sign choices (``a1``, ``c3``, ``c4`` of either sign)
        treat lengths within it as zero.
    intersect_relative
        The default distance above, as a fraction of the robot's size.
    check_position, check_rotation
        The self-check: a table whose forward kinematics deviates from the source's by more than
        ``check_position`` x robot size (position) or ``check_rotation`` rad (orientation), beyond
        what the judgements above account for, is never written.
    cpc_reverse_below
        CPC's R(b) is singular at b = -z. A CPC frame whose axis direction has
        ``b_z < cpc_reverse_below`` in the previous frame is reversed (its joint gets
        ``scale = -scale``), which keeps the table's forward kinematics
        (docs/conventions/cpc.md).
    cpc_singular_margin
        When the tool z would point against the last CPC frame's z, a run of last frames is
        reversed; the frame pair that then turns round must stay this far (in ``b_z``) from
        -1, or it would trade one singularity for another.
    far_factor
        A D-H ``|d|`` or ``|a|`` larger than ``far_factor`` x the robot's size is warned about.
    sane_factor
        Axes farther than ``parallel_angle`` from parallel whose exact common normal would put a
        D-H ``|d|`` or ``|a|`` beyond ``sane_factor`` x the robot's size are treated as parallel
        all the same, with the deviation declared (``dh`` and ``mdh`` never refuse a chain; the
        ``hayati`` convention is exact there). Not with ``--exact``.
    rotation_input
        A rotation typed into a file (POE tool matrix, table matrix) may be off orthonormal by
        this much (it is then orthonormalised, with a warning); more is an input error.
    noise
        Float round-off: relative size below which a difference is not geometry (an axis
        this close to parallel is parallel even with ``--exact``; a pitch this small is zero).
    report
        The exactness urdf2dh promises: a table's forward kinematics within ``report`` x robot
        size and ``report`` rad of its source's, or within the deviation it declares. A
        judgement whose effect is below it is not listed in ``warnings`` (it still counts in the
        self-check); one above it is listed and its bound declared in the table's check. A
        table whose lengths reach so far that float64 evaluation of its FK may round by more
        than it (:data:`FK_ROUNDING`) declares that rounding too.
    written
        A table's parameter within ``written`` (rad, or x robot size) of 0, an angle within it of
        a multiple of pi/2, is written as that (no ``-0.0``, ``a: 2.4e-33`` or
        ``alpha: 1.5707963267948968`` in the files), and a direction's component within it of 0
        is written as 0 with the direction normalised again; the self-check runs on the numbers
        as written. A few units in the last place: each such value costs at most ``written`` x
        its lever, so that a whole table stays within ``report``; a genuine small value (a URDF's
        rounded pi/2 leaving 4.9e-12 rad, round-off of 1e-14 accumulated along a chain) is kept.
    solver_snap
        The exports for analytic inverse-kinematics solvers (``rtb``, ``eaik``;
        :mod:`urdf2dh.conventions.analytic`) write a D-H angle within ``solver_snap`` rad of a
        multiple of pi/2 as that multiple, and a length within ``solver_snap`` x robot size of 0
        as 0: the solvers recognise a spherical wrist or parallel axes by exact relations, and
        roboticstoolbox derives its solver symbolically, where 4.9e-12 rad (a URDF's rounded
        pi/2) is a new symbol and no closed form. Each snap beyond ``written`` is listed with the
        deviation it costs, a bound declared in the file and checked. 0 with ``--exact``.
    """

    parallel_angle: float = 1e-4
    meet_angle: float = 1e-3
    intersect_distance: float | None = None
    intersect_relative: float = 1e-9
    check_position: float = 1e-10
    check_rotation: float = 1e-10
    cpc_reverse_below: float = -0.5
    cpc_singular_margin: float = 1e-3
    far_factor: float = 10.0
    sane_factor: float = 1e3
    rotation_input: float = 1e-3
    noise: float = 256 * EPS
    report: float = 1e-14
    written: float = 4 * EPS
    solver_snap: float = 1e-10

    def __repr__(self) -> str:
        # the values that differ from the defaults: short, and what one passes to get it back
        changed = (f for f in fields(self) if getattr(self, f.name) != f.default)
        return f"Tolerances({', '.join(f'{f.name}={getattr(self, f.name)!r}' for f in changed)})"

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "intersect_distance" and value is None:
                continue
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise TypeError(f"tolerance {f.name} must be a number, not {value!r}")
            if f.name == "cpc_reverse_below":  # a cosine
                if not -1.0 <= value <= 0.0:
                    raise ValueError(f"cpc_reverse_below must lie in [-1, 0], not {value!r}")
                continue
            if not (0.0 <= value < float("inf")):
                raise ValueError(f"tolerance {f.name} must be a finite number >= 0, not {value!r}")
        if self.parallel_angle >= 0.5 * math.pi:
            raise ValueError("parallel_angle must be below pi/2")

    @property
    def exact(self) -> bool:
        """True when no geometric snapping is done (``--exact``)."""
        return self.parallel_angle == 0.0 and self.intersect_distance == 0.0

    def distance(self, size: float) -> float:
        """The intersect distance for a robot of this size (never below float round-off)."""
        chosen = (
            self.intersect_relative * size
            if self.intersect_distance is None
            else self.intersect_distance
        )
        return max(chosen, self.noise * size)

    def with_exact(self) -> Tolerances:
        """The same tolerances with snapping turned off."""
        return replace(
            self, parallel_angle=0.0, intersect_distance=0.0, sane_factor=0.0, solver_snap=0.0
        )


DEFAULT = Tolerances()
EXACT = DEFAULT.with_exact()
